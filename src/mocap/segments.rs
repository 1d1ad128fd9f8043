//! Body segment parameters of de Leva (1996), *Adjustments to
//! Zatsiorsky–Seluyanov's segment inertia parameters*, J. Biomech. 29(9),
//! 1223–1230, Table 4 (male): mass as a fraction of body mass, centre of mass
//! as a fraction of segment length, radii of gyration as fractions of length.
//!
//! Table 4 gives each segment with several pairs of end points; we take the
//! pair our skeletons' bones run between (joint centres where there is one):
//! head + neck from C7 (cervicale) to the vertex, upper trunk from the
//! xiphoid to C7, shank from the knee to the ankle joint centre (its lower
//! rows); middle and lower trunk, arm, forearm and thigh as in its upper rows;
//! the hand from the wrist to the 3rd metacarpal and the foot from heel to toe
//! tip (the only foot row: our foot bone starts at the ankle instead).
//!
//! Checked value by value (2026-11) against `deleva.m` by R. Gurchiek (2018,
//! github.com/gurchiek, a MATLAB transcription of all of Table 4, male and
//! female, both halves) and the de Leva tables of the biorbd model builder.
//! The first version had the head's (vertex–gonion) and upper trunk's
//! (suprasternale–xiphoid) and shank's (knee–lateral malleolus) rows, which
//! do not match the bones they were applied to; those three are now the
//! rows for C7-based head and upper trunk and the ankle-centre shank.
//!
//! Centre-of-mass fractions are restated from the *proximal* end of the bone
//! as our skeletons draw it (the parent-side joint): for the head and trunk
//! pieces de Leva measures from the top, and our bones point up from the
//! pelvis, so those fractions are `1 − table value`.
//!
//! Joint names map to segments by keywords (case-insensitive), covering the
//! Bandai (`Hips Spine Chest Neck Head Shoulder_L UpperArm_L LowerArm_L
//! Hand_L UpperLeg_L LowerLeg_L Foot_L Toes_L`), CMU MotionBuilder
//! (`LHipJoint LeftUpLeg LeftLeg LeftFoot LeftToeBase LowerBack Spine Spine1
//! Neck Neck1 Head LeftShoulder LeftArm LeftForeArm LeftHand LeftFingerBase
//! LFingers LThumb`) and CMU 3dsMax (`LeftHip LeftKnee LeftAnkle LeftToe
//! lowerback Chest Chest2 lowerneck Neck LeftCollar LeftShoulder LeftElbow
//! LeftWrist lhand`) skeletons. See [`classify`] for the rules and
//! `body_of` for the fallback when too few names are recognised.

/// A de Leva segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Segment {
    /// Head and neck (C7 to vertex).
    Head,
    /// Upper trunk (xiphoid to C7), with the clavicles/shoulder girdle.
    UpperTrunk,
    /// Middle trunk (xiphoid to omphalion).
    MiddleTrunk,
    /// Lower trunk / pelvis (omphalion to hip joint centres).
    LowerTrunk,
    UpperArm,
    Forearm,
    /// Hand, fingers included.
    Hand,
    Thigh,
    Shank,
    /// Foot, toes included.
    Foot,
}

/// Which side a joint is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    Left,
    Right,
    Centre,
}

/// de Leva's parameters of one segment.
#[derive(Clone, Copy, Debug)]
pub struct Params {
    /// Fraction of body mass (per side for limbs).
    pub mass: f64,
    /// Centre of mass, fraction of length from the proximal joint.
    pub com: f64,
    /// Radius of gyration about the long axis, fraction of length.
    pub r_long: f64,
    /// Radius of gyration about transverse axes (mean of de Leva's sagittal
    /// and transverse radii: we model segments as axisymmetric about the bone).
    pub r_trans: f64,
}

