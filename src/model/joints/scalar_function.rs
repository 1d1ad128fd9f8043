//! Scalar functions of one coordinate that drive the exponentials of a
//! function-based joint: the OpenSim `Function`s used in CustomJoints.

use super::error::JointSpecError;
use crate::spline::{BSplineCurve, GcvSpline, SimmSpline};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type")]
pub enum ScalarFunction {
    /// f(x) = value.
    Constant { value: f64 },
    /// f(x) = slope·x + intercept (OpenSim `LinearFunction`, coefficients = [slope, intercept]).
    Linear { slope: f64, intercept: f64 },
    /// OpenSim `SimmSpline` (FMM end conditions, linear outside the knots),
    /// or `NaturalCubicSpline` ([`SimmSpline::natural`]).
    SimmSpline(SimmSpline),
    /// OpenSim `PiecewiseLinearFunction`: straight lines between the points,
    /// continued with the end segments' slopes (build with [`ScalarFunction::piecewise_linear`]).
    PiecewiseLinear { x: Vec<f64>, y: Vec<f64> },
    /// f(x) = Σ c_k x^(n−k), highest order first (OpenSim `PolynomialFunction`).
    Polynomial { coefficients: Vec<f64> },
    /// f(x) = scale · g(x) (OpenSim `MultiplierFunction`).
    Multiplier {
        scale: f64,
        function: Box<ScalarFunction>,
    },
    /// A B-spline curve (extrapolated by its end polynomials).
    BSpline(BSplineCurve),
    /// OpenSim `GCVSpline` (interpolating: the natural spline of order 2·half_order).
    GcvSpline(GcvSpline),
}

impl ScalarFunction {
    /// A `PiecewiseLinearFunction` through (x[i], y[i]): at least 2 points, x strictly increasing.
    pub fn piecewise_linear(x: Vec<f64>, y: Vec<f64>) -> Result<Self, JointSpecError> {
        if x.len() != y.len() {
            return Err(JointSpecError(format!(
                "PiecewiseLinearFunction has {} x values but {} y values",
                x.len(),
                y.len()
            )));
        }
        if x.len() < 2 {
            return Err(JointSpecError(
                "PiecewiseLinearFunction needs at least 2 points".into(),
            ));
        }
        if x.iter().chain(&y).any(|v| !v.is_finite()) {
            return Err(JointSpecError(
                "PiecewiseLinearFunction points must be finite".into(),
            ));
        }
        if let Some(i) = (1..x.len()).find(|&i| x[i] <= x[i - 1]) {
            return Err(JointSpecError(format!(
                "PiecewiseLinearFunction x values must be strictly increasing: x[{i}] = {} follows {}",
                x[i],
                x[i - 1]
            )));
        }
        Ok(ScalarFunction::PiecewiseLinear { x, y })
    }

    /// Value, first and second derivative at x.
    pub fn eval(&self, x: f64) -> [f64; 3] {
        let [f, d1, d2, _] = self.eval3(x);
        [f, d1, d2]
    }

    /// Value and first three derivatives at x (the joints' third-derivative kinematics).
    pub fn eval3(&self, x: f64) -> [f64; 4] {
        match self {
            ScalarFunction::Constant { value } => [*value, 0.0, 0.0, 0.0],
            ScalarFunction::Linear { slope, intercept } => {
                [slope * x + intercept, *slope, 0.0, 0.0]
            }
            ScalarFunction::SimmSpline(s) => s.eval3(x),
            ScalarFunction::PiecewiseLinear { x: xs, y } => {
                // segment k with xs[k] ≤ x (first/last segment outside), as OpenSim
                let n = xs.len();
                let k = xs.partition_point(|&xi| xi <= x).clamp(1, n - 1) - 1;
                let slope = (y[k + 1] - y[k]) / (xs[k + 1] - xs[k]);
                [y[k] + slope * (x - xs[k]), slope, 0.0, 0.0]
            }
            ScalarFunction::Polynomial { coefficients } => {
                // Horner's scheme carried to the third derivative.
                let (mut f, mut d1, mut d2, mut d3) = (0.0, 0.0, 0.0, 0.0);
                for &c in coefficients {
                    d3 = d3 * x + 3.0 * d2;
                    d2 = d2 * x + 2.0 * d1;
                    d1 = d1 * x + f;
                    f = f * x + c;
                }
                [f, d1, d2, d3]
            }
            ScalarFunction::Multiplier { scale, function } => function.eval3(x).map(|v| scale * v),
            ScalarFunction::BSpline(c) => c.eval3(x),
            ScalarFunction::GcvSpline(s) => s.eval3(x),
        }
    }

    pub fn is_constant(&self) -> bool {
        match self {
            ScalarFunction::Constant { .. } => true,
            ScalarFunction::Multiplier { function, .. } => function.is_constant(),
            _ => false,
        }
    }
}
