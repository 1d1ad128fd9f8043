//! A body (a [`Model`]) whose coordinates are exactly a clip's DOFs: each BVH
//! position channel a prismatic joint and each rotation channel a revolute
//! joint about its axis, in the file's order (positions first: BVH applies
//! the translation before the rotations whatever the channel order), joint
//! and coordinate named `Joint.channel`. Masses, centres of mass and
//! inertias come from de Leva (1996) ([`super::segments`]) scaled by bone
//! lengths and the total mass.
//!
//! Gravity is against the up the skeleton stands along ([`super::up`]): y
//! for BVH's usual skeletons and anything without feet, z for a z-up one.
//!
//! Links: one per channel (massless except the last), the last named after
//! the BVH joint and carrying its segment; a joint without channels is a
//! fixed link; every End Site is a massless fixed link `Joint.end` (so
//! positions and the viewer reach head top, fingertips and toes).
//!
//! Mass distribution: joints are grouped by (segment, side); each group gets
//! de Leva's mass fraction, split among its joints by bone length. Groups the
//! skeleton lacks leave their share to the others (masses are renormalised
//! to the total). If fewer than 6 groups are recognised (unknown naming), the
//! fallback spreads the whole mass over all bones in proportion to length, as
//! uniform rods (COM mid-bone, radii 0.3 and 0.1 of length).

use super::MocapError;
use super::bvh::{BvhJoint, Channel, Skeleton};
use super::segments::{self, Segment, Side};
use crate::lie::Se3;
use crate::model::joints::{Fixed, Prismatic, Revolute};
use crate::model::{Inertia, Model};
use crate::motion::Mu;
use indexmap::IndexMap;
use nalgebra::{Matrix3, Vector3};
use std::sync::Arc;

/// y-up standard gravity, the convention of mocap skeletons (the default
/// when a skeleton's own up says nothing: [`super::up`]).
pub const GRAVITY_Y_UP: [f64; 3] = [0.0, -9.80665, 0.0];

/// The bone of joint `i`: the vector from its origin to the distal end of its
/// segment (in its own frame, file units). Distal end: the child that
/// continues the chain (the only child; else the child on the centre line, e.g.
/// Hips → Spine; else the mean of the children), or the End Site.
fn bone(sk: &Skeleton, i: usize) -> Vector3<f64> {
    let kids: Vec<usize> = sk.children(i).collect();
    match kids.len() {
        0 => sk.joints[i]
            .end_sites
            .first()
            .copied()
            .unwrap_or_else(Vector3::zeros),
        1 => sk.joints[kids[0]].offset,
        _ => {
            let centre: Vec<usize> = kids
                .iter()
                .copied()
                .filter(|&k| segments::side(&sk.joints[k].name) == Side::Centre)
                .collect();
            let pick = if centre.is_empty() { &kids } else { &centre };
            pick.iter()
                .map(|&k| sk.joints[k].offset)
                .sum::<Vector3<f64>>()
                / pick.len() as f64
        }
    }
}

/// Inertia of a segment of mass `m` along bone `d` (metres), axisymmetric.
pub(crate) fn segment_inertia(
    m: f64,
    d: &Vector3<f64>,
    com_frac: f64,
    r_long: f64,
    r_trans: f64,
) -> Result<Inertia, MocapError> {
    let l = d.norm();
    let com = d * com_frac;
    if m == 0.0 || l < 1e-9 {
        return Inertia::point(m, com).map_err(MocapError::from);
    }
    let u = d / l;
    let (il, it) = (m * (r_long * l).powi(2), m * (r_trans * l).powi(2));
    // I = it·(1 − u uᵀ) + il·u uᵀ
    let uu = u * u.transpose();
    let i = (Matrix3::identity() - uu) * it + uu * il;
    Inertia::from_com(m, com, i).map_err(MocapError::from)
}

/// How `body_of` distributed the mass (for the user and tests).
#[derive(Clone, Debug)]
pub struct MassReport {
    /// (BVH joint, segment or "fallback", mass kg)
    pub joints: Vec<(String, String, f64)>,
    pub used_fallback: bool,
}

