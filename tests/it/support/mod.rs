//! Test models: random trees mixing revolute, prismatic and a configuration-
//! dependent 3-DOF product-of-exponentials joint, and a tiny deterministic RNG.
#![allow(dead_code)]

pub mod graph;

use mx::lie::{Se3, Twist, ad};
use mx::model::joint::{Derivatives, Joint, JointKinematics};
use mx::model::joints::{Prismatic, Revolute};
use mx::model::{Inertia, Model};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use std::sync::Arc;

/// xorshift64*: reproducible without a dependency.
pub struct Rng(u64);
impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// The generator started from this exact state (no seed mixing), for
    /// tests whose recorded cases depend on the sequence.
    pub fn from_state(state: u64) -> Self {
        Rng(state)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    /// Uniform in 0..n (0 when n is 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n.max(1) as u64) as usize
    }
    pub fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len())]
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let x = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * x
    }
    pub fn vec(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.uniform(lo, hi)).collect()
    }
    pub fn v3(&mut self, s: f64) -> Vector3<f64> {
        Vector3::new(
            self.uniform(-s, s),
            self.uniform(-s, s),
            self.uniform(-s, s),
        )
    }
}

/// `G(q) = e^{ξ₀ q₀} e^{ξ₁ q₁} e^{ξ₂ q₂}` with ξ₀ a rotation about x through the
/// origin, ξ₁ a rotation about y through `c`, ξ₂ a translation along `d`:
/// S depends on q (`∂s_j/∂q_k = −ad(s_k, s_j)` for k > j).
#[derive(Debug, Clone)]
pub struct PoeJoint {
    pub c: Vector3<f64>,
    pub d: Unit<Vector3<f64>>,
}

impl PoeJoint {
    fn factors(&self, q: &[f64]) -> [(Se3, Twist); 3] {
        let x = Vector3::x_axis();
        let y = Vector3::y_axis();
        let r1 = Rotation3::from_axis_angle(&y, q[1]).into_inner();
        let cy = self.c.cross(&y); // v = −ω × c
        [
            (
                Se3::from_rotation(Rotation3::from_axis_angle(&x, q[0]).into_inner()),
                Twist::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0),
            ),
            (
                Se3::new(r1, self.c - r1 * self.c),
                Twist::new(0.0, 1.0, 0.0, cy.x, cy.y, cy.z),
            ),
            (
                Se3::from_translation(self.d.into_inner() * q[2]),
                Twist::new(0.0, 0.0, 0.0, self.d.x, self.d.y, self.d.z),
            ),
        ]
    }
}

impl Joint for PoeJoint {
    fn kind(&self) -> &'static str {
        "poe-test"
    }
    fn dof(&self) -> usize {
        3
    }
    fn kinematics(&self, q: &[f64], want: Derivatives, out: &mut JointKinematics) {
        let f = self.factors(q);
        out.transform = f[0].0.compose(&f[1].0).compose(&f[2].0);
        if want >= Derivatives::Jacobian {
            // s_j = Ad_{(e_{j+1}⋯e_2)⁻¹} ξ_j
            let mut tail = Se3::identity();
            for j in (0..3).rev() {
                out.s[j] = tail.inv_ad_twist(&f[j].1);
                tail = f[j].0.compose(&tail);
            }
        }
        if want >= Derivatives::Hessian {
            for j in 0..3 {
                for k in 0..3 {
                    out.ds[j][k] = if k > j {
                        -ad(&out.s[k], &out.s[j])
                    } else {
                        Twist::zeros()
                    };
                }
            }
        }
    }
}

pub fn random_inertia(rng: &mut Rng, mass: f64) -> Inertia {
    let a = Matrix3::from_fn(|_, _| rng.uniform(-0.3, 0.3));
    let i = a * a.transpose() * mass + Matrix3::identity() * 0.01 * mass;
    Inertia::from_com(mass, rng.v3(0.2), i).unwrap()
}

pub fn random_offset(rng: &mut Rng) -> Se3 {
    Se3::new(
        Rotation3::from_euler_angles(
            rng.uniform(-3.0, 3.0),
            rng.uniform(-1.5, 1.5),
            rng.uniform(-3.0, 3.0),
        )
        .into_inner(),
        rng.v3(0.4),
    )
}

