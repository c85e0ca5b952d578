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
            SurfaceSpec::Flat | SurfaceSpec::Profile { .. } => Ok(()),
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
            SurfaceSpec::Profile { file } => {
                let path = if file.is_absolute() {
                    file.clone()
                } else {
                    base.join(file)
                };
                Box::new(Profile::read(&path, width, &format!("{key}.file"))?)
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
