//! Channel names as a type: the one home of the `Joint.Xrotation` naming
//! convention, the left/right rule mirroring uses, and an index of a
//! motion's joints.
//!
//! A DOF name is `joint.suffix` (split at the last `.`) or a bare name with
//! no dot (an OpenSim coordinate such as `hip_flexion_r`, a URDF 1-DOF
//! joint): a bare name is its own joint and a scalar. Suffixes come in two
//! styles, and only the BVH one makes Euler joints, as the operators always
//! did:
//! - BVH: `Xrotation`, `Yposition`, … (any case) → [`Kind::Rotation`] /
//!   [`Kind::Position`] about / along that axis;
//! - model coordinates (`model::Joint::coordinate_suffixes`) and IK targets:
//!   `rx`, `tx`, `x`, … → the same kinds, [`Style::Model`];
//! - anything else (`angle`, `q0`, `knee_angle_r`) → [`Kind::Scalar`].

use super::mu::Mu;

/// What a channel moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A rotation about axis 0 = x, 1 = y, 2 = z.
    Rotation(usize),
    /// A translation along axis 0 = x, 1 = y, 2 = z.
    Position(usize),
    /// Any other coordinate (an angle about a joint's own axis, a spline
    /// parameter, an OpenSim coordinate).
    Scalar,
}

/// Which naming convention a channel's suffix follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// `Joint.Xrotation`, `Joint.Yposition` (BVH channel names).
    Bvh,
    /// `joint.rx`, `joint.tx`, `link.x` (model coordinates, IK targets).
    Model,
    /// No recognised axis suffix, or no suffix at all.
    Other,
}

/// One DOF name, parsed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Channel<'a> {
    /// The joint (or link) part: before the last `.`, the whole name when
    /// there is no `.`.
    pub joint: &'a str,
    /// The part after the last `.`, `None` for a bare name.
    pub suffix: Option<&'a str>,
    pub kind: Kind,
    pub style: Style,
}

fn axis_of(c: u8) -> Option<usize> {
    match c.to_ascii_lowercase() {
        b'x' => Some(0),
        b'y' => Some(1),
        b'z' => Some(2),
        _ => None,
    }
}

impl<'a> Channel<'a> {
    /// Parses a DOF name; never fails (an unknown suffix is a scalar).
    pub fn parse(name: &'a str) -> Channel<'a> {
        let Some((joint, suffix)) = name.rsplit_once('.') else {
            return Channel {
                joint: name,
                suffix: None,
                kind: Kind::Scalar,
                style: Style::Other,
            };
        };
        let (kind, style) = kind_of(suffix);
        Channel {
            joint,
            suffix: Some(suffix),
            kind,
            style,
        }
    }

    /// The axis of a BVH rotation channel (`…Xrotation` → 0): the channels
    /// Euler joints are made of.
    pub fn euler_axis(&self) -> Option<usize> {
        match (self.kind, self.style) {
            (Kind::Rotation(a), Style::Bvh) => Some(a),
            _ => None,
        }
    }

    /// `true` for a BVH position channel (`…Xposition`): the root's.
    pub fn is_bvh_position(&self) -> bool {
        matches!((self.kind, self.style), (Kind::Position(_), Style::Bvh))
    }
}

/// Which of a motion's channels stands for one suffix of one joint
/// ([`channel_for`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Found<'a> {
    One(&'a str),
    /// No name has that suffix.
    Missing,
    /// Several names end in it and none is the joint's own: these.
    Several(Vec<&'a str>),
}

/// The channel of `names` for `suffix` of `joint`: the bare name `suffix`,
/// else `joint.suffix`, else the one name whose suffix (after its last `.`)
/// is `suffix`. How a motion of IK targets is read: its DOFs `x`, `y`, `z`,
/// `LeftFoot.x`, or the one `….x` a single-link motion has.
pub fn channel_for<'a>(names: &[&'a str], joint: &str, suffix: &str) -> Found<'a> {
    let own = |n: &str| n.strip_suffix(suffix).and_then(|j| j.strip_suffix('.')) == Some(joint);
    // the bare name first, then the joint's own
    let mut all = names.iter().copied();
    if let Some(n) = all
        .clone()
        .find(|n| *n == suffix)
        .or_else(|| all.find(|n| own(n)))
    {
        return Found::One(n);
    }
    let found: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| Channel::parse(n).suffix == Some(suffix))
        .collect();
    match found.as_slice() {
        [] => Found::Missing,
        [one] => Found::One(one),
        _ => Found::Several(found),
    }
}

