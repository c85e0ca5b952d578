//! What a law file says about its table besides the numbers: the statistic, the
//! extrapolation policy, the provenance; and the metadata text that carries it
//! (`key = value` lines, specified in `schemas/law.md`).

use crate::error::{Axis, Error};
use std::fmt;

/// What the caller gets outside the tabulated range of one axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Extrapolation {
    /// Return [`crate::EvalError::OutOfRange`].
    Error,
    /// Evaluate the law at the nearest tabulated value: the law (jump and
    /// conductance) is constant beyond the table, derivatives along that axis are 0.
    Clamp,
    /// Continue linearly in the interpolation variable (`ln p`, `h`, `θ`) from the
    /// end value with the end slope (C1 continuation along pressure).
    Linear,
    /// Pressure only: a power law `jump ∝ p̄N^s` (so `k̄c ∝ p̄N^−s` at fixed
    /// flux, the form of the classical correlations), `s` the log–log secant
    /// slope of the end cell of each pressure line; the spread and the
    /// discretization error scale with the jump. Where an end cell holds a
    /// zero jump the continuation is constant.
    Power,
}

impl Extrapolation {
    /// The keyword used in law files: `error`, `clamp`, `linear`, `power`.
    pub const fn keyword(self) -> &'static str {
        match self {
            Extrapolation::Error => "error",
            Extrapolation::Clamp => "clamp",
            Extrapolation::Linear => "linear",
            Extrapolation::Power => "power",
        }
    }

    /// Whether the policy applies to `axis` (`power` is for pressure only).
    pub const fn allowed_on(self, axis: Axis) -> bool {
        !matches!(self, Extrapolation::Power) || matches!(axis, Axis::Pressure)
    }

    /// Parses a keyword of [`Extrapolation::keyword`].
    pub fn from_keyword(s: &str) -> Option<Self> {
        match s {
            "error" => Some(Extrapolation::Error),
            "clamp" => Some(Extrapolation::Clamp),
            "linear" => Some(Extrapolation::Linear),
            "power" => Some(Extrapolation::Power),
            _ => None,
        }
    }
}

impl fmt::Display for Extrapolation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.keyword())
    }
}

/// The extrapolation policy of each axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ExtrapolationPolicy {
    /// Policy along pressure.
    pub pressure: Extrapolation,
    /// Policy along flux.
    pub flux: Extrapolation,
    /// Policy along contact temperature.
    pub contact_temperature: Extrapolation,
}

impl ExtrapolationPolicy {
    /// The same policy on every axis.
    pub const fn uniform(e: Extrapolation) -> Self {
        ExtrapolationPolicy {
            pressure: e,
            flux: e,
            contact_temperature: e,
        }
    }

    /// The policy of one axis.
    pub const fn get(&self, axis: Axis) -> Extrapolation {
        match axis {
            Axis::Pressure => self.pressure,
            Axis::Flux => self.flux,
            Axis::ContactTemperature => self.contact_temperature,
        }
    }

    /// Sets the policy of one axis.
    pub fn set(&mut self, axis: Axis, e: Extrapolation) {
        match axis {
            Axis::Pressure => self.pressure = e,
            Axis::Flux => self.flux = e,
            Axis::ContactTemperature => self.contact_temperature = e,
        }
    }
}

impl Default for ExtrapolationPolicy {
    /// `error` on every axis: a query outside the table fails unless the
    /// caller (or the file) chooses a continuation.
    fn default() -> Self {
        ExtrapolationPolicy::uniform(Extrapolation::Error)
    }
}

impl ExtrapolationPolicy {
    /// Checks that every axis has a policy it allows ([`Extrapolation::allowed_on`]).
    pub fn validate(&self) -> Result<(), Error> {
        for axis in Axis::ALL {
            let e = self.get(axis);
            if !e.allowed_on(axis) {
                return Err(Error::invalid(
                    format!("extrapolation.{}", axis.name()),
                    format!("{e}: allowed on pressure only; expected error, clamp or linear"),
                ));
            }
        }
        Ok(())
    }
}

