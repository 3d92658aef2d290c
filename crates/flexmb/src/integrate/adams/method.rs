//! The variable-order, variable-step Adams–Bashforth–Moulton method of Shampine and Gordon for
//! `ẏ = f(t, y)`: the STEP and INTRP algorithms of *Computer Solution of Ordinary Differential
//! Equations* (1975, ch. 5–7), the non-stiff method of the DADS code.
//!
//! **Formulas.** The derivative history is kept as *modified divided differences*
//! `φ_i(n) = ψ_1(n) ⋯ ψ_{i−1}(n) f[t_n, …, t_{n−i+1}]`, `ψ_i(n) = t_{n+1} − t_{n+1−i}`, so that any
//! step size can be taken without interpolating the history. With `β_i` (the change from `φ_i(n)` to
//! `φ*_i(n)` for the new step), `α_i = h/ψ_i` and the integration coefficients `g_{i,1}` computed by the
//! recurrence `g_{i,q} = g_{i−1,q} − α_{i−1} g_{i−1,q+1}` (`g_{1,q} = 1/q`, `g_{2,q} = 1/(q(q+1))`),
//! one step of order `k` is the PECE pair
//!
//! ```text
//! P:  p_{n+1} = y_n + h Σ_{i=1..k} g_i φ*_i(n)                      (Adams–Bashforth, order k)
//! E:  f^p = f(t_{n+1}, p_{n+1})
//! C:  y_{n+1} = p_{n+1} + h g_{k+1} (f^p − φ^p_1(n+1))              (Adams–Moulton, order k + 1)
//! E:  f_{n+1} = f(t_{n+1}, y_{n+1});  φ_{k+1}(n+1) = f_{n+1} − φ^p_1(n+1),  φ_i(n+1) = φ^p_i(n+1) + φ_{k+1}(n+1)
//! ```
//!
//! **Error control.** The local error of the order-`k` corrector, `h (g_k − g_{k+1}) ‖f^p − φ^p_1‖`,
//! is tested against the tolerance; the solution advances with the order-`k + 1` corrector (local
//! extrapolation), so a run at a fixed order `k` converges with order `k + 1`. Errors the method would
//! have made at orders `k − 2, k − 1, k, k + 1` with constant steps (`σ` corrects for the actual
//! steps) select the order: lowered when the lower orders would have done better, raised only after
//! `k + 1` steps of one size when the order-`k + 1` estimate is the smallest. The step doubles while
//! the estimate is below `2^{−(k+1)}` of the tolerance, is kept while below it, else shrinks by
//! `max(0.5, min(0.9, (½/err)^{1/(k+1)}))`. At the start the order climbs by one and the step doubles
//! every step until an estimate says otherwise. A failed step halves the step (order 1 from the third
//! consecutive failure, then the step the estimate asks for).
//!
//! **Norm.** The tolerance is per component, `atol + rtol |y|` at the start of the step, and the norm
//! is the root-mean-square of the weighted components (as in the BDF), tested against 1.
//!
//! **Dense output** (INTRP) evaluates the same interpolating polynomial at any time of the last step.
//!
//! **Rounding.** As in STEP, when the tolerance is within a factor 100 of the weighted unit round-off,
//! the sums `p = y + h Σ …` and `y = p + …` are compensated (Kahan-style), which keeps the accumulated
//! round-off from swamping the local error.
//!
//! **Hook for invariants.** [`OdeSystem::accept`] receives the corrected solution of an accepted step
//! and may move it (e.g. project a mechanism onto its constraints) before the final evaluation; the
//! differences then hold the derivatives at the moved solution, and `y_n` is the moved one.
//!
//! Nothing here allocates after the stepper is made.

use crate::integrate::share_floor::ShareFloor;
use crate::integrate::error_norm::error_weight;

/// Highest order of the method (the order of its Adams–Bashforth predictor).
pub const MAX_ORDER: usize = 12;

/// STEP's `gstr`: `|γ*_i|`, error constants of the constant-step Adams–Moulton formulas, index `i ≥ 1`.
const GSTR: [f64; 14] =
    [0.0, 0.5, 0.0833, 0.0417, 0.0264, 0.0188, 0.0143, 0.0114, 0.00936, 0.00789, 0.00679, 0.00592, 0.00524, 0.00468];
/// Rows of `φ`: differences 1..=k+2 (k ≤ 12) and two rows for the compensated sums.
const PHI_ROWS: usize = 16;
/// Length of the coefficient arrays (1-based indices as in the book; index 0 unused).
const C: usize = MAX_ORDER + 3;

