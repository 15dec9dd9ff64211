//! Reading a QP `min ½xᵀAx − fᵀx  s.t.  Bx ≤ g` from the Matrix Market files `signorini export`
//! writes (`A.mtx`, `f.mtx`, `B.mtx`, `g.mtx` in one directory), or that another code wrote in
//! the same layout (see `scripts/qp-from-scipy.py`).
//!
//! The reader is a small strict one, not `sprs::io::read_matrix_market`: that reader reads only
//! the `coordinate` format (f and g are `array`), asserts (panics) on an index beyond the declared
//! shape, ignores entries beyond the declared count, and its errors carry neither the line nor
//! the reason ("Bad matrix market file.").  Every refusal here names the file and, when one line
//! is at fault, its number: `dir/A.mtx:7: column index 12 out of range 1..=10`.
//!
//! Accepted: the header `%%MatrixMarket matrix coordinate|array real|integer general|symmetric`
//! (case-insensitive), `%` comment lines and blank lines anywhere after it, the size line, then
//! exactly the declared entries.  A `symmetric` file stores the lower triangle (the full matrix
//! is rebuilt); a `general` A is accepted only when symmetric to
//! [`SYMMETRY_TOLERANCE`] · max|A| and is then replaced by (A + Aᵀ)/2.  Duplicate coordinate
//! entries are summed.  Vectors may be n×1 or 1×n, `array` or `coordinate`.  NaN and infinite
//! values are refused.  `dofs.csv` and `rows.csv`, if present, are not read.
//!
//! An optional `N.mtx` (array n×k, as `export` writes for a body held by contact alone) is a
//! basis of A's null space: each column must be nonzero and satisfy
//! ‖A v‖∞ ≤ [`NULL_SPACE_TOLERANCE`] · ‖A‖∞ · ‖v‖∞; the dual backends need it when A is
//! singular.
//!
//! An optional `blocks.csv` (as `export` writes) names each row's multiplier set, making the
//! problem `min ½xᵀAx − fᵀx + Σ_{box rows i} sᵢ |(Bx − g)ᵢ|  s.t.  (Bx)ᵢ ≤ gᵢ` on the other rows
//! (Tresca friction's tangential rows are box rows, see [`signorini_core::qp::ConstraintBlock`]):
//!
//! ```text
//! row,kind,bound
//! 0,non-negative,
//! 1,box,2.5e-5
//! ```
//!
//! the header `row,kind,bound`, then one line per row of B in order (`row` = 0, 1, …, m − 1, as
//! in `rows.csv`), `kind` `non-negative` (Bx ≤ g, λ ≥ 0; no bound) or `box` (|λ| ≤ `bound`, a
//! finite number ≥ 0).  Blank lines are skipped; anything else is refused naming the line (see
//! [`read_blocks`]).  Without the file every row is `non-negative` (the files of other codes).

use std::fmt;
use std::path::{Path, PathBuf};

use signorini_core::qp::{BlockKind, ConstraintBlock, CscMatrix, QpProblem};

/// A `general` A counts as symmetric when |Aᵢⱼ − Aⱼᵢ| ≤ this · max|A| for every stored entry.
///
/// Assembly round-off in another code (an entry summed from a few dozen element contributions
/// in a different order than its mirror) is ~100 ε ≈ 2e-14 of max|A|; 1e-10 leaves four orders
/// of margin above it.  The symmetrised (A + Aᵀ)/2 then differs from the file by at most
/// 5e-11 · max|A|, ten times below the tightest default KKT tolerance (1e-9) the residual check
/// applies, so the symmetrisation cannot change a verdict.  A genuinely unsymmetric operator
/// (friction, follower loads) differs at O(1) and is refused.
pub const SYMMETRY_TOLERANCE: f64 = 1e-10;

/// The files of a QP directory, in the order they are read.
pub const QP_FILES: [&str; 4] = ["A.mtx", "f.mtx", "B.mtx", "g.mtx"];

/// The optional null-space basis of A.
pub const KERNEL_FILE: &str = "N.mtx";

