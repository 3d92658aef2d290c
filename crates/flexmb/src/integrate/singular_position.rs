//! Passing a singular position: the conditioning of the constraint Jacobian at the step ends, and step ends
//! kept away from where it is lost.
//!
//! At a singular position of a mechanism (the IFToMM double four-bar, `models/benchmarks/double_four_bar.toml`,
//! whose links come into line at t ≈ 0.7141 s) the velocity Jacobian of the constraints in force, `B`, loses
//! rank: its smallest singular value `σ` falls to zero linearly in time and rises again. The motion passes
//! smoothly, but the step equations of the BDF and the generalized-α method hold the constraints at every
//! step end, and there their rounding comes back from the solve amplified: by the condition number
//! `κ = σ_rms / σ` in the positions and velocities (`σ_rms` the root-mean-square singular value), by `κ²` in
//! the multipliers. Measured on the four-bar at rtol = atol = 1e-12 before this guard: at t = 0.7116 s
//! (`σ` = 4.6e-3 of a largest 2.5) the Newton increments were 0.06 to 0.3 of the step's share of the
//! tolerance, mostly in the multipliers, against a Newton tolerance of 2.2e-3, at every step size; the BDF
//! stopped at t = 0.7141 s, generalized-α at 0.7104 s, each with its step size collapsing as the step ends
//! came nearer the position.
//!
//! Hence, for a mechanism with any number of constraint rows in force (`B Bᵀ` is sparse, and its Cholesky
//! factor costs in proportion to the joints: [`GramCholesky`]):
//!
//! - after every accepted step, `σ` is measured (inverse iteration on `B Bᵀ`, warm-started). While `κ`
//!   exceeds [`WATCH`] and grows, the zero of `σ` is extrapolated linearly from the last two step ends:
//!   the predicted singular time `t*`;
//! - a step that would end within half a step before `t*`, or past it, ends half a step before it, or,
//!   when that would leave less than a quarter of the step, as far past `t*` as it starts before it (at
//!   least half a step; at most 1.5 times the step asked for). The solution is smooth through the position:
//!   only the step *ends* are ill-posed, and so they are kept about half a step away from it, where `κ` is
//!   about `2 / (h dσ/dt)` (1,000 to 2,000 on the four-bar at rtol 1e-11 and 1e-12). The step after a moved
//!   one is the size the error control asked for;
//! - while `κ` exceeds [`WATCH`], an attempt's Newton increments at or below [`MARGIN`] times the rounding
//!   amplified by the `κ` predicted at its end (`10 ε κ` relative, the multipliers' increments divided by
//!   `κ`) have converged, and a local error estimate within that level, times the amplification of the
//!   predictor's extrapolation, passes and does not shorten the next step: no iteration and no shorter step
//!   resolves them finer, and shorter steps end nearer the position, where the rounding only grows. Such
//!   steps are counted with the largest `κ`, and the run warns at each passage where the steps there are
//!   resolved more coarsely than `rtol` ([`resolution`](SingularPassage::resolution)).
//!
//! Away from singular positions nothing changes: the guard reads the conditioning, and acts only while it
//! is poor. Its state is not kept in a checkpoint: a resumed run measures the approach afresh from its next
//! two steps.

use crate::data::Data;
use crate::linalg::GramCholesky;
use crate::model::Model;
use crate::stage::jacobian_entries;

/// The approach to a singular position is watched once `κ` at a step end exceeds this.
const WATCH: f64 = 20.0;
/// A step that would end within half a step before the predicted zero of `σ`, or past it, ends half a step
/// before it when that leaves at least a quarter of the step (`d > JUMP_REACH h`, `d` the distance to the
/// zero); nearer, it ends as far past the zero as it starts before it (at least half a step), at most
/// `2 JUMP_REACH h` long.
const JUMP_REACH: f64 = 0.75;
/// What an error estimate within the amplified rounding counts as (in shares of the tolerance): it passes,
/// and the next step may be longer.
const NOISE_ESTIMATE: f64 = 0.3;
/// A step end is moved, and the guard's tests are those of the amplified rounding, only where the steps
/// would be resolved to more than this fraction of `rtol` ([`resolution`](SingularPassage::resolution) at
/// the `κ` predicted there), or where the amplified rounding itself, `10 ε κ`, is more than this fraction
/// of what the step is held to, `rtol` times its share of the tolerance (error per unit step; see
/// [`matters`](SingularPassage::matters)).
const PLACE_FRACTION: f64 = 0.1;
/// Inverse iterations per measurement, from the last smallest singular vector plus [`MIX`] of a vector
/// with a share of every direction.
const INVERSE_ITERATIONS: usize = 3;
/// The share of every direction added to the last smallest singular vector before a measurement.
const MIX: f64 = 0.1;
/// The rounding of a constrained solution near a singular position is about `ROUND_OFF κ` of it: ten units
/// of rounding, as [`Tolerances`](super::Tolerances)'s round-off of an increment, times the condition
/// number.
const ROUND_OFF: f64 = 10.0 * f64::EPSILON;
/// A Newton increment within this many times the amplified rounding `10 ε κ` has converged: the four-bar's
/// stalled increments at rtol 1e-12 were 43 ε κ at κ = 240 (generalized-α), 60 to 300 ε κ at κ = 1,500 to
/// 2,200 (the BDF), rates about 1 at every step size from 4e-8 s down to 4e-14 s.
const MARGIN: f64 = 50.0;