fn kind_of(suffix: &str) -> (Kind, Style) {
    let b = suffix.as_bytes();
    let lower = suffix.to_ascii_lowercase();
    let axis = b.first().copied().and_then(axis_of);
    if let Some(a) = axis {
        match &lower[1..] {
            "rotation" => return (Kind::Rotation(a), Style::Bvh),
            "position" => return (Kind::Position(a), Style::Bvh),
            "" => return (Kind::Position(a), Style::Model),
            _ => {}
        }
    }
    if b.len() == 2 {
        match (b[0], axis_of(b[1])) {
            (b'r', Some(a)) => return (Kind::Rotation(a), Style::Model),
            (b't', Some(a)) => return (Kind::Position(a), Style::Model),
            _ => {}
        }
    }
    (Kind::Scalar, Style::Other)
}

/// The side of the body a joint name is on, by [`mirror_name`]'s rule.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
}

/// The name of the other side's joint (`LeftArm` ↔ `RightArm`, `Arm_L` ↔
/// `Arm_R`, `LArm` ↔ `RArm`, `arm.l` ↔ `arm.r`); `None` for a name with no
/// side. This is the rule `mirror` uses. (`mocap::segments::side` and
/// `library::features` keep their own, slightly different rules: they
/// classify bones of skeletons they have tuned against, e.g. `lhand`, `l_foot`;
/// switching them here would change which bones they find.)
pub fn mirror_name(joint: &str) -> Option<String> {
    mirrored(joint).map(|(_, n)| n)
}

/// The side of `joint` by the mirroring rule, `None` for a centre joint.
pub fn side(joint: &str) -> Option<Side> {
    mirrored(joint).map(|(s, _)| s)
}

fn mirrored(joint: &str) -> Option<(Side, String)> {
    use Side::{Left, Right};
    for (l, r) in [("Left", "Right"), ("left", "right"), ("LEFT", "RIGHT")] {
        if joint.contains(l) {
            return Some((Left, joint.replacen(l, r, 1)));
        }
        if joint.contains(r) {
            return Some((Right, joint.replacen(r, l, 1)));
        }
    }
    for (l, r) in [("_L", "_R"), ("_l", "_r"), (".L", ".R"), (".l", ".r")] {
        if let Some(stem) = joint.strip_suffix(l) {
            return Some((Left, format!("{stem}{r}")));
        }
        if let Some(stem) = joint.strip_suffix(r) {
            return Some((Right, format!("{stem}{l}")));
        }
    }
    let b = joint.as_bytes();
    if b.len() > 1 && b[1].is_ascii_uppercase() {
        match b[0] {
            b'L' => return Some((Left, format!("R{}", &joint[1..]))),
            b'R' => return Some((Right, format!("L{}", &joint[1..]))),
            _ => {}
        }
    }
    None
}

/// The DOF name after mirroring: the joint part swapped by side, the suffix
/// kept; `None` for a bare name or a joint with no side.
pub fn mirror_dof(name: &str) -> Option<String> {
    let c = Channel::parse(name);
    let suffix = c.suffix?;
    Some(format!("{}.{suffix}", mirror_name(c.joint)?))
}

/// The three rotation channels of one joint, in the motion's order.
#[derive(Clone, Debug, PartialEq)]
pub struct EulerJoint {
    /// The joint's name ([`Channel::joint`] of its DOFs).
    pub joint: String,
    /// DOF names, in channel order.
    pub dofs: [String; 3],
    /// The axis (0 = x, 1 = y, 2 = z) of each channel; three distinct axes.
    pub axes: [usize; 3],
}

/// The axis of a BVH rotation channel name (`…Xrotation` → 0), if it is
/// one; a bare name (`Xrotation`) counts, as it always has for `mirror`.
pub fn rotation_axis(dof: &str) -> Option<usize> {
    let c = Channel::parse(dof);
    match kind_of(c.suffix.unwrap_or(c.joint)) {
        (Kind::Rotation(a), Style::Bvh) => Some(a),
        _ => None,
    }
}

/// The axis of a BVH position channel name (`…Yposition` → 1), if it is
/// one; a bare name counts, as for [`rotation_axis`].
pub fn position_axis(dof: &str) -> Option<usize> {
    let c = Channel::parse(dof);
    match kind_of(c.suffix.unwrap_or(c.joint)) {
        (Kind::Position(a), Style::Bvh) => Some(a),
        _ => None,
    }
}