/// A random tree of `n` links; `poe` puts a configuration-dependent joint on every third link.
pub fn random_tree(rng: &mut Rng, n: usize, poe: bool) -> Model {
    let mut m = Model::new("random");
    for i in 0..n {
        let parent = if i == 0 {
            None
        } else {
            Some((rng.uniform(0.0, 1.0) * i as f64) as usize)
        };
        let joint: Arc<dyn Joint> = match i % 3 {
            2 if poe => Arc::new(PoeJoint {
                c: rng.v3(0.3),
                d: Unit::new_normalize(rng.v3(1.0)),
            }),
            1 => Arc::new(Prismatic::new(rng.v3(1.0)).unwrap()),
            _ => Arc::new(Revolute::new(rng.v3(1.0)).unwrap()),
        };
        let mass = rng.uniform(0.5, 3.0);
        let inertia = random_inertia(rng, mass);
        m.add_link(
            &format!("l{i}"),
            parent,
            &format!("j{i}"),
            joint,
            random_offset(rng),
            inertia,
        )
        .unwrap();
    }
    m
}

/// A chain of the library's configuration-dependent joints — a spline curve
/// joint, a closed spline loop, an elliptic joint, a 2-DOF tensor-spline joint,
/// a spherical and a universal joint — with random inertias and offsets: the
/// dynamics' derivatives use each joint's analytic ∂(Ṡ q̇)/∂q on it.
pub fn spline_chain(rng: &mut Rng) -> Model {
    use mx::lie::exp_se3;
    use mx::model::joints::{
        Elliptic, EulerOrder, Spherical, SplineCurveJoint, SplineJoint, SplineLoopJoint, Universal,
    };
    use mx::spline::{BSplineBasis, TensorSpline};
    let mut frames = |m: usize, step: f64| -> Vec<Se3> {
        let mut g = Se3::identity();
        let mut out = vec![g];
        for _ in 1..m {
            let t = Twist::from_fn(|_, _| rng.uniform(-1.0, 1.0));
            g = g.compose(&exp_se3(&(t * step)));
            out.push(g);
        }
        out
    };
    let curve = SplineCurveJoint::from_knots(
        frames(8, 0.5),
        &[-3., -3., -3., -3., -1.6, -0.1, 0.2, 1.1, 3., 3., 3., 3.],
    )
    .unwrap();
    // A closed ring of 7 frames turning about z, wobbling out of the plane.
    let ring: Vec<Se3> = (0..7)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 7.0;
            exp_se3(&Twist::new(
                0.2 * a.sin(),
                0.0,
                a,
                a.cos(),
                a.sin(),
                0.1 * (2.0 * a).sin(),
            ))
        })
        .collect();
    let lp = SplineLoopJoint::new(ring, 2.0).unwrap();
    let b0 = BSplineBasis::clamped_uniform(3, 5, -3.0, 3.0).unwrap();
    let b1 = BSplineBasis::clamped_uniform(3, 4, -3.0, 3.0).unwrap();
    let phis: Vec<TensorSpline> = (0..6)
        .map(|_| {
            let c = (0..20).map(|_| rng.uniform(-0.6, 0.6)).collect();
            TensorSpline::new(vec![b0.clone(), b1.clone()], c).unwrap()
        })
        .collect();
    let surface = SplineJoint::new(Se3::identity(), SplineJoint::standard_twists(), phis).unwrap();
    let joints: Vec<Arc<dyn Joint>> = vec![
        Arc::new(curve),
        Arc::new(lp),
        Arc::new(Elliptic::new(0.4, 0.25).unwrap()),
        Arc::new(surface),
        Arc::new(Spherical::new(EulerOrder::ZXY)),
        Arc::new(Universal::new(Vector3::x(), Vector3::new(0.2, 1.0, -0.3)).unwrap()),
    ];
    let mut m = Model::new("spline chain");
    for (i, j) in joints.into_iter().enumerate() {
        let mass = rng.uniform(0.5, 3.0);
        let inertia = random_inertia(rng, mass);
        m.add_link(
            &format!("l{i}"),
            i.checked_sub(1),
            &format!("j{i}"),
            j,
            random_offset(rng),
            inertia,
        )
        .unwrap();
    }
    m
}
