//! The fill-reducing ordering every sparse factorisation of the project uses: the timing floor,
//! the dual backends' factor of A and the sparse KKT factor of the active-set backend.  One
//! function, so that a floor and the solves it is compared with always share the ordering path.
//!
//! Two orderings are available: approximate minimum degree ([`OrderingMethod::Amd`], faer's
//! AMD) and nested dissection ([`OrderingMethod::Metis`], METIS_NodeND through
//! `signorini-metis`).  [`fill_reducing_order`] picks one by the rule below.
//!
//! RULE_PLACEHOLDER

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;

use super::{faer_view, LinalgError};
use crate::qp::CscMatrix;

/// Which algorithm produced a [`FillOrdering`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrderingMethod {
    /// Approximate minimum degree (faer's AMD).
    Amd,
    /// Nested dissection (METIS_NodeND, METIS 5 defaults).
    Metis,
}

impl OrderingMethod {
    /// The word used in reports (`"amd"`, `"metis"`).
    pub fn as_str(self) -> &'static str {
        match self {
            OrderingMethod::Amd => "amd",
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
    fn from_forward(forward: Vec<usize>, method: OrderingMethod) -> Self {
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

/// Matrices with at least this many rows are ordered by nested dissection, smaller ones by AMD
/// (see the module documentation for the measurements behind it).
pub const METIS_FROM_DOFS: usize = 20_000;

/// The fill-reducing ordering of the symmetric pattern of `a` (both triangles or one may be
/// stored; the pattern of A + Aᵀ is ordered), by the rule of the module documentation: METIS
/// nested dissection from [`METIS_FROM_DOFS`] rows on, AMD below.
pub fn fill_reducing_order(a: &CscMatrix) -> Result<FillOrdering, LinalgError> {
    let method = if a.rows() >= METIS_FROM_DOFS {
        OrderingMethod::Metis
    } else {
        OrderingMethod::Amd
    };
    order_with(a, method)
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
    match method {
        OrderingMethod::Amd => amd_order(a),
        OrderingMethod::Metis => metis_order(a),
    }
}

fn amd_order(a: &CscMatrix) -> Result<FillOrdering, LinalgError> {
    let n = a.rows();
    let view = faer_view(a)?;
    let mut forward = vec![0usize; n];
    let mut inverse = vec![0usize; n];
    let mut buffer = MemBuffer::try_new(amd::order_maybe_unsorted_scratch::<usize>(n, a.nnz()))
        .map_err(|e| LinalgError::Faer(format!("{e:?}")))?;
    amd::order_maybe_unsorted(
        &mut forward,
        &mut inverse,
        view.symbolic(),
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

fn metis_order(a: &CscMatrix) -> Result<FillOrdering, LinalgError> {
    let (xadj, adjncy) = adjacency(a)?;
    let groups = Compressed::of(&xadj, &adjncy);
    let (perm, _) =
        signorini_metis::node_nd_weighted(&groups.xadj, &groups.adjncy, Some(&groups.weight))
            .map_err(|e| LinalgError::Ordering(e.to_string()))?;
    let mut forward = Vec::with_capacity(a.rows());
    for g in perm {
        forward.extend(groups.start[g]..groups.start[g + 1]);
    }
    Ok(FillOrdering::from_forward(forward, OrderingMethod::Metis))
}

/// The graph with runs of consecutive vertices of identical closed neighbourhoods (the two DOFs
/// of a node, numbered one after the other) merged into one weighted vertex: half the vertices
/// and a quarter of the edges of a 2D elasticity DOF graph, so METIS orders it several times
/// faster than the DOF graph (its own compression finds the same groups but only after reading
/// the whole DOF graph).
pub(crate) struct Compressed {
    /// Group g holds the vertices `start[g]..start[g + 1]`.
    pub(crate) start: Vec<usize>,
    pub(crate) weight: Vec<usize>,
    pub(crate) xadj: Vec<usize>,
    pub(crate) adjncy: Vec<usize>,
}

impl Compressed {
    pub(crate) fn of(xadj: &[usize], adjncy: &[usize]) -> Self {
        let n = xadj.len() - 1;
        let closed = |v: usize| -> Vec<usize> {
            let mut l: Vec<usize> = adjncy[xadj[v]..xadj[v + 1]].to_vec();
            l.push(v);
            l.sort_unstable();
            l
        };
        let mut start = vec![0];
        let mut group_of = vec![0usize; n];
        let mut v = 0;
        while v < n {
            let first = closed(v);
            let mut w = v + 1;
            while w < n && xadj[w + 1] - xadj[w] == xadj[v + 1] - xadj[v] && closed(w) == first {
                w += 1;
            }
            for u in v..w {
                group_of[u] = start.len() - 1;
            }
            start.push(w);
            v = w;
        }
        let groups = start.len() - 1;
        let weight: Vec<usize> = (0..groups).map(|g| start[g + 1] - start[g]).collect();
        let mut mark = vec![usize::MAX; groups];
        let mut gx = Vec::with_capacity(groups + 1);
        gx.push(0);
        let mut ga = Vec::new();
        for g in 0..groups {
            mark[g] = g;
            for &w in &adjncy[xadj[start[g]]..xadj[start[g] + 1]] {
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
}

/// The adjacency graph of the pattern of A + Aᵀ without the diagonal, in CSR (`xadj`,
/// `adjncy`), each edge stored both ways once.
pub fn adjacency(a: &CscMatrix) -> Result<(Vec<usize>, Vec<usize>), LinalgError> {
    let n = a.rows();
    let view = faer_view(a)?;
    let sym = view.symbolic();
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
    Ok((xadj, adj))
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
        for method in [OrderingMethod::Amd, OrderingMethod::Metis] {
            let order = order_with(&a, method).unwrap();
            assert_eq!(order.method, method);
            assert_permutation(&order, n);
        }
        assert_permutation(&fill_reducing_order(&grid(12)).unwrap(), 144);
    }

    #[test]
    fn the_rule_switches_at_its_threshold() {
        let small = grid(10);
        assert_eq!(
            fill_reducing_order(&small).unwrap().method,
            OrderingMethod::Amd
        );
        let side = (METIS_FROM_DOFS as f64).sqrt().ceil() as usize;
        let large = grid(side);
        let order = fill_reducing_order(&large).unwrap();
        assert_eq!(order.method, OrderingMethod::Metis);
        assert_permutation(&order, side * side);
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