/// The BDF's crossing of a predicted position in one step
/// ([`crossing_where_conditioned_badly`](SingularPassage::crossing_where_conditioned_badly)): from a step start within `CROSSING_REACH` steps
/// of the predicted position, where `κ` at the last step end or the one predicted at the asked end is at
/// least [`CROSSING_FROM`] and the step is held to less than [`CROSSING_SHARE`] of the tolerance.
const CROSSING_REACH: f64 = 3.0;
/// The condition number from which the BDF crosses a predicted position in one step: the double four-bar's
/// steps of about 1 ms pass within 1.2 ms of its positions, where `κ` is 1,000 (`σ/σ_rms` falls at
/// about 0.84 per s).
const CROSSING_FROM: f64 = 1000.0;
/// The BDF crosses a predicted position in one step only where the step is held to less than this share of
/// the tolerance (error per unit step over a long run): the crossing's estimate passes within the rounding
/// amplified at its ends, and where the share is larger that lets its truncation through (see
/// [`crossing_where_conditioned_badly`](SingularPassage::crossing_where_conditioned_badly)).
const CROSSING_SHARE: f64 = 0.05;
/// Crossings of a predicted position from one step start that may fail before the guard stops crossing
/// from there. After a failed crossing the next attempt is placed before the position; where that fails
/// too and the step is shortened, the shorter step starts within reach again and crossed again to the same
/// end, undoing the shortening: the double four-bar over the run at rtol 9.7e-10 (with a lower floor under
/// the share, not kept) looped at t = 8.4844 s between a crossing of 6.86e-6 s and a step of 3.43e-6 s
/// placed before the position, both failing, without end (and without the interruption's check between
/// steps). A second crossing from the same start passes at times (a fresh Jacobian, the history rescaled);
/// a third is not tried.
const FAILED_CROSSINGS: u32 = 2;

/// Beyond this `κ` the rounding of the generalized-α method's Newton increments and of its error estimate
/// grows as `κ²` (the multipliers' amplification, which reaches its accelerations) rather than as `κ`:
/// measured on the four-bar at rtol 1e-12 just past its seventh position (κ = 4,177 at the last step end,
/// steps of 5e-14 to 1e-11 s, where no truncation error remains), Newton increments stalled at 780 to
/// 5,500 tolerances and error estimates of 7 to 1,400 tolerances, 0.05 to 0.25 `ε κ²` of the solution,
/// against the `50 · 10 ε κ` (460 tolerances) that the BDF's increments stay within; at κ = 1,000 to 1,250
/// (rtol 1e-11, steps of 3e-6 s) the estimates were 0.5 to 1 tolerance, 0.05 `ε κ²`.
const QUADRATIC_FROM: f64 = 1000.0;

/// While `κ` at the last measurement is at most this and no passage is predicted, the conditioning is
/// measured only every [`QUIET_STEPS`] accepted steps, or sooner where the fall of `σ` between the last two
/// measurements, extrapolated, would bring `κ` to [`WATCH`] within four times the time since the last one:
/// a well-conditioned mechanism does not pay the measurement at every step (it was 19 % of generalized-α's
/// time on the peer's chain of 4 rods, 377,069 steps), and an approach is measured at every step from
/// `κ` = 5 on, well before the guard acts. Above it, a `σ` that did not fall between the last two
/// measurements is measured as seldom: a straight chain of `n` rods has `κ ≈ 0.92 n` at every position
/// (59 at 64 rods), which no passage approaches, and measuring it at every step cost the chain of 32 rods
/// a fifth of its Newton iteration's time (74.6 against 62.1 µs).
const QUIET: f64 = WATCH / 4.0;
/// Accepted steps between measurements while the conditioning is good (see [`QUIET`]).
const QUIET_STEPS: usize = 8;

/// The conditioning of the constraint rows in force: `σ_rms / σ_min` of `B` (see the module documentation).
/// `B Bᵀ` is sparse (two rows share entries only where their joints share a body) and factored by
/// [`GramCholesky`], its pattern analysed at the first measurement: a measurement costs in proportion to
/// the joints, and allocates nothing after the first.
struct Conditioning {
    /// Row of `B` of each constraint row in force (`usize::MAX`: not in force).
    row_of: Vec<usize>,
    rows: usize,
    nv: usize,
    /// `B` and the Cholesky factor of `B Bᵀ`, from the first measurement on.
    gram: Option<GramCholesky>,
    /// The last smallest singular vector (in constraint space) and the inverse iteration's work vector.
    x: Vec<f64>,
    y: Vec<f64>,
    /// A fixed unit vector with every component of its own size, [`MIX`] of which is added to the last
    /// singular vector before each measurement (see there).
    spread: Vec<f64>,
}

