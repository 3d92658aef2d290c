//! The allow-list: findings of the fuzzing that other branches of issue 14 fix, tolerated here (class
//! "known finding", counted and listed in the report) until those branches are merged. Each entry names
//! the branch that fixes it and matches its finding narrowly, by the command, the outcome and the
//! mutation. Empty the list after merging them; `FLEXMB_FUZZ_STRICT=1` ignores it, to check that they
//! are fixed.

use super::cases::Case;
use super::outcome::{Class, Ran};

pub struct KnownFinding {
    pub id: &'static str,
    /// The branch (and the point of issue 14) that fixes it.
    pub fixed_by: &'static str,
    pub matches: fn(&Case, &Ran) -> bool,
}

pub const KNOWN_FINDINGS: &[KnownFinding] = &[
    KnownFinding {
        id: "empty-model-passes",
        fixed_by: "issue14-input, empty models: [model] is required and a model needs a body",
        matches: |_, ran| suspicious_with(ran, "an empty model passed"),
    },
    KnownFinding {
        id: "plot-or-spectrum-of-non-finite-or-extreme-data",
        fixed_by: "issue14-input, plot and spectrum on non-finite data (errors) and axes that overflow (refused)",
        matches: |case, ran| {
            matches!(ran.args[0].as_str(), "plot" | "spectrum")
                && (suspicious_with(ran, "succeeded on a non-finite value")
                    || (matches!(ran.class, Class::Timeout | Class::Suspicious) && made_extreme(case, 1e300)))
        },
    },
    KnownFinding {
        id: "output-grid-too-large",
        fixed_by: "issue14-input, output-row limits: more than 10^7 rows or 10^5 ParaView frames are refused",
        matches: |case, ran| ran.class == Class::Timeout && ran.args[0] == "run" && too_many_outputs(case, ran),
    },
    KnownFinding {
        id: "extreme-value-in-a-model",
        fixed_by: "issue14-input (value ranges) and issue14-run (watchdog); check after merging them",
        matches: |case, ran| {
            matches!(ran.args[0].as_str(), "run" | "study")
                && ((ran.class == Class::Timeout && made_extreme(case, 1e6))
                    || (ran.class == Class::Suspicious && made_extreme(case, 1e300)))
        },
    },
];

/// Whether the command succeeded suspiciously for the reason that starts with `detail`.
fn suspicious_with(ran: &Ran, detail: &str) -> bool {
    ran.class == Class::Suspicious && ran.detail.starts_with(detail)
}

/// Whether a mutation of the case put a number of magnitude `at_least` or more, or at most its inverse
/// (but not zero), or not finite, in its file: a mutation described as `… -> VALUE`. (A body of
/// 7.6e-9 kg makes a model as stiff as a spring of 1e9 N/m does.)
fn made_extreme(case: &Case, at_least: f64) -> bool {
    case.mutations.iter().any(|m| extreme(m, at_least))
}

fn extreme(mutation: &str, at_least: f64) -> bool {
    let Some((_, value)) = mutation.rsplit_once(" -> ") else {
        return false;
    };
    value.trim_matches('"').parse::<f64>().is_ok_and(|x| x.is_nan() || x.abs() >= at_least || (x != 0.0 && x.abs() <= 1.0 / at_least))
}

/// Whether the run's model asks for more than 10⁷ output rows over the run's end time (its
/// `[simulation] output_step`, when the command line gives none), or more than 10⁵ ParaView frames.
fn too_many_outputs(case: &Case, ran: &Ran) -> bool {
    let option = |name: &str| ran.args.iter().position(|a| a == name).and_then(|k| ran.args.get(k + 1));
    let t_end: f64 = option("--t-end").and_then(|t| t.parse().ok()).unwrap_or(f64::INFINITY);
    let Some((_, bytes)) = case.files.iter().find(|(path, _)| path.to_str() == Some(ran.args[1].as_str())) else {
        return false;
    };
    let Ok(file) = String::from_utf8_lossy(bytes).parse::<toml::Table>() else {
        return false;
    };
    let setting = |key: &str| file.get("simulation").and_then(|s| s.get(key)).and_then(|v| v.as_float().or(v.as_integer().map(|i| i as f64)));
    let output_step = option("--output-step").and_then(|s| s.parse().ok()).or(setting("output_step"));
    let frames = option("--vtk").and(setting("vtk_step")).is_some_and(|step| t_end / step > 1e5);
    output_step.is_some_and(|step| t_end / step > 1e7) || frames
}

/// The entry that tolerates this failure, if one does.
pub fn known(case: &Case, ran: &Ran) -> Option<&'static KnownFinding> {
    KNOWN_FINDINGS.iter().find(|k| (k.matches)(case, ran))
}

#[test]
fn extreme_values_are_read_from_the_mutations() {
    assert!(extreme("line 24: number \"-9.81\" -> \"1e12\"", 1e6));
    assert!(!extreme("line 24: number \"-9.81\" -> \"1e12\"", 1e300));
    assert!(extreme("line 59: number 2 -> -2e9", 1e6));
    assert!(extreme("line 3: number \"1\" -> \"nan\"", 1e300));
    assert!(!extreme("line 3: number \"1\" -> \"0.5\"", 1e6));
    assert!(extreme("line 33: number 7.567801014641104 -> 7.567801014641105e-9", 1e6));
    assert!(!extreme("line 3: number \"1\" -> \"0\"", 1e6));
    assert!(!extreme("line 3: string \"a\" -> \"b\"", 1e6));
}
