//! Rough surfaces of 3D micro-samples (spec §3 in 3D, issue 12): height
//! functions `f(x, y)` about the mean plane, periodic over the square cell
//! `[0, W]²`, in one global frame for both bodies.
//!
//! - `sinusoid`, `pattern = "egg-box"`: `f = 2·rms·cos(2πx/λ + φx)·cos(2πy/λ + φy)`;
//!   `pattern = "ridges"`: `f = √2·rms·cos(2πx/λ + φx)`, uniform in y. The
//!   phases `φx = phase`, `φy = phase_y` (rad, default 0; `phase_y` egg-box
//!   only) shift the pattern by `−φλ/2π` along each axis: mismatched cells
//!   (paper Sect. 5.3, Figs. 10/11), as the 2D sinusoid's `phase`.
//! - `random`: the keys of the 2D [`RandomSpec`], meaning the **isotropic
//!   areal** spectrum (below).
//! - `heightmap`: a CSV of heights in m, one line per y row (`y_j = j·W/n_y`),
//!   `n_x` comma-separated values per line (`x_i = i·W/n_x`), periodic (the
//!   point at W not repeated), the mean removed; interpolated by the periodic
//!   bicubic B-spline through the data (C², exact at the nodes).
//!
//! # Random areal surfaces
//!
//! `f(x, y) = Σ_m c_m cos(q_m·r) + d_m sin(q_m·r)`, `q_m = 2π(k, l)/W` over
//! the wave vectors of the half plane (`k > 0`, or `k = 0` and `l > 0`) with
//! `0 < k² + l² ≤ K²`, `K` the 2D spec's [`RandomSpec::mode_count`] (the
//! shortest wavelength is the same as in 2D). `c_m = σ_s √w_m a_m`,
//! `d_m = σ_s √w_m b_m` with the isotropic areal spectrum
//! `w_m = exp(−|q_m|² ℓ²/4)` (Gaussian autocorrelation
//! `R(r) = rms² exp(−r²/ℓ²)`) or `w_m = min(1, (|q_m|/q_r)^−2(1+H))`
//! (self-affine: areal spectrum `∝ q^−2(1+H)` beyond the roll-off),
//! `σ_s = rms/√(Σ w_m)` so that the expected mean square is `rms²`
//! (`exact_rms` rescales each sample instead). The modes are ordered by
//! `(k² + l², k, l)` and draw `(a_m, b_m)` in that order from the same
//! portable ChaCha20 stream as the 2D profiles ([`crate::surface::random::StreamRng`], key
//! `(seed, sample, stream)`): a finer cut-off appends modes and leaves the
//! draws of the coarser ones unchanged.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::surface::random::{RandomSpec, SpectrumKind};
use crate::{Error, Result};

/// Largest `K` (mode index) of a random areal surface: about `π K²/2` modes.
pub const MAX_AREAL_MODE_INDEX: usize = 256;

/// A surface height function over `[0, W]²`, zero mean, periodic in x and y.
pub trait ArealSurface: Send + Sync {
    /// Height `f(x, y)` (m) about the mean plane.
    fn height(&self, x: f64, y: f64) -> f64;
}

/// The pattern of a 3D sinusoid.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SinusoidPattern {
    /// `f = 2·rms·cos(2πx/λ + φx)·cos(2πy/λ + φy)`.
    #[default]
    EggBox,
    /// `f = √2·rms·cos(2πx/λ + φx)`, uniform in y.
    Ridges,
}

/// A 3D surface as a case file gives it (`[surface.upper]`, `[surface.lower]`
/// with `[sample] dimension = 3`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ArealSpec {
    /// `f = 0`.
    Flat,
    /// Egg-box or ridges.
    Sinusoid {
        /// RMS roughness (m).
        rms: f64,
        /// Wavelength λ (m); must divide the cell width.
        wavelength: f64,
        /// `egg-box` (default) or `ridges`.
        #[serde(default)]
        pattern: SinusoidPattern,
        /// Phase `φx` along x (rad), for mismatched cells (Sect. 5.3).
        #[serde(default, skip_serializing_if = "is_zero")]
        phase: f64,
        /// Phase `φy` along y (rad; egg-box only).
        #[serde(default, skip_serializing_if = "is_zero")]
        phase_y: f64,
    },
    /// Gaussian random heights with an isotropic areal spectrum (module doc).
    Random(RandomSpec),
    /// A measured height map (module doc).
    Heightmap {
        /// CSV file, relative to the case file.
        file: PathBuf,
        /// SHA-256 of the file's content ([`crate::surface::read_data_file`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        file_sha256: Option<String>,
    },
}

