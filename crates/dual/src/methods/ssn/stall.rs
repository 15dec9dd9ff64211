//! When a moving active set is given up: its checked steps (from
//! [`super::CHECK_MOVING_FROM`] on) either make progress or do not, and either look like the
//! local regime of a Newton method or like noise.
//!
//! * **Stalled** ([`STALL_STEPS`]): a step makes progress when fewer rows change than ever
//!   before, or the checked iterate's worst KKT residual falls below half its best.  A set
//!   that makes neither for [`STALL_STEPS`] steps is cycling through sets too many to remember,
//!   not heading for an answer: the iterate is given as it is, `inaccurate`, instead of dense
//!   factorisations to the iteration limit (a 1e-5-thin strip with m = 903: 100 000 steps,
//!   ~11 min).  The fixtures settle within 14 steps, each making progress.
//! * **Moving as if at random** ([`NOISE_STEPS`]): two sets drawn independently, with a₁ and
//!   a₂ of m rows active, differ in a₁(m − a₂)/m + a₂(m − a₁)/m rows on average.  A step whose
//!   set differs from the last in at least half that many rows ([`NOISE_FRACTION`]) bears no
//!   more relation to it than a random one: the set is decided by noise (the dense H's
//!   round-off, as on a body 10³⁰ times softer than its neighbours), and "fewer rows than
//!   ever" is then met by chance.  [`NOISE_STEPS`] such steps in a row give the iterate up.
//!   Measured with the checked steps' counts (`signorini compare SCENE --backends dual-ssn`):
//!   the 10⁻³⁰ sliver between two bodies (m = 4 857, `tests/ssn_round_off.rs`) changes 82–87 %
//!   of that count at every step (1 882–1 994 rows, residuals 4e12–8e13 without trend); the
//!   partial-contact strip, whose dense steps flip but are no noise (m = 2 001), at most 41 %
//!   (373 rows, from 648 active to 763); Hertz (m = 311) at most 27 %.

/// Steps without progress after which a set that still moves is given up.
pub(super) const STALL_STEPS: usize = 10;

/// Checked steps in a row that move the set as if at random after which it is given up.
pub(super) const NOISE_STEPS: usize = 3;

/// The fraction of the random-set distance from which a step's changes count as noise.
pub(super) const NOISE_FRACTION: f64 = 0.5;

/// The progress of a moving active set over its checked steps (see the module's docs).
#[derive(Debug, Default)]
pub(super) struct Stall {
    /// Fewest rows that changed in a step, the smallest worst residual, and the last step that
    /// improved either.
    best: Option<(usize, f64, usize)>,
    /// Checked steps in a row whose changes count as noise.
    noisy: usize,
}

impl Stall {
    /// Records step `iter`: `changes` rows changed, worst residual `worst`, from a set of
    /// `before` active rows to one of `after` of `rows` (`sizes`).  Says why to stop when it
    /// is time.
    pub(super) fn observe(
        &mut self,
        iter: usize,
        changes: usize,
        worst: f64,
        (before, after, rows): (usize, usize, usize),
    ) -> Option<String> {
        let unrelated = random_distance(before, after, rows);
        if unrelated > 0.0 && changes as f64 >= NOISE_FRACTION * unrelated {
            self.noisy += 1;
        } else {
            self.noisy = 0;
        }
        if self.noisy >= NOISE_STEPS {
            return Some(format!(
                "the active set moves as if at random: {changes} of {rows} rows changed this step (two unrelated sets of these sizes differ in {unrelated:.0}), and at least half as many as that in each of the last {NOISE_STEPS} steps; it is decided by noise (round-off), not converging"
            ));
        }
        let Some((fewest, lowest, at)) = self.best else {
            self.best = Some((changes, worst, iter));
            return None;
        };
        if changes < fewest || worst < 0.5 * lowest {
            self.best = Some((changes.min(fewest), worst.min(lowest), iter));
            return None;
        }
        (iter - at >= STALL_STEPS).then(|| {
            format!(
                "stalled: the active set still moves ({changes} rows this step, never fewer than {fewest}) and the residual has not halved its best ({lowest:.1e}) since step {at}"
            )
        })
    }
}

