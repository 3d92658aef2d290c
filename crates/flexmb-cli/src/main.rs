//! The `flexmb` program.
// The doc comments below are clap's help text for users: they name model-file tables such as
// `[simulation]` and placeholders such as `<stem>`, which are not links nor HTML for rustdoc.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use flexmb_cli::bench::{run_benchmarks, BenchCase, BenchIntegrator, BenchOptions};
use flexmb_cli::check::{check_model, describe, describe_columns, describe_flexible_bodies};
use flexmb_cli::compare::{compare_model, CompareOptions};
use flexmb_cli::work_precision::{work_precision, WorkPrecisionOptions};
use flexmb_cli::equilibrium::{run_equilibrium, EquilibriumOptions};
use flexmb_cli::modes::{run_modes, ModesOptions};
use flexmb_cli::parameters::parse_parameter;
use flexmb_cli::plot::{plot_run_outputs, run_plot, PlotOptions, TimeWindow, Scale, DEFAULT_SIZE};
use flexmb_cli::run::{run_model, RunFiles, RunOptions};
use flexmb_cli::spectrum::estimator::FrequencyBand;
use flexmb_cli::spectrum::{run_spectrum, SpectrumOptions};
use flexmb_fem::modes::EigenSolver;
use flexmb_fem::reduction::Basis;
use flexmb_fem::MassModel;

/// flexmb: dynamics of articulated structures (rigid and flexible multibody systems).
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per run of the program: the size of its largest variant costs nothing.
#[allow(clippy::large_enum_variant)]
/// The model and operating point of `flexmb linearize` and `flexmb eigen`.
#[derive(Args, Debug)]
struct OperatingPointArgs {
    /// Model file (TOML).
    model: PathBuf,
    /// Replace the value of a parameter of the model's [parameters] table: NAME=VALUE (repeatable).
    #[arg(long = "parameter", short = 'p', value_name = "NAME=VALUE", value_parser = parse_parameter)]
    parameter: Vec<(String, f64)>,
    /// The operating point: initial (the assembled initial state, its velocities included) or
    /// equilibrium.
    #[arg(long, value_name = "initial|equilibrium")]
    at: Option<String>,
    /// Linearize at the state a simulation with the model's [simulation] integrator reaches at T (s).
    #[arg(long, value_name = "T")]
    at_time: Option<f64>,
}

