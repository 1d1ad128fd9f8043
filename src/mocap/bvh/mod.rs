//! BVH (Biovision hierarchy) files as plain data: a skeleton and a table of
//! channel values, in the file's own units (degrees, file length units).
//!
//! Conversion to radians and metres, and to motion units, happens above this
//! layer (`mocap::to_motion`), so a read → write round trip is lossless.

mod error;
mod euler;
pub mod fk;
mod read;
mod units;
mod unwrap;
mod write;

pub use error::{BvhError, BvhWarning};
pub use euler::{channel_rotation, joint_local_transform};
pub use read::{parse, parse_with_warnings, read_file, read_file_with_warnings};
pub use units::{CMU_UNIT, UnitChoice, Units, detect_units, resolve as resolve_units};
pub use unwrap::{unwrap_degrees, unwrap_degrees_in};
pub use write::{to_string, write_file};

use nalgebra::Vector3;

/// One of the six BVH channel kinds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    Xposition,
    Yposition,
    Zposition,
    Xrotation,
    Yrotation,
    Zrotation,
}

impl Channel {
    /// The name as written in a CHANNELS line (and used in DOF names).
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }

    /// Parses a channel name; BVH writers differ in case, so case is ignored.
    pub fn parse(s: &str) -> Option<Channel> {
        Some(match s.to_ascii_lowercase().as_str() {
            "xposition" => Channel::Xposition,
            "yposition" => Channel::Yposition,
            "zposition" => Channel::Zposition,
            "xrotation" => Channel::Xrotation,
            "yrotation" => Channel::Yrotation,
            "zrotation" => Channel::Zrotation,
            _ => return None,
        })
    }

    pub fn is_rotation(self) -> bool {
        matches!(
            self,
            Channel::Xrotation | Channel::Yrotation | Channel::Zrotation
        )
    }

    /// The axis index 0, 1, 2 for x, y, z.
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }

    /// The unit vector of the channel's axis.
    pub fn axis_vector(self) -> Vector3<f64> {
        let mut v = Vector3::zeros();
        v[self.axis()] = 1.0;
        v
    }
}

/// One joint of the hierarchy (the ROOT included).
#[derive(Clone, Debug, PartialEq)]
pub struct BvhJoint {
    pub name: String,
    /// Index of the parent joint in [`Skeleton::joints`]; `None` for a root.
    pub parent: Option<usize>,
    /// OFFSET, in file units. A position channel replaces the matching component.
    pub offset: Vector3<f64>,
    /// The channels in file order; rotations apply in this order (intrinsic).
    pub channels: Vec<Channel>,
    /// OFFSETs of the End Sites under this joint (usually zero or one).
    pub end_sites: Vec<Vector3<f64>>,
}

/// The HIERARCHY section: joints in file (depth-first) order, so every parent
/// comes before its children.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Skeleton {
    pub joints: Vec<BvhJoint>,
    /// The body's mass properties, one per joint in its own frame (SI), when
    /// the file carries them (a glTF file mx wrote): `body_of` then builds
    /// the body that was saved instead of estimating one. BVH has none.
    pub inertias: Option<Vec<crate::model::Inertia>>,
}

impl Skeleton {
    /// The total mass the file states, if it carries mass properties.
    pub fn stated_mass(&self) -> Option<f64> {
        self.inertias
            .as_ref()
            .map(|v| v.iter().map(|i| i.mass).sum::<f64>())
            .filter(|m| *m > 0.0)
    }
}

impl Skeleton {
    /// Total number of channels in a frame.
    pub fn channel_count(&self) -> usize {
        self.joints.iter().map(|j| j.channels.len()).sum()
    }

    /// Index of the first channel of each joint in a frame row.
    pub fn channel_starts(&self) -> Vec<usize> {
        let mut acc = 0;
        self.joints
            .iter()
            .map(|j| {
                let s = acc;
                acc += j.channels.len();
                s
            })
            .collect()
    }

    /// `Joint.channel` names of every channel, in frame-row order.
    pub fn channel_names(&self) -> Vec<String> {
        self.joints
            .iter()
            .flat_map(|j| {
                j.channels
                    .iter()
                    .map(move |c| format!("{}.{}", j.name, c.name()))
            })
            .collect()
    }

    /// The joint with this name.
    pub fn find(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// Children of joint `i`, in file order.
    pub fn children(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        self.joints
            .iter()
            .enumerate()
            .filter(move |(_, j)| j.parent == Some(i))
            .map(|(k, _)| k)
    }
}

/// A whole BVH file: skeleton, frame time and the values of every channel in
/// every frame, exactly as written (degrees and file units).
#[derive(Clone, Debug, PartialEq)]
pub struct BvhFile {
    pub skeleton: Skeleton,
    /// Seconds per frame (`Frame Time:`), > 0.
    pub frame_time: f64,
    /// Row-major: frame `f`, channel `c` is `values[f * channels + c]`.
    pub values: Vec<f64>,
}

impl BvhFile {
    pub fn frame_count(&self) -> usize {
        let n = self.skeleton.channel_count();
        self.values.len().checked_div(n).unwrap_or(0)
    }

    /// The values of one frame.
    pub fn frame(&self, f: usize) -> &[f64] {
        let n = self.skeleton.channel_count();
        &self.values[f * n..(f + 1) * n]
    }

    /// The column of channel `c` over all frames.
    pub fn column(&self, c: usize) -> Vec<f64> {
        let n = self.skeleton.channel_count();
        self.values
            .iter()
            .skip(c)
            .step_by(n.max(1))
            .copied()
            .collect()
    }

    /// Replaces column `c`.
    pub fn set_column(&mut self, c: usize, col: &[f64]) {
        let n = self.skeleton.channel_count();
        for (f, v) in col.iter().enumerate() {
            self.values[f * n + c] = *v;
        }
    }

    /// Unwraps every rotation channel in place so that consecutive frames never
    /// differ by more than 180°; values stay equal to the file's modulo 360°.
    /// Returns how many wraps were removed.
    pub fn unwrap_rotations(&mut self) -> usize {
        let mut wraps = 0;
        let n = self.skeleton.channel_count().max(1);
        let kinds = self.skeleton.joints.iter().flat_map(|j| j.channels.iter());
        for (c, kind) in kinds.enumerate() {
            if kind.is_rotation() {
                // In place down the column: copying each column out and back
                // was a tenth of a load.
                wraps += unwrap_degrees_in(self.values.iter_mut().skip(c).step_by(n));
            }
        }
        wraps
    }
}
