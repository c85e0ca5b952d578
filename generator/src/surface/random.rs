//! Random rough surfaces (spec §3, paper Sect. 5.8): Gaussian heights,
//! periodic over the sample width, with a Gaussian autocorrelation or a
//! self-affine power spectrum, drawn from a portable, documented random
//! stream so that sample `s` of seed `k` is the same surface everywhere.
//!
//! # The height function
//!
//! A random profile is the trigonometric polynomial
//!
//! `f(x) = Σ_{k=1..K} c_k cos(q_k x) + d_k sin(q_k x)`, `q_k = 2πk/W`,
//!
//! with `c_k = σ_s √w_k a_k`, `d_k = σ_s √w_k b_k`, `a_k, b_k` independent
//! standard normal draws and `w_k` the discrete power spectrum:
//!
//! - `spectrum = "gaussian"`: `w_k = exp(−(q_k ℓ)²/4)`, the spectrum of the
//!   autocorrelation `R(τ) = rms² exp(−τ²/ℓ²)` (`ℓ = correlation_length`);
//!   modes with `w_k < e⁻³⁶` are dropped (`q_k ℓ > 12`), and so are modes
//!   shorter than `cutoff_wavelength` if it is given;
//! - `spectrum = "self-affine"`: `w_k = 1` for `q_k ≤ q_r` (roll-off,
//!   `q_r = 2π/rolloff_wavelength`, default the width), `w_k = (q_k/q_r)^−(1+2H)`
//!   for `q_r < q_k ≤ q_s` and 0 beyond the cut-off `q_s = 2π/cutoff_wavelength`
//!   (`H = hurst`): the profile spectrum of a self-affine isotropic surface
//!   whose areal spectrum is `∝ q^−2(1+H)`.
//!
//! The mean is zero (no `k = 0` mode) and `f` is periodic over `W` with all
//! its derivatives. `f` is a Gaussian random field: with `σ_s = rms/√(Σ w_k)`
//! its expected mean square is `rms²` and its expected autocorrelation is
//! `R_W(τ) = rms² Σ w_k cos(q_k τ) / Σ w_k` ([`RandomSpec::expected_autocorrelation`]),
//! which tends to `rms² exp(−τ²/ℓ²)` for the Gaussian family as `ℓ/W → 0`
//! (a periodic, zero-mean sample lacks the `k = 0` mode: the deviation is
//! `O(ℓ/W)`). The RMS of one sample therefore scatters about `rms`, and the
//! scatter shrinks as the sample widens (paper Sect. 5.8). With
//! `exact_rms = true` each sample is instead rescaled so that its RMS over one
//! period, `√(Σ (c_k² + d_k²)/2)` (Parseval), is exactly `rms`; this biases
//! the spectrum toward the higher modes when few modes carry the power.
//!
//! # The random stream (part of the table schema, see `schemas/table.md`)
//!
//! ChaCha20 (20 rounds, Bernstein's original variant: 64-bit block counter and
//! 64-bit nonce, as `rand_chacha::ChaCha20Rng`) with the 32-byte key
//! `seed (u64 LE) ‖ sample (u64 LE) ‖ stream (u32 LE) ‖ 12 zero bytes`,
//! nonce 0, starting at block 0. The output is read as consecutive 32-bit
//! little-endian words `w_0, w_1, …`; draw `i` is the 64-bit integer
//! `x_i = w_{2i} + 2³² w_{2i+1}`. Mode `k` uses draws `2(k−1)` and `2k−1`
//! through Box–Muller: `u₁ = (⌊x/2¹¹⌋ + 1)·2⁻⁵³ ∈ (0, 1]`,
//! `u₂ = ⌊x'/2¹¹⌋·2⁻⁵³ ∈ [0, 1)`, `r = √(−2 ln u₁)`, `a_k = r cos 2πu₂`,
//! `b_k = r sin 2πu₂`. The elementary functions are those of the pure-Rust
//! `libm` crate (a port of musl), so the heights are bit-identical on every
//! machine, thread count and shard split. Adding modes (a finer cut-off)
//! leaves the lower modes' draws unchanged. This algorithm changes only with
//! [`RANDOM_SURFACE_VERSION`] (and so with the table schema version).
//!
//! By default the upper body uses stream 0 and the lower body stream 1, so a
//! two-sided pair (both bodies random with the same seed and sample) is two
//! independent surfaces with the same statistics.

