//! The QP backends the driver can run, picked by name at run time: the registry, and `auto`
//! (the automatic choice among them) beside it.

pub mod auto;
pub mod guard;

use std::ffi::OsStr;
use std::fmt;
use std::marker::PhantomData;
use std::str::FromStr;

use clap::builder::{EnumValueParser, PossibleValue, TypedValueParser};
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::ValueEnum;
use signorini_core::qp::{CondensedDual, QpBackend};

/// A backend the command line can name: one row of [`REGISTRY`], which holds its name, help,
/// form and constructor.  Parsed by clap as a [`ValueEnum`] derived from the registry, through
/// [`ChoiceParser`] (help lists the names, a typo gets a suggestion).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BackendKind {
    /// The fastest backend likely to succeed, with fall-backs (see [`auto`]).
    Auto,
    /// Interior point (clarabel).
    Clarabel,
    /// ADMM (OSQP), when built with the `osqp` feature.
    Osqp,
    /// Projected Gauss–Seidel on the condensed dual.
    DualPgs,
    /// Uzawa / projected gradient on the dual.
    DualUzawa,
    /// Primal–dual active set (semismooth Newton) on the condensed dual.
    DualSsn,
    /// Primal–dual active set on the sparse primal KKT system.
    Pdas,
    /// clarabel on the condensed dual (`"clarabel/dual"`, see [`CondensedDual`]).
    ClarabelDual,
    /// OSQP on the condensed dual (`"osqp/dual"`).
    OsqpDual,
}

/// The formulation a backend runs on: the primal QP in x, or the condensed dual in λ.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, ValueEnum)]
pub enum Form {
    /// `min ½xᵀAx − fᵀx  s.t.  Bx ≤ g` (sparse, n unknowns).
    #[value(help = "in the displacements: min ½xᵀAx − fᵀx s.t. Bx ≤ g (sparse)")]
    Primal,
    /// `min ½λᵀHλ − dᵀλ  s.t.  λ ≥ 0`, H = B A⁻¹ Bᵀ dense (m unknowns).
    #[value(help = "in the contact forces: min ½λᵀHλ − dᵀλ s.t. λ ≥ 0, H = B A⁻¹ Bᵀ (dense)")]
    Dual,
}

impl Form {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Form::Primal => "primal",
            Form::Dual => "dual",
        }
    }
}

impl FromStr for Form {
    type Err = BackendError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "primal" => Ok(Form::Primal),
            "dual" => Ok(Form::Dual),
            other => Err(BackendError::UnknownForm(other.to_string())),
        }
    }
}

