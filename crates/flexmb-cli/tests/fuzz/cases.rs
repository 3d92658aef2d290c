//! The cases: for each input family, which file is mutated or generated, where it is written in the
//! worker's copy of `models/`, and which `flexmb` commands run on it.

use std::path::PathBuf;

use super::fe_model::fe_model;
use super::mechanism::mechanism;
use super::mutate::{mutate, Syntax};
use super::rng::Rng;
use super::vetting::Expect;

/// The input families.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Family {
    /// Mutations of the shipped model files: `check`, then `run`.
    Model,
    /// Mechanisms generated valid (a quarter of them mutated afterwards): `check`, then `run`.
    GeneratedModel,
    /// Mutations of the shipped FE model files: `modes`, and `check`/`run` of a model that uses them.
    FeModel,
    /// FE models generated valid (a fifth mutated): `modes`.
    GeneratedFeModel,
    /// Mutations of an `.inp` deck and of the file it includes: `modes` on the deck and on an FE
    /// model file that uses it as its mesh.
    Inp,
    /// Mutations of the shipped study files: `study`.
    Study,
    /// Mutations of result CSVs (and of their JSON summaries) written by short runs: `plot`, `spectrum`.
    Csv,
}

impl Family {
    pub const ALL: [Family; 7] = [
        Family::Model,
        Family::GeneratedModel,
        Family::FeModel,
        Family::GeneratedFeModel,
        Family::Inp,
        Family::Study,
        Family::Csv,
    ];

    /// The family of case `number`: a fixed cycle, so that every run of 20 cases or more covers all.
    pub fn of_case(number: u64) -> Family {
        const CYCLE: [Family; 20] = [
            Family::Model,
            Family::GeneratedModel,
            Family::FeModel,
            Family::Inp,
            Family::Model,
            Family::GeneratedModel,
            Family::Csv,
            Family::GeneratedFeModel,
            Family::Model,
            Family::GeneratedModel,
            Family::FeModel,
            Family::Study,
            Family::Model,
            Family::GeneratedModel,
            Family::Inp,
            Family::Csv,
            Family::Model,
            Family::GeneratedModel,
            Family::FeModel,
            Family::GeneratedFeModel,
        ];
        CYCLE[(number % CYCLE.len() as u64) as usize]
    }

    /// The family's name in `FLEXMB_FUZZ_FAMILY`.
    pub fn key(self) -> &'static str {
        match self {
            Family::Model => "model",
            Family::GeneratedModel => "generated-model",
            Family::FeModel => "fe-model",
            Family::GeneratedFeModel => "generated-fe-model",
            Family::Inp => "inp",
            Family::Study => "study",
            Family::Csv => "csv",
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Family::Model => "model file",
            Family::GeneratedModel => "generated model",
            Family::FeModel => "FE model file",
            Family::GeneratedFeModel => "generated FE model",
            Family::Inp => ".inp deck",
            Family::Study => "study file",
            Family::Csv => "result CSV",
        }
    }
}

/// One `flexmb` command of a case.
#[derive(Clone, Debug)]
pub struct Step {
    pub args: Vec<String>,
    pub expect: Expect,
    /// Run only if the step before succeeded (a `run` after its `check`).
    pub after_success: bool,
}

/// A case: files to write into the worker's directory, then commands to run there.
#[derive(Clone, Debug)]
pub struct Case {
    pub number: u64,
    pub family: Family,
    /// The shipped file it starts from, or "generated".
    pub source: String,
    pub mutations: Vec<String>,
    pub files: Vec<(PathBuf, Vec<u8>)>,
    pub steps: Vec<Step>,
}

/// The shipped inputs, read from the worker template (paths relative to it).
pub struct Corpus {
    pub files: Vec<(String, Vec<u8>)>,
    /// The CSVs of short runs, with their column names.
    pub results: Vec<(String, Vec<String>)>,
}

impl Corpus {
    fn text(&self, path: &str) -> Vec<u8> {
        self.files.iter().find(|(p, _)| p == path).unwrap_or_else(|| panic!("{path} is not in the corpus")).1.clone()
    }
}

pub const MODEL_FILES: &[&str] = &[
    "pendulum.toml",
    "double_pendulum.toml",
    "slider_crank.toml",
    "four_bar.toml",
    "spinning_top.toml",
    "spatial_mechanism.toml",
    "oscillator.toml",
    "motor_friction.toml",
    "flexible_pendulum.toml",
    "door/door.toml",
    "wiper/wiper.toml",
];

/// The FE model files, and the model file that uses each as a flexible body with the name it refers to
/// it by.
pub const FE_MODEL_FILES: &[(&str, Option<(&str, &str)>)] = &[
    ("fe/cantilever.toml", None),
    ("fe/plate.toml", None),
    ("fe/pendulum_beam.toml", Some(("flexible_pendulum.toml", "fe/pendulum_beam.toml"))),
    ("door/door_fe.toml", Some(("door/door.toml", "door_fe.toml"))),
    ("wiper/arm_fe.toml", Some(("wiper/wiper.toml", "arm_fe.toml"))),
    ("inp/frame_mesh.toml", None),
];

