//! The Abaqus / CalculiX `.inp` reader: the beam, shell and solid subset of the input deck that
//! describes a flexible body's mesh, sections, materials, point masses, couplings and supports.
//!
//! # What is read
//!
//! * Syntax: comment lines `**`; keyword lines `*KEYWORD, PARAM=value, FLAG` (case-insensitive,
//!   spaces inside keywords normalized, a keyword line ending in a comma continued on the next line
//!   when that holds parameters); comma-separated data lines; Fortran number formats (`1.`, `2.1E+11`,
//!   `1.5D3`); `*INCLUDE, INPUT=file` relative to the including file (for [`parse_inp`], relative to
//!   the folder of its `file_name`).
//! * `*NODE` (`NSET=`), `*ELEMENT, TYPE=…, ELSET=…` with types `B31`, `B31H`, `B33`, `B33H` (2-node
//!   beams, optionally with a third orientation node), `S3`, `S3R`, `S4`, `S4R` (shells; a quadrilateral
//!   with a repeated node becomes a triangle), `C3D4`, `C3D10`, `C3D6`, `C3D15`, `C3D8`, `C3D8I`,
//!   `C3D20`, `C3D20R` (solids, see [`element::solid`](crate::element::solid)), `MASS`, `ROTARYI`
//!   (one node); a data line ending in a comma continues on the next while nodes are missing.
//! * `*NSET, NSET=` and `*ELSET, ELSET=` with labels and names of sets defined earlier, or
//!   `GENERATE` (`first, last[, increment]`); repeated definitions add to the set. Set and material
//!   names are case-insensitive.
//! * `*MATERIAL, NAME=` with `*ELASTIC` (isotropic E, ν) and `*DENSITY` (ρ).
//! * `*BEAM SECTION, ELSET=, MATERIAL=, SECTION=RECT|CIRC|PIPE|BOX` (dimensions on the first data
//!   line, properties from [`sections`]); `*BEAM GENERAL SECTION, ELSET=, DENSITY=,
//!   SECTION=GENERAL|RECT|CIRC|PIPE|BOX` (first line A, I₁₁, I₁₂, I₂₂, J or the dimensions; third line
//!   E, G, from which ν = E / 2G − 1; I₁₂ must be zero). The second data line is the first section
//!   direction n₁ ([`BeamSection::orientation`](crate::mesh::BeamSection::orientation)); without it
//!   n₁ = (0, 0, −1), the default of Abaqus and CalculiX, and a beam along z is an error (as in
//!   CalculiX). A beam's orientation node, when given, sets n₁ from its first node to that node (a copy
//!   of the section per distinct direction). Sections are Euler–Bernoulli
//!   (`shear_coefficient: None`).
//! * `*SHELL SECTION, ELSET=, MATERIAL=` with the thickness on the data line.
//! * `*SOLID SECTION, ELSET=, MATERIAL=` (data lines, `ORIENTATION` ignored).
//! * `*KINEMATIC COUPLING, REF NODE=` with lines `node or node set, 1, 3` (or `1, 6`), and
//!   `*RIGID BODY, NSET=, REF NODE=`: rigid couplings to a reference node
//!   ([`RigidCoupling`](crate::mesh::RigidCoupling)).
//! * `*DISTRIBUTING COUPLING, ELSET=` with lines `node or node set, weight`, the set holding one
//!   `DCOUP3D` element whose node is the reference node: a distributing coupling
//!   ([`DistributingCoupling`](crate::mesh::DistributingCoupling)). `*COUPLING` (with `*KINEMATIC` or
//!   `*DISTRIBUTING`) is refused with a message that names these forms.
//! * `*MASS, ELSET=` (mass) and `*ROTARY INERTIA, ELSET=` (I₁₁, I₂₂, I₃₃ in global axes; I₁₂, I₁₃, I₂₃
//!   must be zero) for `MASS` / `ROTARYI` elements, which become [`PointMass`](crate::mesh::PointMass)es.
//! * `*BOUNDARY` lines `node or node set, first dof[, last dof[, value]]` or `node, ENCASTRE`
//!   (`PINNED`, `XSYMM`, …), in or out of steps: the degrees of freedom are held fixed (a nonzero value
//!   gives a warning), merged per node into [`Support`](crate::mesh::Support)s.
//!
//! Every other keyword (`*STEP`, `*FREQUENCY`, `*STATIC`, `*CLOAD`, `*NODE PRINT`, `*EL FILE`,
//! `*END STEP`, …) and its data lines are skipped with one warning per keyword. Unknown element types,
//! elements without a section, undefined nodes, sets and materials, and malformed numbers are errors
//! naming the file and line.

mod lexer;
mod reader;
pub mod sections;
#[cfg(test)]
mod tests;

use std::path::Path;

use crate::mesh::FeModel;

pub use reader::DEFAULT_N1;

/// A model read from a deck: the FE model (mesh, supports from `*BOUNDARY`, no static loads, default
/// options) and the warnings about what was skipped or approximated, each `file:line: message`.
#[derive(Clone, Debug, PartialEq)]
pub struct InpModel {
    /// The FE model.
    pub model: FeModel,
    /// What was skipped or approximated, `file:line: message` each.
    pub warnings: Vec<String>,
}

/// Why a deck cannot be read.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InpError {
    /// The file given to [`read_inp`] cannot be read.
    #[error("{file}: cannot read: {message}")]
    Read {
        /// The file's name.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The input is wrong or unsupported at this line.
    #[error("{file}:{line}: {message}")]
    Input {
        /// The file's name.
        file: String,
        /// The line (from 1).
        line: usize,
        /// What is wrong.
        message: String,
    },
}

impl InpError {
    /// The line the error is at (`None` for [`InpError::Read`]).
    pub fn line(&self) -> Option<usize> {
        match self {
            InpError::Read { .. } => None,
            InpError::Input { line, .. } => Some(*line),
        }
    }
}

/// Reads an `.inp` file; `*INCLUDE` files are found relative to it.
pub fn read_inp(path: &Path) -> Result<InpModel, InpError> {
    reader::read(&deck_cards(path)?)
}

/// The cards of the deck at `path`, its `*INCLUDE`s followed.
fn deck_cards(path: &Path) -> Result<Vec<lexer::Card>, InpError> {
    let bytes = crate::input::read_file(path).map_err(|e| InpError::Read {
        file: path.display().to_string(),
        message: e.to_string(),
    })?;
    let text = String::from_utf8_lossy(&bytes);
    lexer::cards(&text, &path.display().to_string(), path.parent())
}

/// Reads only the nodes and the node sets (`*NODE`, `*NSET`) of the deck at `path` (and of the files
/// it `*INCLUDE`s): the geometry of matrices another program exported from that deck, whose elements
/// the matrices already hold. The model has no elements.
pub fn read_inp_nodes(path: &Path) -> Result<InpModel, InpError> {
    let nodes: Vec<_> = deck_cards(path)?.into_iter().filter(|c| c.keyword == "NODE" || c.keyword == "NSET").collect();
    reader::read(&nodes)
}

/// Reads a deck from text; `file_name` is what messages show, and `*INCLUDE` files are found relative
/// to its folder.
pub fn parse_inp(text: &str, file_name: &str) -> Result<InpModel, InpError> {
    let cards = lexer::cards(text, file_name, Path::new(file_name).parent())?;
    reader::read(&cards)
}
