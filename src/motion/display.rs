//! One-line summaries of motions (what `print(m)` and the REPL show).
//! Numbers use the shared shortest round-trip form ([`crate::fmt_num`]).

use std::fmt;

use crate::fmt_num::Rounded;

use super::dof::Dof;
use super::interval::Interval;
use super::mu::Mu;

fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        format!("1 {word}")
    } else {
        format!("{n} {word}s")
    }
}

impl fmt::Display for Interval {
    /// `interval([0, 2.4], 1 function)`; several functions are a conflict.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "interval([{}, {}], {}",
            Rounded(self.start),
            Rounded(self.stop),
            plural(self.funcs.len(), "function")
        )?;
        if self.is_conflict() {
            write!(f, ", conflict")?;
        }
        write!(f, ")")
    }
}

impl fmt::Display for Dof {
    /// `dof(3 intervals over [0, 10], 2 gaps, 1 conflict)` or `dof(empty)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.span() {
            None => write!(f, "dof(empty)"),
            Some((a, b)) => {
                write!(
                    f,
                    "dof({} over [{}, {}]",
                    plural(self.intervals.len(), "interval"),
                    Rounded(a),
                    Rounded(b)
                )?;
                summary_tail(f, self.gaps().len(), self.conflicts().len())
            }
        }
    }
}

impl fmt::Display for Mu {
    /// `mu(60 DOFs over [0, 60], 12 gaps, 1 conflict)` or `mu(2 DOFs, empty)`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let n = plural(self.len(), "DOF");
        match self.span() {
            None => write!(f, "mu({n}, empty)"),
            Some((a, b)) => {
                write!(f, "mu({n} over [{}, {}]", Rounded(a), Rounded(b))?;
                let gaps = self.dofs.values().map(|d| d.gaps().len()).sum();
                let conflicts = self.dofs.values().map(|d| d.conflicts().len()).sum();
                summary_tail(f, gaps, conflicts)
            }
        }
    }
}

fn summary_tail(f: &mut fmt::Formatter<'_>, gaps: usize, conflicts: usize) -> fmt::Result {
    if gaps > 0 {
        write!(f, ", {}", plural(gaps, "gap"))?;
    }
    if conflicts > 0 {
        write!(f, ", {}", plural(conflicts, "conflict"))?;
    }
    write!(f, ")")
}

#[cfg(test)]
mod tests {
    use crate::motion::*;

    #[test]
    fn summaries() {
        let i = Interval::constant(1.0, 0.0, 2.4).unwrap();
        assert_eq!(i.to_string(), "interval([0, 2.4], 1 function)");
        let d = Dof::new(vec![
            i.clone(),
            Interval::constant(2.0, 1.0, 3.0).unwrap(),
            Interval::constant(0.0, 4.0, 5.0).unwrap(),
        ])
        .unwrap();
        assert_eq!(
            d.to_string(),
            "dof(4 intervals over [0, 5], 1 gap, 1 conflict)"
        );
        assert_eq!(
            d.intervals[1].to_string(),
            "interval([1, 2.4], 2 functions, conflict)"
        );
        assert_eq!(Dof::empty().to_string(), "dof(empty)");
        let mut m = Mu::new();
        m.insert("a", d);
        m.insert("b", Dof::from(Interval::constant(0.0, -1.0, 0.5).unwrap()));
        assert_eq!(m.to_string(), "mu(2 DOFs over [-1, 5], 1 gap, 1 conflict)");
        assert_eq!(Mu::new().to_string(), "mu(0 DOFs, empty)");
    }
}
