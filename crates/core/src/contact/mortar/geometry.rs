//! The geometry of one slave segment: its interpolated normal field, the projection of master
//! points onto it along that field, the clipping of a master segment's image to it, and the
//! Gauss rule integrating over each clipped piece.

use crate::geometry::Point;

/// Gauss–Legendre rule on [0, 1] with three points: exact for polynomials of degree ≤ 5.  On a
/// straight slave segment whose two nodal normals are parallel the master parameter η(ξ) and the
/// gap are affine in ξ, so every integrand (ψ_j N_k, ψ_j g) is a quadratic: two points would be
/// exact, three leave a margin for curved slave sides (rational η(ξ), see the module docs).
pub(super) const GAUSS: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// A clipped piece shorter than this (in ξ ∈ [0, 1]) is a touch at a point (a conforming
/// neighbour's shared end, up to round-off), not an overlap.
pub(super) const MIN_PIECE: f64 = 1e-12;

/// 2D cross product a × b.
pub(super) fn cross(a: Point, b: Point) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

/// a · b.
pub(super) fn dot(a: Point, b: Point) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// a − b.
pub(super) fn sub(a: Point, b: Point) -> Point {
    [a[0] - b[0], a[1] - b[1]]
}

/// a / |a|, or `None` for a zero (or non-finite) vector.
pub(super) fn unit(a: Point) -> Option<Point> {
    let len = a[0].hypot(a[1]);
    (len > 0.0 && len.is_finite()).then(|| [a[0] / len, a[1] / len])
}

/// A straight slave segment x(ξ) = (1 − ξ) x₁ + ξ x₂, ξ ∈ [0, 1], with the linear normal field
/// n(ξ) = (1 − ξ) n₁ + ξ n₂ of its two (averaged, unit) nodal normals.
#[derive(Debug, Clone, Copy)]
pub(super) struct SlaveSegment {
    /// First node's position.
    pub x1: Point,
    /// Second node's position.
    pub x2: Point,
    /// First node's unit normal.
    pub n1: Point,
    /// Second node's unit normal.
    pub n2: Point,
}

/// Where a master segment's image along the slave normals falls on a slave segment: the part
/// [lo, hi] ⊂ [0, 1] of the slave parameter it covers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Piece {
    /// Start of the covered part (slave parameter).
    pub lo: f64,
    /// End of the covered part.
    pub hi: f64,
}

/// One Gauss point of a clipped piece: slave parameter ξ, master parameter η, gap g along the
/// slave normal, and the integration weight (Gauss weight × piece length in ξ × slave length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GaussPoint {
    /// Slave parameter.
    pub xi: f64,
    /// Master parameter (0 at the master segment's first node).
    pub eta: f64,
    /// Gap (y − x)·n̂: positive when the master lies ahead of the slave along its outward normal.
    pub gap: f64,
    /// Integration weight (a length).
    pub weight: f64,
}

impl SlaveSegment {
    /// Position x(ξ).
    pub fn point(&self, xi: f64) -> Point {
        [
            self.x1[0] + xi * (self.x2[0] - self.x1[0]),
            self.x1[1] + xi * (self.x2[1] - self.x1[1]),
        ]
    }

    /// Interpolated normal n(ξ) (not normalised).
    pub fn normal(&self, xi: f64) -> Point {
        [
            self.n1[0] + xi * (self.n2[0] - self.n1[0]),
            self.n1[1] + xi * (self.n2[1] - self.n1[1]),
        ]
    }

    /// Length |x₂ − x₁|.
    pub fn length(&self) -> f64 {
        let d = sub(self.x2, self.x1);
        d[0].hypot(d[1])
    }

    /// The slave parameter ξ whose normal line passes through `y`: (x(ξ) − y) × n(ξ) = 0, a
    /// quadratic A ξ² + B ξ + C = 0 with A = Δx × Δn, B = (x₁ − y) × Δn + Δx × n₁,
    /// C = (x₁ − y) × n₁.  Of its real roots the one nearest the segment (|ξ − ½| smallest);
    /// `None` when it has none.  Roots by the cancellation-free formula q = −(B + sgn B √disc)/2,
    /// ξ ∈ {q/A, C/q}: when the normals are parallel (A = 0) only C/q = −C/B remains, the
    /// orthogonal projection.  ξ may lie outside [0, 1] (the caller clips).
    pub fn project(&self, y: Point) -> Option<f64> {
        let dx = sub(self.x2, self.x1);
        let dn = sub(self.n2, self.n1);
        let r = sub(self.x1, y);
        let a = cross(dx, dn);
        let b = cross(r, dn) + cross(dx, self.n1);
        let c = cross(r, self.n1);
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        [q / a, c / q]
            .into_iter()
            .filter(|x| x.is_finite())
            .min_by(|s, t| (s - 0.5).abs().total_cmp(&(t - 0.5).abs()))
    }

