//! `fit`: converts a clip to the 44-DOF model by per-frame least squares on
//! joint positions and segment orientations (Rose 1996 §2, "per-frame least
//! squares on joint angles and positions").
//!
//! Each frame minimises
//!   Σ_k ‖p_k(q) − p̂_k‖² + w² Σ_s ‖log((R̂_s C_s)ᵀ R_s(q))‖² + d ‖q − q_prev‖²
//! over the landmarks k and the segments s the model shares with the clip:
//! `R_s` is the model link's world rotation, `R̂_s` the clip joint's, and
//! `C_s` the constant rotation between the two skeletons' frames of the same
//! bone (they are drawn differently: the Bandai rest pose is not a T-pose).
//! `w` (metres per radian) makes an angle comparable with a distance.
//!
//! `C_s` is itself a least-squares estimate: a first pass fits positions
//! only, `C_s` is the rotation nearest to the mean of `R̂_sᵀ R_s` over its
//! frames (chordal mean), then the second pass fits both. Hinge knees and
//! elbows and 2-DOF ankles and wrists cannot follow all three angles of the
//! clip's joint: least squares takes the nearest pose.
//!
//! Levenberg–Marquardt, warm-started from the previous frame, with the
//! analytic Jacobian of forward kinematics (each coordinate's world twist).
//! The small damping `d` towards the previous frame keeps DOFs that no
//! residual sees (none once orientations count) from drifting.

use super::{Human, Target};
use crate::lie::{Se3, left_jacobian_inv_so3, log_so3};
use crate::mocap::MocapError;
use crate::mocap::bvh::{self, BvhFile};
use crate::model::Model;
use crate::model::joint::{Derivatives, JointKinematics};
use crate::motion::{Curve, Dof, Interval, Mu};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use std::fmt;

/// How `fit` weighs its residuals.
#[derive(Clone, Copy, Debug)]
pub struct FitOptions {
    /// Metres that one radian of segment orientation error counts as;
    /// 0 fits positions only.
    pub angle_weight: f64,
}

impl Default for FitOptions {
    /// 0.1 m/rad: 10° of orientation error weighs like 1.7 cm of position.
    fn default() -> Self {
        FitOptions { angle_weight: 0.1 }
    }
}

/// How well a fit matches the clip (SI units inside; `Display` prints cm
/// and degrees).
#[derive(Clone, Debug)]
pub struct FitReport {
    /// RMS landmark distance over all frames and landmarks (m).
    pub rms: f64,
    /// Largest landmark distance (m).
    pub max: f64,
    /// RMS landmark distance per frame (m).
    pub per_frame: Vec<f64>,
    pub landmarks: usize,
    /// RMS segment orientation error over all frames and segments (rad).
    pub angle_rms: f64,
    /// Largest segment orientation error (rad).
    pub angle_max: f64,
    /// Segments whose orientation is compared.
    pub segments: usize,
    /// The weight used (m/rad).
    pub angle_weight: f64,
}

impl fmt::Display for FitReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "RMS error {:.2} cm (max {:.2} cm) over {} landmark positions, {:.1}° (max {:.1}°) over {} segment orientations",
            self.rms * 100.0,
            self.max * 100.0,
            self.landmarks,
            self.angle_rms.to_degrees(),
            self.angle_max.to_degrees(),
            self.segments
        )
    }
}

/// What one frame is fitted to.
struct Frame {
    points: Vec<Vector3<f64>>,
    /// Clip joint world rotation times the calibration `C_s`, per segment.
    rotations: Vec<Matrix3<f64>>,
}

/// The least-squares problem of one model against one clip.
struct Problem<'a> {
    model: &'a Model,
    /// Model link of each position target.
    point_links: Vec<usize>,
    /// (model link, clip joint) of each orientation target.
    segments: Vec<(usize, usize)>,
    /// For each link: the coordinates that move it (its own and its
    /// ancestors'), so Jacobian columns are only filled where nonzero.
    moved_by: Vec<Vec<usize>>,
}

/// World poses and, per coordinate, its world twist (ω, v): the velocity
/// of a point p fixed to any link it moves is `v + ω × p`.
struct Kinematics {
    poses: Vec<Se3>,
    omega: Vec<Vector3<f64>>,
    vel: Vec<Vector3<f64>>,
    jk: JointKinematics,
}

