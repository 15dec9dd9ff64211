//! `--backend auto`: the fastest backend likely to succeed on this problem, falling back to a
//! robust one when it does not.
//!
//! # The chain
//! [`plan`] picks an ordered list of backends from features of the QP that cost nothing to
//! measure ([`Features`]: n, m, the DOFs B touches, whether A has a kernel); [`AutoBackend`]
//! runs them in turn, each on auto's problem as it stands ([`QpBackend::solve_in_given_units`]:
//! auto's own `solve` has nondimensionalised it already), until one answers `solved` after the
//! core's own check
//! ([`checked_status`] on [`kkt_residuals`](signorini_core::qp::kkt_residuals), exactly as
//! [`signorini_core::solve`] judges every backend; the residual scales computed once for the
//! whole chain).  The rule:
//!
//! * **Short interface** (ℓ = [`Features::length_ratio`] ≤ [`LONG_INTERFACE`], the interface
//!   counted where it touches first, [`first_touch`]; and m ≤
//!   [`SSN_MAX_ROWS`], touched DOFs ≤ [`SSN_MAX_TOUCHED`]): [`SHORT_CHAIN`] = dual-ssn → pdas → clarabel.  dual-ssn (active set
//!   on the condensed dual, H formed from the factor of A with the touched DOFs last) takes
//!   1.1–1.5× the floor on the seed's geometry from 448 to 206 278 DOFs, where clarabel takes
//!   9–30×.
//! * **Long interface** (ℓ above [`LONG_INTERFACE`]: a contact zone long against the body it
//!   runs along, e.g. a thin strip pressed along its length, however thick the foundation under
//!   it), or a dual too large to form densely:
//!   [`LONG_CHAIN`] = pdas → osqp (at most [`OSQP_MAX_ITER`] iterations) → clarabel → dual-ssn.  There the
//!   dual is ill-conditioned and dual-ssn ends `inaccurate` after 7–90× the floor; osqp solves the
//!   strips in 50–100 iterations, 6–11× the floor, 1.1–1.75× faster than clarabel; clarabel
//!   (7–14×) catches whatever osqp does not solve within its cap.
//!
//! pdas (active set on the sparse primal KKT system) joins both chains as soon as it is listed in
//! [`BackendKind::ALL`]; a backend this build lacks (osqp without its feature) is left out.
//!
//! The thresholds come from measurements on the seed fixtures, the hard cases and the strips
//! (`cargo test --release -p signorini --test auto -- --ignored measure --nocapture`; the
//! numbers are in `docs/scene.md`).
//!
//! # Fall-back
//! An attempt that ends with any status but `solved`, or with an error, hands over to the next
//! one; the whole chain shares the time limit (each attempt gets what remains, and an attempt
//! that ran out of time ends the chain with `time-limit`).  [`QpError::TooLarge`] is special:
//! a dense dual method (dual-*, */dual) refused for its m × m matrix says nothing about the
//! sparse primal methods, so the chain goes on; a sparse primal method refused for its factor
//! ends the chain with that error, because every later backend factors A (or a KKT matrix that
//! contains it) too and would need at least as much.
//!
//! The answer written is the first `solved` one; when none is, the last attempt that produced
//! an answer (the most robust method's), with its own status.  [`AutoBackend::record`] keeps
//! what ran and why for `result.json` (`attempts`, `chosen`, `reason`).

use std::time::{Duration, Instant};

use serde::Serialize;
use signorini_core::qp::{
    checked_status, first_touch, kkt_residuals_with, touched_dofs, BlockKind, Components,
    ContactBody, CoulombRows, QpBackend, QpError, QpProblem, QpSolution, QpStatus, SolveOptions,
};
use signorini_core::report::{AttemptReport, RunReport};

use super::{make_backend, BackendKind};

/// dual-ssn goes first only up to this many contact rows (its H is dense, m² doubles, and each
/// Newton step factors the active block of it).
pub const SSN_MAX_ROWS: usize = 1_000;

/// dual-ssn goes first only when B touches at most this many DOFs (the dense trailing block of
/// the factor it forms H from has this size).
pub const SSN_MAX_TOUCHED: usize = 4_000;

