//! Transition points between two clips (Kovar, Gleicher & Pighin 2002, §3.1):
//! frame i of a and frame j of b compared as the joint point clouds of the
//! `window` frames centred on them, after the ground-plane motion that best
//! aligns b's cloud with a's; the distance is the root-mean-square distance
//! of matched points (metres). The candidates are the local minima of the
//! distance over (i, j) below the threshold, best first.

use super::planar::{Planar, fit, rms_after};
use nalgebra::Vector3;

/// A chosen transition point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Last frame of a played before the transition.
    pub i: usize,
    /// First frame of b played after it.
    pub j: usize,
    /// RMS point distance over the window (m).
    pub distance: f64,
    /// The motion that carries b's window onto a's.
    pub align: Planar,
}

/// What the search found for one pair.
#[derive(Clone, Debug)]
pub struct Found {
    pub points: Vec<Point>,
    /// The smallest distance over every (i, j), even above the threshold.
    pub best: f64,
}

/// Distance of a's window at i and b's window at j, with the alignment.
fn window_distance(
    a: &[Vec<Vector3<f64>>],
    b: &[Vec<Vector3<f64>>],
    i: usize,
    j: usize,
    half: usize,
    pa: &mut Vec<Vector3<f64>>,
    pb: &mut Vec<Vector3<f64>>,
) -> (f64, Planar) {
    pa.clear();
    pb.clear();
    for k in 0..=2 * half {
        pa.extend_from_slice(&a[i + k - half]);
        pb.extend_from_slice(&b[j + k - half]);
    }
    let t = fit(pa, pb);
    (rms_after(pa, pb, &t), t)
}

/// The best `k` transition points from a (frames `a`) to b (frames `b`)
/// with windows of `window` frames (odd; an even one is widened by one),
/// whose distance is at most `threshold`. Frames too near either end for a
/// whole window are not candidates. Ties are broken by (i, j), so the result
/// is the same on every run.
pub fn search(
    a: &[Vec<Vector3<f64>>],
    b: &[Vec<Vector3<f64>>],
    window: usize,
    k: usize,
    threshold: f64,
) -> Found {
    let half = window / 2;
    let (na, nb) = (a.len(), b.len());
    if na < 2 * half + 1 || nb < 2 * half + 1 || k == 0 {
        return Found {
            points: vec![],
            best: f64::INFINITY,
        };
    }
    let (ri, rj) = (half..na - half, half..nb - half);
    let (wi, wj) = (ri.len(), rj.len());
    let mut d = vec![0.0; wi * wj];
    let mut al = vec![Planar::IDENTITY; wi * wj];
    let (mut pa, mut pb) = (vec![], vec![]);
    for (x, i) in ri.clone().enumerate() {
        for (y, j) in rj.clone().enumerate() {
            let (dist, t) = window_distance(a, b, i, j, half, &mut pa, &mut pb);
            d[x * wj + y] = dist;
            al[x * wj + y] = t;
        }
    }
    let best = d.iter().copied().fold(f64::INFINITY, f64::min);
    let mut minima = vec![];
    for x in 0..wi {
        for y in 0..wj {
            let v = d[x * wj + y];
            if v > threshold {
                continue;
            }
            // a local minimum over the 8 neighbours (ties: the first in (i, j) order wins)
            let mut is_min = true;
            'n: for dx in -1i64..=1 {
                for dy in -1i64..=1 {
                    let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                    if (dx, dy) == (0, 0) || nx < 0 || ny < 0 || nx >= wi as i64 || ny >= wj as i64
                    {
                        continue;
                    }
                    let w = d[nx as usize * wj + ny as usize];
                    let earlier = (dx, dy) < (0, 0);
                    if w < v || (w == v && earlier) {
                        is_min = false;
                        break 'n;
                    }
                }
            }
            if is_min {
                minima.push(Point {
                    i: ri.start + x,
                    j: rj.start + y,
                    distance: v,
                    align: al[x * wj + y],
                });
            }
        }
    }
    minima.sort_by(|p, q| {
        p.distance
            .total_cmp(&q.distance)
            .then((p.i, p.j).cmp(&(q.i, q.j)))
    });
    minima.truncate(k);
    Found {
        points: minima,
        best,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A walking-like cloud: 5 points moving along x with a sway.
    fn clip(frames: usize, phase: f64) -> Vec<Vec<Vector3<f64>>> {
        (0..frames)
            .map(|f| {
                let t = f as f64 / 30.0 + phase;
                (0..5)
                    .map(|k| {
                        let k = k as f64;
                        Vector3::new(
                            t + 0.1 * k,
                            0.2 * k + 0.05 * (6.0 * t).sin(),
                            0.1 * (3.0 * t + k).cos(),
                        )
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn finds_the_frame_where_a_copy_of_the_motion_matches() {
        let a = clip(60, 0.0);
        // b is a's motion from 0.5 s on, turned and moved elsewhere on the floor
        let t = Planar {
            turn: 1.0,
            x: 3.0,
            z: -2.0,
        };
        let b: Vec<Vec<Vector3<f64>>> = clip(60, 0.5)
            .into_iter()
            .map(|f| f.iter().map(|p| t.apply(p)).collect())
            .collect();
        let found = search(&a, &b, 5, 1, 0.05);
        let p = found.points[0];
        // a's frame 15 + m is b's frame m
        assert_eq!(p.i, p.j + 15, "{p:?}");
        assert!(p.distance < 1e-9);
        // the alignment undoes t
        let back = p.align.then_after(&t);
        assert!(
            back.turn.abs() < 1e-9 && back.x.abs() < 1e-9 && back.z.abs() < 1e-9,
            "{back:?}"
        );
        // nothing below a threshold of zero... except exact matches; a far threshold keeps more
        assert!(search(&a, &b, 5, 3, -1.0).points.is_empty());
    }
}