/// Why `f` could not be evaluated (or the accepted solution could not be adjusted): a fixed
/// description, so that a recoverable failure costs no allocation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvaluationFailure(pub &'static str);

/// A system `ẏ = f(t, y)` for [`AdamsStepper`].
pub trait OdeSystem {
    /// Writes `f(t, y)` into `dy`. A failure makes the step retry with half the step size.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure>;

    /// Called with the corrected solution of a step that passed the error test: may move `y` (onto an
    /// invariant manifold), then writes `f(t, y)` at the final `y` into `dy`. A failure rejects the step.
    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.rhs(t, y, dy)
    }

    /// Writes `f(t, y)` at the predicted solution `y` of an attempt into `dy`, and may first move `y` onto
    /// an invariant manifold where `f` off it is ill-conditioned (a mechanism near a singular position);
    /// the corrector then starts from the moved prediction. By default `f` at `y` as it is.
    fn predicted(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.rhs(t, y, dy)
    }

    /// The factor by which the rounding of `f` at the current attempt's end exceeds that of a
    /// well-conditioned evaluation, `10 ε` of `‖f‖` (1: ordinary; a mechanism near a singular position:
    /// its condition number there, `SingularPassage::amplification`).
    fn rounding_amplification(&self) -> f64 {
        1.0
    }

    /// Whether an error estimate of `error` tolerances of the current attempt at order `k` is within the
    /// rounding of its ends, whatever the step (a mechanism's step across a singular position:
    /// `SingularPassage::crossing_within_rounding`). By default none is.
    fn crossing_within_rounding(&self, _error: f64, _k: usize) -> bool {
        false
    }

    /// Where an attempt from `t` that would end at `t_new`, held to `share` of the tolerance, ends instead
    /// (`None`: where it would): a mechanism keeps its step ends off a singular position
    /// (`SingularPassage::placed_end`).
    fn placed_end(&mut self, _t: f64, _t_new: f64, _share: f64) -> Option<f64> {
        None
    }
}

/// Tolerances and step limits of [`AdamsStepper`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepControl {
    /// Relative tolerance of the local error.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// The span of time whose steps together may make an error of the tolerance
    /// ([`Tolerances::span`](crate::integrate::Tolerances::span)): a step of size `h` is held to `h / span`
    /// of it. Infinite (the default here) is STEP's own test, the whole tolerance per step.
    #[serde(with = "crate::integrate::extended_float", default = "per_step")]
    pub span: f64,
    /// Highest order, 1 to [`MAX_ORDER`].
    pub max_order: usize,
    /// Largest step.
    #[serde(with = "crate::integrate::extended_float")]
    pub h_max: f64,
    /// First step; chosen from the initial derivative when `None` (STEP: `¼ √(tol/‖f‖)`).
    pub h_init: Option<f64>,
}

impl Default for StepControl {
    fn default() -> Self {
        Self { rtol: 1e-6, atol: 1e-6, span: per_step(), max_order: MAX_ORDER, h_max: f64::INFINITY, h_init: None }
    }
}

/// The span of STEP's own error test: the whole tolerance for every step.
fn per_step() -> f64 {
    f64::INFINITY
}

impl StepControl {
    /// The tolerances these are, for the share of the tolerance a step may spend.
    fn tolerances(&self) -> crate::integrate::Tolerances {
        crate::integrate::Tolerances {
            rtol: self.rtol,
            atol: self.atol,
            span: crate::integrate::ToleranceSpan::Seconds(self.span),
            ..Default::default()
        }
    }
}

/// Counters of the stepper.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepperStats {
    /// Accepted steps.
    pub steps: usize,
    /// Attempts rejected by the error test.
    pub error_test_failures: usize,
    /// Attempts abandoned because `f` could not be evaluated or the solution not adjusted.
    pub evaluation_failures: usize,
    /// Calls of [`OdeSystem::rhs`] and [`OdeSystem::accept`].
    pub evaluations: usize,
    /// Accepted steps at each order (index = order).
    pub order_counts: [usize; MAX_ORDER + 1],
    /// Sum of the squared accepted step sizes.
    pub sum_h_squared: f64,
}

/// Why the last attempt at a step failed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AttemptFailure {
    /// The local error test failed with this weighted error (1 = the tolerance).
    ErrorTest {
        /// The weighted error.
        error: f64,
    },
    /// `f` could not be evaluated at the predicted solution.
    Evaluation(EvaluationFailure),
    /// The accepted solution could not be adjusted (or `f` evaluated there).
    Acceptance(EvaluationFailure),
}