/// An interface is *long* when ℓ = [`Features::length_ratio`] exceeds this: the interface of
/// the most slender contact body against the square root of that body's own DOFs
/// ([`ContactBody`]), counting the rows that touch first ([`first_touch`]).  In 2D a body's
/// boundary grows like √(its DOFs), so ℓ measures the contact length against the body it runs
/// along: 0.40–0.43 on the seed's geometry at every mesh size, at most 0.87 on the fixtures
/// (chain-four; 0.39 on the Cattaneo cylinder, 0.04 on the Hertz cylinder), 4.5 to 15.8 on thin
/// strips pressed along their length (lengths 1 to 20, 0.02 thick), whatever the foundation's
/// thickness.  On those the dual Hessian is so ill-conditioned that dual-ssn ends `inaccurate`
/// after paying 7–90× the floor, or solves at 1.3–1.8× where pdas takes 1.0–1.1× (a strip on a
/// foundation 25–100 times thicker; the rule once divided m by √n of the whole model, which
/// such a foundation diluted to 0.8–0.9).  Counting every candidate row instead of those that
/// touch first made the Hertz cylinder long (311 rows sampled every 0.001 along its arc on a cap
/// of 12 918 DOFs: 2.74), and pdas took 7.3× the floor there in 14 steps where dual-ssn takes
/// 2.4×.  Measured by `cargo test --release -p signorini --test auto -- --ignored features
/// --nocapture` over the fixtures.
pub const LONG_INTERFACE: f64 = 1.2;

/// OSQP's iteration cap inside the chain: it needs 50–100 iterations on the strips, and a run
/// that does not converge (50 000 iterations on the stiffness-contrast fixture) must not eat the
/// time of the robust backend after it.
pub const OSQP_MAX_ITER: u32 = 1_000;

/// The chain for short interfaces (small dense duals).
pub const SHORT_CHAIN: [BackendKind; 3] = [
    BackendKind::DualSsn,
    BackendKind::Pdas,
    BackendKind::Clarabel,
];

/// The chain for long interfaces, or duals too large to form densely.
///
/// dual-ssn comes last: slow on long interfaces (it forms the dense H with one sparse solve per
/// row, 70–800× the floor on the 51k-DOF strips) but its refined Newton steps solved every long
/// interface measured, including a strip loaded on a fifth of its length where pdas, osqp and
/// clarabel did not reach the tolerance.
pub const LONG_CHAIN: [BackendKind; 4] = [
    BackendKind::Pdas,
    BackendKind::Osqp,
    BackendKind::Clarabel,
    BackendKind::DualSsn,
];

/// The chain for problems with friction's box rows and a short interface: projected
/// Gauss–Seidel on the condensed dual (the classic method for friction; its projection onto
/// |λₜ| ≤ s is exact), then pdas (stick rows active, slip rows at ±s), then clarabel on the
/// primal form with auxiliary unknowns.  Measured on the Cattaneo cylinder (61 886 DOFs, 125
/// normal rows, Coulomb, three increments): dual-pgs 10×, pdas 39×, clarabel 217× the floor.
pub const FRICTION_SHORT_CHAIN: [BackendKind; 3] = [
    BackendKind::DualPgs,
    BackendKind::Pdas,
    BackendKind::Clarabel,
];

/// The chain for friction on a short interface whose bodies are held only by contact (A has
/// rigid modes, [`Features::kernel`]): the active sets first — dual-ssn (its slips that leave a
/// mode unheld stick, issue 41), pdas — then OSQP and clarabel.  dual-pgs is not in it: the
/// penalty that holds the modes in its dual makes that dual ill-conditioned, and it took 10–200×
/// the floor on a floating block or cap held sideways by friction, or did not converge, where
/// the active sets take 2× (BENCHMARKS.md, "Friction on ordinary scenes").
pub const FRICTION_FLOATING_CHAIN: [BackendKind; 4] = [
    BackendKind::DualSsn,
    BackendKind::Pdas,
    BackendKind::Osqp,
    BackendKind::Clarabel,
];