/// What the driver knows of one backend name: the one place a backend is registered (after
/// clarabel's list of direct solvers, `kktsolvers/direct/quasidef/ldlsolvers/config.rs`: one
/// table, the automatic choice beside it).
#[derive(Debug, Clone, Copy)]
pub struct Entry {
    /// The variant.
    pub kind: BackendKind,
    /// The command-line name.
    pub name: &'static str,
    /// One line of help.
    pub help: &'static str,
    /// The formulation it runs on (`auto` counts as primal: it picks its own per attempt).
    pub form: Form,
    /// An algorithm in its own form: listed once in [`BackendKind::ALL`] (not `auto`, not the
    /// condensed-dual forms of clarabel and osqp).
    pub algorithm: bool,
    /// The same algorithm on the other formulation, when it has one (clarabel and osqp run on
    /// either; `--form` chooses).
    pub other_form: Option<BackendKind>,
    /// Run by `compare` and `sweep` when `--backends` is not given.
    pub compare_default: bool,
    /// In this build.
    pub available: bool,
    /// Creates it with its default settings.
    pub make: fn() -> Result<Box<dyn QpBackend>, BackendError>,
    /// Its own part of a run's peak memory (its factor, its working arrays, its copies), for
    /// the memory guard and `check` ([`crate::guard`]): every backend states its own.
    pub need: fn(&guard::RunShape<'_>) -> Result<guard::Part, signorini_core::qp::QpError>,
}

/// Every backend, in the order reports list them: the algorithms ([`BackendKind::ALL`]) first,
/// then `auto` and the condensed-dual forms.
pub const REGISTRY: [Entry; 9] = [
    Entry {
        kind: BackendKind::Clarabel,
        name: "clarabel",
        help: "interior point (clarabel)",
        form: Form::Primal,
        algorithm: true,
        other_form: Some(BackendKind::ClarabelDual),
        compare_default: true,
        available: true,
        make: make_clarabel,
        need: guard::clarabel,
    },
    Entry {
        kind: BackendKind::Osqp,
        name: "osqp",
        help: "ADMM (OSQP; builds with the osqp feature)",
        form: Form::Primal,
        algorithm: true,
        other_form: Some(BackendKind::OsqpDual),
        compare_default: true,
        available: cfg!(feature = "osqp"),
        make: make_osqp,
        need: guard::osqp,
    },
    Entry {
        kind: BackendKind::DualPgs,
        name: "dual-pgs",
        help: "projected Gauss–Seidel on the condensed dual",
        form: Form::Dual,
        algorithm: true,
        other_form: None,
        compare_default: true,
        available: true,
        make: || {
            Ok(Box::new(signorini_dual::DualBackend::pgs(
                Default::default(),
            )))
        },
        need: guard::dual_pgs,
    },
    Entry {
        kind: BackendKind::DualUzawa,
        name: "dual-uzawa",
        help: "Uzawa / projected gradient on the condensed dual",
        form: Form::Dual,
        algorithm: true,
        other_form: None,
        compare_default: true,
        available: true,
        make: || {
            Ok(Box::new(signorini_dual::DualBackend::uzawa(
                Default::default(),
            )))
        },
        need: guard::dual_uzawa,
    },
    Entry {
        kind: BackendKind::Pdas,
        name: "pdas",
        help: "primal–dual active set on the sparse primal KKT system",
        form: Form::Primal,
        algorithm: true,
        other_form: None,
        compare_default: false,
        available: true,
        make: || Ok(Box::new(signorini_pdas::PdasBackend::default())),
        need: guard::pdas,
    },
    Entry {
        kind: BackendKind::DualSsn,
        name: "dual-ssn",
        help: "primal–dual active set (semismooth Newton) on the condensed dual",
        form: Form::Dual,
        algorithm: true,
        other_form: None,
        compare_default: false,
        available: true,
        make: || {
            Ok(Box::new(signorini_dual::DualBackend::active_set(
                Default::default(),
            )))
        },
        need: guard::dual_ssn,
    },
    Entry {
        kind: BackendKind::Auto,
        name: "auto",
        help: "the fastest backend likely to succeed, with fall-backs",
        form: Form::Primal,
        algorithm: false,
        other_form: None,
        compare_default: false,
        available: true,
        make: || Ok(Box::new(auto::AutoBackend::default())),
        need: guard::auto,
    },
    Entry {
        kind: BackendKind::ClarabelDual,
        name: "clarabel/dual",
        help: "clarabel on the condensed dual",
        form: Form::Dual,
        algorithm: false,
        other_form: Some(BackendKind::Clarabel),
        compare_default: false,
        available: true,
        make: || {
            Ok(Box::new(CondensedDual::new(
                signorini_clarabel::ClarabelBackend::default(),
                "clarabel/dual",
            )))
        },
        need: guard::condensed,
    },
    Entry {
        kind: BackendKind::OsqpDual,
        name: "osqp/dual",
        help: "OSQP on the condensed dual",
        form: Form::Dual,
        algorithm: false,
        other_form: Some(BackendKind::Osqp),
        compare_default: false,
        available: cfg!(feature = "osqp"),
        make: make_osqp_dual,
        need: guard::condensed,
    },
];

fn make_clarabel() -> Result<Box<dyn QpBackend>, BackendError> {
    Ok(Box::new(signorini_clarabel::ClarabelBackend::default()))
}

#[cfg(feature = "osqp")]
fn make_osqp() -> Result<Box<dyn QpBackend>, BackendError> {
    Ok(Box::new(signorini_osqp::OsqpBackend::default()))
}

#[cfg(not(feature = "osqp"))]
fn make_osqp() -> Result<Box<dyn QpBackend>, BackendError> {
    Err(BackendError::NotCompiled("osqp"))
}

#[cfg(feature = "osqp")]
fn make_osqp_dual() -> Result<Box<dyn QpBackend>, BackendError> {
    Ok(Box::new(CondensedDual::new(
        signorini_osqp::OsqpBackend::default(),
        "osqp/dual",
    )))
}

#[cfg(not(feature = "osqp"))]
fn make_osqp_dual() -> Result<Box<dyn QpBackend>, BackendError> {
    Err(BackendError::NotCompiled("osqp"))
}

/// A list derived from the registry.
#[derive(Clone, Copy)]
enum List {
    /// Rows with `algorithm`.
    Algorithms,
    /// Rows without.
    Extra,
    /// Rows with `compare_default`.
    CompareDefault,
    /// Every row.
    Every,
}

impl List {
    const fn keeps(self, e: &Entry) -> bool {
        match self {
            List::Algorithms => e.algorithm,
            List::Extra => !e.algorithm,
            List::CompareDefault => e.compare_default,
            List::Every => true,
        }
    }
}

/// The kinds of the registry's rows in `list`, in its order (N must be their count: checked at
/// compile time).
const fn pick<const N: usize>(list: List) -> [BackendKind; N] {
    let mut out = [BackendKind::Auto; N];
    let (mut i, mut n) = (0, 0);
    while i < REGISTRY.len() {
        if list.keeps(&REGISTRY[i]) {
            assert!(n < N, "more registry rows than N");
            out[n] = REGISTRY[i].kind;
            n += 1;
        }
        i += 1;
    }
    assert!(n == N, "fewer registry rows than N");
    out
}

impl BackendKind {
    /// Every algorithm, each once in its own form, in the order reports list them.
    pub const ALL: [BackendKind; 6] = pick(List::Algorithms);

