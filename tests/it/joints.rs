//! Every joint type: Jacobian S, Hessian ∇S and the third-derivative term
//! ∂(Ṡ q̇)/∂q against central differences at random q, exactly at knots and
//! near the range ends (relative error ≤ 1e-7),
//! C² continuity of the curve joint across knots, and the documented errors.
// Index loops mirror the equations (several arrays per index); iterators would obscure them.
#![allow(clippy::needless_range_loop)]

use mx::lie::{Se3, Twist, exp_se3};
use mx::model::joint::{Derivatives, Joint, JointKinematics};
use mx::model::joints::*;
use mx::spline::{BSplineBasis, SimmSpline, TensorSpline};
use nalgebra::{Matrix4, Vector3};
use std::f64::consts::PI;

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn vee(x: &Matrix4<f64>) -> Twist {
    Twist::new(
        x[(2, 1)],
        x[(0, 2)],
        x[(1, 0)],
        x[(0, 3)],
        x[(1, 3)],
        x[(2, 3)],
    )
}

/// Central differences of G (→ S) and of S (→ ∇S) in coordinate `jj` with step h.
fn central(
    j: &dyn Joint,
    q: &[f64],
    jj: usize,
    h: f64,
    ginv: &Matrix4<f64>,
) -> (Twist, [Twist; 6]) {
    let (mut kp, mut km) = (JointKinematics::default(), JointKinematics::default());
    let mut qp = q.to_vec();
    let mut qm = q.to_vec();
    qp[jj] += h;
    qm[jj] -= h;
    j.kinematics(&qp, Derivatives::Jacobian, &mut kp);
    j.kinematics(&qm, Derivatives::Jacobian, &mut km);
    let dg = (kp.transform.to_matrix() - km.transform.to_matrix()) / (2.0 * h);
    let mut ds = [Twist::zeros(); 6];
    for i in 0..j.dof() {
        ds[i] = (kp.s[i] - km.s[i]) / (2.0 * h);
    }
    (vee(&(ginv * dg)), ds)
}

/// Worst relative error of S and ∇S against central differences at q.
/// At a knot (`kink`), ∇S is continuous but its derivative jumps, so the plain
/// central difference has an O(h) error; Richardson's 2D(h) − D(2h) cancels it.
fn fd_error(j: &dyn Joint, q: &[f64], h: f64, kink: bool) -> (f64, f64) {
    let n = j.dof();
    let mut k0 = JointKinematics::default();
    j.kinematics(q, Derivatives::Hessian, &mut k0);
    let ginv = k0.transform.to_matrix().try_inverse().unwrap();
    let (mut es, mut eh) = (0.0f64, 0.0f64);
    let scale_s = 1.0 + (0..n).map(|i| k0.s[i].norm()).fold(0.0, f64::max);
    let scale_h = 1.0
        + (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, jj)| k0.ds[i][jj].norm())
            .fold(0.0, f64::max);
    for jj in 0..n {
        let (mut s_fd, mut ds_fd) = central(j, q, jj, h, &ginv);
        if kink {
            let (s2, ds2) = central(j, q, jj, 2.0 * h, &ginv);
            s_fd = s_fd * 2.0 - s2;
            for i in 0..n {
                ds_fd[i] = ds_fd[i] * 2.0 - ds2[i];
            }
        }
        es = es.max((s_fd - k0.s[jj]).norm() / scale_s);
        for i in 0..n {
            eh = eh.max((ds_fd[i] - k0.ds[i][jj]).norm() / scale_h);
        }
    }
    (es, eh)
}

/// `Ṡ q̇ = Σ_ij ∂s_i/∂q_j q̇_i q̇_j` at q.
fn sdot_v(j: &dyn Joint, q: &[f64], v: &[f64]) -> Twist {
    let mut k = JointKinematics::default();
    j.kinematics(q, Derivatives::Hessian, &mut k);
    let mut t = Twist::zeros();
    for a in 0..j.dof() {
        for b in 0..j.dof() {
            t += k.ds[a][b] * (v[a] * v[b]);
        }
    }
    t
}

