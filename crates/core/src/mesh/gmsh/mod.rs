//! Meshes read from Gmsh files (MSH 4.1, ASCII or binary), parsed by the `mshio` crate.
//!
//! What is accepted: linear triangles (Gmsh type 2) or linear quadrilaterals (type 3), not both in
//! one file, lying in a plane z = const; points (type 15) and lines (type 1) are read for their
//! physical groups only.  Every node used by a 2-D element becomes a [`Mesh`] node (numbered in the
//! order of their Gmsh tags); nodes used by no 2-D element are dropped.  Elements are reoriented
//! counter-clockwise when *all* of them are clockwise (a surface whose normal points along −z);
//! an element whose orientation differs from the others is refused as inverted.
//!
//! The boundary is the set of element edges used by exactly one element, oriented with the body
//! on the left; it must form exactly one closed loop (one body without holes), which becomes the
//! body's polygon for the parts of the program that look at the outline.
//!
//! **Physical groups.**  Names come from the `$PhysicalNames` section.  `mshio` 0.4 parses the
//! `$Entities` section (which entity carries which physical tags) but skips `$PhysicalNames`; that
//! section is plain text in ASCII and binary files alike (`dim tag "name"` per line), so
//! [`physical_names`] reads those lines.  A physical group without a name is known by its tag
//! written in decimal ("3").  A group's nodes are the mesh nodes of its elements (of any
//! dimension); its edges are the boundary edges it holds: for a group of curves the boundary
//! edges that are line elements of the group, for a group of points or surfaces the boundary
//! edges whose two ends are nodes of the group.
//!
//! One file per step of the import: [`elements`] (element blocks, physical groups' raw members),
//! [`nodes`] (coordinates by tag, the used nodes numbered, planarity, coincidences), [`cells`]
//! (areas and orientation), [`outline`] (the boundary loop), [`groups`] (groups in mesh
//! numbering), [`names`] (`$PhysicalNames`), and [`error`].

mod cells;
mod elements;
mod error;
mod groups;
mod names;
mod nodes;
mod outline;

use std::collections::BTreeMap;
use std::path::Path;

use super::{Cells, Mesh};
use crate::geometry::Point;

pub use error::{GmshError, GmshProblem};
pub use names::physical_names;

/// A physical group of an imported mesh, in the mesh's node numbering.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshGroup {
    /// Largest dimension of the group's entities (0 points, 1 curves, 2 surfaces).
    pub dim: u8,
    /// Mesh nodes of the group's elements, sorted, unique.
    pub nodes: Vec<usize>,
    /// Boundary edges of the mesh held by the group, oriented as in [`Mesh::boundary`], sorted.
    pub edges: Vec<[usize; 2]>,
}

impl MeshGroup {
    /// True when mesh node `n` belongs to the group.
    pub fn has_node(&self, n: usize) -> bool {
        self.nodes.binary_search(&n).is_ok()
    }

    /// True when the boundary edge `[a, b]` (either orientation) belongs to the group.
    pub fn has_edge(&self, a: usize, b: usize) -> bool {
        self.edges.binary_search(&[a, b]).is_ok() || self.edges.binary_search(&[b, a]).is_ok()
    }
}

/// A mesh read from a Gmsh file, with its boundary loop and physical groups.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedMesh {
    /// The file as given in the scene (for messages).
    pub path: String,
    /// The mesh, counter-clockwise elements and boundary.
    pub mesh: Mesh,
    /// The boundary as one closed counter-clockwise loop of node coordinates.
    pub outline: Vec<Point>,
    /// Physical groups by name.
    pub groups: BTreeMap<String, MeshGroup>,
}

impl ImportedMesh {
    /// The group of this name, if any.
    pub fn group(&self, name: &str) -> Option<&MeshGroup> {
        self.groups.get(name)
    }

    /// Group names, comma-separated and quoted, for messages.
    pub fn group_list(&self) -> String {
        if self.groups.is_empty() {
            return "the file defines no physical group".into();
        }
        let names: Vec<String> = self.groups.keys().map(|k| format!("{k:?}")).collect();
        format!("groups in the file: {}", names.join(", "))
    }
}

/// Reads a Gmsh MSH 4.1 file (ASCII or binary).  `label` names the file in errors (the path as
/// written in the scene).
pub fn read_msh(path: &Path, label: &str) -> Result<ImportedMesh, GmshError> {
    let err = |problem| GmshError {
        path: label.to_string(),
        problem,
    };
    let bytes = std::fs::read(path).map_err(|e| err(GmshProblem::Read(e.to_string())))?;
    parse_msh(&bytes, label)
}

/// Parses the bytes of a Gmsh MSH 4.1 file (ASCII or binary); see [`read_msh`].
pub fn parse_msh(bytes: &[u8], label: &str) -> Result<ImportedMesh, GmshError> {
    import(bytes, label).map_err(|problem| GmshError {
        path: label.to_string(),
        problem,
    })
}

/// The steps of the import, in the order their problems are reported: parse, nodes by tag,
/// elements and groups, the used nodes, cells and their orientation, the boundary loop, the
/// groups in mesh numbering.
fn import(bytes: &[u8], label: &str) -> Result<ImportedMesh, GmshProblem> {
    let data = parse(bytes)?;
    let coords = nodes::coordinates(&data)?;
    let names = physical_names(bytes);
    let blocks = elements::read(&data, &names)?;
    let cells_tags = blocks.cells()?;
    let numbered = nodes::number(&cells_tags, &coords)?;
    let cells = cells::orient(&numbered, &cells_tags)?;
    let outline = outline::trace(&cells, &numbered.tags)?;
    let groups = groups::in_mesh_numbering(blocks.groups, &numbered, &outline.boundary);
    let outline_points: Vec<Point> = outline.nodes.iter().map(|&a| numbered.nodes[a]).collect();
    let cells = if blocks.quads.is_empty() {
        Cells::Triangles(cells.iter().map(|c| [c[0], c[1], c[2]]).collect())
    } else {
        Cells::Quads(cells.iter().map(|c| [c[0], c[1], c[2], c[3]]).collect())
    };
    Ok(ImportedMesh {
        path: label.to_string(),
        mesh: Mesh {
            nodes: numbered.nodes,
            cells,
            boundary: outline.boundary,
        },
        outline: outline_points,
        groups,
    })
}

/// The file parsed by `mshio`.  mshio 0.4 still has `unimplemented!`/`expect` on a few malformed
/// inputs: a panic there is turned into a parse error rather than taking the program down.
fn parse(bytes: &[u8]) -> Result<mshio::MshData<u64, i32, f64>, GmshProblem> {
    let parsed = std::panic::catch_unwind(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| {
            let text = e.to_string();
            text.lines().take(6).collect::<Vec<_>>().join("; ")
        })
    })
    .map_err(|_| GmshProblem::Parse("the parser stopped on malformed input".into()))?
    .map_err(GmshProblem::Parse)?;
    Ok(parsed.data)
}