/// A zero phase is not written (case files and hashes without phases keep
/// their serialized form).
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// `f = 0`.
#[derive(Clone, Copy, Debug)]
pub struct ArealFlat;

impl ArealSurface for ArealFlat {
    fn height(&self, _x: f64, _y: f64) -> f64 {
        0.0
    }
}

/// Egg-box or ridges (see [`SinusoidPattern`]).
#[derive(Clone, Copy, Debug)]
pub struct ArealSinusoid {
    /// RMS roughness (m).
    pub rms: f64,
    /// Wavelength (m).
    pub wavelength: f64,
    /// Pattern.
    pub pattern: SinusoidPattern,
    /// Phases `[φx, φy]` (rad; `φy` unused by ridges).
    pub phase: [f64; 2],
}

impl ArealSurface for ArealSinusoid {
    fn height(&self, x: f64, y: f64) -> f64 {
        let q = std::f64::consts::TAU / self.wavelength;
        let [px, py] = self.phase;
        match self.pattern {
            SinusoidPattern::EggBox => 2.0 * self.rms * (q * x + px).cos() * (q * y + py).cos(),
            SinusoidPattern::Ridges => std::f64::consts::SQRT_2 * self.rms * (q * x + px).cos(),
        }
    }
}

impl ArealSpec {
    /// Checks the parameters against the cell width; `key` names the table.
    pub fn validate(&self, key: &str, width: f64) -> Result<()> {
        match self {
            ArealSpec::Flat => Ok(()),
            ArealSpec::Heightmap { file_sha256, .. } => {
                crate::surface::check_sha256_key(key, file_sha256.as_deref())
            }
            ArealSpec::Sinusoid {
                rms,
                wavelength,
                pattern,
                phase,
                phase_y,
            } => {
                // The same rules as the 2D sinusoid (`phase` included).
                crate::surface::SurfaceSpec::Sinusoid {
                    rms: *rms,
                    wavelength: *wavelength,
                    phase: *phase,
                }
                .validate(key, width)?;
                if !phase_y.is_finite() {
                    return Err(Error::invalid(
                        format!("{key}.phase_y"),
                        phase_y,
                        "a finite angle (rad)",
                    ));
                }
                if *pattern == SinusoidPattern::Ridges && *phase_y != 0.0 {
                    return Err(Error::invalid(
                        format!("{key}.phase_y"),
                        phase_y,
                        "absent with pattern = \"ridges\" (uniform in y; its phase along x is phase)",
                    ));
                }
                Ok(())
            }
            ArealSpec::Random(r) => {
                r.validate(key, width)?;
                let k = r.mode_count(width);
                if k > MAX_AREAL_MODE_INDEX {
                    let field = match (r.spectrum, r.cutoff_wavelength) {
                        (SpectrumKind::Gaussian, None) => "correlation_length",
                        _ => "cutoff_wavelength",
                    };
                    return Err(Error::invalid(
                        format!("{key}.{field}"),
                        format!("{k} wavelengths per cell"),
                        format!(
                            "at most {MAX_AREAL_MODE_INDEX} wavelengths per cell in 3D (a shortest wavelength ≥ {:e} m)",
                            width / MAX_AREAL_MODE_INDEX as f64
                        ),
                    ));
                }
                Ok(())
            }
        }
    }

