//! Dense matrices as Matrix Market files (`%%MatrixMarket matrix array real general`: the size, then
//! the entries column by column, one a line), written with 17 significant digits so that they read
//! back exactly; read by `scipy.io.mmread`, MATLAB's `mmread`, Julia's `MatrixMarket`. The linear
//! models of `flexmb linearize` are written this way.

use std::fmt::Write as _;
use std::path::Path;

/// A dense matrix read from a Matrix Market file: its size and entries by rows.
#[derive(Clone, Debug, PartialEq)]
pub struct DenseMatrix {
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Entries, row by row (`rows × cols`).
    pub values: Vec<f64>,
}

impl DenseMatrix {
    /// The entry at row `i`, column `j`.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.values[i * self.cols + j]
    }
}

/// The Matrix Market text of the `rows × cols` matrix whose entries `entry(i, j)` gives.
pub fn matrix_market_text(rows: usize, cols: usize, entry: impl Fn(usize, usize) -> f64) -> String {
    let mut text = format!("%%MatrixMarket matrix array real general\n% written by flexmb\n{rows} {cols}\n");
    for j in 0..cols {
        for i in 0..rows {
            let _ = writeln!(text, "{:.16e}", entry(i, j));
        }
    }
    text
}

/// Writes the `rows × cols` matrix of `entry(i, j)` to `path`.
pub fn write_matrix_market(path: &Path, rows: usize, cols: usize, entry: impl Fn(usize, usize) -> f64) -> Result<(), String> {
    std::fs::write(path, matrix_market_text(rows, cols, entry)).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Reads a dense (`array real general`) Matrix Market file.
pub fn read_matrix_market(path: &Path) -> Result<DenseMatrix, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    parse_matrix_market(&text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Parses the text of a dense (`array real general`) Matrix Market file.
pub fn parse_matrix_market(text: &str) -> Result<DenseMatrix, String> {
    let mut lines = text.lines().enumerate();
    let header = lines.next().map(|(_, l)| l.to_ascii_lowercase()).unwrap_or_default();
    if !(header.starts_with("%%matrixmarket matrix array real general")) {
        return Err("line 1: expected `%%MatrixMarket matrix array real general`".into());
    }
    let mut data = lines.filter(|(_, l)| !l.starts_with('%') && !l.trim().is_empty());
    let (n, size) = data.next().ok_or("no size line")?;
    let dims: Vec<usize> = size.split_whitespace().map(str::parse).collect::<Result<_, _>>().map_err(|e| format!("line {}: {e}", n + 1))?;
    let [rows, cols] = dims[..] else { return Err(format!("line {}: expected `ROWS COLS`", n + 1)) };
    let mut values = vec![0.0; rows * cols];
    for k in 0..rows * cols {
        let (n, line) = data.next().ok_or_else(|| format!("{} entries, expected {}", k, rows * cols))?;
        let x: f64 = line.trim().parse().map_err(|e| format!("line {}: {e}", n + 1))?;
        values[(k % rows) * cols + k / rows] = x;
    }
    Ok(DenseMatrix { rows, cols, values })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every f64 reads back exactly, in its place.
    #[test]
    fn a_matrix_reads_back_exactly() {
        let entry = |i: usize, j: usize| (i as f64 + 1.0).sqrt() * std::f64::consts::PI.powi(j as i32) * 1e-7 - 0.1 * j as f64;
        let m = parse_matrix_market(&matrix_market_text(3, 4, entry)).unwrap();
        assert_eq!((m.rows, m.cols), (3, 4));
        for i in 0..3 {
            for j in 0..4 {
                assert_eq!(m.get(i, j).to_bits(), entry(i, j).to_bits());
            }
        }
        assert!(parse_matrix_market("%%MatrixMarket matrix coordinate real general\n").is_err());
    }
}
