//! `tcgen surface`: the surfaces of a case (or of one sample of a sweep) as
//! CSV, with the error of their NURBS fits at the case's discretization.
//!
//! Both bodies: `x,upper,lower,upper_fit,lower_fit` (m). One body
//! (`--body`): `x,z`, which `kind = "profile"` imports back. The header is the
//! first line; `#` lines after it give the RMS and the fit errors.
//!
//! A 3D case writes one body's heights on the `n × n` grid `(i W/n, j W/n)`
//! in the height-map format that `kind = "heightmap"` imports back: one line
//! per y row, `n` comma-separated heights in m, no header
//! ([`export_heightmap`]).

use std::fmt::Write as _;
use std::path::Path;

use crate::geometry::fit_height_map;
use crate::sample::Case;
use crate::sample::case::{BodySurface, ElementCounts};
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

/// A surface's keys on one line.
fn describe(s: &BodySurface) -> String {
    toml::Value::try_from(s)
        .map(|v| {
            v.to_string()
                .replace('\n', ", ")
                .trim_end_matches([',', ' '])
                .to_string()
        })
        .unwrap_or_default()
}

/// One body's surface of a 3D case on the `n × n` grid, and the measures of both.
#[derive(Clone, Debug)]
pub struct ArealExport {
    /// Grid points per direction `n`.
    pub points: usize,
    /// The body written: 0 upper, 1 lower.
    pub body: usize,
    /// Whether `heights` are the NURBS fit's (else the surface's own).
    pub fitted: bool,
    /// Heights at `(i W/n, j W/n)` (m), row `j` after row, `i` fastest.
    pub heights: Vec<f64>,
    /// RMS of the surfaces on the grid `[upper, lower]` (m).
    pub rms: [f64; 2],
    /// Largest fit error `[upper, lower]` (m), on the fit's dense sample.
    pub fit_max_error: [f64; 2],
    /// RMS fit error `[upper, lower]` (m).
    pub fit_rms_error: [f64; 2],
    /// Description of each surface (its keys).
    pub description: [String; 2],
}