/// The optional constraint blocks (each row's kind and bound); without it every row is
/// one-sided.
pub const BLOCKS_FILE: &str = "blocks.csv";

/// The header line of [`BLOCKS_FILE`].
pub const BLOCKS_HEADER: &str = "row,kind,bound";

/// A column v of `N.mtx` counts as in A's null space when ‖A v‖∞ ≤ this · ‖A‖∞ · ‖v‖∞ (‖A‖∞ the
/// largest row sum of |A|).  A rigid-body mode of an assembled stiffness gives round-off only,
/// ~1e-15 of that bound's scale; a vector outside the null space gives O(1).  1e-8 sits far from
/// both.
pub const NULL_SPACE_TOLERANCE: f64 = 1e-8;

/// Why a QP directory was refused: the file, the line when one line is at fault, and the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct QpFileError {
    /// The file at fault.
    pub file: PathBuf,
    /// 1-based line number, when one line is at fault.
    pub line: Option<usize>,
    /// What is wrong.
    pub reason: String,
}

impl fmt::Display for QpFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: {}", self.file.display(), self.reason),
            None => write!(f, "{}: {}", self.file.display(), self.reason),
        }
    }
}

/// A QP read from a directory.
#[derive(Debug, Clone)]
pub struct QpFiles {
    /// The directory read.
    pub dir: PathBuf,
    /// The problem, with the null space of `N.mtx` when the directory has one.
    pub qp: QpProblem,
    /// The `Scene:` line of `README.txt` when the directory is an export of signorini.
    pub title: Option<String>,
    /// Whether A's file was `general` (symmetrised on reading) rather than `symmetric`.
    pub general: bool,
}

/// The storage of a Matrix Market file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Layout {
    Coordinate,
    Array,
}

/// One Matrix Market file: its shape, whether it is `symmetric`, and its entries (0-based row,
/// column, value, 1-based line).  A symmetric file's entries are those stored (lower triangle).
#[derive(Debug)]
struct Mtx {
    path: PathBuf,
    rows: usize,
    cols: usize,
    size_line: usize,
    symmetric: bool,
    entries: Vec<Entry>,
}

/// One stored value: row, column (from 0), value, and the line it was read from.
type Entry = (usize, usize, f64, usize);

impl Mtx {
    fn error(&self, line: Option<usize>, reason: impl Into<String>) -> QpFileError {
        QpFileError {
            file: self.path.clone(),
            line,
            reason: reason.into(),
        }
    }
}

fn refuse(path: &Path, line: Option<usize>, reason: impl Into<String>) -> QpFileError {
    QpFileError {
        file: path.to_path_buf(),
        line,
        reason: reason.into(),
    }
}

/// A value token: a finite number.
fn value(path: &Path, line: usize, token: &str) -> Result<f64, QpFileError> {
    let v: f64 = token
        .parse()
        .map_err(|_| refuse(path, Some(line), format!("`{token}` is not a number")))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(refuse(
            path,
            Some(line),
            format!("value `{token}` is not finite (NaN or infinite)"),
        ))
    }
}

/// A 1-based index token within 1..=`bound`, returned 0-based.
fn index(
    path: &Path,
    line: usize,
    token: &str,
    what: &str,
    bound: usize,
) -> Result<usize, QpFileError> {
    let i: usize = token.parse().map_err(|_| {
        refuse(
            path,
            Some(line),
            format!("{what} index `{token}` is not a positive integer"),
        )
    })?;
    if i == 0 || i > bound {
        return Err(refuse(
            path,
            Some(line),
            format!("{what} index {i} out of range 1..={bound}"),
        ));
    }
    Ok(i - 1)
}

