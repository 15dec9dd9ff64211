//! Why a Gmsh file could not be used: [`GmshError`] names the file, [`GmshProblem`] says what
//! is wrong with it.

/// Why a Gmsh file could not be used; the message names the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("mesh file {path}: {problem}")]
pub struct GmshError {
    /// The file.
    pub path: String,
    /// What is wrong.
    pub problem: GmshProblem,
}

/// What is wrong with a Gmsh file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GmshProblem {
    /// The file could not be read.
    #[error("cannot be read: {0}")]
    Read(String),
    /// `mshio` refused the file (not MSH 4.1, truncated, malformed).
    #[error("is not a valid MSH 4.1 file (ASCII or binary): {0}")]
    Parse(String),
    /// No triangle or quadrilateral in the file.
    #[error(
        "holds no 2-D element (triangle or quadrilateral); mesh the surface in 2-D, and when the \
         .geo defines physical groups include a Physical Surface (or set Mesh.SaveAll = 1)"
    )]
    NoElements,
    /// An element type the program does not handle.
    #[error(
        "has {count} element(s) of unsupported type {name} (Gmsh type {code}, {dim}-D); only linear \
         triangles (type 2) and quadrilaterals (type 3) are supported (set Mesh.ElementOrder = 1)"
    )]
    UnsupportedElement {
        /// mshio's name, e.g. `Tri6`.
        name: String,
        /// Gmsh's numeric type.
        code: i32,
        /// Dimension of the entity holding the elements.
        dim: i32,
        /// How many.
        count: usize,
    },
    /// Triangles and quadrilaterals in one file.
    #[error(
        "mixes {triangles} triangles and {quads} quadrilaterals; a body has one element type: \
         recombine all of them (Mesh.RecombineAll = 1) or none, or split the part into two bodies"
    )]
    MixedElements {
        /// Triangles.
        triangles: usize,
        /// Quadrilaterals.
        quads: usize,
    },
    /// An element refers to a node that the `$Nodes` section does not define.
    #[error("element {element} uses node {node}, which the file does not define")]
    UnknownNode {
        /// Element tag.
        element: u64,
        /// Node tag.
        node: u64,
    },
    /// Two nodes with the same tag.
    #[error("defines node {0} more than once")]
    DuplicateTag(u64),
    /// The nodes are not in one plane z = const.
    #[error(
        "is not planar: node z ranges over [{z_min}, {z_max}]; a 2-D mesh needs every node at one z"
    )]
    NotPlanar {
        /// Smallest z.
        z_min: f64,
        /// Largest z.
        z_max: f64,
    },
    /// A coordinate is NaN or infinite.
    #[error("node {0} has a coordinate that is not finite")]
    NotFinite(u64),
    /// Two distinct nodes at the same place (an unmerged interface: Coherence / removeDuplicateNodes).
    #[error(
        "nodes {a} and {b} coincide at ({x}, {y}): the mesh is not conforming there (run \
         Coherence Mesh, or gmsh.model.mesh.removeDuplicateNodes())"
    )]
    DuplicateNodes {
        /// Tag of one node.
        a: u64,
        /// Tag of the other.
        b: u64,
        /// x.
        x: f64,
        /// y.
        y: f64,
    },
    /// An element of (nearly) zero area, or a non-convex quadrilateral.
    #[error(
        "element {element} is degenerate (signed area {area:e}, or a non-convex quadrilateral)"
    )]
    Degenerate {
        /// Element tag.
        element: u64,
        /// Its signed area.
        area: f64,
    },
    /// An element oriented against the others.
    #[error(
        "element {element} is inverted: it is oriented {orientation} while {majority} of the {total} \
         elements are oriented the other way"
    )]
    Inverted {
        /// Element tag.
        element: u64,
        /// "clockwise" or "counter-clockwise".
        orientation: &'static str,
        /// Elements of the other orientation.
        majority: usize,
        /// All 2-D elements.
        total: usize,
    },
    /// An edge shared by more than two elements, or by two on the same side of it.
    #[error(
        "the edge between nodes {a} and {b} belongs to {count} elements, two of them on the same \
         side of it (overlapping or folded elements)"
    )]
    NonManifold {
        /// Node tag.
        a: u64,
        /// Node tag.
        b: u64,
        /// Elements sharing it.
        count: usize,
    },
    /// The boundary is not one closed loop.
    #[error(
        "has a boundary of {loops} closed loop(s){pinch}; a body must be one piece without holes \
         (mesh each piece as its own body)"
    )]
    Boundary {
        /// Loops found.
        loops: usize,
        /// " touching itself at node N" when a boundary node starts two edges, " left open at
        /// node N" when a boundary chain ends there.
        pinch: String,
    },
}
