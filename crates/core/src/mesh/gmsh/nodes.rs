//! Nodes: coordinates by Gmsh tag, then the nodes the 2-D elements use, numbered in tag order,
//! checked finite, planar and pairwise distinct.

use std::collections::{BTreeSet, HashMap};

use super::GmshProblem;
use crate::geometry::Point;

/// The used nodes in mesh numbering.
pub(super) struct Numbered {
    /// Gmsh tag of each mesh node (increasing).
    pub tags: Vec<u64>,
    /// Mesh node of each used tag.
    pub index: HashMap<u64, usize>,
    /// Coordinates (x, y) of each mesh node.
    pub nodes: Vec<Point>,
    /// [`crate::geometry::REGION_TOLERANCE`] × the diagonal of the nodes' bounding box.
    pub tol: f64,
    /// That diagonal.
    pub size: f64,
}

/// Coordinates by tag.  mshio keeps the tags only when they are sparse; dense tags run from the
/// section's smallest tag through the blocks in file order (as Gmsh writes them).
pub(super) fn coordinates(
    data: &mshio::MshData<u64, i32, f64>,
) -> Result<HashMap<u64, [f64; 3]>, GmshProblem> {
    let mut coords: HashMap<u64, [f64; 3]> = HashMap::new();
    if let Some(nodes) = &data.nodes {
        let mut next = nodes.min_node_tag;
        for block in &nodes.node_blocks {
            let tags: Vec<u64> = match &block.node_tags {
                Some(map) => sparse_tags(map, block.nodes.len())?,
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
    Ok(coords)
}

/// The tags of a block's `len` nodes from mshio's tag → position map.
fn sparse_tags(map: &HashMap<u64, usize>, len: usize) -> Result<Vec<u64>, GmshProblem> {
    let mut t = vec![0; len];
    for (tag, &i) in map {
        if let Some(slot) = t.get_mut(i) {
            *slot = *tag;
        }
    }
    if map.len() != len {
        // Two nodes of the block share a tag: the map kept one.
        let mut seen = BTreeSet::new();
        let dup = t.iter().find(|x| !seen.insert(**x)).copied().unwrap_or(0);
        return Err(GmshProblem::DuplicateTag(dup));
    }
    Ok(t)
}

/// The nodes the cells use, numbered in tag order: each defined, finite, all at one z, no two
/// at one place.
pub(super) fn number(
    cells_tags: &[(u64, Vec<u64>)],
    coords: &HashMap<u64, [f64; 3]>,
) -> Result<Numbered, GmshProblem> {
    let mut used: BTreeSet<u64> = BTreeSet::new();
    for (element, nodes) in cells_tags {
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
    check_coincident(&nodes, &tags, tol)?;
    Ok(Numbered {
        tags,
        index,
        nodes,
        tol,
        size,
    })
}

/// Refuses two nodes within `tol` of each other (a sweep along x).
fn check_coincident(nodes: &[Point], tags: &[u64], tol: f64) -> Result<(), GmshProblem> {
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
    Ok(())
}
