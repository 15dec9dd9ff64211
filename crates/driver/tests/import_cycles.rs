//! No module imports a module that imports it (issue 19): in every crate of the workspace, the
//! graph of `crate::…` and `super::…` references between top-level modules (`scene`, `mesh`,
//! `fem`, … in core; `study`, `suite`, `plots`, … in the driver) and between files has no
//! cycle.  Test code is left out (files named `tests.rs` and `#[cfg(test)] mod tests { … }`
//! blocks): a test may build its inputs with any module.
//!
//! The reader is textual (comments removed, paths read after `crate::` and `super::`, grouped
//! `crate::{a, b}` imports included); `the_reader_finds_a_planted_cycle` shows it can fail.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Module path (`a::b`) → source text, for the `.rs` files under `src` (`src/bin/` left out).
fn modules(src: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![src.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("read src") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let rel = path
                    .strip_prefix(src)
                    .expect("under src")
                    .with_extension("");
                let mut parts: Vec<String> = rel
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                // Test-only files, and binaries (each its own crate root, whose `crate::` is not
                // the library's).
                if parts.last().is_some_and(|l| l == "tests") || parts[0] == "bin" {
                    continue;
                }
                if parts
                    .last()
                    .is_some_and(|l| l == "mod" || l == "lib" || l == "main")
                {
                    parts.pop();
                }
                let text = std::fs::read_to_string(&path).expect("read file");
                out.insert(parts.join("::"), text);
            }
        }
    }
    out
}

/// The text without line comments and without a trailing `#[cfg(test)] mod tests { … }`.
fn production_code(text: &str) -> String {
    let mut kept = String::new();
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        let trimmed = line.trim_start();
        if trimmed.starts_with("#[cfg(test)]")
            && lines
                .peek()
                .is_some_and(|next| next.trim_start().starts_with("mod tests {"))
        {
            break;
        }
        let code = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        kept.push_str(code);
        kept.push('\n');
    }
    kept
}

/// The module paths `text` names after each occurrence of `prefix` (`crate::` or `super::`):
/// `crate::a::b::C` gives `a::b::C`, `crate::{a::x, b}` gives `a::x` and `b`.
fn paths_after(text: &str, prefix: &str) -> Vec<String> {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    for (i, _) in text.match_indices(prefix) {
        let before = text[..i].chars().next_back();
        if before.is_some_and(ident) {
            continue;
        }
        let rest = &text[i + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let end = group.find('}').unwrap_or(group.len());
            for item in group[..end].split(',') {
                let path: String = item
                    .trim()
                    .chars()
                    .take_while(|c| ident(*c) || *c == ':')
                    .collect();
                if !path.is_empty() {
                    out.push(path);
                }
            }
        } else {
            let path: String = rest
                .chars()
                .take_while(|c| ident(*c) || *c == ':')
                .collect();
            out.push(path.trim_end_matches(':').to_string());
        }
    }
    out
}

/// The longest module of `known` that `path` starts with.
fn resolve(path: &[&str], known: &BTreeMap<String, String>) -> Option<String> {
    (1..=path.len())
        .rev()
        .map(|n| path[..n].join("::"))
        .find(|m| known.contains_key(m))
}

/// Edges module → modules it references, at the granularity `top` (first path component) or
/// per file; a module's references to its own ancestors and descendants are not edges.
fn edges(known: &BTreeMap<String, String>, top: bool) -> BTreeMap<String, BTreeSet<String>> {
    let group = |m: &str| {
        if top {
            m.split("::").next().unwrap_or("").to_string()
        } else {
            m.to_string()
        }
    };
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, text) in known {
        let code = production_code(text);
        let here: Vec<&str> = module.split("::").filter(|s| !s.is_empty()).collect();
        let mut targets = Vec::new();
        for p in paths_after(&code, "crate::") {
            let parts: Vec<&str> = p.split("::").filter(|s| !s.is_empty()).collect();
            targets.extend(resolve(&parts, known));
        }
        for p in paths_after(&code, "super::") {
            let mut parts: Vec<&str> = here[..here.len().saturating_sub(1)].to_vec();
            parts.extend(p.split("::").filter(|s| !s.is_empty()));
            targets.extend(resolve(&parts, known));
        }
        let from = group(module);
        for t in targets {
            let related = t.is_empty()
                || module.is_empty()
                || t.starts_with(&format!("{module}::"))
                || module.starts_with(&format!("{t}::"));
            let to = group(&t);
            if !related && to != from && !to.is_empty() && !from.is_empty() {
                graph.entry(from.clone()).or_default().insert(to);
            }
        }
    }
    graph
}

/// A cycle of `graph`, if it has one (depth-first search).
fn cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        node: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(node.to_string(), 1);
        path.push(node.to_string());
        for next in graph.get(node).into_iter().flatten() {
            match state.get(next.as_str()) {
                Some(1) => {
                    let start = path.iter().position(|p| p == next).unwrap_or(0);
                    let mut found = path[start..].to_vec();
                    found.push(next.clone());
                    return Some(found);
                }
                Some(_) => {}
                None => {
                    if let Some(found) = visit(next, graph, state, path) {
                        return Some(found);
                    }
                }
            }
        }
        path.pop();
        state.insert(node.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for node in graph.keys() {
        if !state.contains_key(node.as_str()) {
            if let Some(found) = visit(node, graph, &mut state, &mut Vec::new()) {
                return Some(found);
            }
        }
    }
    None
}

fn workspace_crates() -> Vec<PathBuf> {
    let crates = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(&crates)
        .expect("crates/")
        .map(|e| e.expect("entry").path().join("src"))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs
}

#[test]
fn no_module_imports_a_module_that_imports_it() {
    let mut found = Vec::new();
    for src in workspace_crates() {
        let known = modules(&src);
        for top in [true, false] {
            if let Some(c) = cycle(&edges(&known, top)) {
                found.push(format!("{}: {}", src.display(), c.join(" → ")));
            }
        }
    }
    assert!(found.is_empty(), "import cycles:\n{}", found.join("\n"));
}

#[test]
fn the_reader_finds_a_planted_cycle() {
    // a/mod.rs uses crate::b, b.rs uses crate::{a::x}; c.rs only uses a.
    let known: BTreeMap<String, String> = [
        ("", "mod a;\nmod b;\nmod c;\n"),
        ("a", "use crate::b::Thing;\npub mod x;\n"),
        ("a::x", "pub struct X;\n"),
        (
            "b",
            "// crate::c is only mentioned\nuse crate::{a::x, a};\n",
        ),
        (
            "c",
            "use crate::a;\n#[cfg(test)]\nmod tests {\n    use crate::c;\n}\n",
        ),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v.to_string()))
    .collect();
    let graph = edges(&known, true);
    assert_eq!(graph["b"], BTreeSet::from(["a".to_string()]), "{graph:?}");
    let c = cycle(&graph).expect("a ↔ b");
    assert!(
        c.contains(&"a".to_string()) && c.contains(&"b".to_string()),
        "{c:?}"
    );
    // Without b's import there is none.
    let mut fixed = known.clone();
    fixed.insert("b".into(), "pub struct Thing;\n".into());
    assert_eq!(cycle(&edges(&fixed, true)), None);
}
