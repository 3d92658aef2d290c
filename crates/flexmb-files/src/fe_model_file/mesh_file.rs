//! `[fe_model] mesh`: an Abaqus/CalculiX `.inp` deck the model starts from, and the conversion of the
//! deck reader's errors into located errors of the deck's own file and line.

use std::path::{Path, PathBuf};

use flexmb_fem::inp::{read_inp, InpError};

use super::build::Builder;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::Name;
use crate::model_file::{ErrorKind, ModelFileError};

/// Reads the deck `mesh` names (relative to `base_dir`) into the builder's empty model, with its names
/// of materials, sections and node sets.
pub(crate) fn add_mesh(b: &mut Builder, mesh: &Name, base_dir: &Path) -> Result<(), ModelFileError> {
    let key = KeyPath::root().key("fe_model").key("mesh");
    if mesh.get_ref().trim().is_empty() {
        return Err(b.ctx.invalid(&mesh.span(), &key, "expected the path of an .inp mesh file, got an empty string"));
    }
    let path = mesh_path(base_dir, mesh.get_ref());
    let shown = path.display().to_string();
    let inp = read_inp(&path).map_err(|e| match e {
        InpError::Read { message, .. } => {
            b.ctx.invalid(&mesh.span(), &key, format!("cannot read the mesh file `{shown}`: {message}"))
        }
        other => inp_error(&other),
    })?;
    let mesh_model = inp.model;
    b.warnings.extend(inp.warnings);
    let m = &mesh_model.mesh;
    b.materials.add_from_mesh(&shown, m.materials.iter().enumerate().map(|(i, x)| (x.name.as_str(), i)));
    b.beam_sections.add_from_mesh(&shown, m.beam_sections.iter().enumerate().map(|(i, x)| (x.name.as_str(), i)));
    b.shell_sections.add_from_mesh(&shown, m.shell_sections.iter().enumerate().map(|(i, x)| (x.name.as_str(), i)));
    b.parts.add_from_mesh(&shown, m.node_sets.keys().map(|name| (name.as_str(), 0)));
    b.support_origins = vec![None; mesh_model.supports.len()];
    b.model = mesh_model;
    b.mesh_file = Some(shown);
    b.sources.extend(deck_files(&path));
    Ok(())
}

/// How deep `*INCLUDE`s are followed (the deck reader's own limit).
const MAX_INCLUDE_DEPTH: usize = 16;

/// The deck at `path` and every file it `*INCLUDE`s (relative to the including file, as the deck
/// reader finds them), each once, in the order met. Files that cannot be read are listed but not
/// followed: the deck reader has already reported them.
pub(crate) fn deck_files(path: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    collect_deck_files(path, 0, &mut files);
    files
}

fn collect_deck_files(path: &Path, depth: usize, files: &mut Vec<PathBuf>) {
    if files.iter().any(|f| f == path) {
        return;
    }
    files.push(path.to_path_buf());
    if depth >= MAX_INCLUDE_DEPTH {
        return;
    }
    let Ok(bytes) = flexmb_fem::input::read_file(path) else { return };
    let text = String::from_utf8_lossy(&bytes);
    for line in text.lines() {
        if let Some(input) = include_input(line) {
            let input = Path::new(&input);
            let included = match path.parent() {
                Some(dir) if input.is_relative() => dir.join(input),
                _ => input.to_path_buf(),
            };
            collect_deck_files(&included, depth + 1, files);
        }
    }
}

/// The `INPUT=` file of an `*INCLUDE` keyword line.
fn include_input(line: &str) -> Option<String> {
    let text = line.trim_start();
    if !text.starts_with('*') || text.starts_with("**") {
        return None;
    }
    let mut parts = text[1..].split(',');
    let keyword: String = parts.next()?.split_whitespace().collect::<Vec<_>>().join(" ");
    if !keyword.eq_ignore_ascii_case("INCLUDE") {
        return None;
    }
    parts.find_map(|p| {
        let (key, value) = p.split_once('=')?;
        key.trim().eq_ignore_ascii_case("INPUT").then(|| value.trim().trim_matches('"').trim().to_string())
    })
}

/// `mesh` relative to `base_dir`, unless it is absolute.
pub(crate) fn mesh_path(base_dir: &Path, mesh: &str) -> PathBuf {
    let mesh = Path::new(mesh);
    if mesh.is_absolute() {
        mesh.to_path_buf()
    } else {
        base_dir.join(mesh)
    }
}

/// A deck reader's error as an error of the deck's file and line.
pub(crate) fn inp_error(error: &InpError) -> ModelFileError {
    match error {
        InpError::Read { file, message } => ModelFileError {
            kind: ErrorKind::Io,
            file: file.clone(),
            line: None,
            key_path: String::new(),
            message: format!("cannot read the mesh file: {message}"),
        },
        InpError::Input { file, line, message } => ModelFileError {
            kind: ErrorKind::Invalid,
            file: file.clone(),
            line: Some(*line),
            key_path: String::new(),
            message: message.clone(),
        },
    }
}
