//! Fuzzing the `flexmb` program through its command line, as a new user would run it: mutations of
//! every shipped model, FE model and study file, of an `.inp` deck and the file it includes, and of
//! result CSVs written by short runs; mechanisms and FE models generated valid. Every command must end
//! in a success whose results are believable or in a clean error, within a wall-clock and a memory
//! bound. See docs/testing.md for what it covers, how to run it long and how to reproduce a failure.
//!
//! Environment: `FLEXMB_FUZZ_CASES` (default 400), `FLEXMB_FUZZ_SEED` (default 14), `FLEXMB_FUZZ_CASE`
//! (run that case alone and print it), `FLEXMB_FUZZ_FAMILY` (only the cases of one family),
//! `FLEXMB_FUZZ_VERBOSE=1` (print every case and what its commands did),
//! `FLEXMB_FUZZ_JOBS` (parallel commands, default the cores), `FLEXMB_FUZZ_TIMEOUT` (seconds per
//! command, default 10), `FLEXMB_FUZZ_MEMORY_MB` (virtual memory per command, default 2048),
//! `FLEXMB_FUZZ_STRICT=1` (ignore the allow-list of known findings), `FLEXMB_FUZZ_FAILURES` (where
//! failing cases are saved, default the temporary directory's `flexmb-fuzz-failures`).

mod cases;
mod fe_model;
mod known;
mod mechanism;
mod mutate;
mod outcome;
mod rng;
mod vetting;

use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use cases::{make_case, Case, Corpus, Family};
use outcome::{run_flexmb, Bounds, Class, Ran};

/// The cases of the default run, which `cargo test` runs: a few seconds on two cores.
const DEFAULT_CASES: u64 = 400;
/// The default seed: the issue that asked for the fuzzing.
const DEFAULT_SEED: u64 = 14;
/// Failing cases saved (with a copy of the worker's directory) per run, at most.
const SAVED_FAILURES: usize = 30;

struct Settings {
    seed: u64,
    cases: Vec<u64>,
    /// Print each case's input and outcome (for one case).
    verbose: bool,
    jobs: usize,
    bounds: Bounds,
    strict: bool,
    failures: PathBuf,
}

fn variable<T: std::str::FromStr>(name: &str) -> Option<T> {
    let text = std::env::var(name).ok()?;
    Some(text.trim().parse().unwrap_or_else(|_| panic!("{name}={text:?} is not a valid value")))
}

impl Settings {
    fn from_environment() -> Self {
        let family: Option<String> = variable("FLEXMB_FUZZ_FAMILY");
        if let Some(f) = &family {
            let keys: Vec<&str> = Family::ALL.iter().map(|f| f.key()).collect();
            assert!(keys.contains(&f.as_str()), "FLEXMB_FUZZ_FAMILY={f:?}: one of {keys:?}");
        }
        let single: Option<u64> = variable("FLEXMB_FUZZ_CASE");
        let cases: Vec<u64> = match single {
            Some(n) => vec![n],
            None => (0..variable("FLEXMB_FUZZ_CASES").unwrap_or(DEFAULT_CASES))
                .filter(|&n| family.as_deref().is_none_or(|f| Family::of_case(n).key() == f))
                .collect(),
        };
        let memory_mb: u64 = variable("FLEXMB_FUZZ_MEMORY_MB").unwrap_or(2048);
        let memory_bytes = outcome::memory_bound_available().then_some(memory_mb << 20);
        let cores = std::thread::available_parallelism().map_or(2, |n| n.get());
        Settings {
            seed: variable("FLEXMB_FUZZ_SEED").unwrap_or(DEFAULT_SEED),
            cases,
            verbose: single.is_some() || std::env::var("FLEXMB_FUZZ_VERBOSE").is_ok_and(|v| v == "1"),
            jobs: variable("FLEXMB_FUZZ_JOBS").unwrap_or(cores).max(1),
            bounds: Bounds { time: Duration::from_secs_f64(variable("FLEXMB_FUZZ_TIMEOUT").unwrap_or(10.0)), memory_bytes },
            strict: std::env::var("FLEXMB_FUZZ_STRICT").is_ok_and(|v| v == "1"),
            failures: variable::<String>("FLEXMB_FUZZ_FAILURES")
                .map_or_else(|| std::env::temp_dir().join("flexmb-fuzz-failures"), PathBuf::from),
        }
    }
}