/// Which statistic of the ensemble the tabulated jump is. The conductance a
/// macroscale code gets is always `|h̄| / jump` of this statistic, so the
/// choice matters: the mean of the jump gives the harmonic-mean conductance
/// (the lower one), the mean of the conductance gives `jump = |h̄| / mean(k̄c)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Statistic {
    /// Mean of the jump over an ensemble of random surface samples.
    EnsembleMean {
        /// Number of samples in the ensemble (≥ 1).
        samples: u32,
    },
    /// The jump of the mean conductance: `|h̄| / mean(k̄c)`, i.e. the harmonic
    /// mean of the samples' jumps.
    EnsembleMeanConductance {
        /// Number of samples in the ensemble (≥ 1).
        samples: u32,
    },
    /// A quantile of the jump over the ensemble (linear interpolation between
    /// order statistics, numpy's default); a high percentile is the
    /// conservative (low-conductance) design value.
    EnsembleQuantile {
        /// Number of samples in the ensemble (≥ 1).
        samples: u32,
        /// The quantile in percent, 1–99.
        percent: u8,
    },
    /// The jump of one deterministic micro-sample (e.g. a sinusoid); the spread array is 0.
    Deterministic,
}

impl Statistic {
    /// The keyword used in law files: `ensemble_mean`,
    /// `ensemble_mean_conductance`, `ensemble_quantile` or `deterministic`.
    pub const fn keyword(self) -> &'static str {
        match self {
            Statistic::EnsembleMean { .. } => "ensemble_mean",
            Statistic::EnsembleMeanConductance { .. } => "ensemble_mean_conductance",
            Statistic::EnsembleQuantile { .. } => "ensemble_quantile",
            Statistic::Deterministic => "deterministic",
        }
    }

    /// Number of samples behind each entry (1 for deterministic).
    pub const fn samples(self) -> u32 {
        match self {
            Statistic::EnsembleMean { samples }
            | Statistic::EnsembleMeanConductance { samples }
            | Statistic::EnsembleQuantile { samples, .. } => samples,
            Statistic::Deterministic => 1,
        }
    }
}

/// The bulk material of one body, as the generator used it (spec §4, Table I
/// keys), so that a law for one material cannot pass for another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMaterial {
    /// Young's modulus `E` \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν` \[–\].
    pub poisson_ratio: f64,
    /// Linear thermal expansion `α0` \[1/K\].
    pub thermal_expansion: f64,
    /// Conductivity at the reference temperature `k0` \[W/(m·K)\], Eq. (5.1).
    pub thermal_conductivity: f64,
    /// Conductivity slope `k1` \[W/(m·K²)\], Eq. (5.1).
    pub conductivity_slope: f64,
    /// Reference temperature `θ0` \[K\].
    pub reference_temperature: f64,
}

impl BodyMaterial {
    /// The property names (law-file keys `material.<body>.<name>`), in file order.
    pub const NAMES: [&'static str; 6] = [
        "youngs_modulus",
        "poisson_ratio",
        "thermal_expansion",
        "thermal_conductivity",
        "conductivity_slope",
        "reference_temperature",
    ];

    /// The values in the order of [`BodyMaterial::NAMES`].
    pub const fn values(&self) -> [f64; 6] {
        [
            self.youngs_modulus,
            self.poisson_ratio,
            self.thermal_expansion,
            self.thermal_conductivity,
            self.conductivity_slope,
            self.reference_temperature,
        ]
    }

    /// Builds from values in the order of [`BodyMaterial::NAMES`].
    pub const fn from_values(v: [f64; 6]) -> Self {
        BodyMaterial {
            youngs_modulus: v[0],
            poisson_ratio: v[1],
            thermal_expansion: v[2],
            thermal_conductivity: v[3],
            conductivity_slope: v[4],
            reference_temperature: v[5],
        }
    }

    /// The first property (name, law value, given value) differing by more
    /// than `rel_tol` relative to the larger magnitude (exact equality for zeros).
    pub fn mismatch(&self, other: &BodyMaterial, rel_tol: f64) -> Option<(&'static str, f64, f64)> {
        let (a, b) = (self.values(), other.values());
        (0..6)
            .find(|&i| {
                let close = (a[i] - b[i]).abs() <= rel_tol * a[i].abs().max(b[i].abs());
                !close
            })
            .map(|i| (Self::NAMES[i], a[i], b[i]))
    }
}

