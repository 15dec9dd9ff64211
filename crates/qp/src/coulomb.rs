//! Coulomb friction's coupling of box rows to normal rows.
//!
//! A Tresca row of a [`ConstraintBlock::Box`] has a fixed bound |λᵢ| ≤ sᵢ, and the problem is a
//! QP.  Coulomb's bound is μᵢ max(0, λₙ) with λₙ the multiplier of the row's *normal* row: the
//! bound depends on the answer, and the problem is no longer a QP (it has no objective whose
//! minimiser it is).  [`CoulombRows`] names those rows in a problem whose box block holds them
//! (with any provisional bounds) and judges an answer with its own bounds: the residuals of
//! [`crate::kkt_residuals`] with sᵢ = μᵢ max(0, λₙ) — Coulomb's conditions exactly.
//!
//! Two ways to solve such a problem: the fixed point over Tresca problems (any backend that
//! solves box rows; the core drives it) and a backend's own method for the coupled conditions
//! ([`crate::QpBackend::solve_coulomb`], e.g. pdas's semismooth Newton).  [`CoulombMethod`]
//! chooses.

use serde::Serialize;

use super::blocks::{row_sets, ConstraintBlock, RowSet};
use super::problem::{QpError, QpProblem};
use super::residuals::{kkt_residuals_in, KktResiduals, ResidualScales};

/// How Coulomb rows are solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum CoulombMethod {
    /// The backend's own method when it has one ([`crate::QpBackend::solves_coulomb`]), else
    /// the fixed point.
    #[default]
    Auto,
    /// The fixed point over Tresca problems, whatever the backend.
    FixedPoint,
    /// The backend's own method; refused by a backend without one.
    Newton,
}

impl CoulombMethod {
    /// Every method, in declaration order.
    pub const ALL: [CoulombMethod; 3] = [
        CoulombMethod::Auto,
        CoulombMethod::FixedPoint,
        CoulombMethod::Newton,
    ];

    /// The method named `word` ([`CoulombMethod::as_str`]), if any.
    pub fn from_name(word: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.as_str() == word)
    }

    /// The word used on the command line and in reports.
    pub fn as_str(self) -> &'static str {
        match self {
            CoulombMethod::Auto => "auto",
            CoulombMethod::FixedPoint => "fixed-point",
            CoulombMethod::Newton => "newton",
        }
    }
}

/// One Coulomb row: the bound of box row `row` is `mu` max(0, λ of `normal_row`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoulombLink {
    /// The row (an index into the problem's rows) in a box block.
    pub row: usize,
    /// Its normal row, in a non-negative block.
    pub normal_row: usize,
    /// The friction coefficient μ ≥ 0.
    pub mu: f64,
}

/// The Coulomb rows of a problem (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct CoulombRows {
    links: Vec<CoulombLink>,
    /// Per link: (the box block's index in `problem.blocks`, the row's index in it).
    slots: Vec<(usize, usize)>,
}

impl CoulombRows {
    /// The Coulomb rows `links` of `problem`: each row in a box block, each normal row in a
    /// non-negative block, no row twice, μ finite and ≥ 0; refused naming the link otherwise.
    pub fn new(problem: &QpProblem, links: Vec<CoulombLink>) -> Result<Self, QpError> {
        let sets: Vec<RowSet> = row_sets(&problem.blocks).collect();
        let mut seen = vec![false; sets.len()];
        let mut slots = Vec::with_capacity(links.len());
        for (k, link) in links.iter().enumerate() {
            let bad = |why: &str| {
                QpError::Dimensions(format!(
                    "Coulomb link {k} (row {}, normal row {}, μ {}): {why}",
                    link.row, link.normal_row, link.mu
                ))
            };
            if !matches!(sets.get(link.row), Some(RowSet::Box(_))) {
                return Err(bad("the row is not in a box block"));
            }
            if !matches!(sets.get(link.normal_row), Some(RowSet::NonNegative)) {
                return Err(bad("the normal row is not in a non-negative block"));
            }
            if !(link.mu.is_finite() && link.mu >= 0.0) {
                return Err(bad("μ must be finite and ≥ 0"));
            }
            if std::mem::replace(&mut seen[link.row], true) {
                return Err(bad("the row is linked twice"));
            }
            slots.push(slot_of(&problem.blocks, link.row));
        }
        Ok(Self { links, slots })
    }

    /// The links, in the order given.
    pub fn links(&self) -> &[CoulombLink] {
        &self.links
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.links.is_empty()
    }

