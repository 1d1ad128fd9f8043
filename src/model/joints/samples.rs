//! Sampled joint motion — desired transforms G_d at coordinates q — and the
//! error of a joint against them.

use super::error::{JointSpecError, jerr};
use crate::lie::{Se3, rotation_angle};
use crate::model::joint::{Derivatives, Joint, JointKinematics};
use nalgebra::Matrix4;
use serde_json::Value;

/// Desired transforms `transforms[k]` at coordinates `q[k]` (sorted, strictly increasing).
#[derive(Debug, Clone, PartialEq)]
pub struct JointSamples {
    pub q: Vec<f64>,
    pub transforms: Vec<Se3>,
}

/// How far a joint is from samples: translation in millimetres, rotation as the
/// angle of R_fit⁻¹ R_ref in degrees.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct JointError {
    pub max_mm: f64,
    pub rms_mm: f64,
    pub max_deg: f64,
    pub rms_deg: f64,
}

impl JointSamples {
    /// Sorts by q; rejects non-finite values, repeated q and mismatched lengths.
    pub fn new(q: Vec<f64>, transforms: Vec<Se3>) -> Result<Self, JointSpecError> {
        if q.len() != transforms.len() {
            return jerr(format!(
                "{} coordinates but {} transforms",
                q.len(),
                transforms.len()
            ));
        }
        if q.len() < 2 {
            return jerr("need at least 2 samples");
        }
        let mut idx: Vec<usize> = (0..q.len()).collect();
        if let Some(k) = (0..q.len()).find(|&k| {
            !q[k].is_finite()
                || transforms[k]
                    .r
                    .iter()
                    .chain(transforms[k].p.iter())
                    .any(|x| !x.is_finite())
        }) {
            return jerr(format!("sample {k} is not finite"));
        }
        idx.sort_by(|&a, &b| q[a].total_cmp(&q[b]));
        let q2: Vec<f64> = idx.iter().map(|&i| q[i]).collect();
        if let Some(w) = q2.windows(2).find(|w| w[1] == w[0]) {
            return jerr(format!(
                "two samples share q = {}: give each coordinate value once",
                w[0]
            ));
        }
        let t2 = idx.iter().map(|&i| transforms[i]).collect();
        Ok(JointSamples {
            q: q2,
            transforms: t2,
        })
    }

    /// The `samples` of an OpenSim samples file (`q`, `T_parent_child` 4×4 rows
    /// first), given the whole document or its `samples` array.
    pub fn from_opensim_json(v: &Value) -> Result<Self, JointSpecError> {
        let arr = v.get("samples").unwrap_or(v).as_array().ok_or_else(|| {
            JointSpecError("samples: expected a `samples` array of {q, T_parent_child}".into())
        })?;
        let mut q = Vec::with_capacity(arr.len());
        let mut t = Vec::with_capacity(arr.len());
        for (k, s) in arr.iter().enumerate() {
            let qk = s
                .get("q")
                .and_then(Value::as_f64)
                .ok_or_else(|| JointSpecError(format!("sample {k} has no numeric `q`")))?;
            let m = s
                .get("T_parent_child")
                .or_else(|| s.get("T"))
                .and_then(mat4)
                .ok_or_else(|| {
                    JointSpecError(format!(
                        "sample {k}: `T_parent_child` must be a 4×4 matrix (rows first)"
                    ))
                })?;
            q.push(qk);
            t.push(Se3::from_matrix(&m));
        }
        JointSamples::new(q, t)
    }

    /// Reads a samples JSON file (the layout of `data/opensim/*_samples.json`).
    pub fn load(path: impl AsRef<std::path::Path>) -> Result<Self, JointSpecError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| JointSpecError(format!("cannot read {}: {e}", path.display())))?;
        let v: Value = serde_json::from_str(&text)
            .map_err(|e| JointSpecError(format!("{} is not valid JSON: {e}", path.display())))?;
        Self::from_opensim_json(&v)
    }

    pub fn len(&self) -> usize {
        self.q.len()
    }
    pub fn is_empty(&self) -> bool {
        self.q.is_empty()
    }
    pub fn range(&self) -> (f64, f64) {
        (self.q[0], self.q[self.q.len() - 1])
    }
}

fn mat4(v: &Value) -> Option<Matrix4<f64>> {
    let rows = v.as_array()?;
    if rows.len() != 4 {
        return None;
    }
    let mut m = Matrix4::zeros();
    for (i, r) in rows.iter().enumerate() {
        let r = r.as_array()?;
        if r.len() != 4 {
            return None;
        }
        for (j, x) in r.iter().enumerate() {
            m[(i, j)] = x.as_f64()?;
        }
    }
    Some(m)
}

/// The error of `joint` (1-DOF) against `samples`.
pub fn joint_error(
    joint: &dyn Joint,
    samples: &JointSamples,
) -> Result<JointError, JointSpecError> {
    if joint.dof() != 1 {
        return jerr(format!(
            "joint_error compares a 1-DOF joint with samples; this {} joint has {} coordinates",
            joint.kind(),
            joint.dof()
        ));
    }
    let mut k = JointKinematics::default();
    let (mut max_mm, mut sum_mm, mut max_deg, mut sum_deg) = (0.0f64, 0.0, 0.0f64, 0.0);
    for (q, gd) in samples.q.iter().zip(&samples.transforms) {
        joint.kinematics(&[*q], Derivatives::Transform, &mut k);
        let g = k.transform;
        let mm = (g.p - gd.p).norm() * 1000.0;
        let deg = rotation_angle(&(g.r.transpose() * gd.r)).to_degrees();
        max_mm = max_mm.max(mm);
        max_deg = max_deg.max(deg);
        sum_mm += mm * mm;
        sum_deg += deg * deg;
    }
    let n = samples.len() as f64;
    Ok(JointError {
        max_mm,
        rms_mm: (sum_mm / n).sqrt(),
        max_deg,
        rms_deg: (sum_deg / n).sqrt(),
    })
}

impl JointSamples {
    /// The same samples with Gaussian noise of standard deviation `sigma_m`
    /// (metres, per translation axis) and `sigma_rad` (radians, per rotation
    /// axis, applied in the child frame), from a fixed seed: the noisy data of
    /// the smoothing study (paper §6.3), identical in the tests and the report.
    pub fn with_noise(&self, sigma_m: f64, sigma_rad: f64, seed: u64) -> Self {
        let mut rng = Gaussian::new(seed);
        let transforms = self
            .transforms
            .iter()
            .map(|g| {
                let (wx, wy, wz) = (rng.next(), rng.next(), rng.next());
                let w = crate::lie::Twist::new(
                    wx * sigma_rad,
                    wy * sigma_rad,
                    wz * sigma_rad,
                    0.0,
                    0.0,
                    0.0,
                );
                let (px, py, pz) = (rng.next(), rng.next(), rng.next());
                let mut n = g.compose(&crate::lie::exp_se3(&w));
                n.p += nalgebra::Vector3::new(px, py, pz) * sigma_m;
                n
            })
            .collect();
        JointSamples {
            q: self.q.clone(),
            transforms,
        }
    }
}

/// Standard normal numbers from a seed: xorshift64 and Box–Muller (no
/// dependency, same sequence on every platform).
struct Gaussian(u64);

impl Gaussian {
    fn new(seed: u64) -> Self {
        // xorshift has a fixed point at 0
        Gaussian(seed.max(1))
    }
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}
