//! Solving with the KKT matrix of a set F through the factor of an earlier set F_f, when the
//! two differ in a few rows (low-rank update by block elimination, no new factorisation).
//!
//! K_F and K_f agree except in the multiplier rows and columns of S = F Δ F_f.  Split S into
//! the rows removed (active in F_f, inactive in F) and added (the other way round); R is every
//! other unknown.  Both matrices share the block K_RR, and
//!
//! * K_RR⁻¹ v comes from K_f: w = K_f⁻¹[v; 0] has nonzero multipliers on the removed rows,
//!   which a correction along Y = K_f⁻¹ P (P the unit columns of the removed rows) cancels:
//!   w ← w − Y (PᵀY)⁻¹ Pᵀ w.  (An added row is decoupled in K_f — its row is −λᵢ/s = 0 — so
//!   its multiplier is zero in w already.)
//! * The added rows a_j = [B_jᵀ; 0] enter through their Schur complement
//!   C = −δI − A_aᵀ K_RR⁻¹ A_a, and for a right-hand side b:
//!   w = K_RR⁻¹ b_R,  λ_a = C⁻¹(b_a − A_aᵀ w),  z_R = w − K_RR⁻¹ A_a λ_a, λ_removed = 0.
//!
//! Setting up costs one solve per changed row; every later solve one solve with K_f plus
//! O((n + m)·|S|) dense work.  The answer is exact up to round-off (and is refined against the
//! unregularised system like any other).

use std::collections::HashMap;
use std::sync::Arc;

use signorini_qp::QpProblem;

use crate::coupling::Coupling;
use crate::dense::DenseLu;
use crate::error::PdasError;
use crate::factor::KktFactor;

/// Solves with the factor of the factored set, kept until the next factorisation:
/// K_f⁻¹ e_{n+i} for rows removed since, K_f⁻¹ [B_jᵀ; 0] for rows added since.  A row that
/// stays removed (or added) over several iterations costs one solve, not one per iteration.
#[derive(Debug, Default)]
pub struct ColumnCache {
    removal: HashMap<usize, Arc<Vec<f64>>>,
    added: HashMap<usize, Arc<Vec<f64>>>,
}

impl ColumnCache {
    /// Forgets every column (the factor changed).
    pub fn clear(&mut self) {
        self.removal.clear();
        self.added.clear();
    }

    /// Columns stored.
    pub fn len(&self) -> usize {
        self.removal.len() + self.added.len()
    }

    /// (rows that differ from the factored set, columns not stored yet) for `active`.
    pub fn need(&self, factored: &[bool], active: &[bool]) -> (usize, usize) {
        let mut rank = 0;
        let mut missing = 0;
        for (i, (&f, &a)) in factored.iter().zip(active).enumerate() {
            if f && !a {
                rank += 1;
                missing += usize::from(!self.removal.contains_key(&i));
            } else if a && !f {
                rank += 1;
                missing += usize::from(!self.added.contains_key(&i));
            }
        }
        (rank, missing)
    }
}

/// The correction data for one set relative to the factored one.
#[derive(Debug)]
pub struct SetUpdate {
    dofs: usize,
    removed: Vec<usize>,
    added: Vec<usize>,
    /// K_f⁻¹ e_{n+i} for the removed rows i.
    removal_columns: Vec<Arc<Vec<f64>>>,
    /// LU of PᵀY (removed × removed).
    removal: Option<DenseLu>,
    /// K_RR⁻¹ a_j for the added rows j.
    added_columns: Vec<Vec<f64>>,
    /// B rows of the added rows as (column, value) lists.
    added_rows: Vec<Vec<(usize, f64)>>,
    /// LU of the Schur complement C (added × added).
    schur: Option<DenseLu>,
}

/// A small dense system of the update is singular (the set is factorised instead).
struct Singular;

