//! Global sparse assembly of the block-diagonal stiffness of all bodies.
//!
//! The CSC pattern is built once from node adjacency (2×2 blocks per node pair), and element
//! matrices are scattered straight into it: no triplet list, so memory stays at the size of the
//! matrix itself even at millions of unknowns.

use nalgebra::DMatrix;

use super::element::{self, Material};
use super::Dofs;
use crate::mesh::Mesh;
use crate::qp::CscMatrix;

/// Sorted neighbour lists (each node is its own neighbour), in global node numbers.
fn adjacency(meshes: &[Mesh], dofs: &Dofs) -> Vec<Vec<usize>> {
    let mut adj: Vec<Vec<usize>> = vec![Vec::new(); dofs.nodes()];
    for (b, mesh) in meshes.iter().enumerate() {
        let off = dofs.node_offset(b);
        for c in 0..mesh.cells.len() {
            let cell = mesh.cells.cell(c);
            for &i in cell {
                for &j in cell {
                    adj[off + i].push(off + j);
                }
            }
        }
    }
    for (n, list) in adj.iter_mut().enumerate() {
        list.push(n);
        list.sort_unstable();
        list.dedup();
    }
    adj
}

/// The stiffness pattern with zero values, and the adjacency it came from.
struct Pattern {
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    adj: Vec<Vec<usize>>,
}

impl Pattern {
    fn new(meshes: &[Mesh], dofs: &Dofs) -> Self {
        let adj = adjacency(meshes, dofs);
        let n = 2 * adj.len();
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let nnz: usize = adj.iter().map(|a| 4 * a.len()).sum();
        let mut row_idx = Vec::with_capacity(nnz);
        for list in &adj {
            for _component in 0..2 {
                for &m in list {
                    row_idx.push(2 * m);
                    row_idx.push(2 * m + 1);
                }
                col_ptr.push(row_idx.len());
            }
        }
        Self {
            col_ptr,
            row_idx,
            adj,
        }
    }

    /// Position in the value array of entry (row dof of node `i`, comp `ci`; column dof of node
    /// `j`, comp `cj`).
    fn position(&self, i: usize, ci: usize, j: usize, cj: usize) -> usize {
        let k = self.adj[j].binary_search(&i).unwrap_or_else(|_| {
            unreachable!("node {i} is adjacent to {j} by construction of the pattern")
        });
        self.col_ptr[2 * j + cj] + 2 * k + ci
    }
}

fn scatter(values: &mut [f64], pattern: &Pattern, nodes: &[usize], ke: &DMatrix<f64>) {
    for (a, &j) in nodes.iter().enumerate() {
        for cj in 0..2 {
            for (b, &i) in nodes.iter().enumerate() {
                let base = pattern.position(i, 0, j, cj);
                values[base] += ke[(2 * b, 2 * a + cj)];
                values[base + 1] += ke[(2 * b + 1, 2 * a + cj)];
            }
        }
    }
}

/// Element stiffness of cell `c` of a mesh, as a dynamic matrix (6×6 or 8×8).
pub fn cell_stiffness(mesh: &Mesh, c: usize, material: &Material, thickness: f64) -> DMatrix<f64> {
    let mut points = Vec::with_capacity(4);
    mesh.cell_points_into(c, &mut points);
    element::of(mesh.cells.kind()).stiffness(&points, &material.elasticity(), thickness)
}

/// The full (all bodies, all DOFs, both triangles) stiffness matrix K = diag(K₁, K₂, …).
pub fn assemble_stiffness(
    meshes: &[Mesh],
    materials: &[Material],
    thickness: f64,
    dofs: &Dofs,
) -> CscMatrix {
    let pattern = Pattern::new(meshes, dofs);
    let mut values = vec![0.0; pattern.row_idx.len()];
    let mut global = Vec::with_capacity(4);
    let mut points = Vec::with_capacity(4);
    for (b, mesh) in meshes.iter().enumerate() {
        let off = dofs.node_offset(b);
        let element = element::of(mesh.cells.kind());
        let d = materials[b].elasticity();
        for c in 0..mesh.cells.len() {
            mesh.cell_points_into(c, &mut points);
            let ke = element.stiffness(&points, &d, thickness);
            global.clear();
            global.extend(mesh.cells.cell(c).iter().map(|n| off + n));
            scatter(&mut values, &pattern, &global, &ke);
        }
    }
    let n = 2 * dofs.nodes();
    CscMatrix::new_csc((n, n), pattern.col_ptr, pattern.row_idx, values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Cells;
    use crate::scene::Plane;

    #[test]
    fn pattern_scatter_matches_dense_assembly() {
        let mesh = Mesh {
            nodes: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.5]],
            cells: Cells::Triangles(vec![[0, 1, 2], [0, 2, 3], [1, 4, 2]]),
            boundary: vec![],
        };
        let material = Material {
            young: 1.0,
            poisson: 0.25,
            plane: Plane::Strain,
        };
        let dofs = Dofs::new(&[5]);
        let k = assemble_stiffness(std::slice::from_ref(&mesh), &[material], 1.0, &dofs);
        let mut dense = DMatrix::<f64>::zeros(10, 10);
        for c in 0..3 {
            let ke = cell_stiffness(&mesh, c, &material, 1.0);
            let nodes = mesh.cells.cell(c);
            for a in 0..3 {
                for b in 0..3 {
                    for i in 0..2 {
                        for j in 0..2 {
                            dense[(2 * nodes[a] + i, 2 * nodes[b] + j)] +=
                                ke[(2 * a + i, 2 * b + j)];
                        }
                    }
                }
            }
        }
        for i in 0..10 {
            for j in 0..10 {
                let v = k.get(i, j).copied().unwrap_or(0.0);
                assert!((v - dense[(i, j)]).abs() < 1e-15, "({i},{j})");
            }
        }
    }
}