/// The mean number of rows in which two independent uniformly random sets of `a` and `b`
/// active rows out of `m` differ: a (m − b)/m + b (m − a)/m.
fn random_distance(a: usize, b: usize, m: usize) -> f64 {
    if m == 0 {
        return 0.0;
    }
    let (a, b, m) = (a as f64, b as f64, m as f64);
    (a * (m - b) + b * (m - a)) / m
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sizes that make the noise rule silent: every step changes far fewer rows than two
    /// random sets would (a = b = 500 of 10 000: 950 apart on average).
    const QUIET: (usize, usize, usize) = (500, 500, 10_000);

    #[test]
    fn a_set_that_stops_improving_is_given_up_after_the_stall_steps() {
        // Steps 3, 4: progress (fewer changes, then a halved residual); from step 5 on neither
        // (more changes, a residual above half the best): given up at step 4 + STALL_STEPS.
        let mut stall = Stall::default();
        assert_eq!(stall.observe(3, 50, 1.0, QUIET), None);
        assert_eq!(stall.observe(4, 40, 0.4, QUIET), None);
        for iter in 5..4 + STALL_STEPS {
            assert_eq!(stall.observe(iter, 45, 0.3, QUIET), None, "step {iter}");
        }
        let why = stall.observe(4 + STALL_STEPS, 45, 0.3, QUIET).unwrap();
        assert!(why.contains("since step 4"), "{why}");
    }

    #[test]
    fn a_set_that_keeps_improving_is_never_given_up() {
        // Alternating progress: fewer changes, then a halved residual, for far longer than the
        // stall window.
        let mut stall = Stall::default();
        let mut residual = 1.0;
        for iter in 3..200 {
            if iter % 2 == 0 {
                residual *= 0.4;
            }
            let changes = 1_000 - iter;
            let sizes = (5_000, 5_000, 10_000);
            assert_eq!(
                stall.observe(iter, changes, residual, sizes),
                None,
                "step {iter}"
            );
        }
    }

    #[test]
    fn two_random_sets_differ_in_the_expected_number_of_rows() {
        // Independent of the formula: count the differences of two sets drawn by a fixed
        // pseudo-random sequence (a linear congruential generator), 40 % and 70 % active.
        let m = 100_000;
        let mut state: u64 = 12_345;
        let mut draw = |p: f64| {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) < p
        };
        let first: Vec<bool> = (0..m).map(|_| draw(0.4)).collect();
        let second: Vec<bool> = (0..m).map(|_| draw(0.7)).collect();
        let count = |s: &[bool]| s.iter().filter(|a| **a).count();
        let differ = first.iter().zip(&second).filter(|(a, b)| a != b).count();
        let expected = random_distance(count(&first), count(&second), m);
        // The standard deviation of the count is below √m ≈ 316: allow 5 of them.
        assert!(
            (differ as f64 - expected).abs() < 5.0 * (m as f64).sqrt(),
            "{differ} vs {expected}"
        );
    }

    #[test]
    fn a_set_moving_on_round_off_is_given_up_at_its_third_checked_step() {
        // The 1e-30 sliver (tests/ssn_round_off.rs), steps 3–5 as measured: (active before,
        // after, changes, worst); m = 4 857.  Before this rule, "fewer changes than ever"
        // (1 994, 1 985, 1 914, …) counted as progress and it ran to the time limit.
        let steps = [
            (2_996, 3_040, 1_994, 3.80e13),
            (3_040, 3_017, 1_985, 7.85e13),
            (3_017, 2_975, 1_914, 4.31e12),
        ];
        let mut stall = Stall::default();
        for (k, &(before, after, changes, worst)) in steps.iter().enumerate() {
            let why = stall.observe(3 + k, changes, worst, (before, after, 4_857));
            assert_eq!(why.is_some(), k == 2, "step {}: {why:?}", 3 + k);
        }
    }

    #[test]
    fn flipping_but_local_sets_are_no_noise() {
        // The partial-contact strip's dense steps (m = 2 001), as measured: they flip, but each
        // set is close to the last (at most 41 % of the random distance).  (active rows,
        // changes) per step from step 3 on; the next set is the next step's.
        let steps = [
            (808, 221),
            (639, 127),
            (536, 114),
            (528, 76),
            (490, 82),
            (486, 72),
            (468, 108),
            (510, 68),
            (468, 53),
            (459, 114),
            (509, 143),
            (538, 244),
            (648, 373),
            (763, 272),
            (661, 147),
            (542, 103),
            (503, 67),
            (474, 92),
            (494, 113),
        ];
        let mut stall = Stall::default();
        for (k, pair) in steps.windows(2).enumerate() {
            let ((before, changes), (after, _)) = (pair[0], pair[1]);
            // A falling residual, so that only the noise rule could stop it.
            let worst = 1e8 * 0.4f64.powi(k as i32);
            let why = stall.observe(3 + k, changes, worst, (before, after, 2_001));
            assert_eq!(why, None, "step {}", 3 + k);
        }
    }
}
