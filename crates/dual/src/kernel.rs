//! Floating bodies: the known kernel R of A, the DOFs that fix it, and the dual's equality
//! constraint G λ = e with G = Rᵀ Bᵀ (k × m) and e = Rᵀ f.
//!
//! Minimising ½ xᵀ A x − fᵀ x + λᵀ(B x − g) over x is bounded only if f − Bᵀλ ⟂ ker A, i.e.
//! Rᵀ(f − Bᵀλ) = 0; then x = A⁺(f − Bᵀλ) + R α, and α is (minus) the multiplier of that
//! equality in the dual.

use signorini_qp::{dot, mat_vec, norm_inf, QpProblem};

use crate::error::DualError;

/// Relative size below which a kernel direction counts as dependent on the others.
const DEPENDENCE: f64 = 1e-10;

/// Relative residual ‖A r‖∞ / (max|A| ‖r‖∞) above which a vector is not in the kernel.
const KERNEL_RESIDUAL: f64 = 1e-8;

/// The rigid-body data of a problem (all empty when A is positive definite).
#[derive(Debug, Clone, Default)]
pub struct RigidModes {
    /// R: the kernel basis, k vectors of length n.
    pub basis: Vec<Vec<f64>>,
    /// k DOFs whose removal makes A positive definite.
    pub fixed: Vec<usize>,
    /// Rows of G = Rᵀ Bᵀ: `coupling[j] = B r_j` (length m each).
    pub coupling: Vec<Vec<f64>>,
    /// e = Rᵀ f (length k).
    pub load: Vec<f64>,
}

impl RigidModes {
    /// Checks the problem's kernel and derives the fixing DOFs, G and e.
    pub fn of(problem: &QpProblem) -> Result<Self, DualError> {
        let basis = &problem.kernel;
        if basis.is_empty() {
            return Ok(Self::default());
        }
        let a_max = norm_inf(problem.stiffness.data());
        for (index, r) in basis.iter().enumerate() {
            let r_max = norm_inf(r);
            // A zero vector is no kernel vector; every vector is one of A = 0 (A r = 0 exactly;
            // the relative residual was 0 / 0 and refused it, found by the conformance suite).
            let residual = if r_max == 0.0 {
                f64::INFINITY
            } else if a_max == 0.0 {
                0.0
            } else {
                norm_inf(&mat_vec(&problem.stiffness, r)) / (a_max * r_max)
            };
            if residual.is_nan() || residual > KERNEL_RESIDUAL {
                return Err(DualError::NotAKernelVector { index, residual });
            }
        }
        let fixed = fixing_dofs(basis)?;
        let coupling = basis
            .iter()
            .map(|r| mat_vec(&problem.constraints, r))
            .collect();
        let load = basis.iter().map(|r| dot(r, &problem.load)).collect();
        Ok(Self {
            basis: basis.clone(),
            fixed,
            coupling,
            load,
        })
    }

    /// The rigid-mode equations' residual e − G λ as the stored A has it at x: −R_Fᵀ r_F, with
    /// r = A x − f + Bᵀ(λ + λ_lo) on the fixing DOFs F — the rows the generalised inverse
    /// leaves out, where every imbalance of x = A⁺(f − Bᵀλ) − R μ ends up.  Equal to e − G λ
    /// in exact arithmetic; in floating point the two differ by (A R)ᵀ x, the stored A's
    /// round-off along R (≈ ε |A| per entry) summed against x over all DOFs: on the
    /// 1.1·10⁶-DOF Hertz cylinder, where x is 10⁴ of the load's own unit, that left a
    /// stationarity residual of 1.3e-8 on the two fixing DOFs while e − G λ was at round-off.
    pub fn measured_residual(
        &self,
        problem: &QpProblem,
        x: &[f64],
        multipliers: &[f64],
        low: &[f64],
    ) -> Vec<f64> {
        let residual_at = |j: usize| {
            // A is symmetric with both triangles stored: its column j is its row j.
            let ax: f64 = problem
                .stiffness
                .outer_view(j)
                .map_or(0.0, |c| c.iter().map(|(i, a)| a * x[i]).sum());
            let btl: f64 = problem.constraints.outer_view(j).map_or(0.0, |c| {
                c.iter().map(|(i, b)| b * (multipliers[i] + low[i])).sum()
            });
            ax - problem.load[j] + btl
        };
        let r_fixed: Vec<f64> = self.fixed.iter().map(|&j| residual_at(j)).collect();
        self.basis
            .iter()
            .map(|r| {
                -self
                    .fixed
                    .iter()
                    .zip(&r_fixed)
                    .map(|(&j, rj)| r[j] * rj)
                    .sum::<f64>()
            })
            .collect()
    }

