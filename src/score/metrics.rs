//! The in-betweening literature's measures over global joint orientations,
//! as Harvey et al. 2020 report them on LaFAN1: L2Q and NPSS.
//!
//! - **L2Q**: per frame, the L2 norm of the difference between the filled
//!   and the captured pose as the stacked unit quaternions of every joint's
//!   world orientation; the mean over the gap's frames. A quaternion and its
//!   negative are one rotation, so each filled quaternion takes the sign
//!   nearer the captured one.
//! - **NPSS** (normalised power spectrum similarity, Gopalakrishnan et al.
//!   2019): per dimension (a joint's quaternion component over the gap's
//!   frames), the power spectrum |X_k|² of its N-point DFT normalised to sum
//!   1 and the earth mover's distance between the two, Σ_k |C_fill(k) −
//!   C_capture(k)| over their cumulative sums; averaged over the dimensions,
//!   each weighted by the capture's total power. It compares how the motion
//!   moves, not where: a motion shifted in time by whole periods scores 0.
//!   LaFAN1's published code squares the DFT's real part only; the paper's
//!   power spectrum, used here, is the squared magnitude, which a time shift
//!   leaves unchanged. Each series is first made continuous in time (the
//!   quaternion's sign chosen nearer the previous frame's), or a sign flip
//!   would read as a jump of every frequency.

use nalgebra::UnitQuaternion;

/// `q`'s coordinates with the sign nearer `to` (the same rotation).
pub fn nearer(q: &UnitQuaternion<f64>, to: &UnitQuaternion<f64>) -> [f64; 4] {
    let (a, b) = (q.coords, to.coords);
    let s = if a.dot(&b) < 0.0 { -1.0 } else { 1.0 };
    [s * a[0], s * a[1], s * a[2], s * a[3]]
}

/// One frame's L2Q term: the L2 norm of the stacked difference of every
/// joint's quaternion, each filled one sign-aligned to its captured one.
pub fn l2q_frame(filled: &[UnitQuaternion<f64>], captured: &[UnitQuaternion<f64>]) -> f64 {
    filled
        .iter()
        .zip(captured)
        .map(|(f, c)| {
            let a = nearer(f, c);
            let b = c.coords;
            (0..4).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>()
        })
        .sum::<f64>()
        .sqrt()
}

/// One joint's quaternions over time as four series, each frame's sign the
/// one nearer the previous frame's (continuous in time).
pub fn continuous_series(qs: &[UnitQuaternion<f64>]) -> [Vec<f64>; 4] {
    let mut out: [Vec<f64>; 4] = Default::default();
    let mut prev: Option<[f64; 4]> = None;
    for q in qs {
        let c = q.coords;
        let mut v = [c[0], c[1], c[2], c[3]];
        if let Some(p) = prev
            && (0..4).map(|i| v[i] * p[i]).sum::<f64>() < 0.0
        {
            v = v.map(|x| -x);
        }
        for (o, x) in out.iter_mut().zip(v) {
            o.push(x);
        }
        prev = Some(v);
    }
    out
}

/// NPSS summed so windows can be pooled as LaFAN1's batch is: the
/// power-weighted sum of the dimensions' distances and the weight.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NpssSum {
    /// Σ_d P_d · EMD_d, P_d the capture's total power in dimension d.
    pub weighted: f64,
    /// Σ_d P_d.
    pub weight: f64,
}

impl NpssSum {
    /// The pooled NPSS (0 where the capture has no power at all).
    pub fn value(&self) -> f64 {
        if self.weight > 0.0 {
            self.weighted / self.weight
        } else {
            0.0
        }
    }

    pub fn add(&mut self, o: NpssSum) {
        self.weighted += o.weighted;
        self.weight += o.weight;
    }
}

/// |X_k|² for k = 0..N of the N-point DFT of `x` (direct: N is a gap's frames).
fn power_spectrum(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    (0..n)
        .map(|k| {
            let (mut re, mut im) = (0.0, 0.0);
            for (t, v) in x.iter().enumerate() {
                // k·t mod n keeps the angle small, so long series stay exact
                let a = -2.0 * std::f64::consts::PI * ((k * t) % n) as f64 / n as f64;
                re += v * a.cos();
                im += v * a.sin();
            }
            re * re + im * im
        })
        .collect()
}

/// The cumulative sums of `p` normalised to end at 1; a series with no power
/// (all zero) is the limit of a small constant: all of it at frequency 0.
fn cumulative(p: &[f64], total: f64) -> Vec<f64> {
    if total <= 0.0 {
        return vec![1.0; p.len()];
    }
    let mut acc = 0.0;
    p.iter()
        .map(|v| {
            acc += v / total;
            acc
        })
        .collect()
}

