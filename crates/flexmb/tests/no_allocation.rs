//! `Bdf::step` and `Adams::step` do not allocate once warmed up (style.md principle 1): a counting global allocator,
//! in this test binary only, counts the allocations made by the test thread while it steps and records
//! each with a backtrace, so that a failure names the culprit.
//!
//! `SparseLu` uses faer's simplicial LU: faer 0.24.4's supernodal numeric LU allocates four times per
//! factorization (`sparse/linalg/lu.rs` lines 733, 1169, 1182, 1189), so it is not used. The strict test
//! below holds the whole step, faer included, to zero allocations.
#![allow(unsafe_code)] // the global allocator below; the engine itself stays free of unsafe code

mod support;

use std::sync::Arc;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use flexmb::force::{ForceElement, ForceFrame, ForceKind};
use flexmb::function::{Expression, TimeFunction};
use flexmb::integrate::{
    Adams, AdamsConfig, Bdf, BdfConfig, GeneralizedAlpha, GeneralizedAlphaConfig, Integrator, Stats, ToleranceSpan,
    Tolerances,
};
use flexmb::integrate::adams::ConstraintHandling;
use flexmb::joint::JointKind;
use flexmb::math::Vec3;
use flexmb::measure::{Measure, MeasureKind};
use flexmb::model::{BodyRef, Model, ModelBuilder};
use support::*;

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
static BACKTRACES: Mutex<Vec<String>> = Mutex::new(Vec::new());
/// Most allocations recorded with a backtrace in one window.
const RECORDED: usize = 20_000;

thread_local! {
    /// Count allocations of this thread (only the test thread while it steps).
    static COUNTING: Cell<bool> = const { Cell::new(false) };
    /// Inside the recording hook: do not count or record the hook's own allocations.
    static IN_HOOK: Cell<bool> = const { Cell::new(false) };
}

