//! The fill-reducing ordering every sparse factorisation of the project uses: the timing floor,
//! the dual backends' factor of A and the sparse KKT factor of the active-set backend.  One
//! function, so that a floor and the solves it is compared with always share the ordering path.
//!
//! Three orderings are available: approximate minimum degree ([`OrderingMethod::Amd`], faer's
//! AMD), the same on the node-compressed graph ([`OrderingMethod::AmdNodes`]) and nested
//! dissection ([`OrderingMethod::Metis`], METIS_NodeND through `signorini-metis`).
//! [`fill_reducing_order`] picks one for A by the rule below; [`kkt_order`] orders the KKT
//! matrices of the active-set backend on their nodes (same fill, found 14–58 % faster; on A
//! the compressed graph lost fill as often as it saved time, see [`kkt_order`]).
//!
//! # The rule: AMD
//!
//! [`fill_reducing_order`] orders every matrix by AMD.  Nested dissection (METIS) cuts the
//! flops of the factorisation of the seed geometry by half or more from 10⁶ DOFs on and nnz(L)
//! by 20–30 %, so its numeric factorisation is 1.3–1.6× faster there; but METIS's ordering
//! (single-threaded, on the node graph: the two DOFs of a node merged) costs 2–7× AMD's on the
//! seed geometry and 5–10× on the strips, more than the numeric factorisation saves, at every
//! size measured up to 5.1·10⁶ DOFs (beyond the 4·10⁶ that fit this machine's memory with a
//! solve): at 5.1·10⁶ AMD takes 36.1 s in all, METIS 40.4 s.  On the long strips METIS does not
//! even reduce the fill much.  The ordering's time is part of the floor, so AMD is the best
//! ordering the project has on this machine.  METIS stays available through [`order_with`] (for
//! a caller that reuses one factor for many solves: each solve costs ∝ nnz(L)).  Picking by
//! nnz(L) would need both orderings, i.e. METIS's time, every time.
//!
//! Measured on the 2-core development machine (24 GiB), each factor with
//! [`super::CholeskyPattern`] (forced supernodal, `Par::Seq`) of the reduced stiffness of real
//! scenes: `seed-hH` is `fixtures/seed/exp3-both-h0.08.toml` with `hmax = H` on both bodies,
//! `strip-hH` is `strip-floating` (a 20 × 0.02 strip on a 20 × 0.04 foundation) at `hmax = H`,
//! `thick-hH` the same with a 0.1-thick strip (10 elements at H = 0.01).  Other builds and
//! solves were running on the machine (load 2.6–4.8 on 2 cores during run A, 4–7 during run B):
//! compare the two rows of one scene, not seconds across scenes.
//!
//! Run A (the code as it is):
//!
//! | scene | n | nnz(A) | ordering | order s | symbolic s | numeric s | total s | nnz(L) | flops |
//! |---|---:|---:|---|---:|---:|---:|---:|---:|---:|
//! | seed-h0.0096 | 126 472 | 1 759 200 | amd | 0.117 | 0.042 | 0.221 | 0.381 | 1.01e7 | 2.42e9 |
//! | | | | metis | 0.313 | 0.057 | 0.209 | 0.579 | 8.46e6 | 1.52e9 |
//! | strip-h0.0025 | 624 065 | 7 818 690 | amd | 0.657 | 0.183 | 0.606 | 1.445 | 2.27e7 | 1.43e9 |
//! | | | | metis | 3.295 | 0.323 | 0.674 | 4.293 | 2.29e7 | 1.31e9 |
//! | seed-h0.003 | 1 276 480 | 17 834 000 | amd | 1.408 | 0.712 | 3.980 | 6.099 | 1.53e8 | 1.03e11 |
//! | | | | metis | 3.181 | 0.550 | 2.820 | 6.552 | 1.17e8 | 5.21e10 |
//! | thick-h0.0025 | 1 360 185 | 16 976 871 | amd | 1.246 | 0.592 | 1.807 | 3.645 | 8.45e7 | 1.42e10 |
//! | | | | metis | 9.089 | 0.973 | 2.104 | 12.166 | 7.24e7 | 8.19e9 |
//! | seed-h0.0021 | 2 598 526 | 36 327 060 | amd | 2.736 | 1.433 | 9.778 | 13.946 | 3.56e8 | 3.38e11 |
//! | | | | metis | 9.630 | 1.658 | 7.479 | 18.767 | 2.58e8 | 1.54e11 |
//! | seed-h0.0015 | 5 090 580 | 71 195 704 | amd | 4.831 | 2.769 | 28.526 | 36.126 | 6.82e8 | 7.39e11 |
//! | | | | metis | 19.336 | 3.338 | 17.713 | 40.387 | 5.42e8 | 4.30e11 |
//!
//! Run B (smaller scenes; METIS then ordered the DOF graph, 1.7× slower than the node graph:
//! 0.78 s against 1.30 s at 126 472 DOFs, 2.98 s against 4.95 s at 356 573, from
//! `measure_metis_steps`; the symbolic column then included the exact nnz(L) count, ≈ 8 % of a
//! factorisation, since moved out of the floor):
//!
//! | scene | n | nnz(A) | ordering | order s | symbolic s | numeric s | total s | nnz(L) | flops |
//! |---|---:|---:|---|---:|---:|---:|---:|---:|---:|
//! | seed-h0.03 | 13 508 | 185 416 | amd | 0.021 | 0.009 | 0.021 | 0.051 | 5.96e5 | 4.78e7 |
//! | | | | metis | 0.043 | 0.013 | 0.020 | 0.077 | 5.92e5 | 4.46e7 |
//! | strip-h0.01 | 51 575 | 631 785 | amd | 0.022 | 0.021 | 0.020 | 0.063 | 5.55e5 | 6.26e6 |
//! | | | | metis | 0.169 | 0.018 | 0.018 | 0.205 | 8.51e5 | 1.63e7 |
//! | thick-h0.01 | 95 619 | 1 176 338 | amd | 0.067 | 0.032 | 0.061 | 0.161 | 2.23e6 | 7.63e7 |
//! | | | | metis | 0.257 | 0.035 | 0.053 | 0.344 | 2.70e6 | 1.14e8 |
//! | strip-h0.005 | 174 271 | 2 152 017 | amd | 0.095 | 0.061 | 0.096 | 0.251 | 3.56e6 | 9.85e7 |
//! | | | | metis | 0.490 | 0.072 | 0.127 | 0.689 | 4.39e6 | 1.53e8 |
//! | thick-h0.005 | 356 573 | 4 481 609 | amd | 0.494 | 0.273 | 0.541 | 1.308 | 1.53e7 | 1.36e9 |
//! | | | | metis | 2.531 | 0.368 | 0.533 | 3.432 | 1.43e7 | 9.87e8 |
//!
//! (A third run under load 7 showed METIS ahead once, at 2 598 526 DOFs, because AMD's ordering
//! took 5× its run-A time there: load, not the ordering; run A repeats that scene.)
//!
//! Produced by (scenes written to /tmp with `sed "s/hmax = 0.08/hmax = H/"` and likewise):
//!
//! ```text
//! SIGNORINI_MEASURE_SCENES="/tmp/floor-scenes/seed-h0.03.toml …" \
//!   cargo test --release -p signorini-core --lib linalg::measure::measure_orderings \
//!   -- --ignored --nocapture
//! ```

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::SymbolicSparseColMatRef;

