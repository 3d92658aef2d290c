//! `[[flexible_body]]` → the engine's modal body: reduced from an FE model file (`fe_model`, through
//! the cache next to it) or read from a flexible-body file written by `flexmb modes` (`body_file`),
//! with its modal damping, initial pose and velocity, and initial modal coordinates and rates. Errors
//! of the FE model file are reported at its own file and line, with the table that referred to it.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::str::FromStr;

use flexmb::body::{HighModeDamping, InitialState, ModalBody, ModalDamping};
use flexmb::model::{BodyId, ModelError};
use flexmb::ModelBuilder;
use flexmb_fem::reduction::{add_modal_stresses, Basis, BodyElement, FlexibleBody, ModalStresses, ModeSet};
use nalgebra::DVector;
use toml::Spanned;

use super::bodies::{initial_state, InitialKeys, GROUND};
use super::body_cache::{basis_name, reduced_body};
use super::context::Context;
use super::engine_errors;
use super::names::NameTable;
use super::nodes::{BodyNodes, FlexibleNodes};
use crate::fe_model_file::{load_fe_model, LoadedFeModel};
use crate::flexible_body::modal_body;
use crate::model_file::error::{ErrorKind, ModelFileError};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{DampingSection, FlexibleBodySection, HighModeDampingSection, Name, Vector};

/// Where a flexible body of a model file came from.
#[derive(Clone, Debug, PartialEq)]
pub enum FlexibleBodyOrigin {
    /// Read from a flexible-body file (`body_file`).
    BodyFile {
        /// The flexible-body file.
        path: PathBuf,
    },
    /// Reduced from the FE model file now, in `seconds`; `cache` is the file it was saved to (`None`
    /// if the cache directory could not be written).
    Reduced {
        /// The FE model file.
        fe_model: PathBuf,
        /// The cached flexible-body file written, if one could be.
        cache: Option<PathBuf>,
        /// The time the reduction took (s).
        seconds: f64,
    },
    /// Read from the cache of an earlier reduction of the same FE model file, mode set and basis.
    Cached {
        /// The FE model file.
        fe_model: PathBuf,
        /// The cached flexible-body file read.
        cache: PathBuf,
    },
}

/// A flexible body of a model file, as loaded: for reports.
#[derive(Clone, Debug, PartialEq)]
pub struct FlexibleBodyInfo {
    /// The body's name in the model.
    pub name: String,
    /// The body in the model.
    pub body: BodyId,
    /// The mode set, e.g. `4N2S`.
    pub mode_set: String,
    /// The basis: raw or mass-orthonormalized modes.
    pub basis: Basis,
    /// The mode labels (`N1`, `S1`, `O1`, …), in basis order.
    pub mode_labels: Vec<String>,
    /// Natural frequencies of the reduced body (Hz), ascending.
    pub frequencies_hz: Vec<f64>,
    /// The damping of its natural modes above a cutoff (`high_mode_damping`), if the table gives one.
    pub high_mode_damping: Option<HighModeDamping>,
    /// Number of nodes.
    pub nodes: usize,
    /// Where the reduced body came from.
    pub origin: FlexibleBodyOrigin,
    /// The FE model file's warnings, the reduction's if it was reduced now, and the table's (a
    /// `high_mode_damping` that damps no mode).
    pub warnings: Vec<String>,
    /// The FE mesh's elements (node indices in the order of the engine's modal nodes), for drawing.
    pub elements: Vec<BodyElement>,
    /// The modal stresses, when the table asks for the body's stresses (`stresses = true`): a run
    /// writes `σ = Σ aⱼ σⱼ` in its ParaView series and reports the hot spot.
    pub stresses: Option<Arc<ModalStresses>>,
}

/// Everything the tables refer to, and where relative paths start.
pub(crate) struct FlexibleTables<'a> {
    pub sections: &'a [Spanned<FlexibleBodySection>],
    /// The model file's directory: `fe_model` and `body_file` paths are relative to it.
    pub base_dir: &'a Path,
    /// Most bytes the mode analysis of a body reduced now may use; `None`: no limit.
    pub memory_limit: Option<u64>,
}