/// Worst relative error of the joint's `∂(Ṡ q̇)/∂q` against differences of
/// `Ṡ q̇` (that is, of the Hessian) at q. Central differences where the joint is
/// smooth; at a knot or a range end (`kink`) the third derivative jumps and the
/// joint gives one side's value (the right side at a knot, the inside at an
/// end), so there it must match the forward or the backward second-order
/// one-sided difference. Joints with a constant Jacobian have no such term.
fn third_error(j: &dyn Joint, q: &[f64], h: f64, kink: bool) -> f64 {
    if j.constant_jacobian() {
        return 0.0;
    }
    let n = j.dof();
    let v = &[0.7, -1.3, 0.4, 1.1, -0.6, 0.9][..n];
    let mut got = [Twist::zeros(); 6];
    assert!(
        j.sdot_v_dq(q, v, &mut got),
        "{} gives no analytic ∂(Ṡ q̇)/∂q",
        j.kind()
    );
    let at = |m: usize, d: f64| {
        let mut qq = q.to_vec();
        qq[m] += d;
        sdot_v(j, &qq, v)
    };
    let scale = 1.0 + (0..n).map(|m| got[m].norm()).fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for m in 0..n {
        let err = |fd: Twist| (fd - got[m]).norm() / scale;
        let e = if kink {
            let side = |s: f64| (at(m, 0.0) * -3.0 + at(m, s) * 4.0 - at(m, 2.0 * s)) / (2.0 * s);
            err(side(h)).min(err(side(-h)))
        } else {
            err((at(m, h) - at(m, -h)) / (2.0 * h))
        };
        worst = worst.max(e);
    }
    worst
}

fn check(name: &str, j: &dyn Joint, qs: &[Vec<f64>], h: f64) {
    check_at(name, j, qs, h, false)
}

fn check_knots(name: &str, j: &dyn Joint, qs: &[Vec<f64>]) {
    check_at(name, j, qs, 1e-5, true)
}

fn check_at(name: &str, j: &dyn Joint, qs: &[Vec<f64>], h: f64, kink: bool) {
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for q in qs {
        let (a, b) = fd_error(j, q, h, kink);
        let c = third_error(j, q, h, kink);
        assert!(
            a <= 1e-7 && b <= 1e-7 && c <= 1e-7,
            "{name} at q = {q:?}: S error {a:.2e}, ∇S error {b:.2e}, ∂(Ṡq̇)/∂q error {c:.2e}"
        );
        worst = (worst.0.max(a), worst.1.max(b), worst.2.max(c));
    }
    println!(
        "{name:>22}: {} points, worst relative error S {:.1e}, ∇S {:.1e}, ∂(Ṡq̇)/∂q {:.1e}",
        qs.len(),
        worst.0,
        worst.1,
        worst.2
    );
}

fn random_qs(rng: &mut Lcg, n: usize, lo: f64, hi: f64, count: usize) -> Vec<Vec<f64>> {
    (0..count)
        .map(|_| (0..n).map(|_| rng.range(lo, hi)).collect())
        .collect()
}

fn random_frames(rng: &mut Lcg, m: usize, step: f64) -> Vec<Se3> {
    let mut g = Se3::identity();
    let mut out = vec![g];
    for _ in 1..m {
        let t = Twist::new(
            rng.range(-1., 1.),
            rng.range(-1., 1.),
            rng.range(-1., 1.),
            rng.range(-1., 1.),
            rng.range(-1., 1.),
            rng.range(-1., 1.),
        );
        g = g.compose(&exp_se3(&(t * step)));
        out.push(g);
    }
    out
}

fn curve_joint(rng: &mut Lcg) -> SplineCurveJoint {
    let frames = random_frames(rng, 8, 0.6);
    // non-uniform clamped knots on [−1, 2]
    let knots = vec![-1., -1., -1., -1., -0.6, -0.1, 0.2, 1.1, 2., 2., 2., 2.];
    SplineCurveJoint::from_knots(frames, &knots).unwrap()
}