/// Why the integration cannot continue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepFailure {
    /// The step size fell below `4u|t|`; the last attempt failed for `last` (if any attempt was made).
    StepSizeTooSmall {
        /// Time (s).
        t: f64,
        /// The step size (s).
        h: f64,
        /// Why the last attempt failed.
        last: Option<AttemptFailure>,
    },
    /// The tolerance is below what the precision allows at this solution: the weighted unit round-off
    /// `2u ‖y‖` exceeds half the tolerance; STEP's suggestion for a workable tolerance factor is given.
    ToleranceTooSmall {
        /// Time (s).
        t: f64,
        /// The factor to multiply the tolerances by.
        factor: f64,
    },
    /// `f` could not be evaluated at the initial point.
    Start(EvaluationFailure),
}

/// The Shampine–Gordon Adams PECE stepper with its workspaces.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AdamsStepper {
    n: usize,
    control: StepControl,
    /// Fixed order and step: no error test, no order or step change (for convergence studies).
    fixed: bool,
    x: f64,
    x_old: f64,
    y: Vec<f64>,
    /// `f(x, y)`.
    yp: Vec<f64>,
    /// Predicted solution.
    p: Vec<f64>,
    /// `f` at the predicted solution, then at the corrected one.
    fp: Vec<f64>,
    y_new: Vec<f64>,
    /// The corrected solution before [`OdeSystem::accept`] (with rounding control only).
    y_corr: Vec<f64>,
    wt: Vec<f64>,
    /// `φ_i`, row `i − 1` for `i = 1..=16` (rows 15, 16: compensation terms of the sums).
    phi: Vec<f64>,
    psi: [f64; C],
    alpha: [f64; C],
    beta: [f64; C],
    sig: [f64; C],
    v: [f64; C],
    w: [f64; C],
    g: [f64; C],
    h: f64,
    hold: f64,
    k: usize,
    kold: usize,
    ns: usize,
    phase1: bool,
    nornd: bool,
    started: bool,
    /// After [`restart`](AdamsStepper::restart): the largest first step (else infinite).
    #[serde(with = "crate::integrate::extended_float")]
    h_restart_cap: f64,
    /// The floors under a step's share of the tolerance (error per unit step): a tenth of the last
    /// accepted step's share, and rounding noise near singular positions (as the BDF's).
    #[serde(default)]
    share_floor: ShareFloor,
    /// Its counters.
    pub stats: StepperStats,
}

const U: f64 = f64::EPSILON / 2.0;
const TWOU: f64 = 2.0 * U;
const FOURU: f64 = 4.0 * U;

impl AdamsStepper {
    /// A stepper for `n` equations at `(t0, y0)` with `f(t0, y0) = yp0`.
    pub(crate) fn new(control: StepControl, t0: f64, y0: &[f64], yp0: &[f64]) -> Self {
        let n = y0.len();
        assert_eq!(yp0.len(), n, "y0 and yp0 differ in length");
        let control = StepControl { max_order: control.max_order.clamp(1, MAX_ORDER), ..control };
        Self {
            n,
            control,
            fixed: false,
            x: t0,
            x_old: t0,
            y: y0.to_vec(),
            yp: yp0.to_vec(),
            p: vec![0.0; n],
            fp: vec![0.0; n],
            y_new: vec![0.0; n],
            y_corr: vec![0.0; n],
            wt: vec![1.0; n],
            phi: vec![0.0; PHI_ROWS * n],
            psi: [0.0; C],
            alpha: [0.0; C],
            beta: [0.0; C],
            sig: [0.0; C],
            v: [0.0; C],
            w: [0.0; C],
            g: [0.0; C],
            h: 0.0,
            hold: 0.0,
            k: 1,
            kold: 0,
            ns: 0,
            phase1: true,
            nornd: true,
            started: false,
            h_restart_cap: f64::INFINITY,
            share_floor: ShareFloor::default(),
            stats: StepperStats::default(),
        }
    }

    /// A stepper at `(t0, y0)` that evaluates `f(t0, y0)` itself (the tests' systems).
    #[cfg(test)]
    pub(crate) fn start<S: OdeSystem + ?Sized>(
        control: StepControl,
        system: &mut S,
        t0: f64,
        y0: &[f64],
    ) -> Result<Self, StepFailure> {
        let mut yp0 = vec![0.0; y0.len()];
        system.rhs(t0, y0, &mut yp0).map_err(StepFailure::Start)?;
        let mut s = Self::new(control, t0, y0, &yp0);
        s.stats.evaluations += 1;
        Ok(s)
    }

