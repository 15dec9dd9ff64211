//! The published contract: the JSON Schemas of the scene file, of `result.json`, of a suite's
//! expectation file and of `suite.json` (`signorini schema scene|result|expectation|suite`),
//! generated from the Rust types that read and write them so
//! that they cannot drift; and the provenance a result records (program, scene file hash, backend
//! settings, machine).

use std::path::Path;

use schemars::generate::SchemaSettings;
use schemars::transform::RecursiveTransform;
use schemars::Schema;
use signorini_core::report::{BackendSettings, Provenance, RunReport};
use signorini_core::scene::{SceneError, SceneFile};

use crate::backends::BackendKind;
use crate::run::DEFAULT_SCENE;

/// Which document a schema describes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Document {
    /// The TOML scene file (read as JSON: every TOML table an object, every array an array).
    Scene,
    /// `result.json`, written by `signorini solve`.
    Result,
    /// `NAME.expected.json`, read (and written by `--bless`) by `signorini suite`.
    Expectation,
    /// `suite.json`, written by `signorini suite`.
    Suite,
}

/// The JSON Schema (draft 2020-12) of `document`.
pub fn schema(document: Document) -> Schema {
    match document {
        Document::Scene => scene_schema(),
        Document::Result => result_schema(),
        Document::Expectation => expectation_schema(),
        Document::Suite => suite_schema(),
    }
}

/// The JSON Schema of the scene file: the deserialisation contract of [`SceneFile`], so every
/// table refuses unknown keys (`additionalProperties: false`) and keys with a default are not
/// required.  It checks structure and types only: lengths of coordinate arrays, ranges of
/// values and cross-references (body names) are checked by `signorini check`.
pub fn scene_schema() -> Schema {
    let mut schema = SchemaSettings::draft2020_12()
        .for_deserialize()
        .into_generator()
        .into_root_schema_for::<SceneFile>();
    schema.insert("title".into(), "signorini scene file".into());
    schema
}

/// The JSON Schema of `result.json`: the serialisation contract of [`RunReport`] (fields written
/// only when present are not required).  serde_json writes a number that is not finite (NaN,
/// ±∞) as `null`, so every number of the result may also be `null`; `status` is then never
/// `"solved"`.
pub fn result_schema() -> Schema {
    let mut schema = SchemaSettings::draft2020_12()
        .for_serialize()
        .with_transform(RecursiveTransform(nullable_numbers))
        .into_generator()
        .into_root_schema_for::<RunReport>();
    schema.insert("title".into(), "signorini result.json".into());
    schema
}

/// The JSON Schema of a suite's expectation file: the deserialisation contract of
/// [`Expectation`](crate::suite::expectation::Expectation) (unknown keys refused).  Value
/// ranges (tolerances in (0, 1), finite figures) are checked when the suite reads the file.
pub fn expectation_schema() -> Schema {
    let mut schema = SchemaSettings::draft2020_12()
        .for_deserialize()
        .into_generator()
        .into_root_schema_for::<crate::suite::expectation::Expectation>();
    schema.insert(
        "title".into(),
        "signorini suite expectation (NAME.expected.json)".into(),
    );
    schema
}

/// The JSON Schema of `suite.json`: the serialisation contract of
/// [`SuiteReport`](crate::suite::report::SuiteReport); numbers may be `null` (see
/// [`result_schema`]).
pub fn suite_schema() -> Schema {
    let mut schema = SchemaSettings::draft2020_12()
        .for_serialize()
        .with_transform(RecursiveTransform(nullable_numbers))
        .into_generator()
        .into_root_schema_for::<crate::suite::report::SuiteReport>();
    schema.insert("title".into(), "signorini suite.json".into());
    schema
}

/// `"type": "number"` becomes `"type": ["number", "null"]` (see [`result_schema`]).
fn nullable_numbers(schema: &mut Schema) {
    if schema.get("type").and_then(|t| t.as_str()) == Some("number") {
        schema.insert("type".into(), serde_json::json!(["number", "null"]));
    }
}

pub use crate::digest::sha256_hex;

/// SHA-256 of the scene file's bytes ([`sha256_hex`]), or of the built-in scene's text when
/// `path` is `None`.
pub fn scene_sha256(path: Option<&Path>) -> Result<String, SceneError> {
    match path {
        Some(p) => std::fs::read(p)
            .map(|bytes| sha256_hex(&bytes))
            .map_err(|source| SceneError::Read {
                path: p.display().to_string(),
                source,
            }),
        None => Ok(sha256_hex(DEFAULT_SCENE.as_bytes())),
    }
}

