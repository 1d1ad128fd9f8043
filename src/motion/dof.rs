//! A DOF: the intervals that define one scalar degree of freedom over time.
//!
//! Normal form (kept by every operation): intervals sorted by time and
//! disjoint except that neighbours may touch (one's stop = the next's start).
//! Where two motions overlap the overlap is *one* interval carrying the
//! functions of both (multiply defined), so conflicts are explicit.
//!
//! Set operations sweep the endpoints of both operands once, O(n + m) after
//! sorting. Endpoints closer than [`time_tol`] are merged first so rounding
//! (e.g. after `affine`) never leaves sliver intervals or sliver gaps.
//! Touching endpoints share a single instant, which has no duration: they are
//! never an overlap, so `[0,1] + [1,2]` is two intervals and no conflict.

use super::curve::Curve;
use super::error::{MotionError, finite};
use super::interval::{Interval, check_span};
use super::time_tol;

/// One degree of freedom: sorted, disjoint (possibly touching) intervals.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dof {
    pub intervals: Vec<Interval>,
}

/// Which operand(s) a piece of the sweep comes from.
#[derive(Clone, Copy, PartialEq)]
enum Keep {
    Both,    // ∧
    OnlyOne, // −
    Either,  // +
}

impl From<Interval> for Dof {
    fn from(i: Interval) -> Dof {
        Dof { intervals: vec![i] }
    }
}

impl Dof {
    /// Whether the DOF holds one value wherever it is defined: every curve is
    /// constant by construction (a constant, equal samples, a flat Hermite or
    /// spline) and every interval starts at the same value. Curves given as
    /// functions cannot be inspected and count as moving; `name` is the DOF's
    /// (for sampling).
    pub fn is_constant(&self, name: &str) -> bool {
        fn curve_flat(c: &Curve) -> bool {
            let flat = |v: &[f64]| v.iter().all(|x| *x == v[0]);
            match c {
                Curve::Constant(_) => true,
                Curve::Samples(s) => flat(s.values()),
                Curve::Hermite(h) => h.q0 == h.q1 && h.v0 == 0.0 && h.v1 == 0.0,
                Curve::Spline(c) => flat(&c.coeffs),
                // flat parts make a flat sum (non-flat ones may cancel: not
                // worth finding out)
                Curve::Sum(a, b) => curve_flat(a) && curve_flat(b),
                Curve::Function(_) => false,
            }
        }
        let curves_flat = self
            .intervals
            .iter()
            .flat_map(|i| &i.funcs)
            .all(|f| curve_flat(&f.curve));
        if !curves_flat {
            return false;
        }
        let mut first = None;
        for iv in &self.intervals {
            let Ok(Some(v)) = self.sample_value(name, iv.start) else {
                return false; // conflicting or undefined: not provably constant
            };
            match first {
                None => first = Some(v),
                Some(f) if (v - f).abs() <= 1e-12 * f64::max(1.0, f.abs()) => {}
                Some(_) => return false,
            }
        }
        true
    }

    pub fn empty() -> Dof {
        Dof::default()
    }

    /// A DOF from any list of intervals (`dof(i1, i2, …)`): they are added
    /// with `+`, so overlapping intervals become an explicit conflict.
    pub fn new(mut intervals: Vec<Interval>) -> Result<Dof, MotionError> {
        for i in &intervals {
            check_span(i.start, i.stop)?;
            if i.funcs.is_empty() {
                return Err(MotionError::NoFunction);
            }
        }
        // Fast path (the usual case, e.g. many clips in sequence): once sorted,
        // disjoint intervals are already in normal form.
        intervals.sort_by(|a, b| a.start.total_cmp(&b.start));
        if intervals.windows(2).all(|w| w[1].start >= w[0].stop) {
            return Ok(Dof { intervals });
        }
        let mut d = Dof::empty();
        for i in intervals {
            d = d.plus(&Dof::from(i));
        }
        Ok(d)
    }

    pub fn is_empty(&self) -> bool {
        self.intervals.is_empty()
    }

    /// First start and last stop, `None` when nothing is defined.
    pub fn span(&self) -> Option<(f64, f64)> {
        Some((self.intervals.first()?.start, self.intervals.last()?.stop))
    }

    /// `self ∧ other`: where both are defined, carrying both's functions.
    pub fn and(&self, other: &Dof) -> Dof {
        sweep(self, other, Keep::Both)
    }

    /// `self − other`: where exactly one is defined, each part keeping its own functions.
    pub fn minus(&self, other: &Dof) -> Dof {
        sweep(self, other, Keep::OnlyOne)
    }

    /// `self + other` = `(self − other), (self ∧ other)`: the union, overlaps multiply defined.
    pub fn plus(&self, other: &Dof) -> Dof {
        sweep(self, other, Keep::Either)
    }

    /// Time t ↦ ts + d·t. `Err` when ts or d is not finite or d ≤ 0.
    pub fn affine(&self, ts: f64, d: f64) -> Result<Dof, MotionError> {
        check_affine(ts, d)?;
        let intervals = self
            .intervals
            .iter()
            .map(|i| i.affine_checked(ts, d))
            .collect::<Result<_, _>>()?;
        Ok(Dof { intervals })
    }