    /// Every name the command line accepts besides [`BackendKind::ALL`]: the chain and the
    /// condensed-dual forms.
    pub const EXTRA: [BackendKind; 3] = pick(List::Extra);

    /// What `compare` and `sweep` run when `--backends` is not given (those not in this build
    /// left out by the caller).
    pub const COMPARE_DEFAULT: [BackendKind; 4] = pick(List::CompareDefault);

    /// Every backend, in the registry's order.
    const EVERY: [BackendKind; 9] = pick(List::Every);

    /// Its row of [`REGISTRY`].
    pub fn entry(self) -> &'static Entry {
        // Every variant has a row (`every_variant_is_registered_once` checks it): a missing one
        // is a programming error, not a reason to answer for another backend.
        REGISTRY
            .iter()
            .find(|e| e.kind == self)
            .unwrap_or_else(|| unreachable!("{self:?} has no row in REGISTRY"))
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// Whether this build contains the backend.
    pub fn available(self) -> bool {
        self.entry().available
    }

    /// The formulation the backend works on (`auto` counts as primal: it picks its own).
    pub fn form(self) -> Form {
        self.entry().form
    }

    /// Whether `--form` can choose this backend's formulation: clarabel and osqp run on either.
    pub fn has_forms(self) -> bool {
        self.entry().other_form.is_some()
    }

    /// The same algorithm on `form`: clarabel and osqp take either ([`Entry::other_form`]);
    /// every other backend only its own (`dual-*` work on the dual, `pdas` and `auto` on the
    /// primal), and asking for the other is [`BackendError::NoForm`].
    pub fn with_form(self, form: Form) -> Result<BackendKind, BackendError> {
        if self.form() == form {
            return Ok(self);
        }
        self.entry()
            .other_form
            .filter(|other| other.form() == form)
            .ok_or(BackendError::NoForm {
                backend: self.name(),
                form: form.name(),
            })
    }
}

impl ValueEnum for BackendKind {
    fn value_variants<'a>() -> &'a [Self] {
        // `auto` first (the default), then the registry's order.
        &Self::VALUE_ORDER
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.entry().help))
    }
}

