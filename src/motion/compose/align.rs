//! `align`: a motion moved rigidly in the ground plane onto another's root pose.

use nalgebra::{UnitQuaternion, Vector3};

use super::super::channel::{MotionChannels, MotionRoot};
use super::super::dof::Dof;
use super::super::error::MotionError;
use super::super::interval::Interval;
use super::super::mu::Mu;
use super::super::rotation;
use super::{common_spans, err, grid, native_dt, sampled};

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

/// The root of `m` (its position DOF names and Euler joint), as the
/// channel index finds it: the first joint with position channels.
fn root_of(m: &Mu) -> Option<MotionRoot> {
    MotionChannels::of(m).root
}

/// The root position and rotation of `m` at `t`.
fn root_pose(
    m: &Mu,
    r: &MotionRoot,
    t: f64,
) -> Result<([f64; 3], UnitQuaternion<f64>), MotionError> {
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