/// The chain for friction on long interfaces or large duals: pdas (no dense m × m matrix;
/// 2.5× the floor on a Tresca strip with 2 001 normal rows, where clarabel takes 13×, osqp
/// 8.6× and dual-pgs ends inaccurate), then clarabel and OSQP on the primal form with
/// auxiliary unknowns.
pub const FRICTION_LONG_CHAIN: [BackendKind; 3] =
    [BackendKind::Pdas, BackendKind::Clarabel, BackendKind::Osqp];

/// The chain for Coulomb friction solved by a backend's own method
/// ([`QpBackend::solve_coulomb`]): pdas's semismooth Newton, 1.9× the floor on the Coulomb strip
/// of BENCHMARKS.md ("Friction") where the fixed point over pdas's Tresca solves takes 17.8×.
/// When no member solves, the core falls back to the fixed point through the frictional chains.
pub const COULOMB_CHAIN: [BackendKind; 1] = [BackendKind::Pdas];

/// The backend's name.
pub const NAME: &str = "auto";

/// What the rule looks at: all read off the QP without factoring anything.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Features {
    /// Unknowns n.
    pub dofs: usize,
    /// Contact rows m.
    pub rows: usize,
    /// Distinct DOFs with a nonzero in some row of B.
    pub touched: usize,
    /// Rigid-body modes held by contact alone (A singular).
    pub kernel: usize,
    /// Rows with bounded multipliers (friction's tangential rows, [`BlockKind::Box`]).
    pub box_rows: usize,
    /// Unknowns of the contact body most slender against its interface ([`ContactBody`]; 0
    /// without normal rows).
    pub body_dofs: usize,
    /// The size of that body's interface where it touches first ([`first_touch`],
    /// [`ContactBody::interface`]: the normal rows touching it, or its own DOFs they touch when
    /// fewer).
    pub body_interface: usize,
}

impl Features {
    /// The features of `problem`.
    pub fn of(problem: &QpProblem) -> Self {
        Self::with_bodies(problem, &Components::of(&problem.stiffness))
    }

    /// The features of `problem` whose bodies (the components of A) are known already (those
    /// of its [`ResidualScales`](signorini_core::qp::ResidualScales)).
    pub fn with_bodies(problem: &QpProblem, bodies: &Components) -> Self {
        let body = ContactBody::most_slender_among(problem, bodies, &first_touch(problem));
        Self {
            dofs: problem.dofs(),
            rows: problem.rows(),
            touched: touched_dofs(&problem.constraints),
            kernel: problem.kernel.len(),
            box_rows: problem
                .blocks
                .iter()
                .filter(|b| b.kind() == BlockKind::Box)
                .map(|b| b.rows())
                .sum(),
            body_dofs: body.map_or(0, |b| b.dofs),
            body_interface: body.map_or(0, |b| b.interface),
        }
    }

    /// The interface's length against the body it runs along (see [`LONG_INTERFACE`]): the
    /// interface of the most slender contact body where it touches first ([`first_touch`]) over
    /// the square root of that body's unknowns ([`ContactBody::slenderness`]).  A thick foundation under a thin strip does
    /// not dilute it: the strip's own unknowns count, not the model's.
    pub fn length_ratio(&self) -> f64 {
        ContactBody {
            dofs: self.body_dofs,
            interface: self.body_interface,
        }
        .slenderness()
    }
}

/// The chain for a problem and the reason for its order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Plan {
    /// Backends to try, in order.
    pub chain: Vec<BackendKind>,
    /// Why, in one sentence.
    pub reason: String,
}

/// Whether the build runs `kind` inside the chain: compiled in and listed in
/// [`BackendKind::ALL`] (so pdas joins the chain the moment it is added there).
fn ready(kind: BackendKind) -> bool {
    kind.available() && BackendKind::ALL.contains(&kind)
}

