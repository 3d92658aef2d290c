//! `flexmb run --plot`: after a run, one PNG per output of the model (or per column asked for),
//! next to the CSV.
//!
//! An output's columns are those sharing a name up to the last `.` (`bob.position.x/.y/.z`,
//! `energy.kinetic/…/.total`, a measure's single column) and a unit; a joint reaction's forces (N)
//! and torques (N m) so make two plots, `….reaction.f` and `….reaction.t`.

use std::path::{Path, PathBuf};

use super::{compose, default_image_path, render, ResultTable, TimeWindow, DEFAULT_SIZE};
use crate::run::CliError;

/// Columns plotted together: one output's columns of one unit.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputGroup {
    pub name: String,
    pub columns: Vec<String>,
}

/// Plots the run's results in `csv`: each of `columns` on its own, or every output group if none
/// are given. Returns the images' paths.
pub fn plot_run_outputs(csv: &Path, columns: &[String]) -> Result<Vec<PathBuf>, CliError> {
    let table = ResultTable::read(csv)?;
    let groups = if columns.is_empty() {
        output_groups(&table)
    } else {
        columns.iter().map(|c| OutputGroup { name: c.clone(), columns: vec![c.clone()] }).collect()
    };
    let mut images = Vec::new();
    for group in groups {
        let mut figure = compose(std::slice::from_ref(&table), "t", &group.columns, TimeWindow::default())?;
        figure.title = format!("{} — {}", group.name, table.stem());
        figure.y_quantity.0.clone_from(&group.name);
        let path = default_image_path(csv, std::slice::from_ref(&group.name));
        render(&figure, &path, DEFAULT_SIZE)?;
        images.push(path);
    }
    Ok(images)
}

/// The table's columns after `t`, grouped by output (name up to the last `.`) and unit.
pub fn output_groups(table: &ResultTable) -> Vec<OutputGroup> {
    let mut groups: Vec<(String, Option<&str>, Vec<String>)> = Vec::new();
    for name in table.names().iter().skip(1) {
        let prefix = name.rsplit_once('.').map_or(name.as_str(), |(p, _)| p);
        let unit = table.unit(name);
        match groups.last_mut() {
            Some((p, u, members)) if p == prefix && *u == unit => members.push(name.clone()),
            _ => groups.push((prefix.to_string(), unit, vec![name.clone()])),
        }
    }
    let shared = |prefix: &str| groups.iter().filter(|(p, ..)| p == prefix).count() > 1;
    groups
        .iter()
        .map(|(prefix, _, members)| OutputGroup {
            name: if shared(prefix) { common_prefix(members) } else { prefix.clone() },
            columns: members.clone(),
        })
        .collect()
}

/// The longest common start of the names, without a trailing `.`.
fn common_prefix(names: &[String]) -> String {
    let first = &names[0];
    let length =
        names.iter().map(|n| first.chars().zip(n.chars()).take_while(|(a, b)| a == b).count()).min().unwrap_or(0);
    first.chars().take(length).collect::<String>().trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn groups_follow_outputs_and_split_forces_from_torques() {
        let column = |name: &str, unit: &str| (name.to_string(), Some(unit.to_string()), vec![0.0]);
        let table = ResultTable::from_columns(
            Path::new("out/p.csv"),
            vec![
                column("t", "s"),
                column("bob.position.x", "m"),
                column("bob.position.y", "m"),
                column("pivot.reaction.fx", "N"),
                column("pivot.reaction.fy", "N"),
                column("pivot.reaction.tz", "N m"),
                column("pivot_angle", "rad"),
            ],
        );
        let groups = output_groups(&table);
        let names: Vec<&str> = groups.iter().map(|g| g.name.as_str()).collect();
        assert_eq!(names, ["bob.position", "pivot.reaction.f", "pivot.reaction.tz", "pivot_angle"]);
        assert_eq!(groups[0].columns, ["bob.position.x", "bob.position.y"]);
    }
}
