//! The built-in functions, one file per domain (`core.rs`, `motion.rs`,
//! `strings.rs`, `compose.rs`, `ik.rs`, `joints.rs`, `spline_joints.rs`, `links.rs`,
//! `mechanics.rs`, `dynamics.rs`, `mocap.rs`, `view.rs`, `ground.rs`, `opensim.rs`,
//! `spacetime.rs`, `score.rs`, `library.rs`). Each is a leaf: it imports [`Args`], [`Value`], the host
//! types it converts (`lang::host`) and the engine, and nothing of its
//! siblings, and registers its functions under their `:help` topic with one
//! line per function:
//!
//! ```
//! let mut reg = mx::lang::Registry::new();
//! reg.add("sin(x)", "Sine of x (radians).", |a, _| Ok(a.number("x")?.sin().into()));
//! ```
//!
//! The framework (`Registry`, `Args`) lives in `lang/registry.rs` and
//! `lang/args.rs`; it is re-exported here for the paths embedders use.

pub mod compose;
pub mod core;
pub mod dynamics;
pub mod ground;
pub mod ik;
pub mod joints;
pub mod library;
pub mod links;
pub mod mechanics;
pub mod mocap;
pub mod motion;
pub mod opensim;
pub mod score;
pub mod spacetime;
pub mod spline_joints;
pub mod strings;
pub mod view;

pub use crate::lang::args::{ArgValue, Args, ObjRef, describe};
pub use crate::lang::eval::{BuiltinFn, LoadFn, SaveFn};
pub use crate::lang::host::{body, sp_report};
pub use crate::lang::registry::{Format, Registry};
pub use crate::lang::value::{Builtin, Value};

impl Registry {
    /// The registry with every domain's built-ins.
    pub fn standard() -> Self {
        let mut r = Registry::new();
        core::register(&mut r);
        strings::register(&mut r);
        motion::register(&mut r);
        compose::register(&mut r);
        ik::register(&mut r);
        joints::register(&mut r);
        spline_joints::register(&mut r);
        links::register(&mut r);
        mechanics::register(&mut r);
        dynamics::register(&mut r);
        mocap::register(&mut r);
        view::register(&mut r);
        ground::register(&mut r);
        opensim::register(&mut r);
        spacetime::register(&mut r);
        score::register(&mut r);
        library::register(&mut r);
        // Functions an embedder registers later are listed with the language.
        r.topic(crate::lang::topic::Topic::Language);
        r
    }
}