    /// The height function; `base` is the directory of the case file.
    pub fn build(&self, key: &str, width: f64, base: &Path) -> Result<Box<dyn ArealSurface>> {
        self.validate(key, width)?;
        Ok(match self {
            ArealSpec::Flat => Box::new(ArealFlat),
            ArealSpec::Sinusoid {
                rms,
                wavelength,
                pattern,
                phase,
                phase_y,
            } => Box::new(ArealSinusoid {
                rms: *rms,
                wavelength: *wavelength,
                pattern: *pattern,
                phase: [*phase, *phase_y],
            }),
            ArealSpec::Random(r) => Box::new(RandomArealSurface::generate(r, key, width)),
            ArealSpec::Heightmap { file, file_sha256 } => {
                let (path, text) =
                    crate::surface::read_data_file(key, file, file_sha256.as_deref(), base)?;
                Box::new(HeightMap::parse(
                    &text,
                    &path,
                    width,
                    &format!("{key}.file"),
                )?)
            }
        })
    }
}

/// One drawn random areal surface (module documentation).
#[derive(Clone, Debug)]
pub struct RandomArealSurface {
    width: f64,
    /// Wave numbers `(k, l)` of the modes, in draw order.
    waves: Vec<(i64, i64)>,
    cos: Vec<f64>,
    sin: Vec<f64>,
}

impl RandomArealSurface {
    /// The wave numbers `(k, l)` of the half plane with `0 < k² + l² ≤ K²`,
    /// ordered by `(k² + l², k, l)`.
    pub fn wave_numbers(k_max: usize) -> Vec<(i64, i64)> {
        let k = k_max as i64;
        let mut waves: Vec<(i64, i64)> = (0..=k)
            .flat_map(|a| (-k..=k).map(move |b| (a, b)))
            .filter(|&(a, b)| (a > 0 || b > 0) && a * a + b * b <= k * k)
            .collect();
        waves.sort_by_key(|&(a, b)| (a * a + b * b, a, b));
        waves
    }

    /// The isotropic areal spectrum weight of wave number `(k, l)`.
    fn weight(spec: &RandomSpec, width: f64, k: i64, l: i64) -> f64 {
        let q = std::f64::consts::TAU * ((k * k + l * l) as f64).sqrt() / width;
        spec.spectrum_weight(width, q, true)
    }

    /// Draws the surface of `spec` for the body `key` names (the spec must be valid).
    pub fn generate(spec: &RandomSpec, key: &str, width: f64) -> Self {
        let waves = Self::wave_numbers(spec.mode_count(width));
        let weights: Vec<f64> = waves
            .iter()
            .map(|&(k, l)| Self::weight(spec, width, k, l))
            .collect();
        let (cos, sin) = spec.draw_coefficients(spec.stream_for(key), &weights);
        RandomArealSurface {
            width,
            waves,
            cos,
            sin,
        }
    }

    /// Number of modes.
    pub fn modes(&self) -> usize {
        self.waves.len()
    }

    /// RMS over the cell (Parseval), `√(Σ (c² + d²)/2)`.
    pub fn rms(&self) -> f64 {
        crate::surface::random::parseval_rms(&self.cos, &self.sin)
    }

    /// The Fourier coefficients in draw order with their wave numbers.
    pub fn coefficients(&self) -> (&[(i64, i64)], &[f64], &[f64]) {
        (&self.waves, &self.cos, &self.sin)
    }
}

impl ArealSurface for RandomArealSurface {
    fn height(&self, x: f64, y: f64) -> f64 {
        let (u, v) = (x / self.width, y / self.width);
        let mut z = 0.0;
        for (m, &(k, l)) in self.waves.iter().enumerate() {
            // Reduce to one period before scaling by 2π: exact periodicity.
            let t = k as f64 * u + l as f64 * v;
            let (s, c) = libm::sincos(std::f64::consts::TAU * (t - libm::floor(t)));
            z += self.cos[m] * c + self.sin[m] * s;
        }
        z
    }
}

/// A measured height map on the cell, interpolated by the periodic bicubic
/// B-spline through its nodes (module documentation).
#[derive(Clone, Debug)]
pub struct HeightMap {
    width: f64,
    nx: usize,
    ny: usize,
    /// Periodic cubic B-spline coefficients, x fastest.
    coef: Vec<f64>,
    /// The mean height removed from the data (m).
    pub removed_mean: f64,
    /// The largest `|height|` of the data, mean removed (m).
    largest: f64,
    /// The steps across the seams at `x = W` and `y = W` and inside.
    seams: [crate::surface::SeamSteps; 2],
}

