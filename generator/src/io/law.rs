//! `tcgen law`: the contact law of a table for macroscale codes — a chosen
//! ensemble statistic of the jump (mean jump, mean conductance or a
//! quantile), its standard deviation and its estimated discretization error
//! over the grid, the bulk materials and the extrapolation policy, in the
//! `lookup` law format (`schemas/law.md`), with provenance.
//!
//! Masked points are never filled in: a table with a failed point (or a
//! shard) is refused with the list of the points concerned, so a law always
//! rests on every sample at every grid point.

use std::path::Path;

use lookup::{
    Axes, Axis, BodyMaterial, Extrapolation, ExtrapolationPolicy, Law, LawInfo, LawMaterial,
    Statistic,
};

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

/// Which statistic of the ensemble the law tabulates (`tcgen law --statistic`).
/// The law's conductance is `|h̄| / jump` of it, so this is the choice
/// between the harmonic mean of the conductances (mean jump), their mean, or
/// a conservative quantile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LawStatistic {
    /// Mean of the samples' jumps (`mean-jump`, the default).
    MeanJump,
    /// Jump of the mean conductance, `|h̄| / mean(k̄c)` (`mean-conductance`).
    MeanConductance,
    /// The quantile of the jumps in percent, 1–99 (`quantile:P`).
    Quantile(u8),
}

impl std::str::FromStr for LawStatistic {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "mean-jump" => Ok(LawStatistic::MeanJump),
            "mean-conductance" => Ok(LawStatistic::MeanConductance),
            _ => s
                .strip_prefix("quantile:")
                .and_then(|p| p.parse::<u8>().ok())
                .filter(|p| (1..=99).contains(p))
                .map(LawStatistic::Quantile)
                .ok_or_else(|| {
                    Error::invalid(
                        "--statistic",
                        s,
                        "expected mean-jump, mean-conductance or quantile:P with P an integer percent in 1..=99",
                    )
                }),
        }
    }
}

impl LawStatistic {
    /// The statistic of `jumps` (≥ 1 values) and, with the samples'
    /// discretization errors, its own error by first-order propagation.
    pub fn of(self, jumps: &[f64], errors: Option<&[f64]>) -> (f64, Option<f64>) {
        let n = jumps.len() as f64;
        match self {
            LawStatistic::MeanJump => (
                jumps.iter().sum::<f64>() / n,
                errors.map(|e| e.iter().sum::<f64>() / n),
            ),
            LawStatistic::MeanConductance => {
                // H = n / Σ 1/j_i; ∂H/∂j_i = H² / (n j_i²). A zero jump (full
                // contact, unbounded conductance) gives H = 0.
                if jumps.iter().any(|&j| j <= 0.0) {
                    return (0.0, errors.map(|_| 0.0));
                }
                let h = n / jumps.iter().map(|j| 1.0 / j).sum::<f64>();
                let e = errors.map(|e| {
                    jumps
                        .iter()
                        .zip(e)
                        .map(|(j, d)| h * h / (n * j * j) * d)
                        .sum::<f64>()
                });
                (h, e)
            }
            LawStatistic::Quantile(percent) => {
                let mut order: Vec<usize> = (0..jumps.len()).collect();
                order.sort_by(|&a, &b| jumps[a].total_cmp(&jumps[b]));
                // numpy's default (linear): position q (n − 1).
                let pos = f64::from(percent) / 100.0 * (n - 1.0);
                let (lo, t) = (pos.floor() as usize, pos - pos.floor());
                let hi = (lo + 1).min(jumps.len() - 1);
                let (a, b) = (order[lo], order[hi]);
                (
                    (1.0 - t) * jumps[a] + t * jumps[b],
                    errors.map(|e| (1.0 - t) * e[a] + t * e[b]),
                )
            }
        }
    }