/// The rule (see the module docs).
pub fn plan(f: &Features) -> Plan {
    let ratio = f.length_ratio();
    let long = ratio > LONG_INTERFACE;
    let large = large_dual(f);
    let (chain, why) = if f.box_rows > 0 && (long || large) {
        (
            &FRICTION_LONG_CHAIN[..],
            format!(
                "{} box rows (friction) on a long interface or a large dual (ℓ = {ratio:.2})",
                f.box_rows
            ),
        )
    } else if f.box_rows > 0 && f.kernel > 0 {
        (
            &FRICTION_FLOATING_CHAIN[..],
            format!(
                "{} box rows (friction) on a short interface (ℓ = {ratio:.2}) of bodies held by contact alone",
                f.box_rows
            ),
        )
    } else if f.box_rows > 0 {
        (
            &FRICTION_SHORT_CHAIN[..],
            format!(
                "{} box rows (friction) on a short interface (ℓ = {ratio:.2})",
                f.box_rows
            ),
        )
    } else if long {
        (
            &LONG_CHAIN[..],
            format!(
                "a long interface (ℓ = {ratio:.2} > {LONG_INTERFACE}): an ill-conditioned dual"
            ),
        )
    } else if large {
        (
            &LONG_CHAIN[..],
            format!(
                "a large dual (m > {SSN_MAX_ROWS} or touched DOFs > {SSN_MAX_TOUCHED}): no dense H"
            ),
        )
    } else {
        (
            &SHORT_CHAIN[..],
            format!("a short interface (ℓ = {ratio:.2} ≤ {LONG_INTERFACE}): a small, well-conditioned dual"),
        )
    };
    let chain: Vec<BackendKind> = chain.iter().copied().filter(|k| ready(*k)).collect();
    let names: Vec<&str> = chain.iter().map(|k| k.name()).collect();
    let reason = format!(
        "n = {}, m = {}, {} DOFs touched, ℓ = interface {} (rows touching first) / √{} DOFs of the most slender contact body{}: {why}; chain {}",
        f.dofs,
        f.rows,
        f.touched,
        f.body_interface,
        f.body_dofs,
        if f.kernel > 0 {
            format!(", {} rigid mode(s) held by contact", f.kernel)
        } else {
            String::new()
        },
        names.join(" → ")
    );
    Plan { chain, reason }
}

/// A chain given by name (`--chain`) for the memory guard: each member with whether its memory
/// refusal ends the chain (a sparse primal member's does, see [`dense_dual`]).
pub fn given_chain(kinds: &[BackendKind]) -> Vec<(BackendKind, bool)> {
    kinds.iter().map(|k| (*k, !dense_dual(k.name()))).collect()
}

/// What the rule runs on `problem`, in order, for the memory guard: with Coulomb rows
/// (`coulomb`) solved by a backend's own method ([`coulomb_by_newton`]), [`COULOMB_CHAIN`]
/// first — a refusal there falls back to the fixed point, so it ends nothing (`false`) — then
/// [`plan`]'s chain, where a sparse member's memory refusal ends the chain (`true`, see
/// [`dense_dual`]).
pub fn chain_for(problem: &QpProblem, coulomb: bool) -> Vec<(BackendKind, bool)> {
    let features = Features::of(problem);
    let mut chain = Vec::new();
    if coulomb && coulomb_by_newton(&features) {
        chain.extend(
            coulomb_plan(&features)
                .chain
                .into_iter()
                .map(|k| (k, false)),
        );
    }
    chain.extend(
        plan(&features)
            .chain
            .into_iter()
            .map(|k| (k, !dense_dual(k.name()))),
    );
    chain
}

/// A backend of the chain by name, with the chain's own limits ([`OSQP_MAX_ITER`]).
fn chain_backend(kind: BackendKind) -> Result<Box<dyn QpBackend>, super::BackendError> {
    #[cfg(feature = "osqp")]
    if kind == BackendKind::Osqp {
        return Ok(Box::new(signorini_osqp::OsqpBackend::new(
            signorini_osqp::OsqpSettings {
                max_iter: OSQP_MAX_ITER,
                ..signorini_osqp::OsqpSettings::default()
            },
        )));
    }
    make_backend(kind)
}

/// One backend's run inside the chain.
#[derive(Debug, Clone)]
pub struct Attempt {
    /// Backend name.
    pub backend: String,
    /// Core-checked status (`None` when the backend returned an error).
    pub status: Option<QpStatus>,
    /// The backend's own verdict.
    pub backend_status: Option<QpStatus>,
    /// Its iterations.
    pub iterations: usize,
    /// Wall-clock time of the attempt.
    pub solve_time: Duration,
    /// The backend's note, or the error.
    pub message: Option<String>,
}