impl<'a> Problem<'a> {
    fn new(h: &'a Human) -> Self {
        let model = &h.model;
        let mut moved_by: Vec<Vec<usize>> = Vec::with_capacity(model.num_links());
        for l in model.links() {
            let mut v = l.parent.map(|p| moved_by[p].clone()).unwrap_or_default();
            v.extend(l.q_index..l.q_index + l.dof);
            moved_by.push(v);
        }
        let point_links = h.targets.iter().map(|(l, _)| *l).collect();
        // A segment's orientation is the clip joint's frame; End Sites have none.
        let segments = h
            .targets
            .iter()
            .filter_map(|(l, t)| match t {
                Target::Joint(j) => Some((*l, *j)),
                Target::EndSite(_) => None,
            })
            .collect();
        Problem {
            model,
            point_links,
            segments,
            moved_by,
        }
    }

    fn rows(&self, with_angles: bool) -> usize {
        3 * self.point_links.len()
            + if with_angles {
                3 * self.segments.len()
            } else {
                0
            }
    }

    /// Forward kinematics, with the coordinates' world twists when `twists`.
    fn kinematics(&self, q: &[f64], twists: bool, k: &mut Kinematics) {
        let want = if twists {
            Derivatives::Jacobian
        } else {
            Derivatives::Transform
        };
        k.poses.clear();
        for l in self.model.links() {
            l.joint
                .kinematics(&q[l.q_index..l.q_index + l.dof], want, &mut k.jk);
            let local = l.offset.compose(&k.jk.transform);
            let pose = match l.parent {
                Some(p) => k.poses[p].compose(&local),
                None => local,
            };
            if twists {
                for c in 0..l.dof {
                    let s = k.jk.s[c];
                    let w = pose.r * Vector3::new(s[0], s[1], s[2]);
                    k.omega[l.q_index + c] = w;
                    k.vel[l.q_index + c] =
                        pose.r * Vector3::new(s[3], s[4], s[5]) + pose.p.cross(&w);
                }
            }
            k.poses.push(pose);
        }
    }

    /// Residuals (and the Jacobian when `jac` is given) at the poses in `k`.
    /// Orientation rows are present when `w > 0`.
    fn residuals(
        &self,
        k: &Kinematics,
        frame: &Frame,
        w: f64,
        r: &mut DVector<f64>,
        mut jac: Option<&mut DMatrix<f64>>,
    ) {
        if let Some(j) = jac.as_deref_mut() {
            j.fill(0.0);
        }
        for (i, &link) in self.point_links.iter().enumerate() {
            let p = k.poses[link].p;
            r.fixed_rows_mut::<3>(3 * i)
                .copy_from(&(p - frame.points[i]));
            if let Some(j) = jac.as_deref_mut() {
                for &c in &self.moved_by[link] {
                    let d = k.vel[c] + k.omega[c].cross(&p);
                    j.fixed_view_mut::<3, 1>(3 * i, c).copy_from(&d);
                }
            }
        }
        if w <= 0.0 {
            return;
        }
        let base = 3 * self.point_links.len();
        for (i, &(link, _)) in self.segments.iter().enumerate() {
            let rm = &k.poses[link].r;
            let e = log_so3(&(frame.rotations[i].transpose() * rm));
            r.fixed_rows_mut::<3>(base + 3 * i).copy_from(&(e * w));
            if let Some(j) = jac.as_deref_mut() {
                // Turning coordinate c by dq turns the link by R_mᵀ ω_c dq in
                // its own frame; the log moves by J_r⁻¹(e) of that.
                let m = left_jacobian_inv_so3(&(-e)) * rm.transpose() * w;
                for &c in &self.moved_by[link] {
                    let d = m * k.omega[c];
                    j.fixed_view_mut::<3, 1>(base + 3 * i, c).copy_from(&d);
                }
            }
        }
    }
}

/// Per-frame solver state, reused across frames so nothing is reallocated.
struct Solver<'a> {
    p: &'a Problem<'a>,
    k: Kinematics,
    w: f64,
    r: DVector<f64>,
    jac: DMatrix<f64>,
}

