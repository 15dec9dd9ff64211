//! Physical groups in mesh numbering: a group's nodes are the mesh nodes of its elements; its
//! edges the boundary edges it holds (for a group of curves the boundary edges that are line
//! elements of the group, for a group of points or surfaces those whose two ends are its nodes).

use std::collections::BTreeMap;

use super::elements::RawGroup;
use super::nodes::Numbered;
use super::MeshGroup;

/// The groups read from the element blocks, in the mesh's numbering; `boundary`: the boundary
/// edges along the loop.
pub(super) fn in_mesh_numbering(
    raw_groups: BTreeMap<String, RawGroup>,
    numbered: &Numbered,
    boundary: &[[usize; 2]],
) -> BTreeMap<String, MeshGroup> {
    let (index, tags) = (&numbered.index, &numbered.tags);
    let mut groups = BTreeMap::new();
    for (name, (dim, node_tags, line_edges)) in raw_groups {
        let group_nodes: Vec<usize> = node_tags
            .iter()
            .filter_map(|t| index.get(t).copied())
            .collect();
        let mut edges: Vec<[usize; 2]> = boundary
            .iter()
            .copied()
            .filter(|&[a, b]| {
                if dim == 1 {
                    let (ta, tb) = (tags[a], tags[b]);
                    line_edges.contains(&[ta.min(tb), ta.max(tb)])
                } else {
                    group_nodes.binary_search(&a).is_ok() && group_nodes.binary_search(&b).is_ok()
                }
            })
            .collect();
        edges.sort_unstable();
        groups.insert(
            name,
            MeshGroup {
                dim: dim.clamp(0, 2) as u8,
                nodes: group_nodes,
                edges,
            },
        );
    }
    groups
}