impl Conditioning {
    fn new(model: &Model, active: &[bool]) -> Option<Self> {
        let mut row_of = vec![usize::MAX; model.layout.nc];
        let mut rows = 0;
        for (r, &in_force) in active.iter().enumerate() {
            if in_force {
                row_of[r] = rows;
                rows += 1;
            }
        }
        if rows == 0 {
            return None;
        }
        let nv = model.layout.nv;
        let x = vec![1.0 / (rows as f64).sqrt(); rows];
        // Components 1 to 2 in a sequence of the golden ratio (no two alike, none zero), then unit length.
        let mut spread: Vec<f64> = (0..rows).map(|k| 1.0 + (k as f64 * 0.618_033_988_749_895).fract()).collect();
        let norm = spread.iter().map(|v| v * v).sum::<f64>().sqrt();
        spread.iter_mut().for_each(|v| *v /= norm);
        Some(Self { row_of, rows, nv, gram: None, x, y: vec![0.0; rows], spread })
    }

    /// Adds the entries of `B` at the kinematics in `data` to `gram`; `false` if one lies outside its
    /// pattern.
    fn fill(gram: &mut GramCholesky, row_of: &[usize], model: &Model, data: &Data) -> bool {
        gram.clear();
        let mut inside = true;
        jacobian_entries(model, data, |r, c, x| {
            if row_of[r] != usize::MAX {
                inside &= gram.add(row_of[r], c, x);
            }
        });
        inside
    }

    /// `κ = σ_rms / σ_min` of `B` at the kinematics in `data` (infinite when `B Bᵀ` is singular to working
    /// precision).
    fn condition(&mut self, model: &Model, data: &Data) -> f64 {
        let n = self.rows;
        let filled = self.gram.as_mut().is_some_and(|gram| Self::fill(gram, &self.row_of, model, data));
        if !filled {
            // The first measurement (or a pattern of `B` not seen before): analyse the pattern.
            let mut entries = Vec::new();
            jacobian_entries(model, data, |r, c, _| {
                if self.row_of[r] != usize::MAX {
                    entries.push((self.row_of[r], c));
                }
            });
            let gram = self.gram.insert(GramCholesky::new(n, self.nv, entries));
            Self::fill(gram, &self.row_of, model, data);
        }
        let gram = self.gram.as_mut().expect("analysed above");
        let Some(trace) = gram.factor(1e-14) else {
            return f64::INFINITY;
        };
        // Inverse iteration: y = (B Bᵀ)⁻¹ x, the smallest eigenvalue 1/‖y‖ for a unit x along its vector.
        // From the last vector with a share of every direction: where the mechanism is several ones
        // that share no body (`B Bᵀ` block diagonal), the last vector lies in one block, and a start
        // there would never see another block's approach to its own singular position.
        self.x.iter_mut().zip(&self.spread).for_each(|(x, s)| *x += MIX * s);
        let norm = self.x.iter().map(|v| v * v).sum::<f64>().sqrt();
        self.x.iter_mut().for_each(|x| *x /= norm);
        let mut smallest = f64::INFINITY;
        for _ in 0..INVERSE_ITERATIONS {
            self.y.copy_from_slice(&self.x);
            gram.solve_in_place(&mut self.y);
            let norm = self.y.iter().map(|v| v * v).sum::<f64>().sqrt();
            if !norm.is_finite() || norm == 0.0 {
                self.x.fill(1.0 / (n as f64).sqrt());
                return f64::INFINITY;
            }
            smallest = 1.0 / norm;
            self.x.iter_mut().zip(&self.y).for_each(|(x, y)| *x = y / norm);
        }
        (trace / n as f64 / smallest).sqrt()
    }
}

/// The predicted passage of a singular position: `σ/σ_rms ≈ slope |t − centre|`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Window {
    centre: f64,
    /// `d(σ/σ_rms)/dt` on the approach.
    slope: f64,
}

impl Window {
    /// The `κ` predicted at `t`: `1 / (slope |t − centre|)`.
    fn condition_at(&self, t: f64) -> f64 {
        1.0 / (self.slope * (t - self.centre).abs())
    }
}

