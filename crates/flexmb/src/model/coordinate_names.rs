//! Names of the generalized coordinates, to read and set a state by name: per body, in the layout's
//! order, the positions `R` (origin), `p` (Euler parameters) and `a` (modal coordinates), and the
//! velocities `Ṙ`, `ω̄` (angular velocity in body axes) and `ȧ`.

use crate::model::Model;

impl Model {
    /// A name for each position coordinate `q`: `<body>.R.x`, `.R.y`, `.R.z`, `<body>.p.0` … `.p.3`,
    /// then `<body>.a.1` … `.a.m` for a flexible body's modal coordinates.
    pub fn position_names(&self) -> Vec<String> {
        self.coordinate_names(&[("R", &["x", "y", "z"]), ("p", &["0", "1", "2", "3"])], "a")
    }

    /// A name for each velocity coordinate `v`: `<body>.Rdot.x` … (the origin's velocity, global axes),
    /// `<body>.omega.x` … (the angular velocity in body axes), then `<body>.adot.1` … `.adot.m`.
    pub fn velocity_names(&self) -> Vec<String> {
        self.coordinate_names(&[("Rdot", &["x", "y", "z"]), ("omega", &["x", "y", "z"])], "adot")
    }

    fn coordinate_names(&self, rigid: &[(&str, &[&str])], modal: &str) -> Vec<String> {
        let mut names = Vec::new();
        for (b, body) in self.bodies.iter().enumerate() {
            for (group, components) in rigid {
                names.extend(components.iter().map(|c| format!("{}.{group}.{c}", body.name)));
            }
            names.extend((1..=self.layout.modes[b]).map(|k| format!("{}.{modal}.{k}", body.name)));
        }
        names
    }
}

#[cfg(test)]
mod tests {
    use crate::analysis::test_models::double_pendulum_with_spring;

    #[test]
    fn one_name_per_coordinate() {
        let model = double_pendulum_with_spring();
        let (q, v) = (model.position_names(), model.velocity_names());
        assert_eq!((q.len(), v.len()), (model.layout.nq, model.layout.nv));
        let first = &model.bodies[0].name;
        assert_eq!(q[..4], [format!("{first}.R.x"), format!("{first}.R.y"), format!("{first}.R.z"), format!("{first}.p.0")]);
        assert_eq!(v[3], format!("{first}.omega.x"));
    }
}