use super::{faer_view, LinalgError};
use crate::CscMatrix;

/// Which algorithm produced a [`FillOrdering`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrderingMethod {
    /// Approximate minimum degree (faer's AMD).
    Amd,
    /// AMD of the node-compressed graph ([`Compressed`]: the DOFs of a node merged where their
    /// neighbourhoods are equal), expanded back: the KKT matrices' ordering ([`KKT_RULE`]).
    AmdNodes,
    /// Nested dissection (METIS_NodeND, METIS 5 defaults).
    Metis,
}

impl OrderingMethod {
    /// Every method, for measurements and tests.
    pub const ALL: [OrderingMethod; 3] = [
        OrderingMethod::Amd,
        OrderingMethod::AmdNodes,
        OrderingMethod::Metis,
    ];

    /// The word used in reports (`"amd"`, `"amd-nodes"`, `"metis"`).
    pub fn as_str(self) -> &'static str {
        match self {
            OrderingMethod::Amd => "amd",
            OrderingMethod::AmdNodes => "amd-nodes",
            OrderingMethod::Metis => "metis",
        }
    }
}

impl std::fmt::Display for OrderingMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A symmetric permutation P (new index → old index in `forward`, old → new in `inverse`) that
/// keeps the Cholesky factor of P A Pᵀ sparse.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FillOrdering {
    /// `forward[new] = old`.
    pub forward: Vec<usize>,
    /// `inverse[old] = new`.
    pub inverse: Vec<usize>,
    /// How it was found.
    pub method: OrderingMethod,
}

