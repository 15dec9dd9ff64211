//! Size and quality measures of a mesh.

use crate::geometry::{distance, orient, Point};

use super::Mesh;

/// ```
/// use signorini_core::mesh::{Cells, Mesh};
/// // Two triangles of the unit square.
/// let mesh = Mesh {
///     nodes: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
///     cells: Cells::Triangles(vec![[0, 1, 2], [0, 2, 3]]),
///     boundary: vec![[0, 1], [1, 2], [2, 3], [3, 0]],
/// };
/// assert_eq!(mesh.max_edge(), 2f64.sqrt());
/// assert!((mesh.min_angle_deg() - 45.0).abs() < 1e-12);
/// assert_eq!(mesh.area(), 1.0);
/// assert_eq!(mesh.boundary_length(), 4.0);
/// ```
impl Mesh {
    /// Corner points of cell `i`.
    fn corners(&self, i: usize) -> impl Iterator<Item = Point> + '_ {
        self.cells.cell(i).iter().map(|&v| self.nodes[v])
    }

    /// Longest cell edge (0 for an empty mesh).
    pub fn max_edge(&self) -> f64 {
        (0..self.cells.len())
            .flat_map(|i| {
                let c = self.cells.cell(i);
                (0..c.len()).map(move |k| (c[k], c[(k + 1) % c.len()]))
            })
            .map(|(a, b)| distance(self.nodes[a], self.nodes[b]))
            .fold(0.0, f64::max)
    }

    /// Smallest interior angle of any cell, in degrees (180 for an empty mesh).
    pub fn min_angle_deg(&self) -> f64 {
        let mut min = 180.0_f64;
        for i in 0..self.cells.len() {
            let p: Vec<Point> = self.corners(i).collect();
            let m = p.len();
            for k in 0..m {
                let (a, b, c) = (p[(k + m - 1) % m], p[k], p[(k + 1) % m]);
                let u = [a[0] - b[0], a[1] - b[1]];
                let v = [c[0] - b[0], c[1] - b[1]];
                let cross = u[0] * v[1] - u[1] * v[0];
                let dot = u[0] * v[0] + u[1] * v[1];
                min = min.min(cross.abs().atan2(dot).to_degrees());
            }
        }
        min
    }

    /// Sum of the signed cell areas (positive for counter-clockwise cells).
    pub fn area(&self) -> f64 {
        (0..self.cells.len())
            .map(|i| {
                let c = self.cells.cell(i);
                let p0 = self.nodes[c[0]];
                (1..c.len() - 1)
                    .map(|k| orient(p0, self.nodes[c[k]], self.nodes[c[k + 1]]))
                    .sum::<f64>()
                    * 0.5
            })
            .fold(CompensatedSum::default(), CompensatedSum::add)
            .value()
    }

    /// Total length of the boundary edges.
    pub fn boundary_length(&self) -> f64 {
        self.boundary
            .iter()
            .map(|&[a, b]| distance(self.nodes[a], self.nodes[b]))
            .fold(CompensatedSum::default(), CompensatedSum::add)
            .value()
    }
}

/// Neumaier's compensated sum: the error does not grow with the number of terms.
#[derive(Default, Clone, Copy)]
struct CompensatedSum {
    sum: f64,
    compensation: f64,
}

impl CompensatedSum {
    fn add(self, x: f64) -> Self {
        let sum = self.sum + x;
        let lost = if self.sum.abs() >= x.abs() {
            (self.sum - sum) + x
        } else {
            (x - sum) + self.sum
        };
        Self {
            sum,
            compensation: self.compensation + lost,
        }
    }

    fn value(self) -> f64 {
        self.sum + self.compensation
    }
}
