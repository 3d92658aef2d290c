//! Laws given as code put into a built model, in place of the expressions its elements were given:
//! a force element's actuator or applied component ([`Model::set_force_law`]) and a driver's motion
//! ([`Model::set_driver_motion`]). The model's shape does not change (the same bodies, equations and
//! measures), so a model loaded from a file takes its laws after loading; the couplings a law adds
//! (through the measures it reads) are found when a simulation starts, as for any expression.

use crate::force::ForceKind;
use crate::function::{Expression, TimeFunction, UserFunction, UserLawFailure, UserMotion};
use crate::joint::JointKind;
use crate::model::{MeasureId, Model};

/// Why a law given as code cannot be put where it was asked.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum UserLawError {
    /// No force element, driver or measure of that name.
    #[error("the model has no {kind} named '{name}': {known}")]
    NotFound {
        /// `force element`, `driver` or `measure`.
        kind: &'static str,
        /// The name asked for.
        name: String,
        /// The names it has.
        known: String,
    },
    /// An applied force or torque needs the component (0, 1, 2 for x, y, z) the law gives; a
    /// spring-damper has one actuator and takes none.
    #[error("force element '{element}' ({keyword}): {problem}")]
    Component {
        /// The element.
        element: String,
        /// Its keyword.
        keyword: &'static str,
        /// What is wrong.
        problem: String,
    },
}

impl Model {
    /// The measure named `name`.
    pub fn find_measure(&self, name: &str) -> Option<MeasureId> {
        self.measures.iter().position(|m| m.name == name).map(MeasureId)
    }

    /// The measures named `names`, in order; the first unknown name is an error listing the model's.
    pub fn measure_ids(&self, names: &[&str]) -> Result<Vec<MeasureId>, UserLawError> {
        names
            .iter()
            .map(|name| {
                self.find_measure(name).ok_or_else(|| UserLawError::NotFound {
                    kind: "measure",
                    name: name.to_string(),
                    known: known(self.measures.iter().map(|m| m.name.as_str())),
                })
            })
            .collect()
    }

    /// Makes `law` the actuator of the spring-damper `element` (`component` `None`), or component
    /// `component` (0, 1, 2: x, y, z of the element's frame) of the applied force or torque `element`.
    pub fn set_force_law(&mut self, element: &str, component: Option<usize>, law: UserFunction) -> Result<(), UserLawError> {
        let Some(force) = self.forces.iter_mut().find(|f| f.name == element) else {
            return Err(UserLawError::NotFound {
                kind: "force element",
                name: element.to_string(),
                known: known(self.forces.iter().map(|f| f.name.as_str())),
            });
        };
        let keyword = force.kind.keyword();
        let problem = |problem: &str| UserLawError::Component { element: element.to_string(), keyword, problem: problem.to_string() };
        match (&mut force.kind, component) {
            (ForceKind::TranslationalSpringDamper { actuator, .. } | ForceKind::RotationalSpringDamper { actuator, .. }, None) => {
                *actuator = Some(Expression::user(law));
            }
            (ForceKind::TranslationalSpringDamper { .. } | ForceKind::RotationalSpringDamper { .. }, Some(_)) => {
                return Err(problem("a spring-damper's law is its actuator: give no component"));
            }
            (ForceKind::AppliedForce { components, .. } | ForceKind::AppliedTorque { components, .. }, Some(k)) if k < 3 => {
                components[k] = Expression::user(law);
            }
            (ForceKind::AppliedForce { .. } | ForceKind::AppliedTorque { .. }, _) => {
                return Err(problem("give the component the law is: x, y or z"));
            }
        }
        Ok(())
    }

    /// Makes `motion` the prescribed function of the driver (angle or displacement driver) or distance
    /// joint `joint`.
    pub fn set_driver_motion(&mut self, joint: &str, motion: UserMotion) -> Result<(), UserLawError> {
        let driven = |kind: &JointKind| matches!(kind, JointKind::AngleDriver { .. } | JointKind::DisplacementDriver { .. } | JointKind::Distance { .. });
        let names = known(self.joints.iter().filter(|j| driven(&j.kind)).map(|j| j.name.as_str()));
        let not_found = || UserLawError::NotFound { kind: "driver", name: joint.to_string(), known: names.clone() };
        let j = self.joints.iter_mut().find(|j| j.name == joint).ok_or_else(not_found)?;
        match &mut j.kind {
            JointKind::AngleDriver { function } | JointKind::DisplacementDriver { function } | JointKind::Distance { length: function } => {
                *function = TimeFunction::user(motion);
                Ok(())
            }
            _ => Err(not_found()),
        }
    }

    /// The names of the laws given as code, in the order of the force elements then the joints.
    pub fn user_laws(&self) -> Vec<&str> {
        let forces = self.forces.iter().flat_map(|f| f.kind.expressions()).filter_map(|e| e.user_function()).map(UserFunction::name);
        forces.chain(self.user_motions().map(UserMotion::name)).collect()
    }

    /// The earliest failure of a law given as code since the last simulation started.
    pub fn user_law_failure(&self) -> Option<UserLawFailure> {
        let forces = self.forces.iter().flat_map(|f| f.kind.expressions()).filter_map(|e| e.user_function()?.failure());
        forces.chain(self.user_motions().filter_map(UserMotion::failure)).min_by(|a, b| a.t.total_cmp(&b.t))
    }

    /// Forgets the failures of the laws given as code (a simulation starts).
    pub(crate) fn clear_user_law_failures(&self) {
        self.forces.iter().flat_map(|f| f.kind.expressions()).filter_map(|e| e.user_function()).for_each(UserFunction::clear_failure);
        self.user_motions().for_each(UserMotion::clear_failure);
    }

    fn user_motions(&self) -> impl Iterator<Item = &UserMotion> {
        self.joints.iter().filter_map(|j| match &j.kind {
            JointKind::AngleDriver { function } | JointKind::DisplacementDriver { function } | JointKind::Distance { length: function } => {
                function.user_motion()
            }
            _ => None,
        })
    }
}

fn known<'a>(names: impl Iterator<Item = &'a str>) -> String {
    let names: Vec<&str> = names.collect();
    if names.is_empty() {
        "it has none".to_string()
    } else {
        format!("it has {}", names.join(", "))
    }
}