impl FillOrdering {
    /// The ordering whose `forward[new] = old` is given (a permutation), its inverse computed.
    pub fn from_forward(forward: Vec<usize>, method: OrderingMethod) -> Self {
        let mut inverse = vec![0; forward.len()];
        for (new, &old) in forward.iter().enumerate() {
            inverse[old] = new;
        }
        Self {
            forward,
            inverse,
            method,
        }
    }
}

/// The ordering [`fill_reducing_order`] uses, for every size: see the module documentation for
/// the measurements behind the rule.
pub const RULE: OrderingMethod = OrderingMethod::Amd;

/// The fill-reducing ordering of the symmetric pattern of `a` (both triangles or one may be
/// stored; the pattern of A + Aᵀ is ordered), by the rule of the module documentation
/// ([`RULE`]: AMD, whose ordering time METIS's smaller factor never paid back on this machine).
pub fn fill_reducing_order(a: &CscMatrix) -> Result<FillOrdering, LinalgError> {
    order_with(a, RULE)
}

/// The ordering the sparse KKT matrices K = [A Bᵀ; B −D] of the active-set backend use: see
/// [`kkt_order`].
pub const KKT_RULE: OrderingMethod = OrderingMethod::AmdNodes;

/// The fill-reducing ordering of a KKT matrix K = [A Bᵀ; B −D] ([`KKT_RULE`]: AMD of its
/// node-compressed graph).  Measured on the KKT matrices of eight scenes (strips of 2·10³ and
/// 2·10⁴ rows, Tresca and frictionless, the partial and the thick floating strip, the Hertz
/// cylinder, the seed geometry at 1.2·10⁵ and 1.05·10⁶ DOFs; BENCHMARKS.md, "ordering the KKT
/// matrix on its nodes"): the same fill (nnz(L) −1.4 … +1.5 %, flops −6.8 … +3.5 %) found
/// 14–58 % faster.  A itself keeps [`RULE`]: on A the compressed graph changed the flops by
/// 0 … +16 % over four scenes, a loss as often as a gain once the numeric factorisation is
/// counted, so the floor's ordering of A stays the one that is never worse there.
///
/// `xadj`, `adjncy`: K's adjacency graph in CSR, without self-loops, each edge stored both
/// ways ([`adjacency`] of K's pattern, or [`super::kkt::kkt_graph`] straight from A and B).
///
/// # Errors
/// [`LinalgError::Ordering`] when the arrays are not such a graph's.
pub fn kkt_order(xadj: &[usize], adjncy: &[usize]) -> Result<FillOrdering, LinalgError> {
    check_graph(xadj, adjncy)?;
    amd_nodes_of(xadj, adjncy)
}

/// `xadj` starts at 0, never decreases and ends at `adjncy`'s length; every neighbour is a
/// vertex.
fn check_graph(xadj: &[usize], adjncy: &[usize]) -> Result<(), LinalgError> {
    let n = xadj.len().saturating_sub(1);
    let well_formed = xadj.first() == Some(&0)
        && xadj.last() == Some(&adjncy.len())
        && xadj.windows(2).all(|w| w[0] <= w[1])
        && adjncy.iter().all(|&v| v < n);
    if well_formed {
        Ok(())
    } else {
        Err(LinalgError::Ordering(
            "the graph to order is not in CSR form over its own vertices".into(),
        ))
    }
}

/// The ordering of `a` by the given method (for measurements and tests; solves use
/// [`fill_reducing_order`]).
pub fn order_with(a: &CscMatrix, method: OrderingMethod) -> Result<FillOrdering, LinalgError> {
    let n = a.rows();
    if a.cols() != n {
        return Err(LinalgError::Shape {
            rows: n,
            cols: a.cols(),
        });
    }
    let a = faer_view(a)?.symbolic();
    match method {
        OrderingMethod::Amd => amd_order(a),
        OrderingMethod::AmdNodes => amd_nodes_order(a),
        OrderingMethod::Metis => metis_order(a),
    }
}

