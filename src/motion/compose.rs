//! The animator's operators beyond Rose's algebra: `blend`, `crossfade`,
//! `align`, `layer`, `mask`, `mirror`, `reverse`, `warp`, `resample`.
//!
//! Operators that mix poses (blend, crossfade, layer, mask) work on every
//! Euler joint's rotation as a unit quaternion ([`super::rotation`]) and write
//! the result back as continuous Euler channels in the joint's own order: the
//! output is sampled on a uniform grid (the inputs' finest sample step, 120 Hz
//! when no input is sampled data) and each frame's Euler triple is chosen
//! nearest the previous frame's, advanced by the inputs' weighted increments.
//! Every other DOF (root translation, scalars) mixes linearly. A joint's
//! rotation is mixed where all its channels are defined in every input.
//!
//! `mirror` and `reverse` are exact (no resampling of sampled data): mirror
//! negates the two rotation channels about axes other than the mirror axis
//! and the position along it, reverse plays each curve backwards.

use std::sync::Arc;

use nalgebra::{UnitQuaternion, Vector3};

use super::curve::{Curve, SampledCurve, TimeFunction};
use super::dof::Dof;
use super::error::MotionError;
use super::func::Func;
use super::interval::Interval;
use super::mu::Mu;
use super::rotation::{self, EulerJoint};
use super::time_tol;

/// The output step when no input holds sampled data: 120 Hz.
pub const DEFAULT_RATE: f64 = 120.0;

fn err(op: &'static str, message: impl Into<String>) -> MotionError {
    MotionError::Compose {
        op,
        message: message.into(),
    }
}

/// A weight: a constant or a function of (global) time.
#[derive(Clone, Debug)]
pub enum Weight {
    Const(f64),
    Func(Arc<dyn TimeFunction>),
}

impl Weight {
    /// The weight at `t`, checked to lie in [0, 1].
    pub fn at(&self, op: &'static str, t: f64) -> Result<f64, MotionError> {
        let w = match self {
            Weight::Const(w) => *w,
            Weight::Func(f) => f.eval(t).map_err(|message| MotionError::Function {
                t,
                message,
                dof: None,
            })?,
        };
        if !(0.0..=1.0).contains(&w) {
            return Err(err(
                op,
                format!("the weight must lie in [0, 1], got {w} at t = {t}"),
            ));
        }
        Ok(w)
    }
}

/// The finest sample step of the sampled data in `ms`, else 1/120 s.
pub fn native_dt(ms: &[&Mu]) -> f64 {
    let mut dt = f64::INFINITY;
    for m in ms {
        for d in m.dofs.values() {
            for i in &d.intervals {
                for f in &i.funcs {
                    if let Curve::Samples(s) = f.curve.as_ref() {
                        dt = dt.min(s.dt() * f.scale);
                    }
                }
            }
        }
    }
    if dt.is_finite() {
        dt
    } else {
        1.0 / DEFAULT_RATE
    }
}

/// Uniform times over [s, e], the step at most `dt` (both ends included).
fn grid(s: f64, e: f64, dt: f64) -> Vec<f64> {
    let n = (((e - s) / dt) - 1e-9).ceil().max(1.0) as usize;
    let h = (e - s) / n as f64;
    (0..=n)
        .map(|k| if k == n { e } else { s + k as f64 * h })
        .collect()
}

/// One sampled-data interval through `values` at `times` (a uniform grid).
fn sampled(times: &[f64], values: Vec<f64>) -> Result<Interval, MotionError> {
    let (s, e) = (times[0], times[times.len() - 1]);
    let dt = (e - s) / (times.len() - 1) as f64;
    Interval::curve(Curve::samples(s, dt, values)?, s, e)
}

/// The maximal spans where every DOF of `dofs` is defined.
fn common_spans(dofs: &[&Dof]) -> Vec<(f64, f64)> {
    let Some(first) = dofs.first() else {
        return vec![];
    };
    let mut acc = (*first).clone();
    for d in &dofs[1..] {
        acc = acc.and(d);
    }
    let mut out: Vec<(f64, f64)> = vec![];
    for i in &acc.intervals {
        match out.last_mut() {
            Some(last) if i.start - last.1 <= time_tol(last.1) => last.1 = i.stop,
            _ => out.push((i.start, i.stop)),
        }
    }
    out
}

/// A group of DOFs mixed together: a joint's three Euler channels or one scalar.
enum Group {
    Rot(EulerJoint),
    Scalar(String),
}

impl Group {
    fn names(&self) -> Vec<&str> {
        match self {
            Group::Rot(j) => j.dofs.iter().map(String::as_str).collect(),
            Group::Scalar(n) => vec![n.as_str()],
        }
    }
}

/// The groups of `names`: Euler joints first found, then the other DOFs.
fn groups(names: &[&str]) -> Vec<Group> {
    let joints = rotation::euler_joints(names.iter().copied());
    let in_joint = |n: &str| joints.iter().any(|j| j.dofs.iter().any(|d| d == n));
    let scalars: Vec<Group> = names
        .iter()
        .copied()
        .filter(|n| !in_joint(n))
        .map(|n| Group::Scalar(n.to_string()))
        .collect();
    joints.into_iter().map(Group::Rot).chain(scalars).collect()
}

