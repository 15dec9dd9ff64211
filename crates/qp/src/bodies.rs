//! The bodies of a QP, read off its matrices: the stiffness of a finite-element model couples
//! no two bodies (only contact does, through B), so the connected components of A's graph are
//! its bodies.  The contact body most slender against its interface decides how
//! ill-conditioned the condensed dual is (see [`ContactBody`]); the interface counted is the
//! one that touches first ([`first_touch`]).

use crate::{row_sets, CscMatrix, QpProblem, QpScaling, RowSet};

/// The connected components of the graph of a symmetric matrix (an edge per stored entry).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Components {
    /// The component of each unknown, numbered 0.. in order of first appearance.
    pub label: Vec<usize>,
    /// Unknowns per component.
    pub sizes: Vec<usize>,
}

impl Components {
    /// The components of the graph of the symmetric `a` (square, CSC; an entry (i, j) joins i
    /// and j whatever its value, so explicit zeros of an assembled pattern join too).  Both
    /// triangles are read, so a matrix stored as one triangle joins the same unknowns.
    ///
    /// Two passes over the entries, neither chasing pointers per entry: each unknown first
    /// points at the smallest unknown its column stores (a forest whose parents precede their
    /// children, resolved to roots in one sweep); then every entry whose ends point at
    /// different parents joins them by union–find — rare on an assembled stiffness with both
    /// triangles stored, whose columns reach their smaller neighbours (a lower triangle alone
    /// reaches none: every entry is then joined, as the one-pass union–find did).  (That
    /// union–find read the parent chain per entry: 1.9 ms against 0.9 ms on the 34 226-DOF
    /// partial strip.)
    pub fn of(a: &CscMatrix) -> Self {
        let n = a.rows().min(a.cols());
        let mut parent: Vec<usize> = (0..n).collect();
        for (j, column) in a.outer_iterator().enumerate().take(n) {
            let smallest = column.indices().iter().copied().filter(|&i| i < n).min();
            parent[j] = smallest.map_or(j, |i| i.min(j));
        }
        // parent[k] ≤ k, and every smaller unknown already points at its root.
        for k in 0..n {
            parent[k] = parent[parent[k]];
        }
        for (j, column) in a.outer_iterator().enumerate().take(n) {
            let own = parent[j];
            for &i in column.indices() {
                if i < n && parent[i] != own {
                    let root = find(&mut parent, j);
                    join(&mut parent, root, i);
                }
            }
        }
        Self::of_forest(&mut parent)
    }

    /// The components of a union–find forest (`parent[k]` = k at a root; see [`join`]),
    /// labelled in order of first appearance.
    pub(crate) fn of_forest(parent: &mut [usize]) -> Self {
        let n = parent.len();
        let mut label = vec![usize::MAX; n];
        let mut sizes = Vec::new();
        let mut of_root = vec![usize::MAX; n];
        for k in 0..n {
            let root = find(parent, k);
            if of_root[root] == usize::MAX {
                of_root[root] = sizes.len();
                sizes.push(0);
            }
            label[k] = of_root[root];
            sizes[label[k]] += 1;
        }
        Self { label, sizes }
    }
}

/// The root of `k`'s tree in the union–find forest `parent`, halving the path on the way.
pub(crate) fn find(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}

/// Joins the tree of `i` to the tree whose root is `root` in the union–find forest `parent`;
/// returns the root of the joined tree.
pub(crate) fn join(parent: &mut [usize], root: usize, i: usize) -> usize {
    let ri = find(parent, i);
    if ri == root {
        return root;
    }
    // The smaller root index wins: deterministic, and the trees stay shallow enough with the
    // halving in `find`.
    let (keep, drop) = if ri < root { (ri, root) } else { (root, ri) };
    parent[drop] = keep;
    keep
}

