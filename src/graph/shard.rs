//! Which pairs a shard does: pair p of the sorted list of ordered pairs
//! belongs to shard p mod n ([`crate::shard::Shard`]), so shares are fixed by
//! the clip names alone and balanced to within one pair.

pub use crate::shard::Shard;

/// Every ordered pair (a, b), a ≠ b, of `n` clips in sorted order.
pub fn pairs(n: usize) -> Vec<(usize, usize)> {
    (0..n)
        .flat_map(|a| (0..n).filter(move |&b| b != a).map(move |b| (a, b)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_pairs() {
        let all = pairs(6);
        assert_eq!(all.len(), 30);
        let mut seen = vec![0; all.len()];
        for i in 0..4 {
            let s = Shard { index: i, count: 4 };
            for (p, n) in seen.iter_mut().enumerate() {
                if s.owns(p) {
                    *n += 1;
                }
            }
        }
        assert!(seen.iter().all(|&c| c == 1));
    }

    #[test]
    fn a_bad_shard_names_the_flag() {
        let e: crate::graph::GraphError = Shard::parse("4/3").unwrap_err().into();
        assert!(e.to_string().contains("bad shard"), "{e}");
        assert_eq!(e.option(), Some("shard"));
    }
}