impl Attempt {
    /// The attempt as a `result.json` entry.
    pub fn report(&self) -> AttemptReport {
        AttemptReport {
            backend: self.backend.clone(),
            status: self
                .status
                .map_or_else(|| "error".to_string(), |s| s.as_str().to_string()),
            backend_status: self.backend_status.map(|s| s.as_str().to_string()),
            iterations: self.iterations,
            solve_s: self.solve_time.as_secs_f64(),
            message: self.message.clone(),
        }
    }

    /// One line for standard error.
    pub fn line(&self) -> String {
        format!(
            "auto: {:<14} {:<17} {:>6} it. {:>10.4} s{}",
            self.backend,
            self.status.map_or("error", |s| s.as_str()),
            self.iterations,
            self.solve_time.as_secs_f64(),
            self.message
                .as_deref()
                .map(|m| format!("  {m}"))
                .unwrap_or_default()
        )
    }
}

/// What the last chain did.
#[derive(Debug, Clone, Default)]
pub struct ChainRecord {
    /// Every attempt, in order.
    pub attempts: Vec<Attempt>,
    /// The backend whose answer was returned, if any.
    pub chosen: Option<String>,
    /// Why the chain had this order, and how it ended.
    pub reason: String,
}

impl ChainRecord {
    /// Adds the chain's fields (`attempts`, `chosen`, `reason`) to a `result.json` report.
    pub fn annotate(&self, report: &mut RunReport) {
        report.attempts = self.attempts.iter().map(Attempt::report).collect();
        report.chosen = self.chosen.clone();
        report.reason = Some(self.reason.clone());
    }
}

/// A backend of the chain: built by name from the rule, or given (tests, `--chain`).
enum Member {
    Kind(BackendKind),
    Given(Box<dyn QpBackend>),
}

/// The `auto` backend (see the module docs).
pub struct AutoBackend {
    given: Option<(Vec<Member>, String)>,
    fixed: bool,
    record: Option<ChainRecord>,
}

impl Default for AutoBackend {
    /// The chain of [`plan`], chosen per problem.
    fn default() -> Self {
        Self {
            given: None,
            fixed: false,
            record: None,
        }
    }
}

impl std::fmt::Debug for AutoBackend {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AutoBackend")
            .field("record", &self.record)
            .finish_non_exhaustive()
    }
}

impl AutoBackend {
    /// A fixed chain of named backends instead of the rule (`--chain`); `reason` is reported.
    pub fn with_kinds(kinds: Vec<BackendKind>, reason: impl Into<String>) -> Self {
        Self {
            given: Some((kinds.into_iter().map(Member::Kind).collect(), reason.into())),
            fixed: true,
            record: None,
        }
    }

    /// A fixed chain of backends built by the caller (e.g. with settings of their own).
    pub fn with_backends(backends: Vec<Box<dyn QpBackend>>, reason: impl Into<String>) -> Self {
        Self {
            given: Some((
                backends.into_iter().map(Member::Given).collect(),
                reason.into(),
            )),
            fixed: true,
            record: None,
        }
    }

    /// What the last solve ran, `None` before the first.
    pub fn record(&self) -> Option<&ChainRecord> {
        self.record.as_ref()
    }
}

/// Whether a backend works on a dense m × m dual (so that its `TooLarge` says nothing about the
/// sparse primal methods).
fn dense_dual(name: &str) -> bool {
    name.starts_with("dual-") || name.ends_with("/dual")
}

