//! Scalar functions of one coordinate that drive the exponentials of a
//! function-based joint: the OpenSim `Function`s used in CustomJoints.

use crate::spline::{BSplineCurve, SimmSpline};
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type")]
pub enum ScalarFunction {
    /// f(x) = value.
    Constant { value: f64 },
    /// f(x) = slope·x + intercept (OpenSim `LinearFunction`, coefficients = [slope, intercept]).
    Linear { slope: f64, intercept: f64 },
    /// OpenSim `SimmSpline` (FMM end conditions, linear outside the knots).
    SimmSpline(SimmSpline),
    /// f(x) = Σ c_k x^(n−k), highest order first (OpenSim `PolynomialFunction`).
    Polynomial { coefficients: Vec<f64> },
    /// f(x) = scale · g(x) (OpenSim `MultiplierFunction`).
    Multiplier {
        scale: f64,
        function: Box<ScalarFunction>,
    },
    /// A B-spline curve (extrapolated by its end polynomials).
    BSpline(BSplineCurve),
}

impl ScalarFunction {
    /// Value, first and second derivative at x.
    pub fn eval(&self, x: f64) -> [f64; 3] {
        match self {
            ScalarFunction::Constant { value } => [*value, 0.0, 0.0],
            ScalarFunction::Linear { slope, intercept } => [slope * x + intercept, *slope, 0.0],
            ScalarFunction::SimmSpline(s) => s.eval(x),
            ScalarFunction::Polynomial { coefficients } => {
                let (mut f, mut d1, mut d2) = (0.0, 0.0, 0.0);
                for &c in coefficients {
                    d2 = d2 * x + 2.0 * d1;
                    d1 = d1 * x + f;
                    f = f * x + c;
                }
                [f, d1, d2]
            }
            ScalarFunction::Multiplier { scale, function } => {
                let v = function.eval(x);
                [scale * v[0], scale * v[1], scale * v[2]]
            }
            ScalarFunction::BSpline(c) => c.eval(x),
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
