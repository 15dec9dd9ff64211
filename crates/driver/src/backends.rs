//! The QP backends the driver can run, picked by name at run time.

use std::ffi::OsStr;
use std::fmt;
use std::marker::PhantomData;
use std::str::FromStr;

use clap::builder::{EnumValueParser, PossibleValue, TypedValueParser};
use clap::error::{ContextKind, ContextValue, ErrorKind};
use clap::ValueEnum;
use signorini_core::qp::{CondensedDual, QpBackend};

/// A backend the command line can name.  Parsed by clap as a [`ValueEnum`] through
/// [`ChoiceParser`] (help lists the names, a typo gets a suggestion); the first line of each
/// variant's doc is its help text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, ValueEnum)]
pub enum BackendKind {
    /// The fastest backend likely to succeed, with fall-backs (see [`crate::auto`]).
    #[value(
        name = "auto",
        help = "the fastest backend likely to succeed, with fall-backs"
    )]
    Auto,
    /// Interior point (clarabel).
    #[value(name = "clarabel", help = "interior point (clarabel)")]
    Clarabel,
    /// ADMM (OSQP), when built with the `osqp` feature.
    #[value(name = "osqp", help = "ADMM (OSQP; builds with the osqp feature)")]
    Osqp,
    /// Projected Gauss–Seidel on the condensed dual.
    #[value(
        name = "dual-pgs",
        help = "projected Gauss–Seidel on the condensed dual"
    )]
    DualPgs,
    /// Uzawa / projected gradient on the dual.
    #[value(
        name = "dual-uzawa",
        help = "Uzawa / projected gradient on the condensed dual"
    )]
    DualUzawa,
    /// Primal–dual active set (semismooth Newton) on the condensed dual.
    #[value(
        name = "dual-ssn",
        help = "primal–dual active set (semismooth Newton) on the condensed dual"
    )]
    DualSsn,
    /// Primal–dual active set on the sparse primal KKT system.
    #[value(
        name = "pdas",
        help = "primal–dual active set on the sparse primal KKT system"
    )]
    Pdas,
    /// clarabel on the condensed dual (`"clarabel/dual"`, see
    /// [`CondensedDual`]).
    #[value(name = "clarabel/dual", help = "clarabel on the condensed dual")]
    ClarabelDual,
    /// OSQP on the condensed dual (`"osqp/dual"`).
    #[value(name = "osqp/dual", help = "OSQP on the condensed dual")]
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
    /// Every name the command line accepts besides [`BackendKind::ALL`]: the chain and the
    /// condensed-dual forms (not in `ALL`, which lists each algorithm once, in its own form).
    pub const EXTRA: [BackendKind; 3] = [
        BackendKind::Auto,
        BackendKind::ClarabelDual,
        BackendKind::OsqpDual,
    ];

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

impl BackendKind {
    /// Every backend, in the order reports list them.
    pub const ALL: [BackendKind; 6] = [
        BackendKind::Clarabel,
        BackendKind::Osqp,
        BackendKind::DualPgs,
        BackendKind::DualUzawa,
        BackendKind::Pdas,
        BackendKind::DualSsn,
    ];