/// How a pose-mixing operator combines its inputs at one time.
trait Mixer {
    /// Weights of the inputs for predicting the next frame's Euler angles.
    fn weights(&self, t: f64) -> Result<Vec<f64>, MotionError>;
    /// The mixed rotation of group `g` from the inputs' rotations.
    fn rot(
        &self,
        g: usize,
        t: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError>;
    /// The input whose pose the mix is at `t` exactly (a blend at w = 0 or 1),
    /// so its Euler channels are copied rather than recomputed.
    fn pick(&self, _t: f64) -> Result<Option<usize>, MotionError> {
        Ok(None)
    }
    /// The mixed value of scalar group `g` from the inputs' values.
    fn scalar(&self, g: usize, t: f64, xs: &[f64]) -> Result<f64, MotionError>;
    /// The input the mix is, exactly, wherever it is evaluated (a blend at a
    /// constant w of 0 or 1, or of inputs that are the same curves
    /// (`same`); a layer at w = 0): its curves are copied, not resampled.
    fn whole(&self, _same: bool) -> Option<usize> {
        None
    }
}

/// Mix `inputs` group by group where all of a group's DOFs are defined in
/// every input; elsewhere each DOF is `keep`'s.
fn mix(inputs: &[&Mu], keep: &Mu, mixer: &dyn Mixer, dt: f64) -> Result<Mu, MotionError> {
    let names: Vec<&str> = inputs[0]
        .names()
        .filter(|n| inputs.iter().all(|m| m.get(n).is_some()))
        .collect();
    let gs = groups(&names);
    let mut mixed: indexmap::IndexMap<String, Vec<Interval>> = indexmap::IndexMap::new();
    for (gi, g) in gs.iter().enumerate() {
        let names = g.names();
        let dofs: Vec<&Dof> = inputs
            .iter()
            .flat_map(|m| names.iter().map(move |n| &m.dofs[*n]))
            .collect();
        let same = inputs[1..]
            .iter()
            .all(|m| names.iter().all(|n| m.dofs[*n] == inputs[0].dofs[*n]));
        for (s, e) in common_spans(&dofs) {
            // Copied where the mix is one input: resampled, it is not that
            // input. The grid is off the input's frames (CMU's 0.0083333 s
            // frame time over [2, 4] s gives 241 steps of 8.299 ms) and the
            // spline through the resampled values has its own ends, so
            // `blend(c, c, 0.5)` on CMU 01_01 clipped to [2, 4] s moved 74 of
            // 96 DOFs at t = 1.1 s, by up to 5.5e-4 rad (measured).
            if let Some(k) = mixer.whole(same) {
                // the weights are still checked at every frame (a weight
                // function leaving [0, 1] is an error even here)
                for &t in &grid(s, e, dt) {
                    mixer.weights(t)?;
                }
                for n in &names {
                    let part = inputs[k].dofs[*n].window(s, e);
                    mixed
                        .entry(n.to_string())
                        .or_default()
                        .extend(part.intervals);
                }
                continue;
            }
            let times = grid(s, e, dt);
            // values[input][channel][frame]
            let mut vals = vec![vec![vec![]; names.len()]; inputs.len()];
            for (k, m) in inputs.iter().enumerate() {
                for (c, n) in names.iter().enumerate() {
                    let v = m.dofs[*n].sample_values_sorted(n, &times)?;
                    vals[k][c] = v
                        .into_iter()
                        .zip(&times)
                        .map(|(x, &t)| {
                            x.ok_or(MotionError::Undefined {
                                dof: n.to_string(),
                                t,
                            })
                        })
                        .collect::<Result<_, _>>()?;
                }
            }
            let mut out = vec![Vec::with_capacity(times.len()); names.len()];
            match g {
                Group::Scalar(_) => {
                    for (f, &t) in times.iter().enumerate() {
                        let xs: Vec<f64> = vals.iter().map(|v| v[0][f]).collect();
                        out[0].push(mixer.scalar(gi, t, &xs)?);
                    }
                }
                Group::Rot(j) => {
                    let mut prev: Option<[f64; 3]> = None;
                    let mut prev_q: Vec<UnitQuaternion<f64>> = vec![];
                    for (f, &t) in times.iter().enumerate() {
                        let eul: Vec<[f64; 3]> =
                            vals.iter().map(|v| [v[0][f], v[1][f], v[2][f]]).collect();
                        // each input's quaternion sign-aligned along time (the
                        // first frame's to the first input's), so mixes of
                        // them are continuous in time
                        let q0 = rotation::from_euler(j.axes, eul[0]);
                        let qs: Vec<_> = eul
                            .iter()
                            .enumerate()
                            .map(|(k, e)| {
                                let q = rotation::from_euler(j.axes, *e);
                                rotation::align_sign(prev_q.get(k).unwrap_or(&q0), &q)
                            })
                            .collect();
                        prev_q = qs.clone();
                        if let Some(k) = mixer.pick(t)? {
                            for c in 0..3 {
                                out[c].push(eul[k][c]);
                            }
                            prev = Some(eul[k]);
                            continue;
                        }
                        let q = mixer.rot(gi, t, &qs)?;
                        let w = mixer.weights(t)?;
                        let near: [f64; 3] = std::array::from_fn(|c| match prev {
                            None => eul.iter().zip(&w).map(|(e, w)| w * e[c]).sum(),
                            Some(p) => {
                                p[c] + vals
                                    .iter()
                                    .zip(&w)
                                    .map(|(v, w)| w * (v[c][f] - v[c][f - 1]))
                                    .sum::<f64>()
                            }
                        });
                        let e = rotation::to_euler_near(j.axes, &q, near);
                        for c in 0..3 {
                            out[c].push(e[c]);
                        }
                        prev = Some(e);
                    }
                }
            }
            for (c, n) in names.iter().enumerate() {
                let i = sampled(&times, std::mem::take(&mut out[c]))?;
                mixed.entry(n.to_string()).or_default().push(i);
            }
        }
    }
    let mut result = Mu::new();
    for (name, dof) in &keep.dofs {
        let out = match mixed.get(name) {
            Some(ivs) => {
                let region = Dof {
                    intervals: ivs
                        .iter()
                        .map(|i| Interval::constant(0.0, i.start, i.stop))
                        .collect::<Result<_, _>>()?,
                };
                dof.minus(&region).plus(&Dof::new(ivs.clone())?)
            }
            None => dof.clone(),
        };
        result.insert(name.clone(), out);
    }
    Ok(result)
}

struct BlendMix<'a> {
    w: &'a Weight,
}

