//! The project's own simplicial LDLᵀ, for a symmetric matrix refactorised many times with one
//! pattern (pdas's KKT matrix) and laid out in its elimination order already.
//!
//! faer's simplicial kernel (up-looking, as this one) finds the pattern of every row of L again
//! on every numeric factorisation — an elimination-tree walk per row, a fifth of the
//! factorisation's time on the KKT matrices of long contact strips.  Here the analysis walks
//! the tree twice as faer's does (column counts, then the patterns) and keeps what the second
//! walk found: the rows of L in each column (for the solves) and the columns of L in each row,
//! in an order where every column comes after the columns it depends on (for the numeric
//! factorisation, which then only does arithmetic).  Indices are 4 bytes, so the two
//! patterns together take the 8 B per entry of L that faer's one pattern takes.
//!
//! The analysis starts with the elimination tree and the column counts alone
//! ([`EliminationTree::of`]), so a caller can ask first whether a simplicial factor suits the
//! matrix at all ([`EliminationTree::suits_simplicial`], faer's own flop rule) before anything
//! of the size of L is allocated.

use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

use super::LinalgError;

/// faer's rule for choosing a supernodal factor: flops per entry of L above this.
const SUPERNODAL_FLOPS_PER_ENTRY: f64 = 40.0;

/// The elimination tree and the column counts of L (diagonal included) of a symmetric matrix
/// given by its upper triangle, in the order it is stored.
#[derive(Debug, Clone)]
pub struct EliminationTree {
    /// `parent[j]`, or `usize::MAX` at a root.  Always `parent[j] > j`.
    parent: Vec<usize>,
    /// Entries of column j of L, diagonal included.
    counts: Vec<usize>,
}

/// No parent: a root of the elimination tree.
const ROOT: usize = usize::MAX;

