//! The per-frame contact forces an animation carries, in its
//! `extras.mx.forces`: `ground_forces`' numbers ([`ForceSeries`]) on the
//! animation's own frames, so an animator's tool can draw them and `load`
//! gives them back.
//!
//! ```json
//! "extras": { "mx": { "forces": {
//!   "points": ["LeftFoot", "RightFoot"],   // contact points (link names)
//!   "nodes": [14, 19],                     // the node each acts at (its origin), null if none
//!   "up": [0, 1, 0],                       // the body's up, in the file's axes
//!   "frame_time": 0.0333333,               // s
//!   "times": [0, 0.0333333, …],            // s from the animation's first key: one per frame
//!   "forces": [[[fx, fy, fz], …], …],      // frames × points × 3: N on the body
//!   "residual": { "force": [[…], …],       // frames × 3: N that no contact supplies
//!                 "moment": [[…], …],      // frames × 3: N·m about the centre of mass
//!                 "percent_bw": […] }      // frames: |residual force| as % of body weight
//! } } }
//! ```
//!
//! Axes are the file's, the nodes' own (mx writes a body's world frame as
//! is: y-up for every body from a BVH clip, as glTF asks; a z-up body's file
//! is z-up, and `up` says so). Numbers are JSON f64, read back exactly.
//! Times and frame time are f64 beside the animation's f32 keys; the reader
//! puts the forces on the grid it reads the animation on (from 0 s), after
//! checking that there is one per frame and each lies on its frame.

use std::path::Path;

use nalgebra::Vector3;
use serde_json::{Value, json};

use super::GltfError;
use super::read::{Which, from_bytes, raw_json};
use crate::ground::ForceSeries;

/// The forces an animation of a file carries, on the frames `load` reads it on.
#[derive(Clone, Debug, PartialEq)]
pub struct SavedForces {
    /// The animation they belong to.
    pub animation: String,
    /// The body's up when it was saved (the file's axes), if the file says.
    pub up: Option<Vector3<f64>>,
    /// Times from 0 s on the loaded animation's frame grid.
    pub series: ForceSeries,
}

/// The `extras.mx.forces` object of an animation whose first key is at
/// `t0` (s, on the motion's clock); `nodes[j]`: the node of point `j`.
pub(super) fn to_extras(
    f: &ForceSeries,
    t0: f64,
    up: Option<Vector3<f64>>,
    nodes: &[Option<usize>],
) -> Value {
    let v3 = |v: &Vector3<f64>| json!([v.x, v.y, v.z]);
    let rows = |vs: &[Vector3<f64>]| Value::Array(vs.iter().map(v3).collect());
    let mut out = json!({
        "points": f.points,
        "nodes": nodes,
        "frame_time": f.frame_time,
        "times": f.times.iter().map(|t| t - t0).collect::<Vec<f64>>(),
        "forces": f.forces.iter().map(|fr| rows(fr)).collect::<Vec<_>>(),
        "residual": {
            "force": rows(&f.residual_force),
            "moment": rows(&f.residual_moment),
            "percent_bw": f.percent_bw,
        },
    });
    if let Some(u) = up {
        // + 0.0: −0 (from −gravity) written as 0
        out["up"] = v3(&u.map(|c| c + 0.0));
    }
    out
}

/// Reads the forces animation `which` of `path` carries: `Err` naming the
/// file and the field when they are missing or malformed.
pub fn load_forces(path: &Path, which: Which) -> Result<SavedForces, GltfError> {
    let bytes = std::fs::read(path).map_err(|source| crate::io::FileError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    forces_from_bytes(&bytes, path, which)
}

/// [`load_forces`] on a file's bytes; `path` names it in errors and is
/// where relative buffer URIs are resolved from.
pub fn forces_from_bytes(
    bytes: &[u8],
    path: &Path,
    which: Which,
) -> Result<SavedForces, GltfError> {
    // the animation read as `load` reads it: its frame grid
    let loaded = from_bytes(bytes, path.parent(), which.clone())?;
    let index = match which {
        Which::First => 0,
        Which::Index(k) => k,
        Which::Name(n) => loaded
            .animations
            .iter()
            .position(|a| *a == n)
            .unwrap_or_default(),
    };
    let raw = raw_json(bytes);
    let field = Fields {
        path,
        root: format!("animations[{index}].extras.mx.forces"),
    };
    let v = &raw["animations"][index]["extras"]["mx"]["forces"];
    if v.is_null() {
        return Err(field.error(
            "",
            format!(
                "animation `{}` carries no contact forces (save it with `forces: true`)",
                loaded.animation
            ),
        ));
    }
    let (frames, frame_time) = (loaded.clip.frames, loaded.clip.frame_time);
    let series = field.series(v, frames, frame_time)?;
    let up = match &v["up"] {
        Value::Null => None,
        u => Some(field.vector(u, "up")?),
    };
    Ok(SavedForces {
        animation: loaded.animation,
        up,
        series,
    })
}

/// Reads the fields of one forces object, naming the file and the field in errors.
struct Fields<'a> {
    path: &'a Path,
    root: String,
}

