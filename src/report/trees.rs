//! Random kinematic trees for timing the dynamics on models nobody tuned on:
//! serial chains, humanoid-like trees (a root, a spine, limbs) and trees whose
//! links hang from random parents, 6–60 coordinates, with mixed joints —
//! revolute about a coordinate axis (either sign) or a general axis,
//! prismatic, spherical and a floating root. Each tree is written as URDF, so
//! that mx and Pinocchio's timer load the same model from the same file.
//!
//! URDF has no spherical or floating joint that both readers load as such, so a
//! spherical joint is three revolutes about x, y, z through two massless links,
//! and a floating root is three prismatic joints along x, y, z then such a
//! spherical joint (six coordinates, the root body on the last link): the same
//! coordinates and the same dynamics in both programs. Offsets translate, and a
//! third of them also rotate; inertias are full (a random principal frame) and
//! physically valid. A seed fixes everything, so a bench run times the same
//! trees every time.

use std::fmt::Write as _;

/// The shape of a generated tree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// One serial chain from the root.
    Chain,
    /// A floating root, a spine and four limbs (two of them hanging from the spine's top).
    Humanoid,
    /// Every link hangs from a parent drawn at random among the links so far.
    Random,
}

/// One generated model: its name and its URDF text.
#[derive(Clone, Debug)]
pub struct Tree {
    pub name: String,
    pub urdf: String,
    /// Coordinates (one per URDF joint that moves).
    pub nq: usize,
}

/// The family the dynamics bench times: each shape at several sizes between
/// 6 and 60 coordinates, each with its own seed.
pub fn family() -> Vec<Tree> {
    let mut out = Vec::new();
    for (shape, sizes) in [
        (Shape::Chain, [6, 24, 60]),
        (Shape::Humanoid, [20, 36, 48]),
        (Shape::Random, [12, 30, 60]),
    ] {
        for (k, nq) in sizes.into_iter().enumerate() {
            out.push(generate(shape, nq, 1000 * (shape as u64 + 1) + k as u64));
        }
    }
    out
}

/// xorshift64: the same numbers on every platform.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn f(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.f(0.0, n as f64) as usize).min(n.saturating_sub(1))
    }
    fn chance(&mut self, p: f64) -> bool {
        self.f(0.0, 1.0) < p
    }
}

/// A joint of the generated tree, before it is spelled as URDF.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// Revolute about a unit axis.
    Revolute([f64; 3]),
    Prismatic([f64; 3]),
    /// Three revolutes (x, y, z) through two massless links.
    Spherical,
    /// Three prismatic joints (x, y, z) then a spherical joint.
    Floating,
}

impl Kind {
    fn dof(self) -> usize {
        match self {
            Kind::Revolute(_) | Kind::Prismatic(_) => 1,
            Kind::Spherical => 3,
            Kind::Floating => 6,
        }
    }
}

/// A random joint below the root: mostly revolute about ±x, ±y or ±z (most
/// robots and skeletons), some about a general axis, some prismatic or spherical.
fn random_kind(r: &mut Rng) -> Kind {
    let p = r.f(0.0, 1.0);
    let principal = |r: &mut Rng| {
        let mut a = [0.0; 3];
        a[r.below(3)] = if r.chance(0.5) { 1.0 } else { -1.0 };
        a
    };
    if p < 0.55 {
        Kind::Revolute(principal(r))
    } else if p < 0.7 {
        Kind::Revolute(unit(r))
    } else if p < 0.8 {
        Kind::Prismatic(if r.chance(0.5) { principal(r) } else { unit(r) })
    } else {
        Kind::Spherical
    }
}

fn unit(r: &mut Rng) -> [f64; 3] {
    loop {
        let v = [r.f(-1.0, 1.0), r.f(-1.0, 1.0), r.f(-1.0, 1.0)];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.2 && n <= 1.0 {
            return v.map(|x| x / n);
        }
    }
}