impl QpBackend for AutoBackend {
    fn name(&self) -> &'static str {
        NAME
    }

    /// Every kind: the rule's chains for box rows hold only backends that solve them.
    fn supports(&self, _kind: BlockKind) -> bool {
        true
    }

    fn solve_valid(
        &mut self,
        problem: &QpProblem,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        self.solve_chain(problem, None, options)
    }

    /// A given chain: when a member has its own Coulomb method.  The rule: on long interfaces
    /// or large duals ([`coulomb_by_newton`]) when a member of [`COULOMB_CHAIN`] has one.
    fn solves_coulomb(&self, problem: &QpProblem) -> bool {
        let solves = |kind: &BackendKind| {
            ready(*kind) && chain_backend(*kind).is_ok_and(|b| b.solves_coulomb(problem))
        };
        match &self.given {
            Some((members, _)) => members.iter().any(|m| match m {
                Member::Kind(kind) => solves(kind),
                Member::Given(backend) => backend.solves_coulomb(problem),
            }),
            None => coulomb_by_newton(&Features::of(problem)) && COULOMB_CHAIN.iter().any(solves),
        }
    }

    /// The members with their own Coulomb method, in order, judged by Coulomb's residuals.
    fn solve_coulomb_valid(
        &mut self,
        problem: &QpProblem,
        coulomb: &CoulombRows,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        self.solve_chain(problem, Some(coulomb), options)
    }
}

impl AutoBackend {
    /// Runs the chain (given, or the rule's: [`plan`], or [`COULOMB_CHAIN`] for `coulomb`) and
    /// records it.
    fn solve_chain(
        &mut self,
        problem: &QpProblem,
        coulomb: Option<&CoulombRows>,
        options: &SolveOptions,
    ) -> Result<QpSolution, QpError> {
        let start = Instant::now();
        // One pass for the chain: every member and every check use these scales.
        let scales = options.residual_scales(problem);
        let given = self.given.take();
        let (mut members, reason) = match given {
            Some(given) => given,
            None => {
                let features = Features::with_bodies(problem, &scales.bodies);
                let p = match coulomb {
                    Some(_) => coulomb_plan(&features),
                    None => plan(&features),
                };
                (p.chain.into_iter().map(Member::Kind).collect(), p.reason)
            }
        };
        let mut record = ChainRecord {
            attempts: Vec::new(),
            chosen: None,
            reason: reason.clone(),
        };
        let options = &SolveOptions {
            scales: Some(scales),
            ..options.clone()
        };
        let run = Run {
            problem,
            coulomb,
            options,
            start,
        };
        let outcome = run_chain(&mut members, &run, &mut record);
        // A given chain stays for the next solve (compare and sweep reuse a backend); the rule's
        // is chosen again per problem.
        if self.fixed {
            self.given = Some((members, reason));
        }
        let result = outcome.map(|mut solution| {
            solution.solve_time = start.elapsed();
            solution.message = Some(summary(&record, solution.message.take()));
            solution
        });
        self.record = Some(record);
        result
    }
}

/// Whether the rule solves Coulomb rows by a backend's own method (pdas's Newton): on long
/// interfaces or large duals, the problems of [`FRICTION_LONG_CHAIN`], and on bodies held by
/// contact alone ([`FRICTION_FLOATING_CHAIN`]: the Newton solves the floating block in one
/// solve's time, 0.7 ms where the fixed point through the chain takes 6.5 ms; where it does not
/// solve, the fixed point follows).  On other short interfaces the fixed point through
/// [`FRICTION_SHORT_CHAIN`] (dual-pgs on the small condensed dual, A factored once per Tresca
/// solve) is faster: on the Cattaneo cylinder (BENCHMARKS.md, "Friction") 13.5× the floor
/// against 18.7× for pdas's Newton.
pub fn coulomb_by_newton(f: &Features) -> bool {
    f.length_ratio() > LONG_INTERFACE || large_dual(f) || f.kernel > 0
}

/// A dual too large to form densely (m > [`SSN_MAX_ROWS`] or touched DOFs > [`SSN_MAX_TOUCHED`]).
fn large_dual(f: &Features) -> bool {
    f.rows > SSN_MAX_ROWS || f.touched > SSN_MAX_TOUCHED
}

/// The chain for Coulomb's own methods ([`COULOMB_CHAIN`]) and why.
pub fn coulomb_plan(f: &Features) -> Plan {
    let chain: Vec<BackendKind> = COULOMB_CHAIN
        .iter()
        .copied()
        .filter(|k| ready(*k))
        .collect();
    let names: Vec<&str> = chain.iter().map(|k| k.name()).collect();
    Plan {
        reason: format!(
            "n = {}, m = {}, {} box rows with Coulomb friction: a backend's own semismooth Newton (the fixed point over Tresca problems if it does not solve); chain {}",
            f.dofs,
            f.rows,
            f.box_rows,
            names.join(" → ")
        ),
        chain,
    }
}

