//! A result file of `flexmb run` read back: the CSV's columns, and their units from the JSON summary
//! beside it (same stem, `.json`) when there is one.

use std::path::{Path, PathBuf};

use crate::model_file::suggest::did_you_mean;
use crate::results::ResultFileError;

/// The columns of one result CSV, by name, with their units.
#[derive(Clone, Debug)]
pub struct ResultTable {
    path: PathBuf,
    names: Vec<String>,
    units: Vec<Option<String>>,
    /// One vector of values per column, in the file's order.
    columns: Vec<Vec<f64>>,
    /// The 1-based line of the file each row was read from.
    lines: Vec<usize>,
}

impl ResultTable {
    /// Reads `path` (header `t,<column>,…`, one row per output time) and the units of its summary.
    ///
    /// ```
    /// let path = std::env::temp_dir().join(format!("flexmb-files-table-{}.csv", std::process::id()));
    /// std::fs::write(&path, "t,x\n0,1.5\n0.1,2.5\n")?;
    /// let table = flexmb_files::ResultTable::read(&path)?;
    /// assert_eq!(table.names(), ["t", "x"]);
    /// assert_eq!(table.column("x")?, [1.5, 2.5]);
    /// assert_eq!(table.unit("t"), Some("s"));
    /// std::fs::remove_file(&path)?;
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn read(path: &Path) -> Result<Self, ResultFileError> {
        let text = flexmb_fem::input::read_text(path)
            .map_err(|e| ResultFileError(format!("cannot read {}: {e}", path.display())))?;
        let mut records = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(text.as_bytes())
            .into_records()
            .filter(|r| r.as_ref().map_or(true, |r| !(r.len() == 1 && r[0].is_empty())));
        let read_error = |e: csv::Error| ResultFileError(format!("cannot read {}: {e}", path.display()));
        let Some(header) = records.next().transpose().map_err(read_error)? else {
            return Err(ResultFileError(format!("{} is empty: no header and no rows", path.display())));
        };
        let names: Vec<String> = header.iter().map(str::to_string).collect();
        let mut columns = vec![Vec::new(); names.len()];
        let mut row_lines = Vec::new();
        // The csv reader counts no blank lines, and a record's position is where the blank lines
        // before it begin: the line is counted from the byte where the record's text begins.
        let (mut line, mut counted) = (1, 0);
        for record in records {
            let record = record.map_err(read_error)?;
            let position = record.position().map_or(counted, |p| p.byte() as usize);
            let start = position + text.as_bytes()[position..].iter().take_while(|b| matches!(b, b'\n' | b'\r')).count();
            line += text.as_bytes()[counted..start].iter().filter(|&&b| b == b'\n').count();
            counted = start;
            push_row(path, line, &record, &names, &mut columns)?;
            row_lines.push(line);
        }
        if columns[0].is_empty() {
            return Err(ResultFileError(format!("{} has a header but no rows", path.display())));
        }
        let units = summary_units(path, &names);
        Ok(Self { path: path.to_path_buf(), names, units, columns, lines: row_lines })
    }

    /// A table from columns in memory (for tests and for results not read from a file), as if read
    /// from a file with the header on line 1 and one row per line after it.
    pub fn from_columns(path: &Path, columns: Vec<(String, Option<String>, Vec<f64>)>) -> Self {
        let mut table =
            Self { path: path.to_path_buf(), names: Vec::new(), units: Vec::new(), columns: Vec::new(), lines: Vec::new() };
        for (name, unit, values) in columns {
            table.names.push(name);
            table.units.push(unit);
            table.columns.push(values);
        }
        table.lines = (2..table.rows() + 2).collect();
        table
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file name without directory and extension: what legends call this run.
    pub fn stem(&self) -> &str {
        self.path.file_stem().and_then(|s| s.to_str()).unwrap_or("results")
    }

    /// The columns' names, in the file's order (`t` first in files `flexmb run` writes).
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }

    /// The values of a column, or an error listing the columns there are.
    pub fn column(&self, name: &str) -> Result<&[f64], ResultFileError> {
        self.index(name).map(|i| self.columns[i].as_slice())
    }

    /// The values of a column, which must all be finite: a NaN or an infinity is an error at its
    /// line, saying that `purpose` ("a plot", "a spectrum") needs finite values.
    pub fn finite_column(&self, name: &str, purpose: &str) -> Result<&[f64], ResultFileError> {
        let values = self.column(name)?;
        match values.iter().position(|v| !v.is_finite()) {
            None => Ok(values),
            Some(row) => Err(ResultFileError(format!(
                "{}: column `{name}` holds {}; {purpose} needs finite values",
                self.location(row),
                values[row]
            ))),
        }
    }

    /// `file:line` of a row (0-based), for messages.
    pub fn location(&self, row: usize) -> String {
        format!("{}:{}", self.path.display(), self.lines.get(row).copied().unwrap_or(row + 2))
    }

    /// The unit of a column: from the summary, `s` for time, else none.
    pub fn unit(&self, name: &str) -> Option<&str> {
        self.index(name).ok().and_then(|i| self.units[i].as_deref())
    }

    fn index(&self, name: &str) -> Result<usize, ResultFileError> {
        self.names.iter().position(|n| n == name).ok_or_else(|| {
            ResultFileError(format!(
                "{} has no column `{name}`{}\navailable columns: {}",
                self.path.display(),
                did_you_mean(name, self.names.iter().map(String::as_str)),
                self.names.join(", ")
            ))
        })
    }
}

