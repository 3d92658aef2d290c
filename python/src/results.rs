//! `flexmb.Results`: the output rows of a run in memory, each column a numpy array by name, with the
//! JSON summary `flexmb run` writes (settings, statistics, residuals, energy, columns).

use std::path::Path;

use flexmb::analysis::{output_columns, OutputTable, SimulationReport, SimulationSettings};
use flexmb::Model;
use flexmb_files::results::{summary_json, RunRequest};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyImportError, PyKeyError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict};

/// The outputs of a run: `time` and every output column as numpy arrays (`results["tip.x"]`), the
/// column names and units, the run's statistics and its summary.
#[pyclass(frozen, module = "flexmb._native")]
pub struct Results {
    columns: Vec<String>,
    units: Vec<String>,
    /// Row-major, `columns.len()` values per row, `t` first.
    values: Vec<f64>,
    /// The JSON summary, as `flexmb run` writes it (its `output.csv` null: no file was written).
    summary: String,
}

impl Results {
    /// The rows of `table` from a run of `model` with `settings` (from the file named `file`) whose
    /// report is `report`, failed with `error` if it did.
    pub fn of_run(
        model: &Model,
        file: &str,
        settings: &SimulationSettings,
        report: &SimulationReport,
        table: &OutputTable,
        error: Option<&str>,
    ) -> Self {
        let request = RunRequest::of(model, settings, file, report);
        let mut summary = summary_json(&request, report, &output_columns(model), Path::new(""), error);
        summary["output"]["csv"] = serde_json::Value::Null;
        let columns = table.columns();
        Self {
            columns: columns.iter().map(|c| c.name.clone()).collect(),
            units: columns.iter().map(|c| c.unit.to_string()).collect(),
            values: (0..table.len()).filter_map(|i| table.row(i)).flatten().copied().collect(),
            summary: summary.to_string(),
        }
    }

    fn rows(&self) -> usize {
        self.values.len() / self.columns.len().max(1)
    }

    fn column_values(&self, c: usize) -> Vec<f64> {
        self.values.chunks_exact(self.columns.len()).map(|row| row[c]).collect()
    }

    fn json<'py>(&self, py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
        py.import("json")?.call_method1("loads", (text,))
    }
}

#[pymethods]
impl Results {
    /// The output times (s), one per row: the column `t`.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.column_values(0))
    }

    /// The column names, `t` first, as in the header of the result CSV.
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.columns.clone()
    }

    /// The unit of each column (`s`, `m`, `rad`, `N`, `J`, …), in the order of `columns`.
    #[getter]
    fn units(&self) -> Vec<String> {
        self.units.clone()
    }

    /// All values as a 2-D numpy array: a row per output time, a column per name of `columns`.
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        PyArray1::from_slice(py, &self.values).reshape([self.rows(), self.columns.len()])
    }

    /// The run's summary as a dict: what `flexmb run` writes to its JSON file (status, settings,
    /// statistics, assembly, constraint residuals, energy, physics checks, warnings, columns).
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.json(py, &self.summary)
    }

    /// The solver statistics of the summary: steps, rejected steps, error-test and Newton failures,
    /// Newton iterations, residual and Jacobian evaluations, matrix factorizations, RMS step size, wall
    /// time, steps per order.
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.summary(py)?.get_item("statistics")
    }

    /// The column named `name` as a numpy array, one value per output time.
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
        match self.columns.iter().position(|c| c == name) {
            Some(c) => Ok(PyArray1::from_vec(py, self.column_values(c))),
            None => Err(PyKeyError::new_err(format!("no output column '{name}' (the columns are: {})", self.columns.join(", ")))),
        }
    }

    fn __contains__(&self, name: &str) -> bool {
        self.columns.iter().any(|c| c == name)
    }

    /// The number of rows (output times).
    fn __len__(&self) -> usize {
        self.rows()
    }

    /// The results as a pandas DataFrame, a column per name of `columns` (`t` included); raises
    /// `ImportError` when pandas is not installed.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py
            .import("pandas")
            .map_err(|e| PyImportError::new_err(format!("Results.to_pandas needs pandas: pip install pandas ({e})")))?;
        let data = PyDict::new(py);
        for (c, name) in self.columns.iter().enumerate() {
            data.set_item(name, PyArray1::from_vec(py, self.column_values(c)))?;
        }
        pandas.call_method1("DataFrame", (data,))
    }

    fn __repr__(&self) -> String {
        format!("<flexmb.Results: {} rows × {} columns>", self.rows(), self.columns.len())
    }

    /// Pickling, for process pools (`concurrent.futures`, `multiprocessing`) and Ray, which hand a
    /// worker's results back: the column names, the units, the values as little-endian bytes (the
    /// same numbers to the last bit) and the summary.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (Vec<String>, Vec<String>, Bound<'py, PyBytes>, String))> {
        let this = slf.get();
        let bytes: Vec<u8> = this.values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let state = (this.columns.clone(), this.units.clone(), PyBytes::new(slf.py(), &bytes), this.summary.clone());
        Ok((slf.get_type().getattr("_from_state")?, state))
    }

    /// The results `__reduce__` took apart, put together again.
    #[staticmethod]
    fn _from_state(columns: Vec<String>, units: Vec<String>, values: &[u8], summary: String) -> PyResult<Self> {
        if columns.is_empty() || units.len() != columns.len() || values.len() % (8 * columns.len()) != 0 {
            return Err(PyValueError::new_err("not the state of a flexmb.Results"));
        }
        let values = values.chunks_exact(8).map(|b| f64::from_le_bytes(std::array::from_fn(|i| b[i]))).collect();
        Ok(Self { columns, units, values, summary })
    }
}