/// Reads one Matrix Market file strictly (see the module's documentation).
fn read_mtx(path: &Path) -> Result<Mtx, QpFileError> {
    let text = read_text(path)?;
    let mut lines = text.lines().enumerate().map(|(k, l)| (k + 1, l.trim()));
    // The header.
    let header = lines.next().map(|(_, l)| l).unwrap_or("");
    let (layout, symmetric) = parse_header(path, header)?;
    let mut data = lines.filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    // The size line.
    let (size_line, size) = data
        .next()
        .ok_or_else(|| refuse(path, None, "the file ends before its size line"))?;
    let counts = parse_size(path, layout, size_line, size)?;
    let (rows, cols) = (counts[0], counts[1]);
    if symmetric && rows != cols {
        return Err(refuse(
            path,
            Some(size_line),
            format!("a symmetric matrix must be square, not {rows}×{cols}"),
        ));
    }
    let mut mtx = Mtx {
        path: path.to_path_buf(),
        rows,
        cols,
        size_line,
        symmetric,
        entries: Vec::new(),
    };
    match layout {
        Layout::Coordinate => mtx.entries = read_coordinate(&mtx, data, counts[2])?,
        Layout::Array => mtx.entries = read_array(&mtx, data)?,
    }
    Ok(mtx)
}

/// The file's text, or a refusal saying it is missing or unreadable.
fn read_text(path: &Path) -> Result<String, QpFileError> {
    std::fs::read_to_string(path).map_err(|e| {
        refuse(
            path,
            None,
            if e.kind() == std::io::ErrorKind::NotFound {
                "missing (a QP directory holds A.mtx, f.mtx, B.mtx and g.mtx)".to_string()
            } else {
                format!("cannot be read: {e}")
            },
        )
    })
}

/// The layout and symmetry the header line declares (real or integer fields only).
fn parse_header(path: &Path, header: &str) -> Result<(Layout, bool), QpFileError> {
    let words: Vec<String> = header
        .split_whitespace()
        .map(|w| w.to_ascii_lowercase())
        .collect();
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    let (layout, symmetric) = match words.as_slice() {
        ["%%matrixmarket", "matrix", layout, field, symmetry] => {
            let layout = match *layout {
                "coordinate" => Layout::Coordinate,
                "array" => Layout::Array,
                other => {
                    return Err(refuse(
                        path,
                        Some(1),
                        format!("format `{other}` not supported (coordinate or array)"),
                    ))
                }
            };
            if !matches!(*field, "real" | "integer") {
                return Err(refuse(
                    path,
                    Some(1),
                    format!("field `{field}` not supported (real or integer)"),
                ));
            }
            let symmetric = match *symmetry {
                "general" => false,
                "symmetric" => true,
                other => {
                    return Err(refuse(
                        path,
                        Some(1),
                        format!("symmetry `{other}` not supported (general or symmetric)"),
                    ))
                }
            };
            (layout, symmetric)
        }
        _ => {
            return Err(refuse(
                path,
                Some(1),
                "not a Matrix Market header: expected `%%MatrixMarket matrix coordinate|array real|integer general|symmetric`",
            ))
        }
    };
    Ok((layout, symmetric))
}

/// The size line's counts: `rows cols entries` for a coordinate file, `rows cols` for an array.
fn parse_size(
    path: &Path,
    layout: Layout,
    size_line: usize,
    size: &str,
) -> Result<Vec<usize>, QpFileError> {
    let tokens: Vec<&str> = size.split_whitespace().collect();
    let want = if layout == Layout::Coordinate { 3 } else { 2 };
    tokens
        .iter()
        .map(|t| t.parse::<usize>())
        .collect::<Result<_, _>>()
        .ok()
        .filter(|c: &Vec<usize>| c.len() == want)
        .ok_or_else(|| {
            refuse(
                path,
                Some(size_line),
                format!(
                    "size line `{size}` must be {} non-negative integers",
                    if want == 3 {
                        "`rows cols entries`: three"
                    } else {
                        "`rows cols`: two"
                    }
                ),
            )
        })
}

