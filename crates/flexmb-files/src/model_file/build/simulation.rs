//! `[model]` and `[simulation]`: the model's name and gravity, and the defaults of a simulation run.

use flexmb::analysis::{ModalAssembly, PhysicsLimits, Start};
use flexmb::integrate::ToleranceSpan;
use flexmb::math::Vec3;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::context::Context;
use crate::model_file::error::{ErrorKind, ModelFileError};
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{ModelFile, Number, SimulationSection};
use crate::model_file::value::NumberOrExpression;
use crate::model_file::SimulationDefaults;

/// The model's name (default `default_name`, the file stem) and gravity (default zero). `[model]` is
/// required, and the model must have a body: an empty or truncated file is an error, not a model of
/// nothing.
pub(crate) fn model_settings(
    ctx: &Context,
    file: &ModelFile,
    default_name: &str,
) -> Result<(String, Vec3), ModelFileError> {
    let Some(section) = &file.model else {
        return Err(ctx.source.error(
            ErrorKind::Schema,
            &(0..0),
            &KeyPath::root(),
            "no [model] table: a model file must have one (`[model]`, whose keys `name` and `gravity` are \
             optional); is the file empty or truncated?",
        ));
    };
    if file.body.is_empty() && file.flexible_body.is_empty() {
        return Err(ctx.invalid(
            &section.span(),
            &KeyPath::root(),
            "the model has no bodies: it needs at least one [[body]] or [[flexible_body]] table",
        ));
    }
    let table = KeyPath::root().key("model");
    let m = section.get_ref();
    let name = match &m.name {
        Some(name) if name.get_ref().trim().is_empty() => {
            return Err(ctx.invalid(&name.span(), &table.key("name"), "the model name must not be empty"))
        }
        Some(name) => name.get_ref().clone(),
        None => default_name.to_string(),
    };
    let gravity = ctx.vector_or_zero(&m.gravity, &table.key("gravity"), Quantity::Acceleration)?;
    Ok((name, gravity))
}

/// The defaults of `flexmb run`; each must be positive.
pub(crate) fn simulation_defaults(
    ctx: &Context,
    section: Option<&Spanned<SimulationSection>>,
) -> Result<SimulationDefaults, ModelFileError> {
    let defaults = SimulationDefaults::default();
    let Some(section) = section else { return Ok(defaults) };
    let table = KeyPath::root().key("simulation");
    let s = section.get_ref();
    // A positive setting, within the window of its quantity if it has one.
    let positive = |value: &Option<Number>, name: &str, default: f64, quantity: Option<Quantity>| {
        let key = table.key(name);
        let x = match (value, quantity) {
            (Some(v), Some(quantity)) => ctx.quantity(v, &key, quantity)?,
            _ => ctx.number_or(value, &key, default)?,
        };
        match value {
            Some(v) if x <= 0.0 => Err(ctx.invalid(&v.span(), &key, format!("{name} must be positive, got {x}"))),
            _ => Ok(x),
        }
    };
    let spectral_radius = ctx.number_or(&s.spectral_radius, &table.key("spectral_radius"), flexmb::integrate::GeneralizedAlphaConfig::DEFAULT_SPECTRAL_RADIUS)?;
    if let Some(v) = &s.spectral_radius {
        if !(0.0..=1.0).contains(&spectral_radius) {
            return Err(ctx.invalid(
                &v.span(),
                &table.key("spectral_radius"),
                format!("spectral_radius must be between 0 and 1, got {spectral_radius}"),
            ));
        }
    }
    let method = match &s.integrator {
        Some(name) => crate::integrator_choice::parse_method(name.get_ref(), spectral_radius)
            .map_err(|e| ctx.invalid(&name.span(), &table.key("integrator"), e))?,
        None => defaults.method,
    };
    let max_order = match &s.max_order {
        Some(v) => {
            let k = ctx.number(v, &table.key("max_order"))?;
            if !(1.0..=5.0).contains(&k) || k.fract() != 0.0 {
                return Err(ctx.invalid(&v.span(), &table.key("max_order"), format!("max_order must be a whole number from 1 to 5, got {k}")));
            }
            Some(k as usize)
        }
        None => None,
    };
    let limit = |value: &Option<Number>, name: &str, default: u64| match value {
        Some(v) => {
            let n = ctx.number(v, &table.key(name))?;
            if n < 1.0 || n.fract() != 0.0 || n > u64::MAX as f64 {
                return Err(ctx.invalid(&v.span(), &table.key(name), format!("{name} must be a whole number of at least 1, got {n}")));
            }
            Ok(n as u64)
        }
        None => Ok(default),
    };
    let step = |value: &Option<Number>, name: &str| value.as_ref().map(|_| positive(value, name, 0.0, Some(Quantity::Time))).transpose();
    let fixed_step = step(&s.fixed_step, "fixed_step")?;
    if let (Some(v), Some(h)) = (&s.fixed_step, fixed_step) {
        if !matches!(method, flexmb::integrate::Method::GeneralizedAlpha(_)) {
            return Err(ctx.invalid(
                &v.span(),
                &table.key("fixed_step"),
                format!(
                    "fixed_step = {h} needs integrator = \"gen-alpha\" in [simulation]: only the generalized-α method \
                     takes a fixed step (limit the others' steps with max_step)"
                ),
            ));
        }
    }
    let modal_assembly = match &s.modal_assembly {
        Some(name) => parse_modal_assembly(name.get_ref()).map_err(|e| ctx.invalid(&name.span(), &table.key("modal_assembly"), e))?,
        None => defaults.modal_assembly,
    };
    let start = match &s.start {
        Some(name) => parse_start(name.get_ref()).map_err(|e| ctx.invalid(&name.span(), &table.key("start"), e))?,
        None => defaults.start,
    };
    Ok(SimulationDefaults {
        method,
        modal_assembly,
        start,
        max_order,
        max_step: step(&s.max_step, "max_step")?,
        fixed_step,
        t_end: positive(&s.t_end, "t_end", defaults.t_end, Some(Quantity::Time))?,
        output_step: positive(&s.output_step, "output_step", defaults.output_step, Some(Quantity::Time))?,
        rtol: positive(&s.rtol, "rtol", defaults.rtol, None)?,
        atol: positive(&s.atol, "atol", defaults.atol, None)?,
        tolerance_span: match &s.tolerance_span {
            Some(v) => match v.get_ref() {
                NumberOrExpression::Expression(word) if word.trim() == "run" => ToleranceSpan::Run,
                NumberOrExpression::Expression(word) if word.trim() == "step" => ToleranceSpan::Step,
                _ => ToleranceSpan::Seconds(positive(&s.tolerance_span, "tolerance_span", 1.0, Some(Quantity::Time))?),
            },
            None => defaults.tolerance_span,
        },
        vtk_step: s.vtk_step.as_ref().map(|_| positive(&s.vtk_step, "vtk_step", 0.0, Some(Quantity::Time))).transpose()?,
        max_output_rows: limit(&s.max_output_rows, "max_output_rows", defaults.max_output_rows)?,
        max_vtk_frames: limit(&s.max_vtk_frames, "max_vtk_frames", defaults.max_vtk_frames)?,
        divergence_check: s.divergence_check.unwrap_or(defaults.divergence_check),
        global_error_estimate: s.global_error_estimate.unwrap_or(defaults.global_error_estimate),
        global_error_control: s.global_error_control.unwrap_or(defaults.global_error_control),
        physics_limits: physics_limits(ctx, s, &|value, name, default| positive(value, name, default, Some(Quantity::Factor)))?,
    })
}

