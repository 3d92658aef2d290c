//! Stiffness and mass matrices exported by other FE programs, with the node coordinates and the map
//! from the matrices' rows to the nodes' degrees of freedom, read into a
//! [`flexmb_fem::mesh::ImportedMatrices`] over the nodes of a mesh (see `docs/fe-model-file.md`,
//! `[matrices]`). The formats:
//!
//! - **`calculix`**: what `ccx` writes for `*FREQUENCY, SOLVER=MATRIXSTORAGE` — `job.sti` and
//!   `job.mas`, one `row column value` line per entry of the upper triangle (1-based), and `job.dof`,
//!   one `node.dof` line per row;
//! - **`matrix-market`**: Matrix Market coordinate files (`%%MatrixMarket matrix coordinate real
//!   symmetric` or `general`), with the same `node.dof` row file;
//! - **`abaqus`**: what Abaqus writes for `*MATRIX GENERATE` with `*MATRIX OUTPUT,
//!   FORMAT=MATRIX INPUT` — `node, dof, node, dof, value` lines, the map inside;
//! - **`ansys`**: what Ansys writes for `*SMAT` and `*EXPORT, …, MMF` (Matrix Market text of one
//!   triangle), the mapping vector of the rows to the nodes (`%` comments, a `count 1` line, then one
//!   node number per line, each standing for that node's x, y and z rows), and the node list (a
//!   header line, then `node x y z` lines) — the files Exudyn's FEM interface reads.
//!
//! A symmetric matrix may be given by one triangle (either) or in full; entries written twice at one
//! position add up, as in coordinate formats.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

/// The formats of exported matrices flexmb reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixFormat {
    /// CalculiX `*FREQUENCY, SOLVER=MATRIXSTORAGE`: `.sti`, `.mas`, `.dof`.
    Calculix,
    /// Matrix Market coordinate files and a `node.dof` row file.
    MatrixMarket,
    /// Abaqus `*MATRIX OUTPUT, FORMAT=MATRIX INPUT`: `node, dof, node, dof, value`.
    Abaqus,
    /// Ansys `*EXPORT, …, MMF` with a mapping vector and a node list (Exudyn's FEM interface).
    Ansys,
}

impl MatrixFormat {
    /// Every format, in the order of the documentation.
    pub const ALL: [MatrixFormat; 4] = [MatrixFormat::Calculix, MatrixFormat::MatrixMarket, MatrixFormat::Abaqus, MatrixFormat::Ansys];

    /// The name in FE model files.
    pub fn name(self) -> &'static str {
        match self {
            MatrixFormat::Calculix => "calculix",
            MatrixFormat::MatrixMarket => "matrix-market",
            MatrixFormat::Abaqus => "abaqus",
            MatrixFormat::Ansys => "ansys",
        }
    }

    /// The format of a name.
    pub fn parse(name: &str) -> Option<MatrixFormat> {
        MatrixFormat::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The supported formats as a sentence, for messages.
    pub fn supported() -> String {
        "calculix (ccx *FREQUENCY, SOLVER=MATRIXSTORAGE: .sti, .mas, .dof), matrix-market (coordinate files with a \
         node.dof row file), abaqus (*MATRIX OUTPUT, FORMAT=MATRIX INPUT), ansys (*EXPORT MMF files, a mapping \
         vector and a node list)"
            .to_string()
    }

    /// Whether the format's row map is a file of its own (`dofs`).
    pub fn needs_dof_file(self) -> bool {
        !matches!(self, MatrixFormat::Abaqus)
    }
}

/// A problem in one of the files: the file, the 1-based line when there is one, and what is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixFileError {
    /// The file as given.
    pub file: String,
    /// The 1-based line.
    pub line: Option<usize>,
    /// What is wrong and what was expected.
    pub message: String,
}

impl std::fmt::Display for MatrixFileError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

/// A matrix row's node (its label) and dof (0 … 5 for `x y z rx ry rz`).
pub type RowDof = (u64, usize);