/// The materials of the two bodies of the micro-sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawMaterial {
    /// Body 1 (slave, upper).
    pub upper: BodyMaterial,
    /// Body 2 (master, lower).
    pub lower: BodyMaterial,
}

impl LawMaterial {
    /// The material of body `"upper"` or `"lower"`.
    pub fn body(&self, name: &str) -> Option<&BodyMaterial> {
        match name {
            "upper" => Some(&self.upper),
            "lower" => Some(&self.lower),
            _ => None,
        }
    }
}

/// Everything a law file holds besides its axes and arrays.
#[derive(Clone, Debug, PartialEq)]
pub struct LawInfo {
    /// Which statistic the jump array holds.
    pub statistic: Statistic,
    /// The default extrapolation policy (callers may override it).
    pub extrapolation: ExtrapolationPolicy,
    /// The bulk materials behind the table (`None`: not recorded, e.g. a law
    /// built from a grid by hand or read from a version-1 file).
    pub material: Option<LawMaterial>,
    /// Generator provenance, in order: keys `[a-z0-9_.-]+` (written as
    /// `provenance.<key>`), values any text without control characters.
    /// Recommended keys: `generator`, `version`, `source`, `identification`,
    /// `surface`, `created`.
    pub provenance: Vec<(String, String)>,
}

impl Default for LawInfo {
    fn default() -> Self {
        LawInfo {
            statistic: Statistic::Deterministic,
            extrapolation: ExtrapolationPolicy::default(),
            material: None,
            provenance: Vec::new(),
        }
    }
}

/// Fixed `key = value` pairs of format version 1: the reader requires exactly these values.
pub(crate) const FIXED: [(&str, &str); 9] = [
    ("format", "tcgen-law"),
    ("layout", "pressure,flux,contact_temperature"),
    ("axis.pressure.unit", "Pa"),
    ("axis.pressure.interpolation", "steffen_log"),
    ("axis.flux.unit", "W/m^2"),
    ("axis.flux.interpolation", "linear"),
    ("axis.contact_temperature.unit", "K"),
    ("axis.contact_temperature.interpolation", "linear"),
    ("jump.unit", "K"),
];

/// Fixed text documenting the sign convention (spec §2).
pub(crate) const FLUX_CONVENTION: (&str, &str) = (
    "flux.convention",
    "magnitude; heat flows from body 1 (slave, upper) to body 2 (master, lower); jump > 0",
);

const PROVENANCE_PREFIX: &str = "provenance.";

fn key_is_valid(key: &str) -> bool {
    !key.is_empty()
        && key.bytes().all(|b| {
            b.is_ascii_lowercase() || b.is_ascii_digit() || matches!(b, b'_' | b'.' | b'-')
        })
}

fn value_is_valid(value: &str) -> bool {
    !value.chars().any(char::is_control)
}

/// Checks the provenance entries of `info` (used by the builder).
pub(crate) fn validate_provenance(provenance: &[(String, String)]) -> Result<(), Error> {
    for (i, (k, v)) in provenance.iter().enumerate() {
        if !key_is_valid(k) {
            return Err(Error::invalid(
                format!("provenance[{i}].key"),
                format!("{k:?}: expected a non-empty key of [a-z0-9_.-]"),
            ));
        }
        if !value_is_valid(v) {
            return Err(Error::invalid(
                format!("provenance[{i}].value"),
                "expected text without control characters (no newline)",
            ));
        }
        if provenance[..i].iter().any(|(k2, _)| k2 == k) {
            return Err(Error::invalid(
                format!("provenance[{i}].key"),
                format!("duplicate key {k:?}"),
            ));
        }
    }
    Ok(())
}

