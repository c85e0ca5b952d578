//! The sweep configuration of `tcgen sweep`: the keys of a `tcgen solve` case
//! file (without `[load]`) plus `[sweep]`:
//!
//! ```toml
//! [sweep]
//! pressures = { from = 1.0e3, to = 1.0e5, count = 8, spacing = "log" }   # Pa
//! fluxes = [1.0e5, 1.0e6]                                                 # W/m²
//! contact_temperatures = 293.15                                           # K
//! samples = 4          # surface samples (random surfaces only; default 1)
//! seed = 1             # ensemble seed k (default 1)
//! continuation = true  # pressure continuation along each path (default true)
//! ```
//!
//! An axis is a number, a list (strictly increasing), or a range
//! `{ from, to, count, spacing = "log" | "linear" }` (both ends included).
//! Random surfaces (`kind = "random"`) get `seed = [sweep] seed` and
//! `sample = s` for sample `s = 0..samples`; they must not set them.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::io::hash::sha256_hex;
use crate::sample::Case;
use crate::{Error, Result};

/// Spacing of a range axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Spacing {
    /// Geometric: equal ratios.
    Log,
    /// Arithmetic: equal steps.
    Linear,
}

/// A range axis `{ from, to, count, spacing }`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RangeSpec {
    /// First value.
    pub from: f64,
    /// Last value (included).
    pub to: f64,
    /// Number of values, ≥ 1 (1: just `from`).
    pub count: usize,
    /// Spacing.
    pub spacing: Spacing,
}

/// One axis of the grid as written.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum AxisSpec {
    /// A single value.
    Value(f64),
    /// Explicit values, strictly increasing.
    List(Vec<f64>),
    /// A range.
    Range(RangeSpec),
}

impl<'de> Deserialize<'de> for AxisSpec {
    /// A number, a list of numbers, or a range table, with an error that
    /// says which form was meant and what is wrong in it.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error as _;
        let v = toml::Value::deserialize(d)?;
        let number = |v: &toml::Value| match v {
            toml::Value::Float(x) => Some(*x),
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        };
        match &v {
            toml::Value::Array(a) => a
                .iter()
                .map(|x| {
                    number(x).ok_or_else(|| D::Error::custom(format!("list entry {x} is not a number")))
                })
                .collect::<std::result::Result<Vec<_>, _>>()
                .map(AxisSpec::List),
            toml::Value::Table(_) => v.clone().try_into::<RangeSpec>().map(AxisSpec::Range).map_err(|e| {
                D::Error::custom(format!(
                    "a range {{ from, to, count, spacing = \"log\" or \"linear\" }}: {}",
                    e.message()
                ))
            }),
            other => number(other).map(AxisSpec::Value).ok_or_else(|| {
                D::Error::custom(format!(
                    "{other} is not a number, a list of numbers or a range {{ from, to, count, spacing }}"
                ))
            }),
        }
    }
}

impl AxisSpec {
    /// The values; `key` names the axis for errors (e.g. `sweep.pressures`).
    pub fn values(&self, key: &str, unit: &str) -> Result<Vec<f64>> {
        let v = match self {
            AxisSpec::Value(x) => vec![*x],
            AxisSpec::List(v) => v.clone(),
            AxisSpec::Range(r) => {
                if !(1..=10_000).contains(&r.count) {
                    return Err(Error::invalid(
                        format!("{key}.count"),
                        r.count,
                        "an integer in 1..=10000",
                    ));
                }
                for (k, x) in [("from", r.from), ("to", r.to)] {
                    if !(x.is_finite() && x > 0.0) {
                        return Err(Error::invalid(
                            format!("{key}.{k}"),
                            x,
                            format!("a finite number > 0 ({unit})"),
                        ));
                    }
                }
                if r.count > 1 && r.to <= r.from {
                    return Err(Error::invalid(
                        format!("{key}.to"),
                        r.to,
                        format!("greater than from = {}", r.from),
                    ));
                }
                let n = r.count;
                (0..n)
                    .map(|i| {
                        if i == 0 {
                            return r.from;
                        }
                        if i == n - 1 {
                            return r.to;
                        }
                        let t = i as f64 / (n - 1) as f64;
                        match r.spacing {
                            Spacing::Linear => r.from + t * (r.to - r.from),
                            Spacing::Log => r.from * (r.to / r.from).powf(t),
                        }
                    })
                    .collect()
            }
        };
        if v.is_empty() {
            return Err(Error::invalid(
                key,
                "[]",
                format!("at least one value ({unit})"),
            ));
        }
        for (i, x) in v.iter().enumerate() {
            if !(x.is_finite() && *x > 0.0) {
                return Err(Error::invalid(
                    format!("{key}[{i}]"),
                    x,
                    format!("a finite number > 0 ({unit})"),
                ));
            }
            if i > 0 && *x <= v[i - 1] {
                return Err(Error::invalid(
                    format!("{key}[{i}]"),
                    x,
                    format!("strictly increasing values (after {})", v[i - 1]),
                ));
            }
        }
        Ok(v)
    }
}

