//! One entry of the hard-case registry (`hard_cases.rs`, `hard_mechanisms.rs`):
//! what the engine returned, the worst error measured and the bound it must stay under.

/// One delicate case and its outcome.
#[derive(Clone, Debug)]
pub struct HardCase {
    pub name: &'static str,
    /// Module it exercises.
    pub area: &'static str,
    /// What the engine returned (a value summary or the error message).
    pub returned: String,
    pub worst_error: f64,
    pub bound: f64,
    pub passed: bool,
}

pub(crate) fn case(
    name: &'static str,
    area: &'static str,
    returned: String,
    worst: f64,
    bound: f64,
) -> HardCase {
    HardCase {
        name,
        area,
        returned,
        worst_error: worst,
        bound,
        passed: worst.is_finite() && worst <= bound,
    }
}
