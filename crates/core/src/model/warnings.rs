//! What assembly approximated or left out, as counted warnings (see the parent module).

use serde::Serialize;

use crate::geometry::Point;

/// Why a contact pair produced no constraint row.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum NoRowReason {
    /// No boundary node of either body is within one element size of the other (no region box).
    NoCandidates,
    /// Candidate slave nodes exist, but no master segment faces any of them.
    NoFacingSegment,
    /// Every row was inert (all its DOFs prescribed) and was removed.
    AllInert,
}

/// One body's part of a free direction ([`ModelWarning::FreeDirection`]): a translation along a
/// unit vector, or a rotation about a point (exactly one of the two is given).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct FreeMotion {
    /// The body, as in the scene.
    pub body: String,
    /// A translation: its unit direction.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub along: Option<Point>,
    /// A rotation: the point it turns about (undeformed coordinates).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub about: Option<Point>,
}

impl std::fmt::Display for FreeMotion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.along, self.about) {
            (Some([_, 0.0]), _) => write!(f, "translation along x"),
            (Some([0.0, _]), _) => write!(f, "translation along y"),
            (Some([x, y]), _) => write!(f, "translation along ({x:.4}, {y:.4})"),
            (None, Some([x, y])) => write!(f, "rotation about ({x}, {y})"),
            (None, None) => write!(f, "no motion"),
        }
    }
}

/// Something assembly had to approximate or leave out, counted per contact pair, or something
/// the checks of the answer found (the last two variants).  `pair` is the 1-based index of the
/// `[[contact]]` section; bodies are named.  [`std::fmt::Display`] gives a one-line message;
/// serialised (JSON) with the variant name in `kind`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ModelWarning {
    /// The pair produced no constraint row at all (it has no effect on the solution).
    NoContactRow {
        /// 1-based pair index.
        pair: usize,
        /// The pair's two bodies, as in the scene.
        bodies: [String; 2],
        /// Why.
        reason: NoRowReason,
    },
    /// Slave candidate nodes that got no row: node-to-segment, no facing master segment (within
    /// its span, on its outer side); mortar, less than a quarter of the node's share of the slave
    /// interface is covered by the master (the ends of the contact zone).  Nothing keeps these
    /// nodes themselves out of the master.
    UnmatchedNodes {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Nodes without a row.
        nodes: usize,
        /// All slave candidate nodes of the pair.
        candidates: usize,
    },
    /// Rows whose tributary length (for the pressure λ / length) does not come from slave edges
    /// facing the master: it falls back to other interface edges, to any adjacent boundary edge,
    /// or (`unit_length` of them) to 1.0.
    TributaryFallback {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Rows with a fallback length.
        rows: usize,
        /// Of those, rows given the length 1.0 (no adjacent boundary edge of positive length).
        unit_length: usize,
    },
    /// The bodies overlap at the start (by less than the pair's larger `hmax`): the slave nodes
    /// inside the master have rows with negative gaps, which push them out.
    InitialOverlap {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Slave nodes starting inside the master, each with a row (negative gap).
        nodes: usize,
        /// Master boundary nodes starting inside the slave (not constrained by node-to-segment
        /// rows).
        master_nodes: usize,
        /// Body of the deepest node.
        deepest_body: String,
        /// Position of the deepest node (undeformed).
        deepest: Point,
        /// Its depth inside the other body.
        depth: f64,
    },
    /// Rows whose every DOF is prescribed on both sides: they constrain nothing a solver can
    /// change and were removed from B and g (their reduced gap is ≥ 0).
    InertRows {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// Rows removed.
        rows: usize,
        /// Slave node position of the first one.
        first: Point,
    },
    /// The answer is one of many minimisers: a rigid motion of floating bodies (held by contact
    /// alone) that no row holding in the answer resists and along which the objective is flat
    /// (`crate::report::free`).  Any amount of it gives another minimiser, so the displacement
    /// along it is arbitrary and backends may return answers that differ by it; the status is
    /// unchanged.
    FreeDirection {
        /// Each moving body's part (one body unless they move together).
        motions: Vec<FreeMotion>,
    },
    /// The deformed-geometry check (`crate::contact::deformed`) could not judge the pair: a slave
    /// node ends inside its deformed master beyond the allowance, but the pair moves more than a
    /// tenth of its smaller body's size, beyond the small-displacement model, so the overlap may
    /// be the model's and not the solver's (the status is not changed).
    DeformedUnjudged {
        /// 1-based pair index.
        pair: usize,
        /// Slave body.
        slave: String,
        /// Master body.
        master: String,
        /// The node's undeformed position.
        position: Point,
        /// How far it ends inside the master's deformed outline.
        depth: f64,
        /// The pair's motion U (max |u| over its two bodies' nodes).
        motion: f64,
        /// The smaller body's size (the smaller side of its bounding box).
        size: f64,
    },
}