/// Samples the areal surface of `body` (0 upper, 1 lower) of a 3D case on
/// the `points × points` grid: its bivariate B-spline fit at the case's
/// discretization (degree, lateral element counts) if `fitted`, else the
/// surface itself; both bodies' RMS and fit errors are measured.
pub fn export_heightmap(
    case: &Case,
    points: usize,
    body: usize,
    fitted: bool,
) -> Result<ArealExport> {
    if points < 4 {
        return Err(Error::invalid("--points", points, "at least 4"));
    }
    let w = case.sample.width;
    let d = &case.discretization;
    let (up, lo) = case.areal_surfaces()?;
    let surfaces = [up, lo];
    let mut fits = Vec::new();
    for (s, e) in surfaces.iter().zip([&d.elements_upper, &d.elements_lower]) {
        let f = |x: f64, y: f64| s.height(x, y);
        fits.push(fit_height_map(&f, w, d.degree, [e.along(0), e.along(1)])?);
    }
    let grid = |z: &dyn Fn(f64, f64) -> f64| -> Vec<f64> {
        (0..points * points)
            .map(|k| {
                let (i, j) = (k % points, k / points);
                z(w * i as f64 / points as f64, w * j as f64 / points as f64)
            })
            .collect()
    };
    let rms = |h: &[f64]| {
        let n = h.len() as f64;
        let mean = h.iter().sum::<f64>() / n;
        (h.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt()
    };
    let exact = [
        grid(&|x, y| surfaces[0].height(x, y)),
        grid(&|x, y| surfaces[1].height(x, y)),
    ];
    let heights = if fitted {
        grid(&|x, y| fits[body].height_at(x, y))
    } else {
        exact[body].clone()
    };
    Ok(ArealExport {
        points,
        body,
        fitted,
        heights,
        rms: [rms(&exact[0]), rms(&exact[1])],
        fit_max_error: [fits[0].max_error, fits[1].max_error],
        fit_rms_error: [fits[0].rms_error, fits[1].rms_error],
        description: [describe(&case.surface.upper), describe(&case.surface.lower)],
    })
}

/// Share of its RMS by which a rough surface's fit on a fixed case mesh may
/// miss it before `tcgen check`, `solve` and `sweep` caution: the egg box's
/// 6 × 6 fit, off by 4.1 % of its RMS (its curvature at the crest 10.7 %
/// low), moved the jump at 100 kPa by −1.1 % against the exact surface on
/// the same mesh, the size of a 1 % target (docs/adaptivity.md, "The
/// surface under refinement"). Fixed meshes solve the fitted surface (`interface_levels`
/// keep the fit); adaptive levels fit the surface itself where they refine.
pub const FIT_CAUTION_SHARE: f64 = 0.04;

/// How the case mesh's NURBS fits represent the two surfaces (upper,
/// lower): sampled as `tcgen surface` samples them (2D: 1024 abscissae; 3D:
/// the 256 × 256 grid), the surfaces of sample 0 of a random ensemble.
#[derive(Clone, Copy, Debug)]
pub struct CaseFits {
    /// RMS of the surfaces `[upper, lower]` (m).
    pub rms: [f64; 2],
    /// Largest fit error `[upper, lower]` (m).
    pub max_error: [f64; 2],
    /// RMS fit error `[upper, lower]` (m).
    pub rms_error: [f64; 2],
}

impl CaseFits {
    /// The fits of `case`'s surfaces on its case mesh.
    pub fn of(case: &Case) -> Result<Self> {
        if case.dimension() == 3 {
            // The surface's own heights (a copy of the grid the measures
            // sample), not a third grid of the fit's.
            let e = export_heightmap(case, 256, 0, false)?;
            Ok(CaseFits {
                rms: e.rms,
                max_error: e.fit_max_error,
                rms_error: e.fit_rms_error,
            })
        } else {
            let e = export_surfaces(case, 1024)?;
            Ok(CaseFits {
                rms: e.rms,
                max_error: e.fit_max_error,
                rms_error: e.fit_rms_error,
            })
        }
    }

    /// Whether body `b`'s fit misses its surface by more than
    /// [`FIT_CAUTION_SHARE`] of its RMS.
    fn misses(&self, b: usize) -> bool {
        self.max_error[b] > FIT_CAUTION_SHARE * self.rms[b]
    }

    /// One line per rough body of `case` (whose fits these are): its RMS
    /// and its fit's errors, also as shares of the RMS, and where the fit
    /// misses it by more than [`FIT_CAUTION_SHARE`], on a fixed mesh the
    /// lateral element counts that fit it within that share
    /// ([`resolving_counts`]); an adaptive case's levels fit the surface
    /// where they refine, and a finer case mesh bought nothing there (a
    /// 512 × 512 height map at 10 kPa: from `[16, 16, 4]` 168 s to level 3
    /// with 115 584 unknowns and an estimate of 2.41 %, from `[8, 8, 4]`
    /// 131 s to level 4 with 113 896 and 2.04 %; docs/3d.md, "Stop 93").
    pub fn describe(&self, case: &Case) -> Result<Vec<String>> {
        let mut out = Vec::new();
        for (b, name) in ["upper", "lower"]
            .into_iter()
            .enumerate()
            .filter(|&(b, _)| self.rms[b] > 0.0)
        {
            let mut line = format!(
                "{name} surface: RMS {:.4e} m; its fit on the case mesh misses it by at most {:.3e} m ({:.1} % of the RMS), {:.3e} m RMS ({:.1} %)",
                self.rms[b],
                self.max_error[b],
                100.0 * self.max_error[b] / self.rms[b],
                self.rms_error[b],
                100.0 * self.rms_error[b] / self.rms[b],
            );
            if self.misses(b) && case.discretization.target_error.is_some() {
                line.push_str("; the adaptive levels fit the surface itself where they refine");
            } else if self.misses(b) {
                let share = 100.0 * FIT_CAUTION_SHARE;
                match resolving_counts(case, b)? {
                    Some((n, max)) => write!(
                        line,
                        "; within {share:.0} % from elements_{name} = {n} ({:.1} %)",
                        100.0 * max / self.rms[b]
                    ),
                    None => write!(
                        line,
                        "; not within {share:.0} % up to {} times the lateral elements",
                        1 << RESOLVING_DOUBLINGS
                    ),
                }
                .expect("a String takes writes");
            }
            out.push(line);
        }
        Ok(out)
    }

    /// A caution for each rough body of a fixed mesh (`target_error`
    /// absent) whose fit misses it by more than [`FIT_CAUTION_SHARE`] of
    /// its RMS.
    pub fn cautions(&self, case: &Case) -> Vec<String> {
        if case.discretization.target_error.is_some() {
            return Vec::new();
        }
        ["upper", "lower"]
            .into_iter()
            .enumerate()
            .filter(|&(b, _)| self.misses(b))
            .map(|(b, name)| {
                format!(
                    "the {name} surface's fit on the case mesh misses it by up to {:.1} % of its RMS ({:.3e} m): a fixed mesh solves the fitted surface (interface_levels keep the fit), and a fit {share:.0} % off moved the egg box's jump by 1.1 % (docs/adaptivity.md, \"The surface under refinement\"); refine elements_{name} laterally (tcgen check names the counts that fit it within {share:.0} %), or set target_error: the adaptive levels fit the surface itself where they refine",
                    100.0 * self.max_error[b] / self.rms[b],
                    self.max_error[b],
                    share = 100.0 * FIT_CAUTION_SHARE,
                )
            })
            .collect()
    }
}

/// What a run of `case` is cautioned with before it starts (`tcgen solve`,
/// `sweep`, and a table's `cautions` attribute): the case's known limits
/// ([`Case::cautions`]) and, for a fixed mesh, the surfaces that its fit
/// misses ([`CaseFits::cautions`]; of a sweep, pass its sample 0). Surfaces
/// that cannot be built give no fit caution: the run itself says why.
pub fn run_cautions(case: &Case) -> Vec<String> {
    let fits = case
        .discretization
        .target_error
        .is_none()
        .then(|| CaseFits::of(case).ok())
        .flatten();
    run_cautions_with(case, fits.as_ref())
}

/// [`run_cautions`] with the fits already measured (`tcgen check`, which
/// prints them too), or none.
pub fn run_cautions_with(case: &Case, fits: Option<&CaseFits>) -> Vec<String> {
    let mut out = case.cautions();
    out.extend(fits.map(|f| f.cautions(case)).unwrap_or_default());
    out
}

/// How many times [`resolving_counts`] doubles the lateral element counts.
pub const RESOLVING_DOUBLINGS: u32 = 4;

/// The case mesh's counts for body `b` with the lateral ones doubled until
/// its fit misses the surface by at most [`FIT_CAUTION_SHARE`] of its RMS
/// (at most [`RESOLVING_DOUBLINGS`] times), and that fit's largest error;
/// `None` where none of them does.
pub fn resolving_counts(case: &Case, b: usize) -> Result<Option<(ElementCounts, f64)>> {
    for k in 1..=RESOLVING_DOUBLINGS {
        let mut finer = case.clone();
        let d = &mut finer.discretization;
        let counts = match b {
            0 => &mut d.elements_upper,
            _ => &mut d.elements_lower,
        };
        *counts = counts.laterally_scaled(1 << k);
        let n = counts.clone();
        let fits = CaseFits::of(&finer)?;
        if !fits.misses(b) {
            return Ok(Some((n, fits.max_error[b])));
        }
    }
    Ok(None)
}

/// The height-map CSV of an areal export: one line per y row.
pub fn heightmap_csv(e: &ArealExport) -> String {
    let mut s = String::new();
    for row in e.heights.chunks(e.points) {
        let line: Vec<String> = row.iter().map(|z| format!("{z:e}")).collect();
        s.push_str(&line.join(","));
        s.push('\n');
    }
    s
}

/// Writes the height-map CSV of an areal export atomically.
pub fn write_heightmap_csv(e: &ArealExport, path: &Path) -> Result<()> {
    crate::io::atomic::write_atomic(path, heightmap_csv(e).as_bytes())
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

    /// `tcgen check` reports the case mesh's fit of each rough surface, and
    /// cautions where a fixed mesh's fit misses its surface by more than
    /// [`FIT_CAUTION_SHARE`] of the RMS: a 3D egg box on 2 × 2 elements (a
    /// fit far off) and on 8 × 8 (1.3 %, below); never for an adaptive case
    /// or a flat body.
    #[test]
    fn a_fixed_mesh_whose_fit_misses_its_surface_is_cautioned() {
        let case = |n: usize, adaptive: bool| {
            Case::from_toml(
                &format!(
                    r#"
[sample]
dimension = 3
width = 1.0e-5
height = 7.0e-6
[surface.upper]
kind = "sinusoid"
pattern = "egg-box"
rms = 1.0e-6
wavelength = 1.0e-5
[surface.lower]
kind = "flat"
[discretization]
elements_upper = [{n}, {n}, 2]
elements_lower = [{n}, {n}, 2]
{}
"#,
                    if adaptive { "target_error = 0.01" } else { "" }
                ),
                Path::new("."),
            )
            .unwrap()
        };
        let coarse = CaseFits::of(&case(2, false)).unwrap();
        let fine = CaseFits::of(&case(8, false)).unwrap();
        // The egg box's RMS on the grid, the flat's none.
        assert!((coarse.rms[0] - 1.0e-6).abs() < 1e-9 && coarse.rms[1] == 0.0);
        assert!(coarse.max_error[0] > FIT_CAUTION_SHARE * coarse.rms[0]);
        assert!(fine.max_error[0] < FIT_CAUTION_SHARE * fine.rms[0]);
        assert!(fine.max_error[0] > fine.rms_error[0] && fine.rms_error[0] > 0.0);
        let cautions = coarse.cautions(&case(2, false));
        assert_eq!(cautions.len(), 1, "{cautions:?}");
        assert!(
            cautions[0].starts_with("the upper surface's fit"),
            "{cautions:?}"
        );
        assert!(coarse.cautions(&case(2, true)).is_empty());
        assert!(fine.cautions(&case(8, false)).is_empty());
        // One line for the rough body, with its share of the RMS.
        let lines = fine.describe(&case(8, false)).unwrap();
        assert_eq!(lines.len(), 1, "{lines:?}");
        let share = format!(
            "({:.1} % of the RMS)",
            100.0 * fine.max_error[0] / fine.rms[0]
        );
        assert!(lines[0].contains(&share), "{lines:?}");
        assert!(!lines[0].contains("within"), "{lines:?}");
        // The coarse fit names the lateral counts that fit within the
        // share: the 8 × 8 mesh's, two doublings away (4 × 4 does not).
        let lines = coarse.describe(&case(2, false)).unwrap();
        let eight = format!(
            "; within 4 % from elements_upper = [8, 8, 2] ({:.1} %)",
            100.0 * fine.max_error[0] / fine.rms[0]
        );
        assert!(lines[0].ends_with(&eight), "{lines:?}");
        let adaptive = coarse.describe(&case(2, true)).unwrap();
        assert!(
            adaptive[0].ends_with("; the adaptive levels fit the surface itself where they refine"),
            "{adaptive:?}"
        );
        let four = CaseFits::of(&case(4, false)).unwrap();
        assert!(four.misses(0), "{four:?}");
    }

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

    /// A 3D case: one body's fitted or exact heights on the grid, in the
    /// height-map format that `kind = "heightmap"` reads back.
    #[test]
    fn an_areal_surface_round_trips_through_heightmap_import() {
        use crate::surface::{ArealSurface, HeightMap};
        let case = Case::from_toml(
            "[sample]\ndimension = 3\n[surface.upper]\nkind = \"sinusoid\"\nrms = 1.0e-6\n\
             wavelength = 5.0e-6\n[surface.lower]\nkind = \"flat\"\n\
             [discretization]\nelements_upper = [8, 6, 2]\nelements_lower = [4, 4, 2]\n",
            Path::new("."),
        )
        .unwrap();
        let w = case.sample.width;
        let (exact, _) = case.areal_surfaces().unwrap();
        let n = 24;
        let fit = export_heightmap(&case, n, 0, true).unwrap();
        let own = export_heightmap(&case, n, 0, false).unwrap();
        assert!((fit.rms[0] / 1e-6 - 1.0).abs() < 1e-9 && fit.rms[1] == 0.0);
        assert!(
            fit.fit_max_error[0] > 0.0 && fit.fit_max_error[0] < 0.5e-6,
            "{}",
            fit.fit_max_error[0]
        );
        assert_eq!(fit.fit_max_error[1], 0.0);
        let csv = heightmap_csv(&fit);
        assert_eq!(csv.lines().count(), n);
        assert!(csv.lines().all(|l| l.split(',').count() == n));
        let p = std::env::temp_dir().join(format!("tcgen-heightmap-{}.csv", std::process::id()));
        for e in [&fit, &own] {
            write_heightmap_csv(e, &p).unwrap();
            let back = HeightMap::read(&p, w, "k").unwrap();
            for k in [0, 5, 77, n * n - 1] {
                let (x, y) = ((k % n) as f64 * w / n as f64, (k / n) as f64 * w / n as f64);
                let z = e.heights[k];
                assert!(
                    (back.height(x, y) + back.removed_mean - z).abs() < 1e-15,
                    "{k}"
                );
                if !e.fitted {
                    assert!((exact.height(x, y) - z).abs() < 1e-18);
                } else {
                    assert!((exact.height(x, y) - z).abs() <= fit.fit_max_error[0]);
                }
            }
        }
        std::fs::remove_file(&p).unwrap();
        let two = Case::from_toml(
            "[surface.upper]\nkind = \"flat\"\n[surface.lower]\nkind = \"flat\"\n",
            Path::new("."),
        )
        .unwrap();
        let e = export_heightmap(&two, 16, 0, true).unwrap_err().to_string();
        assert!(e.contains("sample.dimension"), "{e}");
    }
}