fn default_samples() -> usize {
    1
}

fn default_seed() -> u64 {
    1
}

fn default_true() -> bool {
    true
}

/// `[sweep]` as written.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepSection {
    /// Pressures `p̄N` (Pa).
    pub pressures: AxisSpec,
    /// Flux magnitudes `|h̄|` (W/m²).
    pub fluxes: AxisSpec,
    /// Contact temperatures `θ̄c` (K).
    pub contact_temperatures: AxisSpec,
    /// Number of surface samples (default 1).
    #[serde(default = "default_samples")]
    pub samples: usize,
    /// Ensemble seed `k` (default 1), `0 ≤ k < 2⁶³`.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Pressure continuation along a path (default true): each pressure starts
    /// from the converged state of the previous one. `false` solves every
    /// pressure from zero load with a fresh model (slower, independent points).
    #[serde(default = "default_true")]
    pub continuation: bool,
}

/// A validated sweep configuration.
#[derive(Clone, Debug)]
pub struct SweepConfig {
    /// The case keys; `load` holds the first flux and contact temperature and all pressures.
    pub case: Case,
    /// `[sweep]` as written.
    pub sweep: SweepSection,
    /// Pressures (Pa), increasing.
    pub pressures: Vec<f64>,
    /// Fluxes (W/m²), increasing.
    pub fluxes: Vec<f64>,
    /// Contact temperatures (K), increasing.
    pub contact_temperatures: Vec<f64>,
    /// The resolved configuration as TOML (every key explicit, axes as lists).
    pub resolved: String,
    /// SHA-256 of `resolved`.
    pub sha256: String,
    /// The file read (empty for text).
    pub source: PathBuf,
}

fn config_err(e: impl std::fmt::Display) -> Error {
    Error::Config(e.to_string())
}

impl SweepConfig {
    /// Reads and validates a sweep file.
    pub fn read(path: &Path) -> Result<Self> {
        let text = crate::error::read_text(path)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let mut c = SweepConfig::from_toml(&text, &dir).map_err(|e| match e {
            Error::Config(m) => Error::Config(format!("{}: {m}", path.display())),
            other => other,
        })?;
        c.source = path.to_path_buf();
        Ok(c)
    }