impl BackendKind {
    /// The order `--help` lists the names in: `auto` (the default), then the algorithms, then
    /// the condensed-dual forms.
    const VALUE_ORDER: [BackendKind; 9] = {
        let mut out = [BackendKind::Auto; 9];
        let mut i = 0;
        let mut n = 1;
        while i < Self::EVERY.len() {
            if !matches!(Self::EVERY[i], BackendKind::Auto) {
                out[n] = Self::EVERY[i];
                n += 1;
            }
            i += 1;
        }
        out
    };
}

impl fmt::Display for BackendKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Every name the command line accepts, comma-separated, for error messages.
fn known_names() -> String {
    BackendKind::VALUE_ORDER
        .iter()
        .map(|k| k.name())
        .collect::<Vec<_>>()
        .join(", ")
}

/// A backend name that is not known or not compiled in.
#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    /// Unknown name.
    #[error("unknown backend \"{0}\" (known: {names})", names = known_names())]
    Unknown(String),
    /// Unknown formulation.
    #[error("unknown form \"{0}\" (known: primal, dual)")]
    UnknownForm(String),
    /// The backend does not run on the requested formulation.
    #[error("backend \"{backend}\" has no {form} form (only clarabel and osqp run on both; dual-* work on the dual, pdas and auto on the primal)")]
    NoForm {
        /// Backend name.
        backend: &'static str,
        /// The form asked for.
        form: &'static str,
    },
    /// Known but not in this build.
    #[error("backend \"{0}\" is not compiled in; rebuild with `--features {0}`")]
    NotCompiled(&'static str),
}

impl FromStr for BackendKind {
    type Err = BackendError;

    /// A name of [`REGISTRY`], optionally with its form as `name/primal` or `name/dual`
    /// (`clarabel/primal` is `clarabel`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        let known = |name: &str| REGISTRY.iter().find(|e| e.name == name).map(|e| e.kind);
        if let Some(kind) = known(s) {
            return Ok(kind);
        }
        match s.rsplit_once('/') {
            Some((name, form)) => {
                let kind = known(name).ok_or_else(|| BackendError::Unknown(s.to_string()))?;
                kind.with_form(form.parse()?)
            }
            None => Err(BackendError::Unknown(s.to_string())),
        }
    }
}

/// Creates the backend with its default settings.
pub fn make_backend(kind: BackendKind) -> Result<Box<dyn QpBackend>, BackendError> {
    (kind.entry().make)()
}

#[cfg(test)]
mod names_tests {
    use super::*;

    /// Every variant has exactly one row of the registry, and the lists derived from it
    /// partition it.
    #[test]
    fn every_variant_is_registered_once() {
        for kind in BackendKind::EVERY {
            let rows = REGISTRY.iter().filter(|e| e.kind == kind).count();
            assert_eq!(rows, 1, "{kind:?}");
            assert_eq!(kind.entry().kind, kind);
            assert_eq!(kind.name().parse::<BackendKind>().ok(), Some(kind));
            if let Some(other) = kind.entry().other_form {
                assert_eq!(other.entry().other_form, Some(kind), "{kind:?}");
                assert_ne!(other.form(), kind.form(), "{kind:?}");
            }
        }
        let mut all: Vec<BackendKind> = BackendKind::ALL.into_iter().collect();
        all.extend(BackendKind::EXTRA);
        assert_eq!(all.len(), REGISTRY.len());
        assert_eq!(BackendKind::value_variants().len(), REGISTRY.len());
    }

    /// The "known" list of the unknown-backend message names every backend the parser accepts
    /// (pdas was missing from it when it joined `ALL`).
    #[test]
    fn the_unknown_backend_message_lists_every_name() {
        let message = BackendError::Unknown("x".into()).to_string();
        for kind in BackendKind::ALL.iter().chain(BackendKind::EXTRA.iter()) {
            assert!(
                message.contains(kind.name()),
                "{} missing in {message}",
                kind.name()
            );
        }
    }
}