impl<'a> Solver<'a> {
    fn new(p: &'a Problem<'a>, w: f64) -> Self {
        let nq = p.model.nq();
        let rows = p.rows(w > 0.0);
        Solver {
            p,
            k: Kinematics {
                poses: Vec::with_capacity(p.model.num_links()),
                omega: vec![Vector3::zeros(); nq],
                vel: vec![Vector3::zeros(); nq],
                jk: JointKinematics::default(),
            },
            w,
            r: DVector::zeros(rows),
            jac: DMatrix::zeros(rows, nq),
        }
    }

    fn cost(&mut self, q: &DVector<f64>, frame: &Frame) -> f64 {
        self.p.kinematics(q.as_slice(), false, &mut self.k);
        self.p.residuals(&self.k, frame, self.w, &mut self.r, None);
        self.r.norm_squared()
    }

    /// Levenberg–Marquardt from `q` (updated in place), damped towards `prev`
    /// by `damp`.
    fn solve(
        &mut self,
        q: &mut DVector<f64>,
        prev: &DVector<f64>,
        frame: &Frame,
        iters: usize,
        damp: f64,
    ) {
        let nq = q.len();
        let mut lambda = 1e-3;
        let reg = |q: &DVector<f64>| damp * (q - prev).norm_squared();
        let mut cost = self.cost(q, frame) + reg(q);
        for _ in 0..iters {
            self.p.kinematics(q.as_slice(), true, &mut self.k);
            self.p
                .residuals(&self.k, frame, self.w, &mut self.r, Some(&mut self.jac));
            let jt = self.jac.transpose();
            let mut a = &jt * &self.jac;
            let g = &jt * &self.r + (&*q - prev) * damp;
            for i in 0..nq {
                a[(i, i)] += lambda * (1.0 + a[(i, i)]) + damp;
            }
            let Some(chol) = a.cholesky() else {
                lambda *= 10.0;
                continue;
            };
            let dq = chol.solve(&(-g));
            let qn = &*q + &dq;
            let cn = self.cost(&qn, frame) + reg(&qn);
            if cn < cost {
                *q = qn;
                let gain = cost - cn;
                cost = cn;
                lambda = (lambda * 0.3).max(1e-9);
                // A micrometre (or microradian) step, or a cost that no longer
                // moves, is converged: further digits change nothing visible.
                if dq.norm() < 1e-6 || gain < 1e-9 * cost {
                    break;
                }
            } else {
                lambda *= 10.0;
                if lambda > 1e8 {
                    break;
                }
            }
        }
    }
}

/// The rotation nearest (in the Frobenius norm) to `m`: the chordal mean of
/// the rotations summed into `m`.
fn nearest_rotation(m: &Matrix3<f64>) -> Matrix3<f64> {
    let svd = m.svd(true, true);
    let (Some(u), Some(vt)) = (svd.u, svd.v_t) else {
        return Matrix3::identity();
    };
    let mut d = Matrix3::identity();
    if (u * vt).determinant() < 0.0 {
        d[(2, 2)] = -1.0;
    }
    u * d * vt
}

/// Fits every frame in order, warm-starting each from the previous one.
/// Frame 0 starts from `start` if given, else from the pelvis position and
/// the facing of the hips.
fn sweep(
    h: &Human,
    problem: &Problem,
    frames: &[Frame],
    w: f64,
    start: Option<&DVector<f64>>,
    cancel: Option<&crate::cancel::CancelToken>,
) -> Result<Vec<DVector<f64>>, MocapError> {
    let model = &h.model;
    let mut solver = Solver::new(problem, w);
    let mut q = DVector::<f64>::zeros(model.nq());
    let mut out = Vec::with_capacity(frames.len());
    for (f, frame) in frames.iter().enumerate() {
        if let Some(c) = cancel {
            c.check()
                .map_err(|_| MocapError::invalid("fit cancelled"))?;
        }
        let prev = q.clone();
        let first = f == 0;
        if first {
            match start {
                Some(s) => q.copy_from(s),
                None => initial_guess(h, &frame.points, &mut q),
            }
        }
        let (iters, damp) = if first { (200, 0.0) } else { (30, 1e-6) };
        solver.solve(&mut q, &prev, frame, iters, damp);
        out.push(q.clone());
    }
    Ok(out)
}