use rand_chacha::ChaCha20Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};

use crate::surface::Surface;
use crate::{Error, Result};

/// Version of the random-surface algorithm and stream layout above; the
/// table schema version changes with it.
pub const RANDOM_SURFACE_VERSION: u32 = 1;

/// Largest number of Fourier modes of one profile.
pub const MAX_MODES: usize = 65_536;

/// The power spectrum family of a random surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SpectrumKind {
    /// Gaussian autocorrelation `R(τ) = rms² exp(−τ²/ℓ²)`.
    Gaussian,
    /// Self-affine (fractal) spectrum with roll-off and cut-off.
    SelfAffine,
}

/// The keys of `kind = "random"` in `[surface.upper]` / `[surface.lower]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomSpec {
    /// RMS roughness (m): of the ensemble, or of every sample with `exact_rms`.
    pub rms: f64,
    /// Spectrum family.
    pub spectrum: SpectrumKind,
    /// Correlation length ℓ (m) of the Gaussian autocorrelation (`gaussian` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation_length: Option<f64>,
    /// Hurst exponent `H ∈ (0, 1)` (`self-affine` only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hurst: Option<f64>,
    /// Roll-off wavelength `2π/q_r` (m, `self-affine` only; default the sample width).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rolloff_wavelength: Option<f64>,
    /// Cut-off (shortest) wavelength `2π/q_s` (m); required for `self-affine`,
    /// optional for `gaussian`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cutoff_wavelength: Option<f64>,
    /// Seed `k` of the ensemble (default 0; a sweep sets it from `[sweep] seed`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Sample index `s` in the ensemble (default 0; a sweep sets it per sample).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sample: Option<u64>,
    /// Stream of this surface (default 0 for the upper body, 1 for the lower body).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stream: Option<u32>,
    /// Rescale every sample to exactly `rms` (default false: `rms` is the ensemble RMS).
    #[serde(default)]
    pub exact_rms: bool,
}

impl RandomSpec {
    /// The stream used for the body that `key` names (`…upper` → 0, `…lower` → 1).
    pub fn stream_for(&self, key: &str) -> u32 {
        self.stream
            .unwrap_or(if key.ends_with("lower") { 1 } else { 0 })
    }