/// clap's parser of a backend or form name: surrounding spaces are ignored (`--backends "a, b"`),
/// the [`ValueEnum`] names are matched first, then every longer spelling [`FromStr`] accepts
/// (`clarabel/primal`, `dual-pgs/dual`); an unknown name is refused with the [`BackendError`]
/// message, which names every valid one, and clap's suggestion of the closest.  Help lists the
/// [`ValueEnum`] names.
#[derive(Debug)]
pub struct ChoiceParser<E>(PhantomData<E>);

impl<E> ChoiceParser<E> {
    /// The parser.
    pub fn new() -> Self {
        ChoiceParser(PhantomData)
    }
}

impl<E> Default for ChoiceParser<E> {
    fn default() -> Self {
        Self::new()
    }
}

impl<E> Clone for ChoiceParser<E> {
    fn clone(&self) -> Self {
        Self::new()
    }
}

impl<E> TypedValueParser for ChoiceParser<E>
where
    E: ValueEnum + FromStr<Err = BackendError> + Clone + Send + Sync + 'static,
{
    type Value = E;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<E, clap::Error> {
        let Some(text) = value.to_str() else {
            return Err(clap::Error::new(ErrorKind::InvalidUtf8).with_cmd(cmd));
        };
        let text = text.trim();
        let enum_parser = EnumValueParser::<E>::new();
        let clap_error = match enum_parser.parse_ref(cmd, arg, OsStr::new(text)) {
            Ok(v) => return Ok(v),
            Err(e) => e,
        };
        let error = match text.parse::<E>() {
            Ok(v) => return Ok(v),
            Err(e) => e,
        };
        let kind = match error {
            BackendError::Unknown(_) | BackendError::UnknownForm(_) => ErrorKind::InvalidValue,
            _ => ErrorKind::ValueValidation,
        };
        let tip = match clap_error.get(ContextKind::SuggestedValue) {
            Some(ContextValue::String(s)) if kind == ErrorKind::InvalidValue => {
                format!("\n\n  tip: a similar value exists: '{s}'")
            }
            _ => String::new(),
        };
        let place = arg.map_or(String::new(), |a| format!(" (in --{})", a.get_id()));
        Err(clap::Error::raw(kind, format!("{error}{place}{tip}\n")).with_cmd(cmd))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(
            E::value_variants()
                .iter()
                .filter_map(ValueEnum::to_possible_value),
        ))
    }
}

/// clap's parser of a choice whose names and parsing function live elsewhere (the study's
/// formulations, mesh kinds and elements, whose types are not clap's): help lists `names`, an
/// unknown name is refused with `parse`'s message and clap's suggestion of the closest name.
#[derive(Clone)]
pub struct NamedParser<T> {
    names: &'static [&'static str],
    parse: fn(&str) -> Result<T, String>,
}

impl<T> NamedParser<T> {
    /// The parser of `names` by `parse`.
    pub fn new(names: &'static [&'static str], parse: fn(&str) -> Result<T, String>) -> Self {
        NamedParser { names, parse }
    }
}

impl<T: Clone + Send + Sync + 'static> TypedValueParser for NamedParser<T> {
    type Value = T;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        let Some(text) = value.to_str() else {
            return Err(clap::Error::new(ErrorKind::InvalidUtf8).with_cmd(cmd));
        };
        let message = match (self.parse)(text) {
            Ok(v) => return Ok(v),
            Err(m) => m,
        };
        let listed = clap::builder::PossibleValuesParser::new(self.names.iter().copied());
        let tip = match listed.parse_ref(cmd, arg, OsStr::new(text.trim())) {
            Err(e) => match e.get(ContextKind::SuggestedValue) {
                Some(ContextValue::String(s)) => {
                    format!("\n\n  tip: a similar value exists: '{s}'")
                }
                _ => String::new(),
            },
            Ok(_) => String::new(),
        };
        let place = arg.map_or(String::new(), |a| format!(" (in --{})", a.get_id()));
        Err(
            clap::Error::raw(ErrorKind::InvalidValue, format!("{message}{place}{tip}\n"))
                .with_cmd(cmd),
        )
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.names.iter().map(|n| PossibleValue::new(*n))))
    }
}
