//! A function of time with its first two derivatives, for drivers (`Φ = θ − f(t)`, `ν = f'`, `γ ∋ f''`).

use super::{Expression, ExpressionError, UserMotion};

/// `f(t)`, `f'(t)`, `f''(t)`: an expression differentiated symbolically once when the model is built,
/// or a motion given as code with its own derivatives ([`TimeFunction::user`]).
#[derive(Clone, Debug)]
pub struct TimeFunction {
    f: Expression,
    df: Expression,
    ddf: Expression,
    /// The motion of [`TimeFunction::user`], evaluated in place of the expressions.
    user: Option<UserMotion>,
}

impl TimeFunction {
    /// Parses an expression of `t` alone and differentiates it twice.
    pub fn parse(source: &str) -> Result<Self, ExpressionError> {
        let f = Expression::parse(source, &|_| None)?;
        Self::new(f)
    }

    /// From an expression that must depend on `t` only.
    pub fn new(f: Expression) -> Result<Self, ExpressionError> {
        let df = f.time_derivative()?;
        let ddf = df.time_derivative()?;
        Ok(Self { f, df, ddf, user: None })
    }

    /// A motion given as code; its [`source`](Self::source) is ``user motion `name` ``.
    pub fn user(motion: UserMotion) -> Self {
        let f = Expression::named_constant(format!("user motion `{}`", motion.name()), f64::NAN);
        Self { f: f.clone(), df: f.clone(), ddf: f, user: Some(motion) }
    }

    /// The motion given as code, for a function made by [`TimeFunction::user`].
    pub fn user_motion(&self) -> Option<&UserMotion> {
        self.user.as_ref()
    }

    /// Whether the function changes with time: an expression that names `t`, or a motion given as code.
    /// A constraint written with a constant one (a distance of fixed length) does no work.
    pub fn depends_on_time(&self) -> bool {
        self.user.is_some() || self.f.variables().contains(&super::Variable::Time)
    }

    /// The source text.
    pub fn source(&self) -> &str {
        self.f.source()
    }

    /// `[f(t), f'(t), f''(t)]`.
    #[inline]
    pub fn eval(&self, t: f64) -> [f64; 3] {
        if let Some(motion) = &self.user {
            return motion.eval(t);
        }
        [self.f.eval(t, &[]), self.df.eval(t, &[]), self.ddf.eval(t, &[])]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derivatives_of_a_polynomial_and_a_sine() {
        let f = TimeFunction::parse("0.5*t^2 + 3*t + sin(2*t)").unwrap();
        let t = 0.7;
        let [v, d, dd] = f.eval(t);
        assert!((v - (0.5 * t * t + 3.0 * t + (2.0 * t).sin())).abs() < 1e-12);
        assert!((d - (t + 3.0 + 2.0 * (2.0 * t).cos())).abs() < 1e-12);
        assert!((dd - (1.0 - 4.0 * (2.0 * t).sin())).abs() < 1e-12);
    }

    #[test]
    fn constant_has_zero_derivatives() {
        assert_eq!(TimeFunction::parse("1.5").unwrap().eval(2.0), [1.5, 0.0, 0.0]);
        assert!(!TimeFunction::parse("sqrt(5) + 1").unwrap().depends_on_time());
        assert!(TimeFunction::parse("sqrt(5) + 0*t").unwrap().depends_on_time());
    }
}
