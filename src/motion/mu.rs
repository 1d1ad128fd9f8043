//! Motion units: named DOFs in the order they were first defined.

use indexmap::IndexMap;

use super::dof::Dof;
use super::error::MotionError;

/// A motion unit: DOF name → DOF, in first-definition order (the CSV column
/// order). A DOF the MU does not name is undefined everywhere in it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mu {
    pub dofs: IndexMap<String, Dof>,
}

impl Mu {
    pub fn new() -> Mu {
        Mu::default()
    }

    /// Add or replace a DOF (a replaced DOF keeps its position).
    pub fn insert(&mut self, name: impl Into<String>, dof: Dof) {
        self.dofs.insert(name.into(), dof);
    }

    pub fn get(&self, name: &str) -> Option<&Dof> {
        self.dofs.get(name)
    }

    /// The DOF called `name`, or an error suggesting the closest name.
    pub fn dof(&self, name: &str) -> Result<&Dof, MotionError> {
        self.dofs.get(name).ok_or_else(|| MotionError::UnknownDof {
            name: name.to_string(),
            suggestion: closest(name, self.dofs.keys().map(String::as_str)),
        })
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.dofs.keys().map(String::as_str)
    }

    pub fn len(&self) -> usize {
        self.dofs.len()
    }

    /// No DOF at all (a MU with only empty DOFs is not `is_empty` but has no span).
    pub fn is_empty(&self) -> bool {
        self.dofs.is_empty()
    }

    /// Earliest start and latest stop over all DOFs; `None` if nothing is defined.
    pub fn span(&self) -> Option<(f64, f64)> {
        self.dofs
            .values()
            .filter_map(Dof::span)
            .reduce(|a, b| (a.0.min(b.0), a.1.max(b.1)))
    }

    /// Total number of intervals (a size measure for summaries and budgets).
    pub fn interval_count(&self) -> usize {
        self.dofs.values().map(|d| d.intervals.len()).sum()
    }
}

impl FromIterator<(String, Dof)> for Mu {
    fn from_iter<I: IntoIterator<Item = (String, Dof)>>(iter: I) -> Mu {
        Mu {
            dofs: iter.into_iter().collect(),
        }
    }
}

/// The candidate with the smallest edit distance, if it is close enough to be a likely typo.
pub(crate) fn closest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    let lower = name.to_lowercase();
    candidates
        .map(|c| (levenshtein(&lower, &c.to_lowercase()), c))
        .filter(|(d, c)| *d <= (c.chars().count().max(name.chars().count()) / 3).max(1))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c.to_string())
}

fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != *cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}