/// The normal rows that touch first: those whose gap exceeds the smallest normal gap by at most
/// the load's own displacement unit u₀ ([`QpScaling::displacement`]: the largest nodal load
/// over the mean stiffness, or the overlap or the gap when there is no load).  Every row of a
/// flush interface (a strip laid on a foundation, equal gaps under a block) touches first; of
/// a cylinder on a block only the rows around the first point of contact do, the rest closing
/// only as the bodies deform — and the zone they then form stays compact against the bodies
/// (Hertz: a half-width a ≪ R).  u₀ is the displacement of one DOF under its own load alone, a
/// lower bound on how far the bodies move: a row within it of the first touch is in contact
/// at any load that moves anything.
pub fn first_touch(problem: &QpProblem) -> Vec<bool> {
    let normal: Vec<bool> = row_sets(&problem.blocks)
        .map(|set| set == RowSet::NonNegative)
        .collect();
    let smallest = problem
        .gap
        .iter()
        .zip(&normal)
        .filter(|&(_, &n)| n)
        .map(|(&g, _)| g)
        .fold(f64::INFINITY, f64::min);
    let reach = smallest + QpScaling::of(problem).displacement;
    problem
        .gap
        .iter()
        .zip(&normal)
        .map(|(&g, &n)| n && g <= reach)
        .collect()
}

/// A body that contact rows touch: its unknowns and the size of its contact interface.
///
/// interface / √dofs measures how long the body's contact interface is against the body itself: a 2D
/// body's boundary grows like the square root of its unknowns, so a compact body pressed along
/// one side scores below 1 at any mesh size, while a strip of length L and thickness t pressed
/// along its length scores about √(L / 2t) — and the dual of such an interface (the strip's
/// beam-like compliance seen through B) is ill-conditioned however thick the body it rests on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactBody {
    /// Unknowns of the body (a connected component of A).
    pub dofs: usize,
    /// The interface's size in the body's own resolution: the normal rows touching the body, or
    /// the body's DOFs those rows touch when fewer (a coarse master under a fine slave: many
    /// rows, few of its own nodes).  Friction's tangential rows ([`RowSet::Box`]) are not
    /// counted: they double the rows of the same interface, not its length.
    pub interface: usize,
}

impl ContactBody {
    /// interface / √dofs.
    pub fn slenderness(&self) -> f64 {
        self.interface as f64 / (self.dofs.max(1) as f64).sqrt()
    }

    /// The body of `problem` with the largest [`ContactBody::slenderness`] among those the
    /// normal rows touch (ties: the first); `None` without normal rows.
    pub fn most_slender(problem: &QpProblem) -> Option<Self> {
        let normal: Vec<bool> = row_sets(&problem.blocks)
            .map(|set| set == RowSet::NonNegative)
            .collect();
        Self::most_slender_over(problem, &normal)
    }

    /// [`ContactBody::most_slender`] counting only the rows `counted` marks (rows beyond its
    /// length are not counted): with [`first_touch`], the interface that touches first.
    pub fn most_slender_over(problem: &QpProblem, counted: &[bool]) -> Option<Self> {
        Self::most_slender_among(problem, &Components::of(&problem.stiffness), counted)
    }

