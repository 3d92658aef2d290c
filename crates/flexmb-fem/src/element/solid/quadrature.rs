//! The integration rules of the solid elements, on their reference shapes, with CalculiX's points
//! (`gauss.f`): the brick's `[-1, 1]³`, the tetrahedron's `ξ, η, ζ ≥ 0, ξ + η + ζ ≤ 1` (volume 1/6)
//! and the wedge's triangle `ξ, η ≥ 0, ξ + η ≤ 1` times `ζ ∈ [-1, 1]` (volume 1).

/// A point of an integration rule: natural coordinates and weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct IntegrationPoint {
    /// `ξ η ζ`.
    pub natural: [f64; 3],
    /// The weight (the rule's weights sum to the reference volume).
    pub weight: f64,
}

/// The points and weights of Gauss–Legendre quadrature on [-1, 1] with `order` (1–3) points.
fn gauss_legendre(order: usize) -> Vec<(f64, f64)> {
    match order {
        1 => vec![(0.0, 2.0)],
        2 => {
            let a = 1.0 / 3f64.sqrt();
            vec![(-a, 1.0), (a, 1.0)]
        }
        _ => {
            let a = (0.6f64).sqrt();
            vec![(-a, 5.0 / 9.0), (0.0, 8.0 / 9.0), (a, 5.0 / 9.0)]
        }
    }
}

/// The `order`³ Gauss rule of the brick (ξ fastest), exact for degree 2 order − 1 in each coordinate.
pub(super) fn brick(order: usize) -> Vec<IntegrationPoint> {
    let line = gauss_legendre(order);
    let mut points = Vec::with_capacity(order.pow(3));
    for &(z, wz) in &line {
        for &(y, wy) in &line {
            for &(x, wx) in &line {
                points.push(IntegrationPoint { natural: [x, y, z], weight: wx * wy * wz });
            }
        }
    }
    points
}

/// The tetrahedron's centroid rule (1 point, degree 1).
pub(super) fn tetrahedron_centroid() -> Vec<IntegrationPoint> {
    vec![IntegrationPoint { natural: [0.25; 3], weight: 1.0 / 6.0 }]
}

/// The tetrahedron's 4-point rule (degree 2): `a = (5 − √5) / 20`, `b = (5 + 3√5) / 20`.
pub(super) fn tetrahedron_4() -> Vec<IntegrationPoint> {
    let a = (5.0 - 5f64.sqrt()) / 20.0;
    let b = (5.0 + 3.0 * 5f64.sqrt()) / 20.0;
    [[a, a, a], [b, a, a], [a, b, a], [a, a, b]]
        .into_iter()
        .map(|natural| IntegrationPoint { natural, weight: 1.0 / 24.0 })
        .collect()
}

/// The wedge's rules: a triangle rule (`1` centroid or `3` interior points, degree 1 or 2) times
/// Gauss–Legendre with `line` points in ζ.
pub(super) fn wedge(triangle: usize, line: usize) -> Vec<IntegrationPoint> {
    let triangle: Vec<([f64; 2], f64)> = if triangle == 1 {
        vec![([1.0 / 3.0, 1.0 / 3.0], 0.5)]
    } else {
        let (a, b) = (1.0 / 6.0, 2.0 / 3.0);
        vec![([a, a], 1.0 / 6.0), ([b, a], 1.0 / 6.0), ([a, b], 1.0 / 6.0)]
    };
    let mut points = Vec::new();
    for &(z, wz) in &gauss_legendre(line) {
        for &([x, y], w) in &triangle {
            points.push(IntegrationPoint { natural: [x, y, z], weight: w * wz });
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ ξ^a η^b ζ^c over a rule.
    fn moment(rule: &[IntegrationPoint], [a, b, c]: [i32; 3]) -> f64 {
        rule.iter().map(|p| p.weight * p.natural[0].powi(a) * p.natural[1].powi(b) * p.natural[2].powi(c)).sum()
    }

    fn factorial(n: i32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    #[test]
    fn brick_rules_integrate_their_degree_exactly() {
        for order in 1..=3 {
            let degree = 2 * order as i32 - 1;
            let exact_1d = |k: i32| if k % 2 == 1 { 0.0 } else { 2.0 / (k as f64 + 1.0) };
            for (a, b, c) in [(degree, 0, 0), (0, degree, 0), (degree - 1, degree - 1, degree - 1), (0, 0, degree)] {
                let exact = exact_1d(a) * exact_1d(b) * exact_1d(c);
                assert!((moment(&brick(order), [a, b, c]) - exact).abs() < 1e-14, "order {order} ({a} {b} {c})");
            }
        }
    }

    #[test]
    fn tetrahedron_rules_integrate_their_degree_exactly() {
        // ∫ ξ^a η^b ζ^c over the unit tetrahedron = a! b! c! / (a + b + c + 3)!.
        let exact = |[a, b, c]: [i32; 3]| factorial(a) * factorial(b) * factorial(c) / factorial(a + b + c + 3);
        for powers in [[0, 0, 0], [1, 0, 0], [0, 0, 1]] {
            assert!((moment(&tetrahedron_centroid(), powers) - exact(powers)).abs() < 1e-15);
        }
        for powers in [[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0], [0, 1, 1], [0, 0, 2]] {
            assert!((moment(&tetrahedron_4(), powers) - exact(powers)).abs() < 1e-15, "{powers:?}");
        }
    }

    #[test]
    fn wedge_rules_integrate_their_degree_exactly() {
        // ∫ ξ^a η^b over the triangle = a! b! / (a + b + 2)!; ∫ ζ^c over [-1, 1].
        let exact = |[a, b, c]: [i32; 3]| {
            factorial(a) * factorial(b) / factorial(a + b + 2) * if c % 2 == 1 { 0.0 } else { 2.0 / (c as f64 + 1.0) }
        };
        for powers in [[0, 0, 0], [1, 0, 3], [0, 1, 2]] {
            assert!((moment(&wedge(1, 2), powers) - exact(powers)).abs() < 1e-15, "{powers:?}");
        }
        for powers in [[2, 0, 5], [1, 1, 4], [0, 2, 0], [1, 0, 1]] {
            assert!((moment(&wedge(3, 3), powers) - exact(powers)).abs() < 1e-15, "{powers:?}");
        }
    }
}
