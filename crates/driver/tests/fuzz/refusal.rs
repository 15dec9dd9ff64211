//! The properties of a refusal: it names the key at fault, and the binary — the only path that
//! can write — refuses the same scene with exit 1 (3 for a resource limit) and writes nothing.

use std::path::Path;
use std::process::Command;

use signorini_core::scene::Scene;

use super::gen::{Broken, Case};
use super::props::{limits, Finding};

/// The scene file of a case inside its directory (beside its Gmsh files).
pub const SCENE_FILE: &str = "scene.toml";

/// True when `message` holds `key` as a whole word (not inside a longer name: `hmax` is not
/// named by `refine_hmax`, `x` not by `max`).
pub fn names(message: &str, key: &str) -> bool {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    !key.is_empty()
        && message.match_indices(key).any(|(i, _)| {
            let before = message[..i].chars().next_back();
            let after = message[i + key.len()..].chars().next();
            !before.is_some_and(word) && !after.is_some_and(word)
        })
}

/// The keys a scene's text sets (`key = value` lines).
fn keys_of(toml: &str) -> impl Iterator<Item = &str> {
    toml.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| l.split_once(" = ").map(|(k, _)| k.trim()))
}

/// Where a case was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Parsing or validating the scene: the binary must exit 1.
    Scene,
    /// `check` (the solve ran, so the binary is not asked).
    Check,
    /// The solve, before its backend ran (meshing, assembly, memory): exit 1 or 3.
    Solve,
    /// The backend asked for cannot run this problem, or its own allocation would not fit (not
    /// `check`'s to judge: it verifies what solve verifies before its backend runs): exit 1 or 3,
    /// and naming the backend names what is at fault.
    Backend,
}

/// The message the scene `toml` (in `dir`) is refused with by parsing or `check`, if any.
fn refusal_of(toml: &str, dir: &Path) -> Option<String> {
    match Scene::from_toml_in(toml, dir) {
        Err(e) => Some(e.to_string()),
        Ok(scene) => signorini::check::check(&scene, &limits())
            .err()
            .map(|e| e.to_string()),
    }
}

/// Whether `message` refusing a case names what is at fault: for a broken scene, the very key
/// the mutation broke (or the scene was already refused, with this message, before it was
/// broken); otherwise some key the scene sets.
fn names_its_key(case: &Case, dir: &Path, message: &str, stage: Stage) -> Result<(), String> {
    match &case.must_refuse {
        Some(Broken { key, why, clean }) => {
            let earlier = || clean.as_deref().and_then(|c| refusal_of(c, dir));
            if names(message, key) || earlier().as_deref() == Some(message) {
                Ok(())
            } else {
                Err(format!("does not name `{key}` ({why}): {message}"))
            }
        }
        None if keys_of(&case.toml).any(|k| names(message, k)) => Ok(()),
        None if stage == Stage::Backend && names(message, case.backend.name()) => Ok(()),
        None => Err(format!("names no key of the scene: {message}")),
    }
}

/// The binary's `solve` on the case's scene file: refused with an expected exit code (`input`:
/// 1 only; else 1 or 3) and nothing written — an absent output directory stays absent, an
/// existing one (half the cases, by the scene's length) keeps exactly its earlier file.
fn binary_refuses(case: &Case, dir: &Path, input: bool) -> Result<(), String> {
    let out = dir.join("cli-out");
    let earlier = "an earlier run's result";
    let existing = case.toml.len() % 2 == 1;
    if existing {
        std::fs::create_dir(&out)
            .and_then(|_| std::fs::write(out.join("result.json"), earlier))
            .map_err(|e| format!("cannot prepare {}: {e}", out.display()))?;
    }
    let run = Command::new(env!("CARGO_BIN_EXE_signorini"))
        .arg("solve")
        .arg(dir.join(SCENE_FILE))
        .args(["--backend", case.backend.name(), "--max-elements"])
        .arg(limits().max_elements.to_string())
        .arg("--out")
        .arg(&out)
        .output()
        .map_err(|e| format!("cannot run the binary: {e}"))?;
    let code = run.status.code();
    let expected: &[i32] = if input { &[1] } else { &[1, 3] };
    let mut problems = Vec::new();
    if !code.is_some_and(|c| expected.contains(&c)) {
        problems.push(format!(
            "exit {code:?}, expected {expected:?} ({})",
            String::from_utf8_lossy(&run.stderr).trim()
        ));
    }
    let left: Vec<String> = std::fs::read_dir(&out)
        .map(|d| {
            d.filter_map(Result::ok)
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    let kept = std::fs::read_to_string(out.join("result.json")).ok();
    let unchanged = if existing {
        left == ["result.json"] && kept.as_deref() == Some(earlier)
    } else {
        !out.exists()
    };
    if !unchanged {
        problems.push(format!("the output directory holds {left:?} afterwards"));
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(problems.join("; "))
    }
}

/// Every property of a refusal `message` of the case in `dir` at `stage`.
pub fn check_refusal(case: &Case, dir: &Path, message: &str, stage: Stage) -> Vec<Finding> {
    let mut found = Vec::new();
    if let Err(detail) = names_its_key(case, dir, message, stage) {
        found.push(Finding {
            property: "refusal-names-key",
            detail,
        });
    }
    if stage != Stage::Check {
        let input = stage == Stage::Scene || case.must_refuse.is_some();
        if let Err(e) = binary_refuses(case, dir, input) {
            found.push(Finding {
                property: "refusal-writes-nothing",
                detail: format!("signorini solve: {e}; refused with: {message}"),
            });
        }
    }
    found
}
