//! The graph's errors, typed: what the build's flags, clip loading, the root
//! search and one transition's fill can get wrong. Texts are sentences for
//! the user; the variants let callers tell an option from a clip from SP.

use crate::mocap::MocapError;
use crate::mocap::bvh::BvhError;
use crate::motion::MotionError;
use crate::shard::ShardError;
use crate::spacetime::SpError;

/// An error of a library build, merge or walk.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GraphError {
    /// A sentence for the user (folder layout, store, merge, walk).
    #[error("{0}")]
    Message(String),
    /// A build setting out of range; `option` is the flag without `--`.
    #[error("{message}")]
    InvalidOption {
        option: &'static str,
        message: String,
    },
    /// `--shard i/n` that is not a shard, or Slurm's array variables that
    /// do not name one.
    #[error(transparent)]
    Shard(#[from] ShardError),
    /// The library's root joint cannot be moved on the floor.
    #[error(transparent)]
    Root(#[from] RootError),
}

impl GraphError {
    pub fn new(msg: impl Into<String>) -> GraphError {
        GraphError::Message(msg.into())
    }

    /// The flag of an invalid build setting (`"k"`, `"window"`, …).
    pub fn option(&self) -> Option<&'static str> {
        match self {
            GraphError::InvalidOption { option, .. } => Some(option),
            GraphError::Shard(_) => Some("shard"),
            _ => None,
        }
    }
}

/// Why a clip could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ClipError {
    #[error(transparent)]
    Bvh(#[from] BvhError),
    #[error(transparent)]
    Mocap(#[from] MocapError),
}

/// Why the library's skeleton has no root the floor moves can act on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RootError {
    #[error("the skeleton has no root joint")]
    NoRoot,
    #[error(
        "the still joint `{joint}` above the root is rotated ({channel} = {value}°): turning such a skeleton on the floor is not supported"
    )]
    RotatedStill {
        joint: String,
        channel: String,
        value: f64,
    },
    #[error(
        "the root joint `{0}` needs X, Y and Z position and three rotation channels to be turned and moved on the floor"
    )]
    Channels(String),
}

/// Why one transition could not be filled.
#[derive(Debug, thiserror::Error)]
pub enum TransitionError {
    #[error(
        "no context around the transition (a frame {i} of {a_frames}, b frame {j} of {b_frames})"
    )]
    NoContext {
        i: usize,
        a_frames: usize,
        j: usize,
        b_frames: usize,
    },
    #[error("b's frames: {0}")]
    Frames(MocapError),
    #[error(transparent)]
    Motion(#[from] MotionError),
    #[error("cannot start SP's thread: {0}")]
    Thread(String),
    #[error("SP: {0}")]
    Sp(SpError),
    #[error("torque energy: {0}")]
    Energy(SpError),
    #[error("writing the transition: {0}")]
    Write(MocapError),
    #[error("the transition has {got} frames, expected {want}")]
    FrameCount { got: usize, want: usize },
}
