//! Element blocks: the 2-D cells (linear triangles or quadrilaterals, one kind per file), and
//! the members of each physical group (node tags of its elements, edges of its line elements).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use mshio::ElementType;

use super::GmshProblem;

/// A physical group as read from the element blocks: the largest dimension of its entities,
/// the node tags of its elements, and its line elements as sorted tag pairs.
pub(super) type RawGroup = (i32, BTreeSet<u64>, BTreeSet<[u64; 2]>);

/// What the element blocks hold.
pub(super) struct Blocks {
    /// Triangles: element tag and node tags.
    pub triangles: Vec<(u64, [u64; 3])>,
    /// Quadrilaterals: element tag and node tags.
    pub quads: Vec<(u64, [u64; 4])>,
    /// Physical groups by name.
    pub groups: BTreeMap<String, RawGroup>,
}

impl Blocks {
    /// The 2-D cells as element tag and node tags: triangles or quadrilaterals, not none, not
    /// both.
    pub fn cells(&self) -> Result<Vec<(u64, Vec<u64>)>, GmshProblem> {
        if self.triangles.is_empty() && self.quads.is_empty() {
            return Err(GmshProblem::NoElements);
        }
        if !self.triangles.is_empty() && !self.quads.is_empty() {
            return Err(GmshProblem::MixedElements {
                triangles: self.triangles.len(),
                quads: self.quads.len(),
            });
        }
        Ok(if self.quads.is_empty() {
            self.triangles
                .iter()
                .map(|(t, n)| (*t, n.to_vec()))
                .collect()
        } else {
            self.quads.iter().map(|(t, n)| (*t, n.to_vec())).collect()
        })
    }
}

/// The element blocks, with the physical tags of their entities named by `names` (a group
/// without a name is known by its tag in decimal).
pub(super) fn read(
    data: &mshio::MshData<u64, i32, f64>,
    names: &HashMap<(i32, i32), String>,
) -> Result<Blocks, GmshProblem> {
    let entity_groups = entity_groups(data);
    let group_name = |dim: i32, tag: i32| {
        names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| tag.to_string())
    };
    let mut blocks = Blocks {
        triangles: Vec::new(),
        quads: Vec::new(),
        groups: BTreeMap::new(),
    };
    let Some(elements) = &data.elements else {
        return Ok(blocks);
    };
    for block in &elements.element_blocks {
        supported(block)?;
        let physical = entity_groups
            .get(&(block.entity_dim, block.entity_tag))
            .cloned()
            .unwrap_or_default();
        for el in &block.elements {
            blocks.add_cell(block.element_type, el);
            for &tag in &physical {
                let g = blocks
                    .groups
                    .entry(group_name(block.entity_dim, tag))
                    .or_insert_with(|| (block.entity_dim, BTreeSet::new(), BTreeSet::new()));
                g.0 = g.0.max(block.entity_dim);
                g.1.extend(el.nodes.iter().copied());
                if block.element_type == ElementType::Lin2 && el.nodes.len() == 2 {
                    let (a, b) = (el.nodes[0], el.nodes[1]);
                    g.2.insert([a.min(b), a.max(b)]);
                }
            }
        }
    }
    Ok(blocks)
}

impl Blocks {
    /// Keeps `el` when it is a triangle or a quadrilateral.
    fn add_cell(&mut self, kind: ElementType, el: &mshio::Element<u64>) {
        match kind {
            ElementType::Tri3 if el.nodes.len() == 3 => self
                .triangles
                .push((el.element_tag, [el.nodes[0], el.nodes[1], el.nodes[2]])),
            ElementType::Qua4 if el.nodes.len() == 4 => self.quads.push((
                el.element_tag,
                [el.nodes[0], el.nodes[1], el.nodes[2], el.nodes[3]],
            )),
            _ => {}
        }
    }
}

/// Refuses a block of elements other than triangles, quadrilaterals, lines and points.
fn supported(block: &mshio::ElementBlock<u64, i32>) -> Result<(), GmshProblem> {
    match block.element_type {
        ElementType::Tri3 | ElementType::Qua4 | ElementType::Lin2 | ElementType::Pnt => Ok(()),
        other => Err(GmshProblem::UnsupportedElement {
            name: format!("{other:?}"),
            code: other as i32,
            dim: block.entity_dim,
            count: block.elements.len(),
        }),
    }
}

/// The physical tags of each entity `(dim, tag)` (the `$Entities` section).
fn entity_groups(data: &mshio::MshData<u64, i32, f64>) -> HashMap<(i32, i32), Vec<i32>> {
    let mut entity_groups: HashMap<(i32, i32), Vec<i32>> = HashMap::new();
    if let Some(e) = &data.entities {
        for p in &e.points {
            entity_groups.insert((0, p.tag), p.physical_tags.clone());
        }
        for c in &e.curves {
            entity_groups.insert((1, c.tag), c.physical_tags.clone());
        }
        for s in &e.surfaces {
            entity_groups.insert((2, s.tag), s.physical_tags.clone());
        }
    }
    entity_groups
}
