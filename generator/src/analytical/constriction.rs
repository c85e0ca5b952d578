//! Thermal constriction of periodic contact strips (spec §10.5), and Barber's
//! conductance–stiffness analogy.
//!
//! Two bodies (conductivities `k1`, `k2`) touch on the strips `|x − mλ| < a`
//! with perfect thermal contact (continuous temperature and flux) and are
//! adiabatic in the gaps; small strain, steady conduction, plane. The mean flux
//! `h̄` crosses the interface; the macroscopic jump is the difference of the mean
//! surface temperatures, `jump = θ̄(1) − θ̄(2)`, i.e. the far-face temperature
//! difference less the 1D bulk drops `h̄ (H1/k1 + H2/k2)` (the linearized
//! identification (3.4) of a rigid two-phase sample). The conductance is `h̄/jump`.
//!
//! **Half-spaces.** The contact strips are isothermal and the flux is
//! `q(x) = h̄ cos(πx/λ) / √(sin²(πa/λ) − sin²(πx/λ))`; per unit area, one
//! half-space adds the constriction resistance `R = (λ/(π k)) ln(1/sin(πa/λ))`
//! (the classical isothermal-strip solution of the two-dimensional flux channel,
//! by conformal mapping; e.g. Yovanovich & Marotta, *Thermal spreading and
//! contact resistances*, ch. 4 of Bejan & Kraus (eds.), *Heat Transfer
//! Handbook*, 2003). Isothermal strips are the exact condition for perfect
//! contact between half-spaces (the tests verify that this flux makes the strip
//! isothermal); the often-quoted uniform-flux strip is only an approximation
//! and gives a larger resistance. Both bodies see the same isothermal-strip problem, so
//! `jump/h̄ = (λ/π) (1/k1 + 1/k2) ln(1/sin(πa/λ)) = 2λ ln(1/sin(πa/λ)) / (π k_s)`,
//! `k_s = 2 k1 k2/(k1 + k2)`.
//!
//! **Barber's analogy** (J.R. Barber, *Bounds on the electrical resistance between
//! contacting elastic rough bodies*, Proc. R. Soc. Lond. A 459, 2003, 53–66):
//! the surface Green's functions of heat conduction, `(1/(π k)) ln(1/r)` per
//! body, and of plane-strain elasticity, `(2 (1 − ν²)/(π E)) ln(1/r)`, differ by
//! the factor `E*/k_s`, so the incremental contact conductance is
//! `C = (k_s/E*) dp̄/dδ̄` (Barber's `C = 2/((ρ1 + ρ2) E*) dP/dδ` with the
//! resistivities `ρ = 1/k`). With Westergaard's stiffness
//! `dp̄/dδ̄ = π E*/(2λ ln(1/sin(πa/λ)))` this is exactly the strip conductance
//! above, at every `a/λ` (tested).
//!
//! **Finite heights.** A layer of height `H` whose far face is isothermal
//! (or carries a uniform flux, its mean temperature then being measured, as on
//! the slave's external face of the OHP) answers the surface flux mode
//! `cos(κx)`, `κ = 2πn/λ`, with the surface temperature mode `tanh(κH)/(kκ)`
//! (or `coth(κH)/(kκ)`); the half-space value is `1/(kκ)`. The mixed problem
//! (uniform temperature difference on the strips, zero flux in the gaps) is
//! solved by Galerkin's method in the basis
//! `B_m(x) = cos(πx/λ) T_2m(t) / √(S² − sin²(πx/λ))`, `t = sin(πx/λ)/S`,
//! `S = sin(πa/λ)`, in which the half-space operator is diagonal
//! (`∫ T_k(t) ln|t0 − t| dt/√(1−t²) = −(π/k) T_k(t0)`) and the Fourier modes are
//! polynomials, `cos(2πnx/λ) = (−1)^n T_2n(S t)`; with `N` Fourier modes and
//! `N + 1` basis functions it is exact up to the truncation of the modes, whose
//! correction decays like `e^(−4πnH/λ)`, so `N` is chosen for 1e−17.
//! To leading order, `jump/h̄ − R∞ = (λ/π) cos⁴(πa/λ) Σ_i (f_i(2πH_i/λ) − 1)/k_i`
//! with `f = tanh` or `coth` ([`strip_resistance_height_correction`]).

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};

use crate::{Error, Result};

