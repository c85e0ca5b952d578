//! Contact of the egg-box sinusoid `f = Δ cos(2πx/λ) cos(2πy/λ)` with a flat
//! (3D, frictionless, linear elastic half-spaces; Johnson, Greenwood and
//! Higginson 1985): the full-contact pressure and the two asymptotes of the
//! contact area between which no closed form exists. `E*` is the composite
//! modulus `1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2`; in the case files
//! `Δ = 2·rms` (`pattern = "egg-box"`).
//!
//! - **Full contact**: the surface is a single Fourier mode of wave number
//!   `|k| = 2√2 π/λ`, which a half-space flattens under the pressure
//!   amplitude `E* |k| Δ/2`, so `p* = √2 π E* Δ/λ`; the full-contact
//!   pressure `p̄ + p* cos cos` is non-negative for `p̄ ≥ p*`.
//! - **Low pressure (Hertz)**: each of the two peaks per `λ × λ` cell (at
//!   `cos cos = +1`) is a sphere of radius `R = λ²/(4π² Δ)` carrying the
//!   force `P = p̄ λ²/2`: `a³ = 3PR/(4E*)`, contact fraction `2πa²/λ² =
//!   2π (3√2/(32π))^(2/3) (p̄/p*)^(2/3) ≈ 0.762 (p̄/p*)^(2/3)`.
//! - **Near full contact**: the two gaps per cell (at the valleys, `cos cos
//!   = −1`) are penny-shaped cracks under the tension the full-contact
//!   pressure would need there, `p* − p̄ − p* k² r²/2` (`k = 2π/λ`); they
//!   close smoothly (zero stress intensity, `∫₀ᵇ r σ(r)/√(b² − r²) dr = 0`)
//!   at `b² = 3 (1 − p̄/p*)/k²`, so the non-contact fraction is `2πb²/λ² =
//!   (3/(2π)) (1 − p̄/p*)`.

use std::f64::consts::PI;

#[track_caller]
fn check(e_star: f64, amplitude: f64, wavelength: f64) {
    assert!(
        e_star > 0.0 && amplitude > 0.0 && wavelength > 0.0,
        "egg box: E*, Δ and λ must be > 0, got {e_star}, {amplitude}, {wavelength}"
    );
}

/// Full-contact pressure `p* = √2 π E* Δ/λ` (Pa).
#[track_caller]
pub fn full_contact_pressure(e_star: f64, amplitude: f64, wavelength: f64) -> f64 {
    check(e_star, amplitude, wavelength);
    2f64.sqrt() * PI * e_star * amplitude / wavelength
}

/// Radius of curvature `R = λ²/(4π² Δ)` (m) of the egg box at its peaks.
#[track_caller]
pub fn peak_radius(amplitude: f64, wavelength: f64) -> f64 {
    check(1.0, amplitude, wavelength);
    wavelength * wavelength / (4.0 * PI * PI * amplitude)
}

/// Contact fraction of the low-pressure (Hertz) asymptote: two spheres of
/// radius [`peak_radius`] per cell, each pressed by `p̄ λ²/2`.
#[track_caller]
pub fn hertz_contact_fraction(e_star: f64, amplitude: f64, wavelength: f64, pressure: f64) -> f64 {
    check(e_star, amplitude, wavelength);
    let force = 0.5 * pressure * wavelength * wavelength;
    let a = (3.0 * force * peak_radius(amplitude, wavelength) / (4.0 * e_star)).cbrt();
    2.0 * PI * a * a / (wavelength * wavelength)
}

/// Non-contact fraction `(3/(2π)) (1 − p̄/p*)` of the near-full-contact
/// asymptote (two penny-shaped gaps per cell), for `p̄ ≤ p*`.
pub fn near_full_gap_fraction(pressure_ratio: f64) -> f64 {
    3.0 / (2.0 * PI) * (1.0 - pressure_ratio).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hertz_asymptote_in_units_of_the_full_contact_pressure() {
        let (e, d, l) = (5.5e5, 2e-8, 1e-5);
        let ps = full_contact_pressure(e, d, l);
        let c = 2.0 * PI * (3.0 * 2f64.sqrt() / (32.0 * PI)).powf(2.0 / 3.0);
        for r in [1e-3, 0.02, 0.1] {
            let f = hertz_contact_fraction(e, d, l, r * ps);
            assert!(
                (f / (c * r.powf(2.0 / 3.0)) - 1.0).abs() < 1e-12,
                "{r}: {f}"
            );
        }
        assert!((c - 0.7617).abs() < 1e-3, "{c}");
    }

    #[test]
    fn full_contact_pressure_is_the_single_mode_response() {
        // A half-space loaded by p cos(k·x) displaces by 2p/(E*|k|).
        let (e, d, l) = (1e6, 1e-7, 1e-5);
        let k = 2f64.sqrt() * 2.0 * PI / l;
        let ps = full_contact_pressure(e, d, l);
        assert!((2.0 * ps / (e * k) / d - 1.0).abs() < 1e-12);
        // The peaks' curvature: −∂²f/∂x² = Δ (2π/λ)² = 1/R.
        let r = peak_radius(d, l);
        assert!((r * d * (2.0 * PI / l).powi(2) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn penny_gaps_close_with_zero_stress_intensity() {
        // ∫₀ᵇ r (A + B r²)/√(b² − r²) dr = A b + (2/3) B b³ = 0 at the
        // asymptote's b, with A = p* − p̄ and B = −p* k²/2 (numerically).
        let (ps, ratio, l) = (1.0, 0.9, 1.0);
        let k = 2.0 * PI / l;
        let b2 = 3.0 * (1.0 - ratio) / (k * k);
        let b = b2.sqrt();
        let (a_coef, b_coef) = (ps * (1.0 - ratio), -ps * k * k / 2.0);
        // r = b sin t: ∫₀^{π/2} b sin t (A + B b² sin² t) dt.
        let n = 20000;
        let mut s = 0.0;
        for i in 0..n {
            let t = (i as f64 + 0.5) * (PI / 2.0) / n as f64;
            s += b * t.sin() * (a_coef + b_coef * b2 * t.sin().powi(2)) * (PI / 2.0) / n as f64;
        }
        assert!(s.abs() < 1e-9 * a_coef * b, "{s}");
        let f = near_full_gap_fraction(ratio);
        assert!((f - 2.0 * PI * b2 / (l * l)).abs() < 1e-12);
    }
}