/// Writes the metadata text (format version 2) of `info`; `error_estimated`
/// says whether the law carries a discretization-error estimate.
pub(crate) fn to_text(info: &LawInfo, error_estimated: bool) -> String {
    let mut s = String::new();
    let mut line = |k: &str, v: &str| {
        s.push_str(k);
        s.push_str(" = ");
        s.push_str(v);
        s.push('\n');
    };
    for (k, v) in FIXED {
        line(k, v);
    }
    line(FLUX_CONVENTION.0, FLUX_CONVENTION.1);
    line("statistic", info.statistic.keyword());
    if let Statistic::EnsembleQuantile { percent, .. } = info.statistic {
        line("statistic.percent", &percent.to_string());
    }
    line("ensemble_size", &info.statistic.samples().to_string());
    line(
        "discretization_error",
        if error_estimated {
            "estimated"
        } else {
            "not_estimated"
        },
    );
    for axis in Axis::ALL {
        line(
            &format!("extrapolation.{}", axis.name()),
            info.extrapolation.get(axis).keyword(),
        );
    }
    match &info.material {
        None => line("material", "unspecified"),
        Some(m) => {
            line("material", "recorded");
            for (body, b) in [("upper", &m.upper), ("lower", &m.lower)] {
                for (name, v) in BodyMaterial::NAMES.iter().zip(b.values()) {
                    line(&format!("material.{body}.{name}"), &v.to_string());
                }
            }
        }
    }
    for (k, v) in &info.provenance {
        line(&format!("{PROVENANCE_PREFIX}{k}"), v);
    }
    s
}

/// A canonical integer `>= min` (no sign, no leading zero), as the writer writes it.
fn canonical_u32(value: &str, min: u32) -> Option<u32> {
    value
        .parse::<u32>()
        .ok()
        .filter(|&v| v >= min && v.to_string() == value)
}