/// The guard of one integrator (see the module documentation).
pub(crate) struct SingularPassage {
    conditioning: Option<Conditioning>,
    /// Time and `σ/σ_rms` at the last accepted step end (`None` after a passage).
    last: Option<(f64, f64)>,
    window: Option<Window>,
    /// The relative tolerance: a step end is moved only where the rounding there would matter to it.
    rtol: f64,
    /// The step size asked for by the error control when the current attempt's end was moved.
    pub asked: Option<f64>,
    /// Singular positions passed (steps that ended past a predicted one).
    pub passages: usize,
    /// Accepted steps since the conditioning was last measured, and the time by which it is measured again
    /// while it is good ([`QUIET`]).
    unmeasured_steps: usize,
    measure_by: f64,
    /// The share of the tolerance the last attempt was held to ([`placed_end`](Self::placed_end)).
    held_share: f64,
    /// A passage was counted and `κ` has not been measured at or below [`WATCH`] since.
    just_passed: bool,
    /// Whether the window the step ends are kept out of keeps its width through a passage
    /// ([`crossing_in_one_step`](Self::crossing_in_one_step)), and that width once set.
    kept_width: bool,
    width: Option<f64>,
    /// Whether a step from within [`CROSSING_REACH`] steps of a predicted position crosses it in one step
    /// where the conditioning is poor ([`crossing_where_conditioned_badly`](Self::crossing_where_conditioned_badly)).
    crossing_early: bool,
    /// The start of the last attempt moved across the predicted position.
    crossing_from: Option<f64>,
    /// A step start and the crossings from it that failed ([`FAILED_CROSSINGS`]).
    failed_crossings: (f64, u32),
    /// The start and the end of the last attempt whose end was moved ([`placed_end`](Self::placed_end)).
    placed: Option<(f64, f64)>,
}

impl SingularPassage {
    /// The guard of a model whose constraint rows in force are `active`, integrated at relative tolerance
    /// `rtol`; inactive (it never acts) when there are none.
    pub fn new(model: &Model, active: &[bool], rtol: f64) -> Self {
        Self::measuring(Conditioning::new(model, active), rtol)
    }

    /// The guard measuring `conditioning` (none: it never acts) at relative tolerance `rtol`.
    fn measuring(conditioning: Option<Conditioning>, rtol: f64) -> Self {
        Self {
            conditioning,
            last: None,
            window: None,
            rtol,
            asked: None,
            passages: 0,
            unmeasured_steps: 0,
            measure_by: f64::INFINITY,
            held_share: 1.0,
            just_passed: false,
            kept_width: false,
            width: None,
            crossing_early: false,
            crossing_from: None,
            failed_crossings: (f64::NAN, 0),
            placed: None,
        }
    }

    /// The guard with the window around a predicted position kept as wide as it was when it first moved an
    /// end, half the step asked for then, until the position is passed (the Adams method's): step ends are
    /// then kept out of it however short the steps the error control asks for grow near the position, and
    /// it is crossed in one step from outside it, by the distance to the position. Where a crossing step
    /// fails, the window is halved and the next attempt ends at its new edge before the position.
    ///
    /// Without it (the BDF's and generalized-α's guard) the window is half of each attempt's step: on the
    /// double four-bar over the run's span at rtol 1e-8 the Adams method's accepted steps near the second
    /// position shrank with the distance to it (about a thirteenth of it each), so no end came within half a
    /// step of it, the ends approached it geometrically and the accelerations of the projected states there
    /// grew without bound (κ 1.9e7 at the last ends, 7e-8 s before it): the run stopped, step too small.
    pub fn crossing_in_one_step(mut self) -> Self {
        self.kept_width = true;
        self
    }

    /// The guard that also crosses a predicted position in one step, from `t` to `2 t* − t`, wherever a step
    /// starts within [`CROSSING_REACH`] steps of it (asked for), `κ` at the last step end or predicted at the
    /// asked end is at least [`CROSSING_FROM`], the rounding there matters to the step and the step is held
    /// to less than [`CROSSING_SHARE`] of the tolerance (the BDF's). A crossing that fails is retried as the
    /// guard would place it otherwise.
    ///
    /// Without it the BDF over the double four-bar's 10 s at rtol 1e-9 (steps held to 1e-4 of the
    /// tolerance) approached its fifth position with steps of about 6e-5 s, one end was placed half a step
    /// before it and the step after, crossing it, failed its error test (2.2e6 shares, at `κ` 2.6e4); from
    /// there the ends crept onto the position with steps far shorter than the distance to it, which the
    /// window of half a step never moves, and the run stopped 5.7e-6 s before it (`κ` 1.38e5, step
    /// 9.3e-15 s). Crossing from up to three steps before the position, where `κ` is still 500 to 4,000 at
    /// the start, every tolerance completes (docs/accuracy.md, *The BDF crosses a position in one step*).
    /// Where the share is [`CROSSING_SHARE`] or more (0.1 at rtol 1e-11 over the run, 1 per step) the
    /// crossing passed truncation errors of up to 2,380 shares within the rounding at its ends (rtol 1e-11:
    /// E from 3.4e-8 to 2.8e-7 m), and the steps there are placed as before (the same results).
    pub fn crossing_where_conditioned_badly(mut self) -> Self {
        self.crossing_early = true;
        self
    }