    /// Number k of kernel vectors.
    pub fn count(&self) -> usize {
        self.basis.len()
    }

    /// G λ − e (length k).
    pub fn equality_residual(&self, multipliers: &[f64]) -> Vec<f64> {
        self.coupling
            .iter()
            .zip(&self.load)
            .map(|(row, e)| dot(row, multipliers) - e)
            .collect()
    }

    /// trace(G Gᵀ) = ‖G‖_F², an upper bound of λ_max(Gᵀ G) (0 without kernel).
    pub fn coupling_norm_sq(&self) -> f64 {
        self.coupling.iter().map(|row| dot(row, row)).sum()
    }
}

/// The unknowns with no stiffness that no kernel vector touches, sorted.  Column j of A holding
/// no nonzero puts e_j in the kernel of A, so a basis of that kernel has a vector with rⱼ ≠ 0;
/// when none of the problem's kernel vectors has one, A is singular on j and nothing declares
/// it (the auxiliary unknowns tᵢ of Tresca rows written one-sided,
/// [`signorini_qp::AuxiliaryForm`]).  One pass over A's entries and the kernel.
pub fn undeclared_unstiff_unknowns(problem: &QpProblem) -> Vec<usize> {
    problem
        .stiffness
        .outer_iterator()
        .enumerate()
        .filter(|(_, col)| col.iter().all(|(_, v)| *v == 0.0))
        .map(|(j, _)| j)
        .filter(|&j| problem.kernel.iter().all(|r| r[j] == 0.0))
        .collect()
}

/// Chooses k DOFs such that the k × k block of R on them is well conditioned: greedy
/// Gram–Schmidt with pivoting on the rows of R (QR with column pivoting of Rᵀ).
pub fn fixing_dofs(basis: &[Vec<f64>]) -> Result<Vec<usize>, DualError> {
    let k = basis.len();
    let n = basis.first().map_or(0, Vec::len);
    // rows[i] = (r_1[i], …, r_k[i]), stored flat.
    let mut rows = vec![0.0; n * k];
    for (j, r) in basis.iter().enumerate() {
        for (i, v) in r.iter().enumerate() {
            rows[i * k + j] = *v;
        }
    }
    let norm = |row: &[f64]| row.iter().map(|v| v * v).sum::<f64>().sqrt();
    let first_max = rows.chunks(k).map(norm).fold(0.0, f64::max);
    let mut fixed = Vec::with_capacity(k);
    for _ in 0..k {
        let (best, best_norm) = rows
            .chunks(k)
            .map(norm)
            .enumerate()
            .filter(|(i, _)| !fixed.contains(i))
            .fold(
                (usize::MAX, 0.0),
                |acc, (i, v)| if v > acc.1 { (i, v) } else { acc },
            );
        if best == usize::MAX || best_norm <= DEPENDENCE * first_max || first_max == 0.0 {
            return Err(DualError::DependentKernel { count: k });
        }
        let q: Vec<f64> = rows[best * k..(best + 1) * k]
            .iter()
            .map(|v| v / best_norm)
            .collect();
        for row in rows.chunks_mut(k) {
            let p = dot(row, &q);
            row.iter_mut().zip(&q).for_each(|(v, qi)| *v -= p * qi);
        }
        fixed.push(best);
    }
    Ok(fixed)
}

/// y += Gᵀ v (y of length m, v of length k).
pub fn add_coupling_t(modes: &RigidModes, v: &[f64], y: &mut [f64]) {
    for (row, vj) in modes.coupling.iter().zip(v) {
        if *vj != 0.0 {
            y.iter_mut().zip(row).for_each(|(yi, gi)| *yi += vj * gi);
        }
    }
}

