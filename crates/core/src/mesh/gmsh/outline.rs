//! The boundary: the edges used by exactly one cell, oriented as in their (counter-clockwise)
//! cell, which must form one closed loop.

use std::collections::{BTreeSet, HashMap};

use super::GmshProblem;

/// The boundary loop.
pub(super) struct Outline {
    /// Its nodes, in loop order.
    pub nodes: Vec<usize>,
    /// Its edges, along the loop (deterministic, like the internal mesher's).
    pub boundary: Vec<[usize; 2]>,
}

/// The boundary of `cells` (counter-clockwise, mesh numbering; `tags` name nodes in errors).
pub(super) fn trace(cells: &[Vec<usize>], tags: &[u64]) -> Result<Outline, GmshProblem> {
    let boundary = boundary_edges(cells, tags)?;
    let mut next: HashMap<usize, usize> = HashMap::new();
    for &[a, b] in &boundary {
        if next.insert(a, b).is_some() {
            return Err(GmshProblem::Boundary {
                loops: 0,
                pinch: format!(" touching itself at node {}", tags[a]),
            });
        }
    }
    let nodes = one_loop(&boundary, &next, tags)?;
    let boundary: Vec<[usize; 2]> = nodes
        .iter()
        .filter_map(|&a| next.get(&a).map(|&b| [a, b]))
        .collect();
    Ok(Outline { nodes, boundary })
}

/// The edges used once, sorted; refuses an edge used by more than two cells or by two on one
/// side of it (overlapping or folded cells).
fn boundary_edges(cells: &[Vec<usize>], tags: &[u64]) -> Result<Vec<[usize; 2]>, GmshProblem> {
    let mut edge_use: HashMap<[usize; 2], (usize, [usize; 2])> = HashMap::new();
    for c in cells {
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
    Ok(boundary)
}

/// The nodes of the boundary's first loop, in order; refuses a boundary of several loops or
/// one left open.
fn one_loop(
    boundary: &[[usize; 2]],
    next: &HashMap<usize, usize>,
    tags: &[u64],
) -> Result<Vec<usize>, GmshProblem> {
    let mut outline: Vec<usize> = Vec::new();
    let mut loops = 0;
    let mut visited: BTreeSet<usize> = BTreeSet::new();
    for &[start, _] in boundary {
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
    Ok(outline)
}
