//! Meshes read from Gmsh files (MSH 4.1, ASCII or binary), parsed by the `mshio` crate.
//!
//! What is accepted: linear triangles (Gmsh type 2) or linear quadrilaterals (type 3), not both in
//! one file, lying in a plane z = const; points (type 15) and lines (type 1) are read for their
//! physical groups only.  Every node used by a 2-D element becomes a [`Mesh`] node (numbered in the
//! order of their Gmsh tags); nodes used by no 2-D element are dropped.  Elements are reoriented
//! counter-clockwise when *all* of them are clockwise (a surface whose normal points along −z);
//! an element whose orientation differs from the others is refused as inverted.
//!
//! The boundary is the set of element edges used by exactly one element, oriented with the body
//! on the left; it must form exactly one closed loop (one body without holes), which becomes the
//! body's polygon for the parts of the program that look at the outline.
//!
//! **Physical groups.**  Names come from the `$PhysicalNames` section.  `mshio` 0.4 parses the
//! `$Entities` section (which entity carries which physical tags) but skips `$PhysicalNames`; that
//! section is plain text in ASCII and binary files alike (`dim tag "name"` per line), so
//! [`physical_names`] reads those lines.  A physical group without a name is known by its tag
//! written in decimal ("3").  A group's nodes are the mesh nodes of its elements (of any
//! dimension); its edges are the boundary edges it holds: for a group of curves the boundary
//! edges that are line elements of the group, for a group of points or surfaces the boundary
//! edges whose two ends are nodes of the group.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::Path;

use mshio::ElementType;

use super::{Cells, Mesh};
use crate::geometry::Point;

/// A physical group of an imported mesh, in the mesh's node numbering.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshGroup {
    /// Largest dimension of the group's entities (0 points, 1 curves, 2 surfaces).
    pub dim: u8,
    /// Mesh nodes of the group's elements, sorted, unique.
    pub nodes: Vec<usize>,
    /// Boundary edges of the mesh held by the group, oriented as in [`Mesh::boundary`], sorted.
    pub edges: Vec<[usize; 2]>,
}

impl MeshGroup {
    /// True when mesh node `n` belongs to the group.
    pub fn has_node(&self, n: usize) -> bool {
        self.nodes.binary_search(&n).is_ok()
    }

    /// True when the boundary edge `[a, b]` (either orientation) belongs to the group.
    pub fn has_edge(&self, a: usize, b: usize) -> bool {
        self.edges.binary_search(&[a, b]).is_ok() || self.edges.binary_search(&[b, a]).is_ok()
    }
}

/// A mesh read from a Gmsh file, with its boundary loop and physical groups.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedMesh {
    /// The file as given in the scene (for messages).
    pub path: String,
    /// The mesh, counter-clockwise elements and boundary.
    pub mesh: Mesh,
    /// The boundary as one closed counter-clockwise loop of node coordinates.
    pub outline: Vec<Point>,
    /// Physical groups by name.
    pub groups: BTreeMap<String, MeshGroup>,
}

impl ImportedMesh {
    /// The group of this name, if any.
    pub fn group(&self, name: &str) -> Option<&MeshGroup> {
        self.groups.get(name)
    }

    /// Group names, comma-separated and quoted, for messages.
    pub fn group_list(&self) -> String {
        if self.groups.is_empty() {
            return "the file defines no physical group".into();
        }
        let names: Vec<String> = self.groups.keys().map(|k| format!("{k:?}")).collect();
        format!("groups in the file: {}", names.join(", "))
    }
}

/// Why a Gmsh file could not be used; the message names the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("mesh file {path}: {problem}")]
pub struct GmshError {
    /// The file.
    pub path: String,
    /// What is wrong.
    pub problem: GmshProblem,
}

