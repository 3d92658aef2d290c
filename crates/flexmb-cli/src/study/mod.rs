//! `flexmb study STUDY.toml`: one model in several variants (mode sets, parameter values), each run
//! with several integrators; a table with the seed's columns (type, T_end, CPU, RMS step size) plus
//! steps and rejected steps, and plots that overlay one output column of every case. The runs go on
//! `--jobs` threads at once (`work_queue`); what is printed and written is the same in any case.

mod work_queue;


use std::fmt::Write as _;
use std::path::{Path, PathBuf};


use crate::check::check_model;
use flexmb_files::integrator_choice::parse_study_integrator;
use flexmb_files::model_file::{load_model_with, LoadOptions};
use flexmb_files::SimulationDefaults;
use flexmb_files::results::{record_run, RecordedRun};
use flexmb_files::Restart;
use crate::run::CliError;

pub use flexmb_files::study_file::{load_study, parse_study, Case, Published, Study};
pub use work_queue::default_jobs;

/// One run of a study: a case with an integrator.
#[derive(Clone, Debug)]
pub struct StudyRun {
    pub case: String,
    pub integrator: String,
    pub t_end: f64,
    pub t_reached: f64,
    /// Wall time of the integration (s).
    pub cpu: f64,
    pub rms_step: f64,
    pub steps: usize,
    pub rejected: usize,
    pub csv: PathBuf,
    pub failure: Option<String>,
    pub published: Option<Published>,
}

/// What a study produced.
#[derive(Clone, Debug)]
pub struct StudyReport {
    pub runs: Vec<StudyRun>,
    /// The table as Markdown (also written to `table.md`).
    pub table: String,
    pub files: Vec<PathBuf>,
}

/// Runs every case of the study at `path` with every integrator, writing each run's CSV and JSON
/// summary, the table and the plots into `out_dir` (default `out/<study name>`); `t_end` overrides
/// the study's end time; `parameters` replace values of the model's `[parameters]` in every case
/// (a case's own value of the same parameter wins). The (case, integrator) runs go on `jobs` threads at once (each loads the
/// model itself and writes its own files); the lines printed and the table are in the study's order,
/// as with one job.
pub fn run_study(
    path: &Path,
    out_dir: Option<&Path>,
    t_end: Option<f64>,
    parameters: &[(String, f64)],
    jobs: usize,
    quiet: bool,
) -> Result<StudyReport, CliError> {
    let mut study = load_study(path).map_err(|e| CliError(e.to_string()))?;
    for case in &mut study.cases {
        case.overrides.parameters.splice(0..0, parameters.iter().cloned());
    }
    if let Some(t) = t_end {
        if !(t > 0.0 && t.is_finite()) {
            return Err(CliError(format!("--t-end must be a positive number, got {t}")));
        }
        study.t_end = Some(t);
    }
    let out_dir = out_dir.map(Path::to_path_buf).unwrap_or_else(|| Path::new("out").join(&study.name));
    std::fs::create_dir_all(&out_dir).map_err(|e| CliError(format!("cannot create {}: {e}", out_dir.display())))?;
    let pairs: Vec<(&Case, &String)> =
        study.cases.iter().flat_map(|case| study.integrators.iter().map(move |integrator| (case, integrator))).collect();
    let mut runs = Vec::new();
    let run_pair = |index: usize| run_case(&study, pairs[index].0, pairs[index].1, &out_dir);
    work_queue::run_in_order(pairs.len(), jobs, run_pair, |run| {
        if !quiet {
            println!("{}", run_line(&run));
        }
        runs.push(run);
    })?;
    let table = table(&study, &runs);
    let table_path = out_dir.join("table.md");
    std::fs::write(&table_path, &table).map_err(|e| CliError(format!("cannot write {}: {e}", table_path.display())))?;
    let mut files = vec![table_path];
    files.extend(plot_cases(&study, &runs, &out_dir)?);
    if !quiet {
        println!("\n{table}");
        for f in &files {
            println!("wrote {}", f.display());
        }
    }
    Ok(StudyReport { runs, table, files })
}