impl ColumnCache {
    /// Solves, in one batch with the factor, for the columns of the `removed` rows and of the
    /// `added` rows (B rows `added_rows`) not stored yet, and stores them; `extra` (length
    /// n + m), when given, joins the batch and is overwritten with K_f⁻¹ `extra` (one pass
    /// over the factor for all of them: faer's triangular solves take up to four columns per
    /// pass).
    fn fill(
        &mut self,
        factor: &mut KktFactor,
        (n, dim): (usize, usize),
        (removed, added): (&[usize], &[usize]),
        added_rows: &[Vec<(usize, f64)>],
        extra: Option<&mut [f64]>,
    ) -> Result<(), PdasError> {
        let missing_removed: Vec<usize> = removed
            .iter()
            .copied()
            .filter(|i| !self.removal.contains_key(i))
            .collect();
        let missing_added: Vec<usize> = (0..added.len())
            .filter(|&a| !self.added.contains_key(&added[a]))
            .collect();
        let columns = missing_removed.len() + missing_added.len();
        if columns == 0 {
            if let Some(extra) = extra {
                factor.solve_in_place(extra);
            }
            return Ok(());
        }
        let batch = columns + usize::from(extra.is_some());
        let mut block = vec![0.0; dim * batch];
        for (c, &i) in missing_removed.iter().enumerate() {
            block[c * dim + n + i] = 1.0;
        }
        for (c, &a) in missing_added.iter().enumerate() {
            let column = &mut block[(missing_removed.len() + c) * dim..];
            for &(j, v) in &added_rows[a] {
                column[j] = v;
            }
        }
        if let Some(extra) = &extra {
            block[columns * dim..].copy_from_slice(extra);
        }
        factor.solve_many_in_place(&mut block)?;
        if let Some(extra) = extra {
            extra.copy_from_slice(&block[columns * dim..]);
        }
        let mut columns = block[..columns * dim]
            .chunks_exact(dim)
            .map(|c| Arc::new(c.to_vec()));
        for &i in &missing_removed {
            if let Some(c) = columns.next() {
                self.removal.insert(i, c);
            }
        }
        for &a in &missing_added {
            if let Some(c) = columns.next() {
                self.added.insert(added[a], c);
            }
        }
        Ok(())
    }
}

impl SetUpdate {
    /// Prepares the update from the factored set `factored` to `active`, solving (in one
    /// batch) for the columns `cache` does not hold yet; `Ok(None)` when a small dense system
    /// is singular (then the set is factorised instead).  `rhs` (length n + m), when given,
    /// joins the batch: on `Ok(Some(_))` it is overwritten with K_F⁻¹ `rhs` for the updated
    /// set F — the set's first solve at the cost of one more column (on `Ok(None)` or an error
    /// its content is undefined).
    pub fn new(
        problem: &QpProblem,
        factor: &mut KktFactor,
        cache: &mut ColumnCache,
        (factored, active): (&[bool], &[bool]),
        delta: f64,
        rhs: Option<&mut [f64]>,
    ) -> Result<Option<Self>, PdasError> {
        let n = problem.dofs();
        let dim = n + problem.rows();
        let removed: Vec<usize> = (0..active.len())
            .filter(|&i| factored[i] && !active[i])
            .collect();
        let added: Vec<usize> = (0..active.len())
            .filter(|&i| !factored[i] && active[i])
            .collect();
        let added_rows = b_rows(problem, &added);
        let Some(rhs) = rhs else {
            cache.fill(factor, (n, dim), (&removed, &added), &added_rows, None)?;
            return Ok(Self::assemble(n, cache, removed, added, added_rows, delta).ok());
        };
        let b_added = take_changed(n, (&removed, &added), rhs);
        cache.fill(factor, (n, dim), (&removed, &added), &added_rows, Some(rhs))?;
        let Ok(update) = Self::assemble(n, cache, removed, added, added_rows, delta) else {
            return Ok(None);
        };
        update.complete(rhs, &b_added);
        Ok(Some(update))
    }