/// The entries of a coordinate file: exactly `declared` lines `row column value` (in the lower
/// triangle when symmetric).
fn read_coordinate<'t>(
    mtx: &Mtx,
    data: impl Iterator<Item = (usize, &'t str)>,
    declared: usize,
) -> Result<Vec<Entry>, QpFileError> {
    let (path, rows, cols, size_line) = (mtx.path.as_path(), mtx.rows, mtx.cols, mtx.size_line);
    let mut entries: Vec<Entry> = Vec::new();
    for (line, text) in data {
        if entries.len() == declared {
            return Err(mtx.error(
                Some(line),
                format!("more entries than the {declared} declared on line {size_line}"),
            ));
        }
        let t: Vec<&str> = text.split_whitespace().collect();
        if t.len() != 3 {
            return Err(mtx.error(
                Some(line),
                format!("expected `row column value`, found `{text}`"),
            ));
        }
        let i = index(path, line, t[0], "row", rows)?;
        let j = index(path, line, t[1], "column", cols)?;
        let v = value(path, line, t[2])?;
        if mtx.symmetric && i < j {
            return Err(mtx.error(
                Some(line),
                format!(
                    "entry ({}, {}) lies above the diagonal; a symmetric file stores the lower triangle only",
                    i + 1,
                    j + 1
                ),
            ));
        }
        entries.push((i, j, v, line));
    }
    if entries.len() < declared {
        return Err(mtx.error(
            None,
            format!(
                "the file ends after {} of the {declared} entries declared on line {size_line}",
                entries.len()
            ),
        ));
    }
    Ok(entries)
}

/// The values of an array file: one a line, column-major (a symmetric file's lower triangle
/// column by column), exactly as many as the size declares.
fn read_array<'t>(
    mtx: &Mtx,
    data: impl Iterator<Item = (usize, &'t str)>,
) -> Result<Vec<Entry>, QpFileError> {
    let (path, rows, cols, size_line) = (mtx.path.as_path(), mtx.rows, mtx.cols, mtx.size_line);
    let mut entries: Vec<Entry> = Vec::new();
    // Column-major; a symmetric array stores the lower triangle column by column.
    let positions: Box<dyn Iterator<Item = (usize, usize)>> = if mtx.symmetric {
        Box::new((0..cols).flat_map(move |j| (j..rows).map(move |i| (i, j))))
    } else {
        Box::new((0..cols).flat_map(move |j| (0..rows).map(move |i| (i, j))))
    };
    let mut positions = positions.peekable();
    for (line, text) in data {
        let t: Vec<&str> = text.split_whitespace().collect();
        if t.len() != 1 {
            return Err(mtx.error(
                Some(line),
                format!("expected one value per line in an array file, found `{text}`"),
            ));
        }
        let Some((i, j)) = positions.next() else {
            return Err(mtx.error(
                Some(line),
                format!("more values than the {rows}×{cols} declared on line {size_line}"),
            ));
        };
        let v = value(path, line, t[0])?;
        entries.push((i, j, v, line));
    }
    if positions.peek().is_some() {
        return Err(mtx.error(
            None,
            format!(
                "the file ends after {} values; line {size_line} declares {rows}×{cols}",
                entries.len()
            ),
        ));
    }
    Ok(entries)
}

/// The full CSC matrix of a file (a symmetric file mirrored), duplicates summed.
fn to_csc(m: &Mtx) -> CscMatrix {
    let mut t = sprs::TriMat::with_capacity((m.rows, m.cols), m.entries.len() * 2);
    for &(i, j, v, _) in &m.entries {
        t.add_triplet(i, j, v);
        if m.symmetric && i != j {
            t.add_triplet(j, i, v);
        }
    }
    t.to_csc()
}

/// A vector file: n×1 or 1×n with `n == expected`.
fn to_vector(m: &Mtx, name: &str, expected: usize, what: &str) -> Result<Vec<f64>, QpFileError> {
    let len = match (m.rows, m.cols) {
        (n, 1) | (1, n) => n,
        (r, c) => {
            return Err(m.error(
                Some(m.size_line),
                format!("{name} must be a vector (n×1 or 1×n), not {r}×{c}"),
            ))
        }
    };
    if len != expected {
        return Err(m.error(
            Some(m.size_line),
            format!("{name} has length {len} but {what}"),
        ));
    }
    let mut v = vec![0.0; len];
    for &(i, j, x, _) in &m.entries {
        v[i.max(j)] += x;
    }
    Ok(v)
}