impl Mixer for BlendMix<'_> {
    fn weights(&self, t: f64) -> Result<Vec<f64>, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(vec![1.0 - w, w])
    }
    fn pick(&self, t: f64) -> Result<Option<usize>, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(if w == 0.0 {
            Some(0)
        } else if w == 1.0 {
            Some(1)
        } else {
            None
        })
    }
    fn rot(
        &self,
        _: usize,
        t: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(if w == 0.0 {
            qs[0]
        } else if w == 1.0 {
            qs[1]
        } else {
            rotation::slerp_signed(&qs[0], &qs[1], w)
        })
    }
    fn whole(&self, same: bool) -> Option<usize> {
        match self.w {
            _ if same => Some(0),
            Weight::Const(w) if *w == 0.0 => Some(0),
            Weight::Const(w) if *w == 1.0 => Some(1),
            _ => None,
        }
    }
    fn scalar(&self, _: usize, t: f64, xs: &[f64]) -> Result<f64, MotionError> {
        let w = self.w.at("blend", t)?;
        Ok(if w == 1.0 {
            xs[1]
        } else {
            xs[0] + w * (xs[1] - xs[0])
        })
    }
}

/// `blend(a, b, w)`: where both define a DOF, a mixed toward b by w (joint
/// rotations slerped, other DOFs linear); where only one does, that one.
/// `Err` when a and b have no DOF in common or w leaves [0, 1].
pub fn blend(a: &Mu, b: &Mu, w: &Weight) -> Result<Mu, MotionError> {
    blend_dt(a, b, w, native_dt(&[a, b]))
}

fn blend_dt(a: &Mu, b: &Mu, w: &Weight, dt: f64) -> Result<Mu, MotionError> {
    if !a.names().any(|n| b.get(n).is_some()) {
        let few = |m: &Mu| m.names().take(4).collect::<Vec<_>>().join(", ");
        return Err(err(
            "blend",
            format!(
                "the motions have no DOF in common (a has {}…, b has {}…)",
                few(a),
                few(b)
            ),
        ));
    }
    if let Weight::Const(x) = w {
        w.at("blend", 0.0)
            .map_err(|_| err("blend", format!("the weight must lie in [0, 1], got {x}")))?;
    }
    mix(&[a, b], &super::plus(a, b), &BlendMix { w }, dt)
}

/// The joint that carries the root: the first joint with position channels.
fn root_joint(m: &Mu) -> Option<String> {
    m.names().find_map(|n| {
        let (joint, ch) = n.rsplit_once('.')?;
        ch.to_ascii_lowercase()
            .ends_with("position")
            .then(|| joint.to_string())
    })
}

/// The ground plane of an up axis: (horizontal axis 1, horizontal axis 2).
fn ground(up: usize) -> (usize, usize) {
    match up {
        1 => (2, 0), // y-up: z, x
        2 => (0, 1), // z-up: x, y
        _ => (1, 2),
    }
}

fn axis_char(a: usize) -> char {
    ['X', 'Y', 'Z'][a]
}

/// The heading of `q` about the `up` axis (the angle of its twist about up).
fn heading(q: &UnitQuaternion<f64>, up: usize) -> f64 {
    let v = q.vector();
    2.0 * v[up].atan2(q.scalar())
}

/// The root of `m`: its position DOF names (x, y, z; `None` where absent)
/// and its Euler joint.
struct Root {
    pos: [Option<String>; 3],
    rot: Option<EulerJoint>,
}