    /// Parses TOML text; `base_dir` resolves relative paths (profiles).
    pub fn from_toml(text: &str, base_dir: &Path) -> Result<Self> {
        let mut table: toml::Table = toml::from_str(text).map_err(config_err)?;
        let sweep_value = table.remove("sweep").ok_or_else(|| {
            Error::Config(
                "a sweep configuration needs a [sweep] table (pressures, fluxes, contact_temperatures, samples, seed)".into(),
            )
        })?;
        if table.contains_key("load") {
            return Err(Error::invalid(
                "load",
                "[load]",
                "no [load] table in a sweep configuration: the loads come from [sweep] pressures, fluxes and contact_temperatures",
            ));
        }
        let sweep: SweepSection = sweep_value
            .try_into()
            .map_err(|e: toml::de::Error| Error::Config(format!("[sweep]: {e}")))?;
        let pressures = sweep.pressures.values("sweep.pressures", "Pa")?;
        let fluxes = sweep.fluxes.values("sweep.fluxes", "W/m²")?;
        let contact_temperatures = sweep
            .contact_temperatures
            .values("sweep.contact_temperatures", "K")?;
        if !(1..=1_000_000).contains(&sweep.samples) {
            return Err(Error::invalid(
                "sweep.samples",
                sweep.samples,
                "an integer in 1..=1000000",
            ));
        }
        if sweep.seed > i64::MAX as u64 {
            return Err(Error::invalid(
                "sweep.seed",
                sweep.seed,
                "an integer in 0..2^63",
            ));
        }
        let mut case = Case::from_table(table, base_dir)?;
        case.load.pressures = pressures.clone();
        case.load.flux = fluxes[0];
        case.load.contact_temperature = contact_temperatures[0];
        let mut random = false;
        for (key, s) in [
            ("surface.upper", &case.surface.upper),
            ("surface.lower", &case.surface.lower),
        ] {
            if let Some(r) = s.random() {
                random = true;
                for (name, given) in [("seed", r.seed.is_some()), ("sample", r.sample.is_some())] {
                    if given {
                        return Err(Error::invalid(
                            format!("{key}.{name}"),
                            "given",
                            "absent in a sweep: set by [sweep] seed and the sample index",
                        ));
                    }
                }
            }
        }
        if !random && sweep.samples > 1 {
            return Err(Error::invalid(
                "sweep.samples",
                sweep.samples,
                "1 when no surface is random (deterministic surfaces give identical samples)",
            ));
        }
        case.validate()?;
        case.check_conductivity_at(&contact_temperatures)?;
        // The measured surfaces' content pinned: in the hash, so that
        // checkpoints, shards and tables of other heights are told apart, and
        // in every path's case, so that each reads those heights.
        case.pin_data_files()?;
        let resolved = resolve(&case, &sweep, &pressures, &fluxes, &contact_temperatures)?;
        let sha256 = sha256_hex(resolved.as_bytes());
        Ok(SweepConfig {
            case,
            sweep,
            pressures,
            fluxes,
            contact_temperatures,
            resolved,
            sha256,
            source: PathBuf::new(),
        })
    }

    /// Whether any surface is random.
    pub fn is_random(&self) -> bool {
        self.case.surface.upper.random().is_some() || self.case.surface.lower.random().is_some()
    }

    /// Tasks of the whole sweep (`sweep::run`): one per sample and contact
    /// temperature (its fluxes share a solver), and per pressure too without
    /// continuation; at most this many run at once, whatever the threads.
    pub fn tasks(&self) -> usize {
        let per_path = if self.sweep.continuation {
            1
        } else {
            self.pressures.len()
        };
        self.sweep.samples * self.contact_temperatures.len() * per_path
    }

    /// The threads a run of the whole sweep on `threads` keeps busy: at most
    /// its [`SweepConfig::tasks`], at least one.
    pub fn busy_threads(&self, threads: usize) -> usize {
        threads.min(self.tasks()).max(1)
    }

    /// The case of one path: sample `s`, flux `fluxes[ih]`, temperature
    /// `contact_temperatures[it]`, all pressures.
    pub fn path_case(&self, sample: usize, ih: usize, it: usize) -> Case {
        let mut c = self.case.clone();
        c.load.flux = self.fluxes[ih];
        c.load.contact_temperature = self.contact_temperatures[it];
        for s in [&mut c.surface.upper, &mut c.surface.lower] {
            if let Some(r) = s.random_mut() {
                r.seed = Some(self.sweep.seed);
                r.sample = Some(sample as u64);
            }
        }
        c
    }

    /// The identification method as written in the case (`homogenization.method`).
    pub fn identification(&self) -> String {
        toml::Value::try_from(self.case.homogenization.method)
            .ok()
            .and_then(|v| v.as_str().map(str::to_string))
            .unwrap_or_default()
    }
}