#[test]
fn lower_pairs_match_finite_differences() {
    let mut rng = Lcg(7);
    let h = 1e-6;
    let qs1 = random_qs(&mut rng, 1, -3.0, 3.0, 20);
    check(
        "revolute",
        &Revolute::new(Vector3::new(1., 2., 3.)).unwrap(),
        &qs1,
        h,
    );
    check(
        "prismatic",
        &Prismatic::new(Vector3::new(0., 1., 1.)).unwrap(),
        &qs1,
        h,
    );
    check(
        "helical",
        &Helical::new(Vector3::new(1., -1., 0.5), 0.05).unwrap(),
        &qs1,
        h,
    );
    let qs2 = random_qs(&mut rng, 2, -3.0, 3.0, 20);
    check(
        "cylindrical",
        &Cylindrical::new(Vector3::new(0., 0., 1.)).unwrap(),
        &qs2,
        h,
    );
    check(
        "universal",
        &Universal::new(Vector3::x(), Vector3::new(0., 1., 0.3)).unwrap(),
        &qs2,
        h,
    );
    let mut qs3 = random_qs(&mut rng, 3, -3.0, 3.0, 20);
    qs3.push(vec![0.3, PI / 2.0, -0.2]); // gimbal lock of zyx: S, ∇S still exact
    check("spherical zyx", &Spherical::default(), &qs3, h);
    check(
        "spherical zxz",
        &Spherical::new(EulerOrder::parse("zxz").unwrap()),
        &qs3,
        h,
    );
    check(
        "planar",
        &Planar::new(Vector3::new(0., 1., 1.), Vector3::x()).unwrap(),
        &qs3,
        h,
    );
    let qs6 = random_qs(&mut rng, 6, -2.0, 2.0, 20);
    check("root6 zxy", &Root6::new(EulerOrder::ZXY), &qs6, h);
    // fixed: no coordinates, constant transform
    let t = exp_se3(&Twist::new(0.1, 0.2, 0.3, 1., 2., 3.));
    let mut k = JointKinematics::default();
    Fixed::new(t).kinematics(&[], Derivatives::Hessian, &mut k);
    assert_eq!(k.transform, t);
}

#[test]
fn elliptic_joint_matches_finite_differences_and_stays_tangent() {
    let j = Elliptic::new(2.0, 0.7).unwrap();
    let mut qs: Vec<Vec<f64>> = (0..=40)
        .map(|i| vec![-PI + 2.0 * PI * i as f64 / 40.0])
        .collect();
    qs.push(vec![PI / 2.0 - 1e-9]); // φ wraps through ±π near here: G stays continuous
    check("elliptic", &j, &qs, 1e-6);
    let j2 = Elliptic::with_axis(
        1.0,
        3.0,
        Vector3::new(0.2, 0.1, 1.0),
        exp_se3(&Twist::new(0.3, 0., 0.1, 1., 0., 0.)),
    )
    .unwrap();
    check("elliptic (tilted k, H)", &j2, &qs, 1e-6);
    // tangency: the body x axis is along the ellipse tangent p'(q)
    let mut k = JointKinematics::default();
    for q in [0.0, 0.4, 1.3, 2.9, -2.0] {
        j.kinematics(&[q], Derivatives::Jacobian, &mut k);
        let x = k.transform.r.column(0).into_owned();
        let tangent = Vector3::new(2.0 * f64::cos(q), 0.7 * f64::sin(q), 0.0).normalize();
        assert!((x - tangent).norm() < 1e-12, "q={q}");
    }
    assert!(Elliptic::new(0.0, 1.0).is_err());
    assert!(Elliptic::new(1.0, f64::NAN).is_err());
}

#[test]
fn spline_curve_joint_matches_finite_differences_at_random_q_knots_and_ends() {
    let mut rng = Lcg(42);
    let j = curve_joint(&mut rng);
    let (a, b) = j.domain();
    let qs = random_qs(&mut rng, 1, a, b, 30);
    check("spline curve (random)", &j, &qs, 1e-6);
    // exactly at interior knots ∇S has a kink (S is C¹): a smaller step keeps
    // the O(h) one-sided error of the difference below the tolerance.
    let knots: Vec<Vec<f64>> = j
        .basis()
        .knots()
        .iter()
        .filter(|&&k| k > a && k < b)
        .map(|&k| vec![k])
        .collect();
    check_knots("spline curve (knots)", &j, &knots);
    // near the domain ends (the continuation outside is C¹ only, so the
    // difference step stays inside: 1e-6 < 1e-5)
    let ends = vec![
        vec![a + 1e-5],
        vec![b - 1e-5],
        vec![a + 1e-3],
        vec![b - 1e-3],
    ];
    check("spline curve (ends)", &j, &ends, 1e-6);
    for q in [a, b] {
        let e = third_error(&j, &[q], 1e-5, true);
        assert!(e <= 1e-7, "spline curve at its range end {q}: {e:.2e}");
    }
    // outside: constant-screw continuation, ∇S = 0
    let outside = vec![vec![a - 0.5], vec![b + 0.7]];
    check("spline curve (outside)", &j, &outside, 1e-6);
}

