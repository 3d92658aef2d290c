//! The inertia tensor from its three written forms. Whether it is physical (symmetric, positive
//! definite, triangle inequality) is checked by the engine's own rules when the body is validated.

use flexmb::math::Mat3;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::context::Context;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::value::{InertiaInput, NumberOrExpression};

/// The tensor about the centre of mass in body axes (kg m²).
pub(crate) fn inertia(ctx: &Context, value: &Spanned<InertiaInput>, key: &KeyPath) -> Result<Mat3, ModelFileError> {
    let span = value.span();
    let number =
        |x: &NumberOrExpression, k: &KeyPath| ctx.quantity(&Spanned::new(span.clone(), x.clone()), k, Quantity::Inertia);
    Ok(match value.get_ref() {
        InertiaInput::Diagonal(d) => Mat3::from_diagonal(&flexmb::math::Vec3::new(
            number(&d[0], &key.index(0))?,
            number(&d[1], &key.index(1))?,
            number(&d[2], &key.index(2))?,
        )),
        InertiaInput::Matrix(rows) => {
            let mut m = Mat3::zeros();
            for (r, row) in rows.iter().enumerate() {
                for (c, x) in row.iter().enumerate() {
                    m[(r, c)] = number(x, &key.index(r).index(c))?;
                }
            }
            m
        }
        InertiaInput::Components(c) => {
            let product =
                |x: &Option<NumberOrExpression>, name: &str| x.as_ref().map_or(Ok(0.0), |x| number(x, &key.key(name)));
            let (xy, xz, yz) = (product(&c.xy, "xy")?, product(&c.xz, "xz")?, product(&c.yz, "yz")?);
            Mat3::new(
                number(&c.xx, &key.key("xx"))?,
                xy,
                xz,
                xy,
                number(&c.yy, &key.key("yy"))?,
                yz,
                xz,
                yz,
                number(&c.zz, &key.key("zz"))?,
            )
        }
    })
}