    /// Coulomb's bound μ max(0, λₙ) of each link for the multipliers λ of every row.
    pub fn bounds(&self, multipliers: &[f64]) -> Vec<f64> {
        self.links
            .iter()
            .map(|l| {
                l.mu * multipliers
                    .get(l.normal_row)
                    .copied()
                    .unwrap_or(0.0)
                    .max(0.0)
            })
            .collect()
    }

    /// Writes `bounds` (one per link) into the box blocks of `problem`.
    pub fn set_bounds(&self, problem: &mut QpProblem, bounds: &[f64]) {
        for (&(block, i), s) in self.slots.iter().zip(bounds) {
            if let Some(ConstraintBlock::Box { bounds: b }) = problem.blocks.get_mut(block) {
                b[i] = *s;
            }
        }
    }

    /// Each row's multiplier set with the Coulomb rows bounded by μ max(0, λₙ) of `multipliers`.
    pub fn row_sets(&self, problem: &QpProblem, multipliers: &[f64]) -> Vec<RowSet> {
        let mut sets: Vec<RowSet> = row_sets(&problem.blocks).collect();
        for (link, s) in self.links.iter().zip(self.bounds(multipliers)) {
            sets[link.row] = RowSet::Box(s);
        }
        sets
    }

    /// The KKT residuals of (x, λ) with every Coulomb row judged by its own bound
    /// μ max(0, λₙ): Coulomb's conditions.
    pub fn residuals(
        &self,
        problem: &QpProblem,
        scales: &ResidualScales,
        x: &[f64],
        multipliers: &[f64],
    ) -> KktResiduals {
        if multipliers.len() != problem.rows() {
            return KktResiduals::UNMEASURABLE;
        }
        let sets = self.row_sets(problem, multipliers);
        kkt_residuals_in(problem, &sets, scales, x, multipliers)
    }
}

/// (block index, index within the block) of global row `row`.
fn slot_of(blocks: &[ConstraintBlock], row: usize) -> (usize, usize) {
    let mut start = 0;
    for (b, block) in blocks.iter().enumerate() {
        if row < start + block.rows() {
            return (b, row - start);
        }
        start += block.rows();
    }
    (blocks.len(), 0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::examples::laplacian_with_bounds;

    /// A problem of 4 unknowns with one normal row (0) and one box row (1).
    fn problem() -> QpProblem {
        let p = laplacian_with_bounds(4, 2);
        p.with_blocks(vec![
            ConstraintBlock::NonNegative { rows: 1 },
            ConstraintBlock::Box { bounds: vec![5.0] },
        ])
        .unwrap()
    }

    #[test]
    fn bounds_follow_the_normal_multiplier_and_vanish_in_tension() {
        let p = problem();
        let rows = CoulombRows::new(
            &p,
            vec![CoulombLink {
                row: 1,
                normal_row: 0,
                mu: 0.3,
            }],
        )
        .unwrap();
        assert_eq!(rows.bounds(&[2.0, 0.0]), vec![0.3 * 2.0]);
        assert_eq!(rows.bounds(&[-2.0, 0.0]), vec![0.0]);
        let mut q = p.clone();
        rows.set_bounds(&mut q, &[0.25]);
        assert_eq!(q.blocks[1], ConstraintBlock::Box { bounds: vec![0.25] });
        assert_eq!(
            rows.row_sets(&p, &[1.0, 0.0]),
            vec![RowSet::NonNegative, RowSet::Box(0.3)]
        );
    }

    #[test]
    fn links_to_the_wrong_kind_of_row_are_refused_by_name() {
        let p = problem();
        for (row, normal_row, mu, why) in [
            (0, 0, 0.3, "not in a box block"),
            (1, 1, 0.3, "normal row is not"),
            (1, 0, f64::NAN, "finite"),
            (1, 0, -1.0, "finite"),
            (7, 0, 0.3, "not in a box block"),
        ] {
            let e = CoulombRows::new(
                &p,
                vec![CoulombLink {
                    row,
                    normal_row,
                    mu,
                }],
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains(why) && e.contains("Coulomb link 0"), "{e}");
        }
        let twice = vec![
            CoulombLink {
                row: 1,
                normal_row: 0,
                mu: 0.3,
            };
            2
        ];
        let e = CoulombRows::new(&p, twice).unwrap_err().to_string();
        assert!(e.contains("linked twice"), "{e}");
    }
}