pub const STUDY_FILES: &[&str] = &["door/study.toml", "wiper/study.toml", "studies/pendulum_lengths.toml"];

/// The end time of every run: short, so that a case takes milliseconds.
const T_END: &str = "0.05";

/// The case `number` of a run with seed `seed`.
pub fn make_case(seed: u64, number: u64, corpus: &Corpus) -> Case {
    let rng = &mut Rng::for_case(seed, number);
    let family = Family::of_case(number);
    let mut case = Case { number, family, source: String::new(), mutations: Vec::new(), files: Vec::new(), steps: Vec::new() };
    match family {
        Family::Model => {
            let source = *rng.pick(MODEL_FILES);
            let mut text = corpus.text(source);
            case.mutations = mutate(rng, &mut text, Syntax::Toml);
            let path = beside(source, "fuzz_case.toml");
            model_steps(rng, &mut case, &path);
            case.files.push((path.into(), text));
            case.source = source.into();
        }
        Family::GeneratedModel => {
            let mut text = mechanism(rng).into_bytes();
            if rng.chance(0.25) {
                case.mutations = mutate(rng, &mut text, Syntax::Toml);
            }
            model_steps(rng, &mut case, "fuzz_case.toml");
            case.files.push(("fuzz_case.toml".into(), text));
            case.source = "generated".into();
        }
        Family::FeModel => fe_model_case(rng, &mut case, corpus),
        Family::GeneratedFeModel => {
            let mut text = fe_model(rng).into_bytes();
            if rng.chance(0.2) {
                case.mutations = mutate(rng, &mut text, Syntax::Toml);
            }
            case.steps.push(modes_step(rng, "fe/fuzz_case.toml", false));
            case.files.push(("fe/fuzz_case.toml".into(), text));
            case.source = "generated".into();
        }
        Family::Inp => inp_case(rng, &mut case, corpus),
        Family::Study => {
            let source = *rng.pick(STUDY_FILES);
            let mut text = corpus.text(source);
            case.mutations = mutate(rng, &mut text, Syntax::Toml);
            let path = beside(source, "fuzz_case.toml");
            let args = ["study", &path, "--t-end", "0.02", "--out", "out/study", "--quiet"];
            case.steps.push(step(&args, Expect::Study { dir: "out/study".into() }, false));
            case.files.push((path.into(), text));
            case.source = source.into();
        }
        Family::Csv => csv_case(rng, &mut case, corpus),
    }
    case
}

/// `name` in the folder of `path`.
fn beside(path: &str, name: &str) -> String {
    match path.rsplit_once('/') {
        Some((dir, _)) => format!("{dir}/{name}"),
        None => name.to_string(),
    }
}

fn step(args: &[&str], expect: Expect, after_success: bool) -> Step {
    Step { args: args.iter().map(|a| a.to_string()).collect(), expect, after_success }
}

/// `check MODEL`, then, if it passes, a short `run` (with some of the run options).
fn model_steps(rng: &mut Rng, case: &mut Case, model: &str) {
    case.steps.push(step(&["check", model], Expect::Check, false));
    let mut args = vec!["run", model, "--t-end", T_END, "--out", "out"];
    if rng.chance(0.5) {
        args.extend(["--output-step", *rng.pick(&["0.01", "0.005", "0.05", "0.003"])]);
    }
    if rng.chance(0.2) {
        args.extend(["--integrator", *rng.pick(&["bdf", "adams", "gen-alpha"])]);
    }
    if rng.chance(0.1) {
        args.extend(["--vtk", "out/vtk"]);
    }
    let stem = model.rsplit('/').next().unwrap().trim_end_matches(".toml");
    let expect = Expect::Run { csv: format!("out/{stem}.csv").into(), json: format!("out/{stem}.json").into() };
    case.steps.push(step(&args, expect, true));
}

/// `modes FE_MODEL` with some of its options; `needs_set` for a deck, which has no `[modes]` set.
fn modes_step(rng: &mut Rng, fe_model: &str, needs_set: bool) -> Step {
    let mut args = vec!["modes", fe_model, "--out", "out/body.json"];
    if needs_set || rng.chance(0.2) {
        args.extend(["--modes", *rng.pick(&["4N", "1N", "6N", "2N1S", "20N", "3S"])]);
    }
    if rng.chance(0.2) {
        args.extend(["--mass", *rng.pick(&["lumped", "consistent"])]);
    }
    if rng.chance(0.2) {
        args.extend(["--basis", *rng.pick(&["raw", "orthonormal"])]);
    }
    if rng.chance(0.15) {
        args.extend(["--solver", *rng.pick(&["dense", "lanczos"])]);
    }
    if rng.chance(0.05) {
        args.extend(["--vtk", "out/vtk"]);
    }
    step(&args, Expect::Modes { json: "out/body.json".into() }, false)
}

