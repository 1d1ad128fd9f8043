//! The paper's anatomical model (Rose 1996 §2): 6 root DOFs and 38 joint
//! DOFs, 44 in all, with limb lengths from a clip, and `fit`, which converts
//! a clip to it by per-frame least squares on joint positions and angles.
//!
//! DOFs (y up, facing +z, left = +x, T-pose at q = 0):
//! - root: `root.Xposition/Yposition/Zposition`, `root.Yrotation/Xrotation/Zrotation` (6)
//! - `lumbar.*` 3, `thorax.*` 3, `neck.*` 3 (X flex, Z bend, Y twist), `head.Xrotation` 1
//! - per side S ∈ {L, R}: `clavicle_S.Zrotation` 1, `shoulder_S.*` 3,
//!   `elbow_S.Yrotation` (hinge) 1, `wrist_S.Zrotation/Yrotation` 2;
//!   `hip_S.*` 3, `knee_S.Xrotation` (hinge) 1, `ankle_S.Xrotation/Zrotation` 2, `toe_S.Xrotation` 1.
//!
//! Segment lengths are distances between landmark joints of the clip's
//! skeleton (found by the de Leva name mapping of [`super::segments`]);
//! masses and inertias from de Leva, total `mass`.
//!
//! [`fit`] (in `human/fit.rs`) converts a clip to this model by per-frame
//! least squares on joint positions and segment orientations.

use super::MocapError;
use super::body_of::segment_inertia;
use super::bvh::Skeleton;
use super::segments::{self, Segment, Side};
use crate::lie::Se3;
use crate::model::joints::{Fixed, Prismatic, Revolute};
use crate::model::{Inertia, Model};
use nalgebra::Vector3;
use std::sync::Arc;

mod fit;
pub use fit::{FitOptions, FitReport, fit};

/// Landmark joints of a clip's skeleton (indices into its joints).
#[derive(Clone, Debug)]
struct Landmarks {
    pelvis: usize,
    chest: usize,
    neck: usize,
    head: usize,
    /// [left, right] of: clavicle, shoulder, elbow, wrist, hip, knee, ankle, toe (optional)
    clav: [usize; 2],
    shoulder: [usize; 2],
    elbow: [usize; 2],
    wrist: [usize; 2],
    hip: [usize; 2],
    knee: [usize; 2],
    ankle: [usize; 2],
    toe: [Option<usize>; 2],
}

fn find(sk: &Skeleton, seg: Segment, side: Side, what: &str) -> Result<usize, MocapError> {
    (0..sk.joints.len())
        .find(|&i| {
            let j = &sk.joints[i];
            segments::classify(&j.name, j.parent.map(|p| sk.joints[p].name.as_str())) == Some(seg)
                && segments::side(&j.name) == side
        })
        .ok_or_else(|| {
            MocapError::invalid(format!(
                "human(clip) needs a humanoid skeleton: no {what} joint found (expected names like those of the Bandai or CMU skeletons)"
            ))
        })
}

fn landmarks(sk: &Skeleton) -> Result<Landmarks, MocapError> {
    use Segment::*;
    let sides = [Side::Left, Side::Right];
    let both = |seg: Segment, what: &str| -> Result<[usize; 2], MocapError> {
        Ok([
            find(sk, seg, sides[0], &format!("left {what}"))?,
            find(sk, seg, sides[1], &format!("right {what}"))?,
        ])
    };
    let head = (0..sk.joints.len())
        .rfind(|&i| sk.joints[i].name.to_ascii_lowercase().contains("head"))
        .map(Ok)
        .unwrap_or_else(|| find(sk, Head, Side::Centre, "head"))?;
    let ankle = both(Foot, "ankle/foot")?;
    let toe = [0, 1].map(|s| {
        let a = ankle[s];
        // The toe: a Foot-segment child of the ankle.
        sk.children(a).find(|&c| {
            segments::classify(&sk.joints[c].name, Some(&sk.joints[a].name)) == Some(Foot)
        })
    });
    Ok(Landmarks {
        pelvis: find(sk, LowerTrunk, Side::Centre, "pelvis (Hips)")?,
        chest: find(sk, UpperTrunk, Side::Centre, "chest (upper trunk)")?,
        neck: find(sk, Head, Side::Centre, "neck")?,
        head,
        clav: both(UpperTrunk, "clavicle/collar")?,
        shoulder: both(UpperArm, "upper arm")?,
        elbow: both(Forearm, "forearm/elbow")?,
        wrist: both(Hand, "hand/wrist")?,
        hip: both(Thigh, "thigh/hip")?,
        knee: both(Shank, "shank/knee")?,
        ankle,
        toe,
    })
}