/// The provenance of a comparison of the QP read from the Matrix Market files in `dir`: as
/// [`provenance`], with `scene_path` the directory and `scene_sha256` the SHA-256 of the bytes of
/// its files `A.mtx`, `f.mtx`, `B.mtx`, `g.mtx` in that order.
pub fn qp_provenance(dir: &Path, settings: BackendSettings) -> std::io::Result<Provenance> {
    let mut bytes = Vec::new();
    for name in ["A.mtx", "f.mtx", "B.mtx", "g.mtx"] {
        bytes.extend(std::fs::read(dir.join(name))?);
    }
    Ok(provenance_of(
        Some(dir.display().to_string()),
        sha256_hex(&bytes),
        settings,
    ))
}

/// The provenance of a run of the input at `path` whose bytes hash to `sha256`, with
/// `settings`: this program's version and, when the build recorded it, its commit; the path and
/// hash; the settings; the core count.  (For a suite: the directory and
/// [`crate::suite::suite_sha256`].)
pub fn provenance_of(
    path: Option<String>,
    sha256: String,
    settings: BackendSettings,
) -> Provenance {
    Provenance {
        version: env!("CARGO_PKG_VERSION").to_string(),
        commit: option_env!("SIGNORINI_COMMIT")
            .filter(|c| !c.trim().is_empty())
            .map(|c| c.trim().to_string()),
        scene_path: path,
        scene_sha256: sha256,
        settings,
        cores: cores(),
    }
}

/// The provenance's `settings.form` of a run of `kinds`: each backend's formulation, comma
/// separated in the order of `settings.backend` — `primal` (sparse, in the displacements),
/// `dual` (condensed, in the contact forces: the `dual-*` backends and `X/dual`) or `auto`
/// (`auto` picks the form per attempt, each attempt's backend names it).
pub fn forms(kinds: &[BackendKind]) -> String {
    kinds
        .iter()
        .map(|k| match k {
            BackendKind::Auto => "auto",
            k => k.form().name(),
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// The logical cores this process may use (1 when unknown).
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// The provenance of a run of the scene at `scene` (`None`: the built-in one) with `settings`:
/// this program's version and, when the build recorded it, its commit; the scene's path and
/// SHA-256; the settings; the core count.
pub fn provenance(
    scene: Option<&Path>,
    settings: BackendSettings,
) -> Result<Provenance, SceneError> {
    Ok(provenance_of(
        scene.map(|p| p.display().to_string()),
        scene_sha256(scene)?,
        settings,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FIPS 180-2's test vectors (appendix B.1 and the empty message).
    #[test]
    fn sha256_matches_the_standard_vectors() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(
            sha256_hex(b""),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
    }

    /// `result.json`'s `status` is written with [`QpStatus::as_str`] and described in the schema
    /// by `QpStatus`'s serde names: the two must be the same words.
    /// docs/scene.md's "Statuses" table lists exactly the statuses the program writes.
    #[test]
    fn the_documented_statuses_are_the_programs() {
        use signorini_core::qp::QpStatus;
        let doc = include_str!("../../../docs/scene.md");
        let table = doc.split("## Statuses").nth(1).unwrap();
        let documented: Vec<&str> = table
            .lines()
            .skip_while(|l| !l.starts_with("| `"))
            .take_while(|l| l.starts_with('|'))
            .filter_map(|l| l.strip_prefix("| `")?.split('`').next())
            .collect();
        let written: Vec<&str> = QpStatus::ALL.iter().map(|s| s.as_str()).collect();
        assert_eq!(documented, written);
    }

    #[test]
    fn status_words_are_the_schema_enum() {
        use signorini_core::qp::QpStatus;
        let all = QpStatus::ALL;
        let schema = serde_json::to_value(result_schema()).unwrap();
        let text = schema["$defs"]["QpStatus"].to_string();
        for s in all {
            assert_eq!(serde_json::to_value(s).unwrap(), s.as_str());
            assert!(
                text.contains(&format!("\"{}\"", s.as_str())),
                "{s} in {text}"
            );
        }
    }

    /// Each backend's form as `--form` would name it: the dual methods and `X/dual` are dual.
    #[test]
    fn forms_name_each_backends_formulation() {
        use BackendKind::*;
        assert_eq!(
            forms(&[
                Clarabel,
                ClarabelDual,
                Osqp,
                OsqpDual,
                DualPgs,
                DualUzawa,
                DualSsn,
                Pdas,
                Auto
            ]),
            "primal,dual,primal,dual,dual,dual,dual,primal,auto"
        );
    }

    #[test]
    fn only_plain_numbers_become_nullable() {
        let mut s: Schema = serde_json::json!({"type": "number", "format": "double"})
            .try_into()
            .unwrap();
        nullable_numbers(&mut s);
        assert_eq!(s.get("type"), Some(&serde_json::json!(["number", "null"])));
        let mut s: Schema = serde_json::json!({"type": "integer"}).try_into().unwrap();
        nullable_numbers(&mut s);
        assert_eq!(s.get("type"), Some(&serde_json::json!("integer")));
    }
}
