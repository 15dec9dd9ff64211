//! The fill-reducing ordering every sparse factorisation of the project uses: the timing floor,
//! the dual backends' factor of A and the sparse KKT factor of the active-set backend.  One
//! function, so that a floor and the solves it is compared with always share the ordering path.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;

use super::{faer_view, LinalgError};
use crate::qp::CscMatrix;

/// Which algorithm produced a [`FillOrdering`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrderingMethod {
    /// Approximate minimum degree (faer's AMD).
    Amd,
}

impl OrderingMethod {
    /// The word used in reports (`"amd"`).
    pub fn as_str(self) -> &'static str {
        match self {
            OrderingMethod::Amd => "amd",
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

/// The fill-reducing ordering of the symmetric pattern of `a` (both triangles or one may be
/// stored; the pattern of A + Aᵀ is ordered).
pub fn fill_reducing_order(a: &CscMatrix) -> Result<FillOrdering, LinalgError> {
    let n = a.rows();
    if a.cols() != n {
        return Err(LinalgError::Shape {
            rows: n,
            cols: a.cols(),
        });
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

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
        let order = fill_reducing_order(&t.to_csc()).unwrap();
        let mut seen = order.forward.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..n).collect::<Vec<_>>());
        for (new, &old) in order.forward.iter().enumerate() {
            assert_eq!(order.inverse[old], new);
        }
    }
}