    /// A stepper that takes steps of size `h` at order `k` from `t0` with no error control, its history
    /// the constant-step derivatives `past[j] = f(t0 − j h, y(t0 − j h))`, `j = 0..k` (for measuring
    /// the order of the formulas; `y0` is the solution at `t0`).
    #[cfg(test)]
    pub(crate) fn with_fixed_order_and_step(t0: f64, y0: &[f64], h: f64, past: &[Vec<f64>]) -> Self {
        let k = past.len();
        assert!((1..=MAX_ORDER).contains(&k), "order {k} outside 1..={MAX_ORDER}");
        let control = StepControl { max_order: k, rtol: 1.0, atol: 1.0, ..Default::default() };
        let mut s = Self::new(control, t0, y0, &past[0]);
        let n = s.n;
        // φ_{i+1} = ∇^i f_n (backward differences, the modified divided differences of equal steps).
        let mut diff: Vec<Vec<f64>> = past.to_vec();
        for i in 0..k {
            s.phi[i * n..(i + 1) * n].copy_from_slice(&diff[0]);
            for j in 0..k - 1 - i {
                for l in 0..n {
                    diff[j][l] -= diff[j + 1][l];
                }
            }
        }
        for i in 1..=k {
            s.psi[i] = i as f64 * h;
        }
        s.h = h;
        s.hold = 0.0;
        s.k = k;
        s.kold = k;
        s.ns = 0;
        s.phase1 = false;
        s.nornd = true;
        s.fixed = true;
        s.started = true;
        s.wt.fill(1.0);
        s
    }

    /// Starts again at `(t0, y0)` with `f(t0, y0) = yp0` (same length), at order 1 with a new starting
    /// step, keeping the counters and the workspaces (no allocation).
    pub(crate) fn restart(&mut self, t0: f64, y0: &[f64], yp0: &[f64]) {
        self.x = t0;
        self.x_old = t0;
        self.y.copy_from_slice(y0);
        self.yp.copy_from_slice(yp0);
        self.started = false;
        self.k = 1;
        self.kold = 0;
        self.ns = 0;
        self.hold = 0.0;
        self.phase1 = true;
        // The first step after a restart: STEP's estimate, at most the step planned before it.
        self.h_restart_cap = self.h;
    }

    /// Current time.
    pub fn t(&self) -> f64 {
        self.x
    }
    /// Start of the last accepted step.
    pub fn t_old(&self) -> f64 {
        self.x_old
    }
    /// Solution at [`t`](Self::t).
    pub fn y(&self) -> &[f64] {
        &self.y
    }
    /// `f(t, y)` at the current solution.
    pub fn yp(&self) -> &[f64] {
        &self.yp
    }
    /// Order of the last accepted step (0 before the first).
    pub fn order(&self) -> usize {
        self.kold
    }
    /// Order planned for the next step.
    pub fn next_order(&self) -> usize {
        self.k
    }
    /// Step size planned for the next step.
    pub fn step_size(&self) -> f64 {
        self.h
    }
    /// Sets the size of the next step: after a step moved off a singular position, the one the error control
    /// asked for.
    pub(crate) fn set_step_size(&mut self, h: f64) {
        self.h = h;
    }
    /// Tolerances and limits in force.
    pub fn control(&self) -> &StepControl {
        &self.control
    }

    fn row(&self, i: usize) -> std::ops::Range<usize> {
        (i - 1) * self.n..i * self.n
    }

    /// `‖x‖` in the step's weighted norm, for `x_l = get(l)`.
    fn norm(&self, get: impl Fn(usize) -> f64) -> f64 {
        (0..self.n).map(|l| (get(l) / self.wt[l]).powi(2)).sum::<f64>().sqrt()
    }

