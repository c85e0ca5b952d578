//! Rough surface families (spec §3): height functions `f(x)` about the mean
//! plane, periodic over the sample width, in one global frame for both bodies
//! (two surfaces with the same parameters are identical, hence conforming).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

pub mod areal;
pub mod profile;
pub mod random;

pub use areal::{ArealSpec, ArealSurface, HeightMap, RandomArealSurface, SinusoidPattern};
pub use profile::Profile;
pub use random::{RandomSpec, RandomSurface, SpectrumKind};

/// The data file of a measured surface (`kind = "profile"` in 2D,
/// `"heightmap"` in 3D) of the table `key`: `file` resolved against the case
/// file's directory `base`, and its text. Where the case pins the file's
/// content by `file_sha256` (a sweep writes the digest into its resolved
/// configuration, so that its hash, its checkpoints and its table identify
/// the heights, not only the file's name), a file of another SHA-256 is an
/// error naming `{key}.file_sha256`.
pub fn read_data_file(
    key: &str,
    file: &Path,
    pinned: Option<&str>,
    base: &Path,
) -> Result<(PathBuf, String)> {
    let path = if file.is_absolute() {
        file.to_path_buf()
    } else {
        base.join(file)
    };
    let text = crate::error::read_text(&path)?;
    if let Some(pinned) = pinned {
        let actual = crate::io::hash::sha256_hex(text.as_bytes());
        if !actual.eq_ignore_ascii_case(pinned) {
            return Err(Error::invalid(
                format!("{key}.file_sha256"),
                pinned,
                format!(
                    "the SHA-256 of {}, {actual}: the file has changed since the configuration pinned it (restore the file, or remove the key)",
                    path.display()
                ),
            ));
        }
    }
    Ok((path, text))
}

/// The height steps of a measured surface across its periodic seam (from its
/// last sample back to its first, over every line of samples that crosses
/// it) and between neighbouring samples inside, as RMS values (m). A map
/// that was not made periodic (a crop of a larger scan) steps across its seam
/// by about `√2` times its RMS height, a ridge or trench along the cell's
/// edges that is not in the surface; a periodic one as inside.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeamSteps {
    /// RMS step across the seam (m).
    pub across: f64,
    /// RMS step between neighbouring samples inside (m).
    pub inside: f64,
}

impl SeamSteps {
    /// The ratio `across / inside` above which [`SeamSteps::is_periodic`]
    /// says no: a periodic map's seam steps like its inside (ratios 0.8–1.3
    /// measured on two 32 × 32 maps), corners of a smooth one 2.8–9.6
    /// (docs/3d.md, "Stop 104").
    pub const RATIO: f64 = 3.0;

    /// Of `lines` lines of `n` samples, `at(line, k)` the `k`-th sample.
    pub fn of(lines: usize, n: usize, at: impl Fn(usize, usize) -> f64) -> Self {
        let (mut across, mut inside) = (0.0, 0.0);
        for l in 0..lines {
            across += (at(l, 0) - at(l, n - 1)).powi(2);
            inside += (1..n)
                .map(|k| (at(l, k) - at(l, k - 1)).powi(2))
                .sum::<f64>();
        }
        SeamSteps {
            across: (across / lines as f64).sqrt(),
            inside: (inside / (lines * (n - 1)) as f64).sqrt(),
        }
    }

    /// Whether the seam steps like the inside (within [`SeamSteps::RATIO`]).
    pub fn is_periodic(&self) -> bool {
        self.across <= Self::RATIO * self.inside
    }
}

/// A `file_sha256` key, where given: 64 hexadecimal digits.
pub(crate) fn check_sha256_key(key: &str, digest: Option<&str>) -> Result<()> {
    match digest {
        Some(d) if d.len() != 64 || !d.bytes().all(|b| b.is_ascii_hexdigit()) => {
            Err(Error::invalid(
                format!("{key}.file_sha256"),
                format!("{d:?}"),
                "the file's SHA-256 as 64 hexadecimal digits (`sha256sum FILE`), or absent",
            ))
        }
        _ => Ok(()),
    }
}

/// A surface height function over `[0, width]`, zero mean, periodic.
pub trait Surface: Send + Sync {
    /// Height `f(x)` (m) about the mean plane.
    fn height(&self, x: f64) -> f64;
}