    /// Every name the command line accepts besides [`BackendKind::ALL`]: the chain and the
    /// condensed-dual forms (not in `ALL`, which lists each algorithm once, in its own form).
    pub const EXTRA: [BackendKind; 3] = [
        BackendKind::Auto,
        BackendKind::ClarabelDual,
        BackendKind::OsqpDual,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            BackendKind::Clarabel => "clarabel",
            BackendKind::Osqp => "osqp",
            BackendKind::DualPgs => "dual-pgs",
            BackendKind::DualUzawa => "dual-uzawa",
            BackendKind::DualSsn => "dual-ssn",
            BackendKind::Pdas => "pdas",
            BackendKind::ClarabelDual => "clarabel/dual",
            BackendKind::OsqpDual => "osqp/dual",
            BackendKind::Auto => "auto",
        }
    }

    /// Whether this build contains the backend.
    pub fn available(self) -> bool {
        match self {
            BackendKind::Osqp | BackendKind::OsqpDual => cfg!(feature = "osqp"),
            _ => true,
        }
    }

    /// The formulation the backend works on (`auto` counts as primal: it picks its own).
    pub fn form(self) -> Form {
        match self {
            BackendKind::ClarabelDual
            | BackendKind::OsqpDual
            | BackendKind::DualPgs
            | BackendKind::DualUzawa
            | BackendKind::DualSsn => Form::Dual,
            _ => Form::Primal,
        }
    }

    /// Whether `--form` can choose this backend's formulation: clarabel and osqp run on either.
    pub fn has_forms(self) -> bool {
        matches!(
            self,
            BackendKind::Clarabel
                | BackendKind::Osqp
                | BackendKind::ClarabelDual
                | BackendKind::OsqpDual
        )
    }

    /// The same algorithm on `form`: clarabel and osqp take either; every other backend only
    /// its own (`dual-*` work on the dual, `pdas` and `auto` on the primal), and asking for the
    /// other is [`BackendError::NoForm`].
    pub fn with_form(self, form: Form) -> Result<BackendKind, BackendError> {
        match (self, form) {
            (BackendKind::Clarabel | BackendKind::ClarabelDual, Form::Primal) => {
                Ok(BackendKind::Clarabel)
            }
            (BackendKind::Clarabel | BackendKind::ClarabelDual, Form::Dual) => {
                Ok(BackendKind::ClarabelDual)
            }
            (BackendKind::Osqp | BackendKind::OsqpDual, Form::Primal) => Ok(BackendKind::Osqp),
            (BackendKind::Osqp | BackendKind::OsqpDual, Form::Dual) => Ok(BackendKind::OsqpDual),
            (kind, form) if kind.form() == form => Ok(kind),
            (kind, form) => Err(BackendError::NoForm {
                backend: kind.name(),
                form: form.name(),
            }),
        }
    }
}

impl fmt::Display for BackendKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A backend name that is not known or not compiled in.
#[derive(Debug, thiserror::Error)]
pub enum BackendError {
    /// Unknown name.
    #[error(
        "unknown backend \"{0}\" (known: auto, clarabel, osqp, dual-pgs, dual-uzawa, pdas, dual-ssn, clarabel/dual, osqp/dual)"
    )]
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

    /// A name of [`BackendKind::ALL`] or [`BackendKind::EXTRA`], optionally with its form as
    /// `name/primal` or `name/dual` (`clarabel/primal` is `clarabel`).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let s = s.trim();
        let known = |name: &str| {
            BackendKind::ALL
                .into_iter()
                .chain(BackendKind::EXTRA)
                .find(|k| k.name() == name)
        };
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
    match kind {
        BackendKind::Clarabel => Ok(Box::new(signorini_clarabel::ClarabelBackend::default())),
        #[cfg(feature = "osqp")]
        BackendKind::Osqp => Ok(Box::new(signorini_osqp::OsqpBackend::default())),
        #[cfg(not(feature = "osqp"))]
        BackendKind::Osqp => Err(BackendError::NotCompiled("osqp")),
        BackendKind::DualPgs => Ok(Box::new(signorini_dual::DualBackend::pgs(
            Default::default(),
        ))),
        BackendKind::DualUzawa => Ok(Box::new(signorini_dual::DualBackend::uzawa(
            Default::default(),
        ))),
        BackendKind::DualSsn => Ok(Box::new(signorini_dual::DualBackend::active_set(
            Default::default(),
        ))),
        BackendKind::Pdas => Ok(Box::new(signorini_pdas::PdasBackend::default())),
        BackendKind::ClarabelDual => Ok(Box::new(CondensedDual::new(
            signorini_clarabel::ClarabelBackend::default(),
            "clarabel/dual",
        ))),
        #[cfg(feature = "osqp")]
        BackendKind::OsqpDual => Ok(Box::new(CondensedDual::new(
            signorini_osqp::OsqpBackend::default(),
            "osqp/dual",
        ))),
        #[cfg(not(feature = "osqp"))]
        BackendKind::OsqpDual => Err(BackendError::NotCompiled("osqp")),
        BackendKind::Auto => Ok(Box::new(crate::auto::AutoBackend::default())),
    }
}

#[cfg(test)]
mod names_tests {
    use super::*;

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
