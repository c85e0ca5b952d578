//! `tcgen law`: the contact law of a table for macroscale codes — the
//! ensemble-mean jump and its standard deviation over the grid, in the
//! `lookup` law format (`schemas/law.md`), with provenance.
//!
//! Masked points are never filled in: a table with a failed point (or a
//! shard) is refused with the list of the points concerned, so a law always
//! rests on every sample at every grid point.

use std::path::Path;

use lookup::{Axes, Law, LawInfo, Statistic};

use crate::io::provenance;
use crate::io::table::{PointStatus, SCHEMA_NAME, SCHEMA_VERSION, Table};
use crate::{Error, Result};

/// Most masked points listed in the refusal.
const LISTED: usize = 8;

fn one_line(s: &str) -> String {
    s.split(['\n', '\r', '\t'])
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The surfaces of a table's configuration in one line (provenance `surface`).
pub fn surface_summary(config: &str) -> String {
    let parsed: std::result::Result<toml::Table, _> = toml::from_str(config);
    let Ok(t) = parsed else {
        return "unknown".into();
    };
    let body = |b: &str| {
        t.get("surface")
            .and_then(|s| s.get(b))
            .map_or_else(|| "?".into(), |v| one_line(&v.to_string()))
    };
    // A TOML table prints with its braces: `{ kind = "flat" }`.
    format!("upper: {}; lower: {}", body("upper"), body("lower"))
}

/// The law of a complete table with every point converged; `source` names the
/// table in the provenance.
pub fn law_from_table(t: &Table, source: &str) -> Result<Law> {
    if let Some(s) = t.info.shard {
        return Err(Error::Config(format!(
            "{source} is shard {s} of a sweep: merge the shards first (tcgen merge)"
        )));
    }
    let [np, nh, nt, ns] = t.shape();
    let mut masked = Vec::new();
    for ip in 0..np {
        for ih in 0..nh {
            for it in 0..nt {
                for is in 0..ns {
                    let r = t.point(ip, ih, it, is);
                    if r.status != PointStatus::Converged {
                        masked.push(format!(
                            "p = {:e} Pa, |h| = {:e} W/m², θc = {} K, sample {is}: {} {}",
                            t.pressure[ip],
                            t.flux[ih],
                            t.contact_temperature[it],
                            r.status.meaning(),
                            r.reason
                        ));
                    }
                }
            }
        }
    }
    if !masked.is_empty() {
        let n = masked.len();
        masked.truncate(LISTED);
        return Err(Error::Config(format!(
            "{source}: {n} masked point(s); a law needs every sample at every grid point \
             (rerun those paths with other [solver] settings, or drop the grid values):\n  {}{}",
            masked.join("\n  "),
            if n > LISTED { "\n  …" } else { "" }
        )));
    }
    let st = t.statistics();
    let mut mean = Vec::with_capacity(st.jump.len());
    let mut std = Vec::with_capacity(st.jump.len());
    for s in &st.jump {
        let s = s.expect("every sample converged");
        mean.push(s.mean);
        std.push(if ns > 1 { s.std } else { 0.0 });
    }
    let statistic = if ns > 1 {
        Statistic::EnsembleMean { samples: ns as u32 }
    } else {
        Statistic::Deterministic
    };
    let i = &t.info;
    let provenance = vec![
        ("generator".into(), provenance::generator()),
        ("git_revision".into(), one_line(&i.git_revision)),
        ("source".into(), one_line(source)),
        (
            "table_schema".into(),
            format!("{SCHEMA_NAME} {SCHEMA_VERSION}"),
        ),
        ("table_generator".into(), one_line(&i.generator)),
        ("table_created".into(), one_line(&i.created)),
        ("config_sha256".into(), i.config_sha256.clone()),
        ("identification".into(), one_line(&i.identification)),
        ("surface".into(), surface_summary(&i.config)),
        ("seed".into(), i.seed.to_string()),
        ("samples".into(), ns.to_string()),
        ("created".into(), provenance::utc_now()),
    ];
    let info = LawInfo {
        statistic,
        provenance,
        ..LawInfo::default()
    };
    let axes = Axes {
        pressure: t.pressure.clone(),
        flux: t.flux.clone(),
        contact_temperature: t.contact_temperature.clone(),
    };
    Law::from_grid(axes, mean, std, info).map_err(|e| Error::Config(format!("{source}: law: {e}")))
}

/// Reads a table and writes its law to `output` atomically.
pub fn write_law(table: &Path, output: &Path) -> Result<Law> {
    let t = crate::io::read_table(table)?;
    let law = law_from_table(&t, &table.display().to_string())?;
    crate::io::atomic::write_atomic(output, &law.to_bytes())?;
    Ok(law)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::netcdf::tests::synthetic;
    use crate::io::table::{PointRecord, PointValues};

    fn all_converged() -> Table {
        let mut t = synthetic(None);
        for p in t.points.iter_mut() {
            if p.values.is_none() {
                *p = PointRecord::converged(PointValues {
                    jump: 2.0,
                    conductance: 5e5,
                    contact_fraction: 0.5,
                    mean_gap: 1e-7,
                    self_consistency_iterations: 3,
                    newton_iterations: 10,
                    jump_error: None,
                    error_target_met: None,
                    dofs: 900,
                });
            }
        }
        t
    }

    /// Issue 14 item 6: one pair of braces per surface table.
    #[test]
    fn surface_summary_has_single_braces() {
        let s = surface_summary(
            "[surface.upper]\nkind = \"flat\"\n[surface.lower]\nkind = \"sinusoid\"\nrms = 1.0\n",
        );
        assert!(
            s.starts_with("upper: { kind = \"flat\" }; lower: { "),
            "{s}"
        );
        assert!(!s.contains("{{") && !s.contains("}}"), "{s}");
    }

    #[test]
    fn law_holds_the_ensemble_mean_and_std() {
        let t = all_converged();
        let law = law_from_table(&t, "t.h5").unwrap();
        let st = t.statistics();
        assert_eq!(law.jump_mean().len(), st.jump.len());
        for (k, s) in st.jump.iter().enumerate() {
            let s = s.unwrap();
            assert_eq!(law.jump_mean()[k], s.mean);
            assert_eq!(law.jump_std()[k], s.std);
        }
        assert_eq!(law.info().statistic, Statistic::EnsembleMean { samples: 3 });
        let v = law.eval(1e4, 1e5, 293.15).unwrap();
        assert!((v.jump - st.jump[2].unwrap().mean).abs() < 1e-12);
        // The bytes read back.
        let back = Law::from_bytes(&law.to_bytes()).unwrap();
        assert_eq!(back.jump_mean(), law.jump_mean());
        assert!(
            back.info()
                .provenance
                .iter()
                .any(|(k, v)| k == "config_sha256" && v == &t.info.config_sha256)
        );
    }

    #[test]
    fn masked_points_and_shards_are_refused() {
        let e = law_from_table(&synthetic(None), "t.h5")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("1 masked point") && e.contains("sample 1: failed"),
            "{e}"
        );
        let s = synthetic(Some(crate::sweep::Shard::new(0, 2).unwrap()));
        let e = law_from_table(&s, "s.h5").unwrap_err().to_string();
        assert!(e.contains("merge the shards"), "{e}");
    }
}