/// Rest positions (offsets accumulated, no rotation) of every joint, metres.
fn rest(sk: &Skeleton, s: f64) -> Vec<Vector3<f64>> {
    let mut out: Vec<Vector3<f64>> = Vec::with_capacity(sk.joints.len());
    for j in &sk.joints {
        let p = j.parent.map(|p| out[p]).unwrap_or_else(Vector3::zeros);
        out.push(
            p + if j.parent.is_some() {
                j.offset * s
            } else {
                Vector3::zeros()
            },
        );
    }
    out
}

/// The end of a chain: follow first children from `i` to a leaf; its End Site.
fn chain_end(sk: &Skeleton, mut i: usize) -> (usize, Option<Vector3<f64>>) {
    while let Some(c) = sk.children(i).next() {
        i = c;
    }
    (i, sk.joints[i].end_sites.first().copied())
}

/// A model built by [`human`], with what `fit` needs to match it to a clip.
#[derive(Clone, Debug)]
pub struct Human {
    pub model: Model,
    /// (model link, clip joint; `None` joint = an End Site of the given joint)
    targets: Vec<(usize, Target)>,
}

#[derive(Clone, Copy, Debug)]
enum Target {
    Joint(usize),
    EndSite(usize),
}

/// Adds a chain of 1-DOF joints; intermediate links are massless and named
/// after their joint, the last is `link` with `inertia`. Returns its index.
fn chain(
    m: &mut Model,
    parent: Option<usize>,
    link: &str,
    offset: Vector3<f64>,
    dofs: &[(&str, Vector3<f64>, bool)],
    inertia: Inertia,
) -> Result<usize, MocapError> {
    let mut prev = parent;
    let mut off = Se3::from_translation(offset);
    for (k, (name, axis, prismatic)) in dofs.iter().enumerate() {
        let last = k + 1 == dofs.len();
        let joint: Arc<dyn crate::model::Joint> = if *prismatic {
            Arc::new(Prismatic::new(*axis).ok_or_else(|| MocapError::invalid("bad axis"))?)
        } else {
            Arc::new(Revolute::new(*axis).ok_or_else(|| MocapError::invalid("bad axis"))?)
        };
        let l = m.add_link(
            if last { link } else { name },
            prev,
            name,
            joint,
            off,
            if last { inertia } else { Inertia::zero() },
        )?;
        off = Se3::identity();
        prev = Some(l);
    }
    prev.ok_or_else(|| MocapError::invalid("empty chain"))
}

/// Builds the 44-DOF model with the clip skeleton's limb lengths and total `mass` kg.
pub fn human(sk: &Skeleton, metres_per_unit: f64, mass: f64) -> Result<Human, MocapError> {
    if !(mass.is_finite() && mass > 0.0) {
        return Err(MocapError::invalid_option(
            "mass",
            format!("body mass must be a positive number of kg, got {mass}"),
        ));
    }
    let mut b = Build {
        sk,
        metres_per_unit,
        mass,
        lm: landmarks(sk)?,
        rest: rest(sk, metres_per_unit),
        m: Model::new("human44"),
        targets: vec![],
    };
    b.m.default_gravity = Vector3::from(super::body_of::GRAVITY_Y_UP);
    let (pelvis, thorax) = b.trunk()?;
    // link order (and so coordinate order): per side, the arm, then the leg
    for (s, sign, tag) in [(0usize, 1.0, "L"), (1, -1.0, "R")] {
        b.arm(thorax, s, sign, tag)?;
        b.leg(pelvis, s, sign, tag)?;
    }
    b.keep_total_mass()?;
    debug_assert_eq!(b.m.nq(), 44);
    Ok(Human {
        model: b.m,
        targets: b.targets,
    })
}

/// The model being built by [`human`], with the clip it is measured on.
struct Build<'a> {
    sk: &'a Skeleton,
    metres_per_unit: f64,
    /// total body mass, kg
    mass: f64,
    lm: Landmarks,
    /// rest position of every clip joint, metres
    rest: Vec<Vector3<f64>>,
    m: Model,
    targets: Vec<(usize, Target)>,
}

/// The three rotations of a ball joint named `p` (X, Z, Y: flex, bend, twist).
fn ball(p: &str) -> Vec<(String, Vector3<f64>, bool)> {
    vec![
        (format!("{p}.Xrotation"), Vector3::x(), false),
        (format!("{p}.Zrotation"), Vector3::z(), false),
        (format!("{p}.Yrotation"), Vector3::y(), false),
    ]
}

/// One rotation about `axis`, named `name`.
fn hinge(name: String, axis: Vector3<f64>) -> (String, Vector3<f64>, bool) {
    (name, axis, false)
}