/// One matrix as read: entries `(row, column, value)` over the file's own row numbers (0-based), or,
/// for the Abaqus format, over the rows of its own map.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MatrixEntries {
    /// The file, for messages.
    pub file: String,
    /// `(row, column, value, line)`.
    pub entries: Vec<(usize, usize, f64, usize)>,
    /// The rows' node and dof, when the file gives them (Abaqus).
    pub rows: Vec<RowDof>,
}

fn located(file: &str, line: usize, message: impl Into<String>) -> MatrixFileError {
    MatrixFileError { file: file.to_string(), line: Some(line), message: message.into() }
}

/// Reads a text file, its error as a [`MatrixFileError`].
pub fn read_text(path: &Path, what: &str) -> Result<String, MatrixFileError> {
    let bytes = flexmb_fem::input::read_file(path).map_err(|e| MatrixFileError {
        file: path.display().to_string(),
        line: None,
        message: format!("cannot read the {what}: {e}"),
    })?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

fn parse_real(field: &str) -> Option<f64> {
    field.trim().replace(['D', 'd'], "e").parse::<f64>().ok().filter(|v| v.is_finite())
}

/// Which lines come before a coordinate matrix's entries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordinateLayout {
    /// Entries only (CalculiX).
    Entries,
    /// A size line `ROWS COLUMNS ENTRIES` first, after `%` comments (Ansys' MMF export; a Matrix
    /// Market header, if there is one, is checked).
    SizeLine,
    /// The `%%MatrixMarket matrix coordinate real …` header, comments, the size line.
    MatrixMarket,
}

/// `row column value` lines (1-based) after the lines `layout` asks for; `%` lines are comments.
pub fn parse_coordinate(text: &str, file: &str, layout: CoordinateLayout) -> Result<MatrixEntries, MatrixFileError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty()).peekable();
    let first = lines.peek().map(|(_, l)| l.to_ascii_lowercase()).unwrap_or_default();
    if layout == CoordinateLayout::MatrixMarket || first.starts_with("%%matrixmarket") {
        let words: Vec<&str> = first.split_whitespace().collect();
        let ok = words.len() >= 5
            && words[0] == "%%matrixmarket"
            && words[1] == "matrix"
            && words[2] == "coordinate"
            && matches!(words[3], "real" | "double" | "integer")
            && matches!(words[4], "symmetric" | "general");
        if !ok {
            return Err(located(
                file,
                lines.peek().map_or(1, |(n, _)| *n),
                format!(
                    "expected the Matrix Market header `%%MatrixMarket matrix coordinate real symmetric` (or `general`), \
                     got `{first}`"
                ),
            ));
        }
    }
    let mut data = lines.filter(|(_, l)| !l.starts_with('%'));
    let mut size: Option<(usize, usize)> = None;
    if layout != CoordinateLayout::Entries {
        let (n, line) = data.next().ok_or_else(|| MatrixFileError { file: file.into(), line: None, message: "no size line".into() })?;
        let dims: Option<Vec<usize>> = line.split_whitespace().map(|f| f.parse().ok()).collect();
        match dims.as_deref() {
            Some([rows, cols, _]) => size = Some((*rows, *cols)),
            _ => return Err(located(file, n, format!("expected the size line `ROWS COLUMNS ENTRIES`, got `{line}`"))),
        }
    }
    let mut entries = Vec::new();
    for (n, line) in data {
        let fields: Vec<&str> = line.split_whitespace().collect();
        let parsed = match fields[..] {
            [r, c, v] => r.parse::<usize>().ok().zip(c.parse::<usize>().ok()).zip(parse_real(v)),
            _ => None,
        };
        let Some(((r, c), v)) = parsed.filter(|((r, c), _)| *r >= 1 && *c >= 1) else {
            return Err(located(file, n, format!("expected `ROW COLUMN VALUE` (rows and columns from 1, a finite value), got `{line}`")));
        };
        if let Some((rows, cols)) = size {
            if r > rows || c > cols {
                return Err(located(file, n, format!("entry ({r}, {c}) is outside the matrix's {rows} × {cols}")));
            }
        }
        entries.push((r - 1, c - 1, v, n));
    }
    if entries.is_empty() {
        return Err(MatrixFileError { file: file.to_string(), line: None, message: "the matrix has no entries".into() });
    }
    Ok(MatrixEntries { file: file.to_string(), entries, rows: Vec::new() })
}