/// The columns of `N.mtx`, each checked to lie in A's null space (see [`NULL_SPACE_TOLERANCE`]).
fn kernel(m: &Mtx, a: &CscMatrix) -> Result<Vec<Vec<f64>>, QpFileError> {
    let n = a.rows();
    if m.rows != n || m.cols == 0 || m.cols > n {
        return Err(m.error(
            Some(m.size_line),
            format!(
                "N must be n×k with n = {n} (A is {n}×{n}) and 1 ≤ k ≤ n, not {}×{}",
                m.rows, m.cols
            ),
        ));
    }
    let mut columns = vec![vec![0.0; n]; m.cols];
    for &(i, j, x, _) in &m.entries {
        columns[j][i] += x;
        if m.symmetric && i != j {
            return Err(m.error(None, "N cannot be `symmetric`: it is n×k"));
        }
    }
    let norm_a = (0..n)
        .map(|i| {
            a.outer_view(i)
                .map_or(0.0, |c| c.iter().map(|(_, v)| v.abs()).sum::<f64>())
        })
        .fold(0.0_f64, f64::max);
    for (j, v) in columns.iter().enumerate() {
        let largest = v.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        if largest == 0.0 {
            return Err(m.error(None, format!("column {} of N is zero", j + 1)));
        }
        let av = signorini_core::qp::mat_vec(a, v);
        let residual = av.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        let allowed = NULL_SPACE_TOLERANCE * norm_a * largest;
        if residual > allowed {
            return Err(m.error(
                None,
                format!(
                    "column {} of N is not in A's null space: ‖A v‖∞ = {residual:e} > {NULL_SPACE_TOLERANCE:e} · ‖A‖∞ · ‖v‖∞ = {allowed:e}",
                    j + 1
                ),
            ));
        }
    }
    Ok(columns)
}

/// A's checks: square, symmetric (a `general` file to [`SYMMETRY_TOLERANCE`], then symmetrised),
/// nonnegative diagonal (a necessary condition of positive semidefiniteness).
fn stiffness(m: &Mtx) -> Result<CscMatrix, QpFileError> {
    if m.rows != m.cols {
        return Err(m.error(
            Some(m.size_line),
            format!("A must be square (n×n), not {}×{}", m.rows, m.cols),
        ));
    }
    // Every unknown has stiffness, so A stores an entry in every row: a size line declaring
    // more rows than the entries can cover is refused before anything of that size is
    // allocated (a header claiming 10¹² unknowns must not exhaust memory).
    let covered = m.entries.len() * if m.symmetric { 2 } else { 1 };
    if m.rows > covered {
        return Err(m.error(
            Some(m.size_line),
            format!(
                "A declares {} unknowns but stores {} entries: some unknown has an empty row (no stiffness)",
                m.rows,
                m.entries.len()
            ),
        ));
    }
    let a = to_csc(m);
    for &(i, j, _, line) in &m.entries {
        if i == j && a.get(i, i).copied().unwrap_or(0.0) < 0.0 {
            return Err(m.error(
                Some(line),
                format!(
                    "diagonal entry A({0}, {0}) = {1:e} is negative: A is not positive semidefinite",
                    i + 1,
                    a.get(i, i).copied().unwrap_or(0.0)
                ),
            ));
        }
    }
    if m.symmetric {
        return Ok(a);
    }
    let largest = a.data().iter().fold(0.0_f64, |s, v| s.max(v.abs()));
    let lines: std::collections::HashMap<(usize, usize), usize> = m
        .entries
        .iter()
        .map(|&(i, j, _, line)| ((i, j), line))
        .collect();
    let allowed = SYMMETRY_TOLERANCE * largest;
    for &(i, j, _, line) in &m.entries {
        let (aij, aji) = (
            a.get(i, j).copied().unwrap_or(0.0),
            a.get(j, i).copied().unwrap_or(0.0),
        );
        if (aij - aji).abs() > allowed {
            return Err(m.error(
                Some(line),
                format!(
                    "A is not symmetric: A({}, {}) = {aij:e} here but A({}, {}) = {aji:e} ({}) (allowed difference {SYMMETRY_TOLERANCE:e} · max|A| = {allowed:e}); a `general` A must be symmetric, or store the lower triangle with a `symmetric` header",
                    i + 1,
                    j + 1,
                    j + 1,
                    i + 1,
                    lines
                        .get(&(j, i))
                        .map_or("not stored".to_string(), |l| format!("line {l}"))
                ),
            ));
        }
    }
    // (A + Aᵀ)/2 entry by entry, keeping every stored entry (explicit zeros included: a matrix
    // sum would drop them and change the pattern, hence the floor's ordering and nnz(L)).
    // Halving is exact, so an exactly symmetric file reads back unchanged.
    let mut t = sprs::TriMat::with_capacity((m.rows, m.cols), m.entries.len() * 2);
    for &(i, j, v, _) in &m.entries {
        t.add_triplet(i, j, 0.5 * v);
        t.add_triplet(j, i, 0.5 * v);
    }
    Ok(t.to_csc())
}

