//! Integrator work–precision: every integrator at several steps/tolerances on
//! the OpenSim gait2392 knee pendulum (error against OpenSim's accuracy-1e-12
//! run, or against our own tight Dormand–Prince run when the shared data is
//! absent), and the energy drift of a conservative double pendulum.

use super::plot::{Figure, Series};
use super::timed;
use crate::cancel::CancelToken;
use crate::dynamics::{Integrator, Scene, SceneWorkspace, State, simulate};
use crate::lie::Se3;
use crate::model::joints::{FunctionJoint, Revolute};
use crate::model::{Inertia, Model};
use crate::report::error::{ReportError, ZERO_AXIS};
use nalgebra::{Matrix3, Matrix4, Rotation3, Vector3};
use serde_json::Value;
use std::path::Path;
use std::sync::Arc;

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().filter_map(|x| x.as_f64()).collect())
        .unwrap_or_default()
}

fn rows(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().flat_map(floats).collect())
        .unwrap_or_default()
}

/// The OpenSim knee pendulum of `data/opensim` (run
/// `shank_foot_femur_flexed_50deg`): scene, initial state and OpenSim's
/// accuracy-1e-12 q on a 1 ms grid. Lifted from `benches/dynamics.rs`.
pub fn knee_pendulum(shared: &Path) -> Result<(Scene, State, Vec<f64>), ReportError> {
    let dir = shared.join("data/opensim");
    let read = |f: &str| -> Result<Value, ReportError> {
        let p = dir.join(f);
        let t = std::fs::read_to_string(&p).map_err(|source| ReportError::Read {
            path: p.clone(),
            source,
        })?;
        serde_json::from_str(&t).map_err(|source| ReportError::Json { path: p, source })
    };
    let samples = read("knee_r_gait2392_samples.json")?;
    let pend = read("knee_r_gait2392_pendulum.json")?;
    let bad = |what: &str| ReportError::Field {
        file: "knee_r_gait2392_pendulum.json",
        field: what.to_string(),
    };
    let run = pend["runs"]
        .as_array()
        .and_then(|r| {
            r.iter()
                .find(|r| r["name"] == "shank_foot_femur_flexed_50deg")
        })
        .ok_or_else(|| bad("run shank_foot_femur_flexed_50deg"))?;
    let joint = Arc::new(FunctionJoint::from_opensim_samples_json(&samples)?);
    let mut inertia = Inertia::zero();
    for b in run["setup"]["bodies"]
        .as_array()
        .ok_or_else(|| bad("setup.bodies"))?
    {
        let i = rows(&b["inertia_about_com_in_body"]);
        let t = rows(&b["T_tibia_body"]);
        let c = floats(&b["com_in_body"]);
        if i.len() != 9 || t.len() != 16 || c.len() != 3 {
            return Err(bad("body inertia / frame / com"));
        }
        let local = Inertia::from_com(
            b["mass"].as_f64().ok_or_else(|| bad("mass"))?,
            Vector3::from_vec(c),
            Matrix3::from_row_slice(&i),
        )?;
        inertia += local.transformed(&Se3::from_matrix(&Matrix4::from_row_slice(&t)));
    }
    let flex = run["femur_flexion_rad"]
        .as_f64()
        .ok_or_else(|| bad("femur_flexion_rad"))?;
    let mut m = Model::new("knee");
    m.add_link(
        "tibia_r",
        None,
        "knee_r",
        joint,
        Se3::from_rotation(Rotation3::from_axis_angle(&Vector3::z_axis(), flex).into_inner()),
        inertia,
    )?;
    let scene = Scene::new(Arc::new(m)).with_gravity(Vector3::new(0.0, -9.80665, 0.0))?;
    let init = State {
        q: vec![run["q0"].as_f64().ok_or_else(|| bad("q0"))?],
        v: vec![run["u0"].as_f64().ok_or_else(|| bad("u0"))?],
    };
    Ok((scene, init, floats(&run["q_accuracy_1e-12"])))
}