impl Fields<'_> {
    fn error(&self, field: &str, message: impl Into<String>) -> GltfError {
        GltfError::Forces {
            path: self.path.display().to_string(),
            field: if field.is_empty() {
                self.root.clone()
            } else {
                format!("{}.{field}", self.root)
            },
            message: message.into(),
        }
    }

    /// The arrays of `v` on `frames` frames, `frame_time` apart from 0 s.
    fn series(&self, v: &Value, frames: usize, frame_time: f64) -> Result<ForceSeries, GltfError> {
        let points: Vec<String> = self
            .array(&v["points"], "points", None)?
            .iter()
            .enumerate()
            .map(|(j, p)| match p {
                Value::String(s) if !s.is_empty() => Ok(s.clone()),
                _ => Err(self.error(&format!("points[{j}]"), "not a point's name")),
            })
            .collect::<Result<_, _>>()?;
        if points.is_empty() {
            return Err(self.error("points", "names no contact point"));
        }
        let per_frame = (frames, "one per frame of the animation");
        let times = self.numbers(&v["times"], "times", per_frame)?;
        for (k, t) in times.iter().enumerate() {
            if (t - k as f64 * frame_time).abs() > 0.01 * frame_time {
                return Err(self.error(
                    &format!("times[{k}]"),
                    format!(
                        "{t} s is not frame {k} of the animation ({} s): the forces are of another motion",
                        k as f64 * frame_time
                    ),
                ));
            }
        }
        let forces = self
            .array(&v["forces"], "forces", Some(per_frame))?
            .iter()
            .enumerate()
            .map(|(k, fr)| {
                self.vectors(fr, &format!("forces[{k}]"), (points.len(), "one per point"))
            })
            .collect::<Result<_, _>>()?;
        let r = &v["residual"];
        Ok(ForceSeries {
            times: (0..frames).map(|k| k as f64 * frame_time).collect(),
            frame_time,
            points,
            forces,
            residual_force: self.vectors(&r["force"], "residual.force", per_frame)?,
            residual_moment: self.vectors(&r["moment"], "residual.moment", per_frame)?,
            percent_bw: self.numbers(&r["percent_bw"], "residual.percent_bw", per_frame)?,
        })
    }

    /// `v` as an array (of `len` items, when given).
    fn array<'v>(
        &self,
        v: &'v Value,
        field: &str,
        len: Option<(usize, &str)>,
    ) -> Result<&'v Vec<Value>, GltfError> {
        let a = v.as_array().ok_or_else(|| {
            self.error(
                field,
                if v.is_null() {
                    "missing".to_string()
                } else {
                    format!("not an array: {}", short(v))
                },
            )
        })?;
        match len {
            Some((n, of)) if a.len() != n => Err(self.error(
                field,
                format!("{} items, where {n} are needed ({of})", a.len()),
            )),
            _ => Ok(a),
        }
    }

    /// `len` finite numbers (`of`: what they are one of).
    fn numbers(
        &self,
        v: &Value,
        field: &str,
        (len, of): (usize, &str),
    ) -> Result<Vec<f64>, GltfError> {
        self.array(v, field, Some((len, of)))?
            .iter()
            .enumerate()
            .map(|(k, x)| {
                x.as_f64().filter(|x| x.is_finite()).ok_or_else(|| {
                    self.error(
                        &format!("{field}[{k}]"),
                        format!("not a finite number: {}", short(x)),
                    )
                })
            })
            .collect()
    }

    fn vector(&self, v: &Value, field: &str) -> Result<Vector3<f64>, GltfError> {
        let n = self.numbers(v, field, (3, "x, y, z"))?;
        Ok(Vector3::new(n[0], n[1], n[2]))
    }

    /// `len` vectors of three numbers.
    fn vectors(
        &self,
        v: &Value,
        field: &str,
        (len, of): (usize, &str),
    ) -> Result<Vec<Vector3<f64>>, GltfError> {
        self.array(v, field, Some((len, of)))?
            .iter()
            .enumerate()
            .map(|(k, x)| self.vector(x, &format!("{field}[{k}]")))
            .collect()
    }
}

/// A JSON value cut to a length that fits a message.
fn short(v: &Value) -> String {
    let s = v.to_string();
    match s.char_indices().nth(40) {
        Some((i, _)) => format!("{}…", &s[..i]),
        None => s,
    }
}