/// Generates a tree of `shape` with about `nq` coordinates (exactly `nq`
/// unless the last joint drawn is spherical and would overshoot, in which case
/// a revolute takes its place).
pub fn generate(shape: Shape, nq: usize, seed: u64) -> Tree {
    let mut r = Rng::new(seed);
    // (parent body index or None, kind)
    let mut joints: Vec<(Option<usize>, Kind)> = Vec::new();
    let mut count = 0;
    let push = |joints: &mut Vec<(Option<usize>, Kind)>, parent, kind: Kind, count: &mut usize| {
        let kind = if *count + kind.dof() > nq {
            Kind::Revolute([0.0, 0.0, 1.0])
        } else {
            kind
        };
        *count += kind.dof();
        joints.push((parent, kind));
        joints.len() - 1
    };
    match shape {
        Shape::Chain => {
            let mut parent = None;
            while count < nq {
                let k = random_kind(&mut r);
                parent = Some(push(&mut joints, parent, k, &mut count));
            }
        }
        Shape::Random => {
            let first = if r.chance(0.5) {
                Kind::Floating
            } else {
                random_kind(&mut r)
            };
            push(&mut joints, None, first, &mut count);
            while count < nq {
                let p = r.below(joints.len());
                let k = random_kind(&mut r);
                push(&mut joints, Some(p), k, &mut count);
            }
        }
        Shape::Humanoid => {
            let root = push(&mut joints, None, Kind::Floating, &mut count);
            // the rest: a spine and four limbs sharing what is left
            let left = nq.saturating_sub(6);
            let spine_n = (left / 8).max(1);
            let mut top = root;
            for _ in 0..spine_n {
                if count >= nq {
                    break;
                }
                let k = random_kind(&mut r);
                top = push(&mut joints, Some(top), k, &mut count);
            }
            let limb_n = left.saturating_sub(spine_n).div_ceil(4).max(1);
            let mut limb = 0;
            while count < nq {
                // legs from the root, arms (and a head with what is left) from the top
                let base = if limb % 4 < 2 { root } else { top };
                let mut parent = base;
                let mut n = 0;
                while n < limb_n && count < nq {
                    let k = random_kind(&mut r);
                    n += k.dof().min(limb_n);
                    parent = push(&mut joints, Some(parent), k, &mut count);
                }
                limb += 1;
            }
        }
    }
    let name = format!(
        "gen_{}_{nq}",
        match shape {
            Shape::Chain => "chain",
            Shape::Humanoid => "humanoid",
            Shape::Random => "random",
        }
    );
    let urdf = urdf(&name, &joints, &mut r);
    Tree {
        name,
        urdf,
        nq: count,
    }
}

/// A random physically valid inertia block: `<inertial>` with a com offset,
/// principal moments obeying the triangle inequality and a random principal frame.
fn inertial(r: &mut Rng) -> String {
    let mass = r.f(0.2, 8.0);
    let com = [r.f(-0.1, 0.1), r.f(-0.2, 0.05), r.f(-0.1, 0.1)];
    // principal moments of a box a × b × c: always a valid inertia
    let (a, b, c) = (r.f(0.03, 0.3), r.f(0.03, 0.3), r.f(0.03, 0.3));
    let m12 = mass / 12.0;
    let [ia, ib, ic] = [
        m12 * (b * b + c * c),
        m12 * (a * a + c * c),
        m12 * (a * a + b * b),
    ];
    let rpy = [r.f(-3.1, 3.1), r.f(-1.5, 1.5), r.f(-3.1, 3.1)];
    format!(
        "    <inertial><origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/><mass value=\"{mass}\"/>\
         <inertia ixx=\"{ia}\" ixy=\"0\" ixz=\"0\" iyy=\"{ib}\" iyz=\"0\" izz=\"{ic}\"/></inertial>\n",
        com[0], com[1], com[2], rpy[0], rpy[1], rpy[2]
    )
}