    /// Takes one accepted step, not passing `t_stop` (`t_stop > t`).
    pub(crate) fn step<S: OdeSystem + ?Sized>(&mut self, system: &mut S, t_stop: f64) -> Result<(), StepFailure> {
        let n = self.n;
        let remaining = t_stop - self.x;
        if remaining <= FOURU * self.x.abs() {
            // Closer to t_stop than the time resolution: arrive there without a step.
            self.x = t_stop.max(self.x);
            return Ok(());
        }
        // Error weights from the solution at the start of the step (DE), scaled for an RMS norm.
        let root_n = (n.max(1) as f64).sqrt();
        let tolerances = self.control.tolerances();
        if !self.fixed {
            for l in 0..n {
                self.wt[l] = error_weight(self.control.atol, self.control.rtol, self.y[l]) * root_n;
            }
        }
        let eps = 1.0;
        let p5eps = 0.5 * eps;
        // Block 0: step size and tolerance against the machine precision; the first step.
        let round = TWOU * self.norm(|l| self.y[l]);
        if !self.fixed && p5eps < round {
            return Err(StepFailure::ToleranceTooSmall { t: self.x, factor: 2.0 * round * (1.0 + FOURU) });
        }
        if !self.started {
            self.initialize(remaining, round);
        }
        if !self.fixed {
            self.h = self.h.min(self.control.h_max).min(remaining);
        } else if self.h > remaining {
            self.h = remaining;
        }
        if self.h < FOURU * self.x.abs() || self.h <= 0.0 {
            return Err(StepFailure::StepSizeTooSmall { t: self.x, h: self.h, last: None });
        }
        self.g[1] = 1.0;
        self.g[2] = 0.5;
        self.sig[1] = 1.0;
        let mut ifail = 0;
        let mut share = 1.0;
        loop {
            // The weights of this attempt's share of the tolerance (error per unit step), its end kept off a
            // singular position.
            if !self.fixed {
                let asked_share = self.share_floor.share(&tolerances, self.h);
                if let Some(end) = system.placed_end(self.x, self.x + self.h, asked_share) {
                    self.h = end - self.x;
                }
                let new_share = self.share_floor.share(&tolerances, self.h);
                let rescale = new_share / share;
                self.wt.iter_mut().for_each(|w| *w *= rescale);
                share = new_share;
            }
            self.coefficients();
            // Block 2: φ → φ*, predict, evaluate.
            let (k, kp1, kp2) = (self.k, self.k + 1, self.k + 2);
            let nsp1 = self.ns + 1;
            if k >= nsp1 {
                for i in nsp1..=k {
                    let b = self.beta[i];
                    let r = self.row(i);
                    self.phi[r].iter_mut().for_each(|x| *x *= b);
                }
            }
            {
                let (r1, r2) = (self.row(kp1), self.row(kp2));
                let (lo, hi) = self.phi.split_at_mut(r2.start);
                hi[..n].copy_from_slice(&lo[r1.clone()]);
                lo[r1].fill(0.0);
            }
            self.p.fill(0.0);
            for j in 1..=k {
                let i = kp1 - j;
                let gi = self.g[i];
                let (ri, rip1) = (self.row(i), self.row(i + 1));
                for l in 0..n {
                    self.p[l] += gi * self.phi[ri.start + l];
                    self.phi[ri.start + l] += self.phi[rip1.start + l];
                }
            }
            let h = self.h;
            if self.nornd {
                for l in 0..n {
                    self.p[l] = self.y[l] + h * self.p[l];
                }
            } else {
                let (r15, r16) = (self.row(15), self.row(16));
                for l in 0..n {
                    let tau = h * self.p[l] - self.phi[r15.start + l];
                    self.p[l] = self.y[l] + tau;
                    self.phi[r16.start + l] = (self.p[l] - self.y[l]) - tau;
                }
            }
            let x_new = self.x + h;
            let absh = h.abs();
            self.stats.evaluations += 1;
            let evaluated = if self.nornd {
                system.predicted(x_new, &mut self.p, &mut self.fp)
            } else {
                // The compensation of the predictor's sum is void for the components the system moved.
                self.y_corr.copy_from_slice(&self.p);
                let evaluated = system.predicted(x_new, &mut self.p, &mut self.fp);
                let r16 = self.row(16);
                for l in 0..n {
                    if self.p[l] != self.y_corr[l] {
                        self.phi[r16.start + l] = 0.0;
                    }
                }
                evaluated
            };
            let mut failure = None;
            let (mut erkm1, mut erk) = (0.0, 0.0);
            let mut knew = k;
            match evaluated {
                Err(e) => failure = Some(AttemptFailure::Evaluation(e)),
                Ok(()) => {
                    // Errors at orders k, k−1, k−2 as if the steps had been constant.
                    let r1 = self.row(1);
                    let (mut s2, mut s1, mut s0) = (0.0, 0.0, 0.0);
                    for l in 0..n {
                        let inv = 1.0 / self.wt[l];
                        let d = self.fp[l] - self.phi[r1.start + l];
                        if k >= 3 {
                            s2 += ((self.phi[(k - 2) * n + l] + d) * inv).powi(2);
                        }
                        if k >= 2 {
                            s1 += ((self.phi[(k - 1) * n + l] + d) * inv).powi(2);
                        }
                        s0 += (d * inv).powi(2);
                    }
                    let erkm2 = if k >= 3 { absh * self.sig[k - 1] * GSTR[k - 2] * s2.sqrt() } else { 0.0 };
                    erkm1 = if k >= 2 { absh * self.sig[k] * GSTR[k - 1] * s1.sqrt() } else { 0.0 };
                    let temp5 = absh * s0.sqrt();
                    let err = temp5 * (self.g[k] - self.g[kp1]);
                    erk = temp5 * self.sig[kp1] * GSTR[k];
                    if k >= 3 {
                        if erkm1.max(erkm2) <= erk {
                            knew = k - 1;
                        }
                    } else if k == 2 && erkm1 <= 0.5 * erk {
                        knew = k - 1;
                    }
                    // An estimate within the rounding that the conditioning amplifies passes, and does not
                    // shorten the next step (`estimate_rounding`).
                    let amplification = system.rounding_amplification();
                    let within_rounding = err > eps
                        && ((amplification > 1.0
                            && err <= self.estimate_rounding(absh * (self.g[k] - self.g[kp1]), k, amplification))
                            || system.crossing_within_rounding(err / eps * share, k));
                    if within_rounding {
                        erk = erk.min(p5eps);
                        erkm1 = erkm1.min(p5eps);
                        knew = k;
                    }
                    // An estimate that does not fall as the step is cut is rounding: it passes at its level.
                    let noise = |floor: &mut ShareFloor| floor.is_noise(h, err / eps * share, self.control.rtol);
                    if !(err <= eps || within_rounding || self.fixed || noise(&mut self.share_floor)) {
                        failure = Some(AttemptFailure::ErrorTest { error: err / eps });
                    } else if let Err(e) = self.correct_and_accept(system, x_new) {
                        failure = Some(AttemptFailure::Acceptance(e));
                    }
                }
            }
            let Some(failure) = failure else {
                self.share_floor.accepted(h, share);
                self.update_after_step(x_new, knew, erkm1, erk);
                return Ok(());
            };
            // Block 3: restore φ and ψ, reduce the step.
            match failure {
                AttemptFailure::ErrorTest { .. } => self.stats.error_test_failures += 1,
                _ => self.stats.evaluation_failures += 1,
            }
            if self.fixed {
                return Err(StepFailure::StepSizeTooSmall { t: self.x, h: self.h, last: Some(failure) });
            }
            self.phase1 = false;
            for i in 1..=k {
                let inv = 1.0 / self.beta[i];
                let (ri, rip1) = (self.row(i), self.row(i + 1));
                for l in 0..n {
                    self.phi[ri.start + l] = inv * (self.phi[ri.start + l] - self.phi[rip1.start + l]);
                }
            }
            for i in 2..=k {
                self.psi[i - 1] = self.psi[i] - h;
            }
            ifail += 1;
            let mut factor = 0.5;
            if ifail > 3 && matches!(failure, AttemptFailure::ErrorTest { .. }) && p5eps < 0.25 * erk {
                factor = (p5eps / erk).sqrt();
            }
            if ifail >= 3 {
                knew = 1;
            }
            self.h = factor * h;
            self.k = knew;
            if self.h < FOURU * self.x.abs() || self.h < f64::MIN_POSITIVE {
                return Err(StepFailure::StepSizeTooSmall { t: self.x, h: self.h, last: Some(failure) });
            }
        }
    }