/// One chain run's data: the problem, its Coulomb rows when solving Coulomb's conditions, the
/// options (with the problem's residual scales) and the start of the whole run.
struct Run<'a> {
    problem: &'a QpProblem,
    coulomb: Option<&'a CoulombRows>,
    options: &'a SolveOptions,
    start: Instant,
}

/// `dual-ssn inaccurate → clarabel solved; <chosen's note>`.
fn summary(record: &ChainRecord, note: Option<String>) -> String {
    let steps: Vec<String> = record
        .attempts
        .iter()
        .map(|a| format!("{} {}", a.backend, a.status.map_or("error", |s| s.as_str())))
        .collect();
    let mut text = format!("auto: {}", steps.join(" → "));
    if let Some(n) = note {
        text.push_str("; ");
        text.push_str(&n);
    }
    text
}

/// Runs `members` in order until one's answer is `solved` (see the module docs): each attempt
/// gets the time left of `options.time_limit`, and `record` gets every attempt and the choice.
fn run_chain(
    members: &mut [Member],
    run: &Run<'_>,
    record: &mut ChainRecord,
) -> Result<QpSolution, QpError> {
    let (problem, options, start) = (run.problem, run.options, run.start);
    let deadline = options.time_limit.map(|t| start + t);
    // The best answer so far (the last attempt that produced one) and the last error.
    let mut answer: Option<(QpSolution, String)> = None;
    let mut last_error: Option<QpError> = None;
    let count = members.len();
    for (index, member) in members.iter_mut().enumerate() {
        let Some(remaining) = time_left(deadline) else {
            record.reason.push_str(&format!(
                "; the time limit passed before attempt {} of {count}",
                index + 1
            ));
            if let Some((_, name)) = &answer {
                record.chosen = Some(name.clone());
            }
            return Ok(timed_out(problem, answer, start));
        };
        let attempt_options = SolveOptions {
            time_limit: remaining,
            ..options.clone()
        };
        let mut built;
        let backend: &mut dyn QpBackend = match member {
            Member::Given(b) => b.as_mut(),
            Member::Kind(kind) => match chain_backend(*kind) {
                Ok(b) => {
                    built = b;
                    built.as_mut()
                }
                Err(e) => {
                    record.attempts.push(Attempt {
                        backend: kind.name().to_string(),
                        status: None,
                        backend_status: None,
                        iterations: 0,
                        solve_time: Duration::ZERO,
                        message: Some(e.to_string()),
                    });
                    continue;
                }
            },
        };
        let name = backend.name().to_string();
        let t0 = Instant::now();
        let result = match run.coulomb {
            // In auto's own units: `QpBackend::solve` nondimensionalised the problem before
            // auto saw it (or found it in units of its data already), so a member's own
            // `solve` would only measure that again (`QpScaling::of`, a pass over A).
            None => backend.solve_in_given_units(problem, &attempt_options),
            Some(rows) if backend.solves_coulomb(problem) => {
                backend.solve_coulomb(problem, rows, &attempt_options)
            }
            // A given member without its own Coulomb method: the core's fixed point runs it.
            Some(_) => continue,
        };
        let took = t0.elapsed();
        let next = match result {
            Ok(solution) => {
                let attempt = (index, name, took);
                on_answer(run, solution, attempt, record, &mut answer)
            }
            Err(error) => on_error(error, &name, took, record, &mut last_error),
        };
        match next {
            Next::Chosen(solution) => return Ok(solution),
            Next::Stop => break,
            Next::Continue => {}
        }
    }
    conclude(answer, last_error, record)
}

/// What the chain does after an attempt.
enum Next {
    /// This answer is solved: return it.
    Chosen(QpSolution),
    /// Try the next member.
    Continue,
    /// End the chain (out of time, or out of memory for every later backend).
    Stop,
}