/// Parses the metadata text of a file of format `version` (1 or 2; strict:
/// every required key once, no unknown key). Returns the info and whether the
/// law carries a discretization-error estimate (always false in version 1).
pub(crate) fn from_text(text: &str, version: u32) -> Result<(LawInfo, bool), Error> {
    let v2 = version >= 2;
    let mut fixed_seen = [false; FIXED.len()];
    let mut convention_seen = false;
    let mut statistic: Option<(usize, &str)> = None;
    let mut percent: Option<(usize, u8)> = None;
    let mut ensemble_size: Option<u32> = None;
    let mut error_estimated: Option<bool> = None;
    let mut material: Option<(usize, bool)> = None;
    let mut properties: [[Option<f64>; 6]; 2] = [[None; 6]; 2];
    let mut extrapolation: [Option<Extrapolation>; 3] = [None; 3];
    let mut provenance: Vec<(String, String)> = Vec::new();

    if !text.is_empty() && !text.ends_with('\n') {
        return Err(Error::metadata(
            0,
            "the last line does not end with a newline",
        ));
    }
    for (i, raw) in text.split('\n').enumerate() {
        let n = i + 1;
        if raw.is_empty() || raw.starts_with('#') {
            continue;
        }
        let Some((key, value)) = raw.split_once(" = ") else {
            return Err(Error::metadata(n, "expected 'key = value'"));
        };
        if !key_is_valid(key) {
            return Err(Error::metadata(n, format!("invalid key {key:?}")));
        }
        if !value_is_valid(value) {
            return Err(Error::metadata(n, "value contains control characters"));
        }
        let duplicate = || Error::metadata(n, format!("duplicate key {key:?}"));
        let unknown = || {
            Error::metadata(
                n,
                format!("unknown key {key:?} in a version {version} file"),
            )
        };
        if let Some(j) = FIXED.iter().position(|(k, _)| *k == key) {
            if fixed_seen[j] {
                return Err(duplicate());
            }
            fixed_seen[j] = true;
            if value != FIXED[j].1 {
                return Err(Error::metadata(
                    n,
                    format!(
                        "{key} is {value:?}; version {version} requires {:?}",
                        FIXED[j].1
                    ),
                ));
            }
        } else if key == FLUX_CONVENTION.0 {
            if convention_seen {
                return Err(duplicate());
            }
            convention_seen = true;
            if value != FLUX_CONVENTION.1 {
                return Err(Error::metadata(
                    n,
                    format!(
                        "{key} is {value:?}; version {version} requires {:?}",
                        FLUX_CONVENTION.1
                    ),
                ));
            }
        } else if key == "statistic" {
            if statistic.is_some() {
                return Err(duplicate());
            }
            statistic = Some((n, value));
        } else if key == "statistic.percent" && v2 {
            if percent.is_some() {
                return Err(duplicate());
            }
            match canonical_u32(value, 1).filter(|&q| q <= 99) {
                Some(q) => percent = Some((n, q as u8)),
                None => {
                    return Err(Error::metadata(
                        n,
                        format!("statistic.percent is {value:?}; expected an integer in 1..=99"),
                    ));
                }
            }
        } else if key == "ensemble_size" {
            if ensemble_size.is_some() {
                return Err(duplicate());
            }
            match canonical_u32(value, 1) {
                Some(s) => ensemble_size = Some(s),
                None => {
                    return Err(Error::metadata(
                        n,
                        format!("ensemble_size is {value:?}; expected an integer >= 1"),
                    ));
                }
            }
        } else if key == "discretization_error" && v2 {
            if error_estimated.is_some() {
                return Err(duplicate());
            }
            error_estimated = Some(match value {
                "estimated" => true,
                "not_estimated" => false,
                _ => {
                    return Err(Error::metadata(
                        n,
                        format!("{key} is {value:?}; expected estimated or not_estimated"),
                    ));
                }
            });
        } else if key == "material" && v2 {
            if material.is_some() {
                return Err(duplicate());
            }
            material = Some((
                n,
                match value {
                    "recorded" => true,
                    "unspecified" => false,
                    _ => {
                        return Err(Error::metadata(
                            n,
                            format!("{key} is {value:?}; expected recorded or unspecified"),
                        ));
                    }
                },
            ));
        } else if let Some(rest) = key.strip_prefix("material.").filter(|_| v2) {
            let slot = rest.split_once('.').and_then(|(body, name)| {
                let b = ["upper", "lower"].iter().position(|x| *x == body)?;
                let j = BodyMaterial::NAMES.iter().position(|x| *x == name)?;
                Some((b, j))
            });
            let Some((b, j)) = slot else {
                return Err(unknown());
            };
            if properties[b][j].is_some() {
                return Err(duplicate());
            }
            // Finite and canonical (shortest round-trip form, as written).
            match value.parse::<f64>() {
                Ok(x) if x.is_finite() && x.to_string() == value => properties[b][j] = Some(x),
                _ => {
                    return Err(Error::metadata(
                        n,
                        format!("{key} is {value:?}; expected a finite number"),
                    ));
                }
            }
        } else if let Some(name) = key.strip_prefix("extrapolation.") {
            let Some(axis) = Axis::ALL.into_iter().find(|a| a.name() == name) else {
                return Err(unknown());
            };
            let slot = &mut extrapolation[axis as usize];
            if slot.is_some() {
                return Err(duplicate());
            }
            let e = Extrapolation::from_keyword(value)
                .filter(|e| e.allowed_on(axis) && (v2 || *e != Extrapolation::Power))
                .ok_or_else(|| {
                    Error::metadata(
                        n,
                        format!(
                            "{key} is {value:?}; expected error, clamp, linear{}",
                            if v2 && axis == Axis::Pressure {
                                " or power"
                            } else {
                                ""
                            }
                        ),
                    )
                })?;
            *slot = Some(e);
        } else if let Some(name) = key.strip_prefix(PROVENANCE_PREFIX) {
            if name.is_empty() {
                return Err(Error::metadata(n, "empty provenance key"));
            }
            if provenance.iter().any(|(k, _)| k == name) {
                return Err(duplicate());
            }
            provenance.push((name.to_string(), value.to_string()));
        } else {
            return Err(unknown());
        }
    }

    let missing = |key: &str| Error::metadata(0, format!("missing key {key:?}"));
    if let Some(j) = fixed_seen.iter().position(|seen| !seen) {
        return Err(missing(FIXED[j].0));
    }
    if !convention_seen {
        return Err(missing(FLUX_CONVENTION.0));
    }
    let Some(samples) = ensemble_size else {
        return Err(missing("ensemble_size"));
    };
    let statistic = match statistic {
        None => return Err(missing("statistic")),
        Some((_, "ensemble_mean")) => Statistic::EnsembleMean { samples },
        Some((_, "ensemble_mean_conductance")) if v2 => {
            Statistic::EnsembleMeanConductance { samples }
        }
        Some((n, "ensemble_quantile")) if v2 => match percent {
            Some((_, percent)) => Statistic::EnsembleQuantile { samples, percent },
            None => {
                return Err(Error::metadata(
                    n,
                    "statistic ensemble_quantile needs the key \"statistic.percent\"",
                ));
            }
        },
        Some((n, "deterministic")) => {
            if samples != 1 {
                return Err(Error::metadata(
                    n,
                    format!("statistic deterministic requires ensemble_size = 1, found {samples}"),
                ));
            }
            Statistic::Deterministic
        }
        Some((n, other)) => {
            return Err(Error::metadata(
                n,
                format!(
                    "statistic is {other:?}; expected {}",
                    if v2 {
                        "ensemble_mean, ensemble_mean_conductance, ensemble_quantile or deterministic"
                    } else {
                        "ensemble_mean or deterministic"
                    }
                ),
            ));
        }
    };
    if let (Some((n, _)), false) = (
        percent,
        matches!(statistic, Statistic::EnsembleQuantile { .. }),
    ) {
        return Err(Error::metadata(
            n,
            "statistic.percent is only allowed with statistic = ensemble_quantile",
        ));
    }
    let mut policy = ExtrapolationPolicy::default();
    for axis in Axis::ALL {
        let Some(e) = extrapolation[axis as usize] else {
            return Err(missing(&format!("extrapolation.{}", axis.name())));
        };
        policy.set(axis, e);
    }
    let material = if v2 {
        let Some((line, recorded)) = material else {
            return Err(missing("material"));
        };
        let mut bodies = [None, None];
        for (b, body) in ["upper", "lower"].iter().enumerate() {
            let given = properties[b].iter().filter(|v| v.is_some()).count();
            if !recorded && given > 0 {
                return Err(Error::metadata(
                    line,
                    format!("material = unspecified, yet material.{body}.* keys are given"),
                ));
            }
            if recorded {
                let mut v = [0.0; 6];
                for (j, name) in BodyMaterial::NAMES.iter().enumerate() {
                    v[j] = properties[b][j]
                        .ok_or_else(|| missing(&format!("material.{body}.{name}")))?;
                }
                bodies[b] = Some(BodyMaterial::from_values(v));
            }
        }
        match bodies {
            [Some(upper), Some(lower)] => Some(LawMaterial { upper, lower }),
            _ => None,
        }
    } else {
        None
    };
    let error_estimated = if v2 {
        error_estimated.ok_or_else(|| missing("discretization_error"))?
    } else {
        false
    };
    Ok((
        LawInfo {
            statistic,
            extrapolation: policy,
            material,
            provenance,
        },
        error_estimated,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> LawInfo {
        LawInfo {
            statistic: Statistic::EnsembleMean { samples: 16 },
            extrapolation: ExtrapolationPolicy {
                pressure: Extrapolation::Error,
                flux: Extrapolation::Clamp,
                contact_temperature: Extrapolation::Linear,
            },
            material: None,
            provenance: vec![
                ("generator".into(), "tcgen 0.1.0".into()),
                ("source".into(), "table = a.h5".into()),
            ],
        }
    }

    #[test]
    fn metadata_round_trips() {
        let mut info = sample();
        let text = to_text(&info, true);
        assert_eq!(from_text(&text, 2).unwrap(), (info.clone(), true));
        assert_eq!(to_text(&from_text(&text, 2).unwrap().0, true), text);
        // With a material, a quantile and the power continuation.
        let m = BodyMaterial::from_values([1e6, 0.3, 1e-5, 1.0, 0.01, 293.15]);
        info.material = Some(LawMaterial {
            upper: m,
            lower: BodyMaterial {
                youngs_modulus: 2.1e11,
                ..m
            },
        });
        info.statistic = Statistic::EnsembleQuantile {
            samples: 16,
            percent: 90,
        };
        info.extrapolation.pressure = Extrapolation::Power;
        let text = to_text(&info, false);
        assert!(
            text.contains("material.lower.youngs_modulus = 210000000000\n"),
            "{text}"
        );
        assert_eq!(from_text(&text, 2).unwrap(), (info, false));
    }

    #[test]
    fn metadata_rejects_missing_unknown_duplicate_and_wrong_unit() {
        let text = to_text(&sample(), false);
        let missing = text.replace("jump.unit = K\n", "");
        assert!(
            from_text(&missing, 2)
                .unwrap_err()
                .to_string()
                .contains("jump.unit")
        );
        let unknown = format!("{text}colour = blue\n");
        assert!(
            from_text(&unknown, 2)
                .unwrap_err()
                .to_string()
                .contains("colour")
        );
        let dup = format!("{text}statistic = ensemble_mean\n");
        assert!(
            from_text(&dup, 2)
                .unwrap_err()
                .to_string()
                .contains("duplicate")
        );
        let unit = text.replace("axis.pressure.unit = Pa", "axis.pressure.unit = MPa");
        assert!(from_text(&unit, 2).unwrap_err().to_string().contains("MPa"));
        for bad in ["08", "+8", "0", "-1", "8.0", " 8"] {
            let t = text.replace("ensemble_size = 16", &format!("ensemble_size = {bad}"));
            assert!(
                from_text(&t, 2)
                    .unwrap_err()
                    .to_string()
                    .contains("ensemble_size"),
                "{bad}"
            );
        }
        let det = text.replace("statistic = ensemble_mean", "statistic = deterministic");
        assert!(
            from_text(&det, 2)
                .unwrap_err()
                .to_string()
                .contains("ensemble_size")
        );
        let no_newline = text.trim_end();
        assert!(from_text(no_newline, 2).is_err());
    }

    /// Version 2 keys are refused in a version-1 file and checked in version 2.
    #[test]
    fn version_specific_keys() {
        let text = to_text(&sample(), false);
        let e = from_text(&text, 1).unwrap_err().to_string();
        assert!(e.contains("discretization_error"), "{e}");
        let v1 = text
            .replace("discretization_error = not_estimated\n", "")
            .replace("material = unspecified\n", "");
        assert_eq!(from_text(&v1, 1).unwrap(), (sample(), false));
        let power = v1.replace(
            "extrapolation.pressure = error",
            "extrapolation.pressure = power",
        );
        assert!(from_text(&power, 1).is_err());
        let flux_power = text.replace("extrapolation.flux = clamp", "extrapolation.flux = power");
        let e = from_text(&flux_power, 2).unwrap_err().to_string();
        assert!(e.contains("extrapolation.flux"), "{e}");
        let partial = text.replace(
            "material = unspecified\n",
            "material = recorded\nmaterial.upper.youngs_modulus = 1000000\n",
        );
        let e = from_text(&partial, 2).unwrap_err().to_string();
        assert!(e.contains("material.upper.poisson_ratio"), "{e}");
        let quantile = text.replace("statistic = ensemble_mean", "statistic = ensemble_quantile");
        assert!(
            from_text(&quantile, 2)
                .unwrap_err()
                .to_string()
                .contains("statistic.percent")
        );
        let stray = text.replace(
            "ensemble_size = 16\n",
            "ensemble_size = 16\nstatistic.percent = 50\n",
        );
        assert!(from_text(&stray, 2).is_err());
    }

    #[test]
    fn provenance_rejects_newlines_and_bad_keys() {
        let p = vec![("a".to_string(), "x\ny".to_string())];
        assert!(validate_provenance(&p).is_err());
        let p = vec![("A B".to_string(), "x".to_string())];
        assert!(validate_provenance(&p).is_err());
        let p = vec![("a".to_string(), "x".to_string()); 2];
        assert!(validate_provenance(&p).is_err());
    }
}
