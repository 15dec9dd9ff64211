//! The `$PhysicalNames` section, which `mshio` 0.4 skips.

use std::collections::HashMap;

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
