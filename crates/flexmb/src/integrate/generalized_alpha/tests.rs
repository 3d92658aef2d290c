use std::sync::Arc;
use super::*;
use crate::analysis::{assemble, velocity_analysis, AccelerationSolver, State};

#[test]
fn chung_hulbert_parameters() {
    let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
    // ρ∞ = 1: the trapezoidal rule.
    let c = Coefficients::from_spectral_radius(1.0);
    assert!(close(c.alpha_m, 0.5) && close(c.alpha_f, 0.5) && close(c.gamma, 0.5) && close(c.beta, 0.25), "{c:?}");
    // ρ∞ = 0: asymptotic annihilation.
    let c = Coefficients::from_spectral_radius(0.0);
    assert!(close(c.alpha_m, -1.0) && close(c.alpha_f, 0.0) && close(c.gamma, 1.5) && close(c.beta, 1.0), "{c:?}");
    // ρ∞ = 0.5: α_m = 0, α_f = 1/3, γ = 5/6, β = 4/9.
    let c = Coefficients::from_spectral_radius(0.5);
    assert!(close(c.alpha_m, 0.0) && close(c.alpha_f, 1.0 / 3.0) && close(c.gamma, 5.0 / 6.0), "{c:?}");
    assert!(close(c.beta, 4.0 / 9.0), "{c:?}");
}

/// The amplification matrix of the scheme on `ẍ = −ω² x` (no constraints) has spectral radius `ρ∞` as
/// `h ω → ∞` and 1 as `h ω → 0`, for every `ρ∞`.
#[test]
fn spectral_radius_at_infinite_frequency() {
    for rho in [0.0, 0.3, 0.5, 0.9, 1.0] {
        let c = Coefficients::from_spectral_radius(rho);
        let radius = |hw: f64| {
            // State [x, h v, h² ã] → next: solve the step for ẍ_{n+1} = −ω² x_{n+1} (with v̇ = ẍ).
            let w2 = hw * hw;
            let mut m = [[0.0; 3]; 3];
            for (j, col) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].iter().enumerate() {
                let (x, v, a) = (col[0], col[1], col[2]);
                // v̇_n = −ω² x_n (scaled by h²).
                let vd_n = -w2 * x;
                // x_{n+1} = x + v + (½ − β) a + β ã_{n+1}, ã_{n+1} = ((1 − α_f) v̇_{n+1} + α_f v̇_n − α_m a)/(1 − α_m),
                // v̇_{n+1} = −ω² x_{n+1}: linear in v̇_{n+1}.
                let k = (1.0 - c.alpha_f) / (1.0 - c.alpha_m);
                let a0 = (c.alpha_f * vd_n - c.alpha_m * a) / (1.0 - c.alpha_m);
                let x_free = x + v + (0.5 - c.beta) * a + c.beta * a0;
                let vd = -w2 * x_free / (1.0 + w2 * c.beta * k);
                let a_new = a0 + k * vd;
                let x_new = x_free + c.beta * k * vd;
                let v_new = v + (1.0 - c.gamma) * a + c.gamma * a_new;
                m[0][j] = x_new;
                m[1][j] = v_new;
                m[2][j] = a_new;
            }
            let m = crate::math::Mat3::from_fn(|r, c| m[r][c]);
            m.complex_eigenvalues().iter().map(|z| z.norm()).fold(0.0, f64::max)
        };
        let high = radius(1e6);
        let low = radius(1e-3);
        assert!((high - rho).abs() < 1e-3, "ρ∞ = {rho}: spectral radius at hω = 1e6 is {high}");
        assert!((low - 1.0).abs() < 1e-6, "ρ∞ = {rho}: spectral radius at hω = 1e-3 is {low}");
    }
}

/// The assembled iteration matrix equals the derivative of the scaled step equations with respect to
/// `[v̇, λ, μ̃]` (central differences), entry by entry.
#[test]
fn iteration_matrix_is_the_derivative_of_the_step_equations() {
    let model = crate::analysis::test_models::double_pendulum_with_spring();
    let mut data = Data::new(&model);
    let mut state = State::initial(&model);
    assemble(&model, &mut data, &mut state, Default::default()).unwrap();
    state.v.iter_mut().enumerate().for_each(|(k, v)| *v += 2.0 * (k as f64).sin());
    velocity_analysis(&model, &mut data, &mut state).unwrap();
    let acc = AccelerationSolver::new(&model)
        .solve(&model, &mut data, 0.0, &state.q, &state.v, &state.active)
        .unwrap()
        .clone();
    let mut ga =
        GeneralizedAlpha::new(Arc::new(model.clone()), &state, &acc, Tolerances::default(), GeneralizedAlphaConfig::default()).unwrap();
    let (nv, nc) = (ga.nv, ga.nc);
    let n = nv + 2 * nc;
    let h = 0.02;
    let t_new = h;
    ga.refresh_derivatives(t_new, h);
    ga.predict(h);
    ga.evaluate_residual(t_new, h);
    let d = ga.d_step.clone();
    ga.matrix.factor(&model, &ga.data, &ga.active, h, &ga.coefficients, &d).unwrap();
    let x0 = ga.x.clone();
    let cb = ga.coefficients.beta_prime() * h * h;
    // The step equations at x, with Bᵀμ from B at the predictor (as in the first Newton iteration).
    let residual_at = |ga: &mut GeneralizedAlpha, x: &[f64]| -> Vec<f64> {
        ga.predict(h);
        ga.evaluate_residual(t_new, h);
        ga.x.copy_from_slice(x);
        for r in 0..nc {
            ga.mu[r] = cb * x[nv + nc + r];
        }
        ga.delta.fill(0.0);
        ga.matrix.add_start_jacobian_transpose(&ga.mu, &mut ga.delta);
        add_jacobian_transpose(&model, &ga.data, &ga.mu, &mut ga.delta);
        ga.state_from_unknowns(h);
        ga.evaluate_residual(t_new, h);
        ga.res.clone()
    };
    let mut worst = 0.0_f64;
    for j in 0..n {
        let eps = 1e-5 * x0[j].abs().max(1.0);
        let mut x = x0.clone();
        x[j] += eps;
        let plus = residual_at(&mut ga, &x);
        x[j] -= 2.0 * eps;
        let minus = residual_at(&mut ga, &x);
        for i in 0..n {
            let fd = (plus[i] - minus[i]) / (2.0 * eps);
            let assembled = ga.matrix.entry(i, j);
            let err = (fd - assembled).abs() / (1.0 + fd.abs());
            assert!(err < 1e-6, "entry ({i}, {j}): finite differences {fd}, assembled {assembled}");
            worst = worst.max(err);
        }
    }
    eprintln!("iteration matrix vs central differences: worst relative error {worst:.2e}");
}