/// Abaqus' `node, dof, node, dof, value` lines (`*` lines are headings or comments).
pub fn parse_abaqus(text: &str, file: &str) -> Result<MatrixEntries, MatrixFileError> {
    let mut rows: Vec<RowDof> = Vec::new();
    let mut index: HashMap<RowDof, usize> = HashMap::new();
    let mut entries = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let (n, line) = (i + 1, line.trim());
        if line.is_empty() || line.starts_with('*') {
            continue;
        }
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        let parsed = match fields[..] {
            [a, i, b, j, v] => (|| {
                let dof = |f: &str| f.parse::<usize>().ok().filter(|d| (1..=6).contains(d)).map(|d| d - 1);
                Some(((a.parse::<u64>().ok()?, dof(i)?), (b.parse::<u64>().ok()?, dof(j)?), parse_real(v)?))
            })(),
            _ => None,
        };
        let Some((ra, rb, v)) = parsed else {
            return Err(located(
                file,
                n,
                format!(
                    "expected `NODE, DOF, NODE, DOF, VALUE` (node labels, dofs 1 to 6; Abaqus' internal nodes with \
                     negative labels, Lagrange multipliers, are not supported), got `{line}`"
                ),
            ));
        };
        let mut row_of = |r: RowDof| {
            *index.entry(r).or_insert_with(|| {
                rows.push(r);
                rows.len() - 1
            })
        };
        let (a, b) = (row_of(ra), row_of(rb));
        entries.push((a, b, v, n));
    }
    if entries.is_empty() {
        return Err(MatrixFileError { file: file.to_string(), line: None, message: "the matrix has no entries".into() });
    }
    Ok(MatrixEntries { file: file.to_string(), entries, rows })
}

/// A `node.dof` line per matrix row (CalculiX's `.dof` file).
pub fn parse_dof_file(text: &str, file: &str) -> Result<Vec<RowDof>, MatrixFileError> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('%') || line.starts_with('#') {
            continue;
        }
        let parsed = line.split_once('.').and_then(|(node, dof)| {
            let dof = dof.trim().parse::<usize>().ok().filter(|d| (1..=6).contains(d))?;
            Some((node.trim().parse::<u64>().ok()?, dof - 1))
        });
        match parsed {
            Some(row) => rows.push(row),
            None => return Err(located(file, i + 1, format!("expected `NODE.DOF` (a node label, a dof from 1 to 6), got `{line}`"))),
        }
    }
    Ok(rows)
}

/// Ansys' mapping vector: `%` comments, a `COUNT 1` line, then COUNT node numbers, one a line, each
/// the node of three rows (its x, y, z).
pub fn parse_ansys_mapping(text: &str, file: &str) -> Result<Vec<RowDof>, MatrixFileError> {
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l.trim())).filter(|(_, l)| !l.is_empty() && !l.starts_with('%'));
    let (n, header) = lines.next().ok_or_else(|| MatrixFileError { file: file.into(), line: None, message: "the mapping vector is empty".into() })?;
    let count = match header.split_whitespace().map(str::parse::<usize>).collect::<Result<Vec<_>, _>>().as_deref() {
        Ok([count, 1]) => *count,
        _ => return Err(located(file, n, format!("expected the size line `COUNT 1` of the mapping vector, got `{header}`"))),
    };
    let mut rows = Vec::with_capacity(3 * count);
    for (n, line) in lines {
        let node = parse_real(line).filter(|v| *v >= 1.0 && v.fract() == 0.0).ok_or_else(|| {
            located(file, n, format!("expected a node number, got `{line}`"))
        })? as u64;
        rows.extend((0..3).map(|d| (node, d)));
    }
    if rows.len() != 3 * count {
        return Err(MatrixFileError {
            file: file.into(),
            line: None,
            message: format!("the mapping vector says {count} entries but has {}", rows.len() / 3),
        });
    }
    Ok(rows)
}

