//! Built-ins for the spline-joint mechanisms: `frame` (a control frame from an
//! origin and two axes), `spline_surface` (the n-DOF spline joint on a grid of
//! control frames), `deforming_surface` (a surface whose control frames change
//! with time, carried by a clock coordinate that a scene drives), and
//! `spline_loop` (a closed spline curve joint).

use nalgebra::{Matrix3, Vector3};

use crate::lang::args::{ArgValue, Args};
use crate::lang::diagnostics::{ErrorKind, MxError, MxResult};
use crate::lang::host::joint::{JointValue, matrix_value};
use crate::lang::registry::Registry;
use crate::lang::topic::Topic;
use crate::lang::value::Value;
use crate::lie::Se3;
use crate::model::joints::{EulerOrder, FrameGrid, SplineLoopJoint, SplineSurfaceJoint};

fn vec3_of(a: &Args, name: &str, arg: &ArgValue) -> MxResult<Vector3<f64>> {
    a.vec3_of(name, arg, "a list of 3 finite numbers")
}

/// A pose from an origin, a z axis and an x axis (made orthogonal to z).
fn make_frame(a: &mut Args) -> MxResult<Value> {
    let oarg = a.arg("origin")?;
    let origin = vec3_of(a, "origin", &oarg)?;
    let x = match a.opt_named("x") {
        Some(x) => vec3_of(a, "x", &x)?,
        None => Vector3::x(),
    };
    let z = match a.opt_named("z") {
        Some(z) => vec3_of(a, "z", &z)?,
        None => Vector3::z(),
    };
    let zn = z.norm();
    let xp = x - z * (x.dot(&z) / (zn * zn).max(1e-300));
    if zn < 1e-12 || xp.norm() < 1e-9 * x.norm().max(1e-300) || x.norm() < 1e-12 {
        return Err(a.error(
            ErrorKind::Value,
            "`frame`: `z` must be non-zero and `x` must not be parallel to it",
        ));
    }
    let (xa, za) = (xp.normalize(), z / zn);
    let r = Matrix3::from_columns(&[xa, za.cross(&xa), za]);
    Ok(matrix_value(&Se3::new(r, origin)))
}

fn is_matrix(v: &Value) -> bool {
    v.as_list().is_some_and(|rows| {
        rows.len() == 4
            && rows.iter().all(|r| {
                r.as_number().is_none()
                    && r.as_list()
                        .is_some_and(|r| r.len() == 4 && r.iter().all(|x| x.as_number().is_some()))
            })
    })
}

/// Flattens a nested list of 4×4 matrices of `depth` levels into row-major
/// frames, with the grid's size along each level.
fn grid_of(a: &Args, name: &str, arg: &ArgValue, depth: usize) -> MxResult<(Vec<usize>, Vec<Se3>)> {
    let walk = GridWalk {
        a,
        name,
        arg,
        depth,
    };
    let (mut dims, mut frames) = (vec![], vec![]);
    walk.visit(&arg.value, 0, &mut dims, &mut frames)?;
    Ok((dims, frames))
}

/// What the recursive walk of [`grid_of`] keeps fixed.
struct GridWalk<'a> {
    a: &'a Args,
    name: &'a str,
    arg: &'a ArgValue,
    depth: usize,
}

impl GridWalk<'_> {
    fn visit(
        &self,
        v: &Value,
        level: usize,
        dims: &mut Vec<usize>,
        out: &mut Vec<Se3>,
    ) -> MxResult<()> {
        let (a, name, arg) = (self.a, self.name, self.arg);
        if level == self.depth {
            let av = ArgValue {
                value: v.clone(),
                span: arg.span,
                name: None,
            };
            out.push(a.transform_of(name, &av)?);
            return Ok(());
        }
        let Some(l) = v.as_list() else {
            return Err(a.type_error(name, "a nested list of 4×4 frames", arg));
        };
        if dims.len() == level {
            dims.push(l.len());
        } else if dims[level] != l.len() {
            return Err(MxError::value(format!(
                "`{}`: `{name}` is not a regular grid: along dimension {level} one row has {} frames, another {}",
                a.name(),
                dims[level],
                l.len()
            ))
            .at(arg.span));
        }
        for x in l.iter() {
            self.visit(x, level + 1, dims, out)?;
        }
        Ok(())
    }
}

/// How many list levels lie above the 4×4 matrices.
fn depth_of(v: &Value) -> usize {
    let mut d = 0;
    let mut cur = v;
    while !is_matrix(cur) {
        match cur.as_list().and_then(|l| l.first()) {
            Some(x) => {
                cur = x;
                d += 1;
            }
            None => return d,
        }
    }
    d
}

fn range_of(a: &mut Args, name: &str) -> MxResult<(f64, f64)> {
    match a.opt_named(name) {
        None => Ok((0.0, 1.0)),
        Some(r) => {
            let v = r.value.as_list().and_then(|l| {
                l.iter()
                    .map(|x| x.as_number().filter(|x| x.is_finite()))
                    .collect::<Option<Vec<f64>>>()
            });
            match v {
                Some(v) if v.len() == 2 && v[1] > v[0] => Ok((v[0], v[1])),
                _ => Err(a.type_error(name, "an increasing range [from, to]", &r)),
            }
        }
    }
}

