//! The quasi-static load path (`[[step]]`; docs/scene.md, "Load steps").
//!
//! Loads and prescribed displacements fall into groups that share one factor along the path:
//! group 0 holds every unnamed `[[neumann]]`, `[[dirichlet]]` and the body force (factor 1
//! throughout), group k ≥ 1 the named support or load k − 1 of [`crate::scene::Scene::load_names`].
//! Each group's nodal loads (all DOFs) and prescribed values (at the fixed DOFs) are computed
//! once; the load and the prescribed values of an increment are their sums weighted by the
//! increment's factors, so an increment needs no assembly, only the lifting K_FD u_D and B_D u_D
//! (`crate::solve`).  Step k goes from the factors at the end of step k − 1 (all 0 before the
//! first) to its own in `increments` equal increments.

use super::ModelError;
use crate::effects::{Contribution, Discretisation, Effects, ModelParts, Tractions};
use crate::scene::{LoadStep, Scene};

/// One group's share of the loads.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadGroup {
    /// Nodal forces on all DOFs.
    pub load: Vec<f64>,
    /// Prescribed values at the model's fixed DOFs (in `fixed_dofs` order).
    pub prescribed: Vec<f64>,
}

/// One increment of the path.
#[derive(Debug, Clone, PartialEq)]
pub struct Increment {
    /// The step (1-based).
    pub step: usize,
    /// The increment within the step (1-based).
    pub increment: usize,
    /// The factors of the named loads at the increment's end.
    pub factors: Vec<f64>,
}

/// The load path of a scene with `[[step]]` tables.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadPath {
    /// Group 0 (unnamed, factor 1), then one per named load.
    pub groups: Vec<LoadGroup>,
    /// Every increment, in order.
    pub increments: Vec<Increment>,
}

impl LoadPath {
    /// The path of `scene` (`None` without `[[step]]`): each group's loads from the scene's
    /// load effects, its prescribed values from the support that fixed each DOF (`fixed`).
    pub(super) fn of(
        scene: &Scene,
        effects: &Effects<'_>,
        on: Discretisation<'_>,
        fixed: &[Option<(f64, usize)>],
    ) -> Result<Option<Self>, ModelError> {
        if scene.steps.is_empty() {
            return Ok(None);
        }
        let names: Vec<Option<&str>> = std::iter::once(None)
            .chain(scene.load_names.iter().map(|n| Some(n.as_str())))
            .collect();
        let mut groups = Vec::with_capacity(names.len());
        for (g, name) in names.iter().enumerate() {
            let mut parts = ModelParts::empty(on.dofs.len());
            if let Some(tractions) = &effects.tractions {
                let only = Tractions {
                    list: tractions
                        .list
                        .iter()
                        .filter(|l| l.name == *name)
                        .cloned()
                        .collect(),
                    ..tractions.clone()
                };
                only.contribute(on, &mut parts)?;
            }
            if let (Some(body_force), 0) = (&effects.body_force, g) {
                body_force.contribute(on, &mut parts)?;
            }
            let prescribed = fixed
                .iter()
                .flatten()
                .map(|&(value, support)| {
                    let owner = scene.dirichlet.get(support).and_then(|d| d.name.as_deref());
                    if owner == *name {
                        value
                    } else {
                        0.0
                    }
                })
                .collect();
            groups.push(LoadGroup {
                load: parts.load,
                prescribed,
            });
        }
        Ok(Some(Self {
            groups,
            increments: increments(&scene.steps),
        }))
    }

    /// The nodal loads (all DOFs) at the named loads' `factors`.
    pub fn load_at(&self, factors: &[f64]) -> Vec<f64> {
        self.combine(factors, |g| &g.load)
    }

    /// The prescribed values (at the fixed DOFs) at the named loads' `factors`.
    pub fn prescribed_at(&self, factors: &[f64]) -> Vec<f64> {
        self.combine(factors, |g| &g.prescribed)
    }

    /// The factors of the last increment (the load the model is assembled at).
    pub fn final_factors(&self) -> &[f64] {
        self.increments.last().map_or(&[], |i| &i.factors)
    }

    /// Σ_g factor_g · part(g), group 0 with factor 1.
    fn combine(&self, factors: &[f64], part: impl Fn(&LoadGroup) -> &Vec<f64>) -> Vec<f64> {
        let mut sum = self
            .groups
            .first()
            .map(|g| part(g).clone())
            .unwrap_or_default();
        for (g, &factor) in self.groups.iter().skip(1).zip(factors) {
            if factor != 0.0 {
                for (s, v) in sum.iter_mut().zip(part(g)) {
                    *s += factor * v;
                }
            }
        }
        sum
    }
}

/// The increments of `steps`: step k in its increments from the previous step's factors (0
/// before the first), linearly.
pub fn increments(steps: &[LoadStep]) -> Vec<Increment> {
    let mut list = Vec::new();
    let mut start = vec![0.0; steps.first().map_or(0, |s| s.factors.len())];
    for (k, step) in steps.iter().enumerate() {
        for i in 1..=step.increments {
            let t = i as f64 / step.increments as f64;
            let factors = start
                .iter()
                .zip(&step.factors)
                .map(|(a, b)| {
                    if i == step.increments {
                        *b
                    } else {
                        a + t * (b - a)
                    }
                })
                .collect();
            list.push(Increment {
                step: k + 1,
                increment: i,
                factors,
            });
        }
        start.clone_from(&step.factors);
    }
    list
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn increments_go_linearly_from_each_step_s_start_to_its_factors() {
        let steps = [
            LoadStep {
                factors: vec![1.0, 0.0],
                increments: 2,
            },
            LoadStep {
                factors: vec![1.0, 3.0],
                increments: 3,
            },
        ];
        let got: Vec<(usize, usize, Vec<f64>)> = increments(&steps)
            .into_iter()
            .map(|i| (i.step, i.increment, i.factors))
            .collect();
        assert_eq!(
            got,
            vec![
                (1, 1, vec![0.5, 0.0]),
                (1, 2, vec![1.0, 0.0]),
                (2, 1, vec![1.0, 1.0]),
                (2, 2, vec![1.0, 2.0]),
                (2, 3, vec![1.0, 3.0]),
            ]
        );
    }
}