impl EliminationTree {
    /// Walks the upper triangle `upper` (column k holds rows i ≤ k, in any order) once: the
    /// row subtree of every row of L, from which the parent of each column and the count of
    /// each column follow.
    ///
    /// # Errors
    /// [`LinalgError::Shape`] when `upper` is not square.
    pub fn of(upper: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, LinalgError> {
        let n = square(upper)?;
        let mut parent = vec![ROOT; n];
        let mut counts = vec![1; n];
        let mut mark = vec![ROOT; n];
        for k in 0..n {
            mark[k] = k;
            for &i in upper.row_idx_of_col_raw(k) {
                let mut j = i;
                while j < k && mark[j] != k {
                    mark[j] = k;
                    counts[j] += 1;
                    if parent[j] == ROOT {
                        parent[j] = k;
                    }
                    j = parent[j];
                }
            }
        }
        Ok(Self { parent, counts })
    }

    /// Entries of L, diagonal included.
    pub fn nnz_l(&self) -> usize {
        self.counts.iter().sum()
    }

    /// Whether a simplicial factor suits the matrix: faer's rule, flops of the factorisation
    /// (Σ cⱼ + Σ cⱼ (cⱼ + 1) / 2 over the column counts) per entry of L at most 40 — above it,
    /// columns are long enough for a supernodal factor's dense kernels to win.
    pub fn suits_simplicial(&self) -> bool {
        let flops: f64 = self
            .counts
            .iter()
            .map(|&c| {
                let c = c as f64;
                c + c * (c + 1.0) / 2.0
            })
            .sum();
        flops <= SUPERNODAL_FLOPS_PER_ENTRY * self.nnz_l().max(1) as f64
    }
}

/// The size of a square `upper`.
fn square(upper: SymbolicSparseColMatRef<'_, usize>) -> Result<usize, LinalgError> {
    let n = upper.nrows();
    if upper.ncols() != n {
        return Err(LinalgError::Shape {
            rows: n,
            cols: upper.ncols(),
        });
    }
    Ok(n)
}

/// The pattern of L: the rows of each column (for the solves) and the columns of each row in
/// dependency order (for the numeric factorisation).  Reusable for every matrix with the
/// analysed pattern.
#[derive(Debug, Clone)]
pub struct SimplicialPattern {
    /// Column j of L at `col_ptr[j]..col_ptr[j + 1]` of `row_idx` and of the values: the
    /// diagonal (D's entry) first, then the rows below it, ascending.
    col_ptr: Vec<usize>,
    /// Rows of L, column by column.
    row_idx: Vec<u32>,
    /// Row k's strictly lower entries at `row_ptr[k]..row_ptr[k + 1]` of `row_cols`.
    row_ptr: Vec<usize>,
    /// Columns of the strictly lower entries of L, row by row, each column after its
    /// descendants in the elimination tree — except the first column of a pair (below) in the
    /// rows after the pair, where the pair is worked at its second column.
    row_cols: Vec<u32>,
    /// Entries of each column of the analysed upper triangle, cumulated: a matrix handed to
    /// [`SimplicialLdlt::factor`] must have the same (a cheap check of the pattern).
    upper_ptr: Vec<usize>,
    /// `second[j]`: columns j − 1 and j are a pair, the rows of j − 1 being j's and j itself
    /// (a node's two displacements, mostly): the numeric factorisation works both in one pass
    /// over their rows.
    second: Vec<bool>,
}

impl SimplicialPattern {
    /// The pattern of L for `upper` (the matrix `tree` was computed for): one more walk of the
    /// row subtrees, which records what [`EliminationTree::of`] only counted.
    ///
    /// # Errors
    /// [`LinalgError::Shape`] when `upper` is not the tree's matrix; [`LinalgError::Faer`]
    /// when L has more than 2³² − 1 rows or cannot be allocated.
    pub fn analyse(
        upper: SymbolicSparseColMatRef<'_, usize>,
        tree: &EliminationTree,
    ) -> Result<Self, LinalgError> {
        let n = square(upper)?;
        if tree.parent.len() != n {
            return Err(LinalgError::Shape {
                rows: tree.parent.len(),
                cols: n,
            });
        }
        if u32::try_from(n).is_err() {
            return Err(LinalgError::Faer(format!(
                "{n} unknowns: the simplicial factor indexes at most 2³² − 1"
            )));
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        for &c in &tree.counts {
            col_ptr.push(col_ptr[col_ptr.len() - 1] + c);
        }
        let nnz = col_ptr[n];
        let row_idx = zeroed::<u32>(nnz)?;
        let row_cols = zeroed::<u32>(nnz - n)?;
        let mut pattern = Self {
            col_ptr,
            row_idx,
            row_ptr: Vec::with_capacity(n + 1),
            row_cols,
            upper_ptr: entries_per_column(upper),
            second: pairs(tree),
        };
        pattern.fill(upper, &tree.parent)?;
        Ok(pattern)
    }

    /// Records the row subtree of every row k: its columns into `row_cols` (each walk from an
    /// entry of column k up to a node already visited is one segment, and every later segment
    /// ends below an earlier one, so the segments are laid down last first: each column after
    /// its descendants), and k into the rows of each of those columns (ascending, as k grows).
    ///
    /// # Errors
    /// [`LinalgError::Shape`] when a column outgrows its count: `parent` was not computed for
    /// `upper`.
    fn fill(
        &mut self,
        upper: SymbolicSparseColMatRef<'_, usize>,
        parent: &[usize],
    ) -> Result<(), LinalgError> {
        let n = parent.len();
        let mut mark = vec![ROOT; n];
        let mut next: Vec<usize> = self.col_ptr[..n].iter().map(|&p| p + 1).collect();
        let mut stack = vec![0u32; n];
        let mut end = 0;
        self.row_ptr.push(0);
        for k in 0..n {
            self.row_idx[self.col_ptr[k]] = k as u32;
            mark[k] = k;
            // The segments are stacked from the top of `stack` down.
            let mut top = n;
            for &i in upper.row_idx_of_col_raw(k) {
                let start = top;
                let mut j = i;
                while j < k && mark[j] != k {
                    mark[j] = k;
                    top -= 1;
                    stack[top] = j as u32;
                    j = parent[j];
                }
                // The segment lies reversed (its root first): put it child first.
                stack[top..start].reverse();
            }
            // Every segment now sits below the ones found before it.
            let reach = &stack[top..n];
            for &j in reach {
                let j = j as usize;
                if next[j] >= self.col_ptr[j + 1] {
                    return Err(LinalgError::Shape {
                        rows: n,
                        cols: upper.ncols(),
                    });
                }
                self.row_idx[next[j]] = k as u32;
                next[j] += 1;
                // The first column of a pair is worked with its second, which is in the reach
                // too (the pair's rows are the same) unless it is k itself.
                let with_second = j + 1 < k && self.second[j + 1];
                if !with_second {
                    self.row_cols[end] = j as u32;
                    end += 1;
                }
            }
            self.row_ptr.push(end);
        }
        self.row_cols.truncate(end);
        Ok(())
    }

    /// Size n of the matrix.
    pub fn dim(&self) -> usize {
        self.row_ptr.len().saturating_sub(1)
    }

    /// Entries of L, diagonal included: the values a factor stores.
    pub fn nnz_l(&self) -> usize {
        self.col_ptr.last().copied().unwrap_or(0)
    }

    /// Bytes the pattern holds (both index arrays and their pointers).
    pub fn bytes(&self) -> usize {
        4 * (self.row_idx.len() + self.row_cols.len())
            + 8 * (self.col_ptr.len() + self.row_ptr.len())
    }
}

/// The pairs of columns (j − 1, j) whose rows are the same but for j itself: j is the parent of
/// j − 1 and its column has one entry fewer.  Taken from the left, a column in one pair at most.
fn pairs(tree: &EliminationTree) -> Vec<bool> {
    let n = tree.parent.len();
    let mut second = vec![false; n];
    let mut j = 1;
    while j < n {
        if tree.parent[j - 1] == j && tree.counts[j - 1] == tree.counts[j] + 1 {
            second[j] = true;
            j += 2;
        } else {
            j += 1;
        }
    }
    second
}

/// The entries of each column of `upper`, cumulated from 0.
fn entries_per_column(upper: SymbolicSparseColMatRef<'_, usize>) -> Vec<usize> {
    let mut ptr = Vec::with_capacity(upper.ncols() + 1);
    ptr.push(0);
    for k in 0..upper.ncols() {
        ptr.push(ptr[k] + upper.row_idx_of_col_raw(k).len());
    }
    ptr
}

/// A zero-filled vector, or the allocation failure as an error.
fn zeroed<T: Clone + Default>(len: usize) -> Result<Vec<T>, LinalgError> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|e| LinalgError::Faer(format!("cannot allocate {len} entries of L: {e}")))?;
    v.resize(len, T::default());
    Ok(v)
}