/// Ansys' node list: a header line, then `NODE X Y Z` lines (whitespace between fields; a decimal
/// comma is read as a point, as Exudyn does).
pub fn parse_node_list(text: &str, file: &str) -> Result<Vec<(u64, [f64; 3])>, MatrixFileError> {
    let mut nodes = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('%') || line.starts_with('#') {
            continue;
        }
        let fields: Vec<String> = line.split_whitespace().map(|f| f.replace(',', ".")).collect();
        let parsed = (|| {
            let label = fields.first()?.parse::<u64>().ok()?;
            let xyz: Vec<f64> = fields[1..].iter().map(|f| parse_real(f)).collect::<Option<_>>()?;
            (xyz.len() == 3).then(|| (label, [xyz[0], xyz[1], xyz[2]]))
        })();
        match parsed {
            Some(node) => nodes.push(node),
            None if i == 0 || nodes.is_empty() && fields.first().is_some_and(|f| f.parse::<f64>().is_err()) => continue,
            None => return Err(located(file, i + 1, format!("expected `NODE X Y Z`, got `{line}`"))),
        }
    }
    Ok(nodes)
}

/// The upper triangle over global dofs (`6 node + dof`) of a symmetric matrix read as `entries` over
/// rows that `rows` maps to (node label, dof), with `node_index` giving each label's mesh index. One
/// triangle is mirrored; a matrix given in full must be symmetric (to 1e-6 relative).
pub fn upper_triangle(
    matrix: &MatrixEntries,
    rows: &[RowDof],
    node_index: &HashMap<u64, usize>,
    rows_file: &str,
) -> Result<Vec<(usize, usize, f64)>, MatrixFileError> {
    let global = |row: usize, line: usize| -> Result<usize, MatrixFileError> {
        let &(label, dof) = rows.get(row).ok_or_else(|| {
            located(&matrix.file, line, format!("row {} has no node in the row map `{rows_file}` ({} rows)", row + 1, rows.len()))
        })?;
        let node = node_index.get(&label).ok_or_else(|| {
            located(&matrix.file, line, format!("row {} is of node {label}, which the node coordinates do not define", row + 1))
        })?;
        Ok(6 * node + dof)
    };
    // Sums of the entries on or above and below the diagonal (with a line), by (min, max) position.
    type Sum = Option<(f64, usize)>;
    let mut sums: BTreeMap<(usize, usize), [Sum; 2]> = BTreeMap::new();
    for &(r, c, v, line) in &matrix.entries {
        let (a, b) = (global(r, line)?, global(c, line)?);
        let slot = usize::from(a > b);
        let cell = &mut sums.entry((a.min(b), a.max(b))).or_insert([None, None])[slot];
        *cell = Some((cell.map_or(0.0, |(s, _)| s) + v, line));
    }
    let mut upper = Vec::with_capacity(sums.len());
    for ((a, b), [above, below]) in sums {
        let value = match (above, below) {
            (Some((x, _)), None) | (None, Some((x, _))) => x,
            (Some((x, _)), Some((y, line))) => {
                if (x - y).abs() > 1e-6 * x.abs().max(y.abs()) {
                    return Err(located(
                        &matrix.file,
                        line,
                        format!("the matrix is not symmetric: {x:e} above the diagonal and {y:e} below it at the same position"),
                    ));
                }
                0.5 * (x + y)
            }
            (None, None) => continue,
        };
        upper.push((a, b, value));
    }
    Ok(upper)
}
