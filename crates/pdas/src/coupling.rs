//! Coulomb's slipping rows in the KKT system of a set: λₜ = μ σ λₙ.
//!
//! A Coulomb row that slips with sign σ (see [`crate::active_set`]) carries the multiplier
//! λₜ = μ σ λₙ of its normal row, which is active.  Its force enters the equilibrium as a
//! column μ σ B_tᵀ added to the normal row's column of K:
//!
//! ```text
//! K_c = K + E,   E z = [ Σₖ μₖ σₖ B_{t,k}ᵀ λ_{n,k} ; 0 ]
//! ```
//!
//! — not symmetric (Coulomb's law is not associated), so the LDLᵀ factor of K cannot solve it
//! alone.  With y the normal multipliers of the slipping rows, K z = b − Ê y and y = P z give the
//! small system (I + P K⁻¹ Ê) y = P K⁻¹ b, solved by GMRES with one solve of K per iteration;
//! K⁻¹ Ê is of order μ, so few iterations reach round-off.  Then z = K⁻¹ b − K⁻¹ Ê y, from the
//! solves already made.  This is the linear system of the semismooth Newton step for Coulomb
//! friction (Hüeber, Stadler and Wohlmuth), solved to round-off.

use signorini_qp::CscMatrix;

/// GMRES stops once its residual is this fraction of the right-hand side's size (round-off of
/// the solves with K).
const RELATIVE_TOLERANCE: f64 = 1e-15;

/// GMRES iterations at most (each one solve with K); the map has norm of order μ.
const MAX_ITERATIONS: usize = 60;

/// One slipping Coulomb row tied to its normal row.
#[derive(Debug, Clone)]
struct Link {
    /// The tangential row.
    row: usize,
    /// Its normal row.
    normal: usize,
    /// μ σ.
    coefficient: f64,
    /// The tangential row of B: (column, value).
    entries: Vec<(usize, f64)>,
}

/// The slipping Coulomb rows of a set (see the module documentation).
#[derive(Debug, Clone, Default)]
pub struct Coupling {
    links: Vec<Link>,
    /// n, the number of primal unknowns.
    dofs: usize,
}

impl Coupling {
    /// The coupling of `links` (row, normal row, μ σ) with B's rows read from `rows_of_b`
    /// (B in compressed-row form), for `dofs` primal unknowns.
    pub fn new(links: &[(usize, usize, f64)], rows_of_b: &CscMatrix, dofs: usize) -> Self {
        let links = links
            .iter()
            .map(|&(row, normal, coefficient)| Link {
                row,
                normal,
                coefficient,
                entries: rows_of_b
                    .outer_view(row)
                    .map(|r| r.iter().map(|(j, v)| (j, *v)).collect())
                    .unwrap_or_default(),
            })
            .collect();
        Self { links, dofs }
    }

    /// λ of every tied row set to μ σ λₙ of its normal row.
    pub fn fill(&self, multipliers: &mut [f64]) {
        for l in &self.links {
            multipliers[l.row] = l.coefficient * multipliers[l.normal];
        }
    }

    /// rhs ← Ê y subtracted from the primal part: rhs_x −= Σₖ μₖ σₖ B_{t,k}ᵀ yₖ.
    fn subtract_forces(&self, y: &[f64], rhs: &mut [f64]) {
        for (l, yk) in self.links.iter().zip(y) {
            for &(j, v) in &l.entries {
                rhs[j] -= l.coefficient * v * yk;
            }
        }
    }

    /// P z: the normal multipliers of the tied rows.
    fn normals(&self, z: &[f64]) -> Vec<f64> {
        self.links.iter().map(|l| z[self.dofs + l.normal]).collect()
    }

    /// rhs ← K_c⁻¹ rhs, with `solve` applying K⁻¹ in place; returns the GMRES iterations.
    pub fn solve(&self, rhs: &mut [f64], mut solve: impl FnMut(&mut [f64])) -> usize {
        solve(rhs);
        if self.links.is_empty() {
            return 0;
        }
        let b = self.normals(rhs);
        let size = rhs.len();
        // −K⁻¹ Ê v, kept for every Krylov vector to assemble z at the end.
        let mut responses: Vec<Vec<f64>> = Vec::new();
        let (coefficients, iterations) = {
            let mut apply = |v: &[f64]| -> Vec<f64> {
                let mut z = vec![0.0; size];
                self.subtract_forces(v, &mut z);
                solve(&mut z);
                // z = −K⁻¹ Ê v, so (I + P K⁻¹ Ê) v = v − P z.
                let w = v
                    .iter()
                    .zip(self.normals(&z))
                    .map(|(vi, pz)| vi - pz)
                    .collect();
                responses.push(z);
                w
            };
            gmres(&mut apply, &b)
        };
        // z = K⁻¹ b − K⁻¹ Ê y with y = V c: rhs + Σ cⱼ (−K⁻¹ Ê vⱼ).
        for (c, z) in coefficients.iter().zip(&responses) {
            rhs.iter_mut().zip(z).for_each(|(r, zj)| *r += c * zj);
        }
        iterations
    }
}