/// Table 4 of de Leva (1996), male, in the order mass %, CoM % (from the
/// proximal joint), radii % sagittal, transverse, longitudinal. Masses sum
/// to 1 over head, three trunk pieces and both sides of six limb segments.
pub fn params(s: Segment) -> Params {
    let p = |mass: f64, com: f64, r_sag: f64, r_tr: f64, r_long: f64| Params {
        mass: mass / 100.0,
        com: com / 100.0,
        r_long: r_long / 100.0,
        r_trans: (r_sag + r_tr) / 200.0,
    };
    match s {
        // VERT–CERV row (the VERT–MIDG row has CoM 59.76 and radii 36.2 37.6 31.2).
        Segment::Head => p(6.94, 100.0 - 50.02, 30.3, 31.5, 26.1),
        // CERV–XIPH row (the SUPR–XIPH row has CoM 29.99 and radii 71.6 45.4 65.9).
        Segment::UpperTrunk => p(15.96, 100.0 - 50.66, 50.5, 32.0, 46.5),
        Segment::MiddleTrunk => p(16.33, 100.0 - 45.02, 48.2, 38.3, 46.8),
        Segment::LowerTrunk => p(11.17, 100.0 - 61.15, 61.5, 55.1, 58.7),
        Segment::UpperArm => p(2.71, 57.72, 28.5, 26.9, 15.8),
        Segment::Forearm => p(1.62, 45.74, 27.6, 26.5, 12.1),
        Segment::Hand => p(0.61, 79.00, 62.8, 51.3, 40.1),
        Segment::Thigh => p(14.16, 40.95, 32.9, 32.9, 14.9),
        // KJC–AJC row (the KJC–LMAL row has CoM 44.59 and radii 25.5 24.9 10.3).
        Segment::Shank => p(4.33, 43.95, 25.1, 24.6, 10.2),
        Segment::Foot => p(1.37, 44.15, 25.7, 24.5, 12.4),
    }
}

/// The side of a joint from its name: `Left…`, `L…` + capital, `l` + `hand`,
/// `…_L`, `…_l`, `…Left`; likewise right.
pub fn side(name: &str) -> Side {
    let lower = name.to_ascii_lowercase();
    let b = name.as_bytes();
    let prefix = |c: u8| {
        b.len() > 1 && b[0] == c && (b[1].is_ascii_uppercase() || lower[1..].starts_with("hand"))
    };
    if lower.contains("left")
        || lower.ends_with("_l")
        || lower.ends_with(".l")
        || prefix(b'L')
        || prefix(b'l')
    {
        Side::Left
    } else if lower.contains("right")
        || lower.ends_with("_r")
        || lower.ends_with(".r")
        || prefix(b'R')
        || prefix(b'r')
    {
        Side::Right
    } else {
        Side::Centre
    }
}