    /// The end of an attempt from `t` that would end at `t_new`, held to `share` of the tolerance: `None` to
    /// keep it, else where it ends instead, so that the step ends lie about half a step or more from a
    /// predicted singular position.
    ///
    /// The same attempt again (from the same start to the end placed for it: its iteration matrix was
    /// evaluated afresh after its Newton iteration failed with an older one, and the step was not
    /// shortened) ends where it was placed, and keeps the step asked for and whether it crosses. Before,
    /// it was placed anew from the moved step: a crossing counted as a crossing that failed, and the step
    /// asked for became the moved one, so the steps after the position were as long as the crossing (the
    /// double four-bar over its run at rtol 1e-8: 2.6 ms after the first position instead of 1.4 ms, their
    /// estimates of 4 to 7 shares passed as rounding, the energy rose by 1.8e-8 J in eight steps; at 1e-10,
    /// 2.3 ms instead of 0.58 ms after the second, estimates up to 2,600 shares). It happened at 4, 6 and 6
    /// of the 16 to 24 moved steps at rtol 1e-8, 1e-9 and 1e-10.
    pub fn placed_end(&mut self, t: f64, t_new: f64, share: f64) -> Option<f64> {
        if let Some((from, end)) = self.placed {
            if from == t && (t_new - end).abs() <= 4.0 * f64::EPSILON * end.abs().max(1.0) {
                return Some(end);
            }
        }
        let placed = self.place_end(t, t_new, share);
        self.placed = placed.map(|end| (t, end));
        placed
    }

    /// [`placed_end`](Self::placed_end) of an attempt not placed before.
    fn place_end(&mut self, t: f64, t_new: f64, share: f64) -> Option<f64> {
        self.asked = None;
        self.held_share = share;
        let retry = self.crossing_from.take() == Some(t);
        if retry {
            self.failed_crossings = if self.failed_crossings.0 == t { (t, self.failed_crossings.1 + 1) } else { (t, 1) };
        }
        let failed_here = if self.failed_crossings.0 == t { self.failed_crossings.1 } else { 0 };
        let w = self.window?;
        let (d, h) = (w.centre - t, t_new - t);
        let width = self.width.unwrap_or(0.5 * h);
        if d <= 0.0 {
            return None;
        }
        if self.crossing_early && !retry && failed_here < FAILED_CROSSINGS && d <= CROSSING_REACH * h && share < CROSSING_SHARE {
            let at_start = self.last.map_or(1.0, |(_, s)| 1.0 / s);
            let condition = at_start.max(w.condition_at(t_new));
            if condition >= CROSSING_FROM && self.matters(condition, share) {
                self.asked = Some(h);
                self.crossing_from = Some(t);
                return Some(w.centre + d);
            }
        }
        if t_new <= w.centre - width {
            return None;
        }
        // Only where the rounding at the end would matter to the tolerance: at ordinary tolerances a dip of
        // the conditioning (the 3-D slider-crank's) leaves the steps alone.
        let predicted = w.condition_at(t_new);
        if !self.matters(predicted, share) {
            return None;
        }
        self.asked = Some(h);
        if !self.kept_width {
            let end = if d > JUMP_REACH * h { w.centre - 0.5 * h } else { w.centre + d.max(0.5 * h) };
            return Some(end);
        }
        // The window keeps its width; a crossing that failed halves it.
        let width = if retry { 0.5 * width } else { width };
        self.width = Some(width);
        if d > 2.0 * JUMP_REACH * width {
            return Some(w.centre - width);
        }
        self.crossing_from = Some(t);
        Some(w.centre + d.max(width))
    }

    /// The factor by which the rounding of the solution at the end `t_new` of a step from `t`, held to
    /// `share` of the tolerance, exceeds that of a well-conditioned one: `κ` at the last step end once it
    /// exceeds [`WATCH`], or the `κ` predicted at `t_new` if larger; 1 where the rounding so amplified does
    /// not [`matter`](Self::matters) to the step (its tests are then those of a well-conditioned step).
    pub fn amplification(&self, t: f64, t_new: f64, share: f64) -> f64 {
        let Some((_, last)) = self.last else {
            return 1.0;
        };
        let measured = if 1.0 / last > WATCH { 1.0 / last } else { 1.0 };
        let amplification = match self.window {
            Some(w) => measured.max(w.condition_at(t_new).max(0.25 * w.slope * (t_new - t))),
            None => measured,
        };
        if self.matters(amplification, share) {
            amplification
        } else {
            1.0
        }
    }

    /// Whether the step ends are near a singular position: one is predicted ahead, or one was passed and
    /// `κ` at the step ends has not yet fallen back to [`WATCH`]. There the state at the last step end
    /// carries the rounding of the ill-conditioned constraints, which the predictor of every order
    /// extrapolates (the BDF does not restart at order 1 there).
    pub fn near(&self) -> bool {
        self.window.is_some() || self.just_passed
    }

