//! Length units of a BVH file. BVH states none: Bandai and most exporters use
//! centimetres, CMU's cgspeed conversion uses ASF units of (1/0.45) inch =
//! 0.056444 m. The user may state the scale; otherwise it is detected from the
//! skeleton's size and the choice (with its reason) is reported.

use super::{BvhError, Skeleton};

/// How to convert file lengths to metres.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Units {
    /// Detect from the skeleton's size (see [`detect_units`]).
    #[default]
    Auto,
    /// Metres per file unit, stated by the user (e.g. 0.01 for centimetres).
    MetresPerUnit(f64),
}

/// CMU ASF length unit: 1/0.45 inch (CMU FAQ).
pub const CMU_UNIT: f64 = 0.0254 / 0.45;

/// The scale used for one file and why.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitChoice {
    pub metres_per_unit: f64,
    /// "centimetres", "CMU units (1/0.45 in)", …
    pub name: String,
    /// True when detected rather than stated.
    pub detected: bool,
    /// A sentence for the user: what was measured and chosen.
    pub reason: String,
}

/// The candidate units, and the typical human leg length (hip joint to ankle,
/// metres) that identifies them.
const CANDIDATES: [(f64, &str); 5] = [
    (1.0, "metres"),
    (0.01, "centimetres"),
    (0.001, "millimetres"),
    (0.0254, "inches"),
    (CMU_UNIT, "CMU units (1/0.45 in = 0.056444 m)"),
];

/// A human's summed bone length along its longest root-to-leaf chain,
/// roughly pelvis-to-fingertip or pelvis-to-toe, in metres.
const TYPICAL_CHAIN_M: f64 = 1.0;

/// Resolves `units` for a skeleton.
pub fn resolve(units: Units, skeleton: &Skeleton) -> Result<UnitChoice, BvhError> {
    match units {
        Units::MetresPerUnit(s) if s.is_finite() && s > 0.0 => Ok(UnitChoice {
            metres_per_unit: s,
            name: CANDIDATES
                .iter()
                .find(|(v, _)| (v - s).abs() < 1e-9 * v)
                .map(|(_, n)| n.to_string())
                .unwrap_or_else(|| format!("{s} m per unit")),
            detected: false,
            reason: format!("stated: {s} m per file unit"),
        }),
        Units::MetresPerUnit(s) => Err(BvhError::Unit(s)),
        Units::Auto => Ok(detect_units(skeleton)),
    }
}

/// Detects the unit from the longest chain of bone lengths from a root's
/// children to a leaf (End Site included). Root-to-first-child offsets are
/// left out: Bandai's Hips OFFSET is a world position, not a bone. The
/// candidate whose scaled chain is nearest (in ratio) to a human's ~1 m wins.
pub fn detect_units(skeleton: &Skeleton) -> UnitChoice {
    let chain = longest_chain(skeleton);
    if !(chain.is_finite() && chain > 0.0) {
        return UnitChoice {
            metres_per_unit: 0.01,
            name: "centimetres".into(),
            detected: true,
            reason:
                "skeleton has no bone lengths; assumed centimetres (state the unit to override)"
                    .into(),
        };
    }
    let (scale, name) = CANDIDATES
        .iter()
        .min_by(|a, b| {
            let da = (chain * a.0 / TYPICAL_CHAIN_M).ln().abs();
            let db = (chain * b.0 / TYPICAL_CHAIN_M).ln().abs();
            da.total_cmp(&db)
        })
        .copied()
        .unwrap_or((0.01, "centimetres"));
    UnitChoice {
        metres_per_unit: scale,
        name: name.to_string(),
        detected: true,
        reason: format!(
            "detected {name}: the longest bone chain is {chain:.3} file units, {:.2} m in {name} (a human's is about {TYPICAL_CHAIN_M} m); state the unit to override",
            chain * scale
        ),
    }
}

/// Longest summed bone length from a depth-1 joint (a root's child) to a leaf.
fn longest_chain(s: &Skeleton) -> f64 {
    let n = s.joints.len();
    // Joints come parent-first, so one forward pass accumulates path lengths.
    let mut acc = vec![0.0; n];
    let mut best: f64 = 0.0;
    for (i, j) in s.joints.iter().enumerate() {
        let base = match j.parent {
            None => 0.0,
            Some(p) if s.joints[p].parent.is_none() => acc[p],
            Some(p) => acc[p] + j.offset.norm(),
        };
        acc[i] = base;
        let tip = j.end_sites.iter().map(|e| e.norm()).fold(0.0, f64::max);
        best = best.max(base + tip);
    }
    best
}