/// What a case did: its commands, and where it was saved if it failed.
struct Outcome {
    case: Case,
    ran: Vec<Ran>,
    saved: Option<PathBuf>,
}

impl Outcome {
    /// The worst class of its commands.
    fn class(&self) -> Class {
        self.ran.iter().map(|r| r.class).max().unwrap_or(Class::Success)
    }
}

#[test]
fn every_input_ends_in_a_believable_success_or_a_clean_error_within_bounds() {
    let settings = Settings::from_environment();
    let start = Instant::now();
    let scratch = std::env::temp_dir().join(format!("flexmb-fuzz-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&scratch);
    let template = scratch.join("template");
    let corpus = prepare_template(&template, &settings.bounds);
    let next = AtomicU64::new(0);
    let outcomes = Mutex::new(Vec::new());
    let saved = AtomicU64::new(0);
    std::thread::scope(|s| {
        for worker in 0..settings.jobs.min(settings.cases.len()) {
            let (settings, corpus, next, outcomes, saved, template) = (&settings, &corpus, &next, &outcomes, &saved, &template);
            let dir = scratch.join(format!("worker{worker}"));
            s.spawn(move || {
                copy_dir(template, &dir);
                while let Some(&number) = settings.cases.get(next.fetch_add(1, Ordering::Relaxed) as usize) {
                    let case = make_case(settings.seed, number, corpus);
                    let mut outcome = run_case(&dir, case, settings);
                    if outcome.class().fails() && (saved.fetch_add(1, Ordering::Relaxed) as usize) < SAVED_FAILURES {
                        outcome.saved = Some(save_failure(&dir, &outcome, settings));
                    }
                    clean_case(&dir, &outcome.case);
                    if settings.verbose {
                        println!("{}", describe_case(&outcome, settings, settings.cases.len() == 1));
                    }
                    outcomes.lock().unwrap().push(outcome);
                }
            });
        }
    });
    let mut outcomes = outcomes.into_inner().unwrap();
    outcomes.sort_by_key(|o| o.case.number);
    let report = report(&outcomes, &settings, start.elapsed());
    println!("{report}");
    let _ = std::fs::remove_dir_all(&scratch);
    assert!(outcomes.iter().all(|o| !o.class().fails()), "{report}");
}

/// Writes the case's files into the worker's directory and runs its commands there.
fn run_case(dir: &Path, case: Case, settings: &Settings) -> Outcome {
    std::fs::create_dir_all(dir.join("out")).unwrap();
    for (path, bytes) in &case.files {
        std::fs::write(dir.join(path), bytes).unwrap_or_else(|e| panic!("{}: {e}", dir.join(path).display()));
    }
    let mut ran: Vec<Ran> = Vec::new();
    for step in &case.steps {
        if step.after_success && ran.last().is_some_and(|r| r.class != Class::Success) {
            continue;
        }
        let mut r = run_flexmb(dir, &step.args, &settings.bounds);
        if r.class == Class::Success {
            if let Some(why) = vetting::suspicion(dir, &step.expect, &r.stdout) {
                (r.class, r.detail) = (Class::Suspicious, why);
            }
        }
        if r.class.fails() && !settings.strict {
            if let Some(k) = known::known(&case, &r) {
                r.detail = format!("{} (fixed by {}): {}", k.id, k.fixed_by, r.detail);
                r.class = Class::Known;
            }
        }
        ran.push(r);
    }
    Outcome { case, ran, saved: None }
}

fn clean_case(dir: &Path, case: &Case) {
    for (path, _) in &case.files {
        let _ = std::fs::remove_file(dir.join(path));
    }
    let _ = std::fs::remove_dir_all(dir.join("out"));
}

/// Keeps a copy of the worker's directory as the failing case left it, with a note on how to run it.
fn save_failure(dir: &Path, outcome: &Outcome, settings: &Settings) -> PathBuf {
    let to = settings.failures.join(format!("seed-{}-case-{}", settings.seed, outcome.case.number));
    let _ = std::fs::remove_dir_all(&to);
    copy_dir(dir, &to);
    let _ = std::fs::write(to.join("REPRODUCE.txt"), describe_case(outcome, settings, false));
    to
}

/// The workers' starting directory: `models/` as shipped (without reduction caches), the `.inp`
/// deck in `inp/`, and the results of short runs in `csv/`, whose runs also fill the caches.
fn prepare_template(template: &Path, bounds: &Bounds) -> Corpus {
    let workspace = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    copy_tree(&workspace.join("models"), template, false);
    copy_dir(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz/data"), &template.join("inp"));
    let setup: [&[&str]; 5] = [
        &["run", "oscillator.toml", "--t-end", "1", "--output-step", "0.01", "--out", "csv", "--quiet"],
        &["run", "slider_crank.toml", "--t-end", "0.5", "--output-step", "0.01", "--out", "csv", "--quiet"],
        &["run", "flexible_pendulum.toml", "--t-end", "0.3", "--output-step", "0.005", "--out", "csv", "--quiet"],
        &["check", "door/door.toml"],
        &["check", "wiper/wiper.toml"],
    ];
    for args in setup {
        let args: Vec<String> = args.iter().map(|a| a.to_string()).collect();
        let r = run_flexmb(template, &args, bounds);
        assert_eq!(r.class, Class::Success, "setup: flexmb {args:?}: {}\n{}", r.detail, r.stderr);
    }
    let mut files = Vec::new();
    collect_files(template, template, &mut files);
    let results = files
        .iter()
        .filter(|(p, _)| p.starts_with("csv/") && p.ends_with(".csv"))
        .map(|(p, bytes)| {
            let header = String::from_utf8_lossy(bytes).lines().next().unwrap_or_default().to_string();
            (p.clone(), header.split(',').skip(1).map(str::to_string).collect())
        })
        .collect();
    Corpus { files, results }
}

fn collect_files(root: &Path, dir: &Path, out: &mut Vec<(String, Vec<u8>)>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect_files(root, &path, out);
        } else if !path.components().any(|c| c.as_os_str() == ".flexmb-cache") {
            let relative = path.strip_prefix(root).unwrap().to_string_lossy().replace('\\', "/");
            out.push((relative, std::fs::read(&path).unwrap()));
        }
    }
}

/// Copies a directory tree.
fn copy_dir(from: &Path, to: &Path) {
    copy_tree(from, to, true);
}

/// Copies a directory tree, with or without the reduction caches in it.
fn copy_tree(from: &Path, to: &Path, caches: bool) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap_or_else(|e| panic!("{}: {e}", from.display())).flatten() {
        let (path, target) = (entry.path(), to.join(entry.file_name()));
        if path.is_dir() {
            if caches || entry.file_name() != ".flexmb-cache" {
                copy_tree(&path, &target, caches);
            }
        } else {
            std::fs::copy(&path, &target).unwrap_or_else(|e| panic!("{} -> {}: {e}", path.display(), target.display()));
        }
    }
}