/// The segment a joint's bone belongs to, from its name and its parent's
/// name; `None` for bones that carry no de Leva mass (the BVH root marker).
pub fn classify(name: &str, parent: Option<&str>) -> Option<Segment> {
    let n = name.to_ascii_lowercase();
    let has = |k: &str| n.contains(k);
    let parent_is_collar = parent.is_some_and(|p| {
        let p = p.to_ascii_lowercase();
        p.contains("collar") || p.contains("clavicle")
    });
    Some(
        if has("hand") || has("wrist") || has("finger") || has("thumb") || has("palm") {
            Segment::Hand
        } else if has("forearm") || has("lowerarm") || has("elbow") {
            Segment::Forearm
        } else if has("collar") || has("clavicle") || (has("shoulder") && !parent_is_collar) {
            // The shoulder girdle belongs to de Leva's upper trunk.
            Segment::UpperTrunk
        } else if has("upperarm") || has("shoulder") || has("arm") {
            Segment::UpperArm
        } else if has("toe") || has("foot") || has("ankle") {
            Segment::Foot
        } else if has("knee")
            || has("lowerleg")
            || has("shin")
            || has("calf")
            || (has("leg") && !has("upleg") && !has("upperleg"))
        {
            Segment::Shank
        } else if has("upleg")
            || has("upperleg")
            || has("thigh")
            || (has("hip") && !has("hips") && !has("hipjoint"))
        {
            Segment::Thigh
        } else if has("neck") || has("head") {
            Segment::Head
        } else if has("chest")
            || has("thorax")
            || has("spine1")
            || has("spine2")
            || has("upperback")
        {
            Segment::UpperTrunk
        } else if has("spine") || has("lowerback") || has("abdomen") || has("lumbar") {
            Segment::MiddleTrunk
        } else if has("hips") || has("pelvis") || has("hipjoint") {
            Segment::LowerTrunk
        } else {
            return None;
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masses_sum_to_one() {
        use Segment::*;
        let centre: f64 = [Head, UpperTrunk, MiddleTrunk, LowerTrunk]
            .iter()
            .map(|s| params(*s).mass)
            .sum();
        let limbs: f64 = [UpperArm, Forearm, Hand, Thigh, Shank, Foot]
            .iter()
            .map(|s| params(*s).mass)
            .sum();
        assert!(
            (centre + 2.0 * limbs - 1.0).abs() < 1e-9,
            "{}",
            centre + 2.0 * limbs
        );
    }

    #[test]
    fn bandai_and_cmu_names() {
        use Segment::*;
        let cases: &[(&str, Option<&str>, Option<Segment>, Side)] = &[
            ("joint_Root", None, None, Side::Centre),
            ("Hips", Some("joint_Root"), Some(LowerTrunk), Side::Centre),
            ("Spine", Some("Hips"), Some(MiddleTrunk), Side::Centre),
            ("Chest", Some("Spine"), Some(UpperTrunk), Side::Centre),
            ("Shoulder_L", Some("Chest"), Some(UpperTrunk), Side::Left),
            ("UpperArm_L", Some("Shoulder_L"), Some(UpperArm), Side::Left),
            ("LowerArm_R", Some("UpperArm_R"), Some(Forearm), Side::Right),
            ("Hand_R", None, Some(Hand), Side::Right),
            ("UpperLeg_L", None, Some(Thigh), Side::Left),
            ("LowerLeg_L", None, Some(Shank), Side::Left),
            ("Toes_R", None, Some(Foot), Side::Right),
            ("LHipJoint", Some("Hips"), Some(LowerTrunk), Side::Left),
            ("LeftUpLeg", None, Some(Thigh), Side::Left),
            ("RightLeg", None, Some(Shank), Side::Right),
            ("LeftToeBase", None, Some(Foot), Side::Left),
            ("LowerBack", None, Some(MiddleTrunk), Side::Centre),
            ("Spine1", None, Some(UpperTrunk), Side::Centre),
            ("Neck1", None, Some(Head), Side::Centre),
            ("LeftShoulder", Some("Spine1"), Some(UpperTrunk), Side::Left),
            ("LeftArm", Some("LeftShoulder"), Some(UpperArm), Side::Left),
            ("RightForeArm", None, Some(Forearm), Side::Right),
            ("LFingers", None, Some(Hand), Side::Left),
            ("RThumb", None, Some(Hand), Side::Right),
            ("LeftHip", None, Some(Thigh), Side::Left),
            ("RightKnee", None, Some(Shank), Side::Right),
            ("LeftAnkle", None, Some(Foot), Side::Left),
            ("lowerback", None, Some(MiddleTrunk), Side::Centre),
            ("Chest2", None, Some(UpperTrunk), Side::Centre),
            ("lowerneck", None, Some(Head), Side::Centre),
            ("LeftCollar", None, Some(UpperTrunk), Side::Left),
            (
                "LeftShoulder",
                Some("LeftCollar"),
                Some(UpperArm),
                Side::Left,
            ),
            ("RightElbow", None, Some(Forearm), Side::Right),
            ("lhand", None, Some(Hand), Side::Left),
            ("rhand", None, Some(Hand), Side::Right),
            ("Widget", None, None, Side::Centre),
        ];
        for (n, p, seg, sd) in cases {
            assert_eq!(classify(n, *p), *seg, "{n}");
            assert_eq!(side(n), *sd, "{n}");
        }
    }
}