/// How a pivot of the wrong sign or too small a magnitude is replaced (faer's dynamic
/// regularisation of a quasi-definite LDLᵀ): a pivot whose sign should be +1 and is ≤ ε
/// becomes +δ, one whose sign should be −1 and is ≥ −ε becomes −δ; with δ = 0 none is.
#[derive(Debug, Clone, Copy)]
pub struct Regularisation<'a> {
    /// The expected sign of every pivot, in the elimination order.
    pub signs: &'a [i8],
    /// ε ≥ 0.
    pub epsilon: f64,
    /// δ > 0.
    pub delta: f64,
}

/// A numeric LDLᵀ factor on a [`SimplicialPattern`], refactorised in place.
#[derive(Debug, Clone)]
pub struct SimplicialLdlt {
    /// Column j of L at the pattern's `col_ptr[j]..`: D's entry first, then L's.
    values: Vec<f64>,
    /// A dense row of the factorisation in progress (zero between rows).
    row: Vec<f64>,
    /// The next free slot of each column while a factorisation runs.
    next: Vec<usize>,
}

impl SimplicialLdlt {
    /// Allocates a factor for `pattern` (values zero until [`SimplicialLdlt::factor`]).
    ///
    /// # Errors
    /// [`LinalgError::Faer`] when the values cannot be allocated.
    pub fn new(pattern: &SimplicialPattern) -> Result<Self, LinalgError> {
        Ok(Self {
            values: zeroed(pattern.nnz_l())?,
            row: zeroed(pattern.dim())?,
            next: zeroed(pattern.dim())?,
        })
    }

    /// Bytes the factor holds besides its pattern.
    pub fn bytes(&self) -> usize {
        8 * (self.values.len() + self.row.len() + self.next.len())
    }

