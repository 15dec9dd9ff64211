//! When a moving active set's iterate is checked: the check (x(λ) by a sparse solve, then the KKT
//! residuals) guards against dense steps taken on round-off, so it is worth at most what those
//! steps cost.  Each dense step earns its cost in flops as credit; a check is made once the credit
//! covers the check's own cost, which it then spends.  So the checks never cost more than the
//! dense steps they guard (plus one check), whatever m and n are:
//!
//! * a long interface (m in the thousands: a dense factorisation of order |F| per step, far
//!   dearer than a solve) is checked after every step from [`super::CHECK_MOVING_FROM`] on, as
//!   the round-off test needs;
//! * a short interface on a large mesh (the seed at 117 k DOFs: m = 101, a dense step ~4·10⁴
//!   flops against ~2·10⁷ for a check's backward substitution) is not checked within the few
//!   steps its set needs to settle — those checks were a quarter of its solve time.
//!
//! Counts are flops, as in [`crate::factor`]'s rule for ordering the contact DOFs last.

/// The credit of the moving-set checks (see the module docs).
#[derive(Debug, Clone)]
pub(super) struct CheckBudget {
    /// Flops of one check.
    check: f64,
    /// Flops earned by the dense steps and not yet spent on checks.
    credit: f64,
}

impl CheckBudget {
    /// A budget for checks that cost `check` flops each, with no credit yet.
    pub(super) fn new(check: f64) -> Self {
        Self { check, credit: 0.0 }
    }

    /// The flops of one check: a backward substitution through L (`half_solve`: only the second
    /// half of a solve is needed when the contact DOFs are ordered last, else both halves) —
    /// two flops per stored entry and half — and the KKT residuals (a product with A and two
    /// with B: two flops per stored entry).
    pub(super) fn check_flops(
        factor_entries: usize,
        half_solve: bool,
        stiffness_entries: usize,
        constraint_entries: usize,
    ) -> f64 {
        let halves = if half_solve { 1.0 } else { 2.0 };
        2.0 * halves * factor_entries as f64
            + 2.0 * stiffness_entries as f64
            + 4.0 * constraint_entries as f64
    }

    /// The flops of one dense step on `active` rows with `kernel` rigid modes and m rows in all:
    /// the Cholesky (or LU) factorisation of order p = active + kernel, ~p³/3, and the two
    /// products with the m × m H (2m² each).
    pub(super) fn dense_step_flops(active: usize, kernel: usize, rows: usize) -> f64 {
        let p = (active + kernel) as f64;
        let m = rows as f64;
        p * p * p / 3.0 + 4.0 * m * m
    }

    /// Adds a dense step's flops to the credit.
    pub(super) fn earn(&mut self, flops: f64) {
        self.credit += flops;
    }

    /// Whether a check is paid for now; if so its cost is spent.
    pub(super) fn spend(&mut self) -> bool {
        if self.credit >= self.check {
            self.credit -= self.check;
            true
        } else {
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_check_is_made_once_the_steps_have_paid_for_it_and_not_before() {
        // Each step earns 1 000 flops, a check costs 2 500: checks after the 3rd and the 5th
        // step (credit 3 000 → 500, then 2 500 → 0), none after the 1st, 2nd, 4th.
        let mut budget = CheckBudget::new(2_500.0);
        let made: Vec<bool> = (0..5)
            .map(|_| {
                budget.earn(1_000.0);
                budget.spend()
            })
            .collect();
        assert_eq!(made, [false, false, true, false, true]);
    }

    #[test]
    fn a_long_interface_is_checked_every_step_and_the_seed_never_within_its_steps() {
        // The round-off scene of the driver's tests (4 857 rows, most of them active) on a
        // small mesh: a dense step far dearer than a check, so one check after every step.
        let check = CheckBudget::check_flops(200_000, false, 50_000, 20_000);
        let mut long = CheckBudget::new(check);
        for _ in 0..10 {
            long.earn(CheckBudget::dense_step_flops(4_000, 0, 4_857));
            assert!(long.spend());
        }
        // The seed at 117 572 DOFs: 1.09e7 stored entries of L, nnz(A) ≈ 1.6e6, m = 101 rows
        // (20 active), 8 steps: no check.
        let check = CheckBudget::check_flops(10_940_000, true, 1_600_000, 400);
        let mut seed = CheckBudget::new(check);
        for _ in 0..8 {
            seed.earn(CheckBudget::dense_step_flops(101, 0, 101));
            assert!(!seed.spend());
        }
    }
}
