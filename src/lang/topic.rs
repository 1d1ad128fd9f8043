//! The groups `:help` and `docs/reference.md` list the built-ins in. Each
//! built-in carries the topic its domain registered it under
//! ([`super::registry::Registry::topic`]).

/// A group of built-ins, in the order `:help` shows them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Topic {
    /// Numbers, strings, lists, records, functions, errors.
    #[default]
    Language,
    /// Intervals, DOFs, motion units and the animator's operators.
    Motion,
    /// SP, gap filling, cyclification.
    Spacetime,
    /// The joint library and spline joints.
    Joints,
    /// Bodies, dynamics, scenes, motion capture models.
    Dynamics,
    /// `load`, `save`, file formats, plots and viewers.
    Files,
}

impl Topic {
    /// Every topic in display order.
    pub const ALL: [Topic; 6] = [
        Topic::Language,
        Topic::Motion,
        Topic::Spacetime,
        Topic::Joints,
        Topic::Dynamics,
        Topic::Files,
    ];

    /// The word `:help TOPIC` takes.
    pub fn key(self) -> &'static str {
        match self {
            Topic::Language => "language",
            Topic::Motion => "motion",
            Topic::Spacetime => "spacetime",
            Topic::Joints => "joints",
            Topic::Dynamics => "dynamics",
            Topic::Files => "files",
        }
    }

    /// The heading shown above the group.
    pub fn title(self) -> &'static str {
        match self {
            Topic::Language => "Language",
            Topic::Motion => "Motion",
            Topic::Spacetime => "Spacetime",
            Topic::Joints => "Joints",
            Topic::Dynamics => "Bodies and dynamics",
            Topic::Files => "Files",
        }
    }

    /// The topic a `:help` word names (`bodies` is an alias of `dynamics`).
    pub fn parse(word: &str) -> Option<Topic> {
        let w = word.trim().to_ascii_lowercase();
        if w == "bodies" {
            return Some(Topic::Dynamics);
        }
        Topic::ALL.into_iter().find(|t| t.key() == w)
    }
}