    fn for_law(self, samples: u32) -> Statistic {
        match self {
            LawStatistic::MeanJump => Statistic::EnsembleMean { samples },
            LawStatistic::MeanConductance => Statistic::EnsembleMeanConductance { samples },
            LawStatistic::Quantile(percent) => Statistic::EnsembleQuantile { samples, percent },
        }
    }
}

/// The statistic of a law in words (for messages and deck headers).
pub fn describe_statistic(statistic: Statistic) -> String {
    match statistic {
        Statistic::EnsembleMean { samples } => format!("mean jump of {samples} samples"),
        Statistic::EnsembleMeanConductance { samples } => {
            format!("jump of the mean conductance of {samples} samples")
        }
        Statistic::EnsembleQuantile { samples, percent } => {
            format!("{percent} % quantile of the jump over {samples} samples")
        }
        Statistic::Deterministic => "deterministic".into(),
    }
}

/// What `tcgen law` writes besides the table's numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawOptions {
    /// The ensemble statistic (default: mean of the jump).
    pub statistic: LawStatistic,
    /// The law's extrapolation policy (default: `error` on every axis).
    pub extrapolation: ExtrapolationPolicy,
}

impl Default for LawOptions {
    fn default() -> Self {
        LawOptions {
            statistic: LawStatistic::MeanJump,
            extrapolation: ExtrapolationPolicy::uniform(Extrapolation::Error),
        }
    }
}

/// Applies one `--extrapolate` argument, `POLICY` (every axis) or
/// `AXIS=POLICY`, to `policy`.
pub fn apply_extrapolation(policy: &mut ExtrapolationPolicy, arg: &str) -> Result<()> {
    let expected = "POLICY or AXIS=POLICY, AXIS one of pressure, flux, contact_temperature, \
                    POLICY one of error, clamp, linear, power (pressure only)";
    let (axes, name): (Vec<Axis>, &str) = match arg.split_once('=') {
        None => (Axis::ALL.to_vec(), arg),
        Some((a, p)) => match Axis::ALL.into_iter().find(|x| x.name() == a) {
            Some(axis) => (vec![axis], p),
            None => return Err(Error::invalid("--extrapolate", arg, expected)),
        },
    };
    let e = Extrapolation::from_keyword(name)
        .ok_or_else(|| Error::invalid("--extrapolate", arg, expected))?;
    if let Some(axis) = axes.iter().find(|a| !e.allowed_on(**a)) {
        return Err(Error::invalid(
            "--extrapolate",
            arg,
            format!(
                "{e} is for pressure only (not {}): use --extrapolate pressure={e}",
                axis.name()
            ),
        ));
    }
    for axis in axes {
        policy.set(axis, e);
    }
    Ok(())
}

/// The bulk materials recorded in a table's configuration.
fn law_material(config: &str) -> Result<LawMaterial> {
    let t: toml::Table = toml::from_str(config)
        .map_err(|e| Error::Config(format!("the table's configuration: {e}")))?;
    let material = match t.get("material") {
        Some(toml::Value::Table(m)) => m.clone(),
        _ => toml::Table::new(),
    };
    let (u, l) = crate::sample::case::body_materials(&material)?;
    let body = |m: &crate::material::Material| {
        BodyMaterial::from_values([
            m.youngs_modulus,
            m.poisson_ratio,
            m.thermal_expansion,
            m.thermal_conductivity,
            m.conductivity_slope,
            m.reference_temperature,
        ])
    };
    Ok(LawMaterial {
        upper: body(&u),
        lower: body(&l),
    })
}

/// The law of a complete table with every point converged and the default
/// options; `source` names the table in the provenance.
pub fn law_from_table(t: &Table, source: &str) -> Result<Law> {
    law_from_table_with(t, source, &LawOptions::default())
}