fn amd_order(a: SymbolicSparseColMatRef<'_, usize>) -> Result<FillOrdering, LinalgError> {
    let n = a.nrows();
    let mut forward = vec![0usize; n];
    let mut inverse = vec![0usize; n];
    let mut buffer = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(
        n,
        a.compute_nnz(),
    ))
    .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    amd::order_maybe_unsorted(
        &mut forward,
        &mut inverse,
        a,
        amd::Control::default(),
        MemStack::new(&mut buffer),
    )
    .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    Ok(FillOrdering {
        forward,
        inverse,
        method: OrderingMethod::Amd,
    })
}

/// AMD on the node-compressed graph of A + Aᵀ ([`Compressed`]), expanded back to A's unknowns.
fn amd_nodes_order(a: SymbolicSparseColMatRef<'_, usize>) -> Result<FillOrdering, LinalgError> {
    let (xadj, adjncy) = adjacency_of(a);
    amd_nodes_of(&xadj, &adjncy)
}

/// AMD on the node-compressed form of the graph (`xadj`, `adjncy`), expanded back to its
/// vertices.
fn amd_nodes_of(xadj: &[usize], adjncy: &[usize]) -> Result<FillOrdering, LinalgError> {
    let groups = Compressed::of(xadj, adjncy);
    let g = groups.weight.len();
    let graph =
        SymbolicSparseColMatRef::new_unsorted_checked(g, g, &groups.xadj, None, &groups.adjncy);
    let mut order = vec![0usize; g];
    let mut inverse = vec![0usize; g];
    let mut buffer = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(
        g,
        groups.adjncy.len(),
    ))
    .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    amd::order_maybe_unsorted(
        &mut order,
        &mut inverse,
        graph,
        amd::Control::default(),
        MemStack::new(&mut buffer),
    )
    .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    Ok(FillOrdering::from_forward(
        groups.expand(&order),
        OrderingMethod::AmdNodes,
    ))
}

fn metis_order(a: SymbolicSparseColMatRef<'_, usize>) -> Result<FillOrdering, LinalgError> {
    let (xadj, adjncy) = adjacency_of(a);
    let groups = Compressed::of(&xadj, &adjncy);
    let (perm, _) =
        signorini_metis::node_nd_weighted(&groups.xadj, &groups.adjncy, Some(&groups.weight))
            .map_err(|e| LinalgError::Ordering(e.to_string()))?;
    Ok(FillOrdering::from_forward(
        groups.expand(&perm),
        OrderingMethod::Metis,
    ))
}

/// The graph with runs of consecutive vertices of identical closed neighbourhoods (the two DOFs
/// of a node, numbered one after the other) merged into one weighted vertex: half the vertices
/// and a quarter of the edges of a 2D elasticity DOF graph, so METIS orders it several times
/// faster than the DOF graph (its own compression finds the same groups but only after reading
/// the whole DOF graph).  Public for the hand-run measurement of the ordering rule
/// (`signorini-core`'s `linalg_measure`), not for use.
#[doc(hidden)]
pub struct Compressed {
    /// Group g holds the vertices `start[g]..start[g + 1]`.
    pub start: Vec<usize>,
    /// Number of vertices of each group.
    pub weight: Vec<usize>,
    /// The compressed graph's adjacency, CSR offsets.
    pub xadj: Vec<usize>,
    /// The compressed graph's adjacency, CSR neighbours.
    pub adjncy: Vec<usize>,
}

impl Compressed {
    /// The compressed graph of the CSR graph (`xadj`, `adjncy`: symmetric, no self-loops, no
    /// duplicates): consecutive vertices v, w are one group when w's closed neighbourhood is
    /// v's (they are adjacent and share every other neighbour), checked with a mark array in
    /// O(degree).
    pub fn of(xadj: &[usize], adjncy: &[usize]) -> Self {
        let n = xadj.len() - 1;
        let list = |v: usize| &adjncy[xadj[v]..xadj[v + 1]];
        // stamp[u] == v + 1: u is in v's closed neighbourhood (v the group's first vertex).
        let mut stamp = vec![0usize; n];
        let mut start = vec![0];
        let mut group_of = vec![0usize; n];
        let mut v = 0;
        while v < n {
            stamp[v] = v + 1;
            list(v).iter().for_each(|&u| stamp[u] = v + 1);
            let mut w = v + 1;
            while w < n
                && list(w).len() == list(v).len()
                && stamp[w] == v + 1
                && list(w).iter().all(|&u| stamp[u] == v + 1)
            {
                w += 1;
            }
            let g = start.len() - 1;
            group_of[v..w].iter_mut().for_each(|x| *x = g);
            start.push(w);
            v = w;
        }
        let groups = start.len() - 1;
        let weight: Vec<usize> = (0..groups).map(|g| start[g + 1] - start[g]).collect();
        let mut mark = vec![usize::MAX; groups];
        let mut gx = Vec::with_capacity(groups + 1);
        gx.push(0);
        let mut ga = Vec::with_capacity(adjncy.len() / 2);
        for g in 0..groups {
            mark[g] = g;
            for &w in list(start[g]) {
                let h = group_of[w];
                if mark[h] != g {
                    mark[h] = g;
                    ga.push(h);
                }
            }
            gx.push(ga.len());
        }
        Self {
            start,
            weight,
            xadj: gx,
            adjncy: ga,
        }
    }

