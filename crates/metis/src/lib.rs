//! Nested-dissection ordering of a sparse symmetric graph by METIS (`METIS_NodeND`, METIS 5,
//! compiled from the sources vendored in `metis-sys`), behind one safe function whose input is
//! checked before it reaches C.
//!
//! The crate holds the project's only `unsafe` block (the FFI call); everything else in the
//! workspace forbids unsafe code.
//!
//! ```
//! // A path 0 – 1 – 2 – 3 – 4.
//! let xadj = [0, 1, 3, 5, 7, 8];
//! let adjncy = [1, 0, 2, 1, 3, 2, 4, 3];
//! let (perm, iperm) = signorini_metis::node_nd(&xadj, &adjncy).unwrap();
//! let mut sorted = perm.clone();
//! sorted.sort_unstable();
//! assert_eq!(sorted, vec![0, 1, 2, 3, 4]);
//! for (new, &old) in perm.iter().enumerate() {
//!     assert_eq!(iperm[old], new);
//! }
//! ```

use metis_sys::idx_t;

/// Why [`node_nd`] did not order a graph.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MetisError {
    /// The graph is not a valid undirected graph in CSR form without self loops.
    #[error("invalid graph for METIS: {0}")]
    InvalidGraph(String),
    /// The graph has more vertices or edges than METIS's 32-bit indices hold.
    #[error("graph too large for METIS's 32-bit indices ({vertices} vertices, {entries} adjacency entries)")]
    TooLarge {
        /// Vertices.
        vertices: usize,
        /// Adjacency entries (twice the edges).
        entries: usize,
    },
    /// METIS returned an error code (−2 input, −3 memory, −4 other).
    #[error("METIS_NodeND failed with code {code} ({})", describe(*.code))]
    Metis {
        /// The return code.
        code: i32,
    },
}

fn describe(code: i32) -> &'static str {
    match code {
        -2 => "input error",
        -3 => "out of memory",
        _ => "internal error",
    }
}

/// The nested-dissection ordering of the undirected graph with `n = xadj.len() − 1` vertices,
/// whose neighbours of vertex `i` are `adjncy[xadj[i]..xadj[i + 1]]` (CSR, 0-based, every edge
/// stored in both directions, no self loop; duplicates are not allowed either).
///
/// Returns `(perm, iperm)`: `perm[new] = old` and `iperm[old] = new`, the convention of the
/// METIS manual (row i of the permuted matrix is row `perm[i]` of the original).  METIS's
/// default options are used (compression of vertices with identical adjacency on, so the two
/// DOFs of a node are merged by METIS itself).
///
/// # Errors
/// [`MetisError::InvalidGraph`] when the arrays do not describe such a graph (checked here, in
/// O(n + nnz), so that METIS never reads out of bounds), [`MetisError::TooLarge`] beyond 32-bit
/// indices, [`MetisError::Metis`] when METIS fails.
pub fn node_nd(xadj: &[usize], adjncy: &[usize]) -> Result<(Vec<usize>, Vec<usize>), MetisError> {
    node_nd_weighted(xadj, adjncy, None)
}

