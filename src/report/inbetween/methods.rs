//! The ways of filling a gap the benchmark compares, and the lists of them
//! it runs: the interpolations, the capture itself, SP at its defaults and
//! as it was before grounded SP, SP with contacts planned, SP following the
//! capture's own contacts (the upper bound of any plan), one row per knob
//! of SP's objective, and SP following a held-out clip library.

use crate::report::leave_one_out::LeaveOneOut;
use crate::spacetime::{Contact, Prior, RootFill, SpOptions, Support};
use std::sync::Arc;

/// A way of filling the gaps.
#[derive(Clone, Debug)]
pub enum Method {
    Hermite,
    Slerp,
    /// The captured frames themselves: L2P 0 by definition; the row tells
    /// what a person's motion costs in ∫Στ² against the interpolations.
    Capture,
    /// SP with these options, under this label.
    Sp(String, Box<SpOptions>),
    /// SP with these options and, as the example's library, every clip of
    /// the folder but the window's own file ([`LeaveOneOut`]).
    SpLibrary(String, Box<SpOptions>, Arc<LeaveOneOut>),
    /// SP with these options and `contact:` the capture's own contacts
    /// (`contacts(c, b)`, each stance's `at:` where the capture's point stood:
    /// `score::given_contacts`): the plan no planner can beat.
    SpCaptureContacts(String, Box<SpOptions>),
}

impl Method {
    pub fn label(&self) -> &str {
        match self {
            Method::Hermite => "fill hermite",
            Method::Slerp => "fill slerp",
            Method::Capture => "capture (the answer)",
            Method::Sp(l, _) | Method::SpLibrary(l, _, _) | Method::SpCaptureContacts(l, _) => l,
        }
    }
}

/// Label of SP at its defaults, the row issue 35's goals judge.
pub const SP_DEFAULTS: &str = "SP defaults";
/// Label of [`todays_sp`].
pub const TODAYS_SP: &str = "today's SP";
/// Label of SP following the capture's own contacts.
pub const SP_CAPTURE_CONTACTS: &str = "SP with the capture's contacts (upper bound)";

/// SP as it was before grounded SP changed the defaults: no contact
/// planning (`contact: "none"`), the kinematic root (`root: "pinned"`: the
/// frames after a cut root stay where they were captured, the root's x–z
/// a cubic between the sides) and the prior at its old weight with the
/// motion's own example. Every option that reproduces the old behaviour is
/// set here explicitly, so the row stays the "before" when a default moves
/// (the BOARD of issues 35/36 keeps this list).
pub fn todays_sp() -> SpOptions {
    SpOptions {
        contact: Contact::None,
        root: RootFill::Pinned,
        support: Support::Auto { box_size: 0.02 },
        prior: Prior {
            smoothness: 1e6,
            time_constant: None,
            example: true,
            anchor: false,
        },
        ..Default::default()
    }
}

/// The methods the benchmark and the report compare, on the same windows:
/// the two interpolation baselines, the capture itself (the reference row),
/// SP at its defaults, SP as it was before grounded SP ([`todays_sp`]), with
/// foot contact planned (`contact: "auto"`) and with the capture's own
/// contacts (the upper bound of any contact plan).
pub fn methods() -> Vec<Method> {
    vec![
        Method::Hermite,
        Method::Slerp,
        Method::Capture,
        Method::Sp(SP_DEFAULTS.into(), Box::default()),
        Method::Sp(TODAYS_SP.into(), Box::new(todays_sp())),
        Method::Sp("SP contact: \"auto\"".into(), Box::new(stated_auto())),
        Method::SpCaptureContacts(SP_CAPTURE_CONTACTS.into(), Box::default()),
    ]
}

/// `contact: "auto"` stated, as `SP(m, body: b, contact: "auto")` gives it:
/// a given root stands too (`GroundSettings::stand_root_given`).
fn stated_auto() -> SpOptions {
    let mut o = SpOptions {
        contact: Contact::Auto,
        ..Default::default()
    };
    o.ground.stand_root_given = true;
    o
}

/// A row for each knob of SP's objective (`MX_INBETWEEN_KNOBS=1` in the
/// bench): Rose's ∫Στ² alone (`objective: "torque"`), the prior without the
/// example, the prior's weight (`smoothness:`), its time constant
/// (`time_constant:`, fixed instead of (0.32 s)²/gap), and SP without
/// support IK; each otherwise at the defaults.
pub fn knob_methods() -> Vec<Method> {
    let sp = |label: &str, o: SpOptions| Method::Sp(label.into(), Box::new(o));
    let with_prior = |prior: Prior| SpOptions {
        prior,
        ..Default::default()
    };
    let prior = |f: &dyn Fn(&mut Prior)| {
        let mut p = Prior::default();
        f(&mut p);
        with_prior(p)
    };
    vec![
        sp("SP objective: \"torque\" (Rose)", with_prior(Prior::none())),
        sp("SP example: \"none\"", prior(&|p| p.example = false)),
        sp("SP smoothness: 1e3", prior(&|p| p.smoothness = 1e3)),
        sp(
            "SP time_constant: 0.1s",
            prior(&|p| p.time_constant = Some(0.1)),
        ),
        sp(
            "SP time_constant: 0.3s",
            prior(&|p| p.time_constant = Some(0.3)),
        ),
        sp(
            "SP support: []",
            SpOptions {
                support: Support::Off,
                ..Default::default()
            },
        ),
    ]
}

/// Label of SP following the leave-one-out library alone (issue 36's goals).
pub const SP_LIBRARY: &str = "SP example: lib (leave-one-out)";
/// Label of SP following `[lib, "self"]` (issue 36's goals).
pub const SP_LIBRARY_SELF: &str = "SP example: [lib, \"self\"] (leave-one-out)";

/// The rows that follow a clip library held out from the window's own file
/// (`MX_INBETWEEN_LIBRARY=1` in the bench): SP with `example: lib` and with
/// `example: [lib, "self"]`, lib every clip of the folder but the window's.
pub fn library_methods(libraries: Arc<LeaveOneOut>) -> Vec<Method> {
    let with = |label: &str, example_self: bool| {
        let o = SpOptions {
            prior: Prior {
                example: example_self,
                ..Prior::default()
            },
            ..Default::default()
        };
        Method::SpLibrary(label.into(), Box::new(o), libraries.clone())
    };
    vec![with(SP_LIBRARY, false), with(SP_LIBRARY_SELF, true)]
}
