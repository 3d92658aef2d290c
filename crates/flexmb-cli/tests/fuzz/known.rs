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
        id: "plot-of-non-finite-data",
        fixed_by: "issue14-input, plot and spectrum on non-finite data: non-finite values are errors",
        matches: |_, ran| {
            matches!(ran.args[0].as_str(), "plot" | "spectrum") && suspicious_with(ran, "succeeded on a non-finite value")
        },
    },
    KnownFinding {
        id: "slow-run-on-an-extreme-value",
        fixed_by: "issue14-input (value ranges) and issue14-run (watchdog); check after merging them",
        matches: |case, ran| {
            ran.class == Class::Timeout
                && matches!(ran.args[0].as_str(), "run" | "study")
                && case.mutations.iter().any(|m| made_extreme(m))
        },
    },
];

/// Whether the command succeeded suspiciously for the reason that starts with `detail`.
fn suspicious_with(ran: &Ran, detail: &str) -> bool {
    ran.class == Class::Suspicious && ran.detail.starts_with(detail)
}

/// Whether a mutation put a number of magnitude 10⁶ or more (or not finite) in the file: a mutation
/// described as `… -> VALUE`.
fn made_extreme(mutation: &str) -> bool {
    let Some((_, value)) = mutation.rsplit_once(" -> ") else {
        return false;
    };
    value.trim_matches('"').parse::<f64>().is_ok_and(|x| x.is_nan() || x.abs() >= 1e6)
}

/// The entry that tolerates this failure, if one does.
pub fn known(case: &Case, ran: &Ran) -> Option<&'static KnownFinding> {
    KNOWN_FINDINGS.iter().find(|k| (k.matches)(case, ran))
}

#[test]
fn extreme_values_are_read_from_the_mutations() {
    assert!(made_extreme("line 24: number \"-9.81\" -> \"1e12\""));
    assert!(made_extreme("line 59: number 2 -> -2e9"));
    assert!(made_extreme("line 3: number \"1\" -> \"nan\""));
    assert!(!made_extreme("line 3: number \"1\" -> \"0.5\""));
    assert!(!made_extreme("line 3: string \"a\" -> \"b\""));
}