impl ModelWarning {
    /// The variant's name as serialised in `kind`.
    pub fn kind(&self) -> &'static str {
        match self {
            ModelWarning::NoContactRow { .. } => "no_contact_row",
            ModelWarning::UnmatchedNodes { .. } => "unmatched_nodes",
            ModelWarning::TributaryFallback { .. } => "tributary_fallback",
            ModelWarning::InitialOverlap { .. } => "initial_overlap",
            ModelWarning::InertRows { .. } => "inert_rows",
            ModelWarning::FreeDirection { .. } => "free_direction",
            ModelWarning::DeformedUnjudged { .. } => "deformed_unjudged",
        }
    }

    /// The 1-based contact pair the warning is about (`None` for a free direction, which is
    /// about bodies).
    pub fn pair(&self) -> Option<usize> {
        match self {
            ModelWarning::NoContactRow { pair, .. }
            | ModelWarning::UnmatchedNodes { pair, .. }
            | ModelWarning::TributaryFallback { pair, .. }
            | ModelWarning::InitialOverlap { pair, .. }
            | ModelWarning::InertRows { pair, .. }
            | ModelWarning::DeformedUnjudged { pair, .. } => Some(*pair),
            ModelWarning::FreeDirection { .. } => None,
        }
    }
}

impl std::fmt::Display for ModelWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelWarning::NoContactRow {
                pair,
                bodies,
                reason,
            } => {
                write!(
                    f,
                    "contact #{pair} (\"{}\" – \"{}\") gave no constraint row: ",
                    bodies[0], bodies[1]
                )?;
                match reason {
                    NoRowReason::NoCandidates => write!(
                        f,
                        "no boundary node of either body is within one element size of the other (give the pair a region box if they are meant to touch)"
                    ),
                    NoRowReason::NoFacingSegment => write!(
                        f,
                        "no master segment faces any candidate slave node (check the region box and the bodies' positions)"
                    ),
                    NoRowReason::AllInert => write!(
                        f,
                        "every row had all its DOFs prescribed on both sides and was removed as inert"
                    ),
                }
            }
            ModelWarning::UnmatchedNodes {
                pair,
                slave,
                master,
                nodes,
                candidates,
            } => write!(
                f,
                "contact #{pair}: {nodes} of {candidates} candidate node(s) of slave \"{slave}\" face no segment of master \"{master}\" (mortar: the master covers less than a quarter of their share of the interface) and have no constraint row"
            ),
            ModelWarning::TributaryFallback {
                pair,
                slave,
                master,
                rows,
                unit_length,
            } => {
                write!(
                    f,
                    "contact #{pair} (slave \"{slave}\", master \"{master}\"): {rows} row(s) have no slave edge facing the master; their pressure uses the length of other adjacent edges"
                )?;
                if *unit_length > 0 {
                    write!(f, " ({unit_length} with no edge at all: length 1.0)")?;
                }
                Ok(())
            }
            ModelWarning::InitialOverlap {
                pair,
                slave,
                master,
                nodes,
                master_nodes,
                deepest_body,
                deepest,
                depth,
            } => {
                write!(
                    f,
                    "contact #{pair}: bodies \"{slave}\" (slave) and \"{master}\" (master) overlap at the start, deepest {depth:e} at ({}, {}) of \"{deepest_body}\"; {nodes} slave node(s) start inside the master and are pushed out by rows with negative gaps",
                    deepest[0], deepest[1]
                )?;
                if *master_nodes > 0 {
                    write!(f, ", {master_nodes} master node(s) start inside the slave")?;
                }
                Ok(())
            }
            ModelWarning::InertRows {
                pair,
                slave,
                master,
                rows,
                first,
            } => write!(
                f,
                "contact #{pair} (slave \"{slave}\", master \"{master}\"): {rows} row(s) have every DOF fixed by [[dirichlet]] on both sides (first at ({}, {})) and were removed as inert",
                first[0], first[1]
            ),
            ModelWarning::FreeDirection { motions } => {
                let names: Vec<String> = motions.iter().map(|m| format!("\"{}\"", m.body)).collect();
                let parts: Vec<String> = motions
                    .iter()
                    .map(|m| format!("\"{}\" {m}", m.body))
                    .collect();
                let who = if motions.len() == 1 {
                    "body"
                } else {
                    "bodies"
                };
                write!(
                    f,
                    "the answer is not unique: {who} {} held by contact alone can move freely ({}): no contact row that holds in the answer resists it and the objective is flat along it, so the displacement along it is arbitrary and backends (or settings) may return answers that differ by any amount of it; a support or a load along it makes the answer unique",
                    names.join(" and "),
                    parts.join(", ")
                )
            }
            ModelWarning::DeformedUnjudged {
                pair,
                slave,
                master,
                position,
                depth,
                motion,
                size,
            } => write!(
                f,
                "contact #{pair}: the deformed-geometry check could not judge this pair: slave \"{slave}\" node at ({}, {}) ends {depth:.3e} inside master \"{master}\" in the deformed configuration, but the pair moves {motion:.3e}, more than a tenth of its smaller body's size {size:.3e}, beyond the small-displacement model (the overlap may be the model's, not the solver's; a region box that covers where contact may reach, or a smaller load, lets it be judged)",
                position[0], position[1]
            ),
        }
    }
}