/// Builds the body of a clip's skeleton with total mass `mass` kg.
/// `metres_per_unit` scales the file's lengths. Gravity is against the up
/// its rest pose stands along, else y ([`super::up::skeleton_up`]); with the
/// clip's motion at hand, [`body_of_motion`] also reads a skeleton whose
/// rest pose does not stand.
pub fn body_of(
    sk: &Skeleton,
    mass: f64,
    metres_per_unit: f64,
) -> Result<(Model, MassReport), MocapError> {
    build(sk, None, mass, metres_per_unit)
}

/// [`body_of`] for a skeleton and a motion it drives (DOFs `Joint.channel`):
/// where the rest pose does not stand, gravity is against the up the body
/// stands along over the motion's frames ([`super::up::skeleton_up`]).
pub fn body_of_motion(
    sk: &Skeleton,
    motion: &Mu,
    mass: f64,
    metres_per_unit: f64,
) -> Result<(Model, MassReport), MocapError> {
    build(sk, Some(motion), mass, metres_per_unit)
}

fn build(
    sk: &Skeleton,
    motion: Option<&Mu>,
    mass: f64,
    metres_per_unit: f64,
) -> Result<(Model, MassReport), MocapError> {
    if !(mass.is_finite() && mass > 0.0) {
        return Err(MocapError::invalid_option(
            "mass",
            format!(
                "body mass must be a positive number of kg, got {mass} (e.g. body_of(clip, mass: 70))"
            ),
        ));
    }
    if !(metres_per_unit.is_finite() && metres_per_unit > 0.0) {
        return Err(MocapError::invalid(format!(
            "unit scale must be positive, got {metres_per_unit}"
        )));
    }
    let (inertias, report) = match stated(sk, mass) {
        Some(stated) => stated,
        None => distribute_mass(sk, mass, metres_per_unit)?,
    };
    let mut model = Model::new("body_of");
    model.default_gravity = super::up::skeleton_gravity(sk, motion, metres_per_unit);
    let mut last_link: Vec<usize> = Vec::with_capacity(sk.joints.len());
    for (j, inertia) in sk.joints.iter().zip(inertias) {
        let parent = j.parent.map(|p| last_link[p]);
        last_link.push(add_joint_links(
            &mut model,
            j,
            parent,
            inertia,
            metres_per_unit,
        )?);
    }
    // End sites as massless fixed links.
    for (i, j) in sk.joints.iter().enumerate() {
        for (k, e) in j.end_sites.iter().enumerate() {
            let name = if k == 0 {
                format!("{}.end", j.name)
            } else {
                format!("{}.end{k}", j.name)
            };
            model.add_link(
                &name,
                Some(last_link[i]),
                &name,
                Arc::new(Fixed::new(Se3::identity())),
                Se3::from_translation(e * metres_per_unit),
                Inertia::zero(),
            )?;
        }
    }
    Ok((model, report))
}

/// The mass properties the skeleton's file states (see
/// [`Skeleton::inertias`]), scaled to `mass` kg: the saved body itself when
/// `mass` is the stated total ([`Skeleton::stated_mass`]).
fn stated(sk: &Skeleton, mass: f64) -> Option<(Vec<Inertia>, MassReport)> {
    let v = sk
        .inertias
        .as_ref()
        .filter(|v| v.len() == sk.joints.len())?;
    let scale = mass / sk.stated_mass()?;
    let inertias: Vec<Inertia> = v
        .iter()
        .map(|i| Inertia {
            mass: i.mass * scale,
            h: i.h * scale,
            i_o: i.i_o * scale,
        })
        .collect();
    let report = MassReport {
        joints: sk
            .joints
            .iter()
            .zip(&inertias)
            .map(|(j, i)| (j.name.clone(), "stated".to_string(), i.mass))
            .collect(),
        used_fallback: false,
    };
    Some((inertias, report))
}