    /// The update from the cached columns: the removal correction (LU of PᵀY), the added
    /// rows' columns corrected for the removals, and the LU of their Schur complement.
    fn assemble(
        n: usize,
        cache: &ColumnCache,
        removed: Vec<usize>,
        added: Vec<usize>,
        added_rows: Vec<Vec<(usize, f64)>>,
        delta: f64,
    ) -> Result<Self, Singular> {
        let removal_columns: Vec<Arc<Vec<f64>>> = removed
            .iter()
            .filter_map(|i| cache.removal.get(i).cloned())
            .collect();
        if removal_columns.len() != removed.len() {
            return Err(Singular);
        }
        let removal = removal_lu(n, &removed, &removal_columns)?;
        let mut update = Self {
            dofs: n,
            removed,
            added: Vec::new(),
            removal_columns,
            removal,
            added_columns: Vec::new(),
            added_rows: Vec::new(),
            schur: None,
        };
        let mut added_columns = Vec::with_capacity(added.len());
        for i in &added {
            let mut column = cache.added.get(i).ok_or(Singular)?.as_ref().clone();
            update.correct_removed(&mut column);
            added_columns.push(column);
        }
        update.schur = schur_lu(&added_rows, &added_columns, delta)?;
        update.added = added;
        update.added_rows = added_rows;
        update.added_columns = added_columns;
        Ok(update)
    }

    /// Rows that differ from the factored set.
    pub fn rank(&self) -> usize {
        self.removed.len() + self.added.len()
    }

    /// w ← w − Y (PᵀY)⁻¹ Pᵀ w: turns K_f⁻¹[v; 0] into K_RR⁻¹ v.
    fn correct_removed(&self, v: &mut [f64]) {
        if let Some(lu) = &self.removal {
            let n = self.dofs;
            let mut t: Vec<f64> = self.removed.iter().map(|&i| v[n + i]).collect();
            lu.solve_in_place(&mut t);
            for (column, tj) in self.removal_columns.iter().zip(&t) {
                v.iter_mut()
                    .zip(column.iter())
                    .for_each(|(vi, ci)| *vi -= tj * ci);
            }
            for &i in &self.removed {
                v[n + i] = 0.0;
            }
        }
    }

    /// rhs ← K_F⁻¹ rhs for the updated set F.
    pub fn solve_in_place(&self, factor: &mut KktFactor, rhs: &mut [f64]) {
        let b_added = take_changed(self.dofs, (&self.removed, &self.added), rhs);
        factor.solve_in_place(rhs);
        self.complete(rhs, &b_added);
    }

    /// Ends [`SetUpdate::solve_in_place`] from rhs = K_f⁻¹ v, v the right-hand side with its
    /// changed rows taken out (their added part `b_added`, see [`take_changed`]).
    fn complete(&self, rhs: &mut [f64], b_added: &[f64]) {
        let n = self.dofs;
        self.correct_removed(rhs);
        if let Some(lu) = &self.schur {
            let mut lambda: Vec<f64> = self
                .added_rows
                .iter()
                .zip(b_added)
                .map(|(row, b)| b - row.iter().map(|&(j, v)| v * rhs[j]).sum::<f64>())
                .collect();
            lu.solve_in_place(&mut lambda);
            for (column, l) in self.added_columns.iter().zip(&lambda) {
                rhs.iter_mut().zip(column).for_each(|(r, c)| *r -= l * c);
            }
            for (&i, l) in self.added.iter().zip(&lambda) {
                rhs[n + i] = *l;
            }
        }
    }
}

/// Takes the changed rows out of a right-hand side: returns its entries on the `added` rows
/// and zeroes them and the `removed` rows' (multiplier rows n + i).
fn take_changed(n: usize, (removed, added): (&[usize], &[usize]), rhs: &mut [f64]) -> Vec<f64> {
    let b_added = added.iter().map(|&i| rhs[n + i]).collect();
    for &i in removed.iter().chain(added) {
        rhs[n + i] = 0.0;
    }
    b_added
}