pub(crate) fn add_flexible_bodies(
    ctx: &Context,
    tables: &FlexibleTables,
    builder: &mut ModelBuilder,
    names: &mut NameTable<BodyId>,
    nodes: &mut FlexibleNodes,
) -> Result<Vec<FlexibleBodyInfo>, ModelFileError> {
    let mut infos = Vec::new();
    for (index, section) in tables.sections.iter().enumerate() {
        let element = KeyPath::root().key("flexible_body").index(index);
        let f = section.get_ref();
        names.check_new(&f.name, &element, ctx.source)?;
        if f.name.get_ref() == GROUND {
            return Err(ctx.invalid(
                &f.name.span(),
                &element.key("name"),
                "`ground` is the inertial frame and cannot name a body",
            ));
        }
        let table = Table { ctx, f, element: &element, span: section.span(), memory_limit: tables.memory_limit };
        let mut obtained = table.obtain(tables.base_dir)?;
        let modal = table.modal(&obtained.body, &mut obtained.warnings)?;
        let keys = InitialKeys {
            position: &f.position,
            orientation: &f.orientation,
            velocity: &f.velocity,
            angular_velocity: &f.angular_velocity,
        };
        let initial = initial_state(ctx, &keys, &element)?;
        table.check_with_engine(&initial, &modal)?;
        let name = f.name.get_ref().clone();
        let id = builder
            .add_flexible_body(name.clone(), initial, modal)
            .map_err(engine_errors::at(ctx.source, &section.span(), &element))?;
        // Engine errors about the body are reported at the table's header.
        names.define(&Spanned::new(section.span(), name.clone()), &element, id);
        let stresses = table.stresses(&mut obtained.body)?;
        let body = &obtained.body;
        nodes.insert(
            id,
            BodyNodes {
                body: name.clone(),
                labels: body.nodes.iter().map(|n| n.label).collect(),
                positions: body.nodes.iter().map(|n| n.position).collect(),
                sets: obtained.sets,
            },
        );
        infos.push(FlexibleBodyInfo {
            name,
            body: id,
            mode_set: body.mode_set.clone(),
            basis: body.basis,
            mode_labels: body.modes.iter().map(|m| m.label.clone()).collect(),
            frequencies_hz: body.reduced_frequencies_hz.clone(),
            high_mode_damping: table.high_mode_damping_of_table()?,
            nodes: body.nodes.len(),
            origin: obtained.origin,
            warnings: obtained.warnings,
            elements: body.elements.clone(),
            stresses,
        });
    }
    Ok(infos)
}

/// A reduced body, where it came from, and the FE model's node sets (by label) if there was one.
struct Obtained {
    body: FlexibleBody,
    origin: FlexibleBodyOrigin,
    sets: Option<BTreeMap<String, Vec<u64>>>,
    warnings: Vec<String>,
}

/// One `[[flexible_body]]` table being built.
struct Table<'a> {
    ctx: &'a Context<'a>,
    f: &'a FlexibleBodySection,
    element: &'a KeyPath,
    /// The table's span (its header line).
    span: Range<usize>,
    /// Most bytes the mode analysis may use.
    memory_limit: Option<u64>,
}