/// The case as parsed, every key explicit: defaults, the materials per body,
/// and the automatic values (`bulk_points`, contact penalties) resolved.
fn resolved_case_table(case: &Case) -> Result<toml::Table> {
    let mut case = case.clone();
    // The measured surfaces' files by their content's SHA-256 (a sweep's
    // case is pinned already: its digests are verified against the files
    // again; a case file's are written here).
    case.pin_data_files()?;
    // Automatic values made explicit (the values the solver uses): the bulk
    // Gauss points p + 2, the normal penalty factor 1 (εN = E/h), the
    // thermal contact zone (2D on, 3D off unless given). The
    // thermal penalty of the constraint model stays automatic: its default
    // 10 k0/h depends on the slave element size (schemas/case.md).
    let d = &mut case.discretization;
    d.bulk_points = Some(
        d.bulk_points
            .unwrap_or(crate::quadrature::default_bulk_points(d.degree)),
    );
    case.contact.mechanical_penalty = Some(case.contact.mechanical_penalty.unwrap_or(1.0));
    // The thermal phase's contact zone: by dimension unless given.
    case.contact.thermal_zone = Some(case.contact.thermal_zone_in(case.dimension()));
    // The contact-edge marks' neighbours: explicit unless marked on every
    // level by default, the only behaviour before the key existed (those
    // tables keep the hashes they were built with; the 3D default at p ≥ 2
    // changed in stops 85 and 98, and those cases write `false` or the
    // number of levels).
    let dim = case.dimension();
    let d = &mut case.discretization;
    let every = crate::sample::case::EdgeNeighbours::Every(true);
    let neighbours = d.edge_neighbours_in(dim);
    d.edge_neighbours = if neighbours == every && d.edge_neighbours_by_default(dim) == every {
        None
    } else {
        Some(neighbours)
    };
    // Random surfaces: the stream of each body and the self-affine roll-off
    // (default the width) explicit; `exact_rms` is always written.
    let width = case.sample.width;
    for (key, spec) in [
        ("surface.upper", &mut case.surface.upper),
        ("surface.lower", &mut case.surface.lower),
    ] {
        if let Some(r) = spec.random_mut() {
            r.stream = Some(r.stream_for(key));
            if r.spectrum == crate::surface::SpectrumKind::SelfAffine {
                r.rolloff_wavelength = Some(r.rolloff_wavelength.unwrap_or(width));
            }
        }
    }
    let mut v = toml::Table::try_from(&case).map_err(config_err)?;
    // Every material key explicit, per body (defaults included).
    let (upper, lower) = case.materials()?;
    let mut material = toml::Table::new();
    for (body, m) in [("upper", &upper), ("lower", &lower)] {
        material.insert(body.into(), toml::Value::try_from(m).map_err(config_err)?);
    }
    v.insert("material".into(), toml::Value::Table(material));
    Ok(v)
}

/// The resolved case as TOML (`tcgen check`): every key explicit.
pub fn resolved_case(case: &Case) -> Result<String> {
    toml::to_string(&resolved_case_table(case)?).map_err(config_err)
}