/// The law of a complete table with every point converged; `source` names the
/// table in the provenance.
pub fn law_from_table_with(t: &Table, source: &str, options: &LawOptions) -> Result<Law> {
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
    let cells = st.jump.len();
    let (mut mean, mut std, mut error) = (
        Vec::with_capacity(cells),
        Vec::with_capacity(cells),
        Vec::with_capacity(cells),
    );
    for (c, s) in st.jump.iter().enumerate() {
        let s = s.expect("every sample converged");
        let values: Vec<_> = t.points[c * ns..(c + 1) * ns]
            .iter()
            .filter_map(|p| p.values)
            .collect();
        let jumps: Vec<f64> = values.iter().map(|v| v.jump).collect();
        let errors: Option<Vec<f64>> = values.iter().map(|v| v.jump_error).collect();
        let (value, e) = options.statistic.of(&jumps, errors.as_deref());
        mean.push(value);
        std.push(if ns > 1 { s.std } else { 0.0 });
        error.push(e);
    }
    let error: Option<Vec<f64>> = error.into_iter().collect();
    let statistic = if ns > 1 {
        options.statistic.for_law(ns as u32)
    } else {
        Statistic::Deterministic
    };
    let i = &t.info;
    let mut provenance = vec![
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
    if !i.cautions.is_empty() {
        let all: Vec<String> = i.cautions.iter().map(|c| one_line(c)).collect();
        provenance.push(("cautions".into(), all.join(" | ")));
    }
    if let Some((dimension, cell)) = crate::io::table::sample_cell(&i.config) {
        let cell: Vec<String> = cell.iter().map(|w| format!("{w:e}")).collect();
        provenance.push(("dimension".into(), dimension.to_string()));
        provenance.push(("cell_size".into(), cell.join(" ")));
    }
    let info = LawInfo {
        statistic,
        extrapolation: options.extrapolation,
        material: Some(law_material(&i.config)?),
        provenance,
    };
    let axes = Axes {
        pressure: t.pressure.clone(),
        flux: t.flux.clone(),
        contact_temperature: t.contact_temperature.clone(),
    };
    Law::from_grid_with_error(axes, mean, std, error, info)
        .map_err(|e| Error::Config(format!("{source}: law: {e}")))
}

/// Reads a table and writes its law to `output` atomically.
pub fn write_law(table: &Path, output: &Path, options: &LawOptions) -> Result<Law> {
    let t = crate::io::read_table(table)?;
    let law = law_from_table_with(&t, &table.display().to_string(), options)?;
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
        t.info.config =
            "[material]\nyoungs_modulus = 2.0e6\n[material.lower]\npoisson_ratio = 0.2\n\
                         [sweep]\nsamples = 3\n"
                .into();
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

    /// The statistics by hand (numpy: `np.mean`, `len(j)/np.sum(1/j)`,
    /// `np.quantile(j, 0.9)`), and their errors against finite differences.
    #[test]
    fn statistics_and_their_error_propagation() {
        let j = [4.0, 1.0, 3.0, 2.0];
        let e = [0.04, 0.02, 0.01, 0.03];
        let (m, em) = LawStatistic::MeanJump.of(&j, Some(&e));
        assert!(m == 2.5 && (em.unwrap() - 0.025).abs() < 1e-15);
        let (h, eh) = LawStatistic::MeanConductance.of(&j, Some(&e));
        assert!(
            (h - 4.0 / (1.0 + 0.25 + 1.0 / 3.0 + 0.5)).abs() < 1e-15,
            "{h}"
        );
        let (q, eq) = LawStatistic::Quantile(90).of(&j, Some(&e));
        assert!((q - 3.7).abs() < 1e-14, "{q}"); // np.quantile([1,2,3,4], 0.9)
        assert!((eq.unwrap() - (0.3 * 0.01 + 0.7 * 0.04)).abs() < 1e-15);
        // First-order propagation: moving every sample by its error moves the
        // statistic by the propagated error (to second order).
        for (stat, err) in [
            (LawStatistic::MeanJump, em.unwrap()),
            (LawStatistic::MeanConductance, eh.unwrap()),
            (LawStatistic::Quantile(90), eq.unwrap()),
        ] {
            let eps = 1e-6;
            let moved: Vec<f64> = j.iter().zip(&e).map(|(a, b)| a + eps * b).collect();
            let fd = (stat.of(&moved, None).0 - stat.of(&j, None).0) / eps;
            assert!(
                (fd - err).abs() < 1e-6 * err.max(1e-3),
                "{stat:?}: {fd} vs {err}"
            );
        }
        assert_eq!(LawStatistic::MeanConductance.of(&[0.0, 1.0], None).0, 0.0);
        for (text, s) in [
            ("mean-jump", LawStatistic::MeanJump),
            ("mean-conductance", LawStatistic::MeanConductance),
            ("quantile:95", LawStatistic::Quantile(95)),
        ] {
            assert_eq!(text.parse::<LawStatistic>().unwrap(), s);
        }
        for bad in ["mean", "quantile:0", "quantile:100", "quantile:0.9"] {
            let e = bad.parse::<LawStatistic>().unwrap_err().to_string();
            assert!(e.contains("--statistic") && e.contains("quantile:P"), "{e}");
        }
    }

    /// Issue 14 item 2: the chosen statistic, the materials, the error
    /// estimate and a safe extrapolation default are in the law.
    #[test]
    fn law_records_statistic_material_error_and_policy() {
        let mut t = all_converged();
        // Default: mean jump, error outside the table, materials recorded.
        let law = law_from_table(&t, "t.h5").unwrap();
        assert_eq!(
            law.info().extrapolation,
            ExtrapolationPolicy::uniform(Extrapolation::Error)
        );
        assert!(law.eval(1e2, 1e5, 293.15).is_err());
        let m = law.info().material.unwrap();
        assert_eq!(m.upper.youngs_modulus, 2.0e6);
        assert_eq!(
            (m.lower.youngs_modulus, m.lower.poisson_ratio),
            (2.0e6, 0.2)
        );
        assert_eq!(m.upper.poisson_ratio, 0.3);
        assert_eq!(m.upper.reference_temperature, 293.15);
        // Some samples lack an estimate: none in the law.
        assert!(!law.error_estimated());
        for p in t.points.iter_mut() {
            if let Some(v) = p.values.as_mut() {
                v.jump_error = Some(0.02 * v.jump);
            }
        }
        let mut o = LawOptions {
            statistic: LawStatistic::MeanConductance,
            ..LawOptions::default()
        };
        apply_extrapolation(&mut o.extrapolation, "pressure=power").unwrap();
        apply_extrapolation(&mut o.extrapolation, "flux=clamp").unwrap();
        let law = law_from_table_with(&t, "t.h5", &o).unwrap();
        assert!(law.error_estimated());
        assert_eq!(
            law.info().statistic,
            Statistic::EnsembleMeanConductance { samples: 3 }
        );
        // |h| / the law's jump is the mean of the samples' |h| / jump.
        for k in 0..law.jump_mean().len() {
            let h = t.flux[(k / t.contact_temperature.len()) % t.flux.len()];
            let cell = &t.points[3 * k..3 * k + 3];
            let mean_k = cell.iter().map(|p| h / p.values.unwrap().jump).sum::<f64>() / 3.0;
            assert!((h / law.jump_mean()[k] / mean_k - 1.0).abs() < 1e-12, "{k}");
            assert!((law.jump_error()[k] / law.jump_mean()[k] - 0.02).abs() < 1e-12);
        }
        assert!(law.eval(1e2, 1e5, 293.15).unwrap().extrapolated[0]);
        let back = Law::from_bytes(&law.to_bytes()).unwrap();
        assert_eq!(back, law);
        // Bad options are named.
        let mut p = ExtrapolationPolicy::default();
        for bad in ["flux=power", "power", "sideways", "pressure=cubic"] {
            let e = apply_extrapolation(&mut p, bad).unwrap_err().to_string();
            assert!(e.contains("--extrapolate"), "{e}");
        }
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