fn root_of(m: &Mu) -> Option<Root> {
    let joint = root_joint(m)?;
    let pos = std::array::from_fn(|a| {
        let want = format!("{joint}.{}position", axis_char(a));
        m.names()
            .find(|n| n.eq_ignore_ascii_case(&want))
            .map(str::to_string)
    });
    let rot = rotation::euler_joints(m.names())
        .into_iter()
        .find(|j| j.joint == joint);
    Some(Root { pos, rot })
}

/// The root position and rotation of `m` at `t`.
fn root_pose(m: &Mu, r: &Root, t: f64) -> Result<([f64; 3], UnitQuaternion<f64>), MotionError> {
    let val = |n: &str| -> Result<f64, MotionError> {
        m.sample_value(n, t)?.ok_or(MotionError::Undefined {
            dof: n.to_string(),
            t,
        })
    };
    let mut p = [0.0; 3];
    for (pa, name) in p.iter_mut().zip(&r.pos) {
        if let Some(n) = name {
            *pa = val(n)?;
        }
    }
    let q = match &r.rot {
        Some(j) => rotation::from_euler(
            j.axes,
            [val(&j.dofs[0])?, val(&j.dofs[1])?, val(&j.dofs[2])?],
        ),
        None => UnitQuaternion::identity(),
    };
    Ok((p, q))
}

/// `align(a, b)` with the pose of a at `t_a` as the target: b moved rigidly
/// in the ground plane (rotated about `up`, 0 = x, 1 = y, 2 = z, and
/// translated) so its first root position and heading equal a's at `t_a`.
pub fn align_at(a: &Mu, t_a: f64, b: &Mu, up: usize) -> Result<Mu, MotionError> {
    let ra = root_of(a)
        .ok_or_else(|| err("align", "a has no root position DOFs (`Joint.Xposition` …)"))?;
    let rb = root_of(b)
        .ok_or_else(|| err("align", "b has no root position DOFs (`Joint.Xposition` …)"))?;
    let (h1, h2) = ground(up);
    for (r, which) in [(&ra, "a"), (&rb, "b")] {
        if r.pos[h1].is_none() || r.pos[h2].is_none() {
            return Err(err(
                "align",
                format!(
                    "{which}'s root has no {} and {} position channels to move in the ground plane",
                    axis_char(h1),
                    axis_char(h2)
                ),
            ));
        }
    }
    let Some((b0, _)) = b.span() else {
        return Err(MotionError::EmptyMotion { op: "align" });
    };
    let (pa, qa) = root_pose(a, &ra, t_a)?;
    let (pb, qb) = root_pose(b, &rb, b0)?;
    let dpsi = if ra.rot.is_some() && rb.rot.is_some() {
        heading(&qa, up) - heading(&qb, up)
    } else {
        0.0
    };
    let turn = UnitQuaternion::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::from_fn(|i, _| if i == up { 1.0 } else { 0.0 })),
        dpsi,
    );
    let dt = native_dt(&[b]);
    let mut out = b.clone();
    // Root positions: p' = turn·(p − p_b0) + p_a in the ground plane.
    let (n1, n2) = (
        rb.pos[h1].clone().unwrap_or_default(),
        rb.pos[h2].clone().unwrap_or_default(),
    );
    for (s, e) in common_spans(&[&b.dofs[&n1], &b.dofs[&n2]]) {
        let times = grid(s, e, dt);
        let x1 = b.dofs[&n1].sample_values_sorted(&n1, &times)?;
        let x2 = b.dofs[&n2].sample_values_sorted(&n2, &times)?;
        let (mut o1, mut o2) = (vec![], vec![]);
        for (v1, v2) in x1.into_iter().zip(x2) {
            let mut d = Vector3::zeros();
            d[h1] = v1.unwrap_or(0.0) - pb[h1];
            d[h2] = v2.unwrap_or(0.0) - pb[h2];
            let r = turn * d;
            o1.push(r[h1] + pa[h1]);
            o2.push(r[h2] + pa[h2]);
        }
        replace_span(&mut out, &n1, sampled(&times, o1)?)?;
        replace_span(&mut out, &n2, sampled(&times, o2)?)?;
    }
    if let (Some(j), true) = (&rb.rot, dpsi != 0.0) {
        let dofs: Vec<&Dof> = j.dofs.iter().map(|n| &b.dofs[n]).collect();
        for (s, e) in common_spans(&dofs) {
            let times = grid(s, e, dt);
            let ch: Vec<Vec<Option<f64>>> = j
                .dofs
                .iter()
                .map(|n| b.dofs[n].sample_values_sorted(n, &times))
                .collect::<Result<_, _>>()?;
            let mut o = [vec![], vec![], vec![]];
            let mut prev: Option<[f64; 3]> = None;
            for f in 0..times.len() {
                let e: [f64; 3] = std::array::from_fn(|c| ch[c][f].unwrap_or(0.0));
                let near = match prev {
                    None => e,
                    Some(p) => std::array::from_fn(|c| p[c] + e[c] - ch[c][f - 1].unwrap_or(0.0)),
                };
                let x = rotation::to_euler_near(
                    j.axes,
                    &(turn * rotation::from_euler(j.axes, e)),
                    near,
                );
                for c in 0..3 {
                    o[c].push(x[c]);
                }
                prev = Some(x);
            }
            for (c, n) in j.dofs.iter().enumerate() {
                replace_span(&mut out, n, sampled(&times, std::mem::take(&mut o[c]))?)?;
            }
        }
    }
    Ok(out)
}

