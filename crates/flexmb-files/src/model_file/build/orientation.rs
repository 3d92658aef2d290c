//! Orientations of bodies and markers: axis and angle, rotation matrix, Euler parameters, or (markers
//! only) a z axis with an optional x axis.

use flexmb::math::{EulerParameters, Mat3, Vec3, Vec4};
use toml::Spanned;

use super::context::Context;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{OrientationSection, Vector};

/// How far a matrix may be from a proper rotation (the engine's own tolerance for marker frames).
const ROTATION_TOLERANCE: f64 = 1e-6;
/// How far Euler parameters may be from unit length before they are normalized.
const EULER_PARAMETER_NORM_TOLERANCE: f64 = 1e-3;

/// The rotation an orientation table describes.
pub(crate) fn orientation(
    ctx: &Context,
    section: &Spanned<OrientationSection>,
    key: &KeyPath,
) -> Result<EulerParameters, ModelFileError> {
    let o = section.get_ref();
    let forms = [o.axis.is_some(), o.matrix.is_some(), o.euler_parameters.is_some()];
    let expected = "expected one of { axis = [x, y, z], angle = rad } (or angle_deg = degrees), \
                    { matrix = [[..], [..], [..]] } or { euler_parameters = [e0, e1, e2, e3] }";
    match forms.iter().filter(|f| **f).count() {
        0 => return Err(ctx.invalid(&section.span(), key, format!("orientation is not given; {expected}"))),
        1 => {}
        _ => {
            return Err(ctx.invalid(
                &section.span(),
                key,
                format!("orientation is given in more than one form; {expected}"),
            ))
        }
    }
    if o.axis.is_none() {
        for (name, span) in
            [("angle", o.angle.as_ref().map(Spanned::span)), ("angle_deg", o.angle_deg.as_ref().map(Spanned::span))]
        {
            if let Some(span) = span {
                return Err(ctx.invalid(&span, &key.key(name), format!("`{name}` goes with `axis` only")));
            }
        }
    }
    if let Some(axis) = &o.axis {
        axis_angle(ctx, section, axis, key)
    } else if let Some(matrix) = &o.matrix {
        let a = rotation_matrix(ctx, matrix, &key.key("matrix"))?;
        EulerParameters::from_rotation_matrix(&a).map_err(|e| ctx.invalid(&matrix.span(), &key.key("matrix"), e.to_string()))
    } else if let Some(p) = &o.euler_parameters {
        euler_parameters(ctx, p, &key.key("euler_parameters"))
    } else {
        Err(ctx.invalid(&section.span(), key, expected))
    }
}

fn axis_angle(
    ctx: &Context,
    section: &Spanned<OrientationSection>,
    axis: &Vector,
    key: &KeyPath,
) -> Result<EulerParameters, ModelFileError> {
    let o = section.get_ref();
    let u = ctx.vector(axis, &key.key("axis"))?;
    if u.norm() == 0.0 {
        return Err(ctx.invalid(&axis.span(), &key.key("axis"), "the rotation axis must not be the zero vector"));
    }
    let angle = match (&o.angle, &o.angle_deg) {
        (Some(rad), None) => ctx.number(rad, &key.key("angle"))?,
        (None, Some(deg)) => ctx.number(deg, &key.key("angle_deg"))?.to_radians(),
        (Some(_), Some(deg)) => {
            return Err(ctx.invalid(
                &deg.span(),
                &key.key("angle_deg"),
                "give either `angle` (rad) or `angle_deg`, not both",
            ))
        }
        (None, None) => {
            return Err(ctx.invalid(&section.span(), &key.key("angle"), "an `axis` needs `angle` (rad) or `angle_deg`"))
        }
    };
    EulerParameters::from_axis_angle(&u, angle).map_err(|e| ctx.invalid(&axis.span(), &key.key("axis"), e.to_string()))
}

/// A 3x3 matrix written as three rows.
pub(crate) fn matrix3(ctx: &Context, rows: &Spanned<Vec<Vector>>, key: &KeyPath) -> Result<Mat3, ModelFileError> {
    if rows.get_ref().len() != 3 {
        return Err(ctx.invalid(
            &rows.span(),
            key,
            format!("expected a 3x3 matrix [[..], [..], [..]] of 3 rows, got {} row(s)", rows.get_ref().len()),
        ));
    }
    let mut m = Mat3::zeros();
    for (r, row) in rows.get_ref().iter().enumerate() {
        let values = ctx.numbers::<3>(row, &key.index(r), "a matrix row")?;
        for (c, value) in values.iter().enumerate() {
            m[(r, c)] = *value;
        }
    }
    Ok(m)
}

/// A rotation matrix whose columns are the rotated frame's axes.
fn rotation_matrix(ctx: &Context, rows: &Spanned<Vec<Vector>>, key: &KeyPath) -> Result<Mat3, ModelFileError> {
    let a = matrix3(ctx, rows, key)?;
    let defect = (a.transpose() * a - Mat3::identity()).abs().max().max((a.determinant() - 1.0).abs());
    if defect >= ROTATION_TOLERANCE || defect.is_nan() {
        return Err(ctx.invalid(
            &rows.span(),
            key,
            format!(
                "not a proper rotation: the columns must be orthonormal unit vectors with determinant +1 \
                 (defect {defect:.2e}, allowed {ROTATION_TOLERANCE:.0e})"
            ),
        ));
    }
    Ok(a)
}

fn euler_parameters(ctx: &Context, value: &Vector, key: &KeyPath) -> Result<EulerParameters, ModelFileError> {
    let [e0, e1, e2, e3] = ctx.numbers::<4>(value, key, "Euler parameters [e0, e1, e2, e3]")?;
    let p = Vec4::new(e0, e1, e2, e3);
    if (p.norm() - 1.0).abs() > EULER_PARAMETER_NORM_TOLERANCE {
        return Err(ctx.invalid(
            &value.span(),
            key,
            format!("Euler parameters must have unit length, got length {:.6}", p.norm()),
        ));
    }
    Ok(EulerParameters(p / p.norm()))
}

/// Marker axes from a z axis and an optional x axis (made orthogonal to z). Without an x axis the
/// frame's x is the body's x axis made orthogonal to z, or its y axis if z is nearly along x.
pub(crate) fn axes_from_z(
    ctx: &Context,
    z_axis: &Vector,
    x_axis: Option<&Vector>,
    element: &KeyPath,
) -> Result<Mat3, ModelFileError> {
    let z = ctx.vector(z_axis, &element.key("z_axis"))?;
    if z.norm() == 0.0 {
        return Err(ctx.invalid(&z_axis.span(), &element.key("z_axis"), "`z_axis` must not be the zero vector"));
    }
    let z = z / z.norm();
    let x_hint = match x_axis {
        Some(x_axis) => {
            let x = ctx.vector(x_axis, &element.key("x_axis"))?;
            let along_z = x - z * z.dot(&x);
            if along_z.norm() <= 1e-9 * x.norm().max(f64::MIN_POSITIVE) {
                return Err(ctx.invalid(
                    &x_axis.span(),
                    &element.key("x_axis"),
                    "`x_axis` must not be parallel to `z_axis`",
                ));
            }
            x
        }
        None if z.x.abs() < 0.9 => Vec3::x(),
        None => Vec3::y(),
    };
    let x = (x_hint - z * z.dot(&x_hint)).normalize();
    let y = z.cross(&x);
    Ok(Mat3::from_columns(&[x, y, z]))
}