/// The time left before `deadline` (`Some(None)` without one); `None` once it has passed.
fn time_left(deadline: Option<Instant>) -> Option<Option<Duration>> {
    match deadline {
        Some(d) => match d.checked_duration_since(Instant::now()) {
            Some(r) if r > Duration::ZERO => Some(Some(r)),
            _ => None,
        },
        None => Some(None),
    }
}

/// Records attempt `(index, name, took)` that produced `solution`, judged by the core's check:
/// chosen when solved, else kept as the best `answer` so far (ending the chain at a time limit).
fn on_answer(
    run: &Run<'_>,
    solution: QpSolution,
    (index, name, took): (usize, String, Duration),
    record: &mut ChainRecord,
    answer: &mut Option<(QpSolution, String)>,
) -> Next {
    let problem = run.problem;
    let scales = run.options.residual_scales(problem);
    let residuals = match run.coulomb {
        // Coulomb's conditions: each Coulomb row bounded by μ max(0, λₙ) of the answer.
        Some(rows) => rows.residuals(problem, &scales, &solution.x, &solution.multipliers),
        None => kkt_residuals_with(problem, &scales, &solution.x, &solution.multipliers),
    };
    let status = checked_status(solution.status, &residuals, run.options.tol);
    record.attempts.push(Attempt {
        backend: name.clone(),
        status: Some(status),
        backend_status: Some(solution.status),
        iterations: solution.iterations,
        solve_time: took,
        message: solution.message.clone(),
    });
    if status == QpStatus::Solved {
        record.chosen = Some(name.clone());
        if index > 0 {
            record
                .reason
                .push_str(&format!("; {name} solved after fall-back"));
        }
        return Next::Chosen(solution);
    }
    let out_of_time = status == QpStatus::TimeLimit;
    *answer = Some((solution, name));
    if out_of_time {
        record
            .reason
            .push_str("; the time limit passed during the last attempt");
        return Next::Stop;
    }
    Next::Continue
}

/// Records attempt `name` that failed with `error` (kept as the `last_error`); a memory refusal
/// ends the chain unless the backend is a dense dual one.
fn on_error(
    error: QpError,
    name: &str,
    took: Duration,
    record: &mut ChainRecord,
    last_error: &mut Option<QpError>,
) -> Next {
    record.attempts.push(Attempt {
        backend: name.to_string(),
        status: None,
        backend_status: None,
        iterations: 0,
        solve_time: took,
        message: Some(error.to_string()),
    });
    let ends = matches!(error, QpError::TooLarge { .. }) && !dense_dual(name);
    *last_error = Some(error);
    if ends {
        record.reason.push_str(&format!(
            "; {name} was refused for lack of memory and every later backend factors A too: chain ended"
        ));
        return Next::Stop;
    }
    Next::Continue
}

/// The chain's result when no attempt was solved: the last answer, else the last error.
fn conclude(
    answer: Option<(QpSolution, String)>,
    last_error: Option<QpError>,
    record: &mut ChainRecord,
) -> Result<QpSolution, QpError> {
    match answer {
        Some((solution, name)) => {
            record.reason.push_str(&format!(
                "; no backend solved it: the answer written is {name}'s"
            ));
            record.chosen = Some(name);
            Ok(solution)
        }
        None => {
            record.reason.push_str("; no backend produced an answer");
            Err(last_error.unwrap_or_else(|| QpError::Unavailable {
                backend: NAME,
                reason: "the chain holds no backend this build can run".into(),
            }))
        }
    }
}

/// The chain ran out of time between attempts: the last answer (if any) with status
/// `time-limit`, else an empty one.
fn timed_out(
    problem: &QpProblem,
    answer: Option<(QpSolution, String)>,
    start: Instant,
) -> QpSolution {
    match answer {
        Some((mut solution, name)) => {
            solution.status = QpStatus::TimeLimit;
            solution.message = Some(format!(
                "the time limit passed; the answer is {name}'s ({})",
                solution.message.as_deref().unwrap_or("no message")
            ));
            solution
        }
        None => QpSolution {
            x: vec![0.0; problem.dofs()],
            multipliers: vec![0.0; problem.rows()],
            status: QpStatus::TimeLimit,
            iterations: 0,
            solve_time: start.elapsed(),
            message: Some("the time limit passed before any backend ran".into()),
        },
    }
}
