//! The allow-list: findings of the fuzzing that are someone else's to fix, tolerated here (class "known
//! finding", counted and listed in the report) until they are. Each entry says who fixes it and matches
//! its finding narrowly, by the command, the outcome and the mutation. Remove an entry once its finding
//! is fixed; `FLEXMB_FUZZ_STRICT=1` ignores the list, to check. (The empty model passed as valid, the
//! plot and spectrum of non-finite data, the output grid of 10²⁰ rows and the positions of 1e308 that
//! were here are fixed by issue14-input.)

use super::cases::Case;
use super::outcome::{Class, Ran};

pub struct KnownFinding {
    pub id: &'static str,
    /// Who fixes it (a branch and the point of issue 14), or why nobody does yet.
    pub fixed_by: &'static str,
    pub matches: fn(&Case, &Ran) -> bool,
}

pub const KNOWN_FINDINGS: &[KnownFinding] = &[KnownFinding {
    id: "slow-run-on-an-extreme-value",
    fixed_by: "nobody yet: values inside issue14-input's windows (a spring of 1e12 N/m under Adams, a motor of \
               1e9 N m, a body of 7.6e-9 kg, 1e6 m/s) make a 0.05 s run take minutes, bounded only by max_steps",
    matches: |case, ran| ran.class == Class::Timeout && matches!(ran.args[0].as_str(), "run" | "study") && made_extreme(case, 1e6),
}];

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
