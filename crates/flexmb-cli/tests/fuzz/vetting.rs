//! What a successful command must have printed and written for its success to be believed: finite
//! numbers everywhere, a run that reached its end time, a model with a body in it, a plot or spectrum
//! only of finite data.

use std::path::{Path, PathBuf};

use serde_json::Value;

/// What a command writes, to be looked at when it succeeds.
#[derive(Clone, Debug)]
pub enum Expect {
    /// `flexmb check`: its report.
    Check,
    /// `flexmb run`: the result CSV and the JSON summary.
    Run { csv: PathBuf, json: PathBuf },
    /// `flexmb modes`: the flexible-body file.
    Modes { json: PathBuf },
    /// `flexmb study`: a directory of runs.
    Study { dir: PathBuf },
    /// `flexmb plot` of these columns of a CSV into an image.
    Plot { image: PathBuf, csv: PathBuf, columns: Vec<String> },
    /// `flexmb spectrum` of a column of a CSV.
    Spectrum { csv: PathBuf, column: String },
}

/// Why the success of a command that wrote into `dir` is not to be believed, if it is not.
pub fn suspicion(dir: &Path, expect: &Expect, stdout: &str) -> Option<String> {
    if let Some(token) = non_finite_token(stdout) {
        return Some(format!("printed a non-finite number {token:?}: {}", line_with(stdout, &token)));
    }
    match expect {
        Expect::Check => stdout
            .lines()
            .any(|l| l.starts_with("model ") && l.contains(": 0 bodies") && !stdout.contains("flexible body"))
            .then(|| "an empty model passed as valid: 0 bodies".to_string()),
        Expect::Run { csv, json } => run_suspicion(&dir.join(json)).or_else(|| csv_suspicion(&dir.join(csv))),
        Expect::Modes { json } => json_file(&dir.join(json)).and_then(|v| null_number(&v, "")),
        Expect::Study { dir: out } => study_suspicion(&dir.join(out)),
        Expect::Plot { image, csv, columns } => {
            let written = std::fs::metadata(dir.join(image)).is_ok_and(|m| m.len() > 0);
            if !written {
                return Some(format!("no image written at {}", image.display()));
            }
            columns.iter().find_map(|c| non_finite_in_column(&dir.join(csv), c))
        }
        Expect::Spectrum { csv, column } => non_finite_in_column(&dir.join(csv), column),
    }
}

/// A token Rust prints for a non-finite `f64` (`NaN`, `inf`, `-inf`), if the text holds one.
pub fn non_finite_token(text: &str) -> Option<String> {
    text.split(|c: char| !(c.is_alphanumeric() || matches!(c, '.' | '+' | '-' | '_')))
        .find(|t| matches!(t.trim_start_matches(['+', '-']), "NaN" | "inf"))
        .map(str::to_string)
}

fn line_with<'a>(text: &'a str, token: &str) -> &'a str {
    text.lines().find(|l| l.contains(token)).unwrap_or_default().trim()
}

fn json_file(path: &Path) -> Option<Value> {
    let text = std::fs::read_to_string(path).ok()?;
    serde_json::from_str(&text).ok()
}

/// The first `null` in a JSON document where a number belongs (serde_json writes NaN and infinity as
/// `null`). Null by design: a run's `error` (and an interrupted run's keys), a mode's `load`, and the
/// `frequency_hz` of a static correction mode of the raw basis.
fn null_number(v: &Value, path: &str) -> Option<String> {
    match v {
        Value::Null => Some(format!("{path} is null: a non-finite number was written")),
        Value::Array(items) => items.iter().enumerate().find_map(|(k, x)| null_number(x, &format!("{path}[{k}]"))),
        Value::Object(map) => map
            .iter()
            .filter(|(k, x)| !(x.is_null() && matches!(k.as_str(), "error" | "load" | "frequency_hz" | "interrupted_at" | "reason")))
            .find_map(|(k, x)| null_number(x, &format!("{path}.{k}"))),
        _ => None,
    }
}

