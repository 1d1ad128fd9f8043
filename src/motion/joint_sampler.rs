//! A motion read as a body's joint state: the DOFs named in a fixed order
//! (a body's coordinates) sampled together at a time, NaN where a DOF is
//! undefined or absent. The DOFs are looked up by name once, not at every
//! sample, and every caller that needs "the whole pose at t" reads it the
//! same way.

use super::{Dof, MotionError, Mu};

/// Samples the DOFs `names` of a motion together (see the module docs).
#[derive(Clone, Debug)]
pub struct JointSampler<'a> {
    motion: &'a Mu,
    names: &'a [String],
    /// Each name's DOF in the motion (`None`: the motion has no such DOF).
    dofs: Vec<Option<&'a Dof>>,
}

impl<'a> JointSampler<'a> {
    pub fn new(motion: &'a Mu, names: &'a [String]) -> Self {
        JointSampler {
            motion,
            names,
            dofs: names.iter().map(|n| motion.get(n)).collect(),
        }
    }

    /// How many DOFs a state has.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// `[q, q̇, q̈]` of DOF `i` at `t`; `None` where undefined or absent.
    pub fn sample(&self, i: usize, t: f64) -> Result<Option<[f64; 3]>, MotionError> {
        match self.dofs[i] {
            Some(d) => d.sample(&self.names[i], t),
            // the motion's own answer for a DOF it lacks (checks the time)
            None => self.motion.sample(&self.names[i], t),
        }
    }

    /// Fills q, q̇, q̈ (each [`Self::len`] long) at `t`, NaN where a DOF is
    /// undefined. Returns the first undefined DOF's index, if any.
    pub fn state(
        &self,
        t: f64,
        q: &mut [f64],
        v: &mut [f64],
        a: &mut [f64],
    ) -> Result<Option<usize>, MotionError> {
        let mut first = None;
        for i in 0..self.len() {
            let [x, dx, ddx] = match self.sample(i, t)? {
                Some(s) => s,
                None => {
                    first = first.or(Some(i));
                    [f64::NAN; 3]
                }
            };
            q[i] = x;
            v[i] = dx;
            a[i] = ddx;
        }
        Ok(first)
    }

    /// Every DOF's value at `t`, NaN where undefined.
    pub fn positions(&self, t: f64) -> Result<Vec<f64>, MotionError> {
        (0..self.len())
            .map(|i| Ok(self.sample(i, t)?.map_or(f64::NAN, |s| s[0])))
            .collect()
    }

    /// The name of DOF `i`.
    pub fn name(&self, i: usize) -> &str {
        &self.names[i]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{Curve, Interval};

    fn motion() -> Mu {
        let mut m = Mu::new();
        // x(t) = 2t on [0, 1]; y = 3 on [0, 0.4] and [0.6, 1]
        m.insert(
            "x",
            Dof::from(
                Interval::curve(Curve::samples(0.0, 1.0, vec![0.0, 2.0]).unwrap(), 0.0, 1.0)
                    .unwrap(),
            ),
        );
        m.insert(
            "y",
            Dof::new(vec![
                Interval::constant(3.0, 0.0, 0.4).unwrap(),
                Interval::constant(3.0, 0.6, 1.0).unwrap(),
            ])
            .unwrap(),
        );
        m
    }

    #[test]
    fn a_state_is_the_motions_samples_with_nan_where_undefined() {
        let m = motion();
        let names: Vec<String> = ["y", "nope", "x"].iter().map(|s| s.to_string()).collect();
        let s = JointSampler::new(&m, &names);
        assert_eq!(s.len(), 3);
        let (mut q, mut v, mut a) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]);
        for t in [0.1, 0.5, 0.9] {
            let first = s.state(t, &mut q, &mut v, &mut a).unwrap();
            for (i, n) in names.iter().enumerate() {
                match m.sample(n, t).unwrap() {
                    Some([x, dx, ddx]) => {
                        assert_eq!([q[i], v[i], a[i]], [x, dx, ddx], "{n} at {t}");
                    }
                    None => assert!(q[i].is_nan() && v[i].is_nan() && a[i].is_nan()),
                }
            }
            // "nope" is absent everywhere; y is undefined at 0.5 only
            assert_eq!(first, Some(if t == 0.5 { 0 } else { 1 }));
            let p = s.positions(t).unwrap();
            assert!(
                p.iter()
                    .zip(&q)
                    .all(|(a, b)| a == b || (a.is_nan() && b.is_nan()))
            );
        }
    }

    #[test]
    fn a_bad_time_is_an_error_even_for_an_absent_dof() {
        let m = motion();
        let names = vec!["nope".to_string()];
        assert!(JointSampler::new(&m, &names).positions(f64::NAN).is_err());
    }
}
