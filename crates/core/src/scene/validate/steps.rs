//! Names of supports and loads, and `[[step]]`: the quasi-static load path.  Names are
//! printable, non-empty and unique among all `[[dirichlet]]` and `[[neumann]]` sections; a step
//! names only known loads, with finite factors, in at least one increment.

use super::values::{check_finite, check_text};
use crate::scene::draft::{DraftDirichlet, DraftNeumann};
use crate::scene::file::StepSection;
use crate::scene::types::LoadStep;
use crate::scene::SceneError;

use super::loads::neumann_label;
use super::supports::dirichlet_label;

/// The names of the supports (in order), then of the loads; refuses an empty, unprintable or
/// repeated name, naming the section.
pub(super) fn load_names<'a>(
    dirichlet: &[DraftDirichlet],
    neumann: &[DraftNeumann],
    body: impl Fn(usize) -> &'a str,
) -> Result<Vec<String>, SceneError> {
    let labelled = dirichlet
        .iter()
        .enumerate()
        .map(|(i, d)| (dirichlet_label(i, body(d.body)), &d.name))
        .chain(
            neumann
                .iter()
                .enumerate()
                .map(|(i, n)| (neumann_label(i, body(n.body)), &n.name)),
        );
    let mut names: Vec<String> = Vec::new();
    for (s, name) in labelled {
        let Some(name) = name else { continue };
        if name.trim().is_empty() {
            return Err(SceneError::invalid(&s, "name", "must not be empty"));
        }
        check_text(&s, "name", name)?;
        if names.contains(name) {
            return Err(SceneError::invalid(
                &s,
                "name",
                format!("{name:?} is used twice; names of supports and loads must be unique"),
            ));
        }
        names.push(name.clone());
    }
    Ok(names)
}

/// The `[[step]]` tables: each names known loads only, with finite factors, and ≥ 1 increment.
pub(super) fn validate_steps(
    sections: Vec<StepSection>,
    names: &[String],
) -> Result<Vec<LoadStep>, SceneError> {
    let mut steps = Vec::with_capacity(sections.len());
    for (i, step) in sections.into_iter().enumerate() {
        let s = format!("step #{}", i + 1);
        let increments = match step.increments {
            None => 1,
            Some(n) if n >= 1 => usize::try_from(n).unwrap_or(usize::MAX),
            Some(n) => {
                return Err(SceneError::invalid(
                    &s,
                    "increments",
                    format!("must be at least 1, got {n}"),
                ))
            }
        };
        let mut factors = vec![0.0; names.len()];
        for (name, factor) in step.loads {
            let Some(k) = names.iter().position(|n| *n == name) else {
                let known = if names.is_empty() {
                    "no [[dirichlet]] or [[neumann]] section has a `name`".to_string()
                } else {
                    format!("the named supports and loads are {names:?}")
                };
                return Err(SceneError::invalid(
                    &s,
                    "loads",
                    format!("names {name:?}, which is no support or load: {known}"),
                ));
            };
            check_finite(&s, "loads", &[factor])?;
            factors[k] = factor;
        }
        steps.push(LoadStep {
            factors,
            increments,
        });
    }
    Ok(steps)
}