/// Harmonic-mean conductivity `k_s = 2 k1 k2/(k1 + k2)` (W/(m·K)); `k = ∞` is a perfect conductor.
#[track_caller]
pub fn harmonic_mean_conductivity(k1: f64, k2: f64) -> f64 {
    assert!(
        k1 > 0.0 && k2 > 0.0,
        "harmonic_mean_conductivity: conductivities must be > 0, got {k1}, {k2}"
    );
    2.0 / (1.0 / k1 + 1.0 / k2)
}

/// `ln(1/sin(πa/λ))`, accurate near full contact, for `0 ≤ a ≤ λ/2`.
#[track_caller]
fn log_inverse_sine(wavelength: f64, half_width: f64) -> f64 {
    assert!(
        wavelength > 0.0 && wavelength.is_finite(),
        "strip constriction: wavelength must be finite and > 0, got {wavelength}"
    );
    assert!(
        (0.0..=0.5 * wavelength).contains(&half_width),
        "strip constriction: half-width must be in [0, λ/2] = [0, {}], got {half_width}",
        0.5 * wavelength
    );
    if half_width == 0.5 * wavelength {
        return 0.0;
    }
    let c = (PI * half_width / wavelength).cos();
    -0.5 * (-c * c).ln_1p()
}

/// Constriction resistance per unit area of one half-space on isothermal
/// periodic strips, `R = (λ/(π k)) ln(1/sin(πa/λ))` (m²K/W); `∞` at `a = 0`, `0` at `a = λ/2`.
#[track_caller]
pub fn strip_constriction_resistance(conductivity: f64, wavelength: f64, half_width: f64) -> f64 {
    assert!(
        conductivity > 0.0,
        "strip_constriction_resistance: conductivity must be > 0, got {conductivity}"
    );
    wavelength / (PI * conductivity) * log_inverse_sine(wavelength, half_width)
}

/// Macroscopic conductance `h̄/jump` (W/(m²K)) of periodic strips between two
/// half-spaces: `1/(R1 + R2) = π k_s / (2λ ln(1/sin(πa/λ)))` (module doc).
#[track_caller]
pub fn strip_conductance(k1: f64, k2: f64, wavelength: f64, half_width: f64) -> f64 {
    PI * harmonic_mean_conductivity(k1, k2)
        / (2.0 * wavelength * log_inverse_sine(wavelength, half_width))
}

/// Interface flux of the half-space strip solution,
/// `q(x) = h̄ cos(πx/λ) / √(sin²(πa/λ) − sin²(πx/λ))` in `|x| < a` (x modulo λ), 0 outside;
/// its mean over a period is `h̄` (the sign of `mean_flux` is kept).
#[track_caller]
pub fn strip_flux_half_space(mean_flux: f64, wavelength: f64, half_width: f64, x: f64) -> f64 {
    log_inverse_sine(wavelength, half_width);
    let xr = x - wavelength * (x / wavelength).round();
    if xr.abs() >= half_width {
        return 0.0;
    }
    let d = (PI * (half_width - xr.abs()) / wavelength).sin()
        * (PI * (half_width + xr.abs()) / wavelength).sin();
    mean_flux * (PI * xr / wavelength).cos() / d.sqrt()
}

/// Barber's analogy: incremental contact conductance `C = (k_s/E*) dp̄/dδ̄`
/// (W/(m²K)) from the incremental contact stiffness per unit area `dp̄/dδ̄`
/// (Pa/m) (module doc; Barber 2003), `k_s = 2 k1 k2/(k1 + k2)`.
#[track_caller]
pub fn barber_conductance_from_stiffness(k1: f64, k2: f64, e_star: f64, stiffness: f64) -> f64 {
    assert!(
        e_star > 0.0 && e_star.is_finite(),
        "barber_conductance_from_stiffness: E* must be finite and > 0, got {e_star}"
    );
    assert!(
        stiffness >= 0.0,
        "barber_conductance_from_stiffness: stiffness must be ≥ 0, got {stiffness}"
    );
    harmonic_mean_conductivity(k1, k2) * stiffness / e_star
}

/// Thermal condition on the far (external) face of a layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FarFace {
    /// Uniform temperature (the master's external face in the OHP, (2.12)).
    Isothermal,
    /// Uniform flux; its mean temperature is the measured one (the slave's external face).
    UniformFlux,
}

/// One body of the finite-height strip problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StripLayer {
    /// Thermal conductivity `k` (W/(m·K)) (`∞`: a perfect conductor).
    pub conductivity: f64,
    /// Height `H` from the interface to the far face (m) (`∞`: a half-space).
    pub height: f64,
    /// Condition on the far face.
    pub far_face: FarFace,
}