/// `m`'s DOF `name` with the span of `i` replaced by `i`.
fn replace_span(m: &mut Mu, name: &str, i: Interval) -> Result<(), MotionError> {
    let region = Dof::from(Interval::constant(0.0, i.start, i.stop)?);
    if let Some(d) = m.dofs.get_mut(name) {
        *d = d.minus(&region).plus(&Dof::from(i));
    }
    Ok(())
}

/// `align(a, b)`: b moved rigidly in the ground plane so that its first root
/// position and heading equal a's last.
pub fn align(a: &Mu, b: &Mu, up: usize) -> Result<Mu, MotionError> {
    let Some((_, a1)) = a.span() else {
        return Err(MotionError::EmptyMotion { op: "align" });
    };
    align_at(a, a1, b, up)
}

/// The smoothstep 3s² − 2s³ from 0 at `t0` to 1 at `t1`, as a weight.
#[derive(Debug)]
struct Smoothstep {
    t0: f64,
    t1: f64,
}

impl TimeFunction for Smoothstep {
    fn eval(&self, t: f64) -> Result<f64, String> {
        let s = ((t - self.t0) / (self.t1 - self.t0)).clamp(0.0, 1.0);
        Ok(s * s * (3.0 - 2.0 * s))
    }
}

/// `crossfade(a, b, d)`: b aligned to a's root pose at a's end minus d,
/// started there, and blended from a to b over the overlap with a smoothstep
/// weight (zero slope at both ends, so value and velocity are continuous).
pub fn crossfade(a: &Mu, b: &Mu, d: f64, up: usize) -> Result<Mu, MotionError> {
    let (Some((a0, a1)), Some((b0, b1))) = (a.span(), b.span()) else {
        return Err(MotionError::EmptyMotion { op: "crossfade" });
    };
    if !(d.is_finite() && d > 0.0 && d <= (a1 - a0).min(b1 - b0)) {
        return Err(err(
            "crossfade",
            format!(
                "the overlap d must be positive and no longer than either motion ({} s and {} s), got {d}",
                a1 - a0,
                b1 - b0
            ),
        ));
    }
    let t0 = a1 - d;
    let shifted = super::affine(t0 - b0, 1.0, b)?;
    let aligned = align_at(a, t0, &shifted, up)?;
    let w = Weight::Func(Arc::new(Smoothstep { t0, t1: a1 }));
    blend_dt(a, &aligned, &w, native_dt(&[a, b]))
}

struct LayerMix {
    w: f64,
    refs: Vec<Vec<f64>>,
    axes: Vec<Option<[usize; 3]>>,
}