/// A frictionless double pendulum under gravity: its energy is conserved, so
/// any change is the integrator's.
pub fn double_pendulum() -> Result<(Scene, State), ReportError> {
    let mut m = Model::new("double_pendulum");
    for i in 0..2 {
        let inertia = Inertia::from_com(
            1.0,
            Vector3::new(0.0, -0.5, 0.0),
            Matrix3::identity() * 0.02,
        )?;
        m.add_link(
            &format!("l{i}"),
            if i == 0 { None } else { Some(0) },
            &format!("j{i}"),
            Arc::new(Revolute::new(Vector3::z()).ok_or(ZERO_AXIS)?),
            Se3::from_translation(Vector3::new(0.0, if i == 0 { 0.0 } else { -1.0 }, 0.0)),
            inertia,
        )?;
    }
    let scene = Scene::new(Arc::new(m)).with_gravity(Vector3::new(0.0, -9.80665, 0.0))?;
    Ok((
        scene,
        State {
            q: vec![1.2, -0.6],
            v: vec![0.0, 0.0],
        },
    ))
}

/// One row of the integrator table.
#[derive(Clone, Debug)]
pub struct Row {
    pub method: &'static str,
    pub setting: String,
    pub error: f64,
    pub energy_drift: f64,
    pub ms: f64,
    pub drift_ms: f64,
}

pub struct Outcome {
    pub rows: Vec<Row>,
    pub reference: String,
    pub figures: Vec<Figure>,
}