/// GMRES from x₀ = 0 for A x = b, A applied by `apply`: the coefficients c of x = V c in the
/// Krylov basis V (whose vectors are the arguments of `apply`, in call order) and the
/// iterations.
fn gmres(apply: &mut impl FnMut(&[f64]) -> Vec<f64>, b: &[f64]) -> (Vec<f64>, usize) {
    let beta = norm(b);
    if beta == 0.0 || !beta.is_finite() {
        return (Vec::new(), 0);
    }
    let mut basis: Vec<Vec<f64>> = vec![b.iter().map(|v| v / beta).collect()];
    // The Hessenberg matrix by columns, rotated to triangular form as it grows.
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut rotations: Vec<(f64, f64)> = Vec::new();
    let mut g = vec![beta];
    let target = RELATIVE_TOLERANCE * beta;
    let mut best = beta;
    while columns.len() < MAX_ITERATIONS.min(b.len()) {
        let k = columns.len();
        let mut w = apply(&basis[k]);
        let mut h = Vec::with_capacity(k + 2);
        for v in &basis {
            let hij = dot(&w, v);
            w.iter_mut().zip(v).for_each(|(wi, vi)| *wi -= hij * vi);
            h.push(hij);
        }
        let next = norm(&w);
        h.push(next);
        for (i, &(c, s)) in rotations.iter().enumerate() {
            let (a, bb) = (h[i], h[i + 1]);
            h[i] = c * a + s * bb;
            h[i + 1] = -s * a + c * bb;
        }
        let r = h[k].hypot(h[k + 1]);
        if r == 0.0 || !r.is_finite() {
            break;
        }
        let (c, s) = (h[k] / r, h[k + 1] / r);
        h[k] = r;
        h[k + 1] = 0.0;
        rotations.push((c, s));
        g.push(-s * g[k]);
        g[k] *= c;
        h.truncate(k + 1);
        columns.push(h);
        let residual = g[k + 1].abs();
        // Stop at the target, or when an iteration gains less than half a digit's tenth
        // (round-off of the solves with K decides the floor, not the tolerance).
        if residual <= target || next == 0.0 || residual > 0.99 * best {
            break;
        }
        best = residual;
        basis.push(w.iter().map(|v| v / next).collect());
    }
    (back_substitute(&columns, &g), columns.len())
}

/// Solves the triangular system R c = g of GMRES (R by columns).
fn back_substitute(columns: &[Vec<f64>], g: &[f64]) -> Vec<f64> {
    let k = columns.len();
    let mut c = vec![0.0; k];
    for i in (0..k).rev() {
        let mut sum = g[i];
        for (j, cj) in c.iter().enumerate().skip(i + 1) {
            sum -= columns[j][i] * cj;
        }
        c[i] = sum / columns[i][i];
    }
    c
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// GMRES on a non-symmetric 3×3 system against its exact solution (by hand: A x = b with
    /// x = (1, −2, 3)); three iterations reach round-off in exact arithmetic.
    #[test]
    fn gmres_solves_a_small_non_symmetric_system() {
        let a = [[4.0, 1.0, 0.5], [-1.0, 3.0, 0.2], [0.3, -0.7, 2.0]];
        let x = [1.0, -2.0, 3.0];
        let b: Vec<f64> = a.iter().map(|r| dot(r, &x)).collect();
        let mut vectors: Vec<Vec<f64>> = Vec::new();
        let mut apply = |v: &[f64]| {
            vectors.push(v.to_vec());
            a.iter().map(|r| dot(r, v)).collect::<Vec<f64>>()
        };
        let (c, iterations) = gmres(&mut apply, &b);
        assert!(iterations <= 3);
        let mut got = [0.0; 3];
        for (cj, v) in c.iter().zip(&vectors) {
            got.iter_mut().zip(v).for_each(|(g, vi)| *g += cj * vi);
        }
        for (g, want) in got.iter().zip(x) {
            assert!((g - want).abs() < 1e-13, "{got:?}");
        }
    }
}