    /// Checks the keys against the sample width; `key` names the table.
    pub fn validate(&self, key: &str, width: f64) -> Result<()> {
        let length = |name: &str, v: f64, hi: f64, what: &str| -> Result<()> {
            if v.is_finite() && v > 0.0 && v <= hi {
                Ok(())
            } else {
                Err(Error::invalid(
                    format!("{key}.{name}"),
                    v,
                    format!("a length in (0, {hi:e}] m ({what})"),
                ))
            }
        };
        if !(self.rms.is_finite() && self.rms > 0.0 && self.rms < width) {
            return Err(Error::invalid(
                format!("{key}.rms"),
                self.rms,
                format!("a length in (0, width = {width:e}) m"),
            ));
        }
        let not_for = |name: &str, given: bool| -> Result<()> {
            if given {
                Err(Error::invalid(
                    format!("{key}.{name}"),
                    "given",
                    format!("absent for spectrum = \"{}\"", self.spectrum_name()),
                ))
            } else {
                Ok(())
            }
        };
        match self.spectrum {
            SpectrumKind::Gaussian => {
                let l = self.correlation_length.ok_or_else(|| {
                    Error::invalid(
                        format!("{key}.correlation_length"),
                        "missing",
                        "a length in (0, width] m for spectrum = \"gaussian\"",
                    )
                })?;
                length("correlation_length", l, width, "at most the sample width")?;
                not_for("hurst", self.hurst.is_some())?;
                not_for("rolloff_wavelength", self.rolloff_wavelength.is_some())?;
            }
            SpectrumKind::SelfAffine => {
                not_for("correlation_length", self.correlation_length.is_some())?;
                let h = self.hurst.ok_or_else(|| {
                    Error::invalid(
                        format!("{key}.hurst"),
                        "missing",
                        "a Hurst exponent in (0, 1) for spectrum = \"self-affine\"",
                    )
                })?;
                if !(h.is_finite() && h > 0.0 && h < 1.0) {
                    return Err(Error::invalid(
                        format!("{key}.hurst"),
                        h,
                        "a number in (0, 1)",
                    ));
                }
                let r = self.rolloff_wavelength.unwrap_or(width);
                length("rolloff_wavelength", r, width, "at most the sample width")?;
                if self.cutoff_wavelength.is_none() {
                    return Err(Error::invalid(
                        format!("{key}.cutoff_wavelength"),
                        "missing",
                        "the shortest wavelength (m) for spectrum = \"self-affine\"",
                    ));
                }
            }
        }
        if let Some(c) = self.cutoff_wavelength {
            let hi = match self.spectrum {
                SpectrumKind::SelfAffine => self.rolloff_wavelength.unwrap_or(width),
                SpectrumKind::Gaussian => width,
            };
            length(
                "cutoff_wavelength",
                c,
                hi,
                "at most the roll-off wavelength and width",
            )?;
            if width / c > MAX_MODES as f64 {
                return Err(Error::invalid(
                    format!("{key}.cutoff_wavelength"),
                    c,
                    format!(
                        "at least width/{MAX_MODES} = {:e} m",
                        width / MAX_MODES as f64
                    ),
                ));
            }
        }
        if let SpectrumKind::Gaussian = self.spectrum {
            let k = self.mode_count(width);
            if k > MAX_MODES {
                return Err(Error::invalid(
                    format!("{key}.correlation_length"),
                    self.correlation_length.unwrap_or(0.0),
                    format!(
                        "a correlation length needing at most {MAX_MODES} modes (≥ {:e} m), or set cutoff_wavelength",
                        12.0 * width / (std::f64::consts::TAU * MAX_MODES as f64)
                    ),
                ));
            }
        }
        Ok(())
    }