    /// The vertex order of a group order: each group's vertices in place of the group.
    pub fn expand(&self, group_order: &[usize]) -> Vec<usize> {
        let mut forward = Vec::with_capacity(self.start.last().copied().unwrap_or(0));
        for &g in group_order {
            forward.extend(self.start[g]..self.start[g + 1]);
        }
        forward
    }
}

/// The adjacency graph of the pattern of A + Aᵀ without the diagonal, in CSR (`xadj`,
/// `adjncy`), each edge stored both ways once.
pub fn adjacency(a: &CscMatrix) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    Ok(adjacency_of(faer_view(a)?.symbolic()))
}

/// [`adjacency`] of a pattern.
fn adjacency_of(sym: SymbolicSparseColMatRef<'_, usize>) -> (Vec<usize>, Vec<usize>) {
    let n = sym.nrows();
    // Count both directions of every off-diagonal entry (duplicates when both triangles are
    // stored), fill, then remove the duplicates of each list in place.
    let mut ptr = vec![0usize; n + 1];
    for j in 0..n {
        for i in sym.row_idx_of_col(j) {
            if i != j {
                ptr[i + 1] += 1;
                ptr[j + 1] += 1;
            }
        }
    }
    for j in 0..n {
        ptr[j + 1] += ptr[j];
    }
    let mut fill = ptr.clone();
    let mut adj = vec![0usize; ptr[n]];
    for j in 0..n {
        for i in sym.row_idx_of_col(j) {
            if i != j {
                adj[fill[i]] = j;
                fill[i] += 1;
                adj[fill[j]] = i;
                fill[j] += 1;
            }
        }
    }
    let mut mark = vec![usize::MAX; n];
    let mut xadj = Vec::with_capacity(n + 1);
    xadj.push(0);
    let mut out = 0;
    for v in 0..n {
        for p in ptr[v]..ptr[v + 1] {
            let w = adj[p];
            if mark[w] != v {
                mark[w] = v;
                adj[out] = w;
                out += 1;
            }
        }
        xadj.push(out);
    }
    adj.truncate(out);
    adj.shrink_to_fit();
    (xadj, adj)
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    /// 5-point Laplacian on a side × side grid, both triangles stored.
    pub(crate) fn grid(side: usize) -> CscMatrix {
        let n = side * side;
        let id = |i: usize, j: usize| j * side + i;
        let mut t = TriMat::new((n, n));
        for j in 0..side {
            for i in 0..side {
                t.add_triplet(id(i, j), id(i, j), 4.0);
                if i + 1 < side {
                    t.add_triplet(id(i, j), id(i + 1, j), -1.0);
                    t.add_triplet(id(i + 1, j), id(i, j), -1.0);
                }
                if j + 1 < side {
                    t.add_triplet(id(i, j), id(i, j + 1), -1.0);
                    t.add_triplet(id(i, j + 1), id(i, j), -1.0);
                }
            }
        }
        t.to_csc()
    }

    fn assert_permutation(order: &FillOrdering, n: usize) {
        let mut seen = order.forward.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..n).collect::<Vec<_>>());
        for (new, &old) in order.forward.iter().enumerate() {
            assert_eq!(order.inverse[old], new);
        }
    }

    #[test]
    fn a_permutation_of_every_index() {
        let n = 30;
        let mut t = TriMat::new((n, n));
        for i in 0..n {
            t.add_triplet(i, i, 4.0);
            if i + 1 < n {
                t.add_triplet(i, i + 1, -1.0);
                t.add_triplet(i + 1, i, -1.0);
            }
        }
        let a = t.to_csc();
        for method in OrderingMethod::ALL {
            let order = order_with(&a, method).unwrap();
            assert_eq!(order.method, method);
            assert_permutation(&order, n);
        }
        assert_permutation(&fill_reducing_order(&grid(12)).unwrap(), 144);
    }

    #[test]
    fn the_rule_is_the_measured_one() {
        let a = grid(40);
        let order = fill_reducing_order(&a).unwrap();
        assert_eq!(order.method, RULE);
        assert_eq!(order, order_with(&a, RULE).unwrap());
        let (xadj, adjncy) = adjacency(&a).unwrap();
        let order = kkt_order(&xadj, &adjncy).unwrap();
        assert_eq!(order.method, KKT_RULE);
        assert_eq!(order, order_with(&a, KKT_RULE).unwrap());
    }

    /// A 2-DOF grid's node pairs have equal closed neighbourhoods (each DOF couples to both
    /// DOFs of its node and of every neighbour): one group per node, of weight 2, and the
    /// group graph is the node graph (8 neighbours inside, hand-counted at the corners: 3).
    /// A constraint row on one DOF of node 0 (a KKT matrix) splits that node's pair: the
    /// row's vertex alone, node 0 as two groups, the other nodes still pairs.
    #[test]
    fn the_compressed_graph_merges_exactly_the_dofs_with_equal_neighbourhoods() {
        use crate::examples::two_dof_grid;
        let side = 5;
        let nodes = side * side;
        let a = two_dof_grid(side);
        let (xadj, adjncy) = adjacency(&a).unwrap();
        let g = Compressed::of(&xadj, &adjncy);
        assert_eq!(g.weight, vec![2; nodes]);
        assert_eq!(g.xadj[1] - g.xadj[0], 3, "corner node: 3 neighbours");
        let centre = 2 * side + 2;
        assert_eq!(g.xadj[centre + 1] - g.xadj[centre], 8);
        let mut b = TriMat::new((1, 2 * nodes));
        b.add_triplet(0, 1, 1.0);
        let k = crate::linalg::kkt::kkt_pattern(&a, &b.to_csc()).unwrap();
        let (xadj, adjncy) = adjacency(&k).unwrap();
        let g = Compressed::of(&xadj, &adjncy);
        let mut weights = vec![1, 1];
        weights.extend(vec![2; nodes - 1]);
        weights.push(1);
        assert_eq!(g.weight, weights);
        assert_permutation(&kkt_order(&xadj, &adjncy).unwrap(), 2 * nodes + 1);
        assert!(
            kkt_order(&[0, 1], &[1]).is_err(),
            "a neighbour that is no vertex"
        );
    }

    #[test]
    fn metis_dissects_a_grid_with_less_fill_than_the_natural_order() {
        // Nested dissection of a k × k grid: nnz(L) = O(k² log k); the natural (banded) order
        // fills the band, ≈ k³ = 64 000 at k = 40; METIS stays well under half of that.
        let a = grid(40);
        let metis = order_with(&a, OrderingMethod::Metis).unwrap();
        assert_permutation(&metis, 1600);
        let identity = FillOrdering::from_forward((0..1600).collect(), OrderingMethod::Amd);
        let nnz = |o: &FillOrdering| {
            crate::linalg::CholeskyPattern::analyse_with(&a, o)
                .unwrap()
                .info(&a)
                .unwrap()
                .nnz_l
        };
        assert!(
            2 * nnz(&metis) < nnz(&identity),
            "{} vs {}",
            nnz(&metis),
            nnz(&identity)
        );
    }

    #[test]
    fn adjacency_of_one_triangle_equals_that_of_both() {
        let both = grid(6);
        let mut lower = TriMat::new((36, 36));
        for (v, (i, j)) in both.iter() {
            if i >= j {
                lower.add_triplet(i, j, *v);
            }
        }
        let lower: CscMatrix = lower.to_csc();
        let (xa, aa) = adjacency(&both).unwrap();
        let (xb, ab) = adjacency(&lower).unwrap();
        assert_eq!(xa, xb);
        let sorted = |x: &[usize], a: &[usize]| -> Vec<Vec<usize>> {
            (0..36)
                .map(|v| {
                    let mut l = a[x[v]..x[v + 1]].to_vec();
                    l.sort_unstable();
                    l
                })
                .collect()
        };
        assert_eq!(sorted(&xa, &aa), sorted(&xb, &ab));
        // An interior grid vertex has 4 neighbours, a corner 2: 2 · (edges) = 2 · 2 · 6 · 5.
        assert_eq!(xa[36], 120);
    }
}