/// Solves the circulant system `(c_{i−1} + 4 c_i + c_{i+1})/6 = f_i` (periodic
/// cubic B-spline interpolation at the nodes) in place, by the cyclic Thomas
/// algorithm (Sherman–Morrison); diagonally dominant, so stable.
fn periodic_cubic_coefficients(f: &mut [f64]) {
    let n = f.len();
    let (a, b) = (1.0 / 6.0, 4.0 / 6.0);
    // A = T + u vᵀ with T tridiagonal (b − γ at 0, b − a²/γ at n−1), u = (γ,0,…,a), v = (1,0,…,a/γ).
    let gamma = -b;
    let solve_tri = |rhs: &mut [f64]| {
        let mut c = vec![0.0; n];
        let mut diag = b - gamma;
        c[0] = a / diag;
        rhs[0] /= diag;
        for i in 1..n {
            let d = if i == n - 1 { b - a * a / gamma } else { b };
            diag = d - a * c[i - 1];
            c[i] = a / diag;
            rhs[i] = (rhs[i] - a * rhs[i - 1]) / diag;
        }
        for i in (0..n - 1).rev() {
            rhs[i] -= c[i] * rhs[i + 1];
        }
    };
    let mut u = vec![0.0; n];
    u[0] = gamma;
    u[n - 1] = a;
    solve_tri(f);
    solve_tri(&mut u);
    let vy = f[0] + a / gamma * f[n - 1];
    let vz = u[0] + a / gamma * u[n - 1];
    let factor = vy / (1.0 + vz);
    for (fi, ui) in f.iter_mut().zip(&u) {
        *fi -= factor * ui;
    }
}

/// Uniform cubic B-spline weights of the four coefficients around `t ∈ [0, 1)`.
fn cubic_weights(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        s * s * s / 6.0,
        (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0,
        (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
        t * t * t / 6.0,
    ]
}

impl HeightMap {
    /// Builds from heights `z[j][i]` at `(i W/n_x, j W/n_y)`; `key` names the input.
    pub fn from_grid(rows: Vec<Vec<f64>>, width: f64, key: &str) -> Result<Self> {
        let ny = rows.len();
        let nx = rows.first().map_or(0, Vec::len);
        // Ragged first: a short map's size is only meaningful when its lines agree.
        if let Some(j) = rows.iter().position(|r| r.len() != nx) {
            return Err(Error::invalid(
                key,
                format!("line {} has {} values", j + 1, rows[j].len()),
                format!("{nx} values per line, as on line 1 (a ragged map)"),
            ));
        }
        if nx < 4 || ny < 4 {
            return Err(Error::invalid(
                key,
                format!("{nx} x {ny} points"),
                "at least 4 x 4 heights (one line per y row, the same count per line)",
            ));
        }
        let mut z: Vec<f64> = rows.into_iter().flatten().collect();
        if let Some(k) = z.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                key,
                format!("{} at line {}, value {}", z[k], k / nx + 1, k % nx + 1),
                "finite heights in m",
            ));
        }
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        z.iter_mut().for_each(|v| *v -= mean);
        let (lo, hi) = z
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        if hi - lo >= width {
            return Err(Error::invalid(
                key,
                format!("peak-to-valley {:e} m", hi - lo),
                format!("heights smaller than the cell width {width:e} m (are the units metres?)"),
            ));
        }
        let seams = [
            crate::surface::SeamSteps::of(ny, nx, |j, i| z[j * nx + i]),
            crate::surface::SeamSteps::of(nx, ny, |i, j| z[j * nx + i]),
        ];
        // Tensor-product interpolation: along x per row, then along y per column.
        for row in z.chunks_mut(nx) {
            periodic_cubic_coefficients(row);
        }
        let mut column = vec![0.0; ny];
        for i in 0..nx {
            for j in 0..ny {
                column[j] = z[j * nx + i];
            }
            periodic_cubic_coefficients(&mut column);
            for j in 0..ny {
                z[j * nx + i] = column[j];
            }
        }
        Ok(HeightMap {
            width,
            nx,
            ny,
            coef: z,
            removed_mean: mean,
            largest: hi.max(-lo),
            seams,
        })
    }

    /// Reads the CSV height map (module documentation); `key` names it in errors.
    pub fn read(path: &Path, width: f64, key: &str) -> Result<Self> {
        Self::parse(&crate::error::read_text(path)?, path, width, key)
    }

    /// Parses the text of [`HeightMap::read`]'s CSV, read from `path`.
    pub fn parse(text: &str, path: &Path, width: f64, key: &str) -> Result<Self> {
        let mut rows = Vec::new();
        for (ln, line) in text.lines().enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            let row: std::result::Result<Vec<f64>, _> =
                line.split(',').map(|v| v.trim().parse::<f64>()).collect();
            match row {
                Ok(r) => rows.push(r),
                Err(_) => {
                    return Err(Error::invalid(
                        key,
                        format!("{}: line {}: {line:?}", path.display(), ln + 1),
                        "comma-separated numbers (heights in m), one line per y row",
                    ));
                }
            }
        }
        HeightMap::from_grid(rows, width, &format!("{key} ({})", path.display()))
    }

    /// The steps across the seams at `x = W` (the rows) and `y = W` (the
    /// columns), each against the steps inside along the same direction.
    pub fn seam_steps(&self) -> [crate::surface::SeamSteps; 2] {
        self.seams
    }

    /// Grid size `(n_x, n_y)`.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The largest `|height|` at the nodes, mean removed (m).
    pub fn largest_height(&self) -> f64 {
        self.largest
    }
}

