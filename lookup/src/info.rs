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
}

impl Extrapolation {
    /// The keyword used in law files: `error`, `clamp`, `linear`.
    pub const fn keyword(self) -> &'static str {
        match self {
            Extrapolation::Error => "error",
            Extrapolation::Clamp => "clamp",
            Extrapolation::Linear => "linear",
        }
    }

    /// Parses a keyword of [`Extrapolation::keyword`].
    pub fn from_keyword(s: &str) -> Option<Self> {
        match s {
            "error" => Some(Extrapolation::Error),
            "clamp" => Some(Extrapolation::Clamp),
            "linear" => Some(Extrapolation::Linear),
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
    /// `clamp` on every axis.
    fn default() -> Self {
        ExtrapolationPolicy::uniform(Extrapolation::Clamp)
    }
}

/// Which statistic the tabulated jump is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Statistic {
    /// Mean of the jump over an ensemble of random surface samples; the spread
    /// array holds the sample standard deviation (`n − 1` normalisation, 0 when `samples = 1`).
    EnsembleMean {
        /// Number of samples in the ensemble (≥ 1).
        samples: u32,
    },
    /// The jump of one deterministic micro-sample (e.g. a sinusoid); the spread array is 0.
    Deterministic,
}

impl Statistic {
    /// The keyword used in law files: `ensemble_mean` or `deterministic`.
    pub const fn keyword(self) -> &'static str {
        match self {
            Statistic::EnsembleMean { .. } => "ensemble_mean",
            Statistic::Deterministic => "deterministic",
        }
    }

    /// Number of samples behind each entry (1 for deterministic).
    pub const fn samples(self) -> u32 {
        match self {
            Statistic::EnsembleMean { samples } => samples,
            Statistic::Deterministic => 1,
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

/// Writes the metadata text of `info`.
pub(crate) fn to_text(info: &LawInfo) -> String {
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
    line("ensemble_size", &info.statistic.samples().to_string());
    for axis in Axis::ALL {
        line(
            &format!("extrapolation.{}", axis.name()),
            info.extrapolation.get(axis).keyword(),
        );
    }
    for (k, v) in &info.provenance {
        line(&format!("{PROVENANCE_PREFIX}{k}"), v);
    }
    s
}

/// Parses the metadata text (strict: every required key once, no unknown key).
pub(crate) fn from_text(text: &str) -> Result<LawInfo, Error> {
    let mut fixed_seen = [false; FIXED.len()];
    let mut convention_seen = false;
    let mut statistic: Option<(usize, &str)> = None;
    let mut ensemble_size: Option<u32> = None;
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
        if let Some(j) = FIXED.iter().position(|(k, _)| *k == key) {
            if fixed_seen[j] {
                return Err(duplicate());
            }
            fixed_seen[j] = true;
            if value != FIXED[j].1 {
                return Err(Error::metadata(
                    n,
                    format!("{key} is {value:?}; version 1 requires {:?}", FIXED[j].1),
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
                        "{key} is {value:?}; version 1 requires {:?}",
                        FLUX_CONVENTION.1
                    ),
                ));
            }
        } else if key == "statistic" {
            if statistic.is_some() {
                return Err(duplicate());
            }
            statistic = Some((n, value));
        } else if key == "ensemble_size" {
            if ensemble_size.is_some() {
                return Err(duplicate());
            }
            // Canonical decimal only (no sign, no leading zero), as the writer writes it.
            match value.parse::<u32>() {
                Ok(s) if s >= 1 && s.to_string() == value => ensemble_size = Some(s),
                _ => {
                    return Err(Error::metadata(
                        n,
                        format!("ensemble_size is {value:?}; expected an integer >= 1"),
                    ));
                }
            }
        } else if let Some(name) = key.strip_prefix("extrapolation.") {
            let Some(axis) = Axis::ALL.into_iter().find(|a| a.name() == name) else {
                return Err(Error::metadata(n, format!("unknown key {key:?}")));
            };
            let slot = &mut extrapolation[axis as usize];
            if slot.is_some() {
                return Err(duplicate());
            }
            *slot = Some(Extrapolation::from_keyword(value).ok_or_else(|| {
                Error::metadata(
                    n,
                    format!("{key} is {value:?}; expected error, clamp or linear"),
                )
            })?);
        } else if let Some(name) = key.strip_prefix(PROVENANCE_PREFIX) {
            if name.is_empty() {
                return Err(Error::metadata(n, "empty provenance key"));
            }
            if provenance.iter().any(|(k, _)| k == name) {
                return Err(duplicate());
            }
            provenance.push((name.to_string(), value.to_string()));
        } else {
            return Err(Error::metadata(n, format!("unknown key {key:?}")));
        }
    }

    if let Some(j) = fixed_seen.iter().position(|seen| !seen) {
        return Err(Error::metadata(0, format!("missing key {:?}", FIXED[j].0)));
    }
    if !convention_seen {
        return Err(Error::metadata(
            0,
            format!("missing key {:?}", FLUX_CONVENTION.0),
        ));
    }
    let Some(samples) = ensemble_size else {
        return Err(Error::metadata(0, "missing key \"ensemble_size\""));
    };
    let statistic = match statistic {
        None => return Err(Error::metadata(0, "missing key \"statistic\"")),
        Some((_, "ensemble_mean")) => Statistic::EnsembleMean { samples },
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
                format!("statistic is {other:?}; expected ensemble_mean or deterministic"),
            ));
        }
    };
    let mut policy = ExtrapolationPolicy::default();
    for axis in Axis::ALL {
        let Some(e) = extrapolation[axis as usize] else {
            return Err(Error::metadata(
                0,
                format!("missing key \"extrapolation.{}\"", axis.name()),
            ));
        };
        policy.set(axis, e);
    }
    Ok(LawInfo {
        statistic,
        extrapolation: policy,
        provenance,
    })
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
            provenance: vec![
                ("generator".into(), "tcgen 0.1.0".into()),
                ("source".into(), "table = a.h5".into()),
            ],
        }
    }

    #[test]
    fn metadata_round_trips() {
        let info = sample();
        let text = to_text(&info);
        assert_eq!(from_text(&text).unwrap(), info);
        assert_eq!(to_text(&from_text(&text).unwrap()), text);
    }

    #[test]
    fn metadata_rejects_missing_unknown_duplicate_and_wrong_unit() {
        let text = to_text(&sample());
        let missing = text.replace("jump.unit = K\n", "");
        assert!(
            from_text(&missing)
                .unwrap_err()
                .to_string()
                .contains("jump.unit")
        );
        let unknown = format!("{text}colour = blue\n");
        assert!(
            from_text(&unknown)
                .unwrap_err()
                .to_string()
                .contains("colour")
        );
        let dup = format!("{text}statistic = ensemble_mean\n");
        assert!(
            from_text(&dup)
                .unwrap_err()
                .to_string()
                .contains("duplicate")
        );
        let unit = text.replace("axis.pressure.unit = Pa", "axis.pressure.unit = MPa");
        assert!(from_text(&unit).unwrap_err().to_string().contains("MPa"));
        for bad in ["08", "+8", "0", "-1", "8.0", " 8"] {
            let t = text.replace("ensemble_size = 16", &format!("ensemble_size = {bad}"));
            assert!(
                from_text(&t)
                    .unwrap_err()
                    .to_string()
                    .contains("ensemble_size"),
                "{bad}"
            );
        }
        let det = text.replace("statistic = ensemble_mean", "statistic = deterministic");
        assert!(
            from_text(&det)
                .unwrap_err()
                .to_string()
                .contains("ensemble_size")
        );
        let no_newline = text.trim_end();
        assert!(from_text(no_newline).is_err());
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