/// [`node_nd`] with vertex weights (`vwgt[i]` ≥ 1, e.g. the number of matrix rows a vertex of
/// a compressed graph stands for), which METIS balances the parts by.
///
/// # Errors
/// As [`node_nd`]; a weight vector of the wrong length or with a zero or too large entry is an
/// [`MetisError::InvalidGraph`].
pub fn node_nd_weighted(
    xadj: &[usize],
    adjncy: &[usize],
    vwgt: Option<&[usize]>,
) -> Result<(Vec<usize>, Vec<usize>), MetisError> {
    let n = xadj
        .len()
        .checked_sub(1)
        .ok_or_else(|| MetisError::InvalidGraph("xadj is empty (it needs n + 1 entries)".into()))?;
    let too_large = || MetisError::TooLarge {
        vertices: n,
        entries: adjncy.len(),
    };
    if idx_t::try_from(n).is_err() || idx_t::try_from(adjncy.len()).is_err() {
        return Err(too_large());
    }
    check_graph(n, xadj, adjncy)?;
    let mut vwgt_c: Option<Vec<idx_t>> = match vwgt {
        None => None,
        Some(w) if w.len() != n => {
            return Err(MetisError::InvalidGraph(format!(
                "{} vertex weights for {n} vertices",
                w.len()
            )))
        }
        Some(w) => {
            // The sum must fit METIS's indices too.
            let total: usize = w.iter().fold(0usize, |s, &x| s.saturating_add(x));
            if w.contains(&0) || idx_t::try_from(total).is_err() {
                return Err(MetisError::InvalidGraph(
                    "vertex weights must be positive and sum below 2³¹".into(),
                ));
            }
            Some(w.iter().map(|&x| x as idx_t).collect())
        }
    };
    if n == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    let to_idx = |v: usize| idx_t::try_from(v).map_err(|_| too_large());
    let mut nvtxs = to_idx(n)?;
    let mut xadj_c: Vec<idx_t> = xadj.iter().map(|&v| to_idx(v)).collect::<Result<_, _>>()?;
    // METIS reads adjncy[xadj[n]..] never, but an empty array would be a null-ish pointer.
    let mut adjncy_c: Vec<idx_t> = adjncy
        .iter()
        .map(|&v| to_idx(v))
        .collect::<Result<_, _>>()?;
    adjncy_c.push(0);
    let mut options = [0 as idx_t; metis_sys::METIS_NOPTIONS as usize];
    let mut perm = vec![0 as idx_t; n];
    let mut iperm = vec![0 as idx_t; n];
    #[allow(unsafe_code)]
    // SAFETY: `options` has METIS_NOPTIONS entries as METIS_SetDefaultOptions requires.  For
    // METIS_NodeND: `nvtxs` = n; `xadj_c` has n + 1 nondecreasing entries starting at 0 and
    // `adjncy_c` has at least xadj[n] entries, each in 0..n (checked by `check_graph`), so every
    // read METIS makes is in bounds; `vwgt` is null (unit weights, allowed by the API) or
    // has n positive entries whose sum fits idx_t; `perm`
    // and `iperm` have n entries each, which is what METIS writes.  All buffers are owned here,
    // live across the call, and METIS keeps no pointer to them after it returns.
    let code = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        options[metis_sys::moptions_et_METIS_OPTION_NUMBERING as usize] = 0;
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj_c.as_mut_ptr(),
            adjncy_c.as_mut_ptr(),
            vwgt_c
                .as_mut()
                .map_or(std::ptr::null_mut(), |w| w.as_mut_ptr()),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if code != metis_sys::rstatus_et_METIS_OK {
        return Err(MetisError::Metis { code });
    }
    let to_usize = |v: &idx_t| usize::try_from(*v).ok().filter(|&i| i < n);
    let perm: Option<Vec<usize>> = perm.iter().map(to_usize).collect();
    let iperm: Option<Vec<usize>> = iperm.iter().map(to_usize).collect();
    match (perm, iperm) {
        (Some(perm), Some(iperm))
            if perm.iter().enumerate().all(|(new, &old)| iperm[old] == new) =>
        {
            Ok((perm, iperm))
        }
        _ => Err(MetisError::Metis { code: -4 }),
    }
}