/// The inertia of every joint's bone: de Leva shares of `mass` per segment,
/// split within a segment by bone length; by bone length alone (uniform rods)
/// when the skeleton names fewer than six segments.
fn distribute_mass(
    sk: &Skeleton,
    mass: f64,
    metres_per_unit: f64,
) -> Result<(Vec<Inertia>, MassReport), MocapError> {
    let n = sk.joints.len();
    let bones: Vec<Vector3<f64>> = (0..n).map(|i| bone(sk, i) * metres_per_unit).collect();

    // Classify and group.
    let seg: Vec<Option<Segment>> = (0..n)
        .map(|i| {
            segments::classify(
                &sk.joints[i].name,
                sk.joints[i].parent.map(|p| sk.joints[p].name.as_str()),
            )
        })
        .collect();
    // Insertion order (the skeleton's joint order), so sums over groups are the same
    // in every run: a HashMap's random order changed masses in the last bits.
    let mut groups: IndexMap<(Segment, Side), Vec<usize>> = IndexMap::new();
    for (i, sg) in seg.iter().enumerate() {
        if let Some(s) = *sg {
            let side = match s {
                Segment::Head
                | Segment::UpperTrunk
                | Segment::MiddleTrunk
                | Segment::LowerTrunk => Side::Centre,
                _ => segments::side(&sk.joints[i].name),
            };
            groups.entry((s, side)).or_default().push(i);
        }
    }
    let fallback = groups.len() < 6;
    let mut masses = vec![0.0; n];
    let mut inertias = vec![Inertia::zero(); n];
    let mut report = MassReport {
        joints: vec![],
        used_fallback: fallback,
    };
    if fallback {
        let total: f64 = bones.iter().map(|b| b.norm()).sum();
        for i in 0..n {
            masses[i] = if total > 0.0 {
                mass * bones[i].norm() / total
            } else {
                mass / n as f64
            };
            inertias[i] = segment_inertia(masses[i], &bones[i], 0.5, 0.1, 0.3)?;
            report
                .joints
                .push((sk.joints[i].name.clone(), "fallback".into(), masses[i]));
        }
    } else {
        let share: f64 = groups.keys().map(|(s, _)| segments::params(*s).mass).sum();
        for ((s, _), members) in &groups {
            let p = segments::params(*s);
            let group_mass = mass * p.mass / share;
            let len: f64 = members.iter().map(|&i| bones[i].norm()).sum();
            for &i in members {
                masses[i] = if len > 0.0 {
                    group_mass * bones[i].norm() / len
                } else {
                    group_mass / members.len() as f64
                };
                inertias[i] = segment_inertia(masses[i], &bones[i], p.com, p.r_long, p.r_trans)?;
            }
        }
        for i in 0..n {
            let what = seg[i]
                .map(|s| format!("{s:?}"))
                .unwrap_or_else(|| "massless".into());
            report
                .joints
                .push((sk.joints[i].name.clone(), what, masses[i]));
        }
    }
    Ok((inertias, report))
}

/// The links of one BVH joint under `parent`: one 1-DOF link per channel,
/// translations first (position channels replace their OFFSET components),
/// intermediate links massless and named after their DOF, the last named after
/// the joint and carrying `inertia`; a joint without channels is one fixed
/// link. Returns the joint's last link.
fn add_joint_links(
    model: &mut Model,
    j: &BvhJoint,
    parent: Option<usize>,
    inertia: Inertia,
    metres_per_unit: f64,
) -> Result<usize, MocapError> {
    let mut off = j.offset;
    for c in &j.channels {
        if !c.is_rotation() {
            off[c.axis()] = 0.0;
        }
    }
    let mut offset = Se3::from_translation(off * metres_per_unit);
    let order: Vec<Channel> = j
        .channels
        .iter()
        .filter(|c| !c.is_rotation())
        .chain(j.channels.iter().filter(|c| c.is_rotation()))
        .copied()
        .collect();
    if order.is_empty() {
        let l = model.add_link(
            &j.name,
            parent,
            &j.name,
            Arc::new(Fixed::new(Se3::identity())),
            offset,
            inertia,
        )?;
        return Ok(l);
    }
    let mut prev = parent;
    for (k, c) in order.iter().enumerate() {
        let dof_name = format!("{}.{}", j.name, c.name());
        let is_last = k + 1 == order.len();
        let link_name = if is_last {
            j.name.clone()
        } else {
            dof_name.clone()
        };
        let joint: Arc<dyn crate::model::Joint> = if c.is_rotation() {
            Arc::new(Revolute::new(c.axis_vector()).ok_or_else(|| MocapError::invalid("bad axis"))?)
        } else {
            Arc::new(
                Prismatic::new(c.axis_vector()).ok_or_else(|| MocapError::invalid("bad axis"))?,
            )
        };
        let link_inertia = if is_last { inertia } else { Inertia::zero() };
        let l = model.add_link(&link_name, prev, &dof_name, joint, offset, link_inertia)?;
        offset = Se3::identity();
        prev = Some(l);
    }
    Ok(prev.unwrap_or(0))
}