impl Mixer for LayerMix {
    fn weights(&self, _: f64) -> Result<Vec<f64>, MotionError> {
        Ok(vec![1.0, self.w])
    }
    fn rot(
        &self,
        g: usize,
        _: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError> {
        let r = &self.refs[g];
        let axes = self.axes[g].unwrap_or([0, 1, 2]);
        let q_ref = rotation::from_euler(axes, [r[0], r[1], r[2]]);
        let d = q_ref.inverse() * qs[1];
        let d = rotation::align_sign(&UnitQuaternion::identity(), &d);
        Ok(qs[0] * rotation::pow_signed(&d, self.w))
    }
    fn scalar(&self, g: usize, _: f64, xs: &[f64]) -> Result<f64, MotionError> {
        Ok(xs[0] + self.w * (xs[1] - self.refs[g][0]))
    }
    fn whole(&self, _: bool) -> Option<usize> {
        (self.w == 0.0).then_some(0)
    }
}

/// The values of every group of `names` in `m` at `t` (Euler triples or one value).
fn group_values(
    m: &Mu,
    gs: &[Group],
    t: f64,
    op: &'static str,
) -> Result<Vec<Vec<f64>>, MotionError> {
    gs.iter()
        .map(|g| {
            g.names()
                .iter()
                .map(|n| {
                    m.get(n)
                        .map(|d| d.sample(n, t))
                        .transpose()?
                        .flatten()
                        .map(|v| v[0])
                        .ok_or_else(|| {
                            err(
                                op,
                                format!("the reference pose has no value for `{n}` at t = {t}"),
                            )
                        })
                })
                .collect()
        })
        .collect()
}

/// The Euler axes of each rotation group (`None` for scalars).
fn group_axes(gs: &[Group]) -> Vec<Option<[usize; 3]>> {
    gs.iter()
        .map(|g| match g {
            Group::Rot(j) => Some(j.axes),
            Group::Scalar(_) => None,
        })
        .collect()
}

/// `layer(base, delta, w, reference)`: additive animation. Each joint's
/// rotation becomes base · (ref⁻¹·delta)^w and each scalar base + w·(delta −
/// ref), where ref is `reference`'s first frame (default: delta's first frame).
pub fn layer(base: &Mu, delta: &Mu, w: f64, reference: Option<&Mu>) -> Result<Mu, MotionError> {
    Weight::Const(w).at("layer", 0.0)?;
    let common: Vec<&str> = base.names().filter(|n| delta.get(n).is_some()).collect();
    if common.is_empty() {
        return Err(err("layer", "the base and the delta have no DOF in common"));
    }
    let reference = reference.unwrap_or(delta);
    let Some((r0, _)) = reference.span() else {
        return Err(MotionError::EmptyMotion { op: "layer" });
    };
    let gs = groups(&common);
    let refs = group_values(reference, &gs, r0, "layer")?;
    let axes = group_axes(&gs);
    mix(
        &[base, delta],
        base,
        &LayerMix { w, refs, axes },
        native_dt(&[base, delta]),
    )
}

struct MaskMix {
    w: f64,
    refs: Vec<Vec<f64>>,
    axes: Vec<Option<[usize; 3]>>,
}

impl Mixer for MaskMix {
    fn weights(&self, _: f64) -> Result<Vec<f64>, MotionError> {
        Ok(vec![self.w])
    }
    fn rot(
        &self,
        g: usize,
        _: f64,
        qs: &[UnitQuaternion<f64>],
    ) -> Result<UnitQuaternion<f64>, MotionError> {
        let r = &self.refs[g];
        let q_ref = rotation::from_euler(self.axes[g].unwrap_or([0, 1, 2]), [r[0], r[1], r[2]]);
        Ok(rotation::slerp(&q_ref, &qs[0], self.w))
    }
    fn scalar(&self, g: usize, _: f64, xs: &[f64]) -> Result<f64, MotionError> {
        Ok(self.refs[g][0] + self.w * (xs[0] - self.refs[g][0]))
    }
    fn whole(&self, _: bool) -> Option<usize> {
        (self.w == 1.0).then_some(0)
    }
}

/// `mask(m, patterns, w)`: the DOFs matching `patterns` with their motion
/// away from the reference pose (m's first frame) scaled by w (w = 1: m,
/// w = 0: held at the reference); the other DOFs unchanged.
pub fn mask(m: &Mu, patterns: &[&str], w: f64) -> Result<Mu, MotionError> {
    Weight::Const(w).at("mask", 0.0)?;
    let picked = super::only(m, patterns)?;
    let Some((t0, _)) = picked.span() else {
        return Err(MotionError::EmptyMotion { op: "mask" });
    };
    let gs = groups(&picked.names().collect::<Vec<_>>());
    let refs = group_values(&picked, &gs, t0, "mask")?;
    let axes = group_axes(&gs);
    let scaled = mix(
        &[&picked],
        &picked,
        &MaskMix { w, refs, axes },
        native_dt(&[m]),
    )?;
    let mut out = m.clone();
    for (n, d) in scaled.dofs {
        out.insert(n, d);
    }
    Ok(out)
}

/// The name of the other side's joint (`LeftArm` ↔ `RightArm`, `Arm_L` ↔
/// `Arm_R`, `LArm` ↔ `RArm`, `arm.l` ↔ `arm.r`), the conventions
/// `mocap::segments::side` recognises; `None` for a name with no side.
pub fn mirror_name(joint: &str) -> Option<String> {
    for (l, r) in [("Left", "Right"), ("left", "right"), ("LEFT", "RIGHT")] {
        if joint.contains(l) {
            return Some(joint.replacen(l, r, 1));
        }
        if joint.contains(r) {
            return Some(joint.replacen(r, l, 1));
        }
    }
    for (l, r) in [("_L", "_R"), ("_l", "_r"), (".L", ".R"), (".l", ".r")] {
        if let Some(stem) = joint.strip_suffix(l) {
            return Some(format!("{stem}{r}"));
        }
        if let Some(stem) = joint.strip_suffix(r) {
            return Some(format!("{stem}{l}"));
        }
    }
    let b = joint.as_bytes();
    if b.len() > 1 && b[1].is_ascii_uppercase() {
        match b[0] {
            b'L' => return Some(format!("R{}", &joint[1..])),
            b'R' => return Some(format!("L{}", &joint[1..])),
            _ => {}
        }
    }
    None
}

/// The DOF name after mirroring: the joint part swapped by side.
fn mirror_dof(name: &str) -> Option<String> {
    let (joint, ch) = name.rsplit_once('.')?;
    Some(format!("{}.{ch}", mirror_name(joint)?))
}

/// `d` with every value negated (exact: curves are negated, not resampled).
fn negate(d: &Dof) -> Result<Dof, MotionError> {
    let intervals = d
        .intervals
        .iter()
        .map(|i| {
            let funcs = i
                .funcs
                .iter()
                .map(|f| {
                    let curve = match f.curve.as_ref() {
                        Curve::Constant(v) => Curve::Constant(-v),
                        Curve::Samples(s) => Curve::Samples(SampledCurve::new(
                            s.t0(),
                            s.dt(),
                            s.values().iter().map(|v| -v).collect(),
                        )?),
                        Curve::Hermite(h) => Curve::Hermite(super::curve::HermiteCurve {
                            q0: -h.q0,
                            v0: -h.v0,
                            q1: -h.q1,
                            v1: -h.v1,
                            ..h.clone()
                        }),
                        Curve::Spline(c) => {
                            let mut c = c.clone();
                            c.coeffs.iter_mut().for_each(|v| *v = -*v);
                            Curve::Spline(c)
                        }
                        Curve::Function(g) => Curve::Function(Arc::new(Negated(g.clone()))),
                    };
                    Ok(Func {
                        curve: Arc::new(curve),
                        shift: f.shift,
                        scale: f.scale,
                        offset: -f.offset,
                    })
                })
                .collect::<Result<_, MotionError>>()?;
            Ok(Interval {
                start: i.start,
                stop: i.stop,
                funcs,
            })
        })
        .collect::<Result<_, MotionError>>()?;
    Ok(Dof { intervals })
}

#[derive(Debug)]
struct Negated(Arc<dyn TimeFunction>);

impl TimeFunction for Negated {
    fn eval(&self, t: f64) -> Result<f64, String> {
        self.0.eval(t).map(|v| -v)
    }
}

/// `mirror(m, axis)`: left and right swapped by name and the motion reflected
/// in the plane normal to `axis` (0 = x, 1 = y, 2 = z): positions along the
/// axis and rotations about the two other axes change sign. Exact, and its
/// own inverse. `Err` when no DOF name has a side.
pub fn mirror(m: &Mu, axis: usize) -> Result<Mu, MotionError> {
    if !m.names().any(|n| mirror_dof(n).is_some()) {
        let few: Vec<&str> = m.names().take(4).collect();
        return Err(err(
            "mirror",
            format!(
                "no DOF name has a side to swap (names like `LeftArm.Xrotation`, `Arm_L.…`, `LArm.…`; this motion has {}…)",
                few.join(", ")
            ),
        ));
    }
    let mut out = Mu::new();
    for name in m.names() {
        let target = mirror_dof(name)
            .filter(|n| m.get(n).is_some())
            .unwrap_or_else(|| name.to_string());
        let src = &m.dofs[target.as_str()];
        let ch = name.rsplit('.').next().unwrap_or("").to_ascii_lowercase();
        let flip = if let Some(a) = rotation::rotation_axis(name) {
            a != axis
        } else {
            ch == format!("{}position", ['x', 'y', 'z'][axis])
        };
        out.insert(
            name.to_string(),
            if flip { negate(src)? } else { src.clone() },
        );
    }
    Ok(out)
}

/// A function of time played backwards about `pivot`: t ↦ f(pivot − t).
#[derive(Debug)]
struct Reversed {
    func: Func,
    pivot: f64,
}

impl TimeFunction for Reversed {
    fn eval(&self, t: f64) -> Result<f64, String> {
        self.func.value(self.pivot - t).map_err(|e| e.to_string())
    }
}

/// `reverse(m)`: time reversal over m's own span (t ↦ start + stop − t), so
/// velocities change sign. Sampled data is reversed exactly (the spline
/// through reversed samples is the reversed spline); other curves are
/// evaluated backwards. Its own inverse.
pub fn reverse(m: &Mu) -> Result<Mu, MotionError> {
    let Some((s, e)) = m.span() else {
        return Err(MotionError::EmptyMotion { op: "reverse" });
    };
    let pivot = s + e;
    map_intervals(m, |_, i| {
        let (a, b) = (pivot - i.stop, pivot - i.start);
        let funcs = i
            .funcs
            .iter()
            .map(|f| match f.curve.as_ref() {
                Curve::Constant(_) => Ok(f.clone()),
                Curve::Samples(c) if f.scale == 1.0 => {
                    // local time u = t − shift; reversed local time starts at pivot − shift − t_end
                    let mut v = c.values().to_vec();
                    v.reverse();
                    let t0 = pivot - 2.0 * f.shift - c.t_end();
                    Ok(Func {
                        curve: Arc::new(Curve::samples(t0, c.dt(), v)?),
                        shift: f.shift,
                        scale: 1.0,
                        offset: f.offset,
                    })
                }
                _ => Ok(Func::new(Curve::Function(Arc::new(Reversed {
                    func: f.clone(),
                    pivot,
                })))),
            })
            .collect::<Result<Vec<_>, MotionError>>()?;
        Ok(Some(Interval {
            start: a,
            stop: b,
            funcs,
        }))
    })
}

/// `m` with every interval of every DOF (named) mapped by `f`, or dropped
/// where `f` gives `None`; the results sorted by time.
fn map_intervals(
    m: &Mu,
    mut f: impl FnMut(&str, &Interval) -> Result<Option<Interval>, MotionError>,
) -> Result<Mu, MotionError> {
    let mut out = Mu::new();
    for (name, d) in &m.dofs {
        let mut intervals = vec![];
        for i in &d.intervals {
            if let Some(x) = f(name, i)? {
                intervals.push(x);
            }
        }
        intervals.sort_by(|x, y| x.start.total_cmp(&y.start));
        out.insert(name.clone(), Dof { intervals });
    }
    Ok(out)
}

/// A motion's function seen through a time warp: t ↦ func(f(t)).
#[derive(Debug)]
struct Warped {
    func: Func,
    f: Arc<dyn TimeFunction>,
}

impl TimeFunction for Warped {
    fn eval(&self, t: f64) -> Result<f64, String> {
        let u = self.f.eval(t)?;
        self.func.value(u).map_err(|e| e.to_string())
    }
}

fn call(f: &dyn TimeFunction, t: f64) -> Result<f64, MotionError> {
    match f.eval(t) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(v) => Err(err(
            "warp",
            format!("the warp returned {v} at t = {t}, not a finite number"),
        )),
        Err(message) => Err(MotionError::Function {
            t,
            message,
            dof: None,
        }),
    }
}