/// NPSS of `filled` against `captured`: one series per dimension, each
/// pair of equal length (the gap's frames).
pub fn npss(filled: &[Vec<f64>], captured: &[Vec<f64>]) -> NpssSum {
    let mut sum = NpssSum::default();
    for (f, c) in filled.iter().zip(captured) {
        let (pf, pc) = (power_spectrum(f), power_spectrum(c));
        let (tf, tc) = (pf.iter().sum::<f64>(), pc.iter().sum::<f64>());
        if tc <= 0.0 {
            continue; // a dimension the capture never leaves 0 in weighs nothing
        }
        let (cf, cc) = (cumulative(&pf, tf), cumulative(&pc, tc));
        let emd: f64 = cf.iter().zip(&cc).map(|(a, b)| (a - b).abs()).sum();
        sum.weighted += tc * emd;
        sum.weight += tc;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;
    use std::f64::consts::PI;

    fn cosine(n: usize, k: f64, phase: f64) -> Vec<f64> {
        (0..n)
            .map(|t| (2.0 * PI * k * t as f64 / n as f64 + phase).cos())
            .collect()
    }

    #[test]
    fn npss_of_a_motion_with_itself_is_zero() {
        let x: Vec<Vec<f64>> = (0..5)
            .map(|d| {
                (0..37)
                    .map(|t| ((t * (d + 3)) as f64 * 0.37).sin() + 0.1 * d as f64)
                    .collect()
            })
            .collect();
        let s = npss(&x, &x);
        assert_eq!(s.value(), 0.0);
        assert!(s.weight > 0.0);
    }

    #[test]
    fn a_sinusoid_shifted_in_time_has_the_same_spectrum() {
        // a whole number of periods over the window, shifted by 0.3 rad and by
        // a quarter period (where the DFT's real part alone would be 0)
        for phase in [0.3, PI / 2.0, 2.0] {
            let s = npss(&[cosine(40, 3.0, phase)], &[cosine(40, 3.0, 0.0)]);
            assert!(s.value().abs() < 1e-12, "phase {phase}: {}", s.value());
        }
    }

    #[test]
    fn sinusoids_of_other_frequencies_are_their_bins_apart() {
        // cos at bin k puts half its power at k and half at N − k: the
        // cumulative sums differ by ½ over 2·|k₂ − k₁| bins
        for (k1, k2) in [(2.0, 3.0), (1.0, 5.0), (4.0, 2.0)] {
            let s = npss(&[cosine(32, k2, 0.7)], &[cosine(32, k1, 0.0)]);
            assert!(
                (s.value() - (k2 - k1).abs()).abs() < 1e-9,
                "{k1} vs {k2}: {}",
                s.value()
            );
        }
    }

    #[test]
    fn npss_weighs_dimensions_by_the_captures_power() {
        // dimension 0 exact, dimension 1 two bins off with 4× the power (amplitude 2)
        let c = vec![cosine(24, 2.0, 0.0), cosine(24, 1.0, 0.0).map_x(2.0)];
        let f = vec![cosine(24, 2.0, 0.0), cosine(24, 3.0, 0.0)];
        let s = npss(&f, &c);
        assert!((s.value() - 2.0 * 4.0 / 5.0).abs() < 1e-9, "{}", s.value());
        // pooling two windows is the batch's weighted mean
        let mut pooled = s;
        pooled.add(npss(&c, &c));
        assert!((pooled.value() - 8.0 / 10.0).abs() < 1e-9);
    }

    trait Scale {
        fn map_x(self, a: f64) -> Self;
    }
    impl Scale for Vec<f64> {
        fn map_x(self, a: f64) -> Self {
            self.into_iter().map(|x| a * x).collect()
        }
    }

    #[test]
    fn l2q_is_sign_blind_and_the_stacked_norm() {
        let a = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.4);
        let b = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -0.2);
        let neg = UnitQuaternion::new_unchecked(nalgebra::Quaternion::from(-a.coords));
        assert_eq!(l2q_frame(&[neg], &[a]), 0.0);
        // two joints: the norm of the stacked difference
        let d1 = (a.coords - b.coords).norm();
        let id = UnitQuaternion::identity();
        let d2 = (a.coords - id.coords).norm();
        let got = l2q_frame(&[b, id], &[a, a]);
        assert!((got - (d1 * d1 + d2 * d2).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn series_are_continuous_across_a_sign_flip() {
        let qs: Vec<UnitQuaternion<f64>> = (0..20)
            .map(|k| {
                let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 0.1 * k as f64);
                if k % 3 == 0 {
                    UnitQuaternion::new_unchecked(nalgebra::Quaternion::from(-q.coords))
                } else {
                    q
                }
            })
            .collect();
        let s = continuous_series(&qs);
        for w in s[3].windows(2) {
            assert!((w[1] - w[0]).abs() < 0.1, "{w:?}");
        }
    }
}
