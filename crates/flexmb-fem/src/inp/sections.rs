//! Properties of the Abaqus library beam cross-sections (`SECTION=RECT|CIRC|PIPE|BOX`) in flexmb's
//! local axes: y along the first section direction n₁ (Abaqus' 1-axis), z along n₂ (the 2-axis), so
//! that `iy = ∫ z² dA` is Abaqus' I₁₁ and `iz = ∫ y² dA` is I₂₂.

use std::f64::consts::PI;

use crate::mesh::SectionOutline;

/// Area, second moments and torsion constant of a cross-section (m², m⁴).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionProperties {
    /// Area A (m²).
    pub area: f64,
    /// ∫ z² dA about the local y axis (Abaqus I₁₁).
    pub iy: f64,
    /// ∫ y² dA about the local z axis (Abaqus I₂₂).
    pub iz: f64,
    /// Torsion constant J (m⁴).
    pub torsion_constant: f64,
    /// Where the bending stress is largest.
    pub outline: SectionOutline,
}

/// Why a section's dimensions give no section.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SectionError {
    /// A dimension is zero, negative or not finite.
    #[error("{name} must be positive, got {value}")]
    NotPositive {
        /// The dimension's name (`a`, `r`, `t2`, …).
        name: String,
        /// The value given (m).
        value: f64,
    },
    /// A tube's wall is thicker than its radius.
    #[error("the wall thickness t = {thickness} exceeds the outside radius r = {radius}")]
    WallThickerThanRadius {
        /// The wall thickness (m).
        thickness: f64,
        /// The outside radius (m).
        radius: f64,
    },
    /// A box's opposite walls meet.
    #[error(
        "the walls fill the box: t1 + t3 = {} must be less than a = {a}, t2 + t4 = {} less than b = {b}",
        t[0] + t[2],
        t[1] + t[3]
    )]
    WallsFillBox {
        /// Outside width (m).
        a: f64,
        /// Outside height (m).
        b: f64,
        /// Wall thicknesses `[t1, t2, t3, t4]` (m).
        t: [f64; 4],
    },
}

fn positive(name: &str, value: f64) -> Result<f64, SectionError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(SectionError::NotPositive { name: name.to_string(), value })
    }
}

/// Saint-Venant torsion constant of a solid `a × b` rectangle, from the exact series
/// `J = (l s³ / 3) [1 − (192 / π⁵)(s / l) Σ_{n odd} tanh(n π l / (2 s)) / n⁵]`, with l the longer and
/// s the shorter side (β = 0.1406 for a square, → 1/3 for a thin strip).
pub fn rectangle_torsion_constant(a: f64, b: f64) -> f64 {
    let (l, s) = if a >= b { (a, b) } else { (b, a) };
    let mut sum = 0.0;
    let mut n = 1.0_f64;
    while n < 4000.0 {
        sum += (n * PI * l / (2.0 * s)).tanh() / n.powi(5);
        n += 2.0;
    }
    l * s.powi(3) / 3.0 * (1.0 - 192.0 / PI.powi(5) * (s / l) * sum)
}

/// Solid rectangle, `a` along the 1-direction (local y), `b` along the 2-direction (local z):
/// `iy = a b³ / 12`, `iz = b a³ / 12`, J from [`rectangle_torsion_constant`].
pub fn rect(a: f64, b: f64) -> Result<SectionProperties, SectionError> {
    let (a, b) = (positive("a", a)?, positive("b", b)?);
    Ok(SectionProperties {
        area: a * b,
        iy: a * b.powi(3) / 12.0,
        iz: b * a.powi(3) / 12.0,
        torsion_constant: rectangle_torsion_constant(a, b),
        outline: SectionOutline::Rectangle { half_y: a / 2.0, half_z: b / 2.0 },
    })
}

/// Solid circle of radius `r`: `I = π r⁴ / 4`, `J = π r⁴ / 2`.
pub fn circ(r: f64) -> Result<SectionProperties, SectionError> {
    let r = positive("r", r)?;
    let i = PI * r.powi(4) / 4.0;
    Ok(SectionProperties {
        area: PI * r * r,
        iy: i,
        iz: i,
        torsion_constant: 2.0 * i,
        outline: SectionOutline::Round { radius: r },
    })
}