/// A surface as the case file gives it (`[surface.upper]`, `[surface.lower]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SurfaceSpec {
    /// `f = 0`.
    Flat,
    /// `f(x) = √2·rms·cos(2πx/λ + phase)`.
    Sinusoid {
        /// RMS roughness (m); amplitude `A = √2 rms`.
        rms: f64,
        /// Wavelength λ (m); must divide the sample width.
        wavelength: f64,
        /// Phase (rad), for mismatched sinusoids (Sect. 5.3).
        #[serde(default)]
        phase: f64,
    },
    /// A measured or generated profile: CSV with columns `x,z` in m, periodic over the width.
    Profile {
        /// Path of the CSV file, relative to the case file.
        file: PathBuf,
        /// SHA-256 of the file's content ([`read_data_file`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        file_sha256: Option<String>,
    },
    /// Gaussian random heights, periodic, seeded (see [`random`]); keys of [`RandomSpec`].
    Random(RandomSpec),
}

/// `f(x) = A cos(2πx/λ + φ)`.
#[derive(Clone, Copy, Debug)]
pub struct Sinusoid {
    /// Amplitude `A`.
    pub amplitude: f64,
    /// Wavelength λ.
    pub wavelength: f64,
    /// Phase φ.
    pub phase: f64,
}

impl Surface for Sinusoid {
    fn height(&self, x: f64) -> f64 {
        self.amplitude * (std::f64::consts::TAU * x / self.wavelength + self.phase).cos()
    }
}

/// `f = 0`.
#[derive(Clone, Copy, Debug)]
pub struct Flat;

impl Surface for Flat {
    fn height(&self, _x: f64) -> f64 {
        0.0
    }
}

impl SurfaceSpec {
    /// Checks the parameters against the sample width; `key` names the table (e.g. `surface.upper`).
    pub fn validate(&self, key: &str, width: f64) -> Result<()> {
        match self {
            SurfaceSpec::Flat => Ok(()),
            SurfaceSpec::Profile { file_sha256, .. } => {
                check_sha256_key(key, file_sha256.as_deref())
            }
            SurfaceSpec::Random(r) => r.validate(key, width),
            SurfaceSpec::Sinusoid {
                rms,
                wavelength,
                phase,
            } => {
                if !(rms.is_finite() && *rms >= 0.0 && *rms < width) {
                    return Err(Error::invalid(
                        format!("{key}.rms"),
                        rms,
                        format!("a length in [0, width = {width}) m"),
                    ));
                }
                if !(wavelength.is_finite() && *wavelength > 0.0 && *wavelength <= width) {
                    return Err(Error::invalid(
                        format!("{key}.wavelength"),
                        wavelength,
                        format!("a length in (0, width = {width}] m"),
                    ));
                }
                let n = width / wavelength;
                if (n - n.round()).abs() > 1e-9 * n {
                    return Err(Error::invalid(
                        format!("{key}.wavelength"),
                        wavelength,
                        format!(
                            "a divisor of sample.width = {width} m (periodic samples), e.g. {}",
                            width / n.round().max(1.0)
                        ),
                    ));
                }
                if !phase.is_finite() {
                    return Err(Error::invalid(
                        format!("{key}.phase"),
                        phase,
                        "a finite angle (rad)",
                    ));
                }
                Ok(())
            }
        }
    }

    /// The height function; `base` is the directory of the case file (for profiles).
    pub fn build(&self, key: &str, width: f64, base: &Path) -> Result<Box<dyn Surface>> {
        self.validate(key, width)?;
        Ok(match self {
            SurfaceSpec::Flat => Box::new(Flat),
            SurfaceSpec::Sinusoid {
                rms,
                wavelength,
                phase,
            } => Box::new(Sinusoid {
                amplitude: rms * std::f64::consts::SQRT_2,
                wavelength: *wavelength,
                phase: *phase,
            }),
            SurfaceSpec::Profile { file, file_sha256 } => {
                let (path, text) = read_data_file(key, file, file_sha256.as_deref(), base)?;
                Box::new(Profile::parse(&text, &path, width, &format!("{key}.file"))?)
            }
            SurfaceSpec::Random(r) => Box::new(r.generate(key, width)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sinusoid_rms_is_amplitude_over_sqrt2() {
        let s = SurfaceSpec::Sinusoid {
            rms: 1e-6,
            wavelength: 1e-5,
            phase: 0.3,
        }
        .build("s", 1e-5, Path::new("."))
        .unwrap();
        let n = 1000;
        let (mut m, mut q) = (0.0, 0.0);
        for i in 0..n {
            let h = s.height(1e-5 * i as f64 / n as f64);
            m += h / n as f64;
            q += h * h / n as f64;
        }
        assert!(m.abs() < 1e-18 && (q.sqrt() - 1e-6).abs() < 1e-15);
    }

    #[test]
    fn wavelength_must_divide_the_width() {
        let e = SurfaceSpec::Sinusoid {
            rms: 1e-6,
            wavelength: 3e-6,
            phase: 0.0,
        }
        .validate("surface.upper", 1e-5);
        let msg = e.unwrap_err().to_string();
        assert!(msg.contains("surface.upper.wavelength"), "{msg}");
    }
}
