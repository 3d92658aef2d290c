//! A second run of the same model alongside a run (the shadow), stepped as far as the run's output
//! times ask and its frames handed over one output time at a time: the divergence check's shadow (started
//! a few tolerances away) and the global error estimate's (the same start at a finer tolerance).

use super::{OutputFrame, OutputSink, Simulation};

/// The shadow and its output frames not yet compared.
pub(super) struct ShadowRun {
    simulation: Box<Simulation>,
    /// The shadow's output frames not yet compared, each `[t, q…, v…, values…]`.
    pending: Vec<f64>,
    /// The frame at the last time asked, `[t, q…, v…, values…]`.
    current: Vec<f64>,
    nq: usize,
    nv: usize,
}

/// Collects the shadow's frames as flat rows `[t, q…, v…, values…]`.
struct PendingFrames<'a>(&'a mut Vec<f64>);

impl OutputSink for PendingFrames<'_> {
    fn write_frame(&mut self, frame: &OutputFrame) -> Result<(), String> {
        self.0.push(frame.t);
        self.0.extend_from_slice(frame.q);
        self.0.extend_from_slice(frame.v);
        self.0.extend_from_slice(frame.values);
        Ok(())
    }
}

/// What the shadow has at an output time of the run.
pub(super) enum ShadowFrame {
    /// Its frame there, read by [`ShadowRun::q`], [`ShadowRun::v`] and [`ShadowRun::values`].
    At,
    /// No frame at that time (the grids differ; not with the same settings' grid).
    Missing,
    /// The shadow reached its end or failed before that time: no more frames.
    Ended,
}

impl ShadowRun {
    /// The shadow `simulation`, not yet stepped (its initial state set as its user wants).
    pub(super) fn new(simulation: Simulation) -> Self {
        let (nq, nv) = (simulation.model.layout.nq, simulation.model.layout.nv);
        let stride = 1 + nq + nv + simulation.values.len();
        Self { simulation: Box::new(simulation), pending: Vec::with_capacity(64 * stride), current: vec![0.0; stride], nq, nv }
    }

    /// The shadow simulation.
    pub(super) fn simulation(&self) -> &Simulation {
        &self.simulation
    }

    /// Steps the shadow until it has reported its output at `t` (the run's output time), dropping its
    /// frames before it.
    pub(super) fn frame_at(&mut self, t: f64) -> ShadowFrame {
        let stride = self.current.len();
        let same_time = |a: f64| (a - t).abs() <= 1e-12 * (1.0 + t.abs());
        loop {
            while !self.pending.is_empty() && self.pending[0] < t && !same_time(self.pending[0]) {
                self.pending.drain(..stride);
            }
            if !self.pending.is_empty() {
                break;
            }
            if self.simulation.is_finished() || self.simulation.step(&mut PendingFrames(&mut self.pending)).is_err() {
                return ShadowFrame::Ended;
            }
        }
        if !same_time(self.pending[0]) {
            return ShadowFrame::Missing;
        }
        self.current.copy_from_slice(&self.pending[..stride]);
        self.pending.drain(..stride);
        ShadowFrame::At
    }

    /// The shadow's positions at the last frame [`frame_at`](Self::frame_at) found.
    pub(super) fn q(&self) -> &[f64] {
        &self.current[1..1 + self.nq]
    }

    /// The shadow's velocities there.
    pub(super) fn v(&self) -> &[f64] {
        &self.current[1 + self.nq..1 + self.nq + self.nv]
    }

    /// The shadow's output values there.
    pub(super) fn values(&self) -> &[f64] {
        &self.current[1 + self.nq + self.nv..]
    }
}