/// What is wrong with a Gmsh file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GmshProblem {
    /// The file could not be read.
    #[error("cannot be read: {0}")]
    Read(String),
    /// `mshio` refused the file (not MSH 4.1, truncated, malformed).
    #[error("is not a valid MSH 4.1 file (ASCII or binary): {0}")]
    Parse(String),
    /// No triangle or quadrilateral in the file.
    #[error(
        "holds no 2-D element (triangle or quadrilateral); mesh the surface in 2-D, and when the \
         .geo defines physical groups include a Physical Surface (or set Mesh.SaveAll = 1)"
    )]
    NoElements,
    /// An element type the program does not handle.
    #[error(
        "has {count} element(s) of unsupported type {name} (Gmsh type {code}, {dim}-D); only linear \
         triangles (type 2) and quadrilaterals (type 3) are supported (set Mesh.ElementOrder = 1)"
    )]
    UnsupportedElement {
        /// mshio's name, e.g. `Tri6`.
        name: String,
        /// Gmsh's numeric type.
        code: i32,
        /// Dimension of the entity holding the elements.
        dim: i32,
        /// How many.
        count: usize,
    },
    /// Triangles and quadrilaterals in one file.
    #[error(
        "mixes {triangles} triangles and {quads} quadrilaterals; a body has one element type: \
         recombine all of them (Mesh.RecombineAll = 1) or none, or split the part into two bodies"
    )]
    MixedElements {
        /// Triangles.
        triangles: usize,
        /// Quadrilaterals.
        quads: usize,
    },
    /// An element refers to a node that the `$Nodes` section does not define.
    #[error("element {element} uses node {node}, which the file does not define")]
    UnknownNode {
        /// Element tag.
        element: u64,
        /// Node tag.
        node: u64,
    },
    /// Two nodes with the same tag.
    #[error("defines node {0} more than once")]
    DuplicateTag(u64),
    /// The nodes are not in one plane z = const.
    #[error(
        "is not planar: node z ranges over [{z_min}, {z_max}]; a 2-D mesh needs every node at one z"
    )]
    NotPlanar {
        /// Smallest z.
        z_min: f64,
        /// Largest z.
        z_max: f64,
    },
    /// A coordinate is NaN or infinite.
    #[error("node {0} has a coordinate that is not finite")]
    NotFinite(u64),
    /// Two distinct nodes at the same place (an unmerged interface: Coherence / removeDuplicateNodes).
    #[error(
        "nodes {a} and {b} coincide at ({x}, {y}): the mesh is not conforming there (run \
         Coherence Mesh, or gmsh.model.mesh.removeDuplicateNodes())"
    )]
    DuplicateNodes {
        /// Tag of one node.
        a: u64,
        /// Tag of the other.
        b: u64,
        /// x.
        x: f64,
        /// y.
        y: f64,
    },
    /// An element of (nearly) zero area, or a non-convex quadrilateral.
    #[error(
        "element {element} is degenerate (signed area {area:e}, or a non-convex quadrilateral)"
    )]
    Degenerate {
        /// Element tag.
        element: u64,
        /// Its signed area.
        area: f64,
    },
    /// An element oriented against the others.
    #[error(
        "element {element} is inverted: it is oriented {orientation} while {majority} of the {total} \
         elements are oriented the other way"
    )]
    Inverted {
        /// Element tag.
        element: u64,
        /// "clockwise" or "counter-clockwise".
        orientation: &'static str,
        /// Elements of the other orientation.
        majority: usize,
        /// All 2-D elements.
        total: usize,
    },
    /// An edge shared by more than two elements, or by two on the same side of it.
    #[error(
        "the edge between nodes {a} and {b} belongs to {count} elements, two of them on the same \
         side of it (overlapping or folded elements)"
    )]
    NonManifold {
        /// Node tag.
        a: u64,
        /// Node tag.
        b: u64,
        /// Elements sharing it.
        count: usize,
    },
    /// The boundary is not one closed loop.
    #[error(
        "has a boundary of {loops} closed loop(s){pinch}; a body must be one piece without holes \
         (mesh each piece as its own body)"
    )]
    Boundary {
        /// Loops found.
        loops: usize,
        /// " touching itself at node N" when a boundary node starts two edges, " left open at
        /// node N" when a boundary chain ends there.
        pinch: String,
    },
}