    /// [`ContactBody::most_slender_over`] with the bodies already found (`components`, those
    /// of A: e.g. [`crate::ResidualScales::bodies`]).
    pub fn most_slender_among(
        problem: &QpProblem,
        components: &Components,
        counted: &[bool],
    ) -> Option<Self> {
        let bodies = components.sizes.len();
        // One pass over B's columns (DOFs): (body, row) for every nonzero of a counted row, and
        // the DOFs of each body such a row touches.
        let mut touches: Vec<(usize, usize)> = Vec::with_capacity(problem.constraints.nnz());
        let mut touched = vec![0usize; bodies];
        for (j, column) in problem.constraints.outer_iterator().enumerate() {
            let Some(&label) = components.label.get(j) else {
                break;
            };
            let before = touches.len();
            touches.extend(
                column
                    .iter()
                    .filter(|&(i, &v)| v != 0.0 && counted.get(i).copied().unwrap_or(false))
                    .map(|(i, _)| (label, i)),
            );
            touched[label] += usize::from(touches.len() > before);
        }
        touches.sort_unstable();
        touches.dedup();
        let mut rows = vec![0usize; bodies];
        for &(label, _) in &touches {
            rows[label] += 1;
        }
        rows.iter()
            .zip(&touched)
            .zip(&components.sizes)
            .map(|((&r, &t), &dofs)| Self {
                dofs,
                interface: r.min(t),
            })
            .filter(|body| body.interface > 0)
            .fold(None, |best: Option<Self>, body| match best {
                Some(b) if b.slenderness() >= body.slenderness() => Some(b),
                _ => Some(body),
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sprs::TriMat;

    /// A chain of `n` unknowns coupled to their neighbours, as one body.
    fn chain(t: &mut TriMat<f64>, first: usize, n: usize) {
        for k in first..first + n {
            t.add_triplet(k, k, 2.0);
            if k + 1 < first + n {
                t.add_triplet(k, k + 1, -1.0);
                t.add_triplet(k + 1, k, -1.0);
            }
        }
    }

    #[test]
    fn the_components_of_a_block_diagonal_matrix_are_its_blocks() {
        let mut a = TriMat::new((7, 7));
        chain(&mut a, 0, 3);
        chain(&mut a, 3, 4);
        let c = Components::of(&a.to_csc());
        assert_eq!(c.sizes, vec![3, 4]);
        assert_eq!(c.label, vec![0, 0, 0, 1, 1, 1, 1]);
    }

    /// A matrix stored as one triangle joins the same unknowns as the full one (the lower
    /// triangle alone was read once: an upper-triangle matrix fell apart into single unknowns).
    #[test]
    fn one_stored_triangle_gives_the_same_components() {
        let mut a = TriMat::new((7, 7));
        chain(&mut a, 0, 3);
        chain(&mut a, 3, 4);
        let full = a.to_csc();
        for keep in [|i: usize, j: usize| i <= j, |i: usize, j: usize| i >= j] {
            let mut t = TriMat::new((7, 7));
            for (&v, (i, j)) in full.iter() {
                if keep(i, j) {
                    t.add_triplet(i, j, v);
                }
            }
            assert_eq!(Components::of(&t.to_csc()), Components::of(&full));
        }
    }

    /// Components by a breadth-first search over the symmetrised pattern: the reference.
    fn searched(a: &CscMatrix) -> Vec<Vec<usize>> {
        let n = a.rows();
        let mut neighbours = vec![Vec::new(); n];
        for (_, (i, j)) in a.iter() {
            neighbours[i].push(j);
            neighbours[j].push(i);
        }
        let mut seen = vec![false; n];
        let mut groups = Vec::new();
        for s in 0..n {
            if seen[s] {
                continue;
            }
            seen[s] = true;
            let (mut queue, mut group) = (vec![s], Vec::new());
            while let Some(k) = queue.pop() {
                group.push(k);
                for &i in &neighbours[k] {
                    if !seen[i] {
                        seen[i] = true;
                        queue.push(i);
                    }
                }
            }
            group.sort_unstable();
            groups.push(group);
        }
        groups
    }

    /// The unknowns of each component, in order of their smallest unknown.
    fn groups(c: &Components) -> Vec<Vec<usize>> {
        let mut groups = vec![Vec::new(); c.sizes.len()];
        for (k, &l) in c.label.iter().enumerate() {
            groups[l].push(k);
        }
        groups
    }

    /// Under numberings where many unknowns have no smaller neighbour (the smallest-neighbour
    /// forest then has many roots and the joining pass does the work), with both triangles
    /// and with one, the components are those a breadth-first search finds.
    #[test]
    fn any_numbering_gives_the_components_a_search_finds() {
        // Three grids of 5 × 4 unknowns and one lone unknown, numbered by a fixed scramble.
        let n = 61;
        let scramble = |k: usize| (k * 37 + 11) % n;
        let mut full = TriMat::new((n, n));
        for g in 0..3 {
            for r in 0..4 {
                for c in 0..5 {
                    let k = 20 * g + 5 * r + c;
                    full.add_triplet(scramble(k), scramble(k), 4.0);
                    for other in [(c + 1 < 5).then(|| k + 1), (r + 1 < 4).then(|| k + 5)]
                        .into_iter()
                        .flatten()
                    {
                        full.add_triplet(scramble(k), scramble(other), -1.0);
                        full.add_triplet(scramble(other), scramble(k), -1.0);
                    }
                }
            }
        }
        full.add_triplet(scramble(60), scramble(60), 1.0);
        let full = full.to_csc();
        assert_eq!(groups(&Components::of(&full)), searched(&full));
        let mut sizes = Components::of(&full).sizes;
        sizes.sort_unstable();
        assert_eq!(sizes, vec![1, 20, 20, 20]);
        for upper in [true, false] {
            let mut t = TriMat::new((n, n));
            for (&v, (i, j)) in full.iter() {
                if (i <= j) == upper || i == j {
                    t.add_triplet(i, j, v);
                }
            }
            let one = t.to_csc();
            assert_eq!(groups(&Components::of(&one)), searched(&full));
        }
    }

    #[test]
    fn the_most_slender_body_counts_its_own_rows_against_its_own_unknowns() {
        // Body 0: 4 unknowns, body 1: 100; two rows couple unknowns 3 and 2 of body 0 with body
        // 1, a third touches body 1 only.  Body 0: 2/√4 = 1; body 1: 3/√100 = 0.3.
        let mut a = TriMat::new((104, 104));
        chain(&mut a, 0, 4);
        chain(&mut a, 4, 100);
        let mut b = TriMat::new((3, 104));
        b.add_triplet(0, 3, 1.0);
        b.add_triplet(0, 10, -1.0);
        b.add_triplet(1, 2, 1.0);
        b.add_triplet(1, 11, -1.0);
        b.add_triplet(2, 50, 1.0);
        // An explicit zero does not touch a body.
        b.add_triplet(2, 0, 0.0);
        let p = QpProblem::try_new(a.to_csc(), vec![0.0; 104], b.to_csc(), vec![0.0; 3]).unwrap();
        let body = ContactBody::most_slender(&p).unwrap();
        assert_eq!(
            body,
            ContactBody {
                dofs: 4,
                interface: 2
            }
        );
        assert_eq!(body.slenderness(), 1.0);
    }

    #[test]
    fn a_coarse_body_under_many_rows_counts_its_own_touched_unknowns() {
        // Body 0 (9 unknowns): all six rows touch its unknowns 0 and 1 only; body 1 (36): each
        // row one unknown of its own.  Body 0: min(6, 2)/√9 = 0.67; body 1: 6/√36 = 1.
        let mut a = TriMat::new((45, 45));
        chain(&mut a, 0, 9);
        chain(&mut a, 9, 36);
        let mut b = TriMat::new((6, 45));
        for i in 0..6 {
            b.add_triplet(i, i % 2, -1.0);
            b.add_triplet(i, 9 + i, 1.0);
        }
        let p = QpProblem::try_new(a.to_csc(), vec![0.0; 45], b.to_csc(), vec![0.0; 6]).unwrap();
        let body = ContactBody::most_slender(&p).unwrap();
        assert_eq!(
            body,
            ContactBody {
                dofs: 36,
                interface: 6
            }
        );
    }

    /// u₀ = ‖f‖∞ / mean(Aⱼⱼ) = 4 / 2 = 2 on a chain of diagonal 2: the normal rows within 2
    /// of the smallest normal gap 0.5 touch first (gaps 0.5 and 2.4, not 2.6 or 100); a box
    /// row's gap of 0 is not a normal gap and does not move the smallest.  Hand-computed.
    #[test]
    fn the_rows_that_touch_first_are_within_the_load_displacement_of_the_smallest_gap() {
        use crate::ConstraintBlock;
        let mut a = TriMat::new((6, 6));
        chain(&mut a, 0, 6);
        let mut b = TriMat::new((5, 6));
        for i in 0..5 {
            b.add_triplet(i, i, 1.0);
        }
        let load = vec![4.0, 0.0, -1.0, 0.0, 0.0, 0.0];
        let gap = vec![0.5, 2.4, 2.6, 100.0, 0.0];
        let p = QpProblem::try_new(a.to_csc(), load, b.to_csc(), gap)
            .unwrap()
            .with_blocks(vec![
                ConstraintBlock::NonNegative { rows: 4 },
                ConstraintBlock::Box { bounds: vec![1.0] },
            ])
            .unwrap();
        assert_eq!(first_touch(&p), [true, true, false, false, false]);
        // Counted over those rows, the body's interface is 2 rows, not the 4 normal ones.
        let body = ContactBody::most_slender_over(&p, &first_touch(&p)).unwrap();
        assert_eq!(body.interface, 2);
        assert_eq!(ContactBody::most_slender(&p).unwrap().interface, 4);
    }

    #[test]
    fn no_normal_rows_no_contact_body() {
        let mut a = TriMat::new((2, 2));
        chain(&mut a, 0, 2);
        let b = TriMat::new((0, 2));
        let p = QpProblem::try_new(a.to_csc(), vec![0.0; 2], b.to_csc(), vec![]).unwrap();
        assert_eq!(ContactBody::most_slender(&p), None);
    }
}
