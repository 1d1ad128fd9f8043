//! Every window of every clip under every method, in parallel over windows,
//! each window's methods one after the other on one thread so their times
//! compare; SP rows with the same options solved once per window.

use super::case::Case;
use super::methods::Method;
use super::protocol::{Protocol, RootMode};
use super::window::{WindowResult, run_window};
use crate::report::error::ReportError;

/// Every window of every case under every method (methods side by side on
/// the same windows), in parallel over windows (rayon; `RAYON_NUM_THREADS=1`
/// for one thread). Each window's methods run one after the other on one
/// thread, so their times compare; the results, in window order, do not
/// depend on the number of threads. SP rows whose options are the same
/// ([`same_options`]) are solved once per window and copied under each label.
pub fn run(
    cases: &[Case],
    p: &Protocol,
    methods: &[Method],
    progress: impl Fn(&WindowResult) + Sync,
) -> Result<Vec<WindowResult>, ReportError> {
    use rayon::prelude::*;
    let mut windows = vec![];
    for &root in &p.roots {
        for &gap in &p.gaps {
            for case in cases {
                for start in case.windows(p, gap) {
                    windows.push((root, gap, case, start));
                }
            }
        }
    }
    let firsts = [RootMode::Given, RootMode::Filled].map(|r| same_options(methods, r));
    let per_window: Vec<Result<Vec<WindowResult>, ReportError>> = windows
        .par_iter()
        .map(|&(root, gap, case, start)| {
            let mut rows: Vec<WindowResult> = Vec::with_capacity(methods.len());
            for (i, m) in methods.iter().enumerate() {
                let r = match firsts[usize::from(root == RootMode::Filled)][i] {
                    Some(j) => WindowResult {
                        method: m.label().to_string(),
                        ..rows[j].clone()
                    },
                    None => run_window(case, p, start, gap, root, m)?,
                };
                progress(&r);
                rows.push(r);
            }
            Ok(rows)
        })
        .collect();
    let mut out = Vec::with_capacity(windows.len() * methods.len());
    for rows in per_window {
        out.extend(rows?);
    }
    Ok(out)
}

/// For each method, the index of an earlier SP method with the same options
/// (their `Debug` text), whose result it shares; `None`: solve it. Only
/// [`Method::Sp`] rows share (a library row's options are filled per
/// window, and so are the capture's contacts). With the root given no root
/// channel is cut, so `root:` is moot and left out of the comparison.
pub fn same_options(methods: &[Method], root: RootMode) -> Vec<Option<usize>> {
    let keys: Vec<Option<String>> = methods
        .iter()
        .map(|m| match m {
            Method::Sp(_, o) => {
                let mut o = (**o).clone();
                if root == RootMode::Given {
                    o.root = crate::spacetime::RootFill::default();
                }
                Some(format!("{o:?}"))
            }
            _ => None,
        })
        .collect();
    keys.iter()
        .enumerate()
        .map(|(i, k)| {
            let k = k.as_ref()?;
            keys[..i].iter().position(|e| e.as_ref() == Some(k))
        })
        .collect()
}