/// Reads a Gmsh MSH 4.1 file (ASCII or binary).  `label` names the file in errors (the path as
/// written in the scene).
pub fn read_msh(path: &Path, label: &str) -> Result<ImportedMesh, GmshError> {
    let err = |problem| GmshError {
        path: label.to_string(),
        problem,
    };
    let bytes = std::fs::read(path).map_err(|e| err(GmshProblem::Read(e.to_string())))?;
    parse_msh(&bytes, label)
}

/// Parses the bytes of a Gmsh MSH 4.1 file (ASCII or binary); see [`read_msh`].
pub fn parse_msh(bytes: &[u8], label: &str) -> Result<ImportedMesh, GmshError> {
    import(bytes, label).map_err(|problem| GmshError {
        path: label.to_string(),
        problem,
    })
}

/// The `$PhysicalNames` section: `(dim, tag) → name`.  The section is text in ASCII and binary
/// files alike; `mshio` 0.4 skips it.  Malformed lines are ignored (their groups keep their tag as
/// name).
pub fn physical_names(bytes: &[u8]) -> HashMap<(i32, i32), String> {
    let mut names = HashMap::new();
    let start_tag = b"$PhysicalNames";
    let Some(start) = bytes.windows(start_tag.len()).position(|w| w == start_tag) else {
        return names;
    };
    let rest = &bytes[start + start_tag.len()..];
    let end_tag = b"$EndPhysicalNames";
    let end = rest
        .windows(end_tag.len())
        .position(|w| w == end_tag)
        .unwrap_or(rest.len());
    let text = String::from_utf8_lossy(&rest[..end]);
    for line in text.lines().skip(1) {
        let mut parts = line.trim().splitn(3, char::is_whitespace);
        let (Some(dim), Some(tag), Some(name)) = (parts.next(), parts.next(), parts.next()) else {
            continue;
        };
        let (Ok(dim), Ok(tag)) = (dim.parse::<i32>(), tag.parse::<i32>()) else {
            continue;
        };
        let name = name.trim().trim_matches('"').to_string();
        names.insert((dim, tag), name);
    }
    names
}