/// Reads a positive number at a key of `[simulation]`, or gives the default.
type PositiveNumber<'a> = &'a dyn Fn(&Option<Number>, &str, f64) -> Result<f64, ModelFileError>;

/// The physics watchdog's thresholds, each positive. A warning not given is at most the limit given,
/// and a limit not given at least the warning given; both given, the warning must not exceed the limit.
fn physics_limits(
    ctx: &Context,
    s: &SimulationSection,
    positive: PositiveNumber,
) -> Result<PhysicsLimits, ModelFileError> {
    let d = PhysicsLimits::default();
    let pair = |(warning, limit): (&Option<Number>, &Option<Number>), name: &str, (dw, dl): (f64, f64)| {
        let w = positive(warning, &format!("{name}_warning"), dw)?;
        let l = positive(limit, &format!("{name}_limit"), dl)?;
        match (warning, limit) {
            (Some(v), Some(_)) if w > l => Err(ctx.invalid(
                &v.span(),
                &KeyPath::root().key("simulation").key(&format!("{name}_warning")),
                format!("{name}_warning ({w}) must not exceed {name}_limit ({l})"),
            )),
            (None, _) => Ok((w.min(l), l)),
            _ => Ok((w, l.max(w))),
        }
    };
    let (elastic_deflection_warning, elastic_deflection_limit) = pair(
        (&s.elastic_deflection_warning, &s.elastic_deflection_limit),
        "elastic_deflection",
        (d.elastic_deflection_warning, d.elastic_deflection_limit),
    )?;
    let (energy_balance_warning, energy_balance_limit) = pair(
        (&s.energy_balance_warning, &s.energy_balance_limit),
        "energy_balance",
        (d.energy_balance_warning, d.energy_balance_limit),
    )?;
    Ok(PhysicsLimits { elastic_deflection_warning, elastic_deflection_limit, energy_balance_warning, energy_balance_limit })
}

/// `start = "assembly" | "equilibrium"`.
fn parse_start(name: &str) -> Result<Start, String> {
    match name {
        "assembly" => Ok(Start::Assembly),
        "equilibrium" => Ok(Start::Equilibrium(Default::default())),
        other => Err(format!("unknown start '{other}': expected \"assembly\" or \"equilibrium\"")),
    }
}

/// `modal_assembly = "held" | "free" | "static"`.
fn parse_modal_assembly(name: &str) -> Result<ModalAssembly, String> {
    match name {
        "held" => Ok(ModalAssembly::Held),
        "free" => Ok(ModalAssembly::Free),
        "static" => Ok(ModalAssembly::Static),
        other => Err(format!("unknown modal_assembly '{other}': expected \"held\", \"free\" or \"static\"")),
    }
}
