//! The error of building a joint from user input.

/// Why a joint could not be built; the message says what to change.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct JointSpecError(pub String);

pub(crate) fn jerr<T>(msg: impl Into<String>) -> Result<T, JointSpecError> {
    Err(JointSpecError(msg.into()))
}

/// A unit vector from user input, or an error naming `what`.
pub(crate) fn unit(
    v: nalgebra::Vector3<f64>,
    what: &str,
) -> Result<nalgebra::Vector3<f64>, JointSpecError> {
    let n = v.norm();
    if !(n.is_finite() && n > 1e-12) {
        return jerr(format!(
            "{what} must be a non-zero finite vector, got [{}, {}, {}]",
            v.x, v.y, v.z
        ));
    }
    Ok(v / n)
}