/// The B rows of the `added` rows as (column, value) lists.
fn b_rows(problem: &QpProblem, added: &[usize]) -> Vec<Vec<(usize, f64)>> {
    let rows = problem.constraints.to_csr();
    added
        .iter()
        .map(|&i| {
            rows.outer_view(i)
                .map(|r| r.iter().map(|(j, v)| (j, *v)).collect())
                .unwrap_or_default()
        })
        .collect()
}

/// LU of PᵀY (removed × removed; `None` when nothing is removed).
fn removal_lu(
    n: usize,
    removed: &[usize],
    columns: &[Arc<Vec<f64>>],
) -> Result<Option<DenseLu>, Singular> {
    let kr = removed.len();
    if kr == 0 {
        return Ok(None);
    }
    let mut cap = vec![0.0; kr * kr];
    for (a, &i) in removed.iter().enumerate() {
        for (b, column) in columns.iter().enumerate() {
            cap[a * kr + b] = column[n + i];
        }
    }
    DenseLu::new(cap, kr).map(Some).ok_or(Singular)
}

/// LU of the added rows' Schur complement C = −δI − A_aᵀ K_RR⁻¹ A_a (`None` when nothing is
/// added).
fn schur_lu(
    added_rows: &[Vec<(usize, f64)>],
    added_columns: &[Vec<f64>],
    delta: f64,
) -> Result<Option<DenseLu>, Singular> {
    let ka = added_rows.len();
    if ka == 0 {
        return Ok(None);
    }
    let mut schur = vec![0.0; ka * ka];
    for (a, row) in added_rows.iter().enumerate() {
        for (b, column) in added_columns.iter().enumerate() {
            let product: f64 = row.iter().map(|&(j, v)| v * column[j]).sum();
            schur[a * ka + b] = -product - if a == b { delta } else { 0.0 };
        }
    }
    DenseLu::new(schur, ka).map(Some).ok_or(Singular)
}

/// Solves with the KKT matrix of the current set: the factor itself, or the factor of an
/// earlier set and a [`SetUpdate`].
#[derive(Debug)]
pub struct SetSolver<'a> {
    /// The numeric factor.
    pub factor: &'a mut KktFactor,
    /// The correction when the factored set is not the current one.
    pub update: Option<&'a SetUpdate>,
    /// Coulomb's slipping rows tied to their normal rows, when any (then K_c is solved).
    pub coupling: Option<&'a Coupling>,
}