    /// The part of the slave segment covered by the image of master segment `ya`–`yb` along
    /// the slave normals: the projections of its ends, ordered and clipped to [0, 1].  `None`
    /// when an end cannot be projected or the clipped part is shorter than [`MIN_PIECE`].
    pub fn clip(&self, ya: Point, yb: Point) -> Option<Piece> {
        let (sa, sb) = (self.project(ya)?, self.project(yb)?);
        let lo = sa.min(sb).max(0.0);
        let hi = sa.max(sb).min(1.0);
        (hi - lo > MIN_PIECE).then_some(Piece { lo, hi })
    }

    /// The [`GAUSS`] points of `piece`, each projected along the unit slave normal n̂(ξ) onto
    /// the master segment's line: η solves (y(η) − x(ξ)) × n̂ = 0, y(η) = ya + η (yb − ya),
    /// and g = (y(η) − x(ξ))·n̂.  `None` when the master segment is parallel to a normal.
    pub fn gauss_points(&self, piece: Piece, ya: Point, yb: Point) -> Option<[GaussPoint; 3]> {
        let dy = sub(yb, ya);
        let scale = (piece.hi - piece.lo) * self.length();
        let mut out = [GaussPoint {
            xi: 0.0,
            eta: 0.0,
            gap: 0.0,
            weight: 0.0,
        }; 3];
        for (o, &(s, w)) in out.iter_mut().zip(&GAUSS) {
            let xi = piece.lo + s * (piece.hi - piece.lo);
            let x = self.point(xi);
            let n = unit(self.normal(xi))?;
            let denominator = cross(dy, n);
            if denominator == 0.0 {
                return None;
            }
            let eta = cross(sub(x, ya), n) / denominator;
            let y = [ya[0] + eta * dy[0], ya[1] + eta * dy[1]];
            *o = GaussPoint {
                xi,
                eta,
                gap: dot(sub(y, x), n),
                weight: w * scale,
            };
        }
        Some(out)
    }
}

/// Outward unit normal of a boundary edge a → b (the body on its left), `None` when a = b.
pub(super) fn edge_normal(a: Point, b: Point) -> Option<Point> {
    unit([b[1] - a[1], a[0] - b[0]])
}

/// The dual (biorthogonal) slave basis of a linear segment: ψ₁ = 2N₁ − N₂, ψ₂ = 2N₂ − N₁ with
/// N₁ = 1 − ξ, N₂ = ξ, so that ∫ψ_i N_j = δ_ij ∫N_j over the whole segment and ψ₁ + ψ₂ = 1.
pub(super) fn dual(xi: f64) -> [f64; 2] {
    [2.0 - 3.0 * xi, 3.0 * xi - 1.0]
}

/// Averaged nodal normals: for each slave node, the normalised sum of the outward unit normals
/// of the interface segments `edges` (node pairs of the slave) that touch it; `None` for a node
/// on no interface segment or whose normals cancel.  At a node with a single interface segment
/// (the end of the contact zone, or a body corner whose other edge does not face the master)
/// the normal is that segment's own.
pub(super) fn nodal_normals(nodes: &[Point], edges: &[[usize; 2]]) -> Vec<Option<Point>> {
    let mut sum = vec![[0.0, 0.0]; nodes.len()];
    let mut on = vec![false; nodes.len()];
    for &[p, q] in edges {
        let Some(n) = edge_normal(nodes[p], nodes[q]) else {
            continue;
        };
        for i in [p, q] {
            sum[i] = [sum[i][0] + n[0], sum[i][1] + n[1]];
            on[i] = true;
        }
    }
    sum.into_iter()
        .zip(on)
        .map(|(s, on)| if on { unit(s) } else { None })
        .collect()
}