/// Circular tube of outside radius `r` and wall thickness `t` (exact annulus, not the thin-wall
/// approximation): `I = π (r⁴ − rᵢ⁴) / 4`, `J = 2 I`, `rᵢ = r − t`.
pub fn pipe(r: f64, t: f64) -> Result<SectionProperties, SectionError> {
    let (r, t) = (positive("r", r)?, positive("t", t)?);
    if t > r {
        return Err(SectionError::WallThickerThanRadius { thickness: t, radius: r });
    }
    let ri = r - t;
    let i = PI * (r.powi(4) - ri.powi(4)) / 4.0;
    Ok(SectionProperties {
        area: PI * (r * r - ri * ri),
        iy: i,
        iz: i,
        torsion_constant: 2.0 * i,
        outline: SectionOutline::Round { radius: r },
    })
}

/// Rectangular tube: outside width `a` along the 1-direction, outside height `b` along the
/// 2-direction, wall thicknesses `t = [t1, t2, t3, t4]` of the walls at +1 (right), +2 (top), −1
/// (left) and −2 (bottom), as in the Abaqus figure.
///
/// Area and second moments are exact for the rectangle minus the hole, about the centroid (which
/// moves off the section's centre when opposite walls differ: the second value returned is that
/// offset (1, 2) in section axes, which flexmb does not model). The torsion constant is Bredt's
/// thin-walled one on the wall mid-lines: `J = 4 Aₘ² / ∮ ds/t`, `Aₘ = (a − (t1+t3)/2)(b − (t2+t4)/2)`.
pub fn boxed(a: f64, b: f64, t: [f64; 4]) -> Result<(SectionProperties, [f64; 2]), SectionError> {
    let (a, b) = (positive("a", a)?, positive("b", b)?);
    for (k, &tk) in t.iter().enumerate() {
        positive(&format!("t{}", k + 1), tk)?;
    }
    let [t1, t2, t3, t4] = t;
    let (wh, hh) = (a - t1 - t3, b - t2 - t4);
    if wh <= 0.0 || hh <= 0.0 {
        return Err(SectionError::WallsFillBox { a, b, t });
    }
    let (ao, ah) = (a * b, wh * hh);
    let area = ao - ah;
    let (h1, h2) = ((t3 - t1) / 2.0, (t4 - t2) / 2.0);
    let (c1, c2) = (-ah * h1 / area, -ah * h2 / area);
    let iy =
        a * b.powi(3) / 12.0 + ao * c2 * c2 - (wh * hh.powi(3) / 12.0 + ah * (h2 - c2).powi(2));
    let iz =
        b * a.powi(3) / 12.0 + ao * c1 * c1 - (hh * wh.powi(3) / 12.0 + ah * (h1 - c1).powi(2));
    let (am, bm) = (a - (t1 + t3) / 2.0, b - (t2 + t4) / 2.0);
    let contour = bm / t1 + am / t2 + bm / t3 + am / t4;
    let torsion_constant = 4.0 * (am * bm).powi(2) / contour;
    Ok((
        SectionProperties {
            area,
            iy,
            iz,
            torsion_constant,
            outline: SectionOutline::Rectangle { half_y: a / 2.0, half_z: b / 2.0 },
        },
        [c1, c2],
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, rel: f64) -> bool {
        (a - b).abs() <= rel * a.abs().max(b.abs())
    }

    #[test]
    fn rectangle() {
        let p = rect(0.02, 0.05).unwrap();
        assert!(close(p.area, 1e-3, 1e-14));
        assert!(close(p.iy, 0.02 * 0.05_f64.powi(3) / 12.0, 1e-14));
        assert!(close(p.iz, 0.05 * 0.02_f64.powi(3) / 12.0, 1e-14));
        // Tabulated β (Timoshenko & Goodier): 0.1406 for a square, 0.229 for 2:1, 0.281 for 4:1, 0.312 for 10:1.
        assert!(close(rectangle_torsion_constant(1.0, 1.0), 0.1406, 2e-3));
        assert!(close(
            rectangle_torsion_constant(2.0, 1.0),
            0.229 * 2.0,
            2e-3
        ));
        assert!(close(
            rectangle_torsion_constant(1.0, 4.0),
            0.281 * 4.0,
            2e-3
        ));
        assert!(close(
            rectangle_torsion_constant(10.0, 1.0),
            0.312 * 10.0,
            2e-3
        ));
        assert!(close(
            p.torsion_constant,
            rectangle_torsion_constant(0.05, 0.02),
            1e-15
        ));
        assert!(rect(0.0, 1.0).is_err());
        assert!(rect(1.0, f64::NAN).is_err());
    }

    #[test]
    fn circle_and_pipe() {
        let c = circ(0.01).unwrap();
        assert!(close(c.area, PI * 1e-4, 1e-14));
        assert!(close(c.iy, PI * 1e-8 / 4.0, 1e-14));
        assert!(close(c.torsion_constant, PI * 1e-8 / 2.0, 1e-14));
        let p = pipe(0.05, 0.005).unwrap();
        assert!(close(
            p.area,
            PI * (0.05_f64.powi(2) - 0.045_f64.powi(2)),
            1e-14
        ));
        assert!(close(
            p.iz,
            PI * (0.05_f64.powi(4) - 0.045_f64.powi(4)) / 4.0,
            1e-14
        ));
        assert!(close(p.torsion_constant, 2.0 * p.iy, 1e-15));
        // t = r is the solid circle.
        let full = pipe(0.01, 0.01).unwrap();
        assert!(close(full.iy, c.iy, 1e-14));
        assert!(pipe(0.01, 0.02).is_err());
        assert_eq!(
            pipe(0.01, 0.02).unwrap_err().to_string(),
            "the wall thickness t = 0.02 exceeds the outside radius r = 0.01"
        );
        assert_eq!(rect(0.0, 1.0), Err(SectionError::NotPositive { name: "a".into(), value: 0.0 }));
        assert_eq!(
            boxed(0.1, 0.2, [0.06, 0.01, 0.05, 0.01]).unwrap_err().to_string(),
            "the walls fill the box: t1 + t3 = 0.11 must be less than a = 0.1, t2 + t4 = 0.02 less than b = 0.2"
        );
    }

    #[test]
    fn box_section() {
        // Symmetric: rectangle minus hole, Bredt J on mid-lines.
        let (p, offset) = boxed(0.1, 0.2, [0.01; 4]).unwrap();
        assert!(close(p.area, 0.1 * 0.2 - 0.08 * 0.18, 1e-13));
        assert!(close(
            p.iy,
            (0.1 * 0.2_f64.powi(3) - 0.08 * 0.18_f64.powi(3)) / 12.0,
            1e-13
        ));
        assert!(close(
            p.iz,
            (0.2 * 0.1_f64.powi(3) - 0.18 * 0.08_f64.powi(3)) / 12.0,
            1e-13
        ));
        let (am, bm) = (0.09_f64, 0.19_f64);
        assert!(close(
            p.torsion_constant,
            4.0 * (am * bm).powi(2) / (2.0 * am / 0.01 + 2.0 * bm / 0.01),
            1e-13
        ));
        assert_eq!(offset, [0.0, 0.0]);
        // A thicker top wall moves the centroid up (+2) and not sideways.
        let (q, offset) = boxed(0.1, 0.2, [0.01, 0.03, 0.01, 0.01]).unwrap();
        assert!(offset[1] > 0.0 && offset[0] == 0.0);
        // Parallel-axis check: I about the centroid = I about the centre − A c².
        let about_centre = (0.1 * 0.2_f64.powi(3) - 0.08 * 0.16_f64.powi(3)) / 12.0
            - 0.08 * 0.16 * 0.01_f64.powi(2);
        assert!(close(
            q.iy,
            about_centre - q.area * offset[1].powi(2),
            1e-12
        ));
        assert!(boxed(0.1, 0.2, [0.06, 0.01, 0.05, 0.01]).is_err());
    }
}
