//! `tcgen surface`: the surfaces of a case (or of one sample of a sweep) as
//! CSV, with the error of their NURBS fits at the case's discretization.
//!
//! Both bodies: `x,upper,lower,upper_fit,lower_fit` (m). One body
//! (`--body`): `x,z`, which `kind = "profile"` imports back. The header is the
//! first line; `#` lines after it give the RMS and the fit errors.

use std::fmt::Write as _;
use std::path::Path;

use crate::sample::Case;
use crate::sample::micro::sample_geometry;
use crate::sweep::path::surface_rms;
use crate::{Error, Result};

/// The sampled surfaces of a case and their fits.
#[derive(Clone, Debug)]
pub struct SurfaceExport {
    /// Abscissae `x_j = j W / n` (m).
    pub x: Vec<f64>,
    /// Heights `[upper, lower]` (m).
    pub heights: [Vec<f64>; 2],
    /// Heights of the NURBS fits `[upper, lower]` (m).
    pub fitted: [Vec<f64>; 2],
    /// RMS over one period `[upper, lower]` (m).
    pub rms: [f64; 2],
    /// Largest fit error `[upper, lower]` (m), on the fit's dense sample.
    pub fit_max_error: [f64; 2],
    /// RMS fit error `[upper, lower]` (m).
    pub fit_rms_error: [f64; 2],
    /// Description of each surface (its keys).
    pub description: [String; 2],
}

/// Builds and samples the surfaces of `case` at `points` abscissae.
pub fn export_surfaces(case: &Case, points: usize) -> Result<SurfaceExport> {
    if points < 4 {
        return Err(Error::invalid("--points", points, "at least 4"));
    }
    let w = case.sample.width;
    let (up, lo) = case.surfaces()?;
    let geo = sample_geometry(case, up.as_ref(), lo.as_ref());
    let x: Vec<f64> = (0..points).map(|j| w * j as f64 / points as f64).collect();
    let describe = |s: &crate::surface::SurfaceSpec| {
        toml::Value::try_from(s)
            .map(|v| {
                v.to_string()
                    .replace('\n', ", ")
                    .trim_end_matches([',', ' '])
                    .to_string()
            })
            .unwrap_or_default()
    };
    Ok(SurfaceExport {
        heights: [
            x.iter().map(|&x| up.height(x)).collect(),
            x.iter().map(|&x| lo.height(x)).collect(),
        ],
        fitted: [
            x.iter().map(|&x| geo.fit_upper.height_at(x, 0.0)).collect(),
            x.iter().map(|&x| geo.fit_lower.height_at(x, 0.0)).collect(),
        ],
        rms: [surface_rms(up.as_ref(), w), surface_rms(lo.as_ref(), w)],
        fit_max_error: [geo.fit_upper.max_error(), geo.fit_lower.max_error()],
        fit_rms_error: [geo.fit_upper.rms_error(), geo.fit_lower.rms_error()],
        description: [describe(&case.surface.upper), describe(&case.surface.lower)],
        x,
    })
}

/// Which surfaces to write.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bodies {
    /// Both, with the fits.
    Both,
    /// The upper body only (`x,z`).
    Upper,
    /// The lower body only (`x,z`).
    Lower,
}

/// The CSV text of an export.
pub fn surface_csv(e: &SurfaceExport, bodies: Bodies) -> String {
    let mut s = String::new();
    s.push_str(match bodies {
        Bodies::Both => "x,upper,lower,upper_fit,lower_fit\n",
        _ => "x,z\n",
    });
    for (b, name) in [(0, "upper"), (1, "lower")] {
        if (bodies == Bodies::Upper && b == 1) || (bodies == Bodies::Lower && b == 0) {
            continue;
        }
        let _ = writeln!(s, "# {name}: {}", e.description[b]);
        let _ = writeln!(
            s,
            "# {name}: rms {:e} m; NURBS fit error max {:e} m, rms {:e} m",
            e.rms[b], e.fit_max_error[b], e.fit_rms_error[b]
        );
    }
    for (j, x) in e.x.iter().enumerate() {
        let _ = match bodies {
            Bodies::Both => writeln!(
                s,
                "{x:e},{:e},{:e},{:e},{:e}",
                e.heights[0][j], e.heights[1][j], e.fitted[0][j], e.fitted[1][j]
            ),
            Bodies::Upper => writeln!(s, "{x:e},{:e}", e.heights[0][j]),
            Bodies::Lower => writeln!(s, "{x:e},{:e}", e.heights[1][j]),
        };
    }
    s
}

/// Writes the CSV of an export atomically.
pub fn write_surface_csv(e: &SurfaceExport, bodies: Bodies, path: &Path) -> Result<()> {
    crate::io::atomic::write_atomic(path, surface_csv(e, bodies).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::{Profile, Surface};

    #[test]
    fn a_random_profile_round_trips_through_profile_import() {
        let case = Case::from_toml(
            r#"
[surface.upper]
kind = "random"
rms = 5.0e-7
spectrum = "self-affine"
hurst = 0.8
cutoff_wavelength = 1.0e-6
seed = 1
[surface.lower]
kind = "flat"
"#,
            Path::new("."),
        )
        .unwrap();
        let e = export_surfaces(&case, 256).unwrap();
        assert!(e.fit_max_error[0] > 0.0 && e.fit_max_error[0] < 0.2 * e.rms[0]);
        assert_eq!(e.fit_max_error[1], 0.0);
        let p = std::env::temp_dir().join(format!("tcgen-surface-{}.csv", std::process::id()));
        write_surface_csv(&e, Bodies::Upper, &p).unwrap();
        let back = Profile::read(&p, case.sample.width, "k").unwrap();
        for (j, x) in e.x.iter().enumerate() {
            assert!((back.height(*x) - e.heights[0][j]).abs() < 1e-6 * e.rms[0]);
        }
        std::fs::remove_file(&p).unwrap();
        let both = surface_csv(&e, Bodies::Both);
        assert!(both.starts_with("x,upper,lower,upper_fit,lower_fit\n# upper: "));
        assert_eq!(both.lines().filter(|l| !l.starts_with('#')).count(), 257);
    }
}