    /// The rounding level, in the step's weighted norm, of the error estimate `coefficient · ‖f^p − φ^p_1‖`
    /// of an attempt at order `k` (`coefficient = h (g_k − g_{k+1})`) when each evaluation of `f` carries
    /// the rounding `10 ε · amplification · ‖f‖`. `f^p − φ^p_1` is `f` at the prediction less the value
    /// at the new time of the polynomial through the last `k` derivatives of the table; with equal steps
    /// that extrapolation weighs them by the binomial coefficients `C(k, j)`, whose absolute values add up
    /// to `2^k − 1`, so the difference carries at most `2^k` times the rounding of one evaluation. The
    /// derivatives of the table and at the prediction are evaluated at states of the step's neighbourhood,
    /// `‖f‖` at the start of the step stands for them all. This is already the worst case (the rounding of
    /// the evaluations all of one sign against the extrapolation's weights), so it carries no margin.
    fn estimate_rounding(&self, coefficient: f64, k: usize, amplification: f64) -> f64 {
        let f = self.norm(|l| self.yp[l]);
        coefficient * (1u64 << k) as f64 * 10.0 * f64::EPSILON * amplification * f
    }

    /// Block 0 of the first step: the starting step (STEP: `¼ √(tol/‖f‖)` unless a smaller one is
    /// given) and the rounding control.
    fn initialize(&mut self, remaining: f64, round: f64) {
        let n = self.n;
        let h_init = if self.h_restart_cap.is_finite() { None } else { self.control.h_init };
        let mut absh = h_init.unwrap_or(remaining.min(self.control.h_max).min(self.h_restart_cap));
        self.h_restart_cap = f64::INFINITY;
        if h_init.is_none() {
            let sum = self.norm(|l| self.yp[l]);
            if 1.0 < 16.0 * sum * absh * absh {
                absh = 0.25 * (1.0 / sum).sqrt();
            }
        }
        self.h = absh.max(FOURU * self.x.abs());
        self.phi[..n].copy_from_slice(&self.yp);
        self.phi[n..2 * n].fill(0.0);
        self.hold = 0.0;
        self.k = 1;
        self.kold = 0;
        self.phase1 = true;
        self.nornd = 0.5 > 100.0 * round;
        if !self.nornd {
            let r15 = self.row(15);
            self.phi[r15].fill(0.0);
        }
        self.started = true;
    }