fn cases(smoke: bool) -> Vec<(&'static str, String, Integrator, f64)> {
    let dts: &[f64] = if smoke {
        &[1e-2, 1e-3]
    } else {
        &[1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4]
    };
    let tols: &[f64] = if smoke {
        &[1e-4, 1e-8]
    } else {
        &[1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
    };
    let mut c = Vec::new();
    for (name, m) in [
        ("euler", Integrator::Euler),
        ("semi_implicit_euler", Integrator::SemiImplicitEuler),
        ("rk4", Integrator::Rk4),
    ] {
        for &dt in dts {
            c.push((name, format!("dt = {dt:e} s"), m, dt));
        }
    }
    for &t in tols {
        c.push((
            "dopri5",
            format!("tol = {t:.0e}"),
            Integrator::DormandPrince { rtol: t, atol: t },
            1e-3,
        ));
    }
    c
}

/// The library default the figures mark (the `simulate` built-in uses
/// Dormand–Prince at tolerance 1e-8 unless told otherwise).
pub const DEFAULT: (&str, &str) = ("dopri5", "tol = 1e-8");

/// Max |q − q_ref| at the times both grids share (q_ref every `ref_dt`,
/// the simulation every `dt`); steps are chosen so the grids meet every
/// 1 ms or every `dt`.
fn grid_error(q: &[Vec<f64>], dt: f64, q_ref: &[f64], ref_dt: f64) -> f64 {
    let mut worst = 0.0f64;
    let mut shared = 0usize;
    for (b, r) in q_ref.iter().enumerate() {
        let a = b as f64 * ref_dt / dt;
        let k = a.round();
        if (a - k).abs() > 1e-6 {
            continue;
        }
        match q.get(k as usize) {
            Some(x) => {
                worst = worst.max((x[0] - r).abs());
                shared += 1;
            }
            None => break,
        }
    }
    if shared == 0 { f64::INFINITY } else { worst }
}

/// Every integrator setting of [`cases`] on the knee pendulum against the
/// reference ([`reference`]) and on the double pendulum's energy, and the
/// two [`figures`].
pub fn run(
    shared: Option<&Path>,
    smoke: bool,
    tick: &mut dyn FnMut(),
) -> Result<Outcome, ReportError> {
    let tok = CancelToken::new();
    let duration = if smoke { 0.3 } else { 1.0 };
    let (scene, init, q_ref, reference) = reference(shared, duration, &tok)?;
    let (dp, dp0) = double_pendulum()?;
    let mut sw = SceneWorkspace::new(&dp);
    let e0 = dp.energy(&mut sw, &dp0.q, &dp0.v)?;
    let mut rows = Vec::new();
    for (method, setting, m, dt) in cases(smoke) {
        let (r, secs) = timed(|| simulate(&scene, duration, dt, m, &init, &tok, &mut |_| {}));
        let error = match r {
            Ok(tr) => grid_error(&tr.q, dt, &q_ref, 1e-3),
            Err(_) => f64::INFINITY,
        };
        let (d, dsecs) = timed(|| simulate(&dp, duration * 5.0, dt, m, &dp0, &tok, &mut |_| {}));
        let energy_drift = match d {
            Ok(tr) => {
                let mut w = 0.0f64;
                for (q, v) in tr.q.iter().zip(&tr.v) {
                    let e = dp.energy(&mut sw, q, v)?;
                    w = w.max((e - e0).abs() / e0.abs().max(1e-12));
                }
                w
            }
            Err(_) => f64::INFINITY,
        };
        rows.push(Row {
            method,
            setting,
            error,
            energy_drift,
            ms: secs * 1e3,
            drift_ms: dsecs * 1e3,
        });
        tick();
    }
    Ok(Outcome {
        figures: figures(&rows, duration),
        rows,
        reference,
    })
}

/// The scene every setting is scored on, its initial state, the reference
/// q on a 1 ms grid and a sentence saying what the reference is: OpenSim's
/// knee pendulum where `$MX_SHARED` has it, else a double pendulum against
/// our own Dormand–Prince run at tolerance 1e-13 (saying why).
fn reference(
    shared: Option<&Path>,
    duration: f64,
    tok: &CancelToken,
) -> Result<(Scene, State, Vec<f64>, String), ReportError> {
    let why = match shared.map(knee_pendulum) {
        Some(Ok((s, i, q))) => return Ok((
            s,
            i,
            q,
            "OpenSim 4 knee pendulum, accuracy 1e-12 (`$MX_SHARED/data/opensim/knee_r_gait2392_pendulum.json`)".to_string(),
        )),
        Some(Err(e)) => e.to_string(),
        None => "MX_SHARED not found".to_string(),
    };
    let (s, i) = double_pendulum()?;
    let r = simulate(
        &s,
        duration,
        1e-3,
        Integrator::DormandPrince {
            rtol: 1e-13,
            atol: 1e-13,
        },
        &i,
        tok,
        &mut |_| {},
    )?;
    let q = r.q.iter().map(|x| x[0]).collect();
    Ok((
        s,
        i,
        q,
        format!(
            "self-computed Dormand–Prince tol 1e-13 reference on a double pendulum (OpenSim data unavailable: {why})"
        ),
    ))
}

/// Error and energy drift against wall time, one curve per integrator, the
/// default ringed.
fn figures(rows: &[Row], duration: f64) -> Vec<Figure> {
    let series = |f: &dyn Fn(&Row) -> (f64, f64)| -> Vec<Series> {
        ["euler", "semi_implicit_euler", "rk4", "dopri5"]
            .iter()
            .map(|m| {
                let rs: Vec<&Row> = rows.iter().filter(|r| r.method == *m).collect();
                Series {
                    label: m.to_string(),
                    points: rs.iter().map(|r| f(r)).collect(),
                    default_at: rs
                        .iter()
                        .position(|r| r.method == DEFAULT.0 && r.setting == DEFAULT.1),
                }
            })
            .collect()
    };
    vec![
        Figure {
            file: "integrators_error.svg".into(),
            title: format!("Knee pendulum: max |q − q_ref| over {duration} s"),
            x_label: "wall time (ms, this machine)".into(),
            y_label: "max |Δq| (rad)".into(),
            series: series(&|r| (r.ms, r.error)),
        },
        Figure {
            file: "integrators_energy.svg".into(),
            title: format!("Double pendulum: energy drift over {} s", duration * 5.0),
            x_label: "wall time (ms, this machine)".into(),
            y_label: "max |E − E₀| / |E₀|".into(),
            series: series(&|r| (r.drift_ms, r.energy_drift)),
        },
    ]
}
