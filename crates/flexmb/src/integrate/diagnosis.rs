//! Failure diagnosis of the integrators: when the step size underflows, which equations a person should
//! look at. The largest residuals of the equations of motion and of the constraints at the failed
//! attempt, each named by what it means (a body's kinematic equations, a velocity coordinate's equation
//! of motion, a joint's constraint), and the constraints in force that have become dependent there (a
//! lock or a singular position). Only called when a run fails, so it may allocate.

use std::ops::Range;

use crate::data::Data;
use crate::model::Model;

/// One row of the equations an integrator solves, by what it means.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum EquationRow {
    /// The kinematic equations `q̇ = T(q) v` of body `b`.
    Kinematic(usize),
    /// The equation of motion of velocity coordinate `k`.
    Motion(usize),
    /// The velocity constraint `B v + Φ_t = 0` of constraint row `r`.
    VelocityConstraint(usize),
    /// The position constraint `Φ = 0` of constraint row `r`.
    PositionConstraint(usize),
    /// The Euler-parameter normalization `pᵀp = 1` of body `b`.
    Normalization(usize),
}

impl EquationRow {
    /// The row named for a person.
    pub fn describe(self, model: &Model) -> String {
        match self {
            EquationRow::Kinematic(b) => format!("the kinematic equations of body '{}'", model.bodies[b].name),
            EquationRow::Motion(k) => model.describe_velocity_row(k),
            EquationRow::VelocityConstraint(r) => {
                format!("the velocity constraint of {}", model.describe_constraint_row(r))
            }
            EquationRow::PositionConstraint(r) => {
                format!("the position constraint of {}", model.describe_constraint_row(r))
            }
            EquationRow::Normalization(b) => {
                format!("the Euler-parameter normalization of body '{}'", model.bodies[b].name)
            }
        }
    }
}

/// The row of `rows` with the largest `|residual(i)|`, and that magnitude; `None` when none is above zero.
pub(crate) fn largest_residual(rows: Range<usize>, residual: impl Fn(usize) -> f64) -> Option<(usize, f64)> {
    let (row, value) =
        rows.map(|i| (i, residual(i).abs())).fold((usize::MAX, 0.0), |a, x| if x.1 > a.1 { x } else { a });
    (row != usize::MAX).then_some((row, value))
}

/// The residuals of a failed attempt, one system of equations with rows `0..n` named by `name`:
/// `residual(i)` is row `i`'s residual in its physical units, `motion` the rows of the equations of motion
/// (and kinematics), `constraints` those of the constraints. Says the largest of each and, with the
/// positions `q` at time `t`, the constraints in force that have become dependent (see
/// [`dependent_constraints`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn worst_equations(
    model: &Model,
    data: &mut Data,
    t: f64,
    q: &[f64],
    active: &[bool],
    (motion, constraints): (Range<usize>, Range<usize>),
    residual: impl Fn(usize) -> f64,
    name: impl Fn(usize) -> EquationRow,
) -> String {
    let mut text = String::new();
    if let Some((row, value)) = largest_residual(motion, &residual) {
        text += &format!("largest residual {value:.3e} in {}", name(row).describe(model));
    }
    if let Some((row, value)) = largest_residual(constraints, &residual) {
        text += &format!("; largest constraint residual {value:.3e} in {}", name(row).describe(model));
    }
    text + &dependent_constraints(model, data, t, q, active)
}

/// `"; "` and the constraint rows in force that have become dependent at the positions `q` (the mechanism
/// locks or reaches a singular position there); empty when none has.
pub(crate) fn dependent_constraints(model: &Model, data: &mut Data, t: f64, q: &[f64], active: &[bool]) -> String {
    crate::analysis::newly_dependent_rows(model, data, t, q, active).map(|note| format!("; {note}")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_largest_residual_is_the_largest_magnitude_and_zeros_name_nothing() {
        let residual = [0.5, -3.0, 2.0, 0.0];
        assert_eq!(largest_residual(0..4, |i| residual[i]), Some((1, 3.0)), "a negative residual counts by its size");
        assert_eq!(largest_residual(2..4, |i| residual[i]), Some((2, 2.0)));
        assert_eq!(largest_residual(3..4, |i| residual[i]), None, "a zero residual is nothing to look at");
        assert_eq!(largest_residual(0..0, |i| residual[i]), None);
        assert_eq!(largest_residual(0..2, |i| if i == 0 { 1.0 } else { f64::NAN }), Some((0, 1.0)));
    }
}