/// Reads `blocks.csv` at `path` for a B of `rows` rows (see the module docs): the header
/// `row,kind,bound`, then every row in order with its kind and, for a `box` row, its bound.
/// Consecutive rows of one kind become one [`ConstraintBlock`].  Refused, naming the line: a
/// wrong header, a line without exactly three fields, a row out of order or beyond B's rows, an
/// unknown kind, a bound on a `non-negative` row, a `box` row without a bound or whose bound is
/// not a number, not finite or negative; and, naming the file, fewer lines than B has rows.
pub fn read_blocks(path: &Path, rows: usize) -> Result<Vec<ConstraintBlock>, QpFileError> {
    let text = read_text(path)?;
    let mut lines = text.lines().enumerate().map(|(k, l)| (k + 1, l.trim()));
    let header = lines.next().map_or("", |(_, l)| l);
    if header != BLOCKS_HEADER {
        return Err(refuse(
            path,
            Some(1),
            format!("the header must be `{BLOCKS_HEADER}`, not `{header}`"),
        ));
    }
    let mut blocks: Vec<ConstraintBlock> = Vec::new();
    let mut next = 0;
    for (line, text) in lines.filter(|(_, l)| !l.is_empty()) {
        let at = |reason: String| refuse(path, Some(line), reason);
        let fields: Vec<&str> = text.split(',').map(str::trim).collect();
        let [row, kind, bound] = fields.as_slice() else {
            return Err(at(format!(
                "expected three fields `row,kind,bound`, found {} in `{text}`",
                fields.len()
            )));
        };
        let row: usize = row
            .parse()
            .map_err(|_| at(format!("row `{row}` is not a non-negative integer")))?;
        if row >= rows {
            return Err(at(format!(
                "row {row} is beyond B's {rows} rows (rows are numbered from 0, as in rows.csv)"
            )));
        }
        if row != next {
            return Err(at(format!(
                "row {row} out of order: expected row {next} (every row of B once, in order 0, 1, …)"
            )));
        }
        let kind = match *kind {
            "non-negative" => BlockKind::NonNegative,
            "box" => BlockKind::Box,
            other => return Err(at(format!("unknown kind `{other}` (non-negative or box)"))),
        };
        match kind {
            BlockKind::NonNegative => {
                if !bound.is_empty() {
                    return Err(at(format!(
                        "a non-negative row takes no bound (its multiplier is only ≥ 0), found `{bound}`"
                    )));
                }
                match blocks.last_mut() {
                    Some(ConstraintBlock::NonNegative { rows }) => *rows += 1,
                    _ => blocks.push(ConstraintBlock::NonNegative { rows: 1 }),
                }
            }
            BlockKind::Box => {
                if bound.is_empty() {
                    return Err(at("a box row needs its bound s ≥ 0 (|λ| ≤ s)".into()));
                }
                let s: f64 = bound
                    .parse()
                    .map_err(|_| at(format!("bound `{bound}` is not a number")))?;
                if !s.is_finite() {
                    return Err(at(format!(
                        "bound `{bound}` is not finite (NaN or infinite)"
                    )));
                }
                if s < 0.0 {
                    return Err(at(format!(
                        "bound {s:e} is negative (a box row's |λ| ≤ s needs s ≥ 0)"
                    )));
                }
                match blocks.last_mut() {
                    Some(ConstraintBlock::Box { bounds }) => bounds.push(s),
                    _ => blocks.push(ConstraintBlock::Box { bounds: vec![s] }),
                }
            }
        }
        next += 1;
    }
    if next < rows {
        return Err(refuse(
            path,
            None,
            format!("lists {next} rows but B has {rows}: every row of B needs its line"),
        ));
    }
    Ok(blocks)
}