impl RigidModes {
    /// A rigid motion that B does not see but the load drives (G v = 0 with eᵀv ≠ 0, i.e.
    /// B R v = 0 and fᵀ R v ≠ 0): the objective is then unbounded below.  Returns the index of
    /// the offending kernel vector in the Gram–Schmidt order, if any.
    pub fn unrestrained_mode(&self, load_norm: f64) -> Option<usize> {
        let mut q_rows: Vec<(Vec<f64>, f64)> = Vec::new();
        for (j, (row, e)) in self.coupling.iter().zip(&self.load).enumerate() {
            let mut v = row.clone();
            let mut ev = *e;
            for (q, qe) in &q_rows {
                let p = dot(q, &v);
                v.iter_mut().zip(q).for_each(|(vi, qi)| *vi -= p * qi);
                ev -= p * qe;
            }
            let row_norm = dot(row, row).sqrt();
            let v_norm = dot(&v, &v).sqrt();
            let r_norm = dot(&self.basis[j], &self.basis[j]).sqrt();
            if v_norm <= DEPENDENCE * row_norm.max(f64::MIN_POSITIVE) || row_norm == 0.0 {
                if ev.abs() > 1e-9 * r_norm * load_norm {
                    return Some(j);
                }
            } else {
                q_rows.push((v.iter().map(|x| x / v_norm).collect(), ev / v_norm));
            }
        }
        None
    }
}

/// Relative residual ‖Gλ* − e‖ / ‖e‖ of the best λ* ≥ 0 above which the equality G λ = e
/// counts as infeasible.  Loads that the contacts can balance give round-off (~1e-15).
const EQUALITY_INFEASIBLE: f64 = 1e-8;

impl RigidModes {
    /// Whether some λ ≥ 0 balances the load on the rigid modes (G λ = e).  If none does, the
    /// residual v = e − G λ* of the non-negative least-squares solution λ* is a Farkas
    /// direction: Gᵀv ≤ 0 (B R v ≤ 0: the rigid motion R v opens every contact) and
    /// eᵀv = ‖v‖² > 0 (the load does work on it), so the primal objective is unbounded below.
    /// Returns the message in that case.
    pub fn farkas_direction(&self) -> Option<String> {
        let k = self.count();
        if k == 0 {
            return None;
        }
        let e_norm = dot(&self.load, &self.load).sqrt();
        if e_norm == 0.0 {
            return None;
        }
        let lambda = self.nonnegative_least_squares();
        let residual: Vec<f64> = self.equality_residual(&lambda).iter().map(|r| -r).collect();
        let v_norm = dot(&residual, &residual).sqrt();
        (v_norm > EQUALITY_INFEASIBLE * e_norm).then(|| {
            format!(
                "dual infeasible: no contact forces λ ≥ 0 balance the load on the rigid modes (best ‖Rᵀ(f − Bᵀλ)‖ = {v_norm:.3e} of ‖Rᵀf‖ = {e_norm:.3e}): a rigid motion R v with B R v ≤ 0 and fᵀ R v > 0 moves a floating body away from every contact; the objective is unbounded below"
            )
        })
    }

