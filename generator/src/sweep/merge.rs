//! `tcgen merge`: the shards of one sweep into the table a single run would
//! have written (bit-identical data; only `created`, `wall_time` and
//! `threads` differ).

use crate::io::provenance;
use crate::io::table::{PointStatus, Table};
use crate::sweep::run::path_indices;
use crate::{Error, Result};

/// Merges the shard tables of one sweep (any order). Every shard `0..n` must
/// be present once, from the same configuration and generator.
pub fn merge_tables(shards: &[Table]) -> Result<Table> {
    let first = shards
        .first()
        .ok_or_else(|| Error::Config("merge needs at least one shard".into()))?;
    let count = first.info.shard.map_or(1, |s| s.count);
    let mut by_index: Vec<Option<&Table>> = vec![None; count];
    for (i, t) in shards.iter().enumerate() {
        let s = t.info.shard.ok_or_else(|| {
            Error::Config(format!("input {} is a complete table, not a shard", i + 1))
        })?;
        if s.count != count {
            return Err(Error::Config(format!(
                "input {} is shard {s}, the others are of {count}",
                i + 1
            )));
        }
        if by_index[s.index].replace(t).is_some() {
            return Err(Error::Config(format!("shard {s} is given twice")));
        }
        for (what, a, b) in [
            (
                "config_sha256",
                &t.info.config_sha256,
                &first.info.config_sha256,
            ),
            ("generator", &t.info.generator, &first.info.generator),
            (
                "git_revision",
                &t.info.git_revision,
                &first.info.git_revision,
            ),
        ] {
            if a != b {
                return Err(Error::Config(format!(
                    "shard {s} has {what} {a}, shard {} has {b}: shards of different runs cannot be merged",
                    first.info.shard.map_or_else(String::new, |s| s.to_string())
                )));
            }
        }
        let same_axes = |x: &[f64], y: &[f64]| {
            x.len() == y.len() && x.iter().zip(y).all(|(a, b)| a.to_bits() == b.to_bits())
        };
        if !(same_axes(&t.pressure, &first.pressure)
            && same_axes(&t.flux, &first.flux)
            && same_axes(&t.contact_temperature, &first.contact_temperature)
            && t.samples == first.samples)
        {
            return Err(Error::Config(format!("shard {s} has another grid")));
        }
    }
    let missing: Vec<String> = (0..count)
        .filter(|&i| by_index[i].is_none())
        .map(|i| format!("{i}/{count}"))
        .collect();
    if !missing.is_empty() {
        return Err(Error::Config(format!(
            "missing shard(s) {}",
            missing.join(", ")
        )));
    }
    let tables: Vec<&Table> = by_index.into_iter().map(|t| t.expect("checked")).collect();
    let [np, nh, nt, ns] = first.shape();
    let mut out = first.clone();
    for k in 0..ns * nt * nh {
        let (s, it, ih) = path_indices(k, nh, nt);
        let owner = tables[(k / nh) % count];
        for ip in 0..np {
            let i = out.index(ip, ih, it, s);
            let r = &owner.points[i];
            if r.status == PointStatus::NotComputed {
                return Err(Error::Config(format!(
                    "shard {}/{count} did not compute path {k} (sample {s}): was it interrupted?",
                    (k / nh) % count
                )));
            }
            out.points[i] = r.clone();
        }
    }
    for s in 0..ns {
        if out.surfaces[s].is_none() {
            out.surfaces[s] = tables.iter().find_map(|t| t.surfaces[s]);
        }
    }
    out.info.shard = None;
    out.info.created = provenance::utc_now();
    out.info.wall_time = tables.iter().map(|t| t.info.wall_time).sum();
    out.info.threads = tables.iter().flat_map(|t| t.info.threads.clone()).collect();
    out.check()?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::netcdf::tests::synthetic;
    use crate::sweep::Shard;

    #[test]
    fn two_synthetic_shards_merge_into_the_whole() {
        let whole = synthetic(None);
        let s0 = synthetic(Some(Shard::new(0, 2).unwrap()));
        let mut s1 = synthetic(Some(Shard::new(1, 2).unwrap()));
        // Shard 1's own points: the complement of shard 0's.
        for (i, p) in s1.points.iter_mut().enumerate() {
            *p = if s0.points[i].status == PointStatus::NotComputed {
                whole.points[i].clone()
            } else {
                crate::io::table::PointRecord::not_computed()
            };
        }
        let m = merge_tables(&[s1.clone(), s0.clone()]).unwrap();
        assert_eq!(m.points, whole.points);
        assert_eq!(m.statistics(), whole.statistics());
        assert!(m.info.shard.is_none());
        let e = merge_tables(std::slice::from_ref(&s0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing shard(s) 1/2"), "{e}");
        let e = merge_tables(&[s0.clone(), s0]).unwrap_err().to_string();
        assert!(e.contains("twice"), "{e}");
    }
}
