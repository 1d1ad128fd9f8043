//! Skeletons of the clips loaded in this process, so that a motion unit
//! (which holds only DOFs) can be written back to BVH or given a body
//! without the user carrying the skeleton around: the most recently loaded
//! skeleton whose channels include every DOF of the motion is used.
//! Bounded (the last [`KEEP`] skeletons); identical skeletons are kept once.

use super::bvh::Skeleton;
use crate::motion::Mu;
use std::sync::{Arc, Mutex};

/// How many skeletons are remembered.
pub const KEEP: usize = 64;

/// A remembered skeleton with the scale and frame time of its clip.
#[derive(Clone, Debug)]
pub struct Known {
    pub skeleton: Arc<Skeleton>,
    pub metres_per_unit: f64,
    pub frame_time: f64,
}

static KNOWN: Mutex<Vec<Known>> = Mutex::new(Vec::new());

/// Remembers the skeleton of a loaded clip.
pub fn remember(skeleton: &Skeleton, metres_per_unit: f64, frame_time: f64) {
    let Ok(mut k) = KNOWN.lock() else { return };
    k.retain(|x| *x.skeleton != *skeleton);
    k.push(Known {
        skeleton: Arc::new(skeleton.clone()),
        metres_per_unit,
        frame_time,
    });
    if k.len() > KEEP {
        let extra = k.len() - KEEP;
        k.drain(..extra);
    }
}

/// The most recent skeleton whose channels name every DOF of `mu`.
pub fn find_for(mu: &Mu) -> Option<Known> {
    let k = KNOWN.lock().ok()?;
    k.iter()
        .rev()
        .find(|x| {
            let names = x.skeleton.channel_names();
            mu.names().all(|n| names.iter().any(|c| c == n))
        })
        .cloned()
}