    fn spectrum_name(&self) -> &'static str {
        match self.spectrum {
            SpectrumKind::Gaussian => "gaussian",
            SpectrumKind::SelfAffine => "self-affine",
        }
    }

    /// The number of modes `K` (the spec must be valid).
    pub fn mode_count(&self, width: f64) -> usize {
        let by_cutoff = |c: f64| (width / c * (1.0 + 1e-12)).floor() as usize;
        let k = match self.spectrum {
            SpectrumKind::Gaussian => {
                let l = self.correlation_length.unwrap_or(width);
                let k = (12.0 * width / (std::f64::consts::TAU * l)).floor() as usize;
                match self.cutoff_wavelength {
                    Some(c) => k.min(by_cutoff(c)),
                    None => k,
                }
            }
            SpectrumKind::SelfAffine => self.cutoff_wavelength.map_or(1, by_cutoff),
        };
        k.max(1)
    }

    /// The discrete spectrum `w_k`, `k = 1..=K` (unnormalized).
    pub fn spectrum_weights(&self, width: f64) -> Vec<f64> {
        (1..=self.mode_count(width))
            .map(|k| self.spectrum_weight(width, std::f64::consts::TAU * k as f64 / width, false))
            .collect()
    }

    /// The spectrum weight at wave number `q` (unnormalized): the profile
    /// spectrum (module documentation), or with `areal` the isotropic areal
    /// spectrum of a 3D surface (`q^−2(1+H)` for self-affine; the same
    /// Gaussian form), see [`crate::surface::areal`].
    pub fn spectrum_weight(&self, width: f64, q: f64, areal: bool) -> f64 {
        match self.spectrum {
            SpectrumKind::Gaussian => {
                let l = self.correlation_length.unwrap_or(width);
                libm::exp(-(q * l) * (q * l) / 4.0)
            }
            SpectrumKind::SelfAffine => {
                let qr = std::f64::consts::TAU / self.rolloff_wavelength.unwrap_or(width);
                let h = self.hurst.unwrap_or(0.5);
                let exponent = if areal {
                    -2.0 * (1.0 + h)
                } else {
                    -(1.0 + 2.0 * h)
                };
                if q <= qr * (1.0 + 1e-12) {
                    1.0
                } else {
                    libm::pow(q / qr, exponent)
                }
            }
        }
    }

    /// The expected autocorrelation `E[f(x) f(x+τ)] = rms² Σ w_k cos(q_k τ) / Σ w_k`.
    pub fn expected_autocorrelation(&self, width: f64, lag: f64) -> f64 {
        let w = self.spectrum_weights(width);
        let total: f64 = w.iter().sum();
        let c: f64 = w
            .iter()
            .enumerate()
            .map(|(i, wk)| wk * libm::cos(std::f64::consts::TAU * (i + 1) as f64 * lag / width))
            .sum();
        self.rms * self.rms * c / total
    }

    /// The Fourier coefficients `(c_m, d_m) = σ_s √w_m (a_m, b_m)` of modes with
    /// spectrum weights `weights`, the normal pairs drawn in order from the
    /// stream `(seed, sample, stream)`, scaled to the ensemble RMS (or to the
    /// sample's exact RMS with `exact_rms`). Shared by profiles and areal surfaces.
    pub fn draw_coefficients(&self, stream: u32, weights: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let mut rng = StreamRng::new(self.seed.unwrap_or(0), self.sample.unwrap_or(0), stream);
        let mut cos = Vec::with_capacity(weights.len());
        let mut sin = Vec::with_capacity(weights.len());
        for w in weights {
            let (a, b) = rng.normal_pair();
            let s = w.sqrt();
            cos.push(s * a);
            sin.push(s * b);
        }
        let scale = if self.exact_rms {
            self.rms / parseval_rms(&cos, &sin)
        } else {
            self.rms / weights.iter().sum::<f64>().sqrt()
        };
        for v in cos.iter_mut().chain(sin.iter_mut()) {
            *v *= scale;
        }
        (cos, sin)
    }

    /// Draws the surface of this spec for the body `key` names (the spec must be valid).
    pub fn generate(&self, key: &str, width: f64) -> RandomSurface {
        let seed = self.seed.unwrap_or(0);
        let sample = self.sample.unwrap_or(0);
        let stream = self.stream_for(key);
        let weights = self.spectrum_weights(width);
        let (cos, sin) = self.draw_coefficients(stream, &weights);
        RandomSurface {
            width,
            cos,
            sin,
            seed,
            sample,
            stream,
        }
    }
}

/// The portable random stream of one surface (see the module documentation).
pub struct StreamRng {
    rng: ChaCha20Rng,
}

impl StreamRng {
    /// The stream of `(seed, sample, stream)`.
    pub fn new(seed: u64, sample: u64, stream: u32) -> Self {
        let mut key = [0u8; 32];
        key[0..8].copy_from_slice(&seed.to_le_bytes());
        key[8..16].copy_from_slice(&sample.to_le_bytes());
        key[16..20].copy_from_slice(&stream.to_le_bytes());
        StreamRng {
            rng: ChaCha20Rng::from_seed(key),
        }
    }

    /// The next 32-bit output word.
    pub fn next_word(&mut self) -> u32 {
        self.rng.next_u32()
    }

