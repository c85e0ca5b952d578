//! Shards: deterministic subsets of a sweep's paths for clusters
//! (`tcgen sweep --shard i/n`, then `tcgen merge`).
//!
//! A *path* is one `(sample, contact temperature, flux)` with all its
//! pressures (solved in increasing order, by continuation); paths are
//! numbered `k = (s·n_θ + t)·n_h + h`. The fluxes of one *group*
//! `g = s·n_θ + t = ⌊k/n_h⌋` share a solver, so shards split groups: shard
//! `i` of `n` computes the groups with `g mod n = i` (0-based `i`), i.e. at
//! most `n_s·n_θ` shards do work. The assignment depends only on the grid shape.

use std::fmt;
use std::str::FromStr;

use crate::{Error, Result};

/// Shard `index` of `count` (0-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Shard {
    /// This shard, `0 ≤ index < count`.
    pub index: usize,
    /// Number of shards, ≥ 1.
    pub count: usize,
}

impl Shard {
    /// The whole sweep.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`; the error names `--shard`.
    pub fn new(index: usize, count: usize) -> Result<Self> {
        if count == 0 || index >= count {
            return Err(Error::invalid(
                "--shard",
                format!("{index}/{count}"),
                "i/n with 0 ≤ i < n (0-based, e.g. 0/4 … 3/4)",
            ));
        }
        Ok(Shard { index, count })
    }

    /// Whether this shard computes group number `g` (see the module documentation).
    pub fn owns(&self, g: usize) -> bool {
        g % self.count == self.index
    }

    /// Whether this is the whole sweep.
    pub fn is_all(&self) -> bool {
        self.count == 1
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl FromStr for Shard {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self> {
        let parse = |t: &str| t.trim().parse::<usize>().ok();
        match s.split_once('/') {
            Some((i, n)) => match (parse(i), parse(n)) {
                (Some(i), Some(n)) => Shard::new(i, n),
                _ => Err(Error::invalid("--shard", s, "i/n with integers, e.g. 0/4")),
            },
            None => Err(Error::invalid("--shard", s, "i/n, e.g. 0/4")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_partition_the_paths() {
        let n = 3;
        for k in 0..20 {
            let owners: Vec<usize> = (0..n)
                .filter(|&i| Shard::new(i, n).unwrap().owns(k))
                .collect();
            assert_eq!(owners, vec![k % n]);
        }
    }

    #[test]
    fn parses_and_rejects() {
        assert_eq!(
            "2/5".parse::<Shard>().unwrap(),
            Shard { index: 2, count: 5 }
        );
        for bad in ["5/5", "1", "a/2", "0/0", "-1/3"] {
            let e = bad.parse::<Shard>().unwrap_err().to_string();
            assert!(e.contains("--shard"), "{bad}: {e}");
        }
    }
}
