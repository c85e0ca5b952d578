//! Imported surface profiles: CSV with columns `x,z` (m), sampled uniformly
//! over one period `[0, width)` (a last sample at `x = width` repeating the
//! first is accepted), interpolated periodically (cubic, Catmull–Rom), mean removed.

use std::path::Path;

use crate::surface::Surface;
use crate::{Error, Result};

/// A periodic sampled profile.
#[derive(Clone, Debug)]
pub struct Profile {
    z: Vec<f64>,
    width: f64,
    /// The mean height removed from the data (m).
    pub removed_mean: f64,
}

impl Profile {
    /// Builds from uniformly spaced heights over `[0, width)`; `key` names the input for errors.
    pub fn from_samples(z: Vec<f64>, width: f64, key: &str) -> Result<Self> {
        if z.len() < 4 {
            return Err(Error::invalid(
                key,
                z.len(),
                "at least 4 samples per period",
            ));
        }
        if let Some(v) = z.iter().find(|v| !v.is_finite()) {
            return Err(Error::invalid(key, v, "finite heights"));
        }
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        let z: Vec<f64> = z.iter().map(|v| v - mean).collect();
        let range = z.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - z.iter().cloned().fold(f64::INFINITY, f64::min);
        if range >= width {
            return Err(Error::invalid(
                key,
                format!("peak-to-valley {range:e} m"),
                format!(
                    "heights smaller than the sample width {width:e} m (are the units metres?)"
                ),
            ));
        }
        Ok(Profile {
            z,
            width,
            removed_mean: mean,
        })
    }

    /// The steps across the periodic seam and between the samples inside.
    pub fn seam_steps(&self) -> crate::surface::SeamSteps {
        crate::surface::SeamSteps::of(1, self.z.len(), |_, k| self.z[k])
    }

    /// Reads a CSV file `x,z` (m); an optional header line is skipped.
    pub fn read(path: &Path, width: f64, key: &str) -> Result<Self> {
        Self::parse(&crate::error::read_text(path)?, path, width, key)
    }

    /// Parses the text of [`Profile::read`]'s CSV, read from `path`.
    pub fn parse(text: &str, path: &Path, width: f64, key: &str) -> Result<Self> {
        let mut xs = Vec::new();
        let mut zs = Vec::new();
        for (ln, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            let parsed: Option<(f64, f64)> = match cols.as_slice() {
                [a, b] => a.parse().ok().zip(b.parse().ok()),
                _ => None,
            };
            match parsed {
                Some((x, z)) => {
                    xs.push(x);
                    zs.push(z);
                }
                None if xs.is_empty() && ln == 0 => continue, // header
                None => {
                    return Err(Error::invalid(
                        format!("{key} ({}:{})", path.display(), ln + 1),
                        format!("{line:?}"),
                        "two comma-separated numbers x,z (m)",
                    ));
                }
            }
        }
        let n = xs.len();
        if n < 4 {
            return Err(Error::invalid(
                key,
                format!("{n} samples"),
                "at least 4 samples per period",
            ));
        }
        let dx = xs[1] - xs[0];
        if xs[0].abs() > 1e-9 * width || dx <= 0.0 {
            return Err(Error::invalid(
                key,
                format!("x starts at {:e}, spacing {dx:e}", xs[0]),
                "x from 0 upward in m",
            ));
        }
        for (i, w) in xs.windows(2).enumerate() {
            if ((w[1] - w[0]) - dx).abs() > 1e-6 * dx {
                return Err(Error::invalid(
                    format!("{key} (row {})", i + 2),
                    format!("spacing {:e}", w[1] - w[0]),
                    format!("uniform spacing {dx:e} m"),
                ));
            }
        }
        let last = xs[n - 1];
        // Either x covers [0, W) or [0, W] with a repeated end.
        let (z, ok) = if (last + dx - width).abs() <= 1e-6 * dx {
            (zs, true)
        } else if (last - width).abs() <= 1e-6 * dx {
            let end = zs[n - 1];
            let range = zs.iter().cloned().fold(0.0_f64, |a, b| a.max(b.abs()));
            if (end - zs[0]).abs() > 1e-6 * range.max(f64::MIN_POSITIVE) {
                return Err(Error::invalid(
                    key,
                    format!("z(0) = {:e}, z(W) = {end:e}", zs[0]),
                    "a periodic profile: z(width) = z(0)",
                ));
            }
            (zs[..n - 1].to_vec(), true)
        } else {
            (zs, false)
        };
        if !ok {
            return Err(Error::invalid(
                key,
                format!("x spans [0, {last:e}] m with spacing {dx:e}"),
                format!(
                    "one period of the sample width {width:e} m: last x = width − spacing, or = width"
                ),
            ));
        }
        Profile::from_samples(z, width, key)
    }
}

impl Surface for Profile {
    fn height(&self, x: f64) -> f64 {
        let n = self.z.len();
        let t = (x / self.width).rem_euclid(1.0) * n as f64;
        let i = t.floor() as isize;
        let s = t - i as f64;
        let at = |k: isize| self.z[k.rem_euclid(n as isize) as usize];
        let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
        // Catmull–Rom: C1, interpolating, exact for quadratics on uniform samples.
        0.5 * (2.0 * p1
            + (-p0 + p2) * s
            + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * s * s
            + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * s * s * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `text` in a temporary file, removed when the returned path drops.
    fn write(name: &str, text: &str) -> tempfile::TempPath {
        let file = tempfile::Builder::new()
            .prefix(&format!("tcgen-profile-{name}-"))
            .suffix(".csv")
            .tempfile()
            .unwrap();
        std::fs::write(file.path(), text).unwrap();
        file.into_temp_path()
    }

    #[test]
    fn reads_and_interpolates_a_periodic_profile() {
        let w = 1e-5;
        let n = 64;
        let mut s = String::from("x,z\n");
        for i in 0..=n {
            let x = w * i as f64 / n as f64;
            s += &format!(
                "{x},{}\n",
                1e-6 * (std::f64::consts::TAU * x / w).sin() + 3e-7
            );
        }
        let p = Profile::read(&write("ok", &s), w, "surface.lower.file").unwrap();
        assert!((p.removed_mean - 3e-7).abs() < 1e-15);
        let x = 0.123 * w;
        assert!((p.height(x) - 1e-6 * (std::f64::consts::TAU * 0.123).sin()).abs() < 1e-9);
        assert!((p.height(x + w) - p.height(x)).abs() < 1e-20);
    }

    #[test]
    fn rejects_non_periodic_and_misscaled_profiles() {
        let w = 1e-5;
        let e = Profile::read(
            &write("np", "0,0\n2.5e-6,1e-7\n5e-6,0\n7.5e-6,-1e-7\n1e-5,5e-7\n"),
            w,
            "k",
        )
        .unwrap_err();
        assert!(e.to_string().contains("periodic"), "{e}");
        let e = Profile::read(
            &write("mm", "0,0\n2.5e-6,1e-3\n5e-6,0\n7.5e-6,-1e-3\n"),
            w,
            "k",
        )
        .unwrap_err();
        assert!(e.to_string().contains("metres"), "{e}");
        let e = Profile::read(&write("sp", "0,0\n2e-6,0\n5e-6,0\n7.5e-6,0\n"), w, "k").unwrap_err();
        assert!(e.to_string().contains("uniform spacing"), "{e}");
        let e = Profile::read(&write("wd", "0,0\n1e-6,0\n2e-6,0\n3e-6,0\n"), w, "k").unwrap_err();
        assert!(e.to_string().contains("one period"), "{e}");
    }
}