    /// The next 64-bit draw `w_{2i} + 2³² w_{2i+1}`.
    pub fn next_draw(&mut self) -> u64 {
        let lo = u64::from(self.next_word());
        let hi = u64::from(self.next_word());
        lo | (hi << 32)
    }

    /// Two independent standard normal numbers (Box–Muller, module documentation).
    pub fn normal_pair(&mut self) -> (f64, f64) {
        const EPS: f64 = 1.0 / (1u64 << 53) as f64;
        let u1 = ((self.next_draw() >> 11) + 1) as f64 * EPS;
        let u2 = (self.next_draw() >> 11) as f64 * EPS;
        let r = libm::sqrt(-2.0 * libm::log(u1));
        let (s, c) = libm::sincos(std::f64::consts::TAU * u2);
        (r * c, r * s)
    }
}

/// One drawn random profile: a periodic trigonometric polynomial.
#[derive(Clone, Debug)]
pub struct RandomSurface {
    width: f64,
    cos: Vec<f64>,
    sin: Vec<f64>,
    /// Seed `k`.
    pub seed: u64,
    /// Sample `s`.
    pub sample: u64,
    /// Stream.
    pub stream: u32,
}

impl RandomSurface {
    /// Number of modes `K`.
    pub fn modes(&self) -> usize {
        self.cos.len()
    }

    /// The Fourier coefficients `(c_k, d_k)`, `k = 1..=K`.
    pub fn coefficients(&self) -> (&[f64], &[f64]) {
        (&self.cos, &self.sin)
    }

    /// RMS over one period, `√(Σ (c_k² + d_k²)/2)`.
    pub fn rms(&self) -> f64 {
        parseval_rms(&self.cos, &self.sin)
    }
}

/// RMS over one period of `Σ c_m cos(·) + d_m sin(·)`: `√(Σ (c_m² + d_m²)/2)` (Parseval).
pub fn parseval_rms(cos: &[f64], sin: &[f64]) -> f64 {
    cos.iter()
        .zip(sin)
        .map(|(c, d)| 0.5 * (c * c + d * d))
        .sum::<f64>()
        .sqrt()
}