impl SetSolver<'_> {
    /// rhs ← K_F⁻¹ rhs (K_c⁻¹ rhs with a coupling, see [`Coupling::solve`]).
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        let (factor, update) = (&mut *self.factor, self.update);
        let mut plain = |v: &mut [f64]| match update {
            Some(update) => update.solve_in_place(factor, v),
            None => factor.solve_in_place(v),
        };
        match self.coupling {
            Some(coupling) => {
                coupling.solve(rhs, plain);
            }
            None => plain(rhs),
        }
    }

    /// Sets the multipliers of tied rows from their normal rows (nothing without a coupling).
    pub fn fill(&self, multipliers: &mut [f64]) {
        if let Some(coupling) = self.coupling {
            coupling.fill(multipliers);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use signorini_qp::examples::laplacian_with_bounds;

    /// The update must solve the new set's K exactly as a fresh factorisation does.  Both are
    /// direct solves of the same matrix, so they agree to its condition number times ε: with
    /// δ = 10⁻² and this 100-unknown chain (A's condition number ~10⁴) that is ~1e-12, and
    /// 1e-10 leaves room.  (With δ = 10⁻⁸ each solve alone carries ~ε/δ = 1e-8 of round-off,
    /// which is what the refinement of the backend removes.)
    #[test]
    fn update_matches_a_fresh_factorisation() {
        let p = laplacian_with_bounds(80, 20);
        let (n, m) = (p.dofs(), p.rows());
        let (delta, inactive) = (1e-2, 1.0);
        let factored: Vec<bool> = (0..m).map(|i| i % 3 != 0).collect();
        let mut active = factored.clone();
        for i in [1, 4, 7] {
            active[i] = !active[i]; // removed (they were active)
        }
        for i in [0, 9, 18] {
            active[i] = !active[i]; // added (they were inactive)
        }
        let (mut old, mut kkt) = KktFactor::analyse(&p).unwrap();
        kkt.set_values(&factored, 0.0, delta, inactive);
        old.factor(&kkt, 1e-20, 1e-17).unwrap();
        let mut cache = ColumnCache::default();
        let update = SetUpdate::new(&p, &mut old, &mut cache, (&factored, &active), delta, None)
            .unwrap()
            .unwrap();
        assert_eq!(cache.len(), 6);
        assert_eq!(update.rank(), 6);
        let (mut fresh, _) = KktFactor::analyse(&p).unwrap();
        kkt.set_values(&active, 0.0, delta, inactive);
        fresh.factor(&kkt, 1e-20, 1e-17).unwrap();
        let rhs: Vec<f64> = (0..n + m)
            .map(|k| {
                if k >= n && !active[k - n] {
                    0.0
                } else {
                    (k as f64 * 0.37).sin()
                }
            })
            .collect();
        let mut a = rhs.clone();
        SetSolver {
            coupling: None,
            factor: &mut old,
            update: Some(&update),
        }
        .solve_in_place(&mut a);
        let mut b = rhs;
        fresh.solve_in_place(&mut b);
        let scale = b.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        let diff = a
            .iter()
            .zip(&b)
            .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()));
        assert!(
            diff <= 1e-10 * scale,
            "update differs by {diff:e} (scale {scale:e})"
        );
    }

    /// The set's first solve batched with the update's columns gives the same K_F⁻¹ v as a
    /// fresh factorisation of F (same bound and reason as above), and stores the same columns.
    #[test]
    fn a_right_hand_side_solved_in_the_update_s_batch_matches_a_fresh_factorisation() {
        let p = laplacian_with_bounds(80, 20);
        let (n, m) = (p.dofs(), p.rows());
        let delta = 1e-2;
        let factored: Vec<bool> = (0..m).map(|i| i % 2 == 0).collect();
        let mut active = factored.clone();
        active[2] = false; // removed
        active[5] = true; // added
        let (mut old, mut kkt) = KktFactor::analyse(&p).unwrap();
        kkt.set_values(&factored, 0.0, delta, 1.0);
        old.factor(&kkt, 1e-20, 1e-17).unwrap();
        let rhs: Vec<f64> = (0..n + m)
            .map(|k| {
                if k >= n && !active[k - n] {
                    0.0
                } else {
                    (k as f64 * 0.71).cos()
                }
            })
            .collect();
        let mut batched = rhs.clone();
        let mut cache = ColumnCache::default();
        let update = SetUpdate::new(
            &p,
            &mut old,
            &mut cache,
            (&factored, &active),
            delta,
            Some(&mut batched),
        )
        .unwrap()
        .unwrap();
        assert_eq!(cache.len(), 2);
        let (mut fresh, _) = KktFactor::analyse(&p).unwrap();
        kkt.set_values(&active, 0.0, delta, 1.0);
        fresh.factor(&kkt, 1e-20, 1e-17).unwrap();
        let mut want = rhs.clone();
        fresh.solve_in_place(&mut want);
        let mut again = rhs;
        update.solve_in_place(&mut old, &mut again);
        let scale = want.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
        for got in [&batched, &again] {
            let diff = got
                .iter()
                .zip(&want)
                .fold(0.0_f64, |s, (x, y)| s.max((x - y).abs()));
            assert!(
                diff <= 1e-10 * scale,
                "differs by {diff:e} (scale {scale:e})"
            );
        }
    }
}
