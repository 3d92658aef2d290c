//! The sparse redundancy check (a row-by-row Givens QR) names the same rows as the dense Gram–Schmidt it
//! replaced, on every shipped model: at the initial poses (where the rows that do not hold are kept
//! first) and at the assembled configuration.

use crate::program;

use flexmb::analysis::{assemble, gram_schmidt_redundant_rows, redundant_rows, AssemblySettings, RedundantConstraint, State};
use flexmb::Data;
use program::workspace;

/// Every model file under `models/` (files with a `[model]` table; FE models and studies are not).
fn shipped_models() -> Vec<std::path::PathBuf> {
    fn walk(dir: &std::path::Path, found: &mut Vec<std::path::PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, found);
            } else if path.extension().is_some_and(|e| e == "toml")
                && std::fs::read_to_string(&path).unwrap().lines().any(|l| l.trim() == "[model]")
            {
                found.push(path);
            }
        }
    }
    let mut found = Vec::new();
    walk(&workspace().join("models"), &mut found);
    found.sort();
    found
}

/// Asserts that both checks name the same rows at the initial poses and, when the model assembles, at
/// the assembled configuration; returns the rows the assembly names.
fn assert_same_rows_both_ways(path: &std::path::Path) -> Option<Vec<RedundantConstraint>> {
    let loaded = flexmb_files::load_model(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let model = &loaded.model;
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let tolerance = AssemblySettings::default().tolerance;
    let initial = redundant_rows(model, &mut data, state.t, &state.q, tolerance);
    let reference = gram_schmidt_redundant_rows(model, &mut data, state.t, &state.q, tolerance);
    assert_eq!(initial, reference, "{}: at the initial poses", path.display());
    let report = assemble(model, &mut data, &mut state, loaded.simulation.assembly()).ok()?;
    let assembled: Vec<usize> = report.redundant.iter().map(|r| r.row).collect();
    let reference = gram_schmidt_redundant_rows(model, &mut data, state.t, &state.q, tolerance);
    assert_eq!(assembled, reference, "{}: assembled", path.display());
    Some(report.redundant)
}

#[test]
fn the_sparse_check_names_the_rows_gram_schmidt_names_on_every_shipped_model() {
    let models = shipped_models();
    assert!(models.len() >= 15, "{models:?}");
    for path in &models {
        let redundant = assert_same_rows_both_ways(path);
        assert!(redundant.is_some(), "{} assembles", path.display());
    }
}

#[test]
fn with_their_first_and_last_joints_repeated_the_shipped_rigid_models_name_the_same_rows_both_ways() {
    // Each rigid model with joints, its first and last joint given again (as joints after all the
    // others): their rows repeat rows in force, and the copies are the ones named, besides the rows
    // the model names without them.
    let dir = program::scratch("redundancy-repeated-joints");
    let mut checked = 0;
    for path in shipped_models() {
        let text = std::fs::read_to_string(&path).unwrap();
        let mut doc: toml::Table = text.parse().unwrap();
        if doc.contains_key("flexible_body") {
            continue;
        }
        let Some(joints) = doc.get_mut("joint").and_then(|j| j.as_array_mut()) else { continue };
        let copies: Vec<toml::Value> = [joints.first(), joints.last()]
            .into_iter()
            .flatten()
            .enumerate()
            .map(|(k, joint)| {
                let mut copy = joint.clone();
                let name = copy["name"].as_str().unwrap().to_string();
                copy.as_table_mut().unwrap().insert("name".into(), toml::Value::String(format!("{name}_again{k}")));
                copy
            })
            .collect();
        joints.extend(copies);
        let repeated = dir.join(path.file_name().unwrap());
        std::fs::write(&repeated, toml::to_string(&doc).unwrap()).unwrap();
        // A model redundant already (a planar loop of revolutes) keeps its own redundant rows.
        let own: Vec<String> =
            assert_same_rows_both_ways(&path).unwrap_or_default().into_iter().map(|r| r.description).collect();
        if let Some(redundant) = assert_same_rows_both_ways(&repeated) {
            let (copies, others): (Vec<_>, Vec<_>) =
                redundant.into_iter().map(|r| r.description).partition(|d| d.contains("_again"));
            assert!(!copies.is_empty(), "{}", path.display());
            assert_eq!(others, own, "{}: rows named besides the copies'", path.display());
            checked += 1;
        }
    }
    assert!(checked >= 8, "{checked}");
}