    /// LDLᵀ of the matrix whose upper triangle is `upper` (the pattern's matrix, new values),
    /// row by row: row k of L solves against the rows above it, walking the columns the
    /// pattern lists for it.  Returns how many pivots were replaced ([`Regularisation`]).
    ///
    /// # Errors
    /// [`LinalgError::Shape`] when `upper` (its size or its entries per column) or the signs
    /// do not match the pattern;
    /// [`LinalgError::ZeroPivot`] when a pivot is zero or not finite after the
    /// regularisation (the factor's values are then unusable).
    pub fn factor(
        &mut self,
        pattern: &SimplicialPattern,
        upper: SparseColMatRef<'_, usize, f64>,
        regularisation: Regularisation<'_>,
    ) -> Result<usize, LinalgError> {
        let n = pattern.dim();
        if upper.nrows() != n
            || upper.ncols() != n
            || regularisation.signs.len() != n
            || self.values.len() != pattern.nnz_l()
            || self.row.len() != n
            || entries_per_column(upper.symbolic()) != pattern.upper_ptr
        {
            return Err(LinalgError::Shape {
                rows: upper.nrows(),
                cols: upper.ncols(),
            });
        }
        let (col_ptr, row_idx) = (&pattern.col_ptr, &pattern.row_idx);
        let (epsilon, delta) = (regularisation.epsilon.abs(), regularisation.delta.abs());
        for (slot, &p) in self.next.iter_mut().zip(col_ptr) {
            *slot = p + 1;
        }
        let mut sweep = Sweep {
            row_idx,
            col_ptr,
            values: &mut self.values,
            row: &mut self.row,
            next: &mut self.next,
        };
        let mut replaced = 0;
        for (k, &sign) in regularisation.signs.iter().enumerate() {
            for (&i, &v) in upper.row_idx_of_col_raw(k).iter().zip(upper.val_of_col(k)) {
                if i <= k {
                    sweep.row[i] += v;
                }
            }
            let mut d = sweep.row[k];
            sweep.row[k] = 0.0;
            for &j in &pattern.row_cols[pattern.row_ptr[k]..pattern.row_ptr[k + 1]] {
                let j = j as usize;
                d -= if pattern.second[j] {
                    sweep.eliminate_pair(j - 1)
                } else {
                    sweep.eliminate(j)
                };
            }
            // As faer: no replacement at all when δ = 0.
            if delta > 0.0 && sign > 0 && d <= epsilon {
                d = delta;
                replaced += 1;
            } else if delta > 0.0 && sign < 0 && d >= -epsilon {
                d = -delta;
                replaced += 1;
            }
            debug_assert!(sweep.row.iter().all(|&v| v == 0.0), "row {k} left entries");
            if d == 0.0 || !d.is_finite() {
                sweep.row.fill(0.0);
                return Err(LinalgError::ZeroPivot { index: k, n });
            }
            sweep.values[col_ptr[k]] = d;
        }
        Ok(replaced)
    }

    /// Overwrites `rhs` (length n, in the elimination order) with (L D Lᵀ)⁻¹ rhs.
    ///
    /// # Panics
    /// When `rhs` is shorter than n.
    pub fn solve_in_place(&self, pattern: &SimplicialPattern, rhs: &mut [f64]) {
        let n = pattern.dim();
        assert!(
            rhs.len() >= n,
            "a right-hand side of {} for n = {n}",
            rhs.len()
        );
        let (col_ptr, row_idx, values) = (&pattern.col_ptr, &pattern.row_idx, &self.values);
        // L y = b, a pair of columns in one pass over their common rows.
        let mut j = 0;
        while j < n {
            let (start, end) = (col_ptr[j] + 1, col_ptr[j + 1]);
            if j + 1 < n && pattern.second[j + 1] {
                let (next_start, next_end) = (col_ptr[j + 1] + 1, col_ptr[j + 2]);
                let y0 = rhs[j];
                let y1 = rhs[j + 1] - values[start] * y0;
                rhs[j + 1] = y1;
                for ((&i, &l0), &l1) in row_idx[next_start..next_end]
                    .iter()
                    .zip(&values[start + 1..end])
                    .zip(&values[next_start..next_end])
                {
                    rhs[i as usize] -= l0 * y0 + l1 * y1;
                }
                j += 2;
            } else {
                let y = rhs[j];
                for (&i, &l) in row_idx[start..end].iter().zip(&values[start..end]) {
                    rhs[i as usize] -= l * y;
                }
                j += 1;
            }
        }
        for (x, &p) in rhs.iter_mut().zip(col_ptr) {
            *x /= values[p];
        }
        // Lᵀ x = D⁻¹ y, from the last column back, pairs as above.
        let mut j = n;
        while j > 0 {
            let last = j - 1;
            let (start, end) = (col_ptr[last] + 1, col_ptr[last + 1]);
            if pattern.second[last] {
                let first = last - 1;
                let first_start = col_ptr[first] + 1;
                let (mut s0, mut s1) = (0.0, 0.0);
                for ((&i, &l0), &l1) in row_idx[start..end]
                    .iter()
                    .zip(&values[first_start + 1..start - 1])
                    .zip(&values[start..end])
                {
                    let x = rhs[i as usize];
                    s0 += l0 * x;
                    s1 += l1 * x;
                }
                rhs[last] -= s1;
                rhs[first] -= s0 + values[first_start] * rhs[last];
                j -= 2;
            } else {
                let s: f64 = row_idx[start..end]
                    .iter()
                    .zip(&values[start..end])
                    .map(|(&i, &l)| l * rhs[i as usize])
                    .sum();
                rhs[last] -= s;
                j -= 1;
            }
        }
    }
}

