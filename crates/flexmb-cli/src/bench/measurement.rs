//! What one benchmark case measured: the integrator's counters and the fastest run's wall times,
//! printed as a table row and written as a JSON record.

use std::time::Instant;

use flexmb::analysis::{simulate, SimulationSettings};
use flexmb::integrate::Stats;
use flexmb::Model;

/// The measurement of one case with one integrator.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// The case and its integrator.
    pub name: CaseName,
    /// Relative error tolerance.
    pub rtol: f64,
    /// Absolute error tolerance.
    pub atol: f64,
    /// Simulated time (s).
    pub t_end: f64,
    /// The integrator's counters of the fastest run (the same in every run).
    pub stats: Stats,
    /// Wall time of the integration alone (s), fastest run.
    pub integration_wall: f64,
    /// Wall time of the whole case (s) in the same run: the integration plus what comes before it
    /// (the initial-condition analyses; for the independent pendulums also building and checking the
    /// model).
    pub whole_wall: f64,
    /// Runs made; the fastest is reported.
    pub runs: usize,
    /// Why the run stopped before its end time, if it did (the counters are those up to there).
    pub failure: Option<String>,
}

impl Measurement {
    /// Integration wall time per accepted step (µs).
    pub fn us_per_step(&self) -> f64 {
        per(self.integration_wall * 1e6, self.stats.steps)
    }

    /// Integration wall time per Newton iteration (µs).
    pub fn us_per_newton_iteration(&self) -> f64 {
        per(self.integration_wall * 1e6, self.stats.newton_iterations)
    }

    /// Integration wall time per simulated second (s/s).
    pub fn wall_per_simulated_second(&self) -> f64 {
        self.integration_wall / self.t_end
    }

    /// Wall time before the integration (s): initial-condition analyses (and model building, where the
    /// case times it).
    pub fn setup_wall(&self) -> f64 {
        (self.whole_wall - self.integration_wall).max(0.0)
    }

    /// The header of [`row`](Self::row).
    pub fn header() -> String {
        format!(
            "{:<22} {:<9} {:>7} {:>5} {:>7} {:>6} {:>6} {:>8} {:>6} {:>7} {:>9} {:>9} {:>9} {:>8}",
            "case", "integr.", "tol", "t_end", "steps", "rej.N", "rej.E", "Newton", "Jac.", "LU", "us/step",
            "us/Newton", "s/sim.s", "setup s"
        )
    }

    /// One line of the table: counts, then costs per step, per Newton iteration and per simulated
    /// second, then the time before the integration.
    pub fn row(&self) -> String {
        let s = &self.stats;
        let mut line = format!(
            "{:<22} {:<9} {:>7.0e} {:>5} {:>7} {:>6} {:>6} {:>8} {:>6} {:>7} {:>9.1} {:>9.1} {:>9.4} {:>8.3}",
            self.name.case,
            self.name.integrator,
            self.rtol,
            self.t_end,
            s.steps,
            s.newton_failures,
            s.error_test_failures,
            s.newton_iterations,
            s.jacobian_evaluations,
            s.factorizations,
            self.us_per_step(),
            self.us_per_newton_iteration(),
            self.wall_per_simulated_second(),
            self.setup_wall(),
        );
        if let Some(failure) = &self.failure {
            line.push_str(&format!("  FAILED: {failure}"));
        }
        line
    }

    /// The record written by `--json`: every counter and derived cost, named.
    pub fn to_json(&self) -> serde_json::Value {
        let s = &self.stats;
        serde_json::json!({
            "group": self.name.group,
            "case": self.name.case,
            "integrator": self.name.integrator,
            "rtol": self.rtol,
            "atol": self.atol,
            "t_end": self.t_end,
            "steps": s.steps,
            "newton_failures": s.newton_failures,
            "error_test_failures": s.error_test_failures,
            "newton_iterations": s.newton_iterations,
            "residual_evaluations": s.residual_evaluations,
            "jacobian_evaluations": s.jacobian_evaluations,
            "factorizations": s.factorizations,
            "order_counts": s.order_counts,
            "rms_step": s.rms_step(),
            "integration_wall_s": self.integration_wall,
            "whole_wall_s": self.whole_wall,
            "setup_wall_s": self.setup_wall(),
            "us_per_step": self.us_per_step(),
            "us_per_newton_iteration": self.us_per_newton_iteration(),
            "wall_per_simulated_second": self.wall_per_simulated_second(),
            "runs": self.runs,
            "failure": self.failure,
        })
    }
}

fn per(total: f64, count: usize) -> f64 {
    if count == 0 {
        f64::NAN
    } else {
        total / count as f64
    }
}

/// What identifies a measured case: its group, name and integrator.
#[derive(Clone, Debug)]
pub struct CaseName {
    /// The group the case belongs to (`peer`, `chain`, `pendulums`, `flexible`, `applications`).
    pub group: &'static str,
    /// The case within it, e.g. `heavy-top` or `chain-64`.
    pub case: String,
    /// The integrator's name (`bdf`, `adams`, `gen-alpha`).
    pub integrator: &'static str,
}

/// Simulates `model` with `settings` `repeat` times (at least once) and keeps the fastest run. The
/// integration time is the report's; the whole time also holds the initial-condition analyses. A run
/// that stops early is measured up to there and not repeated.
pub fn measure_simulation(name: CaseName, model: &Model, settings: &SimulationSettings, repeat: usize) -> Measurement {
    measure_repeated(name, settings, repeat, &mut || {
        let start = Instant::now();
        let outcome = simulate(model, settings, &mut |_| {});
        (outcome, start.elapsed().as_secs_f64())
    })
}

/// The outcome of one timed run: the simulation's result and the wall time of the whole run (s).
pub type TimedRun = (Result<flexmb::analysis::SimulationReport, flexmb::analysis::SimulationError>, f64);

/// Makes `repeat` runs of `run` (at least one) and keeps the fastest; see [`measure_simulation`].
pub fn measure_repeated(
    name: CaseName,
    settings: &SimulationSettings,
    repeat: usize,
    run: &mut dyn FnMut() -> TimedRun,
) -> Measurement {
    let mut best = measure_once(&name, settings, run());
    for k in 1..repeat {
        if best.failure.is_some() {
            break;
        }
        let next = measure_once(&name, settings, run());
        if next.whole_wall < best.whole_wall {
            best = next;
        }
        best.runs = k + 1;
    }
    best
}

fn measure_once(name: &CaseName, settings: &SimulationSettings, (outcome, whole_wall): TimedRun) -> Measurement {
    let (report, failure) = match outcome {
        Ok(report) => (report, None),
        Err(e) => (*e.report.clone(), Some(e.to_string())),
    };
    Measurement {
        name: name.clone(),
        rtol: settings.tolerances.rtol,
        atol: settings.tolerances.atol,
        t_end: settings.t_end,
        stats: report.stats,
        integration_wall: report.wall_time,
        whole_wall,
        runs: 1,
        failure,
    }
}