impl StripLayer {
    fn validate(&self, name: &str) -> Result<()> {
        if self.conductivity.is_nan() || self.conductivity <= 0.0 {
            return Err(Error::invalid(
                format!("{name}.conductivity"),
                self.conductivity,
                "must be > 0 [W/(m·K)] (∞ allowed)",
            ));
        }
        if self.height.is_nan() || self.height <= 0.0 {
            return Err(Error::invalid(
                format!("{name}.height"),
                self.height,
                "must be > 0 [m] (∞ allowed)",
            ));
        }
        Ok(())
    }

    /// `f(κH) − 1` with `f = tanh` or `coth`, weighted by `1/k`.
    fn mode_correction(&self, kappa_h: f64) -> f64 {
        if self.height.is_infinite() || self.conductivity.is_infinite() {
            return 0.0;
        }
        let x = 2.0 * kappa_h;
        let f_minus_one = match self.far_face {
            FarFace::Isothermal => -2.0 / (x.exp() + 1.0),
            FarFace::UniformFlux => 2.0 / x.exp_m1(),
        };
        f_minus_one / self.conductivity
    }
}

/// Largest number of Fourier modes the finite-height solution uses (limits `H ≳ 1.6e−3 λ`).
const MAX_MODES: usize = 2048;

/// Macroscopic conductance `h̄/jump` (W/(m²K)) of periodic strips between two
/// layers of finite heights (module doc: Galerkin solution of the mixed
/// problem; agrees with the exact conformal map to 2e−13 relative where that applies). `jump` is the difference of the mean
/// surface temperatures; `∞` at full contact (`a = λ/2`), `0` at `a = 0`.
///
/// Errors name the offending field: conductivities and heights `> 0` (`∞`
/// allowed, not both conductivities), `0 ≤ a ≤ λ/2`, and
/// `min H ≥ 3.3 λ / 2048` (Fourier modes needed).
pub fn strip_conductance_layers(
    upper: &StripLayer,
    lower: &StripLayer,
    wavelength: f64,
    half_width: f64,
) -> Result<f64> {
    upper.validate("upper")?;
    lower.validate("lower")?;
    if upper.conductivity.is_infinite() && lower.conductivity.is_infinite() {
        return Err(Error::invalid(
            "upper.conductivity",
            upper.conductivity,
            "at most one body may be a perfect conductor",
        ));
    }
    if !(wavelength > 0.0 && wavelength.is_finite()) {
        return Err(Error::invalid(
            "wavelength",
            wavelength,
            "must be finite and > 0 [m]",
        ));
    }
    if !(0.0..=0.5 * wavelength).contains(&half_width) {
        return Err(Error::invalid(
            "half_width",
            half_width,
            format!("must be in [0, λ/2] = [0, {}] [m]", 0.5 * wavelength),
        ));
    }
    let h_min = upper.height.min(lower.height);
    // |f − 1| ≈ 2 e^(−4π n H/λ) < 1e−17 for n ≥ 3.22 λ/H.
    let needed = (3.22 * wavelength / h_min).ceil();
    if needed > MAX_MODES as f64 {
        return Err(Error::invalid(
            "height",
            h_min,
            format!(
                "must be ≥ {} [m] (3.22 λ / {MAX_MODES}) for the Fourier series",
                3.22 * wavelength / MAX_MODES as f64
            ),
        ));
    }
    let modes = (needed as usize).max(4);
    Ok(1.0 / strip_jump_galerkin(upper, lower, wavelength, half_width, modes))
}

/// [`strip_conductance_layers`] with isothermal far faces at heights `h1` (body 1, `k1`) and `h2` (body 2, `k2`).
pub fn strip_conductance_finite_height(
    k1: f64,
    k2: f64,
    wavelength: f64,
    half_width: f64,
    h1: f64,
    h2: f64,
) -> Result<f64> {
    let upper = StripLayer {
        conductivity: k1,
        height: h1,
        far_face: FarFace::Isothermal,
    };
    let lower = StripLayer {
        conductivity: k2,
        height: h2,
        far_face: FarFace::Isothermal,
    };
    strip_conductance_layers(&upper, &lower, wavelength, half_width)
}

/// Leading-order finite-height correction of the resistance,
/// `jump/h̄ − R∞ ≈ (λ/π) cos⁴(πa/λ) Σ_i (f_i(2πH_i/λ) − 1)/k_i` (m²K/W)
/// (`f = tanh` for an isothermal far face, `< 0`; `coth` for a uniform flux, `> 0`);
/// relative error `O(e^(−4π H/λ))`. Inputs as in [`strip_conductance_layers`] (unchecked).
pub fn strip_resistance_height_correction(
    upper: &StripLayer,
    lower: &StripLayer,
    wavelength: f64,
    half_width: f64,
) -> f64 {
    let kappa = 2.0 * PI / wavelength;
    let c = (PI * half_width / wavelength).cos();
    let d1 =
        upper.mode_correction(kappa * upper.height) + lower.mode_correction(kappa * lower.height);
    wavelength / PI * c.powi(4) * d1
}