    /// Whether the rounding amplified by the condition number `condition` matters to a step held to `share`
    /// of the tolerance: what the steps there resolve, [`resolution`](Self::resolution), is more than
    /// [`PLACE_FRACTION`] of `rtol`, or the amplified rounding itself, `10 ε κ`, is more than
    /// [`PLACE_FRACTION`] of what the step is held to, `rtol · share`.
    ///
    /// The second bound is that of error per unit step ([`ToleranceSpan`](super::ToleranceSpan)), where a
    /// step's share is `h / span`, far below 1 (the double four-bar over its run of 10 s at rtol 1e-8:
    /// `1e-4` to `1.6e-4`, a step held to 1e-12 to 1.6e-12 of the solution), and the share near a singular
    /// position cannot be below what the arithmetic resolves there. Without it the guard never acted at
    /// rtol 1e-8 (`500 ε κ` reached 1e-9 only at κ = 9,000), while the rounding `10 ε κ` exceeded the
    /// steps' share from κ ≈ 65 on: the BDF's Newton increments stalled at 4 to 50 shares (rates 0.8 to
    /// 2.7 at every step size from 9e-6 s to 2e-14 s) 0.1 ms before the position, at κ = 7,900, and the run
    /// stopped at t = 0.714255 s; generalized-α stopped at 0.709415 s. Per step (`share = 1`) the second
    /// bound is within the first, and nothing changes; at ordinary conditioning (the 3-D slider-crank's dip
    /// to κ = 25 at rtol 1e-8 over the run, its estimates 20 to 30 shares, truncation) it does not act:
    /// with `resolution(κ)` in place of `10 ε κ` it did, and passed those estimates, and E rose from 4.7 to
    /// 17 tolerances.
    fn matters(&self, condition: f64, share: f64) -> bool {
        Self::resolution(condition) > PLACE_FRACTION * self.rtol || ROUND_OFF * condition > PLACE_FRACTION * self.rtol * share
    }

    /// The amplification of the rounding in the generalized-α method's step equations at a step end of
    /// amplification `amplification` ([`amplification`](Self::amplification)): it grows as `κ²` beyond
    /// [`QUADRATIC_FROM`], through the multipliers, whose rounding is `κ²` amplified and which enter its
    /// accelerations, `ã` and its error estimate (see the constant).
    pub fn quadratic_beyond(amplification: f64) -> f64 {
        amplification * (amplification / QUADRATIC_FROM).max(1.0)
    }

    /// Whether the rounding `10 ε κ` amplified by `amplification` exceeds [`PLACE_FRACTION`] of what a step
    /// held to `share` of the tolerance `rtol` may make (the second criterion of `matters` alone).
    pub fn rounding_matters(amplification: f64, rtol: f64, share: f64) -> bool {
        amplification > 1.0 && ROUND_OFF * amplification > PLACE_FRACTION * rtol * share
    }

    /// What the steps resolve near a singular position of condition number `condition`, relative to the
    /// solution: `MARGIN · 10 ε κ`, where the Newton increments are taken as converged.
    pub fn resolution(condition: f64) -> f64 {
        MARGIN * ROUND_OFF * condition
    }

    /// The factor of the round-off level of the Newton increments (below which they have converged whatever
    /// their rate) at the rounding amplified by `amplification`.
    pub fn round_off_factor(amplification: f64) -> f64 {
        if amplification > 1.0 {
            MARGIN * amplification
        } else {
            1.0
        }
    }

    /// Whether an error estimate of `error` tolerances at rtol `rtol` of a method of order `order` is within
    /// the rounding amplified by `amplification`: the estimate compares the solution with a predictor that
    /// extrapolates `order + 1` earlier ones, each resolved to that rounding, which it amplifies by up to
    /// `2^(order+1) − 1`, and divides by `order + 1`.
    fn error_within_rounding(error: f64, rtol: f64, amplification: f64, order: usize) -> bool {
        amplification > 1.0 && error <= Self::estimate_rounding(amplification, rtol, order)
    }

    /// The rounding of an error estimate of a method of order `order` near a singular position, in
    /// tolerances at rtol `rtol`: `MARGIN · gain · 10 ε κ / rtol` with `κ` the amplification and `gain =
    /// 2^(k+1)/(k + 1)` the predictor's ([`error_within_rounding`](Self::error_within_rounding)); 0 where
    /// the rounding is not amplified (`amplification` at most 1). The BDF also keeps the Newton
    /// increments' rounding level up to it (`Bdf::bounded_level`).
    pub fn estimate_rounding(amplification: f64, rtol: f64, order: usize) -> f64 {
        if amplification <= 1.0 {
            return 0.0;
        }
        let gain = (1u64 << (order + 1).min(12)) as f64 / (order + 1) as f64;
        MARGIN * gain * ROUND_OFF * amplification / rtol
    }