    /// Block 1: `β, α, ψ, σ` and the integration coefficients `g` for the step `h` at order `k`,
    /// recomputing only what changed since the last step (nothing once `k + 1` steps had this `h`).
    fn coefficients(&mut self) {
        let (k, kp1, kp2) = (self.k, self.k + 1, self.k + 2);
        let h = self.h;
        if h != self.hold {
            self.ns = 0;
        }
        if self.ns <= self.kold {
            self.ns += 1;
        }
        let ns = self.ns;
        let nsp1 = ns + 1;
        if k < ns {
            return;
        }
        self.beta[ns] = 1.0;
        self.alpha[ns] = 1.0 / ns as f64;
        let mut temp1 = h * ns as f64;
        self.sig[nsp1] = 1.0;
        for i in nsp1..=k {
            let temp2 = self.psi[i - 1];
            self.psi[i - 1] = temp1;
            self.beta[i] = self.beta[i - 1] * self.psi[i - 1] / temp2;
            temp1 = temp2 + h;
            self.alpha[i] = h / temp1;
            self.sig[i + 1] = i as f64 * self.alpha[i] * self.sig[i];
        }
        self.psi[k] = temp1;
        // g: initialize v and w on the first step of a new size, else update them.
        if ns <= 1 {
            for iq in 1..=k {
                self.v[iq] = 1.0 / (iq * (iq + 1)) as f64;
                self.w[iq] = self.v[iq];
            }
        } else {
            if k > self.kold {
                self.v[k] = 1.0 / (k * kp1) as f64;
                for j in 1..=ns.saturating_sub(2) {
                    let i = k - j;
                    self.v[i] -= self.alpha[j + 1] * self.v[i + 1];
                }
            }
            let temp5 = self.alpha[ns];
            for iq in 1..=kp1 - ns {
                self.v[iq] -= temp5 * self.v[iq + 1];
                self.w[iq] = self.v[iq];
            }
            self.g[nsp1] = self.w[1];
        }
        for i in ns + 2..=kp1 {
            let temp6 = self.alpha[i - 1];
            for iq in 1..=kp2 - i {
                self.w[iq] -= temp6 * self.w[iq + 1];
            }
            self.g[i] = self.w[1];
        }
    }

    /// Block 4, first half: the corrected solution into `y_new`, adjusted and evaluated by the system
    /// (`fp` then holds `f` there).
    fn correct_and_accept<S: OdeSystem + ?Sized>(
        &mut self,
        system: &mut S,
        x_new: f64,
    ) -> Result<(), EvaluationFailure> {
        let n = self.n;
        let temp1 = self.h * self.g[self.k + 1];
        let r1 = self.row(1);
        if self.nornd {
            for l in 0..n {
                self.y_new[l] = self.p[l] + temp1 * (self.fp[l] - self.phi[r1.start + l]);
            }
        } else {
            let r16 = self.row(16);
            for l in 0..n {
                let rho = temp1 * (self.fp[l] - self.phi[r1.start + l]) - self.phi[r16.start + l];
                self.y_new[l] = self.p[l] + rho;
                // The compensation of this sum is stored into row 15 once the step is accepted.
                self.phi[r16.start + l] = (self.y_new[l] - self.p[l]) - rho;
            }
        }
        // The system may move y_new; the compensation terms of the components it moved are void.
        if self.nornd {
            self.stats.evaluations += 1;
            return system.accept(x_new, &mut self.y_new, &mut self.fp);
        }
        self.y_corr.copy_from_slice(&self.y_new);
        self.stats.evaluations += 1;
        system.accept(x_new, &mut self.y_new, &mut self.fp)?;
        let r16 = self.row(16);
        for l in 0..n {
            if self.y_new[l] != self.y_corr[l] {
                self.phi[r16.start + l] = 0.0;
            }
        }
        Ok(())
    }

