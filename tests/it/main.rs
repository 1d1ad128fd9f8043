//! The integration tests, one binary (one link of the library instead of one per
//! file: #16). Each module is one former `tests/NAME.rs`; run one with
//! `cargo test --test it NAME::`. Modules that need the `report` feature are
//! compiled with it only.

mod common;
mod contact_plans;
mod support;

mod blender_addon;
mod bvh_malformed;
mod bvh_shared;
mod cli;
mod doc_blocks;
#[cfg(feature = "report")]
mod dynamics;
mod dynamics_lang;
mod dynamics_points;
mod dynamics_sim;
mod first_hour;
mod gltf;
mod gltf_forces;
mod graph;
mod ground;
mod ground_forces;
mod grounded_terms;
#[cfg(feature = "report")]
mod hard_cases;
mod ik;
#[cfg(feature = "report")]
mod inbetween;
mod inbetween_heldout;
mod joints;
mod joints_lang;
mod knee_pendulum;
mod lang_compose;
mod lang_diagnostics;
mod lang_fuzz;
mod lang_isolation;
mod lang_motion;
mod lang_records_strings;
mod layers;
mod library;
mod library_labels;
mod library_shards;
mod library_stretch;
mod lie;
mod mechanisms;
mod mocap_body;
#[cfg(feature = "report")]
mod mocap_examples_data;
mod mocap_human;
mod mocap_lang;
mod mocap_motion;
mod mocap_plot;
mod motion_algebra;
mod motion_compose;
mod motion_io;
mod motion_laws;
mod motion_mocap;
mod motion_props;
mod opensim_couplers;
mod opensim_example;
mod opensim_files;
mod opensim_gcvspline;
mod opensim_knee;
#[cfg(feature = "report")]
mod opensim_knee_fit;
mod opensim_leg_pendulum;
mod opensim_model;
mod opensim_sp;
mod pinocchio;
mod public_surface;
mod reference;
mod repl_pty;
#[cfg(feature = "report")]
mod report_smoke;
#[cfg(feature = "report")]
mod score;
#[cfg(feature = "report")]
mod spacetime_contact;
mod spacetime_cyclify;
mod spacetime_human44;
mod spacetime_lang;
mod spacetime_motion;
mod spacetime_support;
#[cfg(feature = "report")]
mod spacetime_zup;
mod spline;
mod state_cache;
mod typed_errors;
mod urdf_mimic;
mod viewer_chromium;
mod viewer_ground;