fn order_of(a: &mut Args) -> MxResult<EulerOrder> {
    match a.opt_named("order") {
        None => Ok(EulerOrder::ZYX),
        Some(o) => match &o.value {
            Value::Str(s) => {
                EulerOrder::parse(s).map_err(|e| MxError::value(e.to_string()).at(o.span))
            }
            _ => Err(a.type_error("order", "a string such as \"zyx\"", &o)),
        },
    }
}

const COORDS: [&str; 3] = ["u", "v", "w"];

fn make_surface(a: &mut Args) -> MxResult<Value> {
    let farg = a.arg("frames")?;
    let depth = depth_of(&farg.value);
    if !(1..=3).contains(&depth) {
        return Err(a.type_error(
            "frames",
            "a grid of 4×4 frames: a list of rows of frames (2 coordinates), or 1 or 3 levels of lists",
            &farg,
        ));
    }
    let (dims, frames) = grid_of(a, "frames", &farg, depth)?;
    let ranges = (0..depth)
        .map(|d| range_of(a, COORDS[d]))
        .collect::<MxResult<Vec<_>>>()?;
    let order = order_of(a)?;
    let grid = FrameGrid {
        dims,
        ranges,
        frames,
        names: COORDS[..depth].iter().map(|s| s.to_string()).collect(),
        unlimited: vec![false; depth],
    };
    let j = SplineSurfaceJoint::from_grid(&grid, order)
        .map_err(|e| MxError::value(format!("`{}`: {e}", a.name())).at(farg.span))?;
    Ok(Value::object(JointValue::new(j)))
}

fn make_deforming(a: &mut Args) -> MxResult<Value> {
    let karg = a.arg("keys")?;
    let nk = karg.value.as_list().map(|l| l.len()).unwrap_or(0);
    if depth_of(&karg.value) != 3 || nk < 2 {
        return Err(a.type_error(
            "keys",
            "a list of at least 2 surfaces, each a grid (list of rows) of 4×4 frames",
            &karg,
        ));
    }
    let (dims, frames) = grid_of(a, "keys", &karg, 3)?;
    // keys × rows × columns → rows × columns × keys (time varies fastest).
    let (k, r, c) = (dims[0], dims[1], dims[2]);
    let mut reordered = Vec::with_capacity(frames.len());
    for i in 0..r {
        for j in 0..c {
            for t in 0..k {
                reordered.push(frames[(t * r + i) * c + j]);
            }
        }
    }
    let u = range_of(a, "u")?;
    let v = range_of(a, "v")?;
    let during = range_of(a, "during")?;
    let order = order_of(a)?;
    let grid = FrameGrid {
        dims: vec![r, c, k],
        ranges: vec![u, v, during],
        frames: reordered,
        names: vec!["u".into(), "v".into(), "t".into()],
        unlimited: vec![false, false, true],
    };
    let j = SplineSurfaceJoint::from_grid(&grid, order)
        .map_err(|e| MxError::value(format!("`{}`: {e}", a.name())).at(karg.span))?;
    Ok(Value::object(JointValue::new(j)))
}

fn make_loop(a: &mut Args) -> MxResult<Value> {
    let farg = a.arg("frames")?;
    if depth_of(&farg.value) != 1 {
        return Err(a.type_error("frames", "a list of 4×4 frames", &farg));
    }
    let (_, frames) = grid_of(a, "frames", &farg, 1)?;
    let period = a.named_number_or("period", std::f64::consts::TAU)?;
    let j = SplineLoopJoint::new(frames, period)
        .map_err(|e| MxError::value(format!("`spline_loop`: {e}")).at(farg.span))?;
    Ok(Value::object(JointValue::new(j)))
}

pub fn register(reg: &mut Registry) {
    reg.topic(Topic::Joints);
    reg.add(
        "frame(origin, x: [1, 0, 0], z: [0, 0, 1])",
        "A control frame (4×4 pose) at `origin` whose z axis points along `z` and whose x axis is `x` made orthogonal to z (y = z × x).",
        |a, _| make_frame(a),
    );
    reg.add(
        "spline_surface(frames, u: [0, 1], v: [0, 1], order: \"zyx\")",
        "A 2-DOF spline surface joint (spline-joint paper eq. 25) on a grid of control frames: `frames` is a list of rows of 4×4 poses \
         (rows along u, columns along v; a single list gives a 1-DOF joint). Each frame's position and Euler angles in `order` (three different axes; \
         frames must stay 5° from its gimbal lock) are the control points of tensor-product cubic B-splines over the ranges `u` and `v`, \
         which are also the joint's limits (a scene with `limits: true` holds it there). Coordinates `<joint>.u`, `<joint>.v`.",
        |a, _| make_surface(a),
    );
    reg.add(
        "deforming_surface(keys, u: [0, 1], v: [0, 1], during: [0, 10], order: \"zyx\")",
        "A spline surface joint whose control frames change with time: `keys` is a list of frame grids (same layout as spline_surface), \
         B-spline control surfaces spread uniformly over the interval `during` (the first and last are met exactly). It has a third coordinate \
         `<joint>.t`, the surface's time: drive it with `scene(..., driven: {\"<joint>.t\": 1})` so the surface deforms kinematically while the body on it \
         responds to the dynamics.",
        |a, _| make_deforming(a),
    );
    reg.add(
        "spline_loop(frames, period: 2*pi)",
        "A closed 1-DOF spline curve joint through control frames (a list of at least 4 poses): periodic cumulative cubic B-spline on SE(3), \
         one lap every `period` of the coordinate, so it can run round for ever (beads on a wire).",
        |a, _| make_loop(a),
    );
}