impl Surface for RandomSurface {
    fn height(&self, x: f64) -> f64 {
        let u = x / self.width;
        let u = u - libm::floor(u);
        let mut z = 0.0;
        for (i, (c, d)) in self.cos.iter().zip(&self.sin).enumerate() {
            // Reduce k·u to [0, 1) before scaling by 2π: exact periodicity.
            let t = (i + 1) as f64 * u;
            let (s, co) = libm::sincos(std::f64::consts::TAU * (t - libm::floor(t)));
            z += c * co + d * s;
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: f64 = 1.0e-5;

    fn gaussian(l: f64) -> RandomSpec {
        RandomSpec {
            rms: 5.0e-7,
            spectrum: SpectrumKind::Gaussian,
            correlation_length: Some(l),
            hurst: None,
            rolloff_wavelength: None,
            cutoff_wavelength: None,
            seed: Some(1),
            sample: Some(0),
            stream: None,
            exact_rms: false,
        }
    }

    fn self_affine(h: f64) -> RandomSpec {
        RandomSpec {
            rms: 5.0e-7,
            spectrum: SpectrumKind::SelfAffine,
            correlation_length: None,
            hurst: Some(h),
            rolloff_wavelength: Some(W / 4.0),
            cutoff_wavelength: Some(W / 128.0),
            seed: Some(1),
            sample: Some(0),
            stream: None,
            exact_rms: false,
        }
    }

    fn sampled(s: &RandomSurface, n: usize) -> Vec<f64> {
        (0..n).map(|j| s.height(W * j as f64 / n as f64)).collect()
    }

    #[test]
    fn chacha20_stream_is_the_reference_cipher() {
        // ChaCha20 block 0 with an all-zero key and nonce (RFC 7539, A.1 #1):
        // 76 b8 e0 ad a0 f1 3d 90 ...
        let mut r = StreamRng {
            rng: ChaCha20Rng::from_seed([0; 32]),
        };
        assert_eq!(r.next_word(), 0xade0_b876);
        assert_eq!(r.next_word(), 0x903d_f1a0);
    }

    #[test]
    fn exact_rms_samples_have_the_exact_rms_and_zero_mean() {
        for spec in [gaussian(W / 10.0), self_affine(0.7)] {
            for sample in 0..5 {
                let spec = RandomSpec {
                    sample: Some(sample),
                    exact_rms: true,
                    ..spec.clone()
                };
                let s = spec.generate("surface.upper", W);
                let n = 2 * s.modes() + 7;
                let z = sampled(&s, n);
                let mean = z.iter().sum::<f64>() / n as f64;
                let rms = (z.iter().map(|v| v * v).sum::<f64>() / n as f64).sqrt();
                assert!(mean.abs() < 1e-12 * spec.rms, "mean {mean:e}");
                assert!((rms / spec.rms - 1.0).abs() < 1e-12, "rms {rms:e}");
                assert!((s.rms() / spec.rms - 1.0).abs() < 1e-14);
            }
        }
    }

    /// The ensemble mean square of 400 samples is `rms²` within 4 standard
    /// errors; every sample has zero mean.
    #[test]
    fn ensemble_rms_matches_the_target() {
        for spec in [gaussian(W / 10.0), self_affine(0.7)] {
            let m = 400;
            let ms: Vec<f64> = (0..m as u64)
                .map(|k| {
                    let s = RandomSpec {
                        sample: Some(k),
                        ..spec.clone()
                    }
                    .generate("surface.upper", W);
                    let z = sampled(&s, 2 * s.modes() + 7);
                    let mean = z.iter().sum::<f64>() / z.len() as f64;
                    assert!(mean.abs() < 1e-12 * spec.rms);
                    (s.rms() / spec.rms).powi(2)
                })
                .collect();
            let mean = ms.iter().sum::<f64>() / m as f64;
            let sd = (ms.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1) as f64).sqrt();
            assert!(
                (mean - 1.0).abs() < 4.0 * sd / (m as f64).sqrt(),
                "{:?}: <f²>/rms² = {mean} (sd {sd})",
                spec.spectrum
            );
        }
    }

    #[test]
    fn surfaces_are_periodic_over_the_width() {
        let s = self_affine(0.5).generate("surface.upper", W);
        for i in 0..20 {
            let x = W * i as f64 / 20.0;
            let (a, b, c) = (s.height(x), s.height(x + W), s.height(x - 3.0 * W));
            assert!((a - b).abs() < 1e-12 * 5e-7 && (a - c).abs() < 1e-12 * 5e-7);
        }
    }

    #[test]
    fn streams_are_deterministic_and_independent() {
        let spec = gaussian(W / 8.0);
        let a = spec.generate("surface.upper", W);
        let b = spec.generate("surface.upper", W);
        assert_eq!(a.coefficients(), b.coefficients());
        // Bodies, samples and seeds give different surfaces.
        let lower = spec.generate("surface.lower", W);
        let next = RandomSpec {
            sample: Some(1),
            ..spec.clone()
        }
        .generate("surface.upper", W);
        let other = RandomSpec {
            seed: Some(2),
            ..spec.clone()
        }
        .generate("surface.upper", W);
        for s in [&lower, &next, &other] {
            assert_ne!(a.coefficients().0[0], s.coefficients().0[0]);
        }
        // The same on any thread, in any order.
        let ref_bits: Vec<u64> = (0..8)
            .map(|k| {
                RandomSpec {
                    sample: Some(k),
                    ..spec.clone()
                }
                .generate("surface.upper", W)
                .height(0.3 * W)
                .to_bits()
            })
            .collect();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let bits: Vec<u64> = pool.install(|| {
                use rayon::prelude::*;
                (0..8usize)
                    .into_par_iter()
                    .rev()
                    .map(|k| {
                        RandomSpec {
                            sample: Some(k as u64),
                            ..spec.clone()
                        }
                        .generate("surface.upper", W)
                        .height(0.3 * W)
                        .to_bits()
                    })
                    .collect::<Vec<_>>()
                    .into_iter()
                    .rev()
                    .collect()
            });
            assert_eq!(bits, ref_bits, "{threads} threads");
        }
    }