/// Pelvis at the clip's hips, facing along the perpendicular of the hip line.
fn initial_guess(h: &Human, points: &[Vector3<f64>], q: &mut DVector<f64>) {
    q.fill(0.0);
    q[0] = points[0].x;
    q[1] = points[0].y;
    q[2] = points[0].z;
    let at = |name: &str| {
        h.targets
            .iter()
            .position(|(l, _)| h.model.link(*l).name == name)
    };
    if let (Some(a), Some(b)) = (at("thigh_L"), at("thigh_R")) {
        let v = points[a] - points[b];
        q[3] = (-v.z).atan2(v.x);
    }
}

/// Converts a clip to the human model: per-frame least squares on landmark
/// positions and segment orientations. Returns the motion (the model's
/// coordinates, sampled at the clip's frames) and the fit error.
pub fn fit(
    file: &BvhFile,
    metres_per_unit: f64,
    h: &Human,
    options: FitOptions,
    cancel: Option<&crate::cancel::CancelToken>,
) -> Result<(Mu, FitReport), MocapError> {
    let n = file.frame_count();
    if n == 0 {
        return Err(MocapError::invalid("the clip has no frames to fit"));
    }
    let w = options.angle_weight;
    if !(w.is_finite() && w >= 0.0) {
        return Err(MocapError::invalid_option(
            "angle_weight",
            format!("angle_weight must be a number of metres per radian ≥ 0, got {w}"),
        ));
    }
    let model = &h.model;
    let problem = Problem::new(h);
    let mut frames: Vec<Frame> = (0..n)
        .map(|f| {
            let world = bvh::fk::world_transforms(file, f, metres_per_unit);
            let points = h
                .targets
                .iter()
                .map(|(_, t)| match t {
                    Target::Joint(j) => world[*j].p,
                    Target::EndSite(j) => world[*j]
                        .act_point(&(file.skeleton.joints[*j].end_sites[0] * metres_per_unit)),
                })
                .collect();
            let rotations = problem.segments.iter().map(|(_, j)| world[*j].r).collect();
            Frame { points, rotations }
        })
        .collect();

    let mut qs = sweep(h, &problem, &frames, 0.0, None, cancel)?;
    // The calibration C_s from the positions-only fit: mean of R̂ᵀ R_model.
    let mut k = Solver::new(&problem, 0.0).k;
    let mut sums = vec![Matrix3::zeros(); problem.segments.len()];
    for (q, frame) in qs.iter().zip(&frames) {
        problem.kinematics(q.as_slice(), false, &mut k);
        for (s, &(link, _)) in problem.segments.iter().enumerate() {
            sums[s] += frame.rotations[s].transpose() * k.poses[link].r;
        }
    }
    let calibration: Vec<Matrix3<f64>> = sums.iter().map(nearest_rotation).collect();
    for frame in &mut frames {
        for (r, c) in frame.rotations.iter_mut().zip(&calibration) {
            *r *= c;
        }
    }
    if w > 0.0 && !problem.segments.is_empty() {
        let start = qs[0].clone();
        qs = sweep(h, &problem, &frames, w, Some(&start), cancel)?;
    }

    let report = measure(&problem, &qs, &frames, w);
    let mu = motion(model, &qs, file.frame_time)?;
    Ok((mu, report))
}

/// The fit's position and orientation errors.
fn measure(problem: &Problem, qs: &[DVector<f64>], frames: &[Frame], w: f64) -> FitReport {
    let mut k = Solver::new(problem, 0.0).k;
    let (np, ns) = (problem.point_links.len(), problem.segments.len());
    let (mut max, mut sumsq, mut angle_max, mut angle_sumsq) = (0.0f64, 0.0, 0.0f64, 0.0);
    let mut per_frame = Vec::with_capacity(frames.len());
    for (q, frame) in qs.iter().zip(frames) {
        problem.kinematics(q.as_slice(), false, &mut k);
        let mut frame_sq = 0.0;
        for (i, &link) in problem.point_links.iter().enumerate() {
            let d = (k.poses[link].p - frame.points[i]).norm();
            max = max.max(d);
            frame_sq += d * d;
        }
        sumsq += frame_sq;
        per_frame.push((frame_sq / np.max(1) as f64).sqrt());
        for (s, &(link, _)) in problem.segments.iter().enumerate() {
            let a = log_so3(&(frame.rotations[s].transpose() * k.poses[link].r)).norm();
            angle_max = angle_max.max(a);
            angle_sumsq += a * a;
        }
    }
    let nf = frames.len() as f64;
    FitReport {
        rms: (sumsq / (nf * np.max(1) as f64)).sqrt(),
        max,
        per_frame,
        landmarks: np,
        angle_rms: (angle_sumsq / (nf * ns.max(1) as f64)).sqrt(),
        angle_max,
        segments: ns,
        angle_weight: w,
    }
}

