//! The windows of physical magnitudes that values read from input files must lie in (SI units).
//!
//! Double precision holds numbers up to 1.8e308, but a mass of 1e308 kg or a Young's modulus of
//! 1e308 Pa is no model of anything: left alone, such values overflow in the mass or stiffness
//! matrices and come back as "a singular matrix" or "a mechanism" far from where they were written.
//! The readers check each value where they read it against the window of its [`Quantity`] and name
//! the key (or the `.inp` keyword and line) that is out of range.
//!
//! Every window is `|x| ≤ limit`, generous for mechanisms and structures and far below where products
//! of such values overflow: 1e12 for most quantities (lengths, masses, velocities, times, section
//! properties), with the exceptions in [`Quantity::limit`]. Signs and lower bounds (a mass is
//! positive, a density not negative) are checked by the readers as before.

/// A kind of physical quantity read from an input file, with its window of magnitudes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// Positions, origins, centres of mass, node coordinates, sizes, lengths, radii, thicknesses (m).
    Length,
    /// Velocities (m/s).
    Velocity,
    /// Angular velocities (rad/s).
    AngularVelocity,
    /// Accelerations, gravity (m/s²).
    Acceleration,
    /// Times and time steps (s).
    Time,
    /// Masses (kg).
    Mass,
    /// Moments and products of inertia (kg m²).
    Inertia,
    /// Young's and shear moduli (Pa).
    Modulus,
    /// Densities (kg/m³).
    Density,
    /// Cross-section areas (m²).
    Area,
    /// Second moments of area and torsion constants (m⁴).
    SecondMoment,
    /// Spring stiffnesses (N/m or N m/rad).
    Stiffness,
    /// Damping constants (N s/m or N m s/rad).
    Damping,
    /// Dimensionless factors: a shear coefficient, the drilling stiffness factor.
    Factor,
}

/// The limit of most quantities: a trillion SI units.
pub const GENERAL_LIMIT: f64 = 1e12;

impl Quantity {
    /// Every quantity, in the order of the documentation's table.
    pub const ALL: [Quantity; 14] = [
        Quantity::Length,
        Quantity::Velocity,
        Quantity::AngularVelocity,
        Quantity::Acceleration,
        Quantity::Time,
        Quantity::Mass,
        Quantity::Inertia,
        Quantity::Modulus,
        Quantity::Density,
        Quantity::Area,
        Quantity::SecondMoment,
        Quantity::Stiffness,
        Quantity::Damping,
        Quantity::Factor,
    ];

    /// The largest magnitude accepted: [`GENERAL_LIMIT`], except 1e18 kg m² for inertia (1e12 kg a
    /// kilometre from its axis), 1e15 for moduli (diamond's is 1.2e12 Pa) and for spring and damping
    /// constants (penalty springs), and 1e8 kg/m³ for densities (osmium's is 2.3e4 kg/m³).
    pub fn limit(self) -> f64 {
        match self {
            Quantity::Inertia => 1e18,
            Quantity::Modulus | Quantity::Stiffness | Quantity::Damping => 1e15,
            Quantity::Density => 1e8,
            _ => GENERAL_LIMIT,
        }
    }

    /// The SI unit of the quantity.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Length => "m",
            Quantity::Velocity => "m/s",
            Quantity::AngularVelocity => "rad/s",
            Quantity::Acceleration => "m/s²",
            Quantity::Time => "s",
            Quantity::Mass => "kg",
            Quantity::Inertia => "kg m²",
            Quantity::Modulus => "Pa",
            Quantity::Density => "kg/m³",
            Quantity::Area => "m²",
            Quantity::SecondMoment => "m⁴",
            Quantity::Stiffness => "N/m or N m/rad",
            Quantity::Damping => "N s/m or N m s/rad",
            Quantity::Factor => "",
        }
    }

    /// The quantity's name, with its article.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Length => "a length",
            Quantity::Velocity => "a velocity",
            Quantity::AngularVelocity => "an angular velocity",
            Quantity::Acceleration => "an acceleration",
            Quantity::Time => "a time",
            Quantity::Mass => "a mass",
            Quantity::Inertia => "an inertia",
            Quantity::Modulus => "an elastic modulus",
            Quantity::Density => "a density",
            Quantity::Area => "an area",
            Quantity::SecondMoment => "a second moment of area",
            Quantity::Stiffness => "a stiffness",
            Quantity::Damping => "a damping constant",
            Quantity::Factor => "a dimensionless factor",
        }
    }

    /// `value` if its magnitude is within the window; otherwise what is wrong, e.g. `1e308 kg is
    /// outside the range of a mass, |x| ≤ 1e12 kg`.
    pub fn check(self, value: f64) -> Result<f64, String> {
        if value.abs() <= self.limit() {
            return Ok(value);
        }
        let unit = match self.unit() {
            "" => String::new(),
            unit if unit.contains(" or ") => format!(" ({unit})"),
            unit => format!(" {unit}"),
        };
        Err(format!("{value:e}{unit} is outside the range of {}, |x| ≤ {:e}{unit}", self.name(), self.limit()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_within_the_window_pass_and_others_are_named() {
        assert_eq!(Quantity::Mass.check(1e12), Ok(1e12));
        assert_eq!(Quantity::Length.check(-3.5), Ok(-3.5));
        assert_eq!(
            Quantity::Mass.check(1e308).unwrap_err(),
            "1e308 kg is outside the range of a mass, |x| ≤ 1e12 kg"
        );
        assert_eq!(
            Quantity::Modulus.check(-2.5e16).unwrap_err(),
            "-2.5e16 Pa is outside the range of an elastic modulus, |x| ≤ 1e15 Pa"
        );
        assert!(Quantity::Stiffness.check(1e16).unwrap_err().contains("1e16 (N/m or N m/rad)"));
        assert!(Quantity::Density.check(f64::NAN).is_err());
        assert_eq!(
            Quantity::Factor.check(1e300).unwrap_err(),
            "1e300 is outside the range of a dimensionless factor, |x| ≤ 1e12"
        );
    }

    #[test]
    fn real_materials_and_structures_are_inside() {
        assert!(Quantity::Modulus.check(1.2e12).is_ok(), "diamond");
        assert!(Quantity::Density.check(22_590.0).is_ok(), "osmium");
        assert!(Quantity::Inertia.check(8e12).is_ok(), "a large ship about its yaw axis");
        assert!(Quantity::ALL.iter().all(|q| q.limit() >= 1e8 && q.limit() < 1e100));
    }
}
