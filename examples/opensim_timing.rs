//! Load time of an OpenSim model and inverse dynamics per state, for
//! `scripts/opensim_refs.py --timing`, which runs this beside OpenSim in the
//! same session and quotes the ratio.
//!
//!     cargo run --release --example opensim_timing -- MODEL.osim
//!
//! Prints one JSON object: `load_s` (best of 5: read + parse + build) and
//! `inverse_dynamics_per_state_s` (mean over 20,000 calls at one random state).

use std::time::Instant;

use mx::dynamics::{Workspace, inverse_dynamics};
use mx::model::Model;

fn main() {
    let Some(path) = std::env::args().nth(1) else {
        eprintln!("usage: opensim_timing MODEL.osim");
        std::process::exit(2);
    };
    let mut load_s = f64::INFINITY;
    let mut model = None;
    for _ in 0..5 {
        let t = Instant::now();
        let m = match Model::from_osim_file(&path) {
            Ok(m) => m,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(1);
            }
        };
        load_s = load_s.min(t.elapsed().as_secs_f64());
        model = Some(m.model);
    }
    let m = model.expect("loaded five times");
    let n = m.nq();
    // a fixed pseudo-random state (no RNG dependency)
    let mut x = 0.123_456_789f64;
    let mut next = || {
        x = (x * 9301.0 + 49297.0) % 233_280.0;
        x / 233_280.0 * 2.0 - 1.0
    };
    let q: Vec<f64> = (0..n).map(|_| next()).collect();
    let v: Vec<f64> = (0..n).map(|_| 2.0 * next()).collect();
    let a: Vec<f64> = (0..n).map(|_| 3.0 * next()).collect();
    let g = m.default_gravity;
    let mut ws = Workspace::new(&m);
    let mut tau = vec![0.0; n];
    let reps = 20_000;
    let t = Instant::now();
    for _ in 0..reps {
        inverse_dynamics(&m, &mut ws, &q, &v, &a, &g, &mut tau).expect("finite state");
    }
    let id = t.elapsed().as_secs_f64() / reps as f64;
    println!(
        "{{\"load_s\": {load_s:e}, \"inverse_dynamics_per_state_s\": {id:e}, \"nq\": {n}, \"tau0\": {:e}}}",
        tau[0]
    );
}