    /// Sample 0 of seed 1, upper body (stream 0): pinned heights. These values
    /// change only with [`RANDOM_SURFACE_VERSION`] (and the table schema version).
    #[test]
    fn sample_0_of_seed_1_is_pinned() {
        let g = gaussian(W / 10.0).generate("surface.upper", W);
        let a = self_affine(0.8).generate("surface.upper", W);
        let got: Vec<f64> = [0.0, 0.25, 0.5, 0.75]
            .iter()
            .flat_map(|u| [g.height(u * W), a.height(u * W)])
            .collect();
        let pinned = [
            -3.9613307391564893e-7,
            -4.3189229482017326e-7,
            -1.3408996371760544e-7,
            -3.6103291577315514e-7,
            2.6686037224912385e-7,
            3.187591428726008e-7,
            2.1966290236059615e-7,
            4.188353072480321e-7,
        ];
        for (g, p) in got.iter().zip(pinned) {
            assert!((g - p).abs() <= 1e-13 * 5e-7, "{got:?}");
        }
    }

    /// The ensemble autocorrelation of 400 Gaussian-correlated samples matches
    /// its expectation `R_W(τ)` within 4 standard errors, and `R_W` is within
    /// `2ℓ/W = 0.04` of `exp(−τ²/ℓ²)` for `ℓ = W/50`.
    #[test]
    fn gaussian_autocorrelation_matches_the_target() {
        let l = W / 10.0;
        let m = 400;
        let n = 256;
        let lags = [0usize, 4, 8, 13, 20, 32];
        let mut acf = vec![Vec::with_capacity(m); lags.len()];
        let spec = gaussian(l);
        for s in 0..m as u64 {
            let z = sampled(
                &RandomSpec {
                    sample: Some(s),
                    ..spec.clone()
                }
                .generate("surface.upper", W),
                n,
            );
            for (i, &lag) in lags.iter().enumerate() {
                let c = (0..n).map(|j| z[j] * z[(j + lag) % n]).sum::<f64>() / n as f64;
                acf[i].push(c / (spec.rms * spec.rms));
            }
        }
        for (i, &lag) in lags.iter().enumerate() {
            let v = &acf[i];
            let mean = v.iter().sum::<f64>() / m as f64;
            let sd = (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (m - 1) as f64).sqrt();
            let tau = W * lag as f64 / n as f64;
            let target = spec.expected_autocorrelation(W, tau) / (spec.rms * spec.rms);
            let tol = 4.0 * sd / (m as f64).sqrt();
            assert!(
                (mean - target).abs() <= tol,
                "lag {tau:e}: {mean} vs {target} ± {tol}"
            );
        }
        let narrow = gaussian(W / 50.0);
        for t in [0.0, 0.2, 0.5, 1.0, 2.0] {
            let tau = t * W / 50.0;
            let r = narrow.expected_autocorrelation(W, tau) / (narrow.rms * narrow.rms);
            assert!((r - (-t * t).exp()).abs() < 0.04, "τ/ℓ = {t}: {r}");
        }
    }

