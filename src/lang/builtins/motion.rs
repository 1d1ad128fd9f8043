//! Motion built-ins (interval, dof, mu, the algebra, CSV/JSON save and load).
//! They wrap `crate::motion`, which is being built on another branch; until it
//! lands nothing is registered here, so the names are reported as unknown
//! rather than half-working.

use super::Registry;

pub fn register(_reg: &mut Registry) {}