#[test]
fn spline_curve_joint_is_c2_across_knots_and_interpolates_end_frames() {
    let mut rng = Lcg(3);
    let j = curve_joint(&mut rng);
    let (a, b) = j.domain();
    let mut worst = 0.0f64;
    let (mut kl, mut kr) = (JointKinematics::default(), JointKinematics::default());
    for &t in j.basis().knots().iter().filter(|&&k| k > a && k < b) {
        // the left limit is taken on the previous span (largest float below the knot)
        let left = f64::from_bits(t.to_bits() - if t > 0.0 { 1 } else { 0 })
            - if t <= 0.0 {
                f64::EPSILON * t.abs().max(1e-300)
            } else {
                0.0
            };
        j.kinematics(&[left], Derivatives::Hessian, &mut kl);
        j.kinematics(&[t], Derivatives::Hessian, &mut kr);
        let jump_g = (kl.transform.to_matrix() - kr.transform.to_matrix())
            .abs()
            .max();
        let jump_s = (kl.s[0] - kr.s[0]).norm();
        let jump_ds = (kl.ds[0][0] - kr.ds[0][0]).norm();
        worst = worst.max(jump_ds);
        assert!(
            jump_g < 1e-12 && jump_s < 1e-10,
            "knot {t}: G jump {jump_g:e}, S jump {jump_s:e}"
        );
    }
    println!("spline curve joint: worst second-derivative jump across knots {worst:.2e}");
    assert!(worst <= 1e-8);
    // the clamped curve passes through its first and last control frames
    let mut k = JointKinematics::default();
    j.kinematics(&[a], Derivatives::Transform, &mut k);
    assert!(
        (k.transform.to_matrix() - j.frames()[0].to_matrix())
            .abs()
            .max()
            < 1e-12
    );
    j.kinematics(&[b], Derivatives::Transform, &mut k);
    assert!(
        (k.transform.to_matrix() - j.frames().last().unwrap().to_matrix())
            .abs()
            .max()
            < 1e-12
    );
}

#[test]
fn spline_curve_joint_errors() {
    let f0 = Se3::identity();
    let f1 = exp_se3(&Twist::new(0., 0., PI, 0., 0., 0.));
    let f2 = exp_se3(&Twist::new(0., 0., PI - 1e-3, 0., 0., 0.));
    // π apart: rejected with a message that says what to do
    let e = SplineCurveJoint::from_knots(vec![f0, f1, f0, f1], &[0., 1., 2., 3.]).unwrap_err();
    assert!(e.to_string().contains("intermediate frame"), "{e}");
    // just below π is fine
    assert!(SplineCurveJoint::from_knots(vec![f0, f2, f0, f2], &[0., 1., 2., 3.]).is_ok());
    // wrong knot counts, decreasing knots
    assert!(SplineCurveJoint::from_knots(vec![f0; 5], &[0., 1., 2., 3.]).is_err());
    assert!(SplineCurveJoint::from_knots(vec![f0; 4], &[0., 2., 1., 3.]).is_err());
    assert!(SplineCurveJoint::from_knots(vec![f0; 3], &[0., 1., 2.]).is_err());
    // coincident control frames: the Jacobian vanishes and it is reported
    let j = SplineCurveJoint::from_knots(vec![f0; 6], &[0., 1., 2., 3., 4., 5.]).unwrap();
    let e = j.check_jacobian(1e-6).unwrap_err();
    assert!(e.to_string().contains("vanishes"), "{e}");
    // natural parameterization: knot steps are the twist norms
    let fr = vec![f0, exp_se3(&Twist::new(0., 0., 0., 0.3, 0.4, 0.))];
    let q = mx::model::joints::curve::natural_parameters(&fr, 1.0);
    assert!((q[1] - 1.5).abs() < 1e-15);
}

#[test]
fn n_dof_spline_joint_matches_finite_differences() {
    let mut rng = Lcg(11);
    let b0 = BSplineBasis::clamped_uniform(3, 6, -1.0, 1.0).unwrap();
    let b1 = BSplineBasis::new(3, vec![0., 0., 0., 0., 0.5, 0.8, 2., 2., 2., 2.]).unwrap();
    let phis: Vec<TensorSpline> = (0..6)
        .map(|_| {
            TensorSpline::new(
                vec![b0.clone(), b1.clone()],
                (0..36).map(|_| rng.range(-0.8, 0.8)).collect(),
            )
            .unwrap()
        })
        .collect();
    let j = SplineJoint::new(
        exp_se3(&Twist::new(0.1, -0.2, 0.3, 0.5, 0., 0.)),
        SplineJoint::standard_twists(),
        phis,
    )
    .unwrap();
    let mut qs: Vec<Vec<f64>> = (0..25)
        .map(|_| vec![rng.range(-1., 1.), rng.range(0., 2.)])
        .collect();
    qs.push(vec![-1.0 + 1e-6, 2.0 - 1e-6]);
    check("n-DOF spline (random)", &j, &qs, 1e-6);
    check_knots(
        "n-DOF spline (knots)",
        &j,
        &[vec![-1.0 / 3.0, 0.5], vec![1.0 / 3.0, 0.8], vec![0.0, 0.8]],
    );
    // bad input
    assert!(SplineJoint::new(Se3::identity(), SplineJoint::standard_twists(), vec![]).is_err());
}