/// The model's coordinates as a motion sampled at the clip's frames.
fn motion(model: &Model, qs: &[DVector<f64>], dt: f64) -> Result<Mu, MocapError> {
    let frames = qs.len();
    let stop = if frames > 1 {
        (frames - 1) as f64 * dt
    } else {
        dt
    };
    let mut mu = Mu::new();
    for (c, name) in model.coordinate_names().iter().enumerate() {
        let vals: Vec<f64> = qs.iter().map(|q| q[c]).collect();
        let curve = if frames > 1 {
            Curve::samples(0.0, dt, vals)?
        } else {
            Curve::constant(vals[0])?
        };
        mu.insert(
            name.clone(),
            Dof::new(vec![Interval::curve(curve, 0.0, stop)?])?,
        );
    }
    Ok(mu)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mocap::human::human;

    fn walk() -> (BvhFile, f64, Human) {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/data/walk.bvh");
        let f = bvh::read_file(&p).unwrap();
        let s = bvh::detect_units(&f.skeleton).metres_per_unit;
        let h = human(&f.skeleton, s, 70.0).unwrap();
        (f, s, h)
    }

    /// The analytic Jacobian (positions and orientation logs) equals central
    /// differences of the residuals at a pose far from the target.
    #[test]
    fn jacobian_matches_finite_differences() {
        let (f, s, h) = walk();
        let p = Problem::new(&h);
        let world = bvh::fk::world_transforms(&f, 3, s);
        let frame = Frame {
            points: h
                .targets
                .iter()
                .map(|(_, t)| match t {
                    Target::Joint(j) | Target::EndSite(j) => world[*j].p,
                })
                .collect(),
            rotations: p.segments.iter().map(|(_, j)| world[*j].r).collect(),
        };
        let nq = h.model.nq();
        let q = DVector::from_fn(nq, |i, _| 0.3 * ((i as f64) * 1.7).sin());
        let w = 0.37;
        let mut sv = Solver::new(&p, w);
        sv.p.kinematics(q.as_slice(), true, &mut sv.k);
        let mut r = sv.r.clone();
        let mut jac = sv.jac.clone();
        p.residuals(&sv.k, &frame, w, &mut r, Some(&mut jac));
        let h_step = 1e-6;
        let mut worst: f64 = 0.0;
        for c in 0..nq {
            let mut col = DVector::zeros(r.len());
            for (sign, out) in [(1.0, 0), (-1.0, 1)] {
                let mut qc = q.clone();
                qc[c] += sign * h_step;
                sv.cost(&qc, &frame);
                if out == 0 {
                    col += &sv.r;
                } else {
                    col -= &sv.r;
                }
            }
            col /= 2.0 * h_step;
            worst = worst.max((col - jac.column(c)).amax());
        }
        assert!(worst < 1e-6, "largest Jacobian error {worst}");
    }

    #[test]
    fn nearest_rotation_recovers_a_rotation_and_averages() {
        let r = crate::lie::exp_so3(&Vector3::new(0.3, -1.1, 0.4));
        assert!((nearest_rotation(&(r * 2.5)) - r).amax() < 1e-12);
        let a = crate::lie::exp_so3(&Vector3::new(0.0, 0.2, 0.0));
        let b = crate::lie::exp_so3(&Vector3::new(0.0, -0.2, 0.0));
        assert!((nearest_rotation(&(a + b)) - Matrix3::identity()).amax() < 1e-12);
    }

    #[test]
    fn bad_weight_is_an_error() {
        let (f, s, h) = walk();
        for w in [-1.0, f64::NAN, f64::INFINITY] {
            let e = fit(&f, s, &h, FitOptions { angle_weight: w }, None).unwrap_err();
            assert!(e.to_string().contains("angle_weight"), "{e}");
        }
    }
}
