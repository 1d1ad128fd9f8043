//! Quick gap filling: bridge every interior gap of every DOF with the cubic
//! Hermite curve that matches position and velocity at both ends. This is the
//! kinematic baseline a spacetime transition (SP) improves on, and a cheap
//! preview while editing.

use super::curve::{Curve, HermiteCurve};
use super::dof::Dof;
use super::error::MotionError;
use super::interval::Interval;
use super::mu::Mu;

/// `m` with every interior gap filled by a C¹ Hermite cubic. Ends stay
/// undefined. A conflict anywhere is an error (as for SP: resolve it first).
pub fn fill_hermite(m: &Mu) -> Result<Mu, MotionError> {
    let mut out = Mu::new();
    for (name, dof) in &m.dofs {
        if let Some(i) = dof.intervals.iter().find(|i| i.is_conflict()) {
            return Err(MotionError::Conflict {
                dof: name.clone(),
                start: i.start,
                stop: i.stop,
                t: i.start,
            });
        }
        let mut bridges = Vec::new();
        for w in dof.intervals.windows(2) {
            let (l, r) = (&w[0], &w[1]);
            if r.start - l.stop <= super::time_tol(l.stop) {
                continue; // touching: no gap
            }
            let [q0, v0, _] = l.first_func()?.eval(l.stop)?;
            let [q1, v1, _] = r.first_func()?.eval(r.start)?;
            let h = HermiteCurve::new(l.stop, q0, v0, r.start, q1, v1)?;
            bridges.push(Interval::curve(Curve::Hermite(h), l.stop, r.start)?);
        }
        let filled = if bridges.is_empty() {
            dof.clone()
        } else {
            dof.plus(&Dof { intervals: bridges })
        };
        out.insert(name.clone(), filled);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{conflicts, gaps, minus};

    #[test]
    fn fills_interior_gaps_continuously() {
        let f = Curve::Hermite(HermiteCurve::new(0.0, 0.0, 1.0, 4.0, 2.0, -1.0).unwrap());
        let walk: Mu = [(
            "x".to_string(),
            Dof::from(Interval::curve(f, 0.0, 4.0).unwrap()),
        )]
        .into_iter()
        .collect();
        let hole: Mu = [(
            "x".to_string(),
            Dof::from(Interval::constant(0.0, 1.0, 2.5).unwrap()),
        )]
        .into_iter()
        .collect();
        let m = minus(&walk, &hole);
        assert_eq!(gaps(&m).len(), 1);
        let filled = fill_hermite(&m).unwrap();
        assert!(gaps(&filled).is_empty() && conflicts(&filled).is_empty());
        // Position and velocity continuous at both ends of the bridge.
        for t in [1.0, 2.5] {
            let a = m.sample("x", t).unwrap().unwrap();
            let e = 1e-7;
            let left = filled.sample("x", t - e).unwrap().unwrap();
            let right = filled.sample("x", t + e).unwrap().unwrap();
            assert!((left[0] - a[0]).abs() < 1e-6 && (right[0] - a[0]).abs() < 1e-6);
            assert!((left[1] - a[1]).abs() < 1e-5 && (right[1] - a[1]).abs() < 1e-5);
        }
    }

    #[test]
    fn conflicts_are_an_error() {
        let a: Mu = [(
            "x".to_string(),
            Dof::from(Interval::constant(0.0, 0.0, 2.0).unwrap()),
        )]
        .into_iter()
        .collect();
        let b: Mu = [(
            "x".to_string(),
            Dof::from(Interval::constant(1.0, 1.0, 3.0).unwrap()),
        )]
        .into_iter()
        .collect();
        assert!(matches!(
            fill_hermite(&crate::motion::plus(&a, &b)),
            Err(MotionError::Conflict { .. })
        ));
    }
}
