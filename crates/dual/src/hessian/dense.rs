//! The dense symmetric dual Hessian and the dense operations the methods need on it.

use crate::kernel::RigidModes;

/// A dense symmetric m × m matrix, column-major.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseSym {
    /// Entries, column-major (equal to row-major by symmetry).
    pub values: Vec<f64>,
    /// Order m.
    pub size: usize,
}

impl DenseSym {
    /// Column (= row) `j`.
    pub fn col(&self, j: usize) -> &[f64] {
        &self.values[j * self.size..(j + 1) * self.size]
    }

    /// Diagonal entry (j, j).
    pub fn diag(&self, j: usize) -> f64 {
        self.values[j * self.size + j]
    }

    /// y = H v.
    pub fn mul(&self, v: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.size];
        for (j, vj) in v.iter().enumerate() {
            if *vj != 0.0 {
                y.iter_mut()
                    .zip(self.col(j))
                    .for_each(|(yi, hij)| *yi += vj * hij);
            }
        }
        y
    }

    /// Replaces H by (H + Hᵀ)/2 to remove round-off asymmetry.
    pub(crate) fn symmetrise(&mut self) {
        let m = self.size;
        for j in 0..m {
            for i in (j + 1)..m {
                let avg = 0.5 * (self.values[j * m + i] + self.values[i * m + j]);
                self.values[j * m + i] = avg;
                self.values[i * m + j] = avg;
            }
        }
    }

    /// H += c Gᵀ G, the augmented-Lagrangian penalty of the floating-body equality.
    pub fn add_penalty(&mut self, modes: &RigidModes, penalty: f64) {
        if penalty == 0.0 {
            return;
        }
        let m = self.size;
        for row in &modes.coupling {
            for (j, gj) in row.iter().enumerate() {
                if *gj != 0.0 {
                    let col = &mut self.values[j * m..(j + 1) * m];
                    col.iter_mut()
                        .zip(row)
                        .for_each(|(h, gi)| *h += penalty * gj * gi);
                }
            }
        }
    }

    /// λ_max estimated by power iteration (from above: the returned value is at least the
    /// Rayleigh quotient, raised by 5 %).
    pub fn largest_eigenvalue(&self, iterations: usize) -> f64 {
        power_iteration(self.size, iterations, |v| self.mul(v))
    }
}

/// λ_max of a symmetric positive semidefinite operator by power iteration from a fixed
/// pseudo-random positive vector; the largest Rayleigh quotient times 1.05 (a safety margin for
/// step sizes).  An operator that vanishes on every iterate gives 0.
pub fn power_iteration(
    size: usize,
    iterations: usize,
    mut apply: impl FnMut(&[f64]) -> Vec<f64>,
) -> f64 {
    if size == 0 {
        return 0.0;
    }
    let raw: Vec<f64> = (0..size)
        .map(|i| 1.0 + 0.5 * (1.0 + i as f64).sin())
        .collect();
    let raw_norm = raw.iter().map(|x| x * x).sum::<f64>().sqrt();
    let mut v: Vec<f64> = raw.iter().map(|x| x / raw_norm).collect();
    let mut estimate = 0.0_f64;
    for _ in 0..iterations {
        let w = apply(&v);
        let quotient: f64 = v.iter().zip(&w).map(|(a, b)| a * b).sum();
        let norm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        estimate = estimate.max(quotient);
        if !(norm > 0.0 && norm.is_finite()) {
            break;
        }
        v = w.iter().map(|x| x / norm).collect();
    }
    1.05 * estimate
}