/// Checks that `xadj`/`adjncy` describe an undirected graph on `n` vertices: pointers from 0,
/// nondecreasing, ending at `adjncy.len()`; neighbours in range, no self loop, no duplicate,
/// every edge stored both ways.  O(n + nnz) time, one transposed copy of `adjncy` (4 B/entry).
fn check_graph(n: usize, xadj: &[usize], adjncy: &[usize]) -> Result<(), MetisError> {
    let bad = |m: String| Err(MetisError::InvalidGraph(m));
    if xadj[0] != 0 {
        return bad(format!("xadj[0] = {} (must be 0)", xadj[0]));
    }
    if let Some(i) = (0..n).find(|&i| xadj[i] > xadj[i + 1]) {
        return bad(format!("xadj decreases at vertex {i}"));
    }
    if xadj[n] != adjncy.len() {
        return bad(format!(
            "xadj[n] = {} but adjncy has {} entries",
            xadj[n],
            adjncy.len()
        ));
    }
    // `mark[j] = i + 1` while scanning vertex i: detects duplicates in O(nnz).
    let mut mark = vec![0usize; n];
    let mut in_ptr = vec![0usize; n + 1];
    for i in 0..n {
        for &j in &adjncy[xadj[i]..xadj[i + 1]] {
            if j >= n {
                return bad(format!(
                    "neighbour {j} of vertex {i} is out of range (n = {n})"
                ));
            }
            if j == i {
                return bad(format!("vertex {i} has a self loop"));
            }
            if mark[j] == i + 1 {
                return bad(format!("edge {i}–{j} is listed twice"));
            }
            mark[j] = i + 1;
            in_ptr[j + 1] += 1;
        }
    }
    for i in 0..n {
        if in_ptr[i + 1] != xadj[i + 1] - xadj[i] {
            return bad(format!("the adjacency is not symmetric at vertex {i}"));
        }
        in_ptr[i + 1] += in_ptr[i];
    }
    // Transpose (who lists j), then check that every vertex listing i is listed by i: with no
    // duplicates and equal in/out degrees, that makes the two neighbour sets equal.
    let mut fill = in_ptr.clone();
    let mut listed_by = vec![0u32; adjncy.len()];
    for i in 0..n {
        for &j in &adjncy[xadj[i]..xadj[i + 1]] {
            // n ≤ idx_t::MAX was checked by the caller, so i fits in u32.
            listed_by[fill[j]] = i as u32;
            fill[j] += 1;
        }
    }
    mark.iter_mut().for_each(|m| *m = 0);
    for i in 0..n {
        for &j in &adjncy[xadj[i]..xadj[i + 1]] {
            mark[j] = i + 1;
        }
        if let Some(&k) = listed_by[in_ptr[i]..in_ptr[i + 1]]
            .iter()
            .find(|&&k| mark[k as usize] != i + 1)
        {
            return bad(format!(
                "the adjacency is not symmetric: {k} lists {i} but {i} does not list {k}"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_what_metis_cannot_read() {
        assert!(matches!(
            node_nd(&[], &[]),
            Err(MetisError::InvalidGraph(_))
        ));
        // Out of range, self loop, one-way edge, pointer past the end.
        for (xadj, adjncy) in [
            (vec![0, 1, 2], vec![1, 5]),
            (vec![0, 1, 2], vec![0, 1]),
            (vec![0, 1, 1], vec![1]),
            (vec![0, 1, 3], vec![1, 0]),
        ] {
            assert!(
                matches!(node_nd(&xadj, &adjncy), Err(MetisError::InvalidGraph(_))),
                "{xadj:?} {adjncy:?}"
            );
        }
        assert_eq!(node_nd(&[0], &[]), Ok((vec![], vec![])));
    }

    #[test]
    fn a_grid_is_dissected_middle_line_last() {
        // 15 × 15 grid: nested dissection puts a separating line (15 vertices) last.  The last
        // 15 vertices of the order must separate the rest: removing them leaves ≥ 2 components.
        let side = 15;
        let id = |i: usize, j: usize| j * side + i;
        let n = side * side;
        let mut xadj = vec![0];
        let mut adjncy = Vec::new();
        for j in 0..side {
            for i in 0..side {
                if i > 0 {
                    adjncy.push(id(i - 1, j));
                }
                if i + 1 < side {
                    adjncy.push(id(i + 1, j));
                }
                if j > 0 {
                    adjncy.push(id(i, j - 1));
                }
                if j + 1 < side {
                    adjncy.push(id(i, j + 1));
                }
                xadj.push(adjncy.len());
            }
        }
        let (perm, iperm) = node_nd(&xadj, &adjncy).unwrap();
        let mut sorted = perm.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        // The top separator of a 15-grid has 15 vertices (a line); allow METIS up to 2× that.
        let top = 2 * side;
        let removed: Vec<bool> = (0..n).map(|v| iperm[v] >= n - top).collect();
        let mut component = vec![usize::MAX; n];
        let mut count = 0;
        for start in 0..n {
            if removed[start] || component[start] != usize::MAX {
                continue;
            }
            let mut stack = vec![start];
            component[start] = count;
            while let Some(v) = stack.pop() {
                for &w in &adjncy[xadj[v]..xadj[v + 1]] {
                    if !removed[w] && component[w] == usize::MAX {
                        component[w] = count;
                        stack.push(w);
                    }
                }
            }
            count += 1;
        }
        assert!(
            count >= 2,
            "the last {top} vertices do not separate the grid"
        );
    }
}