/// The URDF text of `joints` (parents before children).
fn urdf(name: &str, joints: &[(Option<usize>, Kind)], r: &mut Rng) -> String {
    let mut s =
        format!("<?xml version=\"1.0\"?>\n<robot name=\"{name}\">\n  <link name=\"base\"/>\n");
    // the URDF link each generated body ends on
    let mut body_link: Vec<String> = Vec::with_capacity(joints.len());
    let mut n_joint = 0;
    let mut massless = 0;
    for (i, (parent, kind)) in joints.iter().enumerate() {
        let parent_link =
            parent.map_or_else(|| "base".to_string(), |p: usize| body_link[p].clone());
        let body = format!("b{i}");
        // the fixed placement of the joint in its parent: a translation, a third of them rotated
        let xyz = [r.f(-0.15, 0.15), r.f(-0.4, -0.05), r.f(-0.15, 0.15)];
        let rpy = if r.chance(1.0 / 3.0) {
            [r.f(-1.5, 1.5), r.f(-1.5, 1.5), r.f(-1.5, 1.5)]
        } else {
            [0.0; 3]
        };
        // the elementary joints: (type, axis)
        let steps: Vec<(&str, [f64; 3])> = match *kind {
            Kind::Revolute(a) => vec![("revolute", a)],
            Kind::Prismatic(a) => vec![("prismatic", a)],
            Kind::Spherical => vec![
                ("revolute", [1.0, 0.0, 0.0]),
                ("revolute", [0.0, 1.0, 0.0]),
                ("revolute", [0.0, 0.0, 1.0]),
            ],
            Kind::Floating => vec![
                ("prismatic", [1.0, 0.0, 0.0]),
                ("prismatic", [0.0, 1.0, 0.0]),
                ("prismatic", [0.0, 0.0, 1.0]),
                ("revolute", [1.0, 0.0, 0.0]),
                ("revolute", [0.0, 1.0, 0.0]),
                ("revolute", [0.0, 0.0, 1.0]),
            ],
        };
        let mut from = parent_link;
        for (k, (ty, axis)) in steps.iter().enumerate() {
            let last = k + 1 == steps.len();
            let child = if last {
                body.clone()
            } else {
                massless += 1;
                format!("m{massless}")
            };
            if last {
                let _ = write!(s, "  <link name=\"{child}\">\n{}  </link>\n", inertial(r));
            } else {
                let _ = writeln!(s, "  <link name=\"{child}\"/>");
            }
            let (o, q) = if k == 0 {
                (xyz, rpy)
            } else {
                ([0.0; 3], [0.0; 3])
            };
            let (lo, hi) = if *ty == "prismatic" {
                (-0.5, 0.5)
            } else {
                (-3.0, 3.0)
            };
            n_joint += 1;
            let _ = writeln!(
                s,
                "  <joint name=\"j{n_joint:03}\" type=\"{ty}\"><parent link=\"{from}\"/><child link=\"{child}\"/>\
                 <origin xyz=\"{} {} {}\" rpy=\"{} {} {}\"/><axis xyz=\"{} {} {}\"/>\
                 <limit lower=\"{lo}\" upper=\"{hi}\" effort=\"100\" velocity=\"10\"/></joint>",
                o[0], o[1], o[2], q[0], q[1], q[2], axis[0], axis[1], axis[2]
            );
            from = child;
        }
        body_link.push(body);
    }
    s.push_str("</robot>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    /// Every tree of the family loads, has the coordinates it says, and the
    /// shapes differ: a chain's links each have one child at most, a humanoid
    /// branches.
    #[test]
    fn the_family_loads_with_the_coordinates_it_states() {
        for t in family() {
            let m = Model::from_urdf_str(&t.urdf).unwrap_or_else(|e| panic!("{}: {e}", t.name));
            assert_eq!(m.nq(), t.nq, "{}", t.name);
            assert!((6..=60).contains(&t.nq), "{}", t.name);
            let mut children = vec![0; m.num_links()];
            for l in m.links() {
                if let Some(p) = l.parent {
                    children[p] += 1;
                }
            }
            let branches = children.iter().any(|&c| c > 1);
            if t.name.contains("chain") {
                assert!(!branches, "{}", t.name);
            }
            if t.name.contains("humanoid") {
                assert!(branches, "{}", t.name);
            }
        }
    }

    /// On every tree of the family the two CRBA passes give the same matrix,
    /// and it is symmetric positive definite.
    #[test]
    fn both_crba_passes_agree_on_the_family() {
        use crate::dynamics::{CrbaFrame, Workspace, mass_matrix_in};
        use nalgebra::DMatrix;
        for t in family() {
            let m = Model::from_urdf_str(&t.urdf).unwrap();
            let n = m.nq();
            let mut ws = Workspace::new(&m);
            let mut r = Rng::new(7);
            for _ in 0..3 {
                let q: Vec<f64> = (0..n).map(|_| r.f(-1.2, 1.2)).collect();
                let (mut a, mut b) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
                mass_matrix_in(&m, &mut ws, &q, &mut a, CrbaFrame::World).unwrap();
                mass_matrix_in(&m, &mut ws, &q, &mut b, CrbaFrame::Link).unwrap();
                let scale = a.amax();
                assert!((&a - &b).amax() < 1e-12 * scale, "{}", t.name);
                assert!((&a - a.transpose()).amax() == 0.0, "{}", t.name);
                assert!(
                    a.clone().cholesky().is_some(),
                    "{}: M not positive definite",
                    t.name
                );
            }
        }
    }
}