    /// An error estimate of `error` shares of the tolerance (each `share` tolerances) of a method of order
    /// `order`, or [`NOISE_ESTIMATE`] if it is within the rounding amplified by `amplification`
    /// ([`error_within_rounding`](Self::error_within_rounding)): it passes, and the step size chosen from it
    /// grows a little instead of shrinking toward the position, where the rounding only grows.
    pub fn estimate_beyond_rounding(error: f64, share: f64, rtol: f64, amplification: f64, order: usize) -> f64 {
        if error > NOISE_ESTIMATE && Self::error_within_rounding(error * share, rtol, amplification, order) {
            NOISE_ESTIMATE
        } else {
            error
        }
    }

    /// What an order selection takes, in shares of the tolerance, for an estimate of `estimate` tolerances
    /// of a step held to `share` of the tolerance, of a method of order `order`, that passed as rounding
    /// ([`estimate_beyond_rounding`](Self::estimate_beyond_rounding)): the estimate against the rounding
    /// itself, `gain · 10 ε κ` without the error test's [`MARGIN`], where that is more than the share, and
    /// at least [`NOISE_ESTIMATE`]. The error test lets estimates up to the margin's fifty times the
    /// rounding pass, since shorter steps do not resolve the rounding finer; the step chosen after them aims
    /// at the rounding. Taken as the stand-in, every such estimate let the step grow until its truncation
    /// error reached the margin: Andrews' squeezer, whose every step is within the guard (κ 147 to 204),
    /// passed estimates of up to 48.5 times the rounding (median 1.3) at rtol 1e-9, and they added up to its
    /// error, 9 to 75 tolerances at rtol × 0.97 … 1.03; with the selection aimed at the rounding, 0.5 to
    /// 3.4 (2,200–2,850 steps before, 4,570–4,940 now). Aimed at four times the rounding: 1.4 to 5.4
    /// tolerances in 3,570–4,100 steps.
    /// `None` where the estimate did not pass as rounding (the selection takes it as it is).
    pub fn estimate_for_selection(estimate: f64, share: f64, rtol: f64, amplification: f64, order: usize) -> Option<f64> {
        let error = estimate / share;
        if error <= NOISE_ESTIMATE || !Self::error_within_rounding(error * share, rtol, amplification, order) {
            return None;
        }
        let rounding = Self::estimate_rounding(amplification, rtol, order) / MARGIN;
        Some((estimate / share.max(rounding)).max(NOISE_ESTIMATE))
    }

    /// Whether an estimate of `error` tolerances of a method of order `order` is within the rounding amplified
    /// by the `κ` measured at the last step end (once it exceeds [`WATCH`]), whether or not that rounding
    /// [`matters`](Self::matters) to the step: a failure of the error test there need not be truncation.
    pub fn within_measured_rounding(&self, error: f64, order: usize) -> bool {
        self.last.is_some_and(|(_, s)| 1.0 / s > WATCH && Self::error_within_rounding(error, self.rtol, 1.0 / s, order))
    }

    /// Whether the attempt last placed by [`placed_end`](Self::placed_end) crosses the predicted position.
    pub fn crossing(&self, t: f64) -> bool {
        self.crossing_from == Some(t)
    }

    /// Whether an estimate of `error` tolerances of a method of order `order` on a step across a singular
    /// position from `t` to `end`, held to `share` of the tolerance, is within the rounding amplified by the
    /// `κ` at its ends ([`amplification`](Self::amplification)) that the BDF's estimates pass within
    /// ([`estimate_beyond_rounding`](Self::estimate_beyond_rounding)).
    pub fn crossing_within_rounding(&self, error: f64, t: f64, end: f64, share: f64, order: usize) -> bool {
        Self::error_within_rounding(error, self.rtol, self.amplification(t, end, share), order)
    }

    /// Whether `error`, an estimate in shares of the tolerance returned by
    /// [`estimate_beyond_rounding`](Self::estimate_beyond_rounding), is one that passed as rounding.
    pub fn is_noise(error: f64) -> bool {
        error == NOISE_ESTIMATE
    }

