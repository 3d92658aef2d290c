//! Outputs of a simulation: the frame at one output time, the sinks that take frames, and an
//! in-memory table with named columns.

use crate::analysis::{output_columns, OutputColumn};
use crate::model::Model;

/// The outputs at one output time.
#[derive(Clone, Copy, Debug)]
pub struct OutputFrame<'a> {
    /// The output time (s).
    pub t: f64,
    /// One value per [`output_columns`] entry.
    pub values: &'a [f64],
    /// The positions `q` (per body `R, p, a`) at `t`.
    pub q: &'a [f64],
    /// The velocities `v` (per body `Ṙ, ω̄, ȧ`) at `t`.
    pub v: &'a [f64],
}

/// Where a simulation's output frames go, one at a time as they are computed: a table in memory
/// ([`OutputTable`]), a file writer, a plot, a closure (`FnMut(&OutputFrame)` is a sink that never
/// fails).
pub trait OutputSink {
    /// Takes one frame; an error stops the simulation with [`SimulationFailure::Output`](super::SimulationFailure::Output).
    fn write_frame(&mut self, frame: &OutputFrame) -> Result<(), String>;
}

impl<F: FnMut(&OutputFrame)> OutputSink for F {
    fn write_frame(&mut self, frame: &OutputFrame) -> Result<(), String> {
        self(frame);
        Ok(())
    }
}

/// The output frames of a run in memory: one row per output time, the time first and then one column
/// per [`output_columns`] entry; optionally the positions and velocities of each row too.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OutputTable {
    columns: Vec<OutputColumn>,
    /// Row-major values, `columns.len()` per row.
    values: Vec<f64>,
    keep_states: bool,
    /// Row-major positions and velocities (when kept).
    q: Vec<f64>,
    v: Vec<f64>,
    nq: usize,
    nv: usize,
}

impl OutputTable {
    /// An empty table for the outputs of `model`: column `t` (s), then the model's output columns.
    pub fn new(model: &Model) -> Self {
        let mut columns = vec![OutputColumn { name: "t".into(), unit: "s".into() }];
        columns.extend(output_columns(model));
        Self { columns, nq: model.layout.nq, nv: model.layout.nv, ..Default::default() }
    }

    /// [`new`](Self::new), also keeping the positions `q` and velocities `v` of every row.
    pub fn with_states(model: &Model) -> Self {
        Self { keep_states: true, ..Self::new(model) }
    }

    /// The columns, `t` first.
    pub fn columns(&self) -> &[OutputColumn] {
        &self.columns
    }

    /// Number of rows (output times).
    pub fn len(&self) -> usize {
        self.values.len() / self.columns.len()
    }

    /// No row yet.
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Row `i`: the time, then the output values; `None` for `i` not below [`len`](Self::len).
    pub fn row(&self, i: usize) -> Option<&[f64]> {
        let w = self.columns.len();
        self.values.get(i * w..(i + 1) * w)
    }

    /// The values of the column named `name` (e.g. `t`, `tip.x`, `energy.total`), one per row.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let c = self.columns.iter().position(|col| col.name == name)?;
        let w = self.columns.len();
        Some(self.values.chunks_exact(w).map(|row| row[c]).collect())
    }

    /// The positions of row `i`, if the table keeps them and has that row.
    pub fn positions(&self, i: usize) -> Option<&[f64]> {
        if !self.keep_states {
            return None;
        }
        self.q.get(i * self.nq..(i + 1) * self.nq)
    }

    /// The velocities of row `i`, if the table keeps them and has that row.
    pub fn velocities(&self, i: usize) -> Option<&[f64]> {
        if !self.keep_states {
            return None;
        }
        self.v.get(i * self.nv..(i + 1) * self.nv)
    }
}

impl OutputSink for OutputTable {
    fn write_frame(&mut self, frame: &OutputFrame) -> Result<(), String> {
        if frame.values.len() + 1 != self.columns.len() {
            return Err(format!(
                "the table has {} output columns, the frame {} values",
                self.columns.len() - 1,
                frame.values.len()
            ));
        }
        if self.keep_states && (frame.q.len() != self.nq || frame.v.len() != self.nv) {
            return Err(format!(
                "the table keeps {} positions and {} velocities per row, the frame has {} and {}",
                self.nq,
                self.nv,
                frame.q.len(),
                frame.v.len()
            ));
        }
        self.values.push(frame.t);
        self.values.extend_from_slice(frame.values);
        if self.keep_states {
            self.q.extend_from_slice(frame.q);
            self.v.extend_from_slice(frame.v);
        }
        Ok(())
    }
}