/// The jump per unit mean flux, `jump/h̄` (m²K/W), with `modes` Fourier modes
/// and `modes + 1` Chebyshev basis functions (module doc).
fn strip_jump_galerkin(
    upper: &StripLayer,
    lower: &StripLayer,
    wavelength: f64,
    half_width: f64,
    modes: usize,
) -> f64 {
    let resistivity = 1.0 / upper.conductivity + 1.0 / lower.conductivity; // C∞
    let log_inv_s = log_inverse_sine(wavelength, half_width);
    if log_inv_s == 0.0 {
        return 0.0;
    }
    if half_width == 0.0 {
        return f64::INFINITY;
    }
    let s = (PI * half_width / wavelength).sin();
    // Scaled mode corrections ĉ_n = d_n/(C∞ λ) = Σ_i (f_i − 1)/k_i / (2π n C∞).
    let kappa = 2.0 * PI / wavelength;
    let c_hat: Vec<f64> = (1..=modes)
        .map(|n| {
            let kn = kappa * n as f64;
            (upper.mode_correction(kn * upper.height) + lower.mode_correction(kn * lower.height))
                / (2.0 * PI * n as f64 * resistivity)
        })
        .collect();
    let half_space = log_inv_s / PI;
    if c_hat.iter().all(|&c| c == 0.0) {
        return resistivity * wavelength * half_space;
    }
    // β_mn = (2/π)(−1)^n ∫ T_2m(t) T_2n(S t) dt/√(1−t²) by Gauss–Chebyshev, exact with P = 2N + 1 nodes.
    let basis = modes + 1;
    let nodes = 2 * modes + 1;
    let angles: Vec<f64> = (0..nodes)
        .map(|i| (i as f64 + 0.5) * PI / nodes as f64)
        .collect();
    let cheb = DMatrix::from_fn(basis, nodes, |m, i| (2.0 * m as f64 * angles[i]).cos());
    let mut fourier = DMatrix::zeros(nodes, modes);
    for (i, angle) in angles.iter().enumerate() {
        let y = s * angle.cos();
        // T_k(y) by the three-term recurrence; keep the even orders 2, 4, …, 2N.
        let (mut t_prev, mut t_curr) = (1.0, y);
        for k in 2..=2 * modes {
            let t_next = 2.0 * y * t_curr - t_prev;
            t_prev = t_curr;
            t_curr = t_next;
            if k % 2 == 0 {
                let n = k / 2;
                let sign = if n % 2 == 0 { 1.0 } else { -1.0 };
                fourier[(i, n - 1)] = sign * t_curr;
            }
        }
    }
    let beta = (cheb * fourier) * (2.0 / nodes as f64);
    // ĝ = β diag(ĉ) βᵀ; equations (1/(2π j)) b_j + (ĝ b)_j = 0 for j ≥ 1, with b_0 = 1.
    let scaled = DMatrix::from_fn(basis, modes, |m, n| beta[(m, n)] * c_hat[n]);
    let g = &scaled * beta.transpose();
    let unknowns = modes;
    let mut system = DMatrix::from_fn(unknowns, unknowns, |j, m| g[(j + 1, m + 1)]);
    for j in 0..unknowns {
        system[(j, j)] += 1.0 / (2.0 * PI * (j + 1) as f64);
    }
    let rhs = DVector::from_fn(unknowns, |j, _| -g[(j + 1, 0)]);
    let b = system
        .lu()
        .solve(&rhs)
        .expect("strip_jump_galerkin: the Galerkin matrix is positive definite");
    let g_b0 = g[(0, 0)] + (0..unknowns).map(|m| g[(0, m + 1)] * b[m]).sum::<f64>();
    resistivity * wavelength * (half_space + 0.5 * g_b0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytical::westergaard::{self, tests::graded_gauss};

    const LAMBDA: f64 = 1.0e-5;

    fn half_widths() -> Vec<f64> {
        [0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.45, 0.49]
            .iter()
            .map(|f| f * LAMBDA)
            .collect()
    }

    #[test]
    fn strip_resistance_limits_and_series_sum() {
        let (k1, k2) = (1.0, 3.0);
        let mut last = f64::INFINITY;
        for a in half_widths() {
            let r1 = strip_constriction_resistance(k1, LAMBDA, a);
            assert!(r1 > 0.0 && r1 < last);
            last = r1;
            let c = strip_conductance(k1, k2, LAMBDA, a);
            let series = 1.0 / (r1 + strip_constriction_resistance(k2, LAMBDA, a));
            assert!((c - series).abs() < 1e-13 * c);
            assert_eq!(c, strip_conductance(k2, k1, LAMBDA, a));
        }
        assert_eq!(
            strip_constriction_resistance(k1, LAMBDA, 0.0),
            f64::INFINITY
        );
        assert_eq!(strip_constriction_resistance(k1, LAMBDA, 0.5 * LAMBDA), 0.0);
        assert_eq!(strip_conductance(k1, k2, LAMBDA, 0.0), 0.0);
        assert!((harmonic_mean_conductivity(1.0, f64::INFINITY) - 2.0).abs() < 1e-15);
    }

    /// The strip flux carries `h̄` per period and makes the contact isothermal:
    /// the surface temperature `φ(x) = (1/(π k)) ∫ q(s) ln|2 sin(π(x − s)/λ)| ds`
    /// (zero mean over a period) equals `−h̄ R` on the whole strip (to 2e−11 of
    /// the temperature scale `h̄λ/(πk)`; rounding of `s` near the strip edges,
    /// amplified by cancellation as `a → λ/2`, limits it). Quadrature in
    /// `s = (λ/π) arcsin(S sin ψ)`, which removes the inverse square roots
    /// (`ds/dψ = (λ/π) S cos ψ / cos(πs/λ)`), graded at `s = x`.
    #[test]
    fn half_space_strip_flux_gives_an_isothermal_contact_at_the_constriction_resistance() {
        let (k, h_bar) = (2.5, 1.0e6);
        let mut worst: f64 = 0.0;
        for a in [0.02, 0.1, 0.25, 0.4, 0.47].map(|f| f * LAMBDA) {
            let s_a = (PI * a / LAMBDA).sin();
            let position = |psi: f64| LAMBDA / PI * (s_a * psi.sin()).asin();
            let flux_times_jacobian = |psi: f64| {
                let s = position(psi);
                strip_flux_half_space(h_bar, LAMBDA, a, s) * LAMBDA / PI * s_a * psi.cos()
                    / (PI * s / LAMBDA).cos()
            };
            let total = graded_gauss(flux_times_jacobian, 0.0, 0.5 * PI, 40)
                - graded_gauss(flux_times_jacobian, 0.0, -0.5 * PI, 40);
            assert!(
                (total - h_bar * LAMBDA).abs() < 1e-13 * h_bar * LAMBDA,
                "a/λ = {}: {total}",
                a / LAMBDA
            );
            let expected = -h_bar * strip_constriction_resistance(k, LAMBDA, a);
            for f in [0.0, 0.3, 0.7, 0.95] {
                let x = f * a;
                let psi_x = ((PI * x / LAMBDA).sin() / s_a).asin();
                let integrand = |psi: f64| {
                    let d = x - position(psi);
                    // a node rounding onto the log singularity has a negligible weight
                    if d == 0.0 {
                        0.0
                    } else {
                        flux_times_jacobian(psi) * (2.0 * (PI * d / LAMBDA).sin().abs()).ln()
                    }
                };
                let integral = graded_gauss(integrand, psi_x, 0.5 * PI, 100)
                    - graded_gauss(integrand, psi_x, -0.5 * PI, 100);
                let phi = integral / (PI * k);
                // error on the temperature scale h̄λ/(πk) of the integrand (φ itself → 0 as a → λ/2)
                worst = worst.max((phi - expected).abs() / (h_bar * LAMBDA / (PI * k)));
            }
        }
        assert!(
            worst < 2e-11,
            "surface temperature on the strip vs −h̄R: worst difference {worst:e} (units h̄λ/(πk))"
        );
    }

    /// Barber's analogy with Westergaard's stiffness, obtained by differentiating
    /// `p̄(a)` and `ḡ(a)` numerically, reproduces the strip conductance at every a/λ.
    #[test]
    fn barber_analogy_reproduces_the_strip_conductance_for_westergaard() {
        for (e1, nu1, e2, nu2, k1, k2) in [
            (1.0e6, 0.3, f64::INFINITY, 0.3, 1.0, 1.0),
            (2.1e11, 0.29, 7.0e10, 0.33, 50.0, 200.0),
        ] {
            let e_star = westergaard::effective_modulus(e1, nu1, e2, nu2);
            let amplitude = 1.4e-6;
            let mut worst: f64 = 0.0;
            for a in half_widths() {
                let slope = |h: f64| {
                    let dp = westergaard::mean_pressure(e_star, amplitude, LAMBDA, a + h)
                        - westergaard::mean_pressure(e_star, amplitude, LAMBDA, a - h);
                    dp / (westergaard::mean_gap(amplitude, LAMBDA, a - h)
                        - westergaard::mean_gap(amplitude, LAMBDA, a + h))
                };
                let h = 1e-3 * a.min(0.5 * LAMBDA - a);
                let stiffness = (4.0 * slope(0.5 * h) - slope(h)) / 3.0;
                let barber = barber_conductance_from_stiffness(k1, k2, e_star, stiffness);
                let strips = strip_conductance(k1, k2, LAMBDA, a);
                worst = worst.max((barber / strips - 1.0).abs());
            }
            assert!(
                worst < 1e-10,
                "Barber vs strips: worst relative difference {worst:e}"
            );
        }
    }

    /// Exact resistance of the half-cell `[0, λ/2] × [0, H]` (strip `[0, a]` at
    /// temperature 0 on the bottom, far face `y = H` at 1, adiabatic elsewhere),
    /// less the bulk `H/k`: a conformal map (Jacobi `sn`, written with theta
    /// functions) takes the rectangle onto the upper half-plane; the images
    /// `w1..w4` of the ends of the two isothermal arcs, with those arcs `[w2, w3]`
    /// and `[w4, w1]`, have the cross-ratio of `(−1/ℓ, −1, 1, 1/ℓ)`, and `sn⁻¹(·, ℓ)`
    /// takes that onto a rectangle of conductance `2K(ℓ)/K'(ℓ)` (per unit depth).
    /// `rotated`: the vertical sides map onto `[−1, 1]` and `[1/√m, −1/√m]`
    /// (nome `e^(−πλ/H)`, for low layers), otherwise the horizontal ones
    /// (nome `e^(−4πH/λ)`, for tall layers).
    fn isothermal_layer_jump_by_conformal_map(k: f64, height: f64, a: f64, rotated: bool) -> f64 {
        // Σ over the theta series of c (n + s)² − … in exponent form, to avoid overflow.
        let series = |terms: &dyn Fn(f64) -> f64| -> f64 {
            let mut sum = 0.0;
            for n in 0..400 {
                let t = terms(n as f64);
                sum += t;
                if n > 3 && t.abs() < 1e-30 * sum.abs() {
                    break;
                }
            }
            sum
        };
        let (w1, w2, w3, w4);
        if rotated {
            let c = PI * LAMBDA / height; // q = e^(−c)
            let y = PI * a / height;
            let theta2 = |y: f64| {
                series(&|n| {
                    (-(c * (n + 0.5).powi(2)) + (2.0 * n + 1.0) * y).exp()
                        + (-(c * (n + 0.5).powi(2)) - (2.0 * n + 1.0) * y).exp()
                })
            };
            let theta3 = |y: f64| {
                1.0 + series(&|n| {
                    if n == 0.0 {
                        0.0
                    } else {
                        (-(c * n * n) + 2.0 * n * y).exp() + (-(c * n * n) - 2.0 * n * y).exp()
                    }
                })
            };
            let (t2, t3) = (theta2(0.0), theta3(0.0));
            let zeta = -t3 / t2 * theta2(y) / theta3(y);
            // bottom strip [ζ_a, −1], top [1, 1/√m]
            (w1, w2, w3, w4) = (-1.0, 1.0, t3 * t3 / (t2 * t2), zeta);
        } else {
            let q = (-4.0 * PI * height / LAMBDA).exp();
            let v = 2.0 * PI * a / LAMBDA - 0.5 * PI;
            let theta = |kind: u8, v: f64| -> f64 {
                let head = if kind >= 3 { 1.0 } else { 0.0 };
                head + series(&|n| match kind {
                    1 => {
                        2.0 * (-1f64).powf(n)
                            * q.powf((n + 0.5).powi(2))
                            * ((2.0 * n + 1.0) * v).sin()
                    }
                    2 => 2.0 * q.powf((n + 0.5).powi(2)) * ((2.0 * n + 1.0) * v).cos(),
                    3 if n > 0.0 => 2.0 * q.powf(n * n) * (2.0 * n * v).cos(),
                    4 if n > 0.0 => 2.0 * (-1f64).powf(n) * q.powf(n * n) * (2.0 * n * v).cos(),
                    _ => 0.0,
                })
            };
            let (t2, t3) = (theta(2, 0.0), theta(3, 0.0));
            let zeta = t3 / t2 * theta(1, v) / theta(4, v);
            // bottom strip [−1, ζ_a], top [1/√m, −1/√m] through ∞
            (w1, w2, w3, w4) = (-t3 * t3 / (t2 * t2), -1.0, zeta, t3 * t3 / (t2 * t2));
        }
        // χ = 4ℓ/(1 + ℓ)² and 1 − χ = ((1 − ℓ)/(1 + ℓ))², each from its own product.
        let chi = (w3 - w2) * (w4 - w1) / ((w3 - w1) * (w4 - w2));
        let chi_c = (w2 - w1) * (w4 - w3) / ((w3 - w1) * (w4 - w2));
        let root = chi_c.sqrt();
        let ell = chi / (1.0 + root).powi(2);
        let ell_c = 2.0 * root.sqrt() / (1.0 + root);
        let agm = |mut x: f64, mut y: f64| {
            for _ in 0..60 {
                let (xn, yn) = (0.5 * (x + y), (x * y).sqrt());
                x = xn;
                y = yn;
            }
            x
        };
        // K'(ℓ)/K(ℓ) = AGM(1, ℓ') / AGM(1, ℓ).
        let ratio = agm(1.0, ell_c) / agm(1.0, ell);
        0.5 * LAMBDA * ratio / (2.0 * k) - height / k
    }

    #[test]
    fn conformal_maps_agree_and_tend_to_the_half_space() {
        for a in [0.02, 0.1, 0.25, 0.4, 0.48].map(|f| f * LAMBDA) {
            for height in [0.25, 0.5].map(|f| f * LAMBDA) {
                let rotated = isothermal_layer_jump_by_conformal_map(1.0, height, a, true);
                let upright = isothermal_layer_jump_by_conformal_map(1.0, height, a, false);
                assert!(
                    (rotated / upright - 1.0).abs() < 1e-12,
                    "H/λ = {}, a/λ = {}: {rotated:e} vs {upright:e}",
                    height / LAMBDA,
                    a / LAMBDA
                );
            }
            let tall = isothermal_layer_jump_by_conformal_map(1.0, 3.0 * LAMBDA, a, false);
            let r_inf = strip_constriction_resistance(1.0, LAMBDA, a);
            assert!(
                (tall / r_inf - 1.0).abs() < 1e-11,
                "a/λ = {}: {:e}",
                a / LAMBDA,
                tall / r_inf - 1.0
            );
        }
    }

    #[test]
    fn finite_height_matches_the_conformal_map_solution() {
        let mut worst: f64 = 0.0;
        for height in [0.01, 0.02, 0.05, 0.1, 0.25, 0.5, 1.0].map(|f| f * LAMBDA) {
            for a in [0.02, 0.1, 0.25, 0.4, 0.48].map(|f| f * LAMBDA) {
                // One body on a perfect conductor, and two equal-height bodies (series sum).
                let rotated = height < 0.25 * LAMBDA;
                let exact1 = isothermal_layer_jump_by_conformal_map(1.0, height, a, rotated);
                let single =
                    strip_conductance_finite_height(1.0, f64::INFINITY, LAMBDA, a, height, LAMBDA)
                        .unwrap();
                worst = worst.max((1.0 / single / exact1 - 1.0).abs());
                let exact2 =
                    exact1 + isothermal_layer_jump_by_conformal_map(4.0, height, a, rotated);
                let pair =
                    strip_conductance_finite_height(1.0, 4.0, LAMBDA, a, height, height).unwrap();
                worst = worst.max((1.0 / pair / exact2 - 1.0).abs());
            }
        }
        assert!(
            worst < 1e-12,
            "Galerkin vs conformal map: worst relative difference {worst:e}"
        );
    }

    #[test]
    fn finite_height_converges_exponentially_to_the_half_space() {
        let (k1, k2) = (1.0, 2.0);
        for far_face in [FarFace::Isothermal, FarFace::UniformFlux] {
            for a in [0.05, 0.2, 0.4].map(|f| f * LAMBDA) {
                let r_inf = 1.0 / strip_conductance(k1, k2, LAMBDA, a);
                let mut last_error = f64::INFINITY;
                for height in [0.3, 0.5, 0.75, 1.0, 1.5].map(|f| f * LAMBDA) {
                    let upper = StripLayer {
                        conductivity: k1,
                        height,
                        far_face,
                    };
                    let lower = StripLayer {
                        conductivity: k2,
                        height: 2.0 * height,
                        far_face: FarFace::Isothermal,
                    };
                    let r = 1.0 / strip_conductance_layers(&upper, &lower, LAMBDA, a).unwrap();
                    let error = r - r_inf;
                    // isothermal faces conduct better than half-spaces, uniform flux worse
                    match far_face {
                        FarFace::Isothermal => assert!(error < 0.0),
                        FarFace::UniformFlux => assert!(error > 0.0),
                    }
                    assert!(error.abs() < last_error);
                    last_error = error.abs();
                    let estimate = strip_resistance_height_correction(&upper, &lower, LAMBDA, a);
                    let bound =
                        4.0 * (-4.0 * PI * height / LAMBDA).exp() + 1e-13 * r_inf / error.abs();
                    assert!(
                        (error / estimate - 1.0).abs() < bound,
                        "H/λ = {}, a/λ = {}: {error:e} vs {estimate:e}",
                        height / LAMBDA,
                        a / LAMBDA
                    );
                }
                let upper = StripLayer {
                    conductivity: k1,
                    height: 3.0 * LAMBDA,
                    far_face,
                };
                let lower = StripLayer {
                    conductivity: k2,
                    height: 3.0 * LAMBDA,
                    far_face,
                };
                let r = 1.0 / strip_conductance_layers(&upper, &lower, LAMBDA, a).unwrap();
                assert!(
                    (r / r_inf - 1.0).abs() < 1e-14,
                    "H = 3λ, a/λ = {}: {r:e} vs {r_inf:e}",
                    a / LAMBDA
                );
            }
        }
        let half_spaces = StripLayer {
            conductivity: k1,
            height: f64::INFINITY,
            far_face: FarFace::Isothermal,
        };
        let c = strip_conductance_layers(
            &half_spaces,
            &StripLayer {
                conductivity: k2,
                ..half_spaces
            },
            LAMBDA,
            0.2 * LAMBDA,
        )
        .unwrap();
        assert!((c / strip_conductance(k1, k2, LAMBDA, 0.2 * LAMBDA) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn finite_height_is_converged_in_the_fourier_modes_and_symmetric() {
        for (h1, h2, face) in [
            (0.05, 0.3, FarFace::UniformFlux),
            (0.2, 0.02, FarFace::Isothermal),
        ] {
            let upper = StripLayer {
                conductivity: 1.0,
                height: h1 * LAMBDA,
                far_face: face,
            };
            let lower = StripLayer {
                conductivity: 3.0,
                height: h2 * LAMBDA,
                far_face: FarFace::Isothermal,
            };
            for a in [0.03, 0.25, 0.45].map(|f| f * LAMBDA) {
                let c = strip_conductance_layers(&upper, &lower, LAMBDA, a).unwrap();
                let modes = (3.22 / h1.min(h2)).ceil() as usize;
                let doubled = 1.0 / strip_jump_galerkin(&upper, &lower, LAMBDA, a, 2 * modes);
                assert!((c / doubled - 1.0).abs() < 1e-12, "{c} vs {doubled}");
                let swapped = strip_conductance_layers(&lower, &upper, LAMBDA, a).unwrap();
                assert!((c / swapped - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn finite_height_rejects_bad_input() {
        let good = StripLayer {
            conductivity: 1.0,
            height: LAMBDA,
            far_face: FarFace::Isothermal,
        };
        let bad_k = StripLayer {
            conductivity: 0.0,
            ..good
        };
        let bad_h = StripLayer {
            height: -1.0,
            ..good
        };
        let too_thin = StripLayer {
            height: 1e-4 * LAMBDA,
            ..good
        };
        assert!(
            strip_conductance_layers(&bad_k, &good, LAMBDA, 0.2 * LAMBDA)
                .unwrap_err()
                .to_string()
                .contains("upper.conductivity")
        );
        assert!(
            strip_conductance_layers(&good, &bad_h, LAMBDA, 0.2 * LAMBDA)
                .unwrap_err()
                .to_string()
                .contains("lower.height")
        );
        assert!(strip_conductance_layers(&good, &too_thin, LAMBDA, 0.2 * LAMBDA).is_err());
        assert!(
            strip_conductance_layers(&good, &good, LAMBDA, 0.6 * LAMBDA)
                .unwrap_err()
                .to_string()
                .contains("half_width")
        );
        assert_eq!(
            strip_conductance_layers(&good, &good, LAMBDA, 0.5 * LAMBDA).unwrap(),
            f64::INFINITY
        );
        assert_eq!(
            strip_conductance_layers(&good, &good, LAMBDA, 0.0).unwrap(),
            0.0
        );
    }
}