impl ArealSurface for HeightMap {
    fn height(&self, x: f64, y: f64) -> f64 {
        let locate = |c: f64, n: usize| {
            let s = c / self.width * n as f64;
            let s = s - (s / n as f64).floor() * n as f64;
            let i = (s.floor() as usize).min(n - 1);
            (i, cubic_weights(s - i as f64))
        };
        let (i, wx) = locate(x, self.nx);
        let (j, wy) = locate(y, self.ny);
        let mut z = 0.0;
        for (b, wyb) in wy.iter().enumerate() {
            let jj = (j + self.ny + b - 1) % self.ny;
            let row = &self.coef[jj * self.nx..(jj + 1) * self.nx];
            let mut r = 0.0;
            for (a, wxa) in wx.iter().enumerate() {
                r += wxa * row[(i + self.nx + a - 1) % self.nx];
            }
            z += wyb * r;
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: f64 = 1.0e-5;

    fn mean_square(s: &dyn ArealSurface, n: usize) -> (f64, f64) {
        let (mut m, mut q) = (0.0, 0.0);
        for j in 0..n {
            for i in 0..n {
                let h = s.height(W * i as f64 / n as f64, W * j as f64 / n as f64);
                m += h;
                q += h * h;
            }
        }
        let k = (n * n) as f64;
        (m / k, q / k)
    }

    #[test]
    fn sinusoid_patterns_have_the_stated_rms() {
        for pattern in [SinusoidPattern::EggBox, SinusoidPattern::Ridges] {
            let s = ArealSpec::Sinusoid {
                rms: 1e-6,
                wavelength: W / 2.0,
                pattern,
                phase: 0.0,
                phase_y: 0.0,
            }
            .build("surface.upper", W, Path::new("."))
            .unwrap();
            let (m, q) = mean_square(s.as_ref(), 64);
            assert!(
                m.abs() < 1e-20 && (q.sqrt() / 1e-6 - 1.0).abs() < 1e-12,
                "{pattern:?}"
            );
        }
        let ridges = ArealSinusoid {
            rms: 1e-6,
            wavelength: W,
            pattern: SinusoidPattern::Ridges,
            phase: [0.0, 0.0],
        };
        assert_eq!(ridges.height(1e-6, 0.0), ridges.height(1e-6, 7e-6));
    }

    /// `phase`, `phase_y` shift the pattern by `−φλ/2π` along x and y (the
    /// 2D sinusoid's convention); the RMS is kept; `phase_y` is refused for
    /// ridges and both must be finite, errors naming the key.
    #[test]
    fn sinusoid_phases_shift_the_pattern() {
        let lambda = W / 2.0;
        let spec = |pattern, phase, phase_y| ArealSpec::Sinusoid {
            rms: 1e-6,
            wavelength: lambda,
            pattern,
            phase,
            phase_y,
        };
        let (px, py) = (0.7, -1.9);
        for (pattern, phase_y) in [
            (SinusoidPattern::EggBox, py),
            (SinusoidPattern::Ridges, 0.0),
        ] {
            let base = spec(pattern, 0.0, 0.0)
                .build("surface.upper", W, Path::new("."))
                .unwrap();
            let shifted = spec(pattern, px, phase_y)
                .build("surface.upper", W, Path::new("."))
                .unwrap();
            let (dx, dy) = (
                -px * lambda / std::f64::consts::TAU,
                -phase_y * lambda / std::f64::consts::TAU,
            );
            for (x, y) in [(0.0, 0.0), (1.3e-6, 2.9e-6), (7.7e-6, 4.1e-6)] {
                let (a, b) = (shifted.height(x, y), base.height(x - dx, y - dy));
                assert!(
                    (a - b).abs() < 1e-12 * 1e-6,
                    "{pattern:?} at ({x}, {y}): {a} vs {b}"
                );
            }
            let (m, q) = mean_square(shifted.as_ref(), 64);
            assert!(m.abs() < 1e-20 && (q.sqrt() / 1e-6 - 1.0).abs() < 1e-12);
        }
        // The egg box with φy differs from the one without (φy is used).
        let a = spec(SinusoidPattern::EggBox, px, 0.0)
            .build("surface.upper", W, Path::new("."))
            .unwrap();
        let b = spec(SinusoidPattern::EggBox, px, py)
            .build("surface.upper", W, Path::new("."))
            .unwrap();
        assert!((a.height(1e-6, 1e-6) - b.height(1e-6, 1e-6)).abs() > 1e-8);
        for (s, key) in [
            (
                spec(SinusoidPattern::Ridges, 0.0, 0.5),
                "surface.upper.phase_y",
            ),
            (
                spec(SinusoidPattern::EggBox, f64::NAN, 0.0),
                "surface.upper.phase",
            ),
            (
                spec(SinusoidPattern::EggBox, 0.0, f64::INFINITY),
                "surface.upper.phase_y",
            ),
        ] {
            let e = s.validate("surface.upper", W).unwrap_err().to_string();
            assert!(e.contains(key), "{e}");
        }
    }

    /// The areal random surface: Parseval RMS, zero mean, periodic in x and
    /// y, reproducible, a finer cut-off leaves the coarse modes' draws, and
    /// the ensemble is isotropic with the expected mean square.
    #[test]
    fn random_areal_surface_properties() {
        let spec = |cut: f64, sample: u64| RandomSpec {
            rms: 5e-7,
            spectrum: SpectrumKind::SelfAffine,
            correlation_length: None,
            hurst: Some(0.8),
            rolloff_wavelength: Some(W / 2.0),
            cutoff_wavelength: Some(cut),
            seed: Some(3),
            sample: Some(sample),
            stream: None,
            exact_rms: false,
        };
        let s = RandomArealSurface::generate(&spec(W / 8.0, 0), "surface.lower", W);
        assert_eq!(s.modes(), RandomArealSurface::wave_numbers(8).len());
        let (m, q) = mean_square(&s, 32);
        assert!(m.abs() < 1e-6 * s.rms(), "mean {m}");
        assert!(
            (q.sqrt() / s.rms() - 1.0).abs() < 1e-10,
            "{} vs {}",
            q.sqrt(),
            s.rms()
        );
        for (x, y) in [(1.3e-6, 2.9e-6), (0.0, 9.1e-6)] {
            let h = s.height(x, y);
            assert!((s.height(x + W, y) - h).abs() < 1e-12 * s.rms());
            assert!((s.height(x, y + W) - h).abs() < 1e-12 * s.rms());
        }
        let again = RandomArealSurface::generate(&spec(W / 8.0, 0), "surface.lower", W);
        assert_eq!(s.height(1e-6, 2e-6), again.height(1e-6, 2e-6));
        let fine = RandomArealSurface::generate(&spec(W / 16.0, 0), "surface.lower", W);
        let (_, c0, d0) = s.coefficients();
        let (_, c1, d1) = fine.coefficients();
        // Same draws a_m, b_m: the coefficients differ by the normalisation only.
        let r = c1[0] / c0[0];
        for m in 0..c0.len() {
            assert!((c1[m] / c0[m] - r).abs() < 1e-12 && (d1[m] / d0[m] - r).abs() < 1e-12);
        }
        // Ensemble: mean square ≈ rms², and x and y slopes alike (isotropy).
        let n = 200;
        let (mut ms, mut gx, mut gy) = (0.0, 0.0, 0.0);
        for sample in 0..n {
            let s = RandomArealSurface::generate(&spec(W / 8.0, sample), "surface.upper", W);
            ms += s.rms().powi(2) / n as f64;
            let (waves, c, d) = s.coefficients();
            for (m, &(k, l)) in waves.iter().enumerate() {
                let e = 0.5 * (c[m] * c[m] + d[m] * d[m]) / n as f64;
                gx += e * (k * k) as f64;
                gy += e * (l * l) as f64;
            }
        }
        assert!((ms / 2.5e-13 - 1.0).abs() < 0.1, "mean square {ms:e}");
        assert!((gx / gy - 1.0).abs() < 0.1, "slope anisotropy {}", gx / gy);
        let e = ArealSpec::Random(spec(W / 1000.0, 0))
            .validate("surface.upper", W)
            .unwrap_err()
            .to_string();
        assert!(e.contains("surface.upper.cutoff_wavelength"), "{e}");
    }

    /// The periodic bicubic spline: exact at the nodes, fourth order on a
    /// smooth periodic function, mean removed, and clear errors.
    #[test]
    fn heightmap_interpolates_and_converges() {
        let f = |x: f64, y: f64| {
            let (u, v) = (std::f64::consts::TAU * x / W, std::f64::consts::TAU * y / W);
            1e-7 * (u.sin() * (2.0 * v).cos() + 0.5 * (u + v).cos()) + 3e-8
        };
        let mut errors = Vec::new();
        for n in [16usize, 32, 64] {
            // A non-square grid: n_x = n, n_y = 3n/2.
            let (nx, ny) = (n, 3 * n / 2);
            let node = |i: usize, j: usize| (W * i as f64 / nx as f64, W * j as f64 / ny as f64);
            let rows: Vec<Vec<f64>> = (0..ny)
                .map(|j| {
                    (0..nx)
                        .map(|i| {
                            let (x, y) = node(i, j);
                            f(x, y)
                        })
                        .collect()
                })
                .collect();
            let m = HeightMap::from_grid(rows, W, "surface.upper.file").unwrap();
            assert_eq!(m.size(), (nx, ny));
            assert!((m.removed_mean - 3e-8).abs() < 1e-20);
            let (x, y) = node(3, 5);
            assert!((m.height(x, y) + 3e-8 - f(x, y)).abs() < 1e-20);
            let mut e: f64 = 0.0;
            for k in 0..997 {
                let (x, y) = (
                    W * (k as f64 * 0.618_034).fract(),
                    W * (k as f64 * 0.414_214).fract(),
                );
                e = e.max((m.height(x, y) + 3e-8 - f(x, y)).abs());
            }
            errors.push(e);
        }
        let rate = (errors[1] / errors[2]).log2();
        assert!(rate > 3.7, "rate {rate}: {errors:?}");
        for (rows, needle) in [
            (vec![vec![0.0; 4]; 3], "4 x 4"),
            // A short map that is also ragged: named as ragged.
            (
                vec![vec![0.0; 3], vec![0.0; 3], vec![0.0; 2]],
                "line 3 has 2 values",
            ),
            (
                vec![vec![0.0; 4], vec![0.0; 4], vec![0.0; 5], vec![0.0; 4]],
                "line 3 has 5 values",
            ),
            (vec![vec![0.0, f64::NAN, 0.0, 0.0]; 4], "finite"),
            (vec![vec![0.0, 1.0, 0.0, 0.0]; 4], "peak-to-valley"),
        ] {
            let e = HeightMap::from_grid(rows, W, "surface.upper.file")
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(needle) && e.contains("surface.upper.file"),
                "{e}"
            );
        }
    }
}