#[derive(Subcommand)]
// Parsed once per process: the size of the largest command's options does not matter.
#[allow(clippy::large_enum_variant)]
enum Command {
    /// Simulate a model and write its outputs (CSV) and a summary (JSON).
    Run {
        /// Model file (TOML), e.g. models/slider_crank.toml.
        model: PathBuf,
        /// Replace the value of a parameter of the model's [parameters] table: NAME=VALUE (repeatable).
        #[arg(long = "parameter", short = 'p', value_name = "NAME=VALUE", value_parser = parse_parameter)]
        parameter: Vec<(String, f64)>,
        /// End time (s); default from the model's [simulation].
        #[arg(long)]
        t_end: Option<f64>,
        /// Interval between output times (s).
        #[arg(long)]
        output_step: Option<f64>,
        /// Relative error tolerance of the integrator.
        #[arg(long)]
        rtol: Option<f64>,
        /// Absolute error tolerance of the integrator.
        #[arg(long)]
        atol: Option<f64>,
        /// The span of simulated time whose steps together may make an error of the tolerance: seconds,
        /// `run` (the run's length) or `step` (each step the whole tolerance, the classical error per
        /// step). Each step's local error is held to h / span of it (error per unit step), so that the
        /// global error falls in proportion to the tolerance; `run` keeps the global error within about
        /// 10 tolerances (docs/accuracy.md). Default the model's [simulation] tolerance_span, else `run`
        #[arg(long)]
        tolerance_span: Option<String>,
        /// Integrator: bdf (default; stiff, variable order). Overrides the model's [simulation] integrator.
        #[arg(long)]
        integrator: Option<String>,
        /// Spectral radius at infinity of the generalized-α method (0 to 1). Without --integrator it selects
        /// that method; with another --integrator it is an error.
        #[arg(long)]
        spectral_radius: Option<f64>,
        /// Largest step (s) of any integrator, whatever its error control allows (Adams' HMAX).
        /// Overrides the model's [simulation] max_step.
        #[arg(long, value_name = "H")]
        max_step: Option<f64>,
        /// Hold the generalized-α method's step at H seconds, without error control: the run takes
        /// t_end / H steps, the last one shortened to end on t_end (the peer's fixed-step generalized-α).
        /// Generalized-α only (--integrator gen-alpha). Overrides the model's [simulation] fixed_step.
        #[arg(long, value_name = "H")]
        fixed_step: Option<f64>,
        /// Run a second simulation alongside, started 30 tolerances away, and warn where the two separate
        /// exponentially (chaotic motion): the warning names the time from which the global error is not held
        /// to the tolerance and the estimated Lyapunov exponent. Doubles the cost. Default the model's
        /// [simulation] divergence_check, else off
        #[arg(long)]
        divergence_check: bool,
        /// Run a second simulation alongside from the same start at a tenth of the tolerances and estimate
        /// the run's global error from their difference (in the statistics); warn where it exceeds 10
        /// tolerances, with the tolerance that would deliver the one asked. Costs the finer run (about
        /// 1.6 to 2.5 times the run). Default the model's [simulation] global_error_estimate, else off
        #[arg(long)]
        global_error_estimate: bool,
        /// Global error control: estimate the global error (as --global-error-estimate) and, where it
        /// exceeds 10 tolerances, run again from the start at the tolerances that bring it to about one
        /// (at most twice); the results are the last run's. Default the model's [simulation]
        /// global_error_control, else off
        #[arg(long)]
        global_error_control: bool,
        /// Directory for the result files.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
        /// Also write a ParaView time series into this directory as the run proceeds: DIR/MODEL.pvd
        /// (bodies as their shapes or deformed FE meshes, joints as points) and its files in DIR/MODEL/.
        #[arg(long, value_name = "DIR")]
        vtk: Option<PathBuf>,
        /// Interval between ParaView frames (s), a multiple of the output step; default the model's
        /// [simulation] vtk_step, else the output step.
        #[arg(long, value_name = "DT", requires = "vtk")]
        vtk_step: Option<f64>,
        /// After the run, plot each output (or the columns named) to PNGs next to the CSV. Put it
        /// after the model file: `flexmb run MODEL --plot [COLUMN…]`.
        #[arg(long, num_args = 0.., value_name = "COLUMN")]
        plot: Option<Vec<String>>,
        /// Most output rows the run may write; default the model's [simulation] max_output_rows, else
        /// 10000000. A run that would write more is refused before it starts.
        #[arg(long, value_name = "N")]
        max_output_rows: Option<u64>,
        /// Most ParaView frames --vtk may write; default the model's [simulation] max_vtk_frames, else
        /// 100000.
        #[arg(long, value_name = "N", requires = "vtk")]
        max_vtk_frames: Option<u64>,
        /// Save the simulation's state (a JSON checkpoint) to FILE at the end of the run, or where
        /// SIGINT, SIGTERM or --pause-at stopped it, to continue later with --resume. Not written after a failure:
        /// a failed simulation cannot be continued.
        #[arg(long, value_name = "FILE")]
        save_state: Option<PathBuf>,
        /// Continue the run saved by --save-state in FILE (of the same model file and integrator) up to
        /// the end time, which may be later than the checkpoint's time. The CSV holds the rows after the
        /// checkpoint's time (the first run's CSV followed by these rows is one run's CSV); the JSON
        /// summary counts the whole run.
        #[arg(long, value_name = "FILE")]
        resume: Option<PathBuf>,
        /// Stop the run at the first step at or after T seconds, as an interruption (the steps are not
        /// shortened to land on T, so a run paused with --save-state and continued with --resume gives
        /// the results of one run to --t-end).
        #[arg(long, value_name = "T")]
        pause_at: Option<f64>,
    },
    /// Validate a model, assemble it, and report degrees of freedom and redundant constraints.
    Check {
        /// Model file (TOML).
        model: PathBuf,
        /// Replace the value of a parameter of the model's [parameters] table: NAME=VALUE (repeatable).
        #[arg(long = "parameter", short = 'p', value_name = "NAME=VALUE", value_parser = parse_parameter)]
        parameter: Vec<(String, f64)>,
    },
    /// Find the static equilibrium at t = 0 (gravity, springs, loads, drivers held there): print the
    /// iterations and residuals, write equilibrium.json (poses, modal coordinates, multipliers, joint
    /// reactions) and equilibrium.csv (the model's outputs there) into --out.
    Equilibrium {
        /// Model file (TOML).
        model: PathBuf,
        /// Replace the value of a parameter of the model's [parameters] table: NAME=VALUE (repeatable).
        #[arg(long = "parameter", short = 'p', value_name = "NAME=VALUE", value_parser = parse_parameter)]
        parameter: Vec<(String, f64)>,
        /// Directory for the result files.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Also write the equilibrium (deformed flexible bodies, joints) for ParaView: OUT/equilibrium.pvd.
        #[arg(long)]
        vtk: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Linearize a model at an operating point: mass, damping and stiffness in independent
    /// coordinates (M.mtx, C.mtx, K.mtx, Matrix Market), optionally a state-space model (A, B, C_out,
    /// D) for named inputs and outputs, and linearization.json. See docs/linear-analysis.md.
    Linearize {
        #[command(flatten)]
        point: OperatingPointArgs,
        /// An input of the state-space model (repeatable): NAME.x|y|z of an applied force or torque,
        /// NAME of a spring-damper, or NAME, NAME.rate, NAME.acceleration of an angle or displacement
        /// driver (its offset, rate and acceleration).
        #[arg(long = "input", value_name = "INPUT")]
        input: Vec<String>,
        /// An output of the state-space model: a measure of the model (repeatable).
        #[arg(long = "output", value_name = "MEASURE")]
        output: Vec<String>,
        /// Directory for the files.
        #[arg(long, default_value = "out/linearization")]
        out: PathBuf,
    },
    /// Eigen-analysis of a model at an operating point: frequencies, damping ratios, whirl and mode
    /// shapes of the whole mechanism (table and eigen.json). See docs/linear-analysis.md.
    Eigen {
        #[command(flatten)]
        point: OperatingPointArgs,
        /// One eigen-analysis per value of a parameter: NAME=START:STOP:COUNT (sweep.json, sweep.csv).
        #[arg(long, value_name = "NAME=START:STOP:COUNT", value_parser = flexmb_cli::eigen::parse_sweep)]
        sweep: Option<flexmb_cli::eigen::Sweep>,
        /// Directory for the files.
        #[arg(long, default_value = "out/eigen")]
        out: PathBuf,
        /// Also write a ParaView animation of every oscillating mode of the whole mechanism: OUT/MODEL_mode_K.pvd.
        #[arg(long)]
        vtk: bool,
        /// With --sweep: draw the Campbell diagram (frequencies against the parameter): OUT/campbell.png.
        #[arg(long)]
        plot: bool,
        /// With --plot: the 1x line f = S × parameter, S in Hz per unit of the parameter
        /// (0.15915494 = 1/(2π) for a spin in rad/s, 0.016666667 for rpm); crossings are printed.
        #[arg(long, value_name = "S")]
        one_per_rev: Option<f64>,
    },
    /// Reduce a flexible body's FE model to a mode set: frequencies, mass properties, and the
    /// flexible-body file (JSON) that mechanism models use.
    Modes {
        /// FE model file (TOML, see docs/fe-model-file.md) or an Abaqus/CalculiX .inp mesh.
        fe_model: PathBuf,
        /// Mode set: N vibration and S static correction modes, e.g. 6N, 5S, 4N5S; Craig–Bampton
        /// 20N12C (C: constraint modes of the held dofs); free interface 20F12A; default from the
        /// file's [modes] set.
        #[arg(long)]
        modes: Option<String>,
        /// Basis of the flexible body: the modes as computed (raw, as in the seed) or
        /// mass-orthonormalized; default from the file, else orthonormal.
        #[arg(long, value_enum)]
        basis: Option<BasisArg>,
        /// Mass of every element of the FE model: lumped at the nodes (diagonal, as in the seed) or
        /// consistent (the elements' displacement fields); default from the file's [fe_model] mass,
        /// else consistent for beams and solids and lumped for shells.
        #[arg(long, value_enum)]
        mass: Option<MassArg>,
        /// Flexible-body file to write (default out/NAME.json).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write the mode shapes as VTK (.vtu) into this directory, for ParaView, and an animation
        /// of each mode over one period (NAME_mode_LABEL.pvd).
        #[arg(long)]
        vtk: Option<PathBuf>,
        /// Eigensolver: dense for small models, Lanczos (shift-invert, sparse Cholesky) for large.
        #[arg(long, value_enum, default_value_t = SolverArg::Auto)]
        solver: SolverArg,
        /// Store each mode's stresses in the flexible-body file (at the nodes of solids, the
        /// surfaces of shells, the fibres of beams), for a run's stress output; default from the
        /// file's [modes] stresses.
        #[arg(long)]
        stresses: bool,
    },
    /// Run a model with several integrators and compare cost and accuracy against a tight reference; with
    /// --tolerances, a work-precision diagram (global error against steps) over a range of tolerances.
    Compare {
        /// Model file (TOML).
        model: PathBuf,
        /// Comma-separated integrators, e.g. bdf,adams,gen-alpha.
        #[arg(long, value_delimiter = ',', default_value = "bdf")]
        integrators: Vec<String>,
        /// End time (s); default from the model's [simulation].
        #[arg(long)]
        t_end: Option<f64>,
        /// Relative error tolerance of every integrator.
        #[arg(long, conflicts_with = "tolerances")]
        rtol: Option<f64>,
        /// Absolute error tolerance of every integrator.
        #[arg(long, conflicts_with = "tolerances")]
        atol: Option<f64>,
        /// Work-precision diagram: run every integrator at each of these tolerances (rtol = atol, comma-separated,
        /// e.g. 1e-3,1e-4,1e-5,1e-6), measure each run's global error against the reference in the norm of
        /// docs/accuracy.md (position outputs) and write OUT/MODEL_work_precision.svg (error against steps) and
        /// OUT/MODEL_work_precision.csv
        #[arg(long, value_delimiter = ',')]
        tolerances: Vec<f64>,
        /// The reference of --tolerances: METHOD:TOL, a run of the model, or FILE.csv, a result file with the
        /// model's position outputs' columns at its output times (a tight run made before, or a published solution)
        #[arg(long, default_value = flexmb_cli::work_precision::DEFAULT_REFERENCE, requires = "tolerances", value_parser = flexmb_cli::work_precision::parse_reference)]
        reference: flexmb_cli::work_precision::Reference,
        /// Directory for the diagram and table of --tolerances
        #[arg(long, default_value = "out", requires = "tolerances")]
        out: PathBuf,
        /// Spectral radius at infinity of the generalized-α method (0 to 1).
        #[arg(long, default_value_t = flexmb::integrate::GeneralizedAlphaConfig::DEFAULT_SPECTRAL_RADIUS)]
        spectral_radius: f64,
    },
    /// Run the performance benchmarks and report cost per step, per Newton iteration and per simulated
    /// second, steps, rejections by cause, Jacobians and factorizations.
    Bench {
        /// Cases or groups to run, comma-separated (default: all): peer, chain, pendulums, flexible,
        /// applications, or one case by name.
        #[arg(long, value_enum, value_delimiter = ',')]
        case: Vec<BenchCase>,
        /// Integrators, comma-separated (default: all three for the peer cases and the chains, bdf for
        /// the rest); adams-partitioning, the Adams method with coordinate partitioning, only when named.
        #[arg(long, value_enum, value_delimiter = ',')]
        integrator: Vec<BenchIntegrator>,
        /// Repetitions per case; the fastest is reported.
        #[arg(long, default_value_t = 5)]
        repeat: usize,
        /// Also write every measurement to this JSON file, to compare runs.
        #[arg(long)]
        json: Option<PathBuf>,
        /// The longest chain the `chain` group runs (rods; default: all, 4 to 1024 doubling).
        #[arg(long)]
        max_links: Option<usize>,
        /// The `chain` group as one chain of this many rods (any number from 1), e.g. `--case chain
        /// --links 32` for the cost of one Newton iteration at n = 32.
        #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
        links: Option<u64>,
    },
    /// Plot result columns against time (or another column); several result files are overlaid.
    Plot {
        /// Result files (CSV written by `flexmb run`); units come from the JSON summary beside each.
        #[arg(required = true)]
        results: Vec<PathBuf>,
        /// Columns on the y axis.
        #[arg(long, required = true, num_args = 1..)]
        y: Vec<String>,
        /// Column on the x axis.
        #[arg(long, default_value = "t")]
        x: String,
        /// Image to write, .png or .svg (default: next to the first CSV, <stem>_<column>.png).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Title (default: the columns and the files).
        #[arg(long)]
        title: Option<String>,
        /// Draw only the rows at or after this time (s), whatever column is along x.
        #[arg(long)]
        from: Option<f64>,
        /// Draw only the rows at or before this time (s).
        #[arg(long)]
        to: Option<f64>,
        /// Image width in pixels.
        #[arg(long, default_value_t = DEFAULT_SIZE.0)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = DEFAULT_SIZE.1)]
        height: u32,
    },
    /// Dominant frequencies of a result column: detrended, Hann-windowed, zero-padded FFT with refined peaks.
    Spectrum {
        /// Result file (CSV written by `flexmb run`).
        results: PathBuf,
        /// The column to analyse.
        #[arg(long)]
        y: String,
        /// Start of the record (s); default the first row.
        #[arg(long)]
        from: Option<f64>,
        /// End of the record (s); default the last row.
        #[arg(long)]
        to: Option<f64>,
        /// Number of peaks to report, largest first.
        #[arg(long, default_value_t = 5)]
        peaks: usize,
        /// Report only peaks at or above this frequency (Hz), e.g. a vibration over a slow gross motion.
        #[arg(long)]
        min_frequency: Option<f64>,
        /// Report only peaks at or below this frequency (Hz).
        #[arg(long)]
        max_frequency: Option<f64>,
        /// Also plot the amplitude spectrum to this image (.png or .svg).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Amplitude axis of the plot: log or linear.
        #[arg(long, value_enum, default_value_t = ScaleArg::Log)]
        scale: ScaleArg,
        /// Image width in pixels.
        #[arg(long, default_value_t = DEFAULT_SIZE.0)]
        width: u32,
        /// Image height in pixels.
        #[arg(long, default_value_t = DEFAULT_SIZE.1)]
        height: u32,
    },
    /// Run a study: a model in several variants (mode sets, parameters), each with several
    /// integrators; prints and writes a cost table and plots that overlay the variants.
    Study {
        /// Study file (TOML), e.g. models/door/study.toml.
        study: PathBuf,
        /// Directory for the runs, the table and the plots (default out/<study name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// End time (s) of every run, instead of the study's or the model's.
        #[arg(long)]
        t_end: Option<f64>,
        /// Replace the value of a parameter of the model's [parameters] table in every variant:
        /// NAME=VALUE (repeatable); a variant's own value of that parameter wins.
        #[arg(long = "parameter", short = 'p', value_name = "NAME=VALUE", value_parser = parse_parameter)]
        parameter: Vec<(String, f64)>,
        /// Runs at once, each on its own thread (default: the number of cores this process may
        /// use). The printed lines, the table and the files are the same for any number.
        #[arg(long, short, value_parser = clap::value_parser!(u32).range(1..))]
        jobs: Option<u32>,
        /// Print only the table.
        #[arg(long, short)]
        quiet: bool,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum ScaleArg {
    Log,
    Linear,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum BasisArg {
    Raw,
    Orthonormal,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum MassArg {
    Lumped,
    Consistent,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum SolverArg {
    Auto,
    Dense,
    Lanczos,
}

fn main() -> ExitCode {
    // Without it, a closed pipe would only be an error of the next line printed (a panic); with no handler
    // the program still runs, so a failure to register is not one of the program.
    let _ = flexmb_cli::interrupt::end_on_closed_pipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { model, parameter, t_end, output_step, rtol, atol, tolerance_span, integrator, spectral_radius, max_step, fixed_step, divergence_check, global_error_estimate, global_error_control, out, quiet, vtk, vtk_step, plot, max_output_rows, max_vtk_frames, save_state, resume, pause_at } => {
            let options = RunOptions {
                t_end,
                output_step,
                rtol,
                atol,
                tolerance_span,
                integrator,
                spectral_radius,
                max_step,
                fixed_step,
                divergence_check,
                global_error_estimate,
                global_error_control,
                out_dir: out,
                quiet,
                vtk_dir: vtk,
                vtk_step,
                max_output_rows,
                max_vtk_frames,
                save_state,
                resume,
                pause_at,
                parameters: parameter,
                catch_signals: true,
            };
            match run_model(&model, &options) {
                // Interrupted: the files are complete up to the last step; the status says which signal.
                Ok(RunFiles { interrupted: Some(signal), csv, summary }) => {
                    eprintln!(
                        "interrupted by {}: the rows computed so far are in {}, the summary in {}",
                        signal.name(),
                        csv.display(),
                        summary.display()
                    );
                    return ExitCode::from(signal.exit_status());
                }
                Ok(files) => match plot {
                    Some(columns) => plot_run_outputs(&files.csv, &columns).map(|images| print_plots(&images, quiet)),
                    None => Ok(()),
                },
                Err(e) => Err(e),
            }
        }
        Command::Check { model, parameter } => flexmb_files::load_model_with(&model, &flexmb_cli::parameters::load_options_with(&parameter))
            .map_err(|e| e.to_string())
            .and_then(|loaded| {
                print!("{}", describe_flexible_bodies(&loaded));
                let settings = flexmb_cli::limits::assembly_settings(&loaded.simulation).map_err(|e| e.0)?;
                check_model(&loaded.model, settings)
                    .map(|report| print!("{}{}", describe(&loaded.model, &report), describe_columns(&loaded.model)))
                    .map_err(|e| format!("{}: {e}", model.display()))
            })
            .map_err(flexmb_cli::run::CliError),
        Command::Equilibrium { model, parameter, out, vtk, quiet } => {
            let options = EquilibriumOptions { out_dir: out, vtk, parameters: parameter, quiet };
            run_equilibrium(&model, &options).map(|_| ())
        }
        Command::Linearize { point, input, output, out } => {
            flexmb_cli::linear_analysis::operating_point_choice(point.at.as_deref(), point.at_time)
                .and_then(|choice| {
                    let options = flexmb_cli::linear_analysis::LinearizeOptions { choice, inputs: input, outputs: output, out, parameters: point.parameter };
                    flexmb_cli::linear_analysis::run_linearize(&point.model, &options)
                })
                .map(|report| print!("{report}"))
        }
        Command::Eigen { point, sweep, out, vtk, plot, one_per_rev } => flexmb_cli::linear_analysis::operating_point_choice(point.at.as_deref(), point.at_time)
            .and_then(|choice| {
                let options = flexmb_cli::eigen::EigenOptions { choice, out, parameters: point.parameter, sweep, vtk, plot, one_per_rev };
                flexmb_cli::eigen::run_eigen(&point.model, &options)
            })
            .map(|report| print!("{report}")),
        Command::Modes { fe_model, modes, basis, mass, out, vtk, solver, stresses } => {
            let options = ModesOptions {
                mode_set: modes,
                basis: basis.map(|b| match b {
                    BasisArg::Raw => Basis::Raw,
                    BasisArg::Orthonormal => Basis::Orthonormal,
                }),
                mass: mass.map(|m| match m {
                    MassArg::Lumped => MassModel::Lumped,
                    MassArg::Consistent => MassModel::Consistent,
                }),
                out,
                vtk,
                solver: match solver {
                    SolverArg::Auto => EigenSolver::Auto,
                    SolverArg::Dense => EigenSolver::Dense,
                    SolverArg::Lanczos => EigenSolver::Lanczos,
                },
                stresses,
            };
            run_modes(&fe_model, &options).map(|report| print!("{report}"))
        }
        Command::Compare { model, integrators, t_end, rtol, atol, spectral_radius, tolerances, reference, out } => {
            if tolerances.is_empty() {
                let options = CompareOptions { integrators, t_end, rtol, atol, spectral_radius };
                compare_model(&model, &options).map(|table| print!("{table}"))
            } else {
                let options = WorkPrecisionOptions { integrators, tolerances, reference, t_end, spectral_radius, out };
                work_precision(&model, &options).map(|table| print!("{table}"))
            }
        }
        Command::Bench { case, integrator, repeat, json, max_links, links } => {
            let links = links.map(|n| n as usize);
            let options = BenchOptions { cases: case, integrators: integrator, repeat: repeat.max(1), json, max_links, links };
            run_benchmarks(&options).map_err(flexmb_cli::run::CliError)
        }
        Command::Plot { results, y, x, out, title, from, to, width, height } => {
            let window = TimeWindow { from, to };
            let options = PlotOptions { files: results, y, x, out, title, size: (width, height), window };
            run_plot(&options).map(|image| println!("plot: {}", image.display()))
        }
        Command::Spectrum { results, y, from, to, peaks, min_frequency, max_frequency, out, scale, width, height } => {
            let y_scale = match scale {
                ScaleArg::Log => Scale::Log,
                ScaleArg::Linear => Scale::Linear,
            };
            let band = FrequencyBand { min: min_frequency, max: max_frequency };
            let options = SpectrumOptions { file: results, y, from, to, peaks, band, out, y_scale, size: (width, height) };
            run_spectrum(&options).map(|report| print!("{report}"))
        }
        Command::Study { study, out, t_end, parameter, jobs, quiet } => {
            let jobs = jobs.map_or_else(flexmb_cli::study::default_jobs, |j| j as usize);
            flexmb_cli::study::run_study(&study, out.as_deref(), t_end, &parameter, jobs, quiet).map(|report| {
                if quiet {
                    print!("{}", report.table);
                }
            })
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Lists the images `run --plot` wrote.
fn print_plots(images: &[PathBuf], quiet: bool) {
    if !quiet {
        let paths: Vec<String> = images.iter().map(|p| p.display().to_string()).collect();
        println!("plots: {}", paths.join(", "));
    }
}