    /// Block 4, second half: the new solution and differences, then order and step for the next step.
    fn update_after_step(&mut self, x_new: f64, knew: usize, erkm1: f64, erk: f64) {
        let n = self.n;
        let (k, kp1, kp2) = (self.k, self.k + 1, self.k + 2);
        let h = self.h;
        let absh = h.abs();
        self.kold = k;
        self.hold = h;
        self.x_old = self.x;
        self.x = x_new;
        std::mem::swap(&mut self.y, &mut self.y_new);
        self.yp.copy_from_slice(&self.fp);
        if !self.nornd {
            let (r15, r16) = (self.row(15), self.row(16));
            self.phi.copy_within(r16, r15.start);
        }
        // Differences for the next step.
        let (r1, rkp1, rkp2) = (self.row(1), self.row(kp1), self.row(kp2));
        for l in 0..n {
            let d = self.fp[l] - self.phi[r1.start + l];
            self.phi[rkp1.start + l] = d;
            self.phi[rkp2.start + l] = d - self.phi[rkp2.start + l];
        }
        for i in 1..=k {
            let ri = self.row(i);
            for l in 0..n {
                self.phi[ri.start + l] += self.phi[rkp1.start + l];
            }
        }
        self.stats.steps += 1;
        self.stats.order_counts[k] += 1;
        self.stats.sum_h_squared += h * h;
        if self.fixed {
            return;
        }
        // Order for the next step: the estimate at order k + 1 is made only when the last k + 1 steps
        // had one size, and not in the start phase nor when the order is already to be lowered.
        let max_order = self.control.max_order;
        let lower = knew + 1 == k;
        if lower || k == max_order {
            self.phase1 = false;
        }
        let mut erk = erk;
        enum Next {
            Raise(f64),
            Lower,
            Keep,
        }
        let next = if self.phase1 {
            Next::Raise(0.0)
        } else if lower {
            Next::Lower
        } else if kp1 > self.ns {
            Next::Keep
        } else {
            let erkp1 = absh * GSTR[kp1] * self.norm(|l| self.phi[rkp2.start + l]);
            if k == 1 {
                if erkp1 >= 0.5 * erk {
                    Next::Keep
                } else {
                    Next::Raise(erkp1)
                }
            } else if erkm1 <= erk.min(erkp1) {
                Next::Lower
            } else if erkp1 >= erk || k == max_order {
                Next::Keep
            } else {
                Next::Raise(erkp1)
            }
        };
        match next {
            Next::Raise(e) if k < max_order => {
                self.k = kp1;
                erk = e;
            }
            Next::Lower => {
                self.k = k - 1;
                erk = erkm1;
            }
            _ => {}
        }
        // Step for the next step at the new order: the estimate is of order h^(k+1), its ratio to the
        // step's share of the tolerance of order h^power.
        let p5eps = 0.5;
        let knext = self.k;
        let power = self.control.tolerances().error_power(h, knext + 1);
        let hnew = if self.phase1 || p5eps >= erk * 2f64.powf(power) {
            h + h
        } else if p5eps >= erk {
            h
        } else {
            let r = (p5eps / erk).powf(1.0 / power);
            (absh * r.clamp(0.5, 0.9)).max(FOURU * self.x.abs())
        };
        self.h = hnew;
    }

    /// The solution and its derivative at `t` (normally within the last step) from the interpolating
    /// polynomial of the last step (INTRP). Does not allocate.
    pub(crate) fn interpolate(&self, t: f64, y_out: &mut [f64], yp_out: &mut [f64]) {
        let n = self.n;
        let hi = t - self.x;
        let ki = self.kold + 1;
        let mut g = [0.0; C];
        let mut w = [0.0; C];
        let mut rho = [0.0; C];
        g[1] = 1.0;
        rho[1] = 1.0;
        for (i, wi) in w.iter_mut().enumerate().take(ki + 1).skip(1) {
            *wi = 1.0 / i as f64;
        }
        let mut term = 0.0;
        for j in 2..=ki {
            let psijm1 = self.psi[j - 1];
            let gamma = (hi + term) / psijm1;
            let eta = hi / psijm1;
            for i in 1..=ki + 1 - j {
                w[i] = gamma * w[i] - eta * w[i + 1];
            }
            g[j] = w[1];
            rho[j] = gamma * rho[j - 1];
            term = psijm1;
        }
        y_out.fill(0.0);
        yp_out.fill(0.0);
        for j in 1..=ki {
            let i = ki + 1 - j;
            let r = self.row(i);
            for l in 0..n {
                y_out[l] += g[i] * self.phi[r.start + l];
                yp_out[l] += rho[i] * self.phi[r.start + l];
            }
        }
        for l in 0..n {
            y_out[l] = self.y[l] + hi * y_out[l];
        }
    }
}
