//! The checks every section shares: lengths of arrays, finite numbers, printable names, boxes,
//! and body names looked up; each error names the section and the key.

use crate::geometry::Point;
use crate::scene::draft::DraftBody;
use crate::scene::SceneError;

/// Characters refused in names and the title: Unicode control characters (C0, DEL, C1) and the
/// non-characters U+FFFE and U+FFFF — all of them invalid or unsafe in the XML and JSON the
/// program writes (SVG, VTU, result.json).
pub fn name_forbidden(c: char) -> bool {
    c.is_control() || c == '\u{FFFE}' || c == '\u{FFFF}'
}

/// `body "name"` with the name escaped (quotes, backslashes and control characters).
pub(in crate::scene) fn body_label(name: &str) -> String {
    format!("body {name:?}")
}

/// `n one` or `n many`.
pub(in crate::scene) fn plural(n: usize, one: &str, many: &str) -> String {
    if n == 1 {
        format!("{n} {one}")
    } else {
        format!("{n} {many}")
    }
}

/// `n number(s)`.
fn numbers(n: usize) -> String {
    plural(n, "number", "numbers")
}

/// A fixed-length array from a list, refusing any other length.
pub(super) fn exact<const N: usize>(
    section: &str,
    key: &'static str,
    values: &[f64],
) -> Result<[f64; N], SceneError> {
    <[f64; N]>::try_from(values).map_err(|_| {
        SceneError::invalid(
            section,
            key,
            format!("has {}, needs {N}", numbers(values.len())),
        )
    })
}

/// A list of points, each of exactly two numbers (`what`: "vertex" or "point", numbered from 1).
pub(super) fn points(
    section: &str,
    key: &'static str,
    what: &str,
    list: &[Vec<f64>],
) -> Result<Vec<Point>, SceneError> {
    list.iter()
        .enumerate()
        .map(|(i, p)| {
            <[f64; 2]>::try_from(p.as_slice()).map_err(|_| {
                SceneError::invalid(
                    section,
                    key,
                    format!("{what} {} has {}, needs 2", i + 1, numbers(p.len())),
                )
            })
        })
        .collect()
}

/// Refuses a name or title holding a character that [`name_forbidden`] rejects.
pub(super) fn check_text(section: &str, key: &'static str, text: &str) -> Result<(), SceneError> {
    match text.chars().find(|c| name_forbidden(*c)) {
        Some(c) => Err(SceneError::invalid(
            section,
            key,
            format!(
                "contains the control character U+{:04X}; use printable characters only",
                c as u32
            ),
        )),
        None => Ok(()),
    }
}

/// Refuses a value that is NaN or infinite.
pub(in crate::scene) fn check_finite(
    section: &str,
    key: &'static str,
    values: &[f64],
) -> Result<(), SceneError> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(SceneError::invalid(
            section,
            key,
            format!("must be finite, got {v}"),
        )),
        None => Ok(()),
    }
}

/// A box `[x1, x2, y1, y2]` of finite numbers with x1 ≤ x2 and y1 ≤ y2.
pub(super) fn check_region(section: &str, region: &[f64]) -> Result<[f64; 4], SceneError> {
    let region = exact::<4>(section, "region", region)?;
    check_finite(section, "region", &region)?;
    if region[0] > region[1] || region[2] > region[3] {
        return Err(SceneError::invalid(
            section,
            "region",
            format!("must be [x1, x2, y1, y2] with x1 ≤ x2 and y1 ≤ y2, got {region:?}"),
        ));
    }
    Ok(region)
}

/// Looks bodies up by name; the error names the section and `key`.
pub(super) struct Names<'a>(pub &'a [DraftBody]);

impl Names<'_> {
    /// The index of the body called `name`.
    pub fn find(&self, section: &str, key: &'static str, name: &str) -> Result<usize, SceneError> {
        self.0.iter().position(|b| b.name == name).ok_or_else(|| {
            let known: Vec<String> = self.0.iter().map(|b| format!("{:?}", b.name)).collect();
            SceneError::invalid(
                section,
                key,
                format!(
                    "names an unknown body {name:?} (bodies: {})",
                    known.join(", ")
                ),
            )
        })
    }
}