    /// The ensemble periodogram of 200 self-affine samples, computed from the
    /// heights, has the log–log slope `−(1 + 2H)` within ±0.1 between roll-off
    /// and cut-off, and is flat (slope within ±0.3 of 0) below the roll-off.
    #[test]
    fn self_affine_spectrum_matches_the_target() {
        for h in [0.3, 0.8] {
            let spec = self_affine(h);
            let n = 512;
            let k_max = spec.mode_count(W);
            let mut power = vec![0.0; k_max + 1];
            let m = 200;
            for s in 0..m as u64 {
                let z = sampled(
                    &RandomSpec {
                        sample: Some(s),
                        ..spec.clone()
                    }
                    .generate("surface.lower", W),
                    n,
                );
                for (k, p) in power.iter_mut().enumerate().skip(1) {
                    let (mut re, mut im) = (0.0, 0.0);
                    for (j, zj) in z.iter().enumerate() {
                        let a = std::f64::consts::TAU * ((k * j) % n) as f64 / n as f64;
                        re += zj * a.cos();
                        im += zj * a.sin();
                    }
                    *p += (re * re + im * im) / m as f64;
                }
            }
            let slope = |ks: std::ops::RangeInclusive<usize>| {
                let pts: Vec<(f64, f64)> = ks.map(|k| ((k as f64).ln(), power[k].ln())).collect();
                let nn = pts.len() as f64;
                let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
                let (mx, my) = (sx / nn, sy / nn);
                let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
                let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
                sxy / sxx
            };
            let fractal = slope(8..=k_max);
            assert!(
                (fractal + 1.0 + 2.0 * h).abs() < 0.1,
                "H = {h}: slope {fractal}"
            );
            assert!(
                slope(1..=4).abs() < 0.3,
                "H = {h}: plateau {}",
                slope(1..=4)
            );
            assert!(power[k_max + 1..].iter().all(|p| *p < 1e-20));
        }
    }

    /// Pooled heights of 400 samples (`ℓ = W/50`, about `N = 400·W/(2ℓ) = 10⁴`
    /// independent values): skewness within ±0.1 and kurtosis within 3 ± 0.2,
    /// four standard errors `√(6/N)` and `√(24/N)`.
    #[test]
    fn heights_are_gaussian() {
        let mut z = Vec::new();
        for s in 0..400 {
            let spec = RandomSpec {
                sample: Some(s),
                ..gaussian(W / 50.0)
            };
            z.extend(sampled(&spec.generate("surface.upper", W), 100));
        }
        let n = z.len() as f64;
        let m2 = z.iter().map(|v| v * v).sum::<f64>() / n;
        let m3 = z.iter().map(|v| v.powi(3)).sum::<f64>() / n;
        let m4 = z.iter().map(|v| v.powi(4)).sum::<f64>() / n;
        let (skew, kurt) = (m3 / m2.powf(1.5), m4 / (m2 * m2));
        assert!(
            skew.abs() < 0.1 && (kurt - 3.0).abs() < 0.2,
            "{skew} {kurt}"
        );
    }

    #[test]
    fn invalid_keys_are_named() {
        let mut s = gaussian(W / 10.0);
        s.hurst = Some(0.5);
        assert!(
            s.validate("surface.upper", W)
                .unwrap_err()
                .to_string()
                .contains("surface.upper.hurst")
        );
        let mut s = self_affine(0.5);
        s.cutoff_wavelength = None;
        assert!(
            s.validate("surface.lower", W)
                .unwrap_err()
                .to_string()
                .contains("cutoff_wavelength")
        );
        let mut s = self_affine(1.5);
        s.seed = None;
        assert!(
            s.validate("k", W)
                .unwrap_err()
                .to_string()
                .contains("k.hurst")
        );
        let mut s = gaussian(W / 10.0);
        s.rms = 2.0 * W;
        assert!(
            s.validate("k", W)
                .unwrap_err()
                .to_string()
                .contains("k.rms")
        );
        let s = gaussian(2.0 * W);
        assert!(
            s.validate("k", W)
                .unwrap_err()
                .to_string()
                .contains("correlation_length")
        );
    }
}
