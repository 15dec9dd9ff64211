//! A backend's answer.

use std::time::Duration;

use super::status::QpStatus;

/// A backend's answer: primal x, multipliers λ ≥ 0 (one per constraint row), and how it went.
#[derive(Debug, Clone)]
pub struct QpSolution {
    /// Primal solution x (length n).
    pub x: Vec<f64>,
    /// Multipliers λ of B x ≤ g (length m), the contact forces.
    pub multipliers: Vec<f64>,
    /// The backend's own verdict (to be passed through [`checked_status`](super::checked_status)).
    pub status: QpStatus,
    /// Iterations the backend took (its own notion of an iteration).
    pub iterations: usize,
    /// Wall-clock time inside the backend, including its setup and factorisations.
    pub solve_time: Duration,
    /// Free-form note from the backend (why it stopped, what it detected).
    pub message: Option<String>,
}

impl QpSolution {
    /// Never hand out NaN: an answer with a non-finite entry becomes the all-zero answer (same
    /// lengths) with `numerical-error`, its message kept behind "non-finite answer: ".
    pub fn finite_or_numerical_error(self) -> Self {
        if self
            .x
            .iter()
            .chain(&self.multipliers)
            .all(|v| v.is_finite())
        {
            return self;
        }
        Self {
            x: vec![0.0; self.x.len()],
            multipliers: vec![0.0; self.multipliers.len()],
            status: QpStatus::NumericalError,
            message: Some(format!(
                "non-finite answer: {}",
                self.message.as_deref().unwrap_or("")
            )),
            ..self
        }
    }
}