    pub(crate) fn affine_unchecked(&self, ts: f64, d: f64) -> Dof {
        Dof {
            intervals: self.intervals.iter().map(|i| i.affine(ts, d)).collect(),
        }
    }

    /// The part inside [ts, tf], times unchanged (no span check: see `ops::clip_in_place`).
    pub fn window(&self, ts: f64, tf: f64) -> Dof {
        let mut out = Vec::new();
        for i in &self.intervals {
            let s = i.start.max(ts);
            let e = i.stop.min(tf);
            if e - s > time_tol(s) {
                out.push(Interval {
                    start: s,
                    stop: e,
                    funcs: i.funcs.clone(),
                });
            }
        }
        Dof { intervals: out }
    }

    /// `self` followed by `other` shifted to start where `self` ends.
    /// An empty operand contributes nothing (the other is returned as is).
    pub fn concatenate(&self, other: &Dof) -> Dof {
        match (self.span(), other.span()) {
            (Some((_, end)), Some((start, _))) => {
                self.plus(&other.affine_unchecked(end - start, 1.0))
            }
            (None, _) => other.clone(),
            (_, None) => self.clone(),
        }
    }

    /// Interior gaps: undefined stretches with defined motion on both sides.
    pub fn gaps(&self) -> Vec<(f64, f64)> {
        self.intervals
            .windows(2)
            .filter(|w| w[1].start - w[0].stop > time_tol(w[0].stop))
            .map(|w| (w[0].stop, w[1].start))
            .collect()
    }

    /// Multiply defined stretches.
    pub fn conflicts(&self) -> Vec<(f64, f64)> {
        self.intervals
            .iter()
            .filter(|i| i.is_conflict())
            .map(|i| (i.start, i.stop))
            .collect()
    }
}

pub(crate) fn check_affine(ts: f64, d: f64) -> Result<(), MotionError> {
    finite("affine time shift ts", ts)?;
    if !(d.is_finite() && d > 0.0) {
        return Err(MotionError::BadScale { d });
    }
    Ok(())
}

/// The sweep behind ∧, −, +. Breakpoints are all endpoints of both operands,
/// clustered within `time_tol`; between consecutive breakpoints each operand
/// has at most one active interval (normal form), and the `keep` rule decides
/// which functions the piece carries.
fn sweep(a: &Dof, b: &Dof, keep: Keep) -> Dof {
    let mut pts: Vec<f64> = Vec::with_capacity(2 * (a.intervals.len() + b.intervals.len()));
    for i in a.intervals.iter().chain(&b.intervals) {
        pts.push(i.start);
        pts.push(i.stop);
    }
    pts.sort_by(f64::total_cmp);
    // Cluster: each breakpoint is the first (smallest) of a run of points closer than tol.
    let mut bps: Vec<f64> = Vec::with_capacity(pts.len());
    for p in pts {
        match bps.last() {
            Some(&last) if p - last <= time_tol(last) => {}
            _ => bps.push(p),
        }
    }
    let snap = |t: f64| -> f64 {
        // The cluster holding t is the last whose representative is ≤ t: the
        // next representative lies beyond rep + tol ≥ t.
        let k = bps.partition_point(|&b| b <= t);
        bps[k.saturating_sub(1)]
    };
    let snapped = |d: &Dof| -> Vec<(f64, f64)> {
        d.intervals
            .iter()
            .map(|i| (snap(i.start), snap(i.stop)))
            .collect()
    };
    let sa = snapped(a);
    let sb = snapped(b);

    let mut out: Vec<Interval> = Vec::new();
    let mut last_key: Option<(Option<usize>, Option<usize>)> = None;
    let (mut ia, mut ib) = (0usize, 0usize);
    for w in bps.windows(2) {
        let (lo, hi) = (w[0], w[1]);
        while ia < sa.len() && sa[ia].1 <= lo {
            ia += 1;
        }
        while ib < sb.len() && sb[ib].1 <= lo {
            ib += 1;
        }
        let act_a = (ia < sa.len() && sa[ia].0 <= lo && sa[ia].1 >= hi).then_some(ia);
        let act_b = (ib < sb.len() && sb[ib].0 <= lo && sb[ib].1 >= hi).then_some(ib);
        let take = match (keep, act_a, act_b) {
            (_, None, None) => None,
            (Keep::Both, Some(_), Some(_)) | (Keep::Either, _, _) => Some((act_a, act_b)),
            (Keep::OnlyOne, Some(_), None) | (Keep::OnlyOne, None, Some(_)) => Some((act_a, act_b)),
            _ => None,
        };
        let Some(key) = take else {
            last_key = None;
            continue;
        };
        // Extend the previous piece when it comes from the same operand intervals.
        if last_key == Some(key)
            && let Some(prev) = out.last_mut()
            && prev.stop == lo
        {
            prev.stop = hi;
            continue;
        }
        let mut funcs = Vec::new();
        if let Some(i) = key.0 {
            funcs.extend(a.intervals[i].funcs.iter().cloned());
        }
        if let Some(i) = key.1 {
            funcs.extend(b.intervals[i].funcs.iter().cloned());
        }
        out.push(Interval {
            start: lo,
            stop: hi,
            funcs,
        });
        last_key = Some(key);
    }
    Dof { intervals: out }
}