#[test]
fn function_joint_with_offsets_matches_direct_composition_and_differences() {
    // A 3-D knee-like CustomJoint: all six functions depend on q, offsets are not identities.
    let sp = |ys: &[f64]| {
        ScalarFunction::SimmSpline(
            SimmSpline::new(vec![-2.0, -1.2, -0.5, 0.0, 0.4], ys.to_vec()).unwrap(),
        )
    };
    let ax = |v: [f64; 3], f: ScalarFunction| TransformAxis {
        axis: Vector3::new(v[0], v[1], v[2]),
        coordinate: Some(0),
        function: f,
    };
    let rot = [
        ax(
            [0., 0., 1.],
            ScalarFunction::Linear {
                slope: 1.0,
                intercept: 0.1,
            },
        ),
        ax([1., 0., 0.], sp(&[0.1, 0.05, 0.0, -0.02, 0.0])),
        ax([0., 1., 0.], sp(&[-0.2, -0.1, 0.0, 0.03, 0.05])),
    ];
    let tr = [
        ax([1., 0., 0.], sp(&[-0.003, 0.004, 0.002, -0.0045, -0.005])),
        ax([0., 1., 0.], sp(&[-0.42, -0.405, -0.398, -0.396, -0.395])),
        ax(
            [0., 0., 1.],
            ScalarFunction::Polynomial {
                coefficients: vec![0.001, -0.002, 0.003],
            },
        ),
    ];
    let pf = Se3::new(
        function_based::body_fixed_xyz([0.1, -0.2, 0.3]),
        Vector3::new(0.01, -0.02, 0.03),
    );
    let cm = Se3::new(
        function_based::body_fixed_xyz([-0.05, 0.15, 0.0]),
        Vector3::new(0.0, 0.05, -0.01),
    );
    let j =
        FunctionJoint::new("knee3d", vec!["q".into()], rot.clone(), tr.clone(), pf, cm).unwrap();
    let mut k = JointKinematics::default();
    for q in [-1.9, -1.2, -0.3, 0.0, 0.3, 0.6] {
        j.kinematics(&[q], Derivatives::Transform, &mut k);
        let v = j.axis_values(&[q]);
        let rm = |a: &TransformAxis, ang: f64| {
            nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(a.axis), ang)
                .into_inner()
        };
        let r = rm(&rot[0], v[0]) * rm(&rot[1], v[1]) * rm(&rot[2], v[2]);
        let t = tr[0].axis * v[3] + tr[1].axis * v[4] + tr[2].axis * v[5];
        let g = pf.compose(&Se3::new(r, t)).compose(&cm.inverse());
        assert!(
            (g.to_matrix() - k.transform.to_matrix()).abs().max() < 1e-15,
            "q={q}"
        );
    }
    // SimmSpline is C² inside its knots and C¹ at its ends (linear extension),
    // so the grid avoids the end knots −2 and 0.4 themselves.
    let qs: Vec<Vec<f64>> = (0..=30)
        .map(|i| vec![-2.31 + 3.0 * i as f64 / 30.0])
        .collect();
    check("function-based (3-D)", &j, &qs, 1e-6);
    check_knots(
        "function-based (knots)",
        &j,
        &[vec![-1.2], vec![-0.5], vec![0.0]],
    );
    // Exactly at the end knots the third-derivative term is the inside one
    // (the linear extension outside has none).
    for q in [-2.0, 0.4] {
        let e = third_error(&j, &[q], 1e-5, true);
        assert!(e <= 1e-7, "function-based at its range end {q}: {e:.2e}");
    }
}

