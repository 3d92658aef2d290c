//! What one benchmark case measured: the integrator's counters and the fastest run's times, printed
//! as a table row and written as a JSON record. Costs are in the thread's CPU time where the system
//! gives it (Linux), which other processes on a shared machine do not stretch as they stretch the
//! wall time; the wall times are recorded too.

use std::time::Instant;

use std::sync::Arc;

use flexmb::analysis::{OutputFrame, Simulation, SimulationError, SimulationReport, SimulationSettings};
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
    /// Time of the integration alone, fastest run.
    pub integration: Elapsed,
    /// Time of the whole case in the same run: the integration plus what comes before it (the
    /// initial-condition analyses; for the independent pendulums also the check).
    pub whole: Elapsed,
    /// Runs made; the fastest is reported.
    pub runs: usize,
    /// Why the run stopped before its end time, if it did (the counters are those up to there).
    pub failure: Option<String>,
}

impl Measurement {
    /// Integration time per accepted step (µs), CPU time where known ([`Elapsed::best`]).
    pub fn us_per_step(&self) -> f64 {
        per(self.integration.best() * 1e6, self.stats.steps)
    }

    /// Integration time per Newton iteration (µs; projection iterations for the Adams method).
    pub fn us_per_newton_iteration(&self) -> f64 {
        per(self.integration.best() * 1e6, self.stats.newton_iterations)
    }

    /// Integration time per simulated second (s/s).
    pub fn time_per_simulated_second(&self) -> f64 {
        self.integration.best() / self.t_end
    }

    /// Time before the integration (s): the initial-condition analyses (and the check, where the case
    /// times it).
    pub fn setup_time(&self) -> f64 {
        (self.whole.best() - self.integration.best()).max(0.0)
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
            "{:<22} {:<9} {:>7.0e} {:>5} {:>7} {:>6} {:>6} {:>8} {:>6} {:>7} {:>9.1} {:>9} {:>9.4} {:>8.3}",
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
            // None for a method that makes no Newton iterations (the Adams method on a model its
            // projections need no iteration for).
            Some(self.us_per_newton_iteration()).filter(|x| x.is_finite()).map_or("–".to_string(), |x| format!("{x:.1}")),
            self.time_per_simulated_second(),
            self.setup_time(),
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
            "integration_wall_s": self.integration.wall,
            "integration_cpu_s": self.integration.cpu,
            "whole_wall_s": self.whole.wall,
            "whole_cpu_s": self.whole.cpu,
            "setup_s": self.setup_time(),
            "us_per_step": self.us_per_step(),
            "us_per_newton_iteration": self.us_per_newton_iteration(),
            "time_per_simulated_second": self.time_per_simulated_second(),
            "clock": if self.integration.cpu.is_some() { "thread-cpu" } else { "wall" },
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

/// Simulates `model` with `settings` `repeat` times (at least once) and keeps the fastest run (see
/// [`timed_simulation`]). A run that stops early is measured up to there and not repeated.
pub fn measure_simulation(name: CaseName, model: &Model, settings: &SimulationSettings, repeat: usize) -> Measurement {
    measure_repeated(name, settings, repeat, &mut || timed_simulation(model, settings))
}

/// One run of `model` with `settings`, its start (the initial-condition analyses) and its integration
/// timed apart.
pub fn timed_simulation(model: &Model, settings: &SimulationSettings) -> TimedRun {
    let whole = Clocks::start();
    let started = Simulation::new(Arc::new(model.clone()), *settings);
    let integration = Clocks::start();
    match started {
        Ok(mut simulation) => {
            let run = simulation.run(&mut |_: &OutputFrame| {}, &|| None);
            let integration = integration.elapsed();
            let report = simulation.into_report();
            let outcome = run.map(|()| report.clone()).map_err(|cause| SimulationError { cause, report: Box::new(report) });
            TimedRun { outcome, whole: whole.elapsed(), integration }
        }
        Err(e) => TimedRun { outcome: Err(e), whole: whole.elapsed(), integration: Elapsed::default() },
    }
}

/// Wall time and the thread's CPU time elapsed (s); the CPU time where the system tells it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Elapsed {
    /// Wall-clock time (s).
    pub wall: f64,
    /// Time the calling thread spent on a CPU (s): unlike the wall time, not stretched by other
    /// processes sharing the machine. `None` where the system does not give it (not Linux).
    pub cpu: Option<f64>,
}

impl Elapsed {
    /// The CPU time where known, else the wall time (s).
    pub fn best(&self) -> f64 {
        self.cpu.unwrap_or(self.wall)
    }
}

/// The wall clock and the thread's CPU clock at a start.
#[derive(Clone, Copy, Debug)]
pub struct Clocks {
    wall: Instant,
    cpu: Option<f64>,
}

impl Clocks {
    /// Both clocks now.
    pub fn start() -> Self {
        Clocks { wall: Instant::now(), cpu: thread_cpu_time() }
    }

    /// The time elapsed on both since [`start`](Self::start).
    pub fn elapsed(&self) -> Elapsed {
        let cpu = match (self.cpu, thread_cpu_time()) {
            (Some(a), Some(b)) => Some(b - a),
            _ => None,
        };
        Elapsed { wall: self.wall.elapsed().as_secs_f64(), cpu }
    }
}

/// The calling thread's time on a CPU (s), the first field of Linux's `/proc/thread-self/schedstat`
/// (nanoseconds); `None` where it cannot be read. The engine is single-threaded, so this is the
/// run's CPU time.
pub fn thread_cpu_time() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: u64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns as f64 * 1e-9)
}

/// One timed run: the simulation's outcome, the time of the whole run and of its integration.
pub struct TimedRun {
    /// The report, or the failure with the report up to it.
    pub outcome: Result<SimulationReport, SimulationError>,
    /// The whole run: the integration and what comes before it.
    pub whole: Elapsed,
    /// The integration alone.
    pub integration: Elapsed,
}

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
        if next.whole.best() < best.whole.best() {
            best = next;
        }
        best.runs = k + 1;
    }
    best
}

fn measure_once(name: &CaseName, settings: &SimulationSettings, run: TimedRun) -> Measurement {
    let (report, failure) = match run.outcome {
        Ok(report) => (report, None),
        Err(e) => (*e.report.clone(), Some(e.to_string())),
    };
    Measurement {
        name: name.clone(),
        rtol: settings.tolerances.rtol,
        atol: settings.tolerances.atol,
        t_end: settings.t_end,
        stats: report.stats,
        integration: run.integration,
        whole: run.whole,
        runs: 1,
        failure,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The thread's CPU time grows while it works, and never by more than the wall time (one thread
    /// is on at most one CPU at a time).
    #[test]
    fn the_threads_cpu_time_grows_by_no_more_than_the_wall_time() {
        let clocks = Clocks::start();
        let mut x = 0.0f64;
        for k in 0..2_000_000 {
            x = (x + k as f64).sqrt();
        }
        let elapsed = clocks.elapsed();
        assert!(x > 0.0);
        if let Some(cpu) = elapsed.cpu {
            assert!(cpu > 0.0 && cpu <= elapsed.wall + 1e-6, "cpu {cpu} s, wall {} s", elapsed.wall);
        }
        assert_eq!(elapsed.best(), elapsed.cpu.unwrap_or(elapsed.wall));
    }
}