/// A case and what each command did: the input (in full with `input`, else where it was saved), the
/// commands and their standard error, and the one command that makes it again.
fn describe_case(outcome: &Outcome, settings: &Settings, input: bool) -> String {
    let case = &outcome.case;
    let mut s = String::new();
    let _ = writeln!(s, "case {} ({}, from {}): {}", case.number, case.family.name(), case.source, outcome.class().name());
    for m in &case.mutations {
        let _ = writeln!(s, "  mutation: {m}");
    }
    for r in &outcome.ran {
        let _ = writeln!(s, "  flexmb {} -> {} in {:.2} s{}", r.args.join(" "), r.class.name(), r.seconds, detail(&r.detail));
        if r.class != Class::Success {
            for line in r.stderr.lines().take(6) {
                let shown: String = line.chars().take(400).collect();
                let _ = writeln!(s, "    | {shown}{}", if shown.len() < line.len() { " …" } else { "" });
            }
        }
    }
    if input {
        for (path, bytes) in &case.files {
            let text = String::from_utf8_lossy(bytes);
            let _ = writeln!(s, "  --- {} ({} bytes)", path.display(), bytes.len());
            for line in text.lines().take(400) {
                let _ = writeln!(s, "  {line}");
            }
        }
    }
    if let Some(dir) = &outcome.saved {
        let _ = writeln!(s, "  saved in {} (the commands run in that directory)", dir.display());
    }
    let _ = writeln!(
        s,
        "  again: FLEXMB_FUZZ_SEED={} FLEXMB_FUZZ_CASE={} cargo test --release -p flexmb-cli --test fuzz -- --nocapture",
        settings.seed, case.number
    );
    s
}