/// Joints with exactly three BVH rotation channels about distinct axes, in
/// the order their first channel appears in `names`. Joints with one or two
/// rotation channels are not Euler joints (each channel is then a plain
/// angle about a fixed axis).
pub fn euler_joints<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<EulerJoint> {
    let mut found: indexmap::IndexMap<&str, Vec<(&str, usize)>> = indexmap::IndexMap::new();
    for n in names {
        let c = Channel::parse(n);
        if let (Some(axis), Some(_)) = (c.euler_axis(), c.suffix) {
            found.entry(c.joint).or_default().push((n, axis));
        }
    }
    found
        .into_iter()
        .filter_map(|(joint, chans)| {
            let [a, b, c] = chans.as_slice() else {
                return None;
            };
            if a.1 == b.1 || b.1 == c.1 || a.1 == c.1 {
                return None;
            }
            Some(EulerJoint {
                joint: joint.to_string(),
                dofs: [a.0.to_string(), b.0.to_string(), c.0.to_string()],
                axes: [a.1, b.1, c.1],
            })
        })
        .collect()
}

/// The root of a motion: the joint that carries it through the world.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionRoot {
    pub joint: String,
    /// Its position DOF names along x, y, z (`None` where absent).
    pub pos: [Option<String>; 3],
    /// Its Euler joint, when it has three rotation channels.
    pub rot: Option<EulerJoint>,
}

/// An index of a motion's channels: its joints, its Euler joints, its root.
#[derive(Clone, Debug, PartialEq)]
pub struct MotionChannels {
    /// Joint names in the order their first DOF appears (bare names are
    /// their own joint).
    pub joints: Vec<String>,
    /// See [`euler_joints`].
    pub euler: Vec<EulerJoint>,
    /// The first joint with BVH position channels, if any.
    pub root: Option<MotionRoot>,
}

impl MotionChannels {
    pub fn of(m: &Mu) -> MotionChannels {
        let names: Vec<&str> = m.names().collect();
        Self::of_names(names.iter().copied())
    }