fn fe_model_case(rng: &mut Rng, case: &mut Case, corpus: &Corpus) {
    let (source, user) = *rng.pick(FE_MODEL_FILES);
    let mut text = corpus.text(source);
    case.mutations = mutate(rng, &mut text, Syntax::Toml);
    let path = beside(source, "fuzz_case.toml");
    case.steps.push(modes_step(rng, &path, false));
    if let Some((model, reference)) = user {
        let model_text = String::from_utf8(corpus.text(model)).unwrap();
        let reference_to_case = beside(reference, "fuzz_case.toml");
        let user_text = model_text.replace(&format!("\"{reference}\""), &format!("\"{reference_to_case}\""));
        let user_path = beside(model, "fuzz_user.toml");
        model_steps(rng, case, &user_path);
        case.files.push((user_path.into(), user_text.into_bytes()));
    }
    case.files.push((path.into(), text));
    case.source = source.into();
}

fn inp_case(rng: &mut Rng, case: &mut Case, corpus: &Corpus) {
    let deck = String::from_utf8(corpus.text("inp/frame.inp")).unwrap().replace("frame_nodes.inp", "fuzz_nodes.inp");
    let mut deck = deck.into_bytes();
    let mut nodes = corpus.text("inp/frame_nodes.inp");
    case.source = if rng.chance(0.75) {
        case.mutations = mutate(rng, &mut deck, Syntax::Inp);
        "inp/frame.inp".into()
    } else {
        case.mutations = mutate(rng, &mut nodes, Syntax::Inp);
        "inp/frame_nodes.inp".into()
    };
    case.steps.push(modes_step(rng, "inp/fuzz_case.inp", true));
    if rng.chance(0.5) {
        let mesh = String::from_utf8(corpus.text("inp/frame_mesh.toml")).unwrap().replace("\"frame.inp\"", "\"fuzz_case.inp\"");
        case.steps.push(modes_step(rng, "inp/fuzz_mesh.toml", false));
        case.files.push(("inp/fuzz_mesh.toml".into(), mesh.into_bytes()));
    }
    case.files.push(("inp/fuzz_case.inp".into(), deck));
    case.files.push(("inp/fuzz_nodes.inp".into(), nodes));
}

fn csv_case(rng: &mut Rng, case: &mut Case, corpus: &Corpus) {
    let (source, columns) = rng.pick(&corpus.results).clone();
    let mut csv = corpus.text(&source);
    let mut json = corpus.text(&source.replace(".csv", ".json"));
    case.mutations = if rng.chance(0.85) { mutate(rng, &mut csv, Syntax::Csv) } else { mutate(rng, &mut json, Syntax::Csv) };
    let mut column = || if rng.chance(0.9) { rng.pick(&columns).clone() } else { "no_such_column".to_string() };
    let (y, y2, x) = (column(), column(), column());
    let mut plot = vec!["plot".to_string(), "csv/fuzz_case.csv".into(), "--y".into(), y.clone()];
    let mut plotted = vec![y.clone()];
    if rng.chance(0.3) {
        plot.push(y2.clone());
        plotted.push(y2);
    }
    if rng.chance(0.3) {
        plot.extend(["--x".into(), x.clone()]);
        plotted.push(x);
    } else {
        plotted.push("t".into());
    }
    let image = if rng.chance(0.2) { "out/plot.svg" } else { "out/plot.png" };
    plot.extend(["--out".into(), image.into(), "--width".into(), "320".into(), "--height".into(), "240".into()]);
    let expect = Expect::Plot { image: image.into(), csv: "csv/fuzz_case.csv".into(), columns: plotted };
    case.steps.push(Step { args: plot, expect, after_success: false });
    let mut spectrum = vec!["spectrum".to_string(), "csv/fuzz_case.csv".into(), "--y".into(), y.clone()];
    for (option, values) in [
        ("--from", &["0", "0.2", "-1", "1e300"][..]),
        ("--to", &["0.5", "0.9", "0"]),
        ("--peaks", &["1", "0", "3"]),
        ("--min-frequency", &["0", "5", "1e6"]),
    ] {
        if rng.chance(0.25) {
            spectrum.extend([option.to_string(), rng.pick(values).to_string()]);
        }
    }
    if rng.chance(0.3) {
        spectrum.extend(["--out".into(), "out/spectrum.png".into(), "--width".into(), "320".into(), "--height".into(), "240".into()]);
    }
    let expect = Expect::Spectrum { csv: "csv/fuzz_case.csv".into(), column: y };
    case.steps.push(Step { args: spectrum, expect, after_success: false });
    case.files.push(("csv/fuzz_case.csv".into(), csv));
    case.files.push(("csv/fuzz_case.json".into(), json));
    case.source = source;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_models_and_fe_models_are_toml() {
        for case in 0..200 {
            for text in [mechanism(&mut Rng::for_case(1, case)), fe_model(&mut Rng::for_case(2, case))] {
                let parsed: Result<toml::Table, _> = text.parse();
                assert!(parsed.is_ok(), "case {case}: {:?}\n{text}", parsed.err());
            }
        }
    }
}
