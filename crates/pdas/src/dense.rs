//! A small dense LU with partial pivoting, for the k × k systems of the rigid modes and of the
//! low-rank set updates (k is at most a few dozen).

/// P A = L U of a k × k matrix, row-major.
#[derive(Debug, Clone)]
pub struct DenseLu {
    lu: Vec<f64>,
    pivots: Vec<usize>,
    k: usize,
}

impl DenseLu {
    /// Factors the row-major k × k `matrix`; `None` when a pivot is zero or not finite.
    pub fn new(mut matrix: Vec<f64>, k: usize) -> Option<Self> {
        debug_assert_eq!(matrix.len(), k * k);
        let mut pivots = Vec::with_capacity(k);
        for col in 0..k {
            let pivot = (col..k).max_by(|&a, &b| {
                matrix[a * k + col]
                    .abs()
                    .total_cmp(&matrix[b * k + col].abs())
            })?;
            let p = matrix[pivot * k + col];
            if p == 0.0 || !p.is_finite() {
                return None;
            }
            for j in 0..k {
                matrix.swap(col * k + j, pivot * k + j);
            }
            pivots.push(pivot);
            for row in col + 1..k {
                let factor = matrix[row * k + col] / p;
                matrix[row * k + col] = factor;
                for j in col + 1..k {
                    matrix[row * k + j] -= factor * matrix[col * k + j];
                }
            }
        }
        Some(Self {
            lu: matrix,
            pivots,
            k,
        })
    }

    /// Overwrites `rhs` (length k) with A⁻¹ rhs.
    pub fn solve_in_place(&self, rhs: &mut [f64]) {
        let k = self.k;
        for (col, &p) in self.pivots.iter().enumerate() {
            rhs.swap(col, p);
        }
        for row in 0..k {
            let s: f64 = (0..row).map(|j| self.lu[row * k + j] * rhs[j]).sum();
            rhs[row] -= s;
        }
        for row in (0..k).rev() {
            let s: f64 = (row + 1..k).map(|j| self.lu[row * k + j] * rhs[j]).sum();
            rhs[row] = (rhs[row] - s) / self.lu[row * k + row];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_system_that_needs_pivoting() {
        // [[0, 2, 1], [1, 1, 0], [3, 0, 1]] x = b with x = (1, −2, 3).
        let a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let x = [1.0, -2.0, 3.0];
        let mut b: Vec<f64> = (0..3)
            .map(|i| (0..3).map(|j| a[i * 3 + j] * x[j]).sum())
            .collect();
        DenseLu::new(a, 3).unwrap().solve_in_place(&mut b);
        for (u, v) in b.iter().zip(x) {
            assert!((u - v).abs() < 1e-14, "{b:?}");
        }
        assert!(DenseLu::new(vec![1.0, 2.0, 2.0, 4.0], 2).is_none());
    }
}