    /// A step ending at `t` was accepted, with the kinematics of its solution in `data`. Measures `κ` there
    /// and predicts the zero of `σ` of an approaching singular position; returns the `κ` of a step accepted
    /// while one was predicted (`None` otherwise). Once a step has ended past it, it is counted in
    /// [`passages`](Self::passages) and forgotten, and the approach to the next is measured afresh.
    pub fn accepted(&mut self, model: &Model, data: &Data, t: f64) -> Option<f64> {
        self.asked = None;
        self.conditioning.as_ref()?;
        self.unmeasured_steps += 1;
        // Quiet where no passage is predicted and either the conditioning is good or `σ` did not fall at
        // the last measurement (`measure_by` infinite: a long chain's `κ` grows with its rods but stays),
        // and, where a passage is predicted, while the rounding at twice the last `κ` would not matter to
        // the last attempt's share (`σ` falls by at most a quarter before `measure_by`).
        let steady = self.measure_by == f64::INFINITY;
        let far = |s: f64| self.window.is_some() && !self.matters(2.0 / s, self.held_share);
        let quiet = self.last.is_some_and(|(_, s)| far(s) || (self.window.is_none() && (s * QUIET >= 1.0 || steady)));
        if quiet && self.unmeasured_steps < QUIET_STEPS && t < self.measure_by {
            return None;
        }
        self.unmeasured_steps = 0;
        let condition = self.conditioning.as_mut()?.condition(model, data);
        let s = 1.0 / condition;
        self.measure_by = match self.last {
            Some((t_prev, s_prev)) if s < s_prev && t > t_prev => {
                // Below the watch, a quarter of the predicted time to the zero of `σ`: the measurements
                // come closer as the passage nears, at every step from four steps before it.
                let to = if s * WATCH < 1.0 { s } else { s - 1.0 / WATCH };
                t + 0.25 * to * (t - t_prev) / (s_prev - s)
            }
            _ => f64::INFINITY,
        };
        let watched = self.window.is_some();
        if self.window.is_some_and(|w| t > w.centre) {
            self.window = None;
            self.width = None;
            self.just_passed = true;
            self.passages += 1;
            self.last = Some((t, s));
            return Some(condition);
        }
        match self.last.replace((t, s)) {
            Some((t_prev, s_prev)) if s < s_prev && condition > WATCH && t > t_prev => {
                let slope = (s_prev - s) / (t - t_prev);
                self.window = Some(Window { centre: t + s / slope, slope });
            }
            Some(_) if condition <= WATCH => {
                self.window = None;
                self.width = None;
                self.just_passed = false;
            }
            _ => {}
        }
        watched.then_some(condition)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where the amplified rounding matters: per step (share 1) only where `500 ε κ` is a tenth of rtol, as
    /// before; with error per unit step also where `10 ε κ` is a tenth of what the step is held to. The
    /// double four-bar at rtol 1e-8 over its 10 s (shares 1e-4 to 1.6e-4): from κ ≈ 65 on, where per step it
    /// never acted below κ = 9,000; the 3-D slider-crank's dip to κ = 25 at the same tolerance and share: not.
    #[test]
    fn the_rounding_matters_against_what_the_step_is_held_to() {
        let guard = |rtol| SingularPassage::measuring(None, rtol);
        let per_step = guard(1e-8);
        assert!(!per_step.matters(8_000.0, 1.0) && per_step.matters(10_000.0, 1.0));
        assert!(guard(1e-12).matters(21.0, 1.0), "per step at the finest tolerance: from the watch on");
        assert!(per_step.matters(70.0, 1.4e-4) && !per_step.matters(40.0, 1.4e-4));
        assert!(!per_step.matters(25.0, 1e-4), "the slider-crank's dip");
        assert!(!guard(1e-6).matters(8_000.0, 3e-4), "at an ordinary tolerance over the run (steps of 3 ms)");
    }

    /// The BDF's guard crosses a predicted position from one step start at most [`FAILED_CROSSINGS`] times:
    /// each failed crossing is followed by an attempt placed before the position, and once two crossings
    /// from the start have failed, the attempts from it that follow are no longer moved across (they were,
    /// to the same end, for as long as the attempts failed). A step from elsewhere crosses again. The double
    /// four-bar's numbers at rtol 1e-9: κ 1,000 about 1.2 ms from the position, steps held to 1e-4 of the
    /// tolerance; every attempt asks for the distance to the position and fails.
    #[test]
    fn a_step_start_crosses_a_position_at_most_twice() {
        let mut guard = SingularPassage::measuring(None, 1e-9).crossing_where_conditioned_badly();
        guard.window = Some(Window { centre: 1.0, slope: 1.0 / (1000.0 * 1.2e-3) });
        guard.last = Some((0.9996, 1.0 / 1500.0));
        let (t, share, h) = (0.9996, 1e-4, 4e-4);
        let ends: Vec<Option<f64>> = (0..12).map(|_| guard.placed_end(t, t + h, share)).collect();
        let crossing = 1.0004;
        let crossings = ends.iter().filter(|e| e.is_some_and(|e| (e - crossing).abs() < 1e-12)).count();
        assert_eq!(crossings, 2, "{ends:?}");
        assert!(ends[0].is_some_and(|e| (e - crossing).abs() < 1e-12), "the first attempt crosses: {ends:?}");
        assert!(ends[4..].iter().all(|e| e.is_some_and(|e| e < 1.0)), "later attempts end before the position: {ends:?}");
        let later = 0.9997;
        let end = guard.placed_end(later, later + 3e-4, share);
        assert!(end.is_some_and(|e| (e - 1.0003).abs() < 1e-12), "from another start it crosses: {end:?}");
    }
}