/// Parses one data row into `columns`; `line_number` is 1-based, for the message.
fn push_row(
    path: &Path,
    line_number: usize,
    fields: &csv::StringRecord,
    names: &[String],
    columns: &mut [Vec<f64>],
) -> Result<(), ResultFileError> {
    if fields.len() != names.len() {
        return Err(ResultFileError(format!(
            "{}:{line_number}: {} values, but the header has {} columns",
            path.display(),
            fields.len(),
            names.len()
        )));
    }
    for ((field, name), column) in fields.iter().zip(names).zip(columns.iter_mut()) {
        let value = field.parse::<f64>().map_err(|_| {
            ResultFileError(format!("{}:{line_number}: column `{name}`: `{field}` is not a number", path.display()))
        })?;
        column.push(value);
    }
    Ok(())
}

/// The unit of each column: from `output.columns` of the summary beside the CSV, `s` for `t`.
fn summary_units(csv: &Path, names: &[String]) -> Vec<Option<String>> {
    let from_summary = read_summary_units(&csv.with_extension("json"));
    names
        .iter()
        .map(|name| {
            let unit = from_summary.iter().find(|(n, _)| n == name).map(|(_, u)| u.clone());
            unit.or_else(|| (name == "t").then(|| "s".to_string())).filter(|u| !u.is_empty())
        })
        .collect()
}

/// `(name, unit)` of every column the summary lists; nothing if there is no readable summary.
fn read_summary_units(summary: &Path) -> Vec<(String, String)> {
    let Ok(text) = flexmb_fem::input::read_text(summary) else {
        return Vec::new();
    };
    let Ok(json) = serde_json::from_str::<serde_json::Value>(&text) else {
        return Vec::new();
    };
    let Some(columns) = json["output"]["columns"].as_array() else {
        return Vec::new();
    };
    columns.iter().filter_map(|c| Some((c["name"].as_str()?.to_string(), c["unit"].as_str()?.to_string()))).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("flexmb-csv-table-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn reads_columns_and_units_from_the_summary() {
        let dir = scratch("units");
        let csv = dir.join("run.csv");
        std::fs::write(&csv, "t,tip.y,angle\n0.0,1.5,0.1\n0.5,2.5,0.2\n").unwrap();
        std::fs::write(dir.join("run.json"), r#"{"output": {"columns": [{"name": "tip.y", "unit": "m"}]}}"#).unwrap();
        let table = ResultTable::read(&csv).unwrap();
        assert_eq!(table.stem(), "run");
        assert_eq!(table.rows(), 2);
        assert_eq!(table.column("tip.y").unwrap(), &[1.5, 2.5]);
        assert_eq!(table.unit("t"), Some("s"));
        assert_eq!(table.unit("tip.y"), Some("m"));
        assert_eq!(table.unit("angle"), None, "not in the summary: no unit");
    }

    #[test]
    fn unknown_column_lists_the_columns_and_suggests_the_closest() {
        let table = ResultTable::from_columns(
            Path::new("out/a.csv"),
            vec![("t".into(), None, vec![0.0]), ("bob.position.y".into(), None, vec![1.0])],
        );
        let e = table.column("bob.postion.y").unwrap_err().to_string();
        assert!(e.contains("no column `bob.postion.y`; did you mean `bob.position.y`?"), "{e}");
        assert!(e.contains("available columns: t, bob.position.y"), "{e}");
    }

    #[test]
    fn bad_files_say_what_is_wrong_and_where() {
        let dir = scratch("bad");
        let empty = dir.join("empty.csv");
        std::fs::write(&empty, "").unwrap();
        assert!(ResultTable::read(&empty).unwrap_err().to_string().contains("is empty"));
        let header_only = dir.join("header.csv");
        std::fs::write(&header_only, "t,x\n").unwrap();
        assert!(ResultTable::read(&header_only).unwrap_err().to_string().contains("a header but no rows"));
        let ragged = dir.join("ragged.csv");
        std::fs::write(&ragged, "t,x\n0,1\n1\n").unwrap();
        assert!(ResultTable::read(&ragged).unwrap_err().to_string().contains("ragged.csv:3: 1 values"));
        let text = dir.join("text.csv");
        std::fs::write(&text, "t,x\n0,abc\n").unwrap();
        let e = ResultTable::read(&text).unwrap_err().to_string();
        assert!(e.contains("text.csv:2: column `x`: `abc` is not a number"), "{e}");
        let e = ResultTable::read(&dir.join("missing.csv")).unwrap_err().to_string();
        assert!(e.contains("cannot read") && e.contains("missing.csv"), "{e}");
    }

    #[test]
    fn non_finite_values_are_named_by_line_and_column() {
        let dir = scratch("finite");
        let csv = dir.join("run.csv");
        std::fs::write(&csv, "t,x,y\n0,1,2\n\n1,inf,3\n2,4,NaN\n").unwrap();
        let table = ResultTable::read(&csv).unwrap();
        let e = table.finite_column("x", "a plot").unwrap_err().to_string();
        assert_eq!(e, format!("{}:4: column `x` holds inf; a plot needs finite values", csv.display()));
        let e = table.finite_column("y", "a spectrum").unwrap_err().to_string();
        assert!(e.ends_with("run.csv:5: column `y` holds NaN; a spectrum needs finite values"), "{e}");
        assert_eq!(table.finite_column("t", "a plot").unwrap(), &[0.0, 1.0, 2.0]);
    }
}