/// A run summary that says the run completed must hold finite statistics and a time reached at the
/// end time.
fn run_suspicion(json: &Path) -> Option<String> {
    let Some(summary) = json_file(json) else {
        return Some(format!("no readable summary at {}", json.display()));
    };
    if summary["status"] != "completed" {
        return Some(format!("exit status 0 but the summary's status is {}", summary["status"]));
    }
    let t_end = summary["settings"]["t_end"].as_f64();
    let reached = summary["t_reached"].as_f64();
    match (t_end, reached) {
        (Some(t_end), Some(reached)) if reached < t_end * (1.0 - 1e-9) => {
            return Some(format!("exit status 0 but the run reached t = {reached} of t_end = {t_end}"));
        }
        (Some(_), Some(_)) => {}
        _ => return Some(format!("t_end {:?} or t_reached {:?} missing or null", t_end, reached)),
    }
    ["settings", "constraints", "energy", "statistics", "assembly"]
        .iter()
        .find_map(|k| null_number(&summary[*k], k))
}

/// A result CSV must be a header and rows of as many finite numbers, at increasing times.
fn csv_suspicion(csv: &Path) -> Option<String> {
    let Ok(text) = std::fs::read_to_string(csv) else {
        return Some(format!("no readable result file {}", csv.display()));
    };
    let mut lines = text.lines();
    let columns = lines.next().map_or(0, |h| h.split(',').count());
    let mut last_t = f64::NEG_INFINITY;
    for (k, line) in lines.enumerate() {
        let values: Vec<f64> = line.split(',').map(|x| x.parse().unwrap_or(f64::NAN)).collect();
        if values.len() != columns {
            return Some(format!("{} row {}: {} values for {columns} columns", csv.display(), k + 1, values.len()));
        }
        if let Some(j) = values.iter().position(|v| !v.is_finite()) {
            let name = text.lines().next().and_then(|h| h.split(',').nth(j)).unwrap_or_default().to_string();
            return Some(format!("{} row {}: column {name} is {:?}", csv.display(), k + 1, line.split(',').nth(j)));
        }
        if values[0] <= last_t {
            return Some(format!("{} row {}: time {} after {last_t}", csv.display(), k + 1, values[0]));
        }
        last_t = values[0];
    }
    None
}

fn study_suspicion(out: &Path) -> Option<String> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(out).ok()?.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.sort();
    files.iter().find_map(|f| match f.extension().and_then(|e| e.to_str()) {
        Some("csv") => csv_suspicion(f),
        Some("json") => run_suspicion(f),
        _ => None,
    })
}

/// A non-finite (or unreadable) value in column `name` of a CSV that was plotted or analysed.
fn non_finite_in_column(csv: &Path, name: &str) -> Option<String> {
    let text = std::fs::read(csv).ok()?;
    let text = String::from_utf8_lossy(&text);
    let mut lines = text.lines();
    let k = lines.next()?.split(',').position(|h| h == name)?;
    lines.enumerate().find_map(|(row, line)| {
        let field = line.split(',').nth(k)?;
        let v: f64 = field.trim().parse().ok()?;
        (!v.is_finite()).then(|| format!("succeeded on a non-finite value {field:?} in column {name}, row {}", row + 1))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_numbers_are_found_as_rust_prints_them_and_not_inside_words() {
        assert_eq!(non_finite_token("energy initial NaN J"), Some("NaN".into()));
        assert_eq!(non_finite_token("f = -inf Hz"), Some("-inf".into()));
        assert_eq!(non_finite_token("residual 1.5e-3, information, infinite, Nan_body"), None);
    }

    #[test]
    fn nulls_are_suspicious_except_where_they_are_by_design() {
        let v: Value = serde_json::from_str(r#"{"error": null, "modes": [{"load": null, "f": 1}], "x": [1, null]}"#).unwrap();
        assert_eq!(null_number(&v, "").unwrap(), ".x[1] is null: a non-finite number was written");
    }
}