    /// The index of a list of DOF names (in motion order).
    pub fn of_names<'a>(names: impl IntoIterator<Item = &'a str> + Clone) -> MotionChannels {
        let mut joints: indexmap::IndexSet<&str> = indexmap::IndexSet::new();
        for n in names.clone() {
            joints.insert(Channel::parse(n).joint);
        }
        let euler = euler_joints(names.clone());
        let root = names
            .clone()
            .into_iter()
            .map(Channel::parse)
            .find(Channel::is_bvh_position)
            .map(|c| {
                let joint = c.joint.to_string();
                let pos = std::array::from_fn(|a| {
                    names
                        .clone()
                        .into_iter()
                        .find(|n| {
                            let o = Channel::parse(n);
                            o.joint == joint && o.is_bvh_position() && o.kind == Kind::Position(a)
                        })
                        .map(str::to_string)
                });
                let rot = euler.iter().find(|j| j.joint == joint).cloned();
                MotionRoot { joint, pos, rot }
            });
        MotionChannels {
            joints: joints.into_iter().map(str::to_string).collect(),
            euler,
            root,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_joints_channel_is_found_by_its_suffix() {
        let names = ["LeftFoot.x", "RightFoot.x", "LeftFoot.y", "z", "Hips.rx"];
        assert_eq!(
            channel_for(&names, "RightFoot", "x"),
            Found::One("RightFoot.x")
        );
        assert_eq!(channel_for(&names, "Any", "z"), Found::One("z"));
        // not the joint's own, but the only one
        assert_eq!(channel_for(&names, "Any", "y"), Found::One("LeftFoot.y"));
        assert_eq!(channel_for(&names, "Any", "rx"), Found::One("Hips.rx"));
        assert_eq!(
            channel_for(&names, "Hand", "x"),
            Found::Several(vec!["LeftFoot.x", "RightFoot.x"])
        );
        assert_eq!(channel_for(&names, "LeftFoot", "ry"), Found::Missing);
        // a suffix is the part after the last dot, not any ending
        assert_eq!(channel_for(&["a.bx"], "a", "x"), Found::Missing);
        assert_eq!(
            channel_for(&["Arm.L.x"], "Arm.L", "x"),
            Found::One("Arm.L.x")
        );
    }

    #[test]
    fn bvh_names_parse() {
        let c = Channel::parse("LeftUpLeg.Xrotation");
        assert_eq!((c.joint, c.suffix), ("LeftUpLeg", Some("Xrotation")));
        assert_eq!((c.kind, c.style), (Kind::Rotation(0), Style::Bvh));
        assert_eq!(c.euler_axis(), Some(0));
        let c = Channel::parse("Hips.zposition");
        assert_eq!((c.kind, c.style), (Kind::Position(2), Style::Bvh));
        assert!(c.is_bvh_position());
        // a dotted joint name splits at the last dot
        let c = Channel::parse("mixamorig.Hips.Yrotation");
        assert_eq!((c.joint, c.kind), ("mixamorig.Hips", Kind::Rotation(1)));
    }

    #[test]
    fn urdf_and_model_names_parse() {
        // a 1-DOF URDF joint: its coordinate is its name
        let c = Channel::parse("l_hip_pitch");
        assert_eq!(
            (c.joint, c.suffix, c.kind),
            ("l_hip_pitch", None, Kind::Scalar)
        );
        // spherical / free joints: rx… and tx…
        let c = Channel::parse("shoulder.rz");
        assert_eq!((c.kind, c.style), (Kind::Rotation(2), Style::Model));
        assert_eq!(c.euler_axis(), None, "only BVH channels make Euler joints");
        assert_eq!(Channel::parse("root.ty").kind, Kind::Position(1));
        assert_eq!(Channel::parse("LeftFoot.x").kind, Kind::Position(0));
        assert_eq!(Channel::parse("base.angle").kind, Kind::Scalar);
        assert_eq!(Channel::parse("spline.q0").kind, Kind::Scalar);
    }

    #[test]
    fn opensim_names_parse() {
        for n in [
            "hip_flexion_r",
            "knee_angle_l",
            "pelvis_tx",
            "lumbar_extension",
        ] {
            let c = Channel::parse(n);
            assert_eq!((c.joint, c.suffix, c.kind), (n, None, Kind::Scalar), "{n}");
        }
        // each bare coordinate is its own joint
        let ix = MotionChannels::of_names(["pelvis_tx", "hip_flexion_r"]);
        assert_eq!(ix.joints, ["pelvis_tx", "hip_flexion_r"]);
        assert!(ix.euler.is_empty() && ix.root.is_none());
    }

    #[test]
    fn mirroring_rule() {
        let m = |n: &str| mirror_name(n);
        assert_eq!(m("LeftArm").as_deref(), Some("RightArm"));
        assert_eq!(m("RightUpLeg").as_deref(), Some("LeftUpLeg"));
        assert_eq!(m("left_hand").as_deref(), Some("right_hand"));
        assert_eq!(m("Arm_L").as_deref(), Some("Arm_R"));
        assert_eq!(m("foot_r").as_deref(), Some("foot_l"));
        assert_eq!(m("arm.l").as_deref(), Some("arm.r"));
        assert_eq!(m("LArm").as_deref(), Some("RArm"));
        assert_eq!(m("Hips"), None);
        assert_eq!(
            m("Leg"),
            None,
            "a capital L before a lower-case letter is no side"
        );
        assert_eq!(m("l_foot"), None, "the mirror rule has no `l_` prefix");
        assert_eq!(side("LeftArm"), Some(Side::Left));
        assert_eq!(side("Toe_R"), Some(Side::Right));
        assert_eq!(side("Spine"), None);
        for n in ["LeftArm", "Arm_L", "arm.r", "LArm"] {
            assert_eq!(
                m(&m(n).unwrap()).as_deref(),
                Some(n),
                "its own inverse: {n}"
            );
        }
        assert_eq!(
            mirror_dof("LeftArm.Zrotation").as_deref(),
            Some("RightArm.Zrotation")
        );
        assert_eq!(
            mirror_dof("knee_angle_l"),
            None,
            "a bare name has no joint part"
        );
    }

    #[test]
    fn index_finds_joints_euler_joints_and_root() {
        let names = [
            "Hips.Xposition",
            "Hips.Yposition",
            "Hips.Zposition",
            "Hips.Zrotation",
            "Hips.Xrotation",
            "Hips.Yrotation",
            "Knee.Xrotation",
            "Spine.Zrotation",
            "Spine.Xrotation",
            "Spine.Yrotation",
        ];
        let ix = MotionChannels::of_names(names);
        assert_eq!(ix.joints, ["Hips", "Knee", "Spine"]);
        assert_eq!(ix.euler.len(), 2, "a hinge is no Euler joint");
        assert_eq!(ix.euler[0].axes, [2, 0, 1]);
        let root = ix.root.unwrap();
        assert_eq!(root.joint, "Hips");
        assert_eq!(root.pos[1].as_deref(), Some("Hips.Yposition"));
        assert_eq!(root.rot.unwrap().joint, "Hips");
    }
}
