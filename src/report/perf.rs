//! Per-call dynamics timings on a URDF, side by side with Pinocchio's C++
//! timer when it is built (`$MX_SHARED/tools/pinocchio/build.sh
//! /tmp/pinocchio-bench`, or `$MX_PINOCCHIO_BENCH`), run in the same session on
//! the same file. The measurement is the one of `benches/dynamics.rs`.

use crate::dynamics::{
    JointState, StateGradient, Workspace, forward_dynamics, inverse_dynamics, mass_matrix,
    rnea_derivatives, torque_sq_gradient,
};
use crate::model::Model;
use nalgebra::DMatrix;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Median µs per call of `f(i)` over `n` states, timing each call after a warm-up.
pub fn median_us(n: usize, mut f: impl FnMut(usize)) -> f64 {
    for i in 0..n.min(200) {
        f(i);
    }
    let mut t: Vec<f64> = (0..n)
        .map(|i| {
            let s = Instant::now();
            f(i);
            s.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    t.sort_by(|a, b| a.total_cmp(b));
    t[n / 2]
}

/// Path of Pinocchio's timer: `$MX_PINOCCHIO_BENCH`, else `$PINOCCHIO_BENCH`,
/// else where `build.sh` puts it by default.
pub fn pinocchio_exe() -> PathBuf {
    std::env::var_os("MX_PINOCCHIO_BENCH")
        .or_else(|| std::env::var_os("PINOCCHIO_BENCH"))
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/tmp/pinocchio-bench/bench"))
}

/// Pinocchio's medians in µs (rnea, aba, crba, rnea_derivatives), if its timer runs.
pub fn pinocchio(urdf: &Path) -> Option<[f64; 4]> {
    let out = std::process::Command::new(pinocchio_exe())
        .arg(urdf)
        .output()
        .ok()?;
    let text = String::from_utf8_lossy(&out.stdout);
    let get = |name: &str| -> Option<f64> {
        text.lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|x| x.parse().ok())
    };
    Some([
        get("rnea")?,
        get("aba")?,
        get("crba")?,
        get("rnea_derivatives")?,
    ])
}

/// Our medians in µs: rnea, aba, crba, rnea_derivatives, adjoint Σwτ² gradient.
pub fn per_call(model: &Model, n_states: usize) -> Result<[f64; 5], String> {
    let n = model.nq();
    let g = model.default_gravity;
    let mut s = 0x1234_5678u64;
    let mut r = |lo: f64, hi: f64| {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        lo + (hi - lo) * ((s >> 11) as f64 / (1u64 << 53) as f64)
    };
    let states: Vec<[Vec<f64>; 3]> = (0..n_states)
        .map(|_| {
            [
                (0..n).map(|_| r(-1.0, 1.0)).collect(),
                (0..n).map(|_| r(-2.0, 2.0)).collect(),
                (0..n).map(|_| r(-5.0, 5.0)).collect(),
            ]
        })
        .collect();
    let mut ws = Workspace::new(model);
    let mut out = vec![0.0; n];
    let (mut gq, mut gv, mut ga) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let w = vec![1.0; n];
    let mut mm = DMatrix::zeros(n, n);
    let mut dq = DMatrix::zeros(n, n);
    let mut dv = DMatrix::zeros(n, n);
    // Check once that every algorithm accepts the model before timing (errors, not panics).
    {
        let [q, v, a] = &states[0];
        inverse_dynamics(model, &mut ws, q, v, a, &g, &mut out).map_err(|e| e.to_string())?;
        forward_dynamics(model, &mut ws, q, v, a, &g, &mut out).map_err(|e| e.to_string())?;
        mass_matrix(model, &mut ws, q, &mut mm).map_err(|e| e.to_string())?;
        rnea_derivatives(
            model,
            &mut ws,
            &JointState::new(q, v, a),
            &g,
            &mut dq,
            &mut dv,
        )
        .map_err(|e| e.to_string())?;
        torque_sq_gradient(
            model,
            &mut ws,
            &JointState::new(q, v, a),
            &g,
            &w,
            StateGradient {
                q: &mut gq,
                v: &mut gv,
                a: &mut ga,
            },
        )
        .map_err(|e| e.to_string())?;
    }
    let rnea = median_us(n_states, |i| {
        let [q, v, a] = &states[i];
        let _ = inverse_dynamics(model, &mut ws, q, v, a, &g, &mut out);
        black_box(&out);
    });
    let aba = median_us(n_states, |i| {
        let [q, v, a] = &states[i];
        let _ = forward_dynamics(model, &mut ws, q, v, a, &g, &mut out);
        black_box(&out);
    });
    let crba = median_us(n_states, |i| {
        let _ = mass_matrix(model, &mut ws, &states[i][0], &mut mm);
        black_box(&mm);
    });
    let der = median_us(n_states, |i| {
        let [q, v, a] = &states[i];
        let _ = rnea_derivatives(
            model,
            &mut ws,
            &JointState::new(q, v, a),
            &g,
            &mut dq,
            &mut dv,
        );
        black_box(&dq);
    });
    let adj = median_us(n_states, |i| {
        let [q, v, a] = &states[i];
        let j = torque_sq_gradient(
            model,
            &mut ws,
            &JointState::new(q, v, a),
            &g,
            &w,
            StateGradient {
                q: &mut gq,
                v: &mut gv,
                a: &mut ga,
            },
        );
        let _ = black_box(j);
    });
    Ok([rnea, aba, crba, der, adj])
}
