//! The `flexmb` program.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use flexmb_cli::bench::{run_benchmarks, BenchCase};
use flexmb_cli::check::{check_model, describe, describe_flexible_bodies};
use flexmb_cli::compare::{compare_model, CompareOptions};
use flexmb_cli::modes::{run_modes, ModesOptions};
use flexmb_cli::run::{run_model, RunOptions};
use flexmb_fem::modes::EigenSolver;
use flexmb_fem::reduction::Basis;

/// flexmb: dynamics of articulated structures (rigid and flexible multibody systems).
#[derive(Parser)]
#[command(version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a model and write its outputs (CSV) and a summary (JSON).
    Run {
        /// Model file (TOML), e.g. models/slider_crank.toml.
        model: PathBuf,
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
        /// Integrator: bdf (default; stiff, variable order). Overrides the model's [simulation] integrator.
        #[arg(long)]
        integrator: Option<String>,
        /// Spectral radius at infinity of the generalized-α method (0 to 1).
        #[arg(long)]
        spectral_radius: Option<f64>,
        /// Directory for the result files.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Validate a model, assemble it, and report degrees of freedom and redundant constraints.
    Check {
        /// Model file (TOML).
        model: PathBuf,
    },
    /// Reduce a flexible body's FE model to a mode set: frequencies, mass properties, and the
    /// flexible-body file (JSON) that mechanism models use.
    Modes {
        /// FE model file (TOML, see docs/fe-model-file.md) or an Abaqus/CalculiX .inp mesh.
        fe_model: PathBuf,
        /// Mode set: N vibration and S static correction modes, e.g. 6N, 5S, 4N5S; default from the
        /// file's [modes] set.
        #[arg(long)]
        modes: Option<String>,
        /// Basis of the flexible body: the modes as computed (raw, as in the seed) or
        /// mass-orthonormalized; default from the file, else orthonormal.
        #[arg(long, value_enum)]
        basis: Option<BasisArg>,
        /// Flexible-body file to write (default out/NAME.json).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Also write the mode shapes as VTK (.vtu) into this directory, for ParaView.
        #[arg(long)]
        vtk: Option<PathBuf>,
        /// Eigensolver: dense for small models, Lanczos (shift-invert, sparse Cholesky) for large.
        #[arg(long, value_enum, default_value_t = SolverArg::Auto)]
        solver: SolverArg,
    },
    /// Run a model with several integrators and compare cost and accuracy against a tight reference.
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
        #[arg(long)]
        rtol: Option<f64>,
        /// Absolute error tolerance of every integrator.
        #[arg(long)]
        atol: Option<f64>,
        /// Spectral radius at infinity of the generalized-α method (0 to 1).
        #[arg(long, default_value_t = 0.9)]
        spectral_radius: f64,
    },
    /// Run the performance benchmarks and report cost per step and per simulated second.
    Bench {
        /// Which case to run (default: all).
        #[arg(long, value_enum)]
        case: Option<BenchCase>,
        /// Repetitions per case; the fastest is reported.
        #[arg(long, default_value_t = 5)]
        repeat: usize,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum BasisArg {
    Raw,
    Orthonormal,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum SolverArg {
    Auto,
    Dense,
    Lanczos,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { model, t_end, output_step, rtol, atol, integrator, spectral_radius, out, quiet } => {
            let options = RunOptions { t_end, output_step, rtol, atol, integrator, spectral_radius, out_dir: out, quiet };
            run_model(&model, &options).map(|_| ())
        }
        Command::Check { model } => flexmb_cli::load_model(&model)
            .map_err(|e| e.to_string())
            .and_then(|loaded| {
                print!("{}", describe_flexible_bodies(&loaded));
                check_model(&loaded.model, loaded.simulation.assembly())
                    .map(|report| print!("{}", describe(&loaded.model, &report)))
                    .map_err(|e| format!("{}: {e}", model.display()))
            })
            .map_err(flexmb_cli::run::CliError),
        Command::Modes { fe_model, modes, basis, out, vtk, solver } => {
            let options = ModesOptions {
                mode_set: modes,
                basis: basis.map(|b| match b {
                    BasisArg::Raw => Basis::Raw,
                    BasisArg::Orthonormal => Basis::Orthonormal,
                }),
                out,
                vtk,
                solver: match solver {
                    SolverArg::Auto => EigenSolver::Auto,
                    SolverArg::Dense => EigenSolver::Dense,
                    SolverArg::Lanczos => EigenSolver::Lanczos,
                },
            };
            run_modes(&fe_model, &options).map(|report| print!("{report}"))
        }
        Command::Compare { model, integrators, t_end, rtol, atol, spectral_radius } => {
            let options = CompareOptions { integrators, t_end, rtol, atol, spectral_radius };
            compare_model(&model, &options).map(|table| print!("{table}"))
        }
        Command::Bench { case, repeat } => run_benchmarks(case, repeat.max(1)).map_err(flexmb_cli::run::CliError),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