fn run_case(study: &Study, case: &Case, integrator: &str, out_dir: &Path) -> Result<StudyRun, CliError> {
    let options = LoadOptions { overrides: case.overrides.clone(), ..crate::limits::load_options() };
    let loaded = load_model_with(&study.model, &options).map_err(|e| CliError(format!("{}: {e}", case.location)))?;
    let model = &loaded.model;
    let d = loaded.simulation;
    let (t_end, rtol, atol) = (study.t_end.unwrap_or(d.t_end), study.rtol.unwrap_or(d.rtol), study.atol.unwrap_or(d.atol));
    let (method, max_order) = parse_study_integrator(integrator).map_err(CliError)?;
    flexmb_files::output_limits::check_output_rows(t_end, d.output_step, d.max_output_rows, false)
        .map_err(|e| CliError(format!("{}: {}: {e}", case.location, study.model.display())))?;
    let assembly = crate::limits::assembly_settings(&d)?;
    check_model(model, assembly).map_err(|e| CliError(format!("{}: {}: {e}", case.location, study.model.display())))?;
    let stem = format!("{}-{}", case.name, integrator.replace(':', "-order"));
    let csv_path = out_dir.join(format!("{stem}.csv"));
    let summary_path = out_dir.join(format!("{stem}.json"));
    let max_order = max_order.or(d.max_order);
    let settings = SimulationDefaults { t_end, rtol, atol, method, max_order, ..d }.settings(model, assembly);
    let model_file = study.model.display().to_string();
    let RecordedRun { report, error: failure, .. } =
        record_run(model, &settings, &model_file, (&csv_path, &summary_path), Restart::default(), &mut |_| {}, &|| None)?;
    Ok(StudyRun {
        case: case.name.clone(),
        integrator: integrator.to_string(),
        t_end,
        t_reached: report.t_reached,
        cpu: report.wall_time,
        rms_step: report.stats.rms_step(),
        steps: report.stats.steps,
        rejected: report.stats.rejected_steps(),
        csv: csv_path,
        failure,
        published: case.published,
    })
}

fn run_line(run: &StudyRun) -> String {
    let status = match &run.failure {
        None => "completed".to_string(),
        Some(e) => format!("FAILED at t = {:.6} s: {e}", run.t_reached),
    };
    format!(
        "{:<8} {:<10} {:>7} steps, RMS step {:.3e} s, {:.3} s: {status}",
        run.case, run.integrator, run.steps, run.rms_step, run.cpu
    )
}

/// The seed's table (type, T_end, CPU, RMS step size) plus integrator, steps and rejected steps, and
/// the published figures beside ours where the study gives them.
fn table(study: &Study, runs: &[StudyRun]) -> String {
    let with_published = runs.iter().any(|r| r.published.is_some());
    let mut t = String::new();
    let _ = writeln!(t, "Study {} ({}): {} cases × {} integrators\n", study.name, study.model.display(), study.cases.len(), study.integrators.len());
    let _ = write!(t, "| type | integrator | T_end [s] | CPU [s] | RMS step size [s] | steps | rejected |");
    if with_published {
        let _ = write!(t, " published CPU [s] | published RMS step [s] | CPU ratio |");
    }
    let _ = writeln!(t);
    let _ = write!(t, "|---|---|---|---|---|---|---|");
    if with_published {
        let _ = write!(t, "---|---|---|");
    }
    let _ = writeln!(t);
    for r in runs {
        // In full ({:?}: 2.0, 0.02): one decimal printed a 0.02 s run as 0.0.
        let t_end = if r.failure.is_some() { format!("{:.4} (failed)", r.t_reached) } else { format!("{:?}", r.t_end) };
        let _ = write!(t, "| {} | {} | {t_end} | {:.3} | {:.4e} | {} | {} |", r.case, r.integrator, r.cpu, r.rms_step, r.steps, r.rejected);
        if with_published {
            let p = r.published.unwrap_or(Published { t_end: None, cpu: None, rms_step: None });
            let cpu = p.cpu.map_or("–".to_string(), |c| format!("{c}"));
            let step = p.rms_step.map_or("–".to_string(), |s| format!("{s:.4e}"));
            // The ratio compares like with like only when the run went as far as the published one.
            let same_end = p.t_end.is_none_or(|t| (t - r.t_end).abs() <= 1e-9 * t) && r.failure.is_none();
            let ratio = match p.cpu {
                Some(c) if same_end => format!("1 : {:.0}", c / r.cpu.max(1e-9)),
                _ => "–".to_string(),
            };
            let _ = write!(t, " {cpu} | {step} | {ratio} |");
        }
        let _ = writeln!(t);
    }
    t
}

/// One plot per requested column, a curve per case, from the runs of the first integrator.
fn plot_cases(study: &Study, runs: &[StudyRun], out_dir: &Path) -> Result<Vec<PathBuf>, CliError> {
    let Some(first) = study.integrators.first() else { return Ok(Vec::new()) };
    let csvs: Vec<&Path> = runs.iter().filter(|r| &r.integrator == first).map(|r| r.csv.as_path()).collect();
    let mut files = Vec::new();
    for column in &study.plot {
        let options = crate::plot::PlotOptions {
            files: csvs.iter().map(|p| p.to_path_buf()).collect(),
            y: vec![column.clone()],
            x: "t".to_string(),
            out: Some(out_dir.join(format!("{column}-{first}.png"))),
            title: Some(format!("{}: {column} ({first})", study.name)),
            size: crate::plot::DEFAULT_SIZE,
            window: crate::plot::TimeWindow::default(),
        };
        files.push(crate::plot::run_plot(&options)?);
    }
    Ok(files)
}