fn record() {
    let counting = COUNTING.try_with(Cell::get).unwrap_or(false);
    let in_hook = IN_HOOK.try_with(Cell::get).unwrap_or(true);
    if !counting || in_hook {
        return;
    }
    let n = ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    if n < RECORDED {
        IN_HOOK.with(|h| h.set(true));
        let trace = std::backtrace::Backtrace::force_capture().to_string();
        if let Ok(mut list) = BACKTRACES.lock() {
            list.push(trace);
        }
        IN_HOOK.with(|h| h.set(false));
    }
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        record();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        record();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        record();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `f` on this thread, and their backtraces (up to `RECORDED`).
fn count_allocations<R>(f: impl FnOnce() -> R) -> (usize, Vec<String>, R) {
    // One counting window at a time: the counter and the backtrace list are shared by the test threads.
    static WINDOW: Mutex<()> = Mutex::new(());
    let _window = WINDOW.lock().unwrap_or_else(|e| e.into_inner());
    BACKTRACES.lock().unwrap().clear();
    ALLOCATIONS.store(0, Ordering::Relaxed);
    COUNTING.with(|c| c.set(true));
    let r = f();
    COUNTING.with(|c| c.set(false));
    let traces = std::mem::take(&mut *BACKTRACES.lock().unwrap());
    (ALLOCATIONS.load(Ordering::Relaxed), traces, r)
}

/// A slider-crank (revolute, spherical, universal, translational joints; gravity) loaded by a
/// spring–damper with an actuator expression that reads a measure, a rotational spring–damper with an
/// actuator on the crank, and an applied force; optionally driven by an angle driver on the crank.
fn loaded_slider_crank(driven: bool) -> Model {
    let (r, l) = (0.1, 0.3);
    let mut b = ModelBuilder::new("loaded slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    let SliderCrank { crank_joint, slide, pivot_ground, pivot, rod_slider_end: rod_b, slider_pin } =
        slider_crank_linkage(&mut b, r, l, Some(Vec3::new(0.0, 0.0, 8.0)));
    let anchor = marker(&mut b, "anchor", BodyRef::Ground, Vec3::new(0.8, 0.0, 0.0));
    if driven {
        let f = TimeFunction::parse("8*t + 0.5*sin(3*t)").unwrap();
        joint(&mut b, "crank_motion", JointKind::AngleDriver { function: f }, pivot_ground, pivot);
    }
    let v = b.add_measure(Measure { name: "slider_v".into(), kind: MeasureKind::JointVelocity(slide) }).unwrap();
    let w = b.add_measure(Measure { name: "crank_rate".into(), kind: MeasureKind::JointRate(crank_joint) }).unwrap();
    let resolve = |name: &str| match name {
        "slider_v" => Some(v),
        "crank_rate" => Some(w),
        _ => None,
    };
    b.add_force(ForceElement {
        name: "spring".into(),
        kind: ForceKind::TranslationalSpringDamper {
            marker_i: anchor,
            marker_j: slider_pin,
            stiffness: 200.0,
            damping: 2.0,
            free_length: 0.35,
            actuator: Some(Expression::parse("2*sin(3*t) - 0.5*slider_v", &resolve).unwrap()),
        },
    }).unwrap();
    b.add_force(ForceElement {
        name: "motor".into(),
        kind: ForceKind::RotationalSpringDamper {
            joint: crank_joint,
            stiffness: 0.0,
            damping: 0.01,
            free_angle: 0.0,
            actuator: Some(Expression::parse("0.2 - 0.02*crank_rate", &resolve).unwrap()),
        },
    }).unwrap();
    b.add_force(ForceElement {
        name: "push".into(),
        kind: ForceKind::AppliedForce {
            marker: rod_b,
            components: [
                Expression::parse("0.1*cos(t)", &resolve).unwrap(),
                Expression::constant(0.0),
                Expression::parse("0.05*slider_v", &resolve).unwrap(),
            ],
            frame: ForceFrame::Global,
        },
    }).unwrap();
    b.build().unwrap()
}

/// A flexible beam-like body on a revolute under gravity, with initial modal rates and a force at its
/// tip: the modal kinematics, node markers, inertia and force terms all run inside the step.
fn flexible_pendulum() -> Model {
    let (mut b, _, tip) = lumped_flexible_pendulum([400.0, 3000.0, 9000.0], [0.1, 0.0, 0.0]);
    b.add_force(ForceElement {
        name: "push".into(),
        kind: ForceKind::AppliedForce {
            marker: tip,
            components: [Expression::constant(0.0), Expression::constant(0.0), Expression::parse("0.2*sin(5*t)", &|_| None).unwrap()],
            frame: ForceFrame::Global,
        },
    }).unwrap();
    b.build().unwrap()
}

/// Whether an allocation happened inside faer's sparse LU factorization.
fn in_faer_lu(trace: &str) -> bool {
    trace.contains("faer::sparse::linalg::lu") || trace.contains("factorize_supernodal_numeric_lu")
}

/// Steps `model` 20 times, then counts the allocations of up to `window` more steps (which must include
/// refactorizations, and with the tolerance held per step, whose steps the windows were chosen on,
/// also Jacobian re-evaluations and rejected attempts). Returns (allocations outside faer's LU
/// factorization with their backtraces, allocations inside it).
fn allocations_while_stepping(model: &Model, window: usize, span: ToleranceSpan) -> (Vec<String>, usize) {
    let (state, acc) = consistent_start(model);
    let tolerances = Tolerances { span, ..Tolerances::new(1e-7, 1e-7) };
    let mut bdf = Bdf::new(Arc::new(model.clone()), &state, &acc, tolerances, BdfConfig::default()).unwrap();
    let t_end = 3.0;
    for _ in 0..20 {
        bdf.step(t_end).unwrap();
    }
    let before: Stats = bdf.stats;
    let (count, traces, ()) = count_allocations(|| {
        for _ in 0..window {
            if bdf.t() >= t_end {
                break;
            }
            bdf.step(t_end).expect("step");
        }
    });
    let after = bdf.stats;
    assert_eq!(count, traces.len(), "every allocation recorded");
    let (faer, engine): (Vec<String>, Vec<String>) = traces.into_iter().partition(|t| in_faer_lu(t));
    let factorizations = after.factorizations - before.factorizations;
    eprintln!(
        "{}: {} steps counted (to t = {:.3} s), {} Jacobians, {factorizations} factorizations, {} rejected attempts; \
         {count} allocations: {} inside faer's LU factorization ({:.1} per factorization), {} elsewhere",
        model.name(),
        after.steps - before.steps,
        bdf.t(),
        after.jacobian_evaluations - before.jacobian_evaluations,
        after.rejected_steps() - before.rejected_steps(),
        faer.len(),
        faer.len() as f64 / factorizations.max(1) as f64,
        engine.len()
    );
    // The window exercises the expensive paths too: new Jacobians, refactorizations, rejected attempts
    // (the error per unit step over the run takes other steps, with none of the first and last in the
    // same windows: it is counted beside, for its own paths, the share's floors).
    assert!(after.steps - before.steps >= 100, "steps counted");
    assert!(factorizations > 0, "the iteration matrix was refactored in the window");
    if span == ToleranceSpan::Step {
        assert!(after.jacobian_evaluations > before.jacobian_evaluations, "a Jacobian was re-evaluated in the window");
        assert!(after.rejected_steps() > before.rejected_steps(), "a step attempt was rejected in the window");
    }
    (engine, faer.len())
}

fn first_traces(traces: &[String]) -> String {
    traces.iter().take(3).cloned().collect::<Vec<_>>().join("\n----------------\n")
}

/// Asserts that `window` BDF steps of `model` after warm-up with the tolerance's `span` allocate nothing.
fn assert_bdf_steps_do_not_allocate(model: &Model, window: usize, span: ToleranceSpan) {
    let (engine, in_faer) = allocations_while_stepping(model, window, span);
    assert!(
        engine.is_empty() && in_faer == 0,
        "{}: Bdf::step allocated {} times in faer's LU factorization and {} times elsewhere; first elsewhere:\n{}",
        model.name(),
        in_faer,
        engine.len(),
        first_traces(&engine)
    );
}

#[test]
fn bdf_step_does_not_allocate_after_warm_up() {
    for span in [ToleranceSpan::Step, ToleranceSpan::Run] {
        for driven in [false, true] {
            assert_bdf_steps_do_not_allocate(&loaded_slider_crank(driven), 400, span);
        }
    }
}

#[test]
fn bdf_step_of_a_flexible_model_does_not_allocate() {
    for span in [ToleranceSpan::Step, ToleranceSpan::Run] {
        assert_bdf_steps_do_not_allocate(&flexible_pendulum(), 5000, span);
    }
}

/// Steps the Adams method 20 times, then counts the allocations of up to `window` more steps and of an
/// interpolation inside each (the window must include rejected steps). Returns their backtraces and the
/// projection iterations made in the window.
fn adams_allocations_while_stepping(model: &Model, window: usize) -> (Vec<String>, usize) {
    let (state, acc) = consistent_start(model);
    let tolerances = Tolerances::new(1e-7, 1e-7);
    let mut adams = Adams::new(Arc::new(model.clone()), &state, &acc, tolerances, AdamsConfig::default()).unwrap();
    let t_end = 3.0;
    for _ in 0..20 {
        adams.step(t_end).unwrap();
    }
    let (mut q, mut v) = (vec![0.0; model.layout().nq], vec![0.0; model.layout().nv]);
    let before: Stats = *adams.stats();
    let (count, traces, ()) = count_allocations(|| {
        for _ in 0..window {
            if adams.t() >= t_end {
                break;
            }
            let t0 = adams.t();
            adams.step(t_end).expect("step");
            let t_mid = 0.5 * (t0 + adams.t());
            Integrator::interpolate(&mut adams, t_mid, &mut q, &mut v);
        }
    });
    let after = *adams.stats();
    assert_eq!(count, traces.len(), "every allocation recorded");
    eprintln!(
        "{} (adams): {} steps counted (to t = {:.3} s), {} factorizations, {} rejected attempts, {} projection \
         iterations; {count} allocations",
        model.name(),
        after.steps - before.steps,
        adams.t(),
        after.factorizations - before.factorizations,
        after.rejected_steps() - before.rejected_steps(),
        after.newton_iterations - before.newton_iterations,
    );
    assert!(after.steps - before.steps >= 100, "steps counted");
    assert!(after.rejected_steps() > before.rejected_steps(), "a step attempt was rejected in the window");
    (traces, after.newton_iterations - before.newton_iterations)
}

#[test]
fn adams_step_does_not_allocate_after_warm_up() {
    let mut projection_iterations = 0;
    for model in [loaded_slider_crank(false), loaded_slider_crank(true), flexible_pendulum()] {
        let (traces, iterations) = adams_allocations_while_stepping(&model, 3000);
        projection_iterations += iterations;
        assert!(
            traces.is_empty(),
            "{}: Adams::step allocated {} times; first:\n{}",
            model.name(),
            traces.len(),
            first_traces(&traces)
        );
    }
    assert!(projection_iterations > 0, "the projection iterated in a window");
}

/// The Adams method with coordinate partitioning on the chain of 16 rods (`Φ̂_u` of 64 rows, factored
/// sparse on kept pivots) and the slider-crank (dense): 20 steps, then up to `window` more, each with an
/// interpolation inside it, do not allocate, but for the steps that re-choose the partition (a new
/// pattern of `Φ̂_u`, analysed once per partition), which are counted apart.
#[test]
fn adams_step_with_partitioning_does_not_allocate_after_warm_up() {
    let partitioning = AdamsConfig { constraints: ConstraintHandling::Partitioning, ..Default::default() };
    for model in [peer_chain(16), loaded_slider_crank(false)] {
        let (state, acc) = consistent_start(&model);
        let mut adams = Adams::new(Arc::new(model.clone()), &state, &acc, Tolerances::new(1e-7, 1e-7), partitioning).unwrap();
        let t_end = 3.0;
        for _ in 0..20 {
            adams.step(t_end).unwrap();
        }
        let (mut q, mut v) = (vec![0.0; model.layout().nq], vec![0.0; model.layout().nv]);
        let (mut traces, mut steps, mut repartitioning_steps) = (Vec::new(), 0, 0);
        while steps < 300 && adams.t() < t_end {
            let repartitions = adams.partition().expect("partitioning").repartitions;
            let (_, step_traces, ()) = count_allocations(|| {
                let t0 = adams.t();
                adams.step(t_end).expect("step");
                let t_mid = 0.5 * (t0 + adams.t());
                Integrator::interpolate(&mut adams, t_mid, &mut q, &mut v);
            });
            if adams.partition().expect("partitioning").repartitions == repartitions {
                steps += 1;
                traces.extend(step_traces);
            } else {
                repartitioning_steps += 1;
            }
        }
        eprintln!("{} (adams, partitioning): {steps} steps counted, {repartitioning_steps} apart", model.name());
        assert!(steps >= 100, "{}: {steps} steps counted", model.name());
        assert!(traces.is_empty(), "{}: Adams::step allocated {} times; first:\n{}", model.name(), traces.len(), first_traces(&traces));
    }
}

/// Steps the generalized-α method 100 times, then counts the allocations of up to `window` more steps and
/// of an interpolation inside each. Returns their backtraces and the window's statistics.
fn generalized_alpha_allocations_while_stepping(
    model: &Model,
    alpha: GeneralizedAlphaConfig,
    window: usize,
) -> (Vec<String>, Stats) {
    let (state, acc) = consistent_start(model);
    let tolerances = Tolerances::new(1e-7, 1e-7);
    let mut ga = GeneralizedAlpha::new(Arc::new(model.clone()), &state, &acc, tolerances, alpha).unwrap();
    let t_end = 3.0;
    // faer's simplicial LU keeps its numeric storage between factorizations and grows it (doubling) when
    // a pivot sequence needs more fill than any before; on the stiff-slider pendulum that happens once,
    // between steps 50 and 100, hence the longer warm-up.
    for _ in 0..100 {
        ga.step(t_end).unwrap();
    }
    let (mut q, mut v) = (vec![0.0; model.layout().nq], vec![0.0; model.layout().nv]);
    let before: Stats = ga.stats;
    let (count, traces, ()) = count_allocations(|| {
        for _ in 0..window {
            if ga.t() >= t_end {
                break;
            }
            let t0 = ga.t();
            ga.step(t_end).expect("step");
            let t_mid = 0.5 * (t0 + ga.t());
            Integrator::interpolate(&mut ga, t_mid, &mut q, &mut v);
        }
    });
    let after = ga.stats;
    assert_eq!(count, traces.len(), "every allocation recorded");
    let window_stats = Stats {
        steps: after.steps - before.steps,
        error_test_failures: after.error_test_failures - before.error_test_failures,
        newton_failures: after.newton_failures - before.newton_failures,
        jacobian_evaluations: after.jacobian_evaluations - before.jacobian_evaluations,
        factorizations: after.factorizations - before.factorizations,
        ..Default::default()
    };
    eprintln!(
        "{} (gen-alpha): {} steps counted (to t = {:.3} s), {} Jacobians, {} factorizations, {} rejected attempts; \
         {count} allocations",
        model.name(),
        window_stats.steps,
        ga.t(),
        window_stats.jacobian_evaluations,
        window_stats.factorizations,
        window_stats.rejected_steps(),
    );
    assert!(window_stats.steps >= 100, "steps counted");
    assert!(window_stats.factorizations > 0, "the iteration matrix was refactored in the window");
    (traces, window_stats)
}

#[test]
fn generalized_alpha_step_does_not_allocate_after_warm_up() {
    let (mut jacobians, mut rejected) = (0, 0);
    let adaptive = GeneralizedAlphaConfig::default();
    let fixed = GeneralizedAlphaConfig { spectral_radius: 1.0, fixed_step: Some(0.01) };
    for (model, alpha) in [
        (loaded_slider_crank(false), adaptive),
        (loaded_slider_crank(true), adaptive),
        (flexible_pendulum(), adaptive),
        (pendulum_with_stiff_slider(1e-3), fixed),
    ] {
        let (traces, stats) = generalized_alpha_allocations_while_stepping(&model, alpha, 3000);
        jacobians += stats.jacobian_evaluations;
        rejected += stats.rejected_steps();
        assert!(
            traces.is_empty(),
            "{}: GeneralizedAlpha::step allocated {} times; first:\n{}",
            model.name(),
            traces.len(),
            first_traces(&traces)
        );
    }
    // The windows exercise the expensive paths too.
    assert!(jacobians > 0, "finite-difference parts re-evaluated in a window");
    assert!(rejected > 0, "a step attempt rejected in a window");
}

#[test]
fn counting_allocator_sees_allocations() {
    let (count, traces, v) = count_allocations(|| vec![1.0_f64; 100]);
    assert_eq!(v.len(), 100);
    assert!(count >= 1, "a Vec allocation is counted");
    assert!(!traces.is_empty() && traces[0].contains("counting_allocator_sees_allocations"), "with its backtrace");
}

/// `Simulation::step` adds nothing that allocates to the integrator's step: the outputs at the output
/// times (accelerations, output values, energies, the watchdog's checks) and the frame handed to a sink
/// are evaluated in workspaces made once.
#[test]
fn simulation_step_with_its_outputs_does_not_allocate() {
    use flexmb::analysis::{OutputFrame, Simulation};
    let model = Arc::new(loaded_slider_crank(false));
    let mut simulation = Simulation::new(model.clone(), settings(3.0, 0.002, 1e-7)).unwrap();
    let mut sink = |_: &OutputFrame| {};
    for _ in 0..20 {
        simulation.step(&mut sink).unwrap();
    }
    let (steps, frames_before) = (simulation.stats().steps, simulation.report().output_frames);
    let (count, traces, ()) = count_allocations(|| {
        for _ in 0..500 {
            simulation.step(&mut sink).unwrap();
        }
    });
    let counted_frames = simulation.report().output_frames - frames_before;
    assert!(simulation.stats().steps - steps == 500 && counted_frames > 100, "{counted_frames} frames counted");
    assert!(count == 0, "Simulation::step allocated {count} times; first:\n{}", first_traces(&traces));
}