impl Build<'_> {
    /// Distance between two clip joints at rest, metres.
    fn d(&self, a: usize, b: usize) -> f64 {
        (self.rest[a] - self.rest[b]).norm()
    }

    /// The de Leva inertia of segment `s` along `bone`.
    fn seg(&self, s: Segment, bone: Vector3<f64>) -> Result<Inertia, MocapError> {
        let p = segments::params(s);
        segment_inertia(self.mass * p.mass, &bone, p.com, p.r_long, p.r_trans)
    }

    /// A chain of 1-DOF joints under `parent` ending in link `link` (see [`chain`]).
    fn add(
        &mut self,
        parent: usize,
        link: &str,
        off: Vector3<f64>,
        dofs: Vec<(String, Vector3<f64>, bool)>,
        inertia: Inertia,
    ) -> Result<usize, MocapError> {
        let refs: Vec<(&str, Vector3<f64>, bool)> =
            dofs.iter().map(|(n, a, p)| (n.as_str(), *a, *p)).collect();
        chain(&mut self.m, Some(parent), link, off, &refs, inertia)
    }

    /// Pelvis (with the six root DOFs), abdomen, thorax, neck and head; returns
    /// (pelvis, thorax), where the legs and arms attach.
    fn trunk(&mut self) -> Result<(usize, usize), MocapError> {
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let lm = self.lm.clone();
        let spine = self.d(lm.pelvis, lm.chest);
        let pelvis_inertia = self.seg(Segment::LowerTrunk, y * spine * 0.3)?;
        let pelvis = chain(
            &mut self.m,
            None,
            "pelvis",
            Vector3::zeros(),
            &[
                ("root.Xposition", x, true),
                ("root.Yposition", y, true),
                ("root.Zposition", z, true),
                ("root.Yrotation", y, false),
                ("root.Xrotation", x, false),
                ("root.Zrotation", z, false),
            ],
            pelvis_inertia,
        )?;
        self.targets.push((pelvis, Target::Joint(lm.pelvis)));
        let inertia = self.seg(Segment::MiddleTrunk, y * spine)?;
        let abdomen = self.add(pelvis, "abdomen", Vector3::zeros(), ball("lumbar"), inertia)?;
        let c_n = self.d(lm.chest, lm.neck);
        let inertia = self.seg(Segment::UpperTrunk, y * c_n)?;
        let thorax = self.add(abdomen, "thorax", y * spine, ball("thorax"), inertia)?;
        self.targets.push((thorax, Target::Joint(lm.chest)));
        let neck = self.add(thorax, "neck", y * c_n, ball("neck"), Inertia::zero())?;
        self.targets.push((neck, Target::Joint(lm.neck)));
        let (_, head_top) = chain_end(self.sk, lm.head);
        let head_len = head_top
            .map(|e| e.norm() * self.metres_per_unit)
            .filter(|l| *l > 0.05)
            .unwrap_or(0.2);
        let inertia = self.seg(Segment::Head, y * head_len)?;
        let head = self.add(
            neck,
            "head",
            y * self.d(lm.neck, lm.head),
            vec![hinge("head.Xrotation".into(), x)],
            inertia,
        )?;
        self.targets.push((head, Target::Joint(lm.head)));
        Ok((pelvis, thorax))
    }

    /// Clavicle, upper arm, forearm and hand of side `s` (`sign` +1 left, −1 right).
    fn arm(&mut self, thorax: usize, s: usize, sign: f64, tag: &str) -> Result<(), MocapError> {
        let (y, z) = (Vector3::y(), Vector3::z());
        let lat = Vector3::x() * sign;
        let lm = self.lm.clone();
        let clav = self.add(
            thorax,
            &format!("clavicle_{tag}"),
            y * self.d(lm.chest, lm.clav[s]),
            vec![hinge(format!("clavicle_{tag}.Zrotation"), z)],
            Inertia::zero(),
        )?;
        self.targets.push((clav, Target::Joint(lm.clav[s])));
        let ua = self.d(lm.shoulder[s], lm.elbow[s]);
        let inertia = self.seg(Segment::UpperArm, lat * ua)?;
        let upper = self.add(
            clav,
            &format!("upperarm_{tag}"),
            lat * self.d(lm.clav[s], lm.shoulder[s]),
            ball(&format!("shoulder_{tag}")),
            inertia,
        )?;
        self.targets.push((upper, Target::Joint(lm.shoulder[s])));
        let fa = self.d(lm.elbow[s], lm.wrist[s]);
        let inertia = self.seg(Segment::Forearm, lat * fa)?;
        let fore = self.add(
            upper,
            &format!("forearm_{tag}"),
            lat * ua,
            vec![hinge(format!("elbow_{tag}.Yrotation"), y)],
            inertia,
        )?;
        self.targets.push((fore, Target::Joint(lm.elbow[s])));
        let (hend_j, hend_site) = chain_end(self.sk, lm.wrist[s]);
        let hand_len = {
            let tip =
                self.rest[hend_j] + hend_site.unwrap_or_else(Vector3::zeros) * self.metres_per_unit;
            (tip - self.rest[lm.wrist[s]]).norm().max(0.05)
        };
        let inertia = self.seg(Segment::Hand, lat * hand_len)?;
        let hand = self.add(
            fore,
            &format!("hand_{tag}"),
            lat * fa,
            vec![
                hinge(format!("wrist_{tag}.Zrotation"), z),
                hinge(format!("wrist_{tag}.Yrotation"), y),
            ],
            inertia,
        )?;
        self.targets.push((hand, Target::Joint(lm.wrist[s])));
        Ok(())
    }

    /// Thigh, shank, foot and toes of side `s`, and the toes' End Site when the
    /// clip has one.
    fn leg(&mut self, pelvis: usize, s: usize, sign: f64, tag: &str) -> Result<(), MocapError> {
        let (x, y, z) = (Vector3::x(), Vector3::y(), Vector3::z());
        let lat = x * sign;
        let lm = self.lm.clone();
        let half = self.d(lm.hip[0], lm.hip[1]) / 2.0;
        let vert = (self.d(lm.pelvis, lm.hip[s]).powi(2) - half * half)
            .max(0.0)
            .sqrt();
        let th = self.d(lm.hip[s], lm.knee[s]);
        let inertia = self.seg(Segment::Thigh, -y * th)?;
        let thigh = self.add(
            pelvis,
            &format!("thigh_{tag}"),
            lat * half - y * vert,
            ball(&format!("hip_{tag}")),
            inertia,
        )?;
        self.targets.push((thigh, Target::Joint(lm.hip[s])));
        let sh = self.d(lm.knee[s], lm.ankle[s]);
        let inertia = self.seg(Segment::Shank, -y * sh)?;
        let shank = self.add(
            thigh,
            &format!("shank_{tag}"),
            -y * th,
            vec![hinge(format!("knee_{tag}.Xrotation"), x)],
            inertia,
        )?;
        self.targets.push((shank, Target::Joint(lm.knee[s])));
        let foot_len = lm.toe[s]
            .map(|t| self.d(lm.ankle[s], t))
            .filter(|l| *l > 0.03)
            .unwrap_or(0.12);
        let foot_dir = Vector3::new(0.0, -0.45, 0.89).normalize();
        let inertia = self.seg(Segment::Foot, foot_dir * foot_len)?;
        let foot = self.add(
            shank,
            &format!("foot_{tag}"),
            -y * sh,
            vec![
                hinge(format!("ankle_{tag}.Xrotation"), x),
                hinge(format!("ankle_{tag}.Zrotation"), z),
            ],
            inertia,
        )?;
        self.targets.push((foot, Target::Joint(lm.ankle[s])));
        let toes = self.add(
            foot,
            &format!("toes_{tag}"),
            foot_dir * foot_len,
            vec![hinge(format!("toe_{tag}.Xrotation"), x)],
            Inertia::zero(),
        )?;
        let Some(t) = lm.toe[s] else { return Ok(()) };
        self.targets.push((toes, Target::Joint(t)));
        if let (tj, Some(site)) = chain_end(self.sk, t) {
            let l = site.norm() * self.metres_per_unit;
            if l > 1e-3 && tj == t {
                let end = self.m.add_link(
                    &format!("toes_{tag}.end"),
                    Some(toes),
                    &format!("toes_{tag}.end"),
                    Arc::new(Fixed::new(Se3::identity())),
                    Se3::from_translation(z * l),
                    Inertia::zero(),
                )?;
                self.targets.push((end, Target::EndSite(t)));
            }
        }
        Ok(())
    }

    /// Scales every massive link so the total is exactly `mass` (neck and
    /// clavicles carry none; their de Leva shares sit on head and thorax).
    fn keep_total_mass(&mut self) -> Result<(), MocapError> {
        let total = self.m.total_mass();
        if total > 0.0 {
            for i in 0..self.m.num_links() {
                let l = self.m.link(i).inertia;
                if l.mass > 0.0 {
                    let k = self.mass / total;
                    let scaled = Inertia::from_com(l.mass * k, l.com(), l.inertia_com() * k)
                        .map_err(MocapError::from)?;
                    self.m.set_inertia(i, scaled)?;
                }
            }
        }
        Ok(())
    }
}