/// The state of one numeric factorisation while it runs: L's pattern (the columns' rows and
/// where each column starts), the values so far, the dense row k, the next free slot of each
/// column.
struct Sweep<'a> {
    row_idx: &'a [u32],
    col_ptr: &'a [usize],
    values: &'a mut [f64],
    row: &'a mut [f64],
    next: &'a mut [usize],
}

impl Sweep<'_> {
    /// Row k's entry in column j (its value y in `row`, all of row k's entries left of j
    /// final): subtracts y times column j's rows above k from `row`, writes lₖⱼ = y / dⱼ into
    /// column j's next slot, and returns lₖⱼ y, what the pivot of row k loses.
    fn eliminate(&mut self, j: usize) -> f64 {
        let y = self.row[j];
        self.row[j] = 0.0;
        let start = self.col_ptr[j];
        let slot = self.next[j];
        for (&i, &l_ij) in self.row_idx[start + 1..slot]
            .iter()
            .zip(&self.values[start + 1..slot])
        {
            self.row[i as usize] -= l_ij * y;
        }
        let l_kj = y / self.values[start];
        self.values[slot] = l_kj;
        self.next[j] = slot + 1;
        l_kj * y
    }

    /// [`Sweep::eliminate`] for the pair of columns j and j + 1 (see
    /// `SimplicialPattern::second`) in one pass over their common rows: column j's entry in
    /// row j + 1 first, then both columns.
    fn eliminate_pair(&mut self, j: usize) -> f64 {
        let (first, second) = (self.col_ptr[j], self.col_ptr[j + 1]);
        let (first_slot, second_slot) = (self.next[j], self.next[j + 1]);
        let y0 = self.row[j];
        let y1 = self.row[j + 1] - self.values[first + 1] * y0;
        self.row[j] = 0.0;
        self.row[j + 1] = 0.0;
        for ((&i, &l0), &l1) in self.row_idx[second + 1..second_slot]
            .iter()
            .zip(&self.values[first + 2..first_slot])
            .zip(&self.values[second + 1..second_slot])
        {
            self.row[i as usize] -= l0 * y0 + l1 * y1;
        }
        let (l_k0, l_k1) = (y0 / self.values[first], y1 / self.values[second]);
        self.values[first_slot] = l_k0;
        self.values[second_slot] = l_k1;
        self.next[j] = first_slot + 1;
        self.next[j + 1] = second_slot + 1;
        l_k0 * y0 + l_k1 * y1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::cholesky::ldlt::factor::LdltRegularization;
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, SymmetricOrdering,
    };
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::{SparseColMat, Triplet};
    use faer::{Conj, MatMut, Par, Side};

    /// The couplings (p, q, value) of the five-point Laplacian on a `side`² grid, plus 0.1 on
    /// its diagonal, node by node, each pair once.
    fn grid_laplacian(side: usize, visit: &mut impl FnMut(usize, usize, f64)) {
        for r in 0..side {
            for c in 0..side {
                let k = r * side + c;
                visit(k, k, 4.1);
                if c + 1 < side {
                    visit(k, k + 1, -1.0);
                }
                if r + 1 < side {
                    visit(k, k + side, -1.0);
                }
            }
        }
    }

    /// A quasi-definite matrix [A, Bᵀ; B, −δI] with A a 2D five-point Laplacian (plus a little
    /// of the identity) on a `side`² grid and `m` rows of B coupling scattered unknowns, its
    /// unknowns scrambled by a fixed permutation when `scrambled` (which fills L up: small
    /// sizes only), else the grid row by row and the multipliers last; the upper triangle,
    /// and the signs of the pivots.
    fn quasi_definite(
        side: usize,
        m: usize,
        scrambled: bool,
    ) -> (SparseColMat<usize, f64>, Vec<i8>) {
        let n = side * side;
        let dim = n + m;
        let scramble = |k: usize| if scrambled { (k * 7919) % dim } else { k };
        let mut triplets = Vec::new();
        let mut push = |i: usize, j: usize, v: f64| {
            let (i, j) = (scramble(i), scramble(j));
            triplets.push(Triplet::new(i.min(j), i.max(j), v));
        };
        grid_laplacian(side, &mut push);
        for row in 0..m {
            let a = (row * 37) % n;
            let b = (row * 101 + 13) % n;
            push(n + row, a, 1.0);
            if a != b {
                push(n + row, b, -0.7);
            }
            push(n + row, n + row, -1e-3);
        }
        let mut signs = vec![1i8; dim];
        for row in 0..m {
            signs[scramble(n + row)] = -1;
        }
        (
            SparseColMat::try_new_from_triplets(dim, dim, &triplets).unwrap(),
            signs,
        )
    }

    /// faer's simplicial LDLᵀ of the same upper triangle, without a permutation: the values of
    /// L and D, laid out as faer stores them (its own pattern).
    fn faer_solve(upper: &SparseColMat<usize, f64>, signs: &[i8], rhs: &mut [f64]) {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(
            upper.symbolic(),
            Side::Upper,
            SymmetricOrdering::Identity,
            params,
        )
        .unwrap();
        let mut values = vec![0.0; symbolic.len_val()];
        let mut buffer = MemBuffer::new(faer::dyn_stack::StackReq::any_of(&[
            symbolic.factorize_numeric_ldlt_scratch::<f64>(Par::Seq, Default::default()),
            symbolic.solve_in_place_scratch::<f64>(1, Par::Seq),
        ]));
        symbolic
            .factorize_numeric_ldlt(
                &mut values,
                upper.as_ref(),
                Side::Upper,
                LdltRegularization {
                    dynamic_regularization_signs: Some(signs),
                    dynamic_regularization_delta: 1e-12,
                    dynamic_regularization_epsilon: 1e-14,
                },
                Par::Seq,
                MemStack::new(&mut buffer),
                Default::default(),
            )
            .unwrap();
        let n = rhs.len();
        LdltRef::new(&symbolic, &values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut buffer),
        );
    }

    /// K z, from the upper triangle (both triangles applied).
    fn apply(upper: &SparseColMat<usize, f64>, z: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; z.len()];
        for j in 0..upper.ncols() {
            for (&i, &v) in upper
                .symbolic()
                .row_idx_of_col_raw(j)
                .iter()
                .zip(upper.val_of_col(j))
            {
                out[i] += v * z[j];
                if i != j {
                    out[j] += v * z[i];
                }
            }
        }
        out
    }

    /// The same K solved by faer's simplicial LDLᵀ and by this one agree to round-off, and the
    /// residual K z − b is a small multiple of ε ‖K‖ ‖z‖ (`solves_as_faer`), refactorised with
    /// other values on the same pattern.
    #[test]
    fn agrees_with_faer_and_solves_to_round_off() {
        for (side, m, scrambled) in [(1, 0, true), (6, 4, true), (20, 60, true), (45, 300, false)] {
            let (mut upper, signs) = quasi_definite(side, m, scrambled);
            let tree = EliminationTree::of(upper.symbolic()).unwrap();
            let pattern = SimplicialPattern::analyse(upper.symbolic(), &tree).unwrap();
            let mut factor = SimplicialLdlt::new(&pattern).unwrap();
            for round in 0..2 {
                if round == 1 {
                    for v in upper.val_mut() {
                        *v *= 1.5;
                    }
                }
                let regularisation = Regularisation {
                    signs: &signs,
                    epsilon: 1e-14,
                    delta: 1e-12,
                };
                let replaced = factor
                    .factor(&pattern, upper.as_ref(), regularisation)
                    .unwrap();
                assert_eq!(replaced, 0, "side {side}, m {m}");
                solves_as_faer(&upper, &signs, &pattern, &factor, &format!("side {side}"));
            }
            assert_eq!(pattern.nnz_l(), tree.nnz_l());
        }
    }

    /// A 2D grid with two unknowns per node (the Laplacian ⊗ [[2, 0.5], [0.5, 1]], as an
    /// elasticity stiffness couples a node's displacements), numbered node by node, plus `m`
    /// multiplier rows: its upper triangle and pivot signs.
    fn two_per_node(side: usize, m: usize, scrambled: bool) -> (SparseColMat<usize, f64>, Vec<i8>) {
        let nodes = side * side;
        let n = 2 * nodes;
        let block = [[2.0, 0.5], [0.5, 1.0]];
        // The nodes renumbered (a node's two unknowns stay together): a branching tree.
        let renumber = |p: usize| if scrambled { (p * 7919) % nodes } else { p };
        let mut triplets = Vec::new();
        let mut couple = |p: usize, q: usize, w: f64| {
            let (p, q) = (renumber(p), renumber(q));
            for (a, block_row) in block.iter().enumerate() {
                for (b, &v) in block_row.iter().enumerate() {
                    let (i, j) = (2 * p + a, 2 * q + b);
                    if p != q || a <= b {
                        triplets.push(Triplet::new(i.min(j), i.max(j), w * v));
                    }
                }
            }
        };
        grid_laplacian(side, &mut couple);
        for row in 0..m {
            let node = (row * 37) % nodes;
            triplets.push(Triplet::new(2 * node + 1, n + row, 1.0));
            triplets.push(Triplet::new(n + row, n + row, -1e-3));
        }
        let signs = (0..n + m).map(|k| if k < n { 1 } else { -1 }).collect();
        (
            SparseColMat::try_new_from_triplets(n + m, n + m, &triplets).unwrap(),
            signs,
        )
    }

    /// A node's two unknowns are worked as a pair (most columns here are in one), and the
    /// factor still agrees with faer's and solves K z = b to round-off (`solves_as_faer`), on a
    /// banded and on a branching elimination tree.
    #[test]
    fn a_nodes_two_unknowns_are_worked_as_a_pair() {
        for scrambled in [false, true] {
            pairs_agree_with_faer(scrambled);
        }
    }

    /// One case of `a_nodes_two_unknowns_are_worked_as_a_pair`.
    fn pairs_agree_with_faer(scrambled: bool) {
        let (upper, signs) = two_per_node(25, 40, scrambled);
        let dim = upper.ncols();
        let tree = EliminationTree::of(upper.symbolic()).unwrap();
        let pattern = SimplicialPattern::analyse(upper.symbolic(), &tree).unwrap();
        let pairs = pattern.second.iter().filter(|&&p| p).count();
        assert!(
            2 * pairs >= 1200,
            "scrambled {scrambled}: {pairs} pairs of {dim} columns"
        );
        let mut factor = SimplicialLdlt::new(&pattern).unwrap();
        let regularisation = Regularisation {
            signs: &signs,
            epsilon: 1e-14,
            delta: 1e-12,
        };
        assert_eq!(
            factor
                .factor(&pattern, upper.as_ref(), regularisation)
                .unwrap(),
            0
        );
        solves_as_faer(
            &upper,
            &signs,
            &pattern,
            &factor,
            &format!("scrambled {scrambled}"),
        );
    }

    /// Solves K z = b (a fixed b) with `factor` and asserts that z agrees with faer's solve and
    /// that K z − b is within 1e3 ε ‖K‖∞ max |z|: a backward-stable LDLᵀ leaves a modest
    /// multiple of ε there, and 1e3 leaves room for the growth of a factorisation without
    /// pivoting on a quasi-definite K.  The two kernels agree far closer than K's condition
    /// allows in general: they do nearly the same arithmetic in the same order.
    fn solves_as_faer(
        upper: &SparseColMat<usize, f64>,
        signs: &[i8],
        pattern: &SimplicialPattern,
        factor: &SimplicialLdlt,
        case: &str,
    ) {
        let dim = upper.ncols();
        let b: Vec<f64> = (0..dim).map(|k| (k as f64 * 0.37 + 0.5).sin()).collect();
        let mut z = b.clone();
        factor.solve_in_place(pattern, &mut z);
        let mut z_faer = b.clone();
        faer_solve(upper, signs, &mut z_faer);
        let ones = vec![1.0; dim];
        let norm = apply(&abs(upper), &ones)
            .into_iter()
            .fold(0.0_f64, f64::max);
        let z_max = z.iter().fold(0.0_f64, |r, v| r.max(v.abs()));
        let bound = 1e3 * f64::EPSILON * norm * z_max;
        let max_diff = |a: &[f64], b: &[f64]| {
            a.iter()
                .zip(b)
                .fold(0.0_f64, |r, (a, b)| r.max((a - b).abs()))
        };
        let gap = max_diff(&z, &z_faer);
        assert!(gap <= bound, "{case}: gap {gap:e} over {bound:e}");
        let residual = max_diff(&apply(upper, &z), &b);
        assert!(
            residual <= bound,
            "{case}: residual {residual:e} over {bound:e}"
        );
    }

    /// `upper` with every value replaced by its magnitude.
    fn abs(upper: &SparseColMat<usize, f64>) -> SparseColMat<usize, f64> {
        let mut m = upper.clone();
        for v in m.val_mut() {
            *v = v.abs();
        }
        m
    }

    /// Every column of a row's pattern comes after its descendants, and the rows of every
    /// column ascend: checked against the definition on the scrambled matrices above.
    #[test]
    fn rows_list_their_columns_after_the_columns_below_them() {
        let (upper, _) = quasi_definite(20, 90, true);
        let tree = EliminationTree::of(upper.symbolic()).unwrap();
        let pattern = SimplicialPattern::analyse(upper.symbolic(), &tree).unwrap();
        for k in 0..pattern.dim() {
            let cols = &pattern.row_cols[pattern.row_ptr[k]..pattern.row_ptr[k + 1]];
            for (a, &j) in cols.iter().enumerate() {
                // No later column of the row is a descendant of j.
                for &later in &cols[a + 1..] {
                    let mut up = later as usize;
                    while up != ROOT && up < k {
                        assert_ne!(up, j as usize, "row {k}: {later} after its ancestor {j}");
                        up = tree.parent[up];
                    }
                }
            }
        }
        for j in 0..pattern.dim() {
            let rows = &pattern.row_idx[pattern.col_ptr[j]..pattern.col_ptr[j + 1]];
            assert_eq!(rows[0] as usize, j);
            assert!(rows.windows(2).all(|w| w[0] < w[1]), "column {j}: {rows:?}");
        }
    }

    /// A pivot of the wrong sign is replaced by ±δ and counted; a zero pivot where no sign
    /// asks for a replacement is an error, not a factor with an infinity in it.
    #[test]
    fn wrong_signs_are_replaced_and_zero_pivots_refused() {
        // [[1, 1], [1, 1]] (upper): the second pivot is 1 − 1 = 0.
        let upper = SparseColMat::<usize, f64>::try_new_from_triplets(
            2,
            2,
            &[
                Triplet::new(0, 0, 1.0),
                Triplet::new(0, 1, 1.0),
                Triplet::new(1, 1, 1.0),
            ],
        )
        .unwrap();
        let tree = EliminationTree::of(upper.symbolic()).unwrap();
        let pattern = SimplicialPattern::analyse(upper.symbolic(), &tree).unwrap();
        let mut factor = SimplicialLdlt::new(&pattern).unwrap();
        let replaced = factor
            .factor(
                &pattern,
                upper.as_ref(),
                Regularisation {
                    signs: &[1, 1],
                    epsilon: 1e-12,
                    delta: 1e-6,
                },
            )
            .unwrap();
        assert_eq!(replaced, 1);
        assert_eq!(factor.values, vec![1.0, 1.0, 1e-6]);
        let refused = factor.factor(
            &pattern,
            upper.as_ref(),
            Regularisation {
                signs: &[1, 0],
                epsilon: 1e-12,
                delta: 1e-6,
            },
        );
        assert!(matches!(
            refused,
            Err(LinalgError::ZeroPivot { index: 1, n: 2 })
        ));
        // δ = 0 replaces nothing (as faer): the same zero pivot is refused whatever its sign.
        let unregularised = factor.factor(
            &pattern,
            upper.as_ref(),
            Regularisation {
                signs: &[1, 1],
                epsilon: 1e-12,
                delta: 0.0,
            },
        );
        assert!(matches!(
            unregularised,
            Err(LinalgError::ZeroPivot { index: 1, n: 2 })
        ));
        // A matrix with another pattern than the analysed one is refused, not factored.
        let diagonal = SparseColMat::<usize, f64>::try_new_from_triplets(
            2,
            2,
            &[Triplet::new(0, 0, 1.0), Triplet::new(1, 1, 1.0)],
        )
        .unwrap();
        let other = factor.factor(
            &pattern,
            diagonal.as_ref(),
            Regularisation {
                signs: &[1, 1],
                epsilon: 1e-12,
                delta: 1e-6,
            },
        );
        assert!(matches!(other, Err(LinalgError::Shape { .. })));
        assert!(factor.row.iter().all(|&v| v == 0.0));
    }

    /// The flop rule: a chain is simplicial, a dense block supernodal.
    #[test]
    fn a_chain_suits_a_simplicial_factor_and_a_dense_block_does_not() {
        let chain: Vec<_> = (0..50)
            .flat_map(|k| {
                let mut t = vec![Triplet::new(k, k, 2.0)];
                if k > 0 {
                    t.push(Triplet::new(k - 1, k, -1.0));
                }
                t
            })
            .collect();
        let chain = SparseColMat::<usize, f64>::try_new_from_triplets(50, 50, &chain).unwrap();
        assert!(EliminationTree::of(chain.symbolic())
            .unwrap()
            .suits_simplicial());
        let dense: Vec<_> = (0..200)
            .flat_map(|j| {
                (0..=j).map(move |i| Triplet::new(i, j, if i == j { 300.0 } else { 1.0 }))
            })
            .collect();
        let dense = SparseColMat::<usize, f64>::try_new_from_triplets(200, 200, &dense).unwrap();
        assert!(!EliminationTree::of(dense.symbolic())
            .unwrap()
            .suits_simplicial());
    }
}