/// The time t in [lo, hi] with f(t) = target (f increasing there), by bisection.
fn invert(f: &dyn TimeFunction, target: f64, mut lo: f64, mut hi: f64) -> Result<f64, MotionError> {
    // exact where f fixes the target (the identity warp keeps m's span)
    if (lo..=hi).contains(&target) && call(f, target)? == target {
        return Ok(target);
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if call(f, mid)? < target {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= time_tol(hi) * 1e-3 {
            break;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// `warp(m, f)`: m played on the clock f, out(t) = m(f(t)), for f strictly
/// increasing. The result is defined where f(t) falls in m's span; f is
/// checked on a grid of m's sample step over that domain, and where it is not
/// increasing the error names the time.
pub fn warp(m: &Mu, f: Arc<dyn TimeFunction>) -> Result<Mu, MotionError> {
    let Some((s, e)) = m.span() else {
        return Err(MotionError::EmptyMotion { op: "warp" });
    };
    // Bracket the domain [f⁻¹(s), f⁻¹(e)], starting from m's span.
    let (mut lo, mut hi) = (s, e);
    let width = (e - s).max(1.0);
    let mut grow = width;
    for _ in 0..60 {
        let (flo, fhi) = (call(f.as_ref(), lo)?, call(f.as_ref(), hi)?);
        if flo <= s && fhi >= e {
            break;
        }
        if flo > s {
            lo -= grow;
        }
        if fhi < e {
            hi += grow;
        }
        grow *= 2.0;
    }
    if call(f.as_ref(), lo)? > s || call(f.as_ref(), hi)? < e {
        return Err(err(
            "warp",
            format!(
                "the warp never reaches m's span [{s}, {e}] (f({lo}) = {}, f({hi}) = {})",
                call(f.as_ref(), lo)?,
                call(f.as_ref(), hi)?
            ),
        ));
    }
    let d0 = invert(f.as_ref(), s, lo, hi)?;
    let d1 = invert(f.as_ref(), e, lo, hi)?;
    let times = grid(d0, d1, native_dt(&[m]) / 4.0);
    let mut prev = call(f.as_ref(), times[0])?;
    for w in times.windows(2) {
        let v = call(f.as_ref(), w[1])?;
        if v <= prev {
            return Err(err(
                "warp",
                format!(
                    "the warp must be strictly increasing, but f({}) = {prev} and f({}) = {v}",
                    w[0], w[1]
                ),
            ));
        }
        prev = v;
    }
    map_intervals(m, |_, i| {
        let a = if (i.start - s).abs() <= time_tol(s) {
            d0
        } else {
            invert(f.as_ref(), i.start, d0, d1)?
        };
        let b = if (i.stop - e).abs() <= time_tol(e) {
            d1
        } else {
            invert(f.as_ref(), i.stop, d0, d1)?
        };
        if b - a <= time_tol(a) {
            return Ok(None);
        }
        let funcs = i
            .funcs
            .iter()
            .map(|func| {
                Func::new(Curve::Function(Arc::new(Warped {
                    func: func.clone(),
                    f: f.clone(),
                })))
            })
            .collect();
        Ok(Some(Interval {
            start: a,
            stop: b,
            funcs,
        }))
    })
}

/// `resample(m, rate)`: every interval of every DOF sampled at `rate` Hz on
/// its own span and replaced by the C² spline through the samples.
pub fn resample(m: &Mu, rate: f64) -> Result<Mu, MotionError> {
    if !(rate.is_finite() && rate > 0.0) {
        return Err(MotionError::BadRate { rate });
    }
    map_intervals(m, |name, i| {
        let times = grid(i.start, i.stop, 1.0 / rate);
        if times.len() > 50_000_000 {
            return Err(MotionError::TooManySamples {
                span: i.stop - i.start,
                rate,
                rows: times.len() as f64,
            });
        }
        if i.is_conflict() {
            return Err(MotionError::Conflict {
                dof: name.to_string(),
                start: i.start,
                stop: i.stop,
                t: i.start,
            });
        }
        let f = i.first_func()?;
        let v = times
            .iter()
            .map(|&t| f.value(t))
            .collect::<Result<Vec<f64>, _>>()?;
        Ok(Some(sampled(&times, v)?))
    })
}