/// Twice the signed area of a polygon given by node indices.
fn twice_area(nodes: &[Point], cell: &[usize]) -> f64 {
    let n = cell.len();
    (0..n)
        .map(|i| {
            let (p, q) = (nodes[cell[i]], nodes[cell[(i + 1) % n]]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum()
}

/// True when every corner of the cell turns the same way as its area (convex, non-degenerate).
fn corners_agree(nodes: &[Point], cell: &[usize], sign: f64, tol: f64) -> bool {
    let n = cell.len();
    (0..n).all(|i| {
        let (a, b, c) = (
            nodes[cell[(i + n - 1) % n]],
            nodes[cell[i]],
            nodes[cell[(i + 1) % n]],
        );
        let cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
        sign * cross > tol
    })
}

fn import(bytes: &[u8], label: &str) -> Result<ImportedMesh, GmshProblem> {
    // mshio 0.4 still has `unimplemented!`/`expect` on a few malformed inputs: a panic there is
    // turned into a parse error rather than taking the program down.
    let parsed = std::panic::catch_unwind(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| {
            let text = e.to_string();
            text.lines().take(6).collect::<Vec<_>>().join("; ")
        })
    })
    .map_err(|_| GmshProblem::Parse("the parser stopped on malformed input".into()))?
    .map_err(GmshProblem::Parse)?;
    let data = parsed.data;

    // Nodes by tag.  mshio keeps the tags only when they are sparse; dense tags run from the
    // section's smallest tag through the blocks in file order (as Gmsh writes them).
    let mut coords: HashMap<u64, [f64; 3]> = HashMap::new();
    if let Some(nodes) = &data.nodes {
        let mut next = nodes.min_node_tag;
        for block in &nodes.node_blocks {
            let tags: Vec<u64> = match &block.node_tags {
                Some(map) => {
                    let mut t = vec![0; block.nodes.len()];
                    for (tag, &i) in map {
                        if let Some(slot) = t.get_mut(i) {
                            *slot = *tag;
                        }
                    }
                    if map.len() != block.nodes.len() {
                        // Two nodes of the block share a tag: the map kept one.
                        let mut seen = BTreeSet::new();
                        let dup = t.iter().find(|x| !seen.insert(**x)).copied().unwrap_or(0);
                        return Err(GmshProblem::DuplicateTag(dup));
                    }
                    t
                }
                None => {
                    let t = (0..block.nodes.len() as u64)
                        .map(|i| next.saturating_add(i))
                        .collect();
                    next = next.saturating_add(block.nodes.len() as u64);
                    t
                }
            };
            for (tag, node) in tags.into_iter().zip(&block.nodes) {
                if coords.insert(tag, [node.x, node.y, node.z]).is_some() {
                    return Err(GmshProblem::DuplicateTag(tag));
                }
            }
        }
    }

    // Entities → physical tags; physical names.
    let mut entity_groups: HashMap<(i32, i32), Vec<i32>> = HashMap::new();
    if let Some(e) = &data.entities {
        for p in &e.points {
            entity_groups.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &e.curves {
            entity_groups.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &e.surfaces {
            entity_groups.insert((2, s.tag), s.physical_tags.clone());
        }
    }
    let names = physical_names(bytes);
    let group_name = |dim: i32, tag: i32| {
        names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| tag.to_string())
    };

    // Elements: 2-D cells, and the node tags / edges of every physical group.
    let mut triangles: Vec<(u64, [u64; 3])> = Vec::new();
    let mut quads: Vec<(u64, [u64; 4])> = Vec::new();
    // group name → (dim, node tags, line-element edges as sorted tag pairs)
    type RawGroup = (i32, BTreeSet<u64>, BTreeSet<[u64; 2]>);
    let mut raw_groups: BTreeMap<String, RawGroup> = BTreeMap::new();
    if let Some(elements) = &data.elements {
        for block in &elements.element_blocks {
            let count = block.elements.len();
            match block.element_type {
                ElementType::Tri3 | ElementType::Qua4 | ElementType::Lin2 | ElementType::Pnt => {}
                other => {
                    return Err(GmshProblem::UnsupportedElement {
                        name: format!("{other:?}"),
                        code: other as i32,
                        dim: block.entity_dim,
                        count,
                    })
                }
            }
            let physical = entity_groups
                .get(&(block.entity_dim, block.entity_tag))
                .cloned()
                .unwrap_or_default();
            for el in &block.elements {
                match block.element_type {
                    ElementType::Tri3 if el.nodes.len() == 3 => {
                        triangles.push((el.element_tag, [el.nodes[0], el.nodes[1], el.nodes[2]]))
                    }
                    ElementType::Qua4 if el.nodes.len() == 4 => quads.push((
                        el.element_tag,
                        [el.nodes[0], el.nodes[1], el.nodes[2], el.nodes[3]],
                    )),
                    _ => {}
                }
                for &tag in &physical {
                    let g = raw_groups
                        .entry(group_name(block.entity_dim, tag))
                        .or_insert_with(|| (block.entity_dim, BTreeSet::new(), BTreeSet::new()));
                    g.0 = g.0.max(block.entity_dim);
                    g.1.extend(el.nodes.iter().copied());
                    if block.element_type == ElementType::Lin2 && el.nodes.len() == 2 {
                        let (a, b) = (el.nodes[0], el.nodes[1]);
                        g.2.insert([a.min(b), a.max(b)]);
                    }
                }
            }
        }
    }
    if triangles.is_empty() && quads.is_empty() {
        return Err(GmshProblem::NoElements);
    }
    if !triangles.is_empty() && !quads.is_empty() {
        return Err(GmshProblem::MixedElements {
            triangles: triangles.len(),
            quads: quads.len(),
        });
    }
    let cells_tags: Vec<(u64, Vec<u64>)> = if quads.is_empty() {
        triangles.iter().map(|(t, n)| (*t, n.to_vec())).collect()
    } else {
        quads.iter().map(|(t, n)| (*t, n.to_vec())).collect()
    };

    // Used nodes, numbered in tag order.
    let mut used: BTreeSet<u64> = BTreeSet::new();
    for (element, nodes) in &cells_tags {
        for &n in nodes {
            if !coords.contains_key(&n) {
                return Err(GmshProblem::UnknownNode {
                    element: *element,
                    node: n,
                });
            }
            used.insert(n);
        }
    }
    let tags: Vec<u64> = used.into_iter().collect();
    let index: HashMap<u64, usize> = tags.iter().enumerate().map(|(i, t)| (*t, i)).collect();
    let mut z_min = f64::INFINITY;
    let mut z_max = f64::NEG_INFINITY;
    let mut nodes: Vec<Point> = Vec::with_capacity(tags.len());
    for &t in &tags {
        let c = coords[&t];
        if !c.iter().all(|v| v.is_finite()) {
            return Err(GmshProblem::NotFinite(t));
        }
        z_min = z_min.min(c[2]);
        z_max = z_max.max(c[2]);
        nodes.push([c[0], c[1]]);
    }
    let bbox = crate::geometry::bounding_box(nodes.iter());
    let size = (bbox[1] - bbox[0]).hypot(bbox[3] - bbox[2]);
    let tol = crate::geometry::REGION_TOLERANCE * size;
    if z_max - z_min > tol {
        return Err(GmshProblem::NotPlanar { z_min, z_max });
    }
    // Coincident nodes: sweep along x.
    let mut order: Vec<usize> = (0..nodes.len()).collect();
    order.sort_by(|&a, &b| nodes[a][0].total_cmp(&nodes[b][0]));
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if nodes[j][0] - nodes[i][0] > tol {
                break;
            }
            if (nodes[j][1] - nodes[i][1]).abs() <= tol {
                let (a, b) = (tags[i].min(tags[j]), tags[i].max(tags[j]));
                return Err(GmshProblem::DuplicateNodes {
                    a,
                    b,
                    x: nodes[i][0],
                    y: nodes[i][1],
                });
            }
        }
    }

    // Cells, orientation.
    let mut cells: Vec<Vec<usize>> = cells_tags
        .iter()
        .map(|(_, n)| n.iter().map(|t| index[t]).collect())
        .collect();
    let areas: Vec<f64> = cells.iter().map(|c| 0.5 * twice_area(&nodes, c)).collect();
    let area_tol = tol * size;
    for (k, a) in areas.iter().enumerate() {
        if a.abs() <= area_tol {
            return Err(GmshProblem::Degenerate {
                element: cells_tags[k].0,
                area: *a,
            });
        }
    }
    let ccw = areas.iter().filter(|a| **a > 0.0).count();
    let cw = areas.len() - ccw;
    let sign = if ccw >= cw { 1.0 } else { -1.0 };
    if let Some(k) = areas.iter().position(|a| a.signum() != sign) {
        return Err(GmshProblem::Inverted {
            element: cells_tags[k].0,
            orientation: if areas[k] > 0.0 {
                "counter-clockwise"
            } else {
                "clockwise"
            },
            majority: ccw.max(cw),
            total: areas.len(),
        });
    }
    for (k, c) in cells.iter().enumerate() {
        if !corners_agree(&nodes, c, sign, tol * tol) {
            return Err(GmshProblem::Degenerate {
                element: cells_tags[k].0,
                area: areas[k],
            });
        }
    }
    if sign < 0.0 {
        for c in &mut cells {
            c.reverse();
        }
    }

    // Boundary: edges used once, oriented as in their (counter-clockwise) cell.
    let mut edge_use: HashMap<[usize; 2], (usize, [usize; 2])> = HashMap::new();
    for c in &cells {
        let n = c.len();
        for i in 0..n {
            let (a, b) = (c[i], c[(i + 1) % n]);
            let e = edge_use.entry([a.min(b), a.max(b)]).or_insert((0, [a, b]));
            e.0 += 1;
            // Two elements on the same side of an edge overlap (a folded mesh).
            if e.0 == 2 && e.1 == [a, b] {
                return Err(GmshProblem::NonManifold {
                    a: tags[a],
                    b: tags[b],
                    count: 2,
                });
            }
        }
    }
    let mut boundary: Vec<[usize; 2]> = Vec::new();
    for (key, (count, oriented)) in &edge_use {
        if *count > 2 {
            return Err(GmshProblem::NonManifold {
                a: tags[key[0]],
                b: tags[key[1]],
                count: *count,
            });
        }
        if *count == 1 {
            boundary.push(*oriented);
        }
    }
    boundary.sort_unstable();
    // One closed loop.
    let mut next: HashMap<usize, usize> = HashMap::new();
    for &[a, b] in &boundary {
        if next.insert(a, b).is_some() {
            return Err(GmshProblem::Boundary {
                loops: 0,
                pinch: format!(" touching itself at node {}", tags[a]),
            });
        }
    }
    let mut outline: Vec<usize> = Vec::new();
    let mut loops = 0;
    let mut visited: BTreeSet<usize> = BTreeSet::new();
    for &[start, _] in &boundary {
        if visited.contains(&start) {
            continue;
        }
        loops += 1;
        let mut at = start;
        let mut this = Vec::new();
        while visited.insert(at) {
            this.push(at);
            at = match next.get(&at) {
                Some(&n) => n,
                None => {
                    return Err(GmshProblem::Boundary {
                        loops,
                        pinch: format!(" left open at node {}", tags[at]),
                    })
                }
            };
        }
        if outline.is_empty() {
            outline = this;
        }
    }
    if loops != 1 {
        return Err(GmshProblem::Boundary {
            loops,
            pinch: String::new(),
        });
    }
    // Order the boundary edges along the loop (deterministic, like the internal mesher's).
    let boundary: Vec<[usize; 2]> = outline
        .iter()
        .filter_map(|&a| next.get(&a).map(|&b| [a, b]))
        .collect();
    let outline_points: Vec<Point> = outline.iter().map(|&a| nodes[a]).collect();

    // Groups in mesh numbering.
    let mut groups = BTreeMap::new();
    for (name, (dim, node_tags, line_edges)) in raw_groups {
        let group_nodes: Vec<usize> = node_tags
            .iter()
            .filter_map(|t| index.get(t).copied())
            .collect();
        let mut edges: Vec<[usize; 2]> = boundary
            .iter()
            .copied()
            .filter(|&[a, b]| {
                if dim == 1 {
                    let (ta, tb) = (tags[a], tags[b]);
                    line_edges.contains(&[ta.min(tb), ta.max(tb)])
                } else {
                    group_nodes.binary_search(&a).is_ok() && group_nodes.binary_search(&b).is_ok()
                }
            })
            .collect();
        edges.sort_unstable();
        groups.insert(
            name,
            MeshGroup {
                dim: dim.clamp(0, 2) as u8,
                nodes: group_nodes,
                edges,
            },
        );
    }

    let cells = if quads.is_empty() {
        Cells::Triangles(cells.iter().map(|c| [c[0], c[1], c[2]]).collect())
    } else {
        Cells::Quads(cells.iter().map(|c| [c[0], c[1], c[2], c[3]]).collect())
    };
    Ok(ImportedMesh {
        path: label.to_string(),
        mesh: Mesh {
            nodes,
            cells,
            boundary,
        },
        outline: outline_points,
        groups,
    })
}