impl Table<'_> {
    fn key(&self, name: &str) -> KeyPath {
        self.element.key(name)
    }

    /// The reduced body, from `fe_model` or `body_file` (exactly one).
    fn obtain(&self, base_dir: &Path) -> Result<Obtained, ModelFileError> {
        match (&self.f.fe_model, &self.f.body_file) {
            (Some(fe_model), None) => self.reduce_fe_model(fe_model, base_dir),
            (None, Some(body_file)) => self.read_body_file(body_file, base_dir),
            (Some(_), Some(body_file)) => Err(self.ctx.invalid(
                &body_file.span(),
                &self.key("body_file"),
                "give either `fe_model` (an FE model file to reduce) or `body_file` (a flexible-body file written by \
                 `flexmb modes`), not both",
            )),
            (None, None) => Err(self.ctx.source.error(
                ErrorKind::Schema,
                &self.span,
                self.element,
                "a flexible body needs `fe_model = \"….toml\"` (an FE model file, reduced here) or `body_file = \
                 \"….json\"` (a flexible-body file written by `flexmb modes`)",
            )),
        }
    }

    /// `path` relative to `base_dir`, unless absolute; an empty path is an error.
    fn path(&self, value: &Name, key: &KeyPath, base_dir: &Path, what: &str) -> Result<PathBuf, ModelFileError> {
        let text = value.get_ref();
        if text.trim().is_empty() {
            return Err(self.ctx.invalid(
                &value.span(),
                key,
                format!("expected the path of {what}, got an empty string"),
            ));
        }
        let path = Path::new(text);
        let path = if path.is_absolute() { path.to_path_buf() } else { base_dir.join(path) };
        if let Err(e) = flexmb_fem::input::check_file(&path) {
            return Err(self.ctx.invalid(&value.span(), key, format!("cannot read {what} `{}`: {e}", path.display())));
        }
        Ok(path)
    }

    fn reduce_fe_model(&self, fe_model: &Name, base_dir: &Path) -> Result<Obtained, ModelFileError> {
        let key = self.key("fe_model");
        let path = self.path(fe_model, &key, base_dir, "the FE model file")?;
        let loaded = load_fe_model(&path).map_err(|e| self.fe_model_error(e, fe_model, &key, &path))?;
        let set = self.mode_set(&loaded, &path)?;
        let basis = match &self.f.basis {
            Some(word) => self.ctx.keyword(
                word,
                &self.key("basis"),
                "basis",
                &[("orthonormal", Basis::Orthonormal), ("raw", Basis::Raw)],
            )?,
            None => loaded.defaults.basis.unwrap_or_default(),
        };
        let obtained = reduced_body(&loaded, &path, &set, basis, self.memory_limit).map_err(|e| {
            let (span, key) = match &self.f.modes {
                Some(modes) => (modes.span(), self.key("modes")),
                None => (fe_model.span(), key.clone()),
            };
            self.ctx.invalid(
                &span,
                &key,
                format!("cannot reduce the FE model `{}` to {set} ({} basis): {e}", path.display(), basis_name(basis)),
            )
        })?;
        let mesh = &loaded.model.mesh;
        let sets = mesh
            .node_sets
            .iter()
            .map(|(name, members)| (name.clone(), members.iter().map(|&k| mesh.nodes[k].label).collect()))
            .collect();
        let mut warnings = loaded.warnings.clone();
        warnings.extend(obtained.warnings);
        let mut body = obtained.body;
        if self.wants_stresses() && body.stresses.is_none() {
            // Recovered now from the FE model (the cache holds them only when the FE model file's
            // `[modes] stresses` asks for them).
            add_modal_stresses(&loaded.model, &mut body).map_err(|e| {
                self.ctx.invalid(&fe_model.span(), &key, format!("cannot recover the modal stresses of `{}`: {e}", path.display()))
            })?;
        }
        Ok(Obtained { body, origin: obtained.origin, sets: Some(sets), warnings })
    }

    /// An error of the FE model file: at its own file and line, with the reference appended; an error
    /// of the file as a whole (it cannot be read), at the reference.
    fn fe_model_error(&self, e: ModelFileError, fe_model: &Name, key: &KeyPath, path: &Path) -> ModelFileError {
        if e.line.is_none() && e.file == path.display().to_string() {
            return self.ctx.invalid(&fe_model.span(), key, format!("FE model file `{}`: {}", e.file, e.message));
        }
        let line = self.ctx.source.line(fe_model.span().start);
        ModelFileError {
            message: format!("{} (in the FE model of {key}, {}:{line})", e.message, self.ctx.source.file()),
            ..e
        }
    }

    /// `modes`, else the FE model file's `[modes] set`; not more static modes than it has loads.
    fn mode_set(&self, loaded: &LoadedFeModel, path: &Path) -> Result<ModeSet, ModelFileError> {
        let key = self.key("modes");
        let Some(text) = &self.f.modes else {
            return loaded.defaults.mode_set.clone().ok_or_else(|| {
                self.ctx.source.error(
                    ErrorKind::Schema,
                    &self.span,
                    &key,
                    format!(
                        "missing required key `modes`: the FE model file `{}` has no `[modes] set`; give the mode set, \
                         e.g. `modes = \"4N2S\"` (4 vibration, then 2 static correction modes)",
                        path.display()
                    ),
                )
            });
        };
        let set = ModeSet::from_str(text.get_ref()).map_err(|e| self.ctx.invalid(&text.span(), &key, e.to_string()))?;
        let loads = loaded.model.static_loads.len();
        if set.statics() > loads {
            return Err(self.ctx.invalid(
                &text.span(),
                &key,
                format!(
                    "mode set `{set}` asks for {} static correction mode(s) but the FE model `{}` has {loads} static \
                     load(s) ([[static_load]] tables)",
                    set.statics(),
                    path.display()
                ),
            ));
        }
        Ok(set)
    }

    fn read_body_file(&self, body_file: &Name, base_dir: &Path) -> Result<Obtained, ModelFileError> {
        for (name, value) in [("modes", &self.f.modes), ("basis", &self.f.basis)] {
            if let Some(value) = value {
                return Err(self.ctx.invalid(
                    &value.span(),
                    &self.key(name),
                    format!(
                        "`{name}` goes with `fe_model` only: a flexible-body file holds a body already reduced, with \
                         its own mode set and basis"
                    ),
                ));
            }
        }
        let key = self.key("body_file");
        let path = self.path(body_file, &key, base_dir, "the flexible-body file")?;
        let body = FlexibleBody::read(&path).map_err(|e| {
            self.ctx.invalid(&body_file.span(), &key, format!("cannot read the flexible-body file: {e}"))
        })?;
        Ok(Obtained { body, origin: FlexibleBodyOrigin::BodyFile { path }, sets: None, warnings: Vec::new() })
    }

    /// The engine's modal body with the table's damping (and high-mode damping) and initial modal
    /// coordinates and rates; a warning when the high-mode damping's cutoff lies above every mode.
    fn modal(&self, body: &FlexibleBody, warnings: &mut Vec<String>) -> Result<ModalBody, ModelFileError> {
        let labels: Vec<&str> = body.modes.iter().map(|m| m.label.as_str()).collect();
        let damping = self.damping(&labels)?;
        let mut modal = modal_body(body, &damping).map_err(|message| match &self.f.damping {
            Some(d) => self.ctx.invalid(&d.span(), &self.key("damping"), message),
            None => self.ctx.invalid(&self.span, self.element, message),
        })?;
        if let (Some(section), Some(high)) = (&self.f.high_mode_damping, self.high_mode_damping_of_table()?) {
            let key = self.key("high_mode_damping");
            let matrix = modal
                .high_mode_damping_matrix(&high)
                .map_err(|e| self.ctx.invalid(&section.span(), &key, e.to_string()))?;
            if modal.modes_above_cutoff(&high) == 0 {
                let highest = body.reduced_frequencies_hz.last().copied().unwrap_or(0.0);
                warnings.push(format!(
                    "high_mode_damping damps nothing: no natural mode lies above {} Hz (the highest \
                     is {highest:.4} Hz)",
                    high.above_hz
                ));
            }
            modal.damping += matrix;
        }
        match self.f.geometric_stiffening {
            Some(false) => modal.geometric_stiffness = None,
            Some(true) if modal.geometric_stiffness.is_none() => warnings.push(
                "geometric_stiffening = true, but the body has no geometric-stiffness terms (a flexible-body file \
                 written before them): it keeps its unstressed stiffness"
                    .to_string(),
            ),
            _ => {}
        }
        modal.initial_coordinates = self.modal_vector(&self.f.modal_coordinates, "modal_coordinates", &labels)?;
        modal.initial_rates = self.modal_vector(&self.f.modal_rates, "modal_rates", &labels)?;
        Ok(modal)
    }

    /// Whether the table asks for the body's stresses (`stresses = true`).
    fn wants_stresses(&self) -> bool {
        self.f.stresses.as_ref().is_some_and(|s| *s.get_ref())
    }

    /// The body's modal stresses if the table asks for them; an error if the body has none (a
    /// flexible-body file written without them, or a mesh without elements that recover them).
    fn stresses(&self, body: &mut FlexibleBody) -> Result<Option<Arc<ModalStresses>>, ModelFileError> {
        let Some(flag) = self.f.stresses.as_ref().filter(|s| *s.get_ref()) else { return Ok(None) };
        match body.stresses.take() {
            Some(stresses) => Ok(Some(Arc::new(stresses))),
            None => Err(self.ctx.invalid(
                &flag.span(),
                &self.key("stresses"),
                match self.f.body_file.is_some() {
                    true => "the flexible-body file holds no modal stresses: write it with `flexmb modes --stresses` \
                             (or `stresses = true` in the FE model file's [modes] table)",
                    false => "the FE model has no element whose stresses are recovered (solids, beams and shells are)",
                },
            )),
        }
    }

    /// The table's `high_mode_damping`, checked; `None` without one.
    fn high_mode_damping_of_table(&self) -> Result<Option<HighModeDamping>, ModelFileError> {
        self.f
            .high_mode_damping
            .as_ref()
            .map(|section| self.high_mode_damping(section.get_ref(), &self.key("high_mode_damping")))
            .transpose()
    }

    /// `high_mode_damping = { above = f, ratio = ζ }`: a positive cutoff in Hz and a non-negative ratio
    /// (default [`HighModeDamping::DEFAULT_RATIO`]).
    fn high_mode_damping(&self, d: &HighModeDampingSection, key: &KeyPath) -> Result<HighModeDamping, ModelFileError> {
        let above_key = key.key("above");
        let above_hz = self.ctx.number(&d.above, &above_key)?;
        if above_hz <= 0.0 {
            return Err(self.ctx.invalid(
                &d.above.span(),
                &above_key,
                format!("the cutoff frequency must be positive (Hz: modes above it are damped), got {above_hz}"),
            ));
        }
        let ratio = match &d.ratio {
            Some(r) => self.non_negative(r, &key.key("ratio"), "a damping ratio")?,
            None => HighModeDamping::DEFAULT_RATIO,
        };
        Ok(HighModeDamping { above_hz, ratio })
    }

    /// `damping = { ratio = ζ }`, `{ ratios = [ζ₁, …] }` or `{ rayleigh = [α, β] }`; none by default.
    fn damping(&self, labels: &[&str]) -> Result<ModalDamping, ModelFileError> {
        let Some(section) = &self.f.damping else { return Ok(ModalDamping::None) };
        let key = self.key("damping");
        let d: &DampingSection = section.get_ref();
        let expected = "expected one of { ratio = ζ } (the damping ratio of every mode), { ratios = [ζ1, ζ2, …] } \
                        (one per mode) or { rayleigh = [alpha, beta] } (D = alpha M + beta K)";
        match [d.ratio.is_some(), d.ratios.is_some(), d.rayleigh.is_some()].iter().filter(|x| **x).count() {
            0 => return Err(self.ctx.invalid(&section.span(), &key, format!("damping is not given; {expected}"))),
            1 => {}
            _ => {
                return Err(self.ctx.invalid(
                    &section.span(),
                    &key,
                    format!("damping is given in more than one form; {expected}"),
                ))
            }
        }
        if let Some(ratio) = &d.ratio {
            let zeta = self.non_negative(ratio, &key.key("ratio"), "a damping ratio")?;
            Ok(ModalDamping::Ratios(vec![zeta]))
        } else if let Some(ratios) = &d.ratios {
            let key = key.key("ratios");
            self.check_length(ratios, &key, labels, "damping ratios")?;
            let values = ratios
                .get_ref()
                .iter()
                .enumerate()
                .map(|(k, r)| self.non_negative(r, &key.index(k), "a damping ratio"))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(ModalDamping::Ratios(values))
        } else if let Some(rayleigh) = &d.rayleigh {
            let key = key.key("rayleigh");
            let [alpha, beta] = self.ctx.numbers::<2>(rayleigh, &key, "Rayleigh coefficients [alpha, beta]")?;
            for (k, (name, value)) in [("alpha", alpha), ("beta", beta)].into_iter().enumerate() {
                if value < 0.0 {
                    return Err(self.ctx.invalid(
                        &rayleigh.get_ref()[k].span(),
                        &key.index(k),
                        format!("the Rayleigh coefficient {name} must not be negative, got {value}"),
                    ));
                }
            }
            Ok(ModalDamping::Rayleigh { alpha, beta })
        } else {
            Err(self.ctx.invalid(&section.span(), &key, expected))
        }
    }

    fn non_negative(
        &self,
        value: &crate::model_file::schema::Number,
        key: &KeyPath,
        what: &str,
    ) -> Result<f64, ModelFileError> {
        let x = self.ctx.number(value, key)?;
        if x < 0.0 {
            return Err(self.ctx.invalid(&value.span(), key, format!("{what} must not be negative, got {x}")));
        }
        Ok(x)
    }

    /// An array with one value per mode.
    fn check_length(&self, value: &Vector, key: &KeyPath, labels: &[&str], what: &str) -> Result<(), ModelFileError> {
        let n = value.get_ref().len();
        if n == labels.len() {
            return Ok(());
        }
        Err(self.ctx.invalid(
            &value.span(),
            key,
            format!("expected {} {what}, one per mode ({}), got {n}", labels.len(), mode_list(labels)),
        ))
    }

    /// Initial modal coordinates or rates: zero by default, else one per mode.
    fn modal_vector(
        &self,
        value: &Option<Vector>,
        name: &str,
        labels: &[&str],
    ) -> Result<DVector<f64>, ModelFileError> {
        let Some(value) = value else { return Ok(DVector::zeros(labels.len())) };
        let key = self.key(name);
        let what = name.replace('_', " ");
        self.check_length(value, &key, labels, &what)?;
        let values = value
            .get_ref()
            .iter()
            .enumerate()
            .map(|(k, x)| self.ctx.number(x, &key.index(k)))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(DVector::from_vec(values))
    }

    /// The engine's checks of a flexible body (sizes, a positive definite mass matrix, a proper
    /// orientation) on this body alone, so that a problem is reported at this table.
    fn check_with_engine(&self, initial: &InitialState, modal: &ModalBody) -> Result<(), ModelFileError> {
        let mut alone = ModelBuilder::new("flexible body check");
        let Err(error) = alone.add_flexible_body(self.f.name.get_ref().clone(), initial.clone(), modal.clone()) else {
            return Ok(());
        };
        let (span, key, message) = match (&error, &self.f.orientation) {
            (ModelError::BadFrame { problem, .. }, Some(o)) => (o.span(), self.key("orientation"), problem.clone()),
            (ModelError::BadValue { problem, .. }, _) => (self.span.clone(), self.element.clone(), problem.clone()),
            (other, _) => (self.span.clone(), self.element.clone(), other.to_string()),
        };
        Err(self.ctx.invalid(&span, &key, message))
    }
}

/// `O1, O2, …, O6` (all of them when there are few).
fn mode_list(labels: &[&str]) -> String {
    match labels {
        [] => "no modes".to_string(),
        _ if labels.len() <= 6 => labels.join(", "),
        [first, second, .., last] => format!("{first}, {second}, …, {last}"),
        _ => labels.join(", "),
    }
}
