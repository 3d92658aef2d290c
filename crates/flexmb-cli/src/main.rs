//! The `flexmb` program.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use flexmb_cli::bench::{run_benchmarks, BenchCase};
use flexmb_cli::check::{check_model, describe};
use flexmb_cli::run::{run_model, RunOptions};

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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run { model, t_end, output_step, rtol, atol, out, quiet } => {
            let options = RunOptions { t_end, output_step, rtol, atol, out_dir: out, quiet };
            run_model(&model, &options).map(|_| ())
        }
        Command::Check { model } => flexmb_cli::load_model(&model)
            .map_err(|e| e.to_string())
            .and_then(|loaded| {
                check_model(&loaded.model)
                    .map(|report| print!("{}", describe(&loaded.model, &report)))
                    .map_err(|e| format!("{}: {e}", model.display()))
            })
            .map_err(flexmb_cli::run::CliError),
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