#[test]
fn spherical_singularity_is_reported() {
    let s = Spherical::default();
    assert!((s.singularity_measure(&[0.3, 0.0, 0.2]) - 1.0).abs() < 1e-12);
    assert!(s.singularity_measure(&[0.3, PI / 2.0, 0.2]) < 1e-12);
    let p = Spherical::new(EulerOrder::parse("zxz").unwrap());
    assert!(p.singularity_measure(&[0.3, 0.0, 0.2]) < 1e-12);
    assert!(EulerOrder::parse("zzx").is_err() && EulerOrder::parse("ab").is_err());
    assert!(Universal::new(Vector3::x(), Vector3::x() * 2.0).is_err());
    assert!(Helical::new(Vector3::zeros(), 0.1).is_err());
    assert!(Planar::new(Vector3::z(), Vector3::z()).is_err());
}

#[test]
fn curve_joint_with_a_double_knot_is_c1_there_and_exact_elsewhere() {
    // A double interior knot lowers continuity to C¹ at that knot (documented);
    // elsewhere S and ∇S stay exact and everything is finite.
    let mut rng = Lcg(5);
    let frames = random_frames(&mut rng, 7, 0.5);
    let knots = vec![0., 0., 0., 0., 0.4, 1.0, 1.0, 2., 2., 2., 2.];
    let j = SplineCurveJoint::from_knots(frames, &knots).unwrap();
    let qs: Vec<Vec<f64>> = [0.1, 0.5, 0.9, 1.1, 1.7].iter().map(|&q| vec![q]).collect();
    check("spline curve (double knot)", &j, &qs, 1e-6);
    let mut k = JointKinematics::default();
    j.kinematics(&[1.0], Derivatives::Hessian, &mut k);
    assert!(
        k.transform.to_matrix().iter().all(|x| x.is_finite())
            && k.ds[0][0].iter().all(|x| x.is_finite())
    );
    // tiny and huge coordinate steps stay finite (screw continuation far outside)
    for q in [-1e6, -1e-300, 1e-300, 1e6] {
        j.kinematics(&[q], Derivatives::Hessian, &mut k);
        assert!(
            k.transform.r.iter().all(|x| x.is_finite()) && k.s[0].iter().all(|x| x.is_finite()),
            "q = {q}"
        );
        let rtr = k.transform.r.transpose() * k.transform.r;
        assert!(
            (rtr - nalgebra::Matrix3::identity()).abs().max() < 1e-9,
            "q = {q}"
        );
    }
}

#[test]
fn curve_joint_knot_forms_agree() {
    // breakpoints (frames − 2) and the equivalent full clamped knot vector give the same joint
    let mut rng = Lcg(9);
    let frames = random_frames(&mut rng, 6, 0.4);
    let a = SplineCurveJoint::from_knots(frames.clone(), &[0.0, 0.3, 1.0, 2.0]).unwrap();
    let b =
        SplineCurveJoint::from_knots(frames, &[0., 0., 0., 0., 0.3, 1.0, 2., 2., 2., 2.]).unwrap();
    let (mut ka, mut kb) = (JointKinematics::default(), JointKinematics::default());
    for q in [0.0, 0.2, 0.7, 1.5, 2.0] {
        a.kinematics(&[q], Derivatives::Hessian, &mut ka);
        b.kinematics(&[q], Derivatives::Hessian, &mut kb);
        assert_eq!(ka.transform, kb.transform);
        assert_eq!(ka.ds[0][0], kb.ds[0][0]);
    }
}

#[test]
fn spline_loop_joint_matches_finite_differences_at_random_q_knots_and_across_the_seam() {
    let mut rng = Lcg(11);
    // A closed, wobbling ring of 8 control frames, one lap = 2π.
    let frames: Vec<Se3> = (0..8)
        .map(|k| {
            let a = k as f64 * 2.0 * PI / 8.0;
            let wobble = Twist::new(
                0.1 * a.sin(),
                0.0,
                a,
                a.cos(),
                a.sin(),
                0.1 * (2.0 * a).sin(),
            );
            exp_se3(&wobble)
        })
        .collect();
    let j = SplineLoopJoint::new(frames, 2.0 * PI).unwrap();
    let qs = random_qs(&mut rng, 1, -7.0, 7.0, 30);
    check("spline loop (random)", &j, &qs, 1e-6);
    // knots at multiples of the step, the seam at 0 and one lap further
    let h = j.period() / 8.0;
    let knots: Vec<Vec<f64>> = [0.0, h, 3.0 * h, -2.0 * h, j.period()]
        .iter()
        .map(|&k| vec![k])
        .collect();
    check_knots("spline loop (knots)", &j, &knots);
}
