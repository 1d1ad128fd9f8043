//! When each contact point touches the floor: within `height` of it and
//! moving horizontally slower than `speed`, frame by frame at the motion's
//! frame rate; runs of such frames are the contact intervals.

use super::GroundError;
use super::points::{GroundOptions, Tracks, contact_points, tracks};
use super::stance::in_stance;
use crate::model::Model;
use crate::motion::Mu;
use nalgebra::Vector3;

/// One run of frames in contact, ends included.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactInterval {
    /// First and last frame index in contact.
    pub first: usize,
    pub last: usize,
    /// Their times (s).
    pub start: f64,
    pub stop: f64,
}

/// A point's contacts.
#[derive(Clone, Debug, PartialEq)]
pub struct PointContacts {
    pub name: String,
    /// Link index in the body.
    pub link: usize,
    /// Per frame: on the floor.
    pub in_contact: Vec<bool>,
    pub intervals: Vec<ContactInterval>,
}

/// Every contact point's contacts over a motion.
#[derive(Clone, Debug, PartialEq)]
pub struct Contacts {
    /// The floor height along `up` (m).
    pub floor: f64,
    pub up: Vector3<f64>,
    pub times: Vec<f64>,
    pub frame_time: f64,
    pub points: Vec<PointContacts>,
}

/// The runs of `true` in `flags`: (first, last) index, inclusive. The one
/// rule for "runs of flags" that `contacts()` and SP's plans share.
pub fn runs_of(flags: &[bool]) -> Vec<(usize, usize)> {
    let mut out = vec![];
    let mut k = 0;
    while k < flags.len() {
        if !flags[k] {
            k += 1;
            continue;
        }
        let first = k;
        while k + 1 < flags.len() && flags[k + 1] {
            k += 1;
        }
        out.push((first, k));
        k += 1;
    }
    out
}

/// Runs of `true` in `flags` as intervals over `times`.
pub fn runs(flags: &[bool], times: &[f64]) -> Vec<ContactInterval> {
    runs_of(flags)
        .into_iter()
        .map(|(first, last)| ContactInterval {
            first,
            last,
            start: times[first],
            stop: times[last],
        })
        .collect()
}

/// Contacts from tracks already sampled (SP's contact schedule reuses them).
pub fn contacts_of_tracks(tr: &Tracks, opts: &GroundOptions) -> Result<Contacts, GroundError> {
    opts.check()?;
    let floor = tr.floor(opts.floor);
    let points = tr
        .points
        .iter()
        .enumerate()
        .map(|(j, p)| {
            let in_contact: Vec<bool> = (0..tr.times.len())
                .map(|k| {
                    in_stance(
                        tr.height(k, j) - floor,
                        tr.speed(k, j),
                        opts.height,
                        opts.speed,
                    )
                })
                .collect();
            PointContacts {
                name: p.name.clone(),
                link: p.link,
                intervals: runs(&in_contact, &tr.times),
                in_contact,
            }
        })
        .collect();
    Ok(Contacts {
        floor,
        up: tr.up,
        times: tr.times.clone(),
        frame_time: tr.frame_time,
        points,
    })
}

/// Where each contact point of `body` touches the floor over `m`.
pub fn contacts(m: &Mu, body: &Model, opts: &GroundOptions) -> Result<Contacts, GroundError> {
    let pts = contact_points(body, opts.points.as_deref())?;
    let tr = tracks(m, body, &pts, opts)?;
    contacts_of_tracks(&tr, opts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_of_flags() {
        let t: Vec<f64> = (0..6).map(|k| k as f64 * 0.1).collect();
        let r = runs(&[true, true, false, false, true, true], &t);
        assert_eq!(r.len(), 2);
        assert_eq!((r[0].first, r[0].last), (0, 1));
        assert_eq!((r[1].first, r[1].last), (4, 5));
        assert!((r[1].stop - 0.5).abs() < 1e-12);
        assert!(runs(&[false, false], &t[..2]).is_empty());
    }
}