fn detail(d: &str) -> String {
    if d.is_empty() {
        String::new()
    } else {
        format!(": {d}")
    }
}

/// Counts per family and class, the known findings, and every failing case.
fn report(outcomes: &[Outcome], settings: &Settings, elapsed: Duration) -> String {
    let mut s = String::new();
    let commands: usize = outcomes.iter().map(|o| o.ran.len()).sum();
    let _ = writeln!(
        s,
        "fuzz: seed {}, {} cases, {commands} commands in {:.1} s on {} jobs (bounds: {:.0} s, {})",
        settings.seed,
        outcomes.len(),
        elapsed.as_secs_f64(),
        settings.jobs,
        settings.bounds.time.as_secs_f64(),
        settings.bounds.memory_bytes.map_or("no memory bound".into(), |b| format!("{} MB", b >> 20)),
    );
    let mut table: BTreeMap<Family, BTreeMap<Class, usize>> = BTreeMap::new();
    for o in outcomes {
        for r in &o.ran {
            *table.entry(o.case.family).or_default().entry(r.class).or_default() += 1;
        }
    }
    let _ = write!(s, "{:<20}", "commands by family");
    for c in Class::ALL {
        let _ = write!(s, " {:>8}", short(c));
    }
    s.push('\n');
    for (family, counts) in &table {
        let _ = write!(s, "{:<20}", family.name());
        for c in Class::ALL {
            let _ = write!(s, " {:>8}", counts.get(&c).copied().unwrap_or(0));
        }
        s.push('\n');
    }
    let _ = writeln!(s, "(columns: {})", Class::ALL.map(|c| format!("{} = {}", short(c), c.name())).join(", "));
    let mut known: BTreeMap<String, Vec<u64>> = BTreeMap::new();
    for o in outcomes {
        for r in o.ran.iter().filter(|r| r.class == Class::Known) {
            known.entry(r.detail.split(" (fixed by").next().unwrap().to_string()).or_default().push(o.case.number);
        }
    }
    for (id, numbers) in &known {
        let _ = writeln!(s, "known finding {id}: cases {numbers:?}");
    }
    let refused = refused_valid_inputs(outcomes);
    if !refused.is_empty() {
        let _ = writeln!(s, "generated inputs (not mutated) that a run or mode analysis refused: {} (not failures; to review)", refused.len());
        for line in refused.iter().take(10) {
            let _ = writeln!(s, "  {line}");
        }
    }
    let failing: Vec<&Outcome> = outcomes.iter().filter(|o| o.class().fails()).collect();
    for o in failing.iter().take(SAVED_FAILURES) {
        s.push_str(&describe_case(o, settings, false));
    }
    if failing.len() > SAVED_FAILURES {
        let _ = writeln!(s, "… and {} more failing cases", failing.len() - SAVED_FAILURES);
    }
    s
}

/// The generated inputs, valid by construction and not mutated, whose `run` (after a passing
/// `check`) or `modes` ended in an error: a singular position a driver reaches, a conditioning
/// limit, or a defect; the report lists them for review.
fn refused_valid_inputs(outcomes: &[Outcome]) -> Vec<String> {
    let generated = |o: &&Outcome| matches!(o.case.family, Family::GeneratedModel | Family::GeneratedFeModel) && o.case.mutations.is_empty();
    outcomes
        .iter()
        .filter(generated)
        .filter_map(|o| {
            let r = o.ran.iter().find(|r| r.class == Class::CleanError && matches!(r.args[0].as_str(), "run" | "modes"))?;
            let error: String = r.stderr.lines().next().unwrap_or_default().chars().take(200).collect();
            Some(format!("case {} ({}): {error}", o.case.number, r.args[0]))
        })
        .collect()
}

fn short(c: Class) -> &'static str {
    match c {
        Class::Success => "ok",
        Class::CleanError => "error",
        Class::Known => "known",
        Class::Suspicious => "suspect",
        Class::Panic => "panic",
        Class::Signal => "signal",
        Class::OutOfMemory => "oom",
        Class::Timeout => "timeout",
        Class::UncleanExit => "unclean",
    }
}