/// Reads A, f, B, g from `dir` and checks their shapes against each other.
pub fn read_qp_dir(dir: &Path) -> Result<QpFiles, QpFileError> {
    if !dir.is_dir() {
        return Err(refuse(
            dir,
            None,
            "not a directory (--qp takes a directory holding A.mtx, f.mtx, B.mtx and g.mtx)",
        ));
    }
    let [a, f, b, g] = QP_FILES.map(|name| dir.join(name));
    let a = read_mtx(&a)?;
    let stiffness = stiffness(&a)?;
    let n = a.rows;
    let f = read_mtx(&f)?;
    let load = to_vector(&f, "f", n, &format!("A ({}) is {n}×{n}", a.path.display()))?;
    let b = read_mtx(&b)?;
    if b.cols != n {
        return Err(b.error(
            Some(b.size_line),
            format!(
                "B is {}×{} but must have n = {n} columns (A is {n}×{n})",
                b.rows, b.cols
            ),
        ));
    }
    let m = b.rows;
    // Likewise every constraint involves an unknown (and g is allocated at B's row count).
    if m > b.entries.len() {
        return Err(b.error(
            Some(b.size_line),
            format!(
                "B declares {m} rows but stores {} entries: some constraint row is empty",
                b.entries.len()
            ),
        ));
    }
    let constraints = to_csc(&b);
    let g = read_mtx(&g)?;
    let gap = to_vector(
        &g,
        "g",
        m,
        &format!("B ({}) has {m} rows", b.path.display()),
    )?;
    let kernel_path = dir.join(KERNEL_FILE);
    let kernel = if kernel_path.exists() {
        kernel(&read_mtx(&kernel_path)?, &stiffness)?
    } else {
        Vec::new()
    };
    let blocks_path = dir.join(BLOCKS_FILE);
    let blocks = if blocks_path.exists() {
        Some(read_blocks(&blocks_path, m)?)
    } else {
        None
    };
    let qp = QpProblem::try_new(stiffness, load, constraints, gap)
        .and_then(|qp| qp.with_kernel(kernel))
        .and_then(|qp| match blocks {
            Some(blocks) => qp.with_blocks(blocks),
            None => Ok(qp),
        })
        .map_err(|e| refuse(dir, None, e.to_string()))?;
    let title = std::fs::read_to_string(dir.join("README.txt"))
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("Scene: ").map(|s| s.trim().to_string()))
        });
    Ok(QpFiles {
        dir: dir.to_path_buf(),
        qp,
        title,
        general: !a.symmetric,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) {
        std::fs::write(dir.join(name), text).unwrap();
    }

    /// x ≤ 1 on min x² − 4x written by hand: a symmetric 1×1 A, an array f, coordinate B, g.
    fn scalar(dir: &Path) {
        write(
            dir,
            "A.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n1 1 1\n1 1 2\n",
        );
        write(
            dir,
            "f.mtx",
            "%%MatrixMarket matrix array real general\n% c\n1 1\n4\n",
        );
        write(
            dir,
            "B.mtx",
            "%%MatrixMarket matrix coordinate real general\n1 1 1\n1 1 1\n",
        );
        write(
            dir,
            "g.mtx",
            "%%MatrixMarket matrix array real general\n1 1\n1\n",
        );
    }

    #[test]
    fn a_hand_written_qp_reads_back() {
        let d = tempfile::tempdir().unwrap();
        scalar(d.path());
        let q = read_qp_dir(d.path()).unwrap();
        assert_eq!(q.qp.load, vec![4.0]);
        assert_eq!(q.qp.gap, vec![1.0]);
        assert_eq!(q.qp.stiffness.get(0, 0), Some(&2.0));
        assert!(!q.general);
    }

    #[test]
    fn a_symmetric_file_is_mirrored_and_a_general_one_symmetrised() {
        let d = tempfile::tempdir().unwrap();
        scalar(d.path());
        write(
            d.path(),
            "A.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2\n2 1 -1\n2 2 2\n",
        );
        write(
            d.path(),
            "f.mtx",
            "%%MatrixMarket matrix array real general\n2 1\n1\n1\n",
        );
        write(
            d.path(),
            "B.mtx",
            "%%MatrixMarket matrix coordinate real general\n1 2 1\n1 1 1\n",
        );
        let q = read_qp_dir(d.path()).unwrap();
        assert_eq!(q.qp.stiffness.get(0, 1), Some(&-1.0));
        assert_eq!(q.qp.stiffness.get(1, 0), Some(&-1.0));
        // A general A off by 1e-12 · max|A| (within 1e-10) is averaged.
        write(
            d.path(),
            "A.mtx",
            "%%MatrixMarket matrix coordinate real general\n2 2 4\n1 1 2\n2 1 -1\n1 2 -1.000000000002\n2 2 2\n",
        );
        let q = read_qp_dir(d.path()).unwrap();
        assert_eq!(q.qp.stiffness.get(0, 1), q.qp.stiffness.get(1, 0));
        assert!(q.general);
    }

    #[test]
    fn blocks_csv_gives_each_row_its_set_and_its_absence_one_sided_rows() {
        let d = tempfile::tempdir().unwrap();
        scalar(d.path());
        write(
            d.path(),
            "B.mtx",
            "%%MatrixMarket matrix coordinate real general\n4 1 4\n1 1 1\n2 1 1\n3 1 -1\n4 1 1\n",
        );
        write(
            d.path(),
            "g.mtx",
            "%%MatrixMarket matrix array real general\n4 1\n1\n2\n3\n4\n",
        );
        let q = read_qp_dir(d.path()).unwrap();
        assert_eq!(q.qp.blocks, vec![ConstraintBlock::NonNegative { rows: 4 }]);
        write(
            d.path(),
            BLOCKS_FILE,
            "row,kind,bound\n0,non-negative,\n1, box ,0.5\n\n2,box,0\r\n3,non-negative,\n",
        );
        let q = read_qp_dir(d.path()).unwrap();
        assert_eq!(
            q.qp.blocks,
            vec![
                ConstraintBlock::NonNegative { rows: 1 },
                ConstraintBlock::Box {
                    bounds: vec![0.5, 0.0]
                },
                ConstraintBlock::NonNegative { rows: 1 },
            ]
        );
        // Out of order (a row listed twice).
        write(
            d.path(),
            BLOCKS_FILE,
            "row,kind,bound\n0,non-negative,\n0,box,1\n",
        );
        let e = read_qp_dir(d.path()).unwrap_err();
        assert_eq!(e.line, Some(3), "{e}");
        assert!(
            e.to_string()
                .contains("blocks.csv:3: row 0 out of order: expected row 1"),
            "{e}"
        );
        // Too few rows: the file is named, no line is at fault.
        write(d.path(), BLOCKS_FILE, "row,kind,bound\n0,box,inf\n");
        let e = read_qp_dir(d.path()).unwrap_err();
        assert!(
            e.to_string()
                .contains("blocks.csv:2: bound `inf` is not finite"),
            "{e}"
        );
        write(d.path(), BLOCKS_FILE, "row,kind,bound\n0,box,1\n");
        let e = read_qp_dir(d.path()).unwrap_err();
        assert_eq!(e.line, None);
        assert!(
            e.to_string()
                .contains("blocks.csv: lists 1 rows but B has 4"),
            "{e}"
        );
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let d = tempfile::tempdir().unwrap();
        scalar(d.path());
        write(
            d.path(),
            "A.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n1 1 1\n\n1 2 2\n",
        );
        let e = read_qp_dir(d.path()).unwrap_err();
        assert_eq!(e.line, Some(4), "{e}");
        assert!(
            e.to_string()
                .contains("A.mtx:4: column index 2 out of range 1..=1"),
            "{e}"
        );
    }
}