/// The canonical TOML of a configuration: the case as parsed (defaults
/// explicit) without `[load]`, and `[sweep]` with the axes as lists.
fn resolve(
    case: &Case,
    sweep: &SweepSection,
    pressures: &[f64],
    fluxes: &[f64],
    contact_temperatures: &[f64],
) -> Result<String> {
    let mut v = resolved_case_table(case)?;
    v.remove("load");
    let s = SweepSection {
        pressures: AxisSpec::List(pressures.to_vec()),
        fluxes: AxisSpec::List(fluxes.to_vec()),
        contact_temperatures: AxisSpec::List(contact_temperatures.to_vec()),
        samples: sweep.samples,
        seed: sweep.seed,
        continuation: sweep.continuation,
    };
    v.insert(
        "sweep".into(),
        toml::Value::try_from(&s).map_err(config_err)?,
    );
    toml::to_string(&v).map_err(config_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    const BASE: &str = r#"
[surface.upper]
kind = "random"
rms = 5.0e-7
spectrum = "gaussian"
correlation_length = 2.0e-6
[surface.lower]
kind = "flat"
[sweep]
pressures = { from = 1.0e3, to = 1.0e5, count = 3, spacing = "log" }
fluxes = [1.0e5, 1.0e6]
contact_temperatures = 293.15
samples = 2
seed = 5
"#;

    #[test]
    fn axes_resolve_and_the_config_hashes() {
        let c = SweepConfig::from_toml(BASE, Path::new(".")).unwrap();
        assert_eq!(c.pressures.len(), 3);
        assert!((c.pressures[1] - 1e4).abs() < 1e-9);
        assert_eq!(c.fluxes, vec![1e5, 1e6]);
        assert_eq!(c.contact_temperatures, vec![293.15]);
        assert_eq!(c.sha256.len(), 64);
        // The resolved text is itself a valid sweep config with the same hash.
        let again = SweepConfig::from_toml(&c.resolved, Path::new(".")).unwrap();
        assert_eq!(again.resolved, c.resolved);
        assert_eq!(again.sha256, c.sha256);
        // Every material key is explicit (issue 14 item 6).
        let resolved: toml::Table = toml::from_str(&c.resolved).unwrap();
        for body in ["upper", "lower"] {
            let m = &resolved["material"][body];
            for key in [
                "youngs_modulus",
                "poisson_ratio",
                "thermal_conductivity",
                "conductivity_slope",
            ] {
                assert!(m.get(key).is_some(), "material.{body}.{key}");
            }
        }
        // Automatic values explicit: quadrature, penalty factor, the random
        // surface's stream and exact_rms.
        assert_eq!(
            resolved["discretization"]["bulk_points"].as_integer(),
            Some(4)
        );
        assert_eq!(
            resolved["contact"]["mechanical_penalty"].as_float(),
            Some(1.0)
        );
        let up = &resolved["surface"]["upper"];
        assert_eq!(up["stream"].as_integer(), Some(0));
        assert_eq!(up["exact_rms"].as_bool(), Some(false));
        let p = c.path_case(1, 1, 0);
        assert_eq!(p.load.flux, 1e6);
        let r = p.surface.upper.random().unwrap();
        assert_eq!((r.seed, r.sample), (Some(5), Some(1)));
        assert_eq!(c.identification(), "two-phase-self-consistent");
    }

    /// A 3D sweep: areal random surfaces take the seed and sample of the
    /// sweep, the resolved text records the dimension and the three counts
    /// and reads back with the same hash.
    #[test]
    fn a_3d_sweep_resolves() {
        let t = format!(
            "[sample]\ndimension = 3\n[discretization]\nelements_upper = [6, 6, 3]\nelements_lower = [5, 5, 3]\n{BASE}"
        );
        let c = SweepConfig::from_toml(&t, Path::new(".")).unwrap();
        assert!(c.is_random());
        let resolved: toml::Table = toml::from_str(&c.resolved).unwrap();
        assert_eq!(resolved["sample"]["dimension"].as_integer(), Some(3));
        assert_eq!(
            resolved["discretization"]["elements_upper"]
                .as_array()
                .map(Vec::len),
            Some(3)
        );
        assert_eq!(resolved["surface"]["upper"]["stream"].as_integer(), Some(0));
        let again = SweepConfig::from_toml(&c.resolved, Path::new(".")).unwrap();
        assert_eq!(again.sha256, c.sha256);
        let p = c.path_case(1, 0, 0);
        let r = p.surface.upper.random().unwrap();
        assert_eq!((r.seed, r.sample), (Some(5), Some(1)));
        assert!(p.areal_surfaces().is_ok());
        let e = SweepConfig::from_toml(&t.replace("[6, 6, 3]", "[6, 3]"), Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("discretization.elements_upper") && e.contains("three"),
            "{e}"
        );
    }

    #[test]
    fn errors_name_the_key() {
        for (from, to, key) in [
            (
                "fluxes = [1.0e5, 1.0e6]",
                "fluxes = [1.0e6, 1.0e5]",
                "sweep.fluxes[1]",
            ),
            ("count = 3", "count = 0", "sweep.pressures.count"),
            ("samples = 2", "samples = 2\nsamplez = 3", "samplez"),
            (
                "kind = \"flat\"",
                "kind = \"flat\"\n[load]\nflux = 1.0",
                "[load]",
            ),
            (
                "correlation_length = 2.0e-6",
                "correlation_length = 2.0e-6\nseed = 3",
                "surface.upper.seed",
            ),
            (
                "contact_temperatures = 293.15",
                "contact_temperatures = -1.0",
                "sweep.contact_temperatures[0]",
            ),
            // Issue 14 item 4: a bad spacing says which form and what is wrong.
            (
                "spacing = \"log\"",
                "spacing = \"logarithmic\"",
                "`pressures`",
            ),
            (
                "spacing = \"log\"",
                "spacing = \"logarithmic\"",
                "expected `log` or `linear`",
            ),
            // A conductivity that vanishes at one of the sweep's temperatures.
            (
                "contact_temperatures = 293.15\nsamples = 2\nseed = 5",
                "contact_temperatures = [293.15, 400.0]\nsamples = 2\nseed = 5\n[material]\nconductivity_slope = -0.01",
                "material.upper.conductivity_slope",
            ),
        ] {
            let t = BASE.replace(from, to);
            let e = SweepConfig::from_toml(&t, Path::new("."))
                .unwrap_err()
                .to_string();
            assert!(e.contains(key), "{key}: {e}");
        }
        let flat = BASE.replace(
            "kind = \"random\"\nrms = 5.0e-7\nspectrum = \"gaussian\"\ncorrelation_length = 2.0e-6",
            "kind = \"flat\"",
        );
        let e = SweepConfig::from_toml(&flat, Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(e.contains("sweep.samples"), "{e}");
        let e = SweepConfig::from_toml("[surface.upper]\nkind = \"flat\"\n", Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(e.contains("[sweep]"), "{e}");
    }

    /// A measured surface's file enters the configuration by its content:
    /// the resolved text pins its SHA-256, the hash changes with the heights
    /// (not only with the file's name), every path's case carries the digest,
    /// and a file changed after pinning, or a malformed digest, is an error
    /// naming `file_sha256`. In 2D (a profile) and 3D (a height map).
    #[test]
    fn a_measured_surface_is_hashed_by_its_content() {
        let dir = tempfile::tempdir().unwrap();
        let sweep = "[sweep]\npressures = [1.0e3]\nfluxes = 1.0e6\ncontact_temperatures = 293.15\n";
        let profile = |amplitude: f64| -> String {
            let mut s = String::from("x,z\n");
            for i in 0..32 {
                let x = 1e-5 * i as f64 / 32.0;
                s += &format!(
                    "{x:e},{:e}\n",
                    amplitude * (std::f64::consts::TAU * x / 1e-5).sin()
                );
            }
            s
        };
        let map = |amplitude: f64| -> String {
            (0..8)
                .map(|j| {
                    (0..8)
                        .map(|i| format!("{:e}", amplitude * ((i + 2 * j) as f64 * 0.7).sin()))
                        .collect::<Vec<_>>()
                        .join(",")
                })
                .collect::<Vec<_>>()
                .join("\n")
        };
        let cases = [
            ("heights.csv", String::new(), "profile"),
            (
                "map.csv",
                "[sample]\ndimension = 3\n[discretization]\nelements_upper = [4, 4, 2]\nelements_lower = [3, 3, 2]\n".to_string(),
                "heightmap",
            ),
        ];
        for (file, head, kind) in cases {
            let write = |a: f64| {
                let text = if kind == "profile" {
                    profile(a)
                } else {
                    map(a)
                };
                std::fs::write(dir.path().join(file), text).unwrap();
            };
            let text = format!(
                "{head}[surface.upper]\nkind = \"{kind}\"\nfile = \"{file}\"\n[surface.lower]\nkind = \"flat\"\n{sweep}"
            );
            write(4e-7);
            let a = SweepConfig::from_toml(&text, dir.path()).unwrap();
            let digest =
                crate::io::hash::sha256_hex(&std::fs::read(dir.path().join(file)).unwrap());
            let resolved: toml::Table = toml::from_str(&a.resolved).unwrap();
            assert_eq!(
                resolved["surface"]["upper"]["file_sha256"].as_str(),
                Some(digest.as_str()),
                "{kind}"
            );
            // The same content, the same hash; the resolved text reads back.
            assert_eq!(
                SweepConfig::from_toml(&text, dir.path()).unwrap().sha256,
                a.sha256
            );
            let again = SweepConfig::from_toml(&a.resolved, dir.path()).unwrap();
            assert_eq!(again.sha256, a.sha256, "{kind}");
            let mut p = a.path_case(0, 0, 0);
            assert!(p.pin_data_files().is_ok());
            // Other heights under the same name: another hash, and the
            // pinned configurations refuse the file.
            write(5e-7);
            let b = SweepConfig::from_toml(&text, dir.path()).unwrap();
            assert_ne!(b.sha256, a.sha256, "{kind}");
            for e in [
                SweepConfig::from_toml(&a.resolved, dir.path()).unwrap_err(),
                p.pin_data_files().unwrap_err(),
            ] {
                let e = e.to_string();
                assert!(
                    e.contains("surface.upper.file_sha256") && e.contains("has changed"),
                    "{kind}: {e}"
                );
            }
            let built = if kind == "profile" {
                p.surfaces().err()
            } else {
                p.areal_surfaces().err()
            };
            assert!(
                built.is_some_and(|e| e.to_string().contains("file_sha256")),
                "{kind}"
            );
            let bad = text.replace(
                &format!("file = \"{file}\""),
                &format!("file = \"{file}\"\nfile_sha256 = \"abc\""),
            );
            let e = SweepConfig::from_toml(&bad, dir.path())
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("file_sha256") && e.contains("64 hexadecimal"),
                "{kind}: {e}"
            );
        }
    }
}