    /// argmin ‖G λ − e‖ over λ ≥ 0 (Lawson–Hanson active set; G has k ≤ a few rows, so the
    /// passive set stays small).
    fn nonnegative_least_squares(&self) -> Vec<f64> {
        let m = self.coupling.first().map_or(0, Vec::len);
        let k = self.count();
        let column = |j: usize| -> Vec<f64> { self.coupling.iter().map(|row| row[j]).collect() };
        let g_max = self
            .coupling
            .iter()
            .map(|row| norm_inf(row))
            .fold(0.0, f64::max);
        let tol = 1e-13 * g_max * norm_inf(&self.load).max(f64::MIN_POSITIVE);
        let mut lambda = vec![0.0; m];
        let mut passive: Vec<usize> = Vec::new();
        for _ in 0..(3 * k + 10) {
            let residual: Vec<f64> = self.equality_residual(&lambda).iter().map(|r| -r).collect();
            // w = Gᵀ (e − G λ).
            let mut w = vec![0.0; m];
            add_coupling_t(self, &residual, &mut w);
            let best = (0..m).filter(|j| !passive.contains(j)).fold(
                None,
                |acc: Option<(usize, f64)>, j| match acc {
                    Some((_, v)) if v >= w[j] => acc,
                    _ => Some((j, w[j])),
                },
            );
            let Some((j, wj)) = best else { break };
            if wj <= tol {
                break;
            }
            passive.push(j);
            // Inner loop: least squares on the passive set, stepping back to stay ≥ 0.
            loop {
                let cols: Vec<Vec<f64>> = passive.iter().map(|&j| column(j)).collect();
                let Some(z) = least_squares(&cols, &self.load) else {
                    passive.pop();
                    break;
                };
                if z.iter().all(|v| *v > 0.0) {
                    for (&j, v) in passive.iter().zip(&z) {
                        lambda[j] = *v;
                    }
                    break;
                }
                let alpha = passive
                    .iter()
                    .zip(&z)
                    .filter(|(_, v)| **v <= 0.0)
                    .map(|(&j, v)| lambda[j] / (lambda[j] - v))
                    .fold(1.0_f64, f64::min);
                for (&j, v) in passive.iter().zip(&z) {
                    lambda[j] += alpha * (v - lambda[j]);
                }
                passive.retain(|&j| lambda[j] > 0.0);
                for (j, l) in lambda.iter_mut().enumerate() {
                    if !passive.contains(&j) {
                        *l = 0.0;
                    }
                }
                if passive.is_empty() {
                    break;
                }
            }
        }
        lambda
    }
}

/// argmin ‖Σ_j z_j c_j − e‖ by the normal equations (at most a few columns of length k);
/// `None` when they are singular.
fn least_squares(columns: &[Vec<f64>], e: &[f64]) -> Option<Vec<f64>> {
    let p = columns.len();
    let mut normal = vec![vec![0.0; p + 1]; p];
    for a in 0..p {
        for b in 0..p {
            normal[a][b] = dot(&columns[a], &columns[b]);
        }
        normal[a][p] = dot(&columns[a], e);
    }
    // Gaussian elimination with partial pivoting on the p × (p + 1) augmented matrix.
    let scale = (0..p).map(|a| normal[a][a]).fold(0.0, f64::max);
    for c in 0..p {
        let pivot = (c..p).max_by(|&x, &y| normal[x][c].abs().total_cmp(&normal[y][c].abs()))?;
        if normal[pivot][c].abs() <= 1e-12 * scale {
            return None;
        }
        normal.swap(c, pivot);
        let (upper, lower) = normal.split_at_mut(c + 1);
        let pivot_row = &upper[c];
        for row in lower.iter_mut() {
            let factor = row[c] / pivot_row[c];
            row.iter_mut()
                .zip(pivot_row)
                .skip(c)
                .for_each(|(v, pv)| *v -= factor * pv);
        }
    }
    let mut z = vec![0.0; p];
    for c in (0..p).rev() {
        let tail: f64 = ((c + 1)..p).map(|q| normal[c][q] * z[q]).sum();
        z[c] = (normal[c][p] - tail) / normal[c][c];
    }
    Some(z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_qp::examples::csc;

    #[test]
    fn every_vector_is_a_kernel_vector_of_a_zero_stiffness() {
        // A = 0: ‖A r‖ / (‖A‖ ‖r‖) was 0 / 0 and refused r = (1) as "not in the null space".
        let zero = QpProblem::try_new(
            csc(1, 1, &[&[0.0]]),
            vec![1.0],
            sprs::CsMat::zero((0, 1)).to_csc(),
            vec![],
        )
        .and_then(|p| p.with_kernel(vec![vec![1.0]]))
        .expect("valid");
        assert!(RigidModes::of(&zero).is_ok());
        // A zero vector is still refused.
        let none = zero.clone().with_kernel(vec![vec![0.0]]).expect("valid");
        assert!(matches!(
            RigidModes::of(&none),
            Err(DualError::NotAKernelVector { index: 0, .. })
        ));
    }
}
