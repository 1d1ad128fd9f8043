//! A deterministic share of a long job for one of several processes: item k
//! of a sorted list belongs to shard k mod n, so shares are fixed by the list
//! alone and balanced to within one item. The share is `--shard i/n`, else
//! Slurm's job-array variables, else the whole list. `mx graph build` shares
//! its clip pairs this way, `mx library build` its clip files.

use indicatif::{ProgressBar, ProgressStyle};
use std::fmt;

/// Shard `index` of `count`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

/// Why a shard could not be told: a `--shard` that is not one, or Slurm's
/// array variables that do not name one.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShardError {
    #[error(
        "bad shard `{given}`: {why}; write i/n with 0 <= i < n, e.g. --shard 0/3 for the first of three"
    )]
    Bad { given: String, why: String },
    #[error("{0}")]
    Slurm(String),
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl Shard {
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// `i/n` with 0 <= i < n.
    pub fn parse(s: &str) -> Result<Shard, ShardError> {
        let bad = |why: &str| ShardError::Bad {
            given: s.to_string(),
            why: why.to_string(),
        };
        let (i, n) = s.split_once('/').ok_or_else(|| bad("no `/`"))?;
        let i: usize = i
            .trim()
            .parse()
            .map_err(|_| bad("i is not a whole number"))?;
        let n: usize = n
            .trim()
            .parse()
            .map_err(|_| bad("n is not a whole number"))?;
        if n == 0 {
            return Err(bad("n must be at least 1"));
        }
        if i >= n {
            return Err(bad(&format!(
                "shard {i} does not exist among {n} (they count from 0)"
            )));
        }
        Ok(Shard { index: i, count: n })
    }

    /// The share from `--shard`, else `SLURM_ARRAY_TASK_ID` of
    /// `SLURM_ARRAY_TASK_COUNT` (an array `--array=0-(n-1)`), else everything.
    pub fn from_flag_or_env(
        flag: Option<&str>,
        env: impl Fn(&str) -> Option<String>,
    ) -> Result<Shard, ShardError> {
        if let Some(f) = flag {
            return Shard::parse(f);
        }
        match (env("SLURM_ARRAY_TASK_ID"), env("SLURM_ARRAY_TASK_COUNT")) {
            (Some(i), Some(n)) => {
                // Slurm counts tasks from the array's first index: --array=0-2 gives 0, 1, 2
                let min = env("SLURM_ARRAY_TASK_MIN")
                    .and_then(|m| m.trim().parse::<usize>().ok())
                    .unwrap_or(0);
                let i: usize = i.trim().parse().map_err(|_| {
                    ShardError::Slurm(format!("SLURM_ARRAY_TASK_ID=`{i}` is not a whole number"))
                })?;
                Shard::parse(&format!("{}/{}", i.saturating_sub(min), n.trim())).map_err(|e| {
                    ShardError::Slurm(format!("from SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT: {e} (submit with --array=0-(n-1))"))
                })
            }
            (Some(_), None) => Err(ShardError::Slurm(
                "SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not".into(),
            )),
            _ => Ok(Shard::WHOLE),
        }
    }

    /// Whether item `k` of the list is this shard's.
    pub fn owns(&self, k: usize) -> bool {
        k % self.count == self.index
    }

    /// The shard's name in file and folder names.
    pub fn dir_name(&self) -> String {
        format!("{}-of-{}", self.index, self.count)
    }
}

impl Shard {
    /// The bar over this shard's `len` `items` still to do, hidden unless
    /// `show` (`--progress`): one look for every sharded build.
    pub fn progress_bar(self, show: bool, len: usize, items: &str) -> ProgressBar {
        let bar = if show {
            ProgressBar::new(len as u64)
        } else {
            ProgressBar::hidden()
        };
        let template =
            format!("{{bar:30}} {{pos}}/{{len}} {items} [{{elapsed}} < {{eta}}] {{msg}}");
        if let Ok(style) = ProgressStyle::with_template(&template) {
            bar.set_style(style);
        }
        bar.set_message(format!("shard {self}"));
        bar
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_a_list() {
        let mut seen = [0; 30];
        for i in 0..4 {
            let s = Shard { index: i, count: 4 };
            for (k, n) in seen.iter_mut().enumerate() {
                if s.owns(k) {
                    *n += 1;
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }

    #[test]
    fn shard_specs_are_checked() {
        assert_eq!(Shard::parse("2/3").unwrap(), Shard { index: 2, count: 3 });
        for bad in ["4/3", "3/3", "1/0", "x/3", "3", "-1/3"] {
            let e = Shard::parse(bad).unwrap_err();
            assert!(e.to_string().contains("bad shard"), "{bad}: {e}");
        }
        let env = |k: &str| match k {
            "SLURM_ARRAY_TASK_ID" => Some("2".to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("3".to_string()),
            _ => None,
        };
        assert_eq!(
            Shard::from_flag_or_env(None, env).unwrap(),
            Shard { index: 2, count: 3 }
        );
        assert_eq!(
            Shard::from_flag_or_env(Some("0/1"), env).unwrap(),
            Shard::WHOLE
        );
        assert_eq!(
            Shard::from_flag_or_env(None, |_| None).unwrap(),
            Shard::WHOLE
        );
        // an array that starts at 1
        let from_one = |k: &str| match k {
            "SLURM_ARRAY_TASK_ID" => Some("3".to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("3".to_string()),
            "SLURM_ARRAY_TASK_MIN" => Some("1".to_string()),
            _ => None,
        };
        assert_eq!(
            Shard::from_flag_or_env(None, from_one).unwrap(),
            Shard { index: 2, count: 3 }
        );
        let e = Shard::from_flag_or_env(None, |k: &str| {
            (k == "SLURM_ARRAY_TASK_ID").then(|| "1".to_string())
        })
        .unwrap_err();
        assert!(matches!(e, ShardError::Slurm(_)), "{e}");
    }
}
