//! Size effects of the coupled identification (paper Sect. 2.2.3, (2.15)) and
//! the jump of textured conforming resistive interfaces (Sect. 3.2, (3.5)–(3.7))
//! (spec §10.6–10.7).
//!
//! **Signs.** Heat flows from body 1 (upper, hot) to body 2 (lower), so that in
//! the paper's convention `h̄ < 0` and the macroscopic jump `ϑ̄c(1) > 0` (spec
//! §2). Here `ḡ = |h̄|/k0 ≥ 0` is the magnitude of the temperature gradient in
//! both samples (temperature rising upwards), `ϑc > 0` the microscopic jump
//! from body 2 to body 1, and fluxes enter as magnitudes `|h̄|`. The jumps
//! returned are magnitudes (`ϑ̄c(1)` and `−ϑ̄c(2)`).
//!
//! **The test of Sect. 2.2.3.** Rigid samples of equal height `H0`, constant
//! conductivity `k0`, smooth surfaces with a contact resistance that produces
//! the micro jump `ϑc`. The physical state is fixed: the lower contact surface at
//! `θs`, the upper at `θs + ϑc`. The master designation only changes which of
//! them is the macroscopic contact temperature `θ̄c` imposed in the ABP (2.10)
//! and projected by (2.12):
//!
//! | master | `θ̄c` | `θ_ABP(1)` | `θ_ABP(2)` | `θ(1)` | `θ(2)` |
//! |---|---|---|---|---|---|
//! | body 2 | `θs` | `θ̄c + ḡH0` | `θ̄c − ḡH0` | `θ̄c + ϑc + ḡH0` | `θ̄c − ḡH0` (imposed) |
//! | body 1 | `θs + ϑc` | `θ̄c + ḡH0` | `θ̄c − ḡH0` | `θ̄c + ḡH0` (imposed) | `θ̄c − ϑc − ḡH0` |
//!
//! (the OHP fields are the same in both rows; the OCR of the paper garbles this
//! list, the table is derived from the stated assumptions). The coupled
//! identification (2.14), `ϑ̄c(I) = (θ(I)/θ_ABP(I) − 1) θ̄c` with `I` the slave,
//! then gives (2.15):
//! `ϑ̄c(1) = (1 − ḡH0/(θ̄c + ḡH0)) ϑc ≤ ϑc ≤ −ϑ̄c(2) = (1 + ḡH0/(θ̄c − ḡH0)) ϑc`,
//! where `θ̄c` is the master's contact temperature of the respective row
//! (`θs` on the left, `θs + ϑc` on the right), while the linearized
//! identification (3.4) and the two-phase framework give `±ϑc` for every `H0`.

use crate::sample::case::MasterBody;

#[track_caller]
fn check_sample(theta_c: f64, g_bar: f64, h0: f64) {
    assert!(
        theta_c > 0.0 && theta_c.is_finite(),
        "size effects: θ̄c must be finite and > 0 K, got {theta_c}"
    );
    assert!(
        g_bar >= 0.0 && g_bar.is_finite(),
        "size effects: ḡ = |h̄|/k0 must be finite and ≥ 0 K/m, got {g_bar}"
    );
    assert!(
        h0 >= 0.0 && h0.is_finite(),
        "size effects: H0 must be finite and ≥ 0 m, got {h0}"
    );
}

/// Eq. (2.15), body 1 slave (body 2 master, its contact surface at `θ̄c`):
/// `ϑ̄c(1) = (1 − ḡH0/(θ̄c + ḡH0)) ϑc` (K) (module doc).
#[track_caller]
pub fn coupled_jump_upper_slave(theta_c: f64, g_bar: f64, h0: f64, micro_jump: f64) -> f64 {
    check_sample(theta_c, g_bar, h0);
    let gh = g_bar * h0;
    (1.0 - gh / (theta_c + gh)) * micro_jump
}

/// Eq. (2.15), body 2 slave (body 1 master, its contact surface at `θ̄c`, i.e.
/// the lower surface temperature plus `ϑc`): `−ϑ̄c(2) = (1 + ḡH0/(θ̄c − ḡH0)) ϑc` (K).
/// Panics unless `θ̄c > ḡH0` (the lower ABP face stays above 0 K).
#[track_caller]
pub fn coupled_jump_lower_slave(theta_c: f64, g_bar: f64, h0: f64, micro_jump: f64) -> f64 {
    check_sample(theta_c, g_bar, h0);
    let gh = g_bar * h0;
    assert!(
        theta_c > gh,
        "size effects: θ̄c = {theta_c} K must exceed ḡH0 = {gh} K"
    );
    (1.0 + gh / (theta_c - gh)) * micro_jump
}

/// Temperatures of the test of Sect. 2.2.3 for one master designation (module doc) (K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResistiveSampleTemperatures {
    /// The macroscopic contact temperature `θ̄c` (the master's contact surface).
    pub theta_c: f64,
    /// `θ_ABP(1)`, top face of the upper accompanying bar.
    pub theta_abp_1: f64,
    /// `θ_ABP(2)`, bottom face of the lower accompanying bar.
    pub theta_abp_2: f64,
    /// `θ(1)`, top face of the upper OHP sample.
    pub theta_1: f64,
    /// `θ(2)`, bottom face of the lower OHP sample.
    pub theta_2: f64,
}

/// The ABP and OHP temperatures of Sect. 2.2.3 (module doc) for the lower
/// contact surface at `lower_surface_temperature` (`θs`), the upper at
/// `θs + ϑc`, gradient `ḡ = |h̄|/k0`, equal heights `H0`, and the given master.
#[track_caller]
pub fn resistive_sample_temperatures(
    lower_surface_temperature: f64,
    g_bar: f64,
    h0: f64,
    micro_jump: f64,
    master: MasterBody,
) -> ResistiveSampleTemperatures {
    check_sample(lower_surface_temperature, g_bar, h0);
    let gh = g_bar * h0;
    let upper_surface_temperature = lower_surface_temperature + micro_jump;
    let theta_c = match master {
        MasterBody::Lower => lower_surface_temperature,
        MasterBody::Upper => upper_surface_temperature,
    };
    ResistiveSampleTemperatures {
        theta_c,
        theta_abp_1: theta_c + gh,
        theta_abp_2: theta_c - gh,
        theta_1: upper_surface_temperature + gh,
        theta_2: lower_surface_temperature - gh,
    }
}

/// Jump of a textured, perfectly conforming resistive interface at scale
/// separation, Eq. (3.5): `ϑ̄c = |h̄| / (kθ [pN^α])` (K), with the microscopic
/// conductance `kc = kθ pN^α` and `[pN^α]` from [`mean_pressure_power`].
#[track_caller]
pub fn textured_jump(flux: f64, k_theta: f64, mean_pressure_power: f64) -> f64 {
    assert!(
        k_theta > 0.0,
        "textured_jump: kθ must be > 0, got {k_theta}"
    );
    assert!(
        mean_pressure_power > 0.0,
        "textured_jump: [pN^α] must be > 0 (no contact conducts no heat), got {mean_pressure_power}"
    );
    flux.abs() / (k_theta * mean_pressure_power)
}

/// Jump of a smooth (flat) resistive interface, Eq. (3.6): `ϑc = |h̄| / (kθ p̄N^α)` (K).
/// By (3.7), `textured_jump = (p̄N^α/[pN^α]) flat_jump`.
#[track_caller]
pub fn flat_jump(flux: f64, k_theta: f64, pressure: f64, alpha: f64) -> f64 {
    assert!(pressure > 0.0, "flat_jump: p̄N must be > 0, got {pressure}");
    textured_jump(flux, k_theta, pressure.powf(alpha))
}

/// `[pN^α] = |A|⁻¹ ∫ pN^α dA` over the (reference) rough interface, Eqs. (3.5)–(3.7),
/// by quadrature: `Σ_i w_i pN_i^α` with `w_i = dA_i/|A|` the quadrature weights
/// of the rough surface divided by the projected (macroscopic) area `|A|`, so
/// `Σ w_i` is the area ratio (≥ 1 for a texture). Points out of contact
/// (`pN ≤ 0`) carry no heat and contribute nothing, for every `α` (at `α = 0`
/// the result is the real contact area fraction). Panics on mismatched lengths,
/// negative weights or non-finite pressures.
#[track_caller]
pub fn mean_pressure_power(pressures: &[f64], weights: &[f64], alpha: f64) -> f64 {
    assert_eq!(
        pressures.len(),
        weights.len(),
        "mean_pressure_power: {} pressures but {} weights",
        pressures.len(),
        weights.len()
    );
    assert!(
        alpha.is_finite() && alpha >= 0.0,
        "mean_pressure_power: α must be finite and ≥ 0, got {alpha}"
    );
    pressures
        .iter()
        .zip(weights)
        .map(|(&p, &w)| {
            assert!(
                p.is_finite(),
                "mean_pressure_power: pressure {p} is not finite"
            );
            assert!(w >= 0.0, "mean_pressure_power: weight {w} is negative");
            if p > 0.0 { w * p.powf(alpha) } else { 0.0 }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytical::westergaard;
    use std::f64::consts::PI;

    /// (2.14): `ϑ̄c(I) = (θ(I)/θ_ABP(I) − 1) θ̄c`.
    fn coupled_identification(theta: f64, theta_abp: f64, theta_c: f64) -> f64 {
        (theta / theta_abp - 1.0) * theta_c
    }

    fn samples() -> Vec<(f64, f64, f64, f64)> {
        // (θs, ḡ, H0, ϑc): Table I / Fig. 13 (θ0, |h̄0| = 1 W/mm², k0 = 1, micro jump 10 K) and others
        let mut out = Vec::new();
        for theta_s in [293.15, 350.0, 80.0] {
            for g_bar in [1.0e4, 1.0e6] {
                for h0 in [1.0e-6, 1.0e-5, 3.0e-5] {
                    for jump in [0.1, 10.0] {
                        out.push((theta_s, g_bar, h0, jump));
                    }
                }
            }
        }
        out
    }

    #[test]
    fn coupled_jumps_follow_from_eq_2_14() {
        for (theta_s, g_bar, h0, jump) in samples() {
            let lower = resistive_sample_temperatures(theta_s, g_bar, h0, jump, MasterBody::Lower);
            let upper = resistive_sample_temperatures(theta_s, g_bar, h0, jump, MasterBody::Upper);
            // same physical OHP fields, different ABP
            assert_eq!(
                (lower.theta_1, lower.theta_2),
                (upper.theta_1, upper.theta_2)
            );
            assert!((upper.theta_c - lower.theta_c - jump).abs() < 1e-12 * theta_s);
            let from_2_14 = coupled_identification(lower.theta_1, lower.theta_abp_1, lower.theta_c);
            let eq_2_15 = coupled_jump_upper_slave(lower.theta_c, g_bar, h0, jump);
            assert!(
                (from_2_14 / eq_2_15 - 1.0).abs() < 1e-12,
                "{from_2_14} vs {eq_2_15}"
            );
            let from_2_14 = coupled_identification(upper.theta_2, upper.theta_abp_2, upper.theta_c);
            assert!(from_2_14 < 0.0, "body 2 as slave gives a negative jump");
            let eq_2_15 = coupled_jump_lower_slave(upper.theta_c, g_bar, h0, jump);
            assert!(
                (-from_2_14 / eq_2_15 - 1.0).abs() < 1e-12,
                "{from_2_14} vs {eq_2_15}"
            );
        }
    }

    #[test]
    fn bounds_of_eq_2_15_hold_and_close_as_the_height_vanishes() {
        for (theta_s, g_bar, h0, jump) in samples() {
            let left = coupled_jump_upper_slave(theta_s, g_bar, h0, jump);
            let right = coupled_jump_lower_slave(theta_s + jump, g_bar, h0, jump);
            assert!(left < jump && jump < right);
            // the deviation grows with H0 and vanishes with it
            assert!(coupled_jump_upper_slave(theta_s, g_bar, 2.0 * h0, jump) < left);
            assert!(coupled_jump_lower_slave(theta_s + jump, g_bar, 2.0 * h0, jump) > right);
            assert_eq!(coupled_jump_upper_slave(theta_s, g_bar, 0.0, jump), jump);
            assert_eq!(
                coupled_jump_lower_slave(theta_s + jump, g_bar, 0.0, jump),
                jump
            );
        }
        // Fig. 13a setting: θ̄c = 293.15 K, ḡ = 1e6 K/m, H0 = 10 μm, ϑc = 10 K → 9.67 K and 10.34 K.
        let left = coupled_jump_upper_slave(293.15, 1.0e6, 1.0e-5, 10.0);
        let right = coupled_jump_lower_slave(303.15, 1.0e6, 1.0e-5, 10.0);
        assert!((left - 10.0 * 293.15 / 303.15).abs() < 1e-12);
        assert!((right - 10.0 * 303.15 / 293.15).abs() < 1e-12);
    }

    /// The linearized identification (3.4), `θ(I) − θ_ABP(I)`, recovers `±ϑc`
    /// for both designations and every height (the expected response, Sect. 3.1).
    #[test]
    fn linearized_identification_recovers_the_micro_jump() {
        for (theta_s, g_bar, h0, jump) in samples() {
            let lower = resistive_sample_temperatures(theta_s, g_bar, h0, jump, MasterBody::Lower);
            let upper = resistive_sample_temperatures(theta_s, g_bar, h0, jump, MasterBody::Upper);
            assert!((lower.theta_1 - lower.theta_abp_1 - jump).abs() < 1e-12 * theta_s);
            assert!((upper.theta_2 - upper.theta_abp_2 + jump).abs() < 1e-12 * theta_s);
            // 1D consistency: the OHP drop is the bulk drop 2ḡH0 plus the micro jump
            assert!(
                (lower.theta_1 - lower.theta_2 - (2.0 * g_bar * h0 + jump)).abs() < 1e-12 * theta_s
            );
        }
    }

    #[test]
    fn textured_jump_matches_eq_3_7() {
        // Fig. 3: facets inclined at β carry p̄N; their area per projected area is 1/cos β.
        let (flux, k_theta, p_bar) = (1.0e6, 10.0, 2.0e5);
        for alpha in [0.0, 0.5, 1.0, 2.0] {
            for beta in [0.0, 0.3, 0.7] {
                let facets = 16;
                let pressures = vec![p_bar; facets];
                let weights = vec![1.0 / (facets as f64 * f64::cos(beta)); facets];
                let mean = mean_pressure_power(&pressures, &weights, alpha);
                let textured = textured_jump(-flux, k_theta, mean);
                let flat = flat_jump(flux, k_theta, p_bar, alpha);
                assert!((textured / (p_bar.powf(alpha) / mean * flat) - 1.0).abs() < 1e-14);
                assert!((textured / flat - f64::cos(beta)).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn mean_pressure_power_is_a_surface_average() {
        // p = p̄ (1 + ½ cos 2πx/λ) on a flat: [p] = p̄, [p²] = (1 + 1/8) p̄² (trapezoid rule, exact for trigonometric polynomials)
        let (p_bar, n) = (3.0, 64);
        let pressures: Vec<f64> = (0..n)
            .map(|i| p_bar * (1.0 + 0.5 * (2.0 * PI * i as f64 / n as f64).cos()))
            .collect();
        let weights = vec![1.0 / n as f64; n];
        assert!((mean_pressure_power(&pressures, &weights, 1.0) / p_bar - 1.0).abs() < 1e-14);
        assert!(
            (mean_pressure_power(&pressures, &weights, 2.0) / (1.125 * p_bar * p_bar) - 1.0).abs()
                < 1e-14
        );
        // α = 0 gives the real contact fraction of Westergaard's pressure, 2a/λ (to the grid spacing)
        let (e_star, amp, lambda, a) = (1.0e6, 1.0e-6, 1.0e-5, 0.3e-5);
        let n = 10_000;
        let pressures: Vec<f64> = (0..n)
            .map(|i| {
                westergaard::pressure(e_star, amp, lambda, a, (i as f64 + 0.5) / n as f64 * lambda)
            })
            .collect();
        let weights = vec![1.0 / n as f64; n];
        let fraction = mean_pressure_power(&pressures, &weights, 0.0);
        assert!(
            (fraction - 2.0 * a / lambda).abs() <= 2.0 / n as f64,
            "{fraction}"
        );
        // the first power is the mean pressure (midpoint rule on a function with √ edges)
        let p_mean = mean_pressure_power(&pressures, &weights, 1.0);
        let exact = westergaard::mean_pressure(e_star, amp, lambda, a);
        assert!((p_mean / exact - 1.0).abs() < 1e-5, "{p_mean} vs {exact}");
    }

    #[test]
    #[should_panic(expected = "3 pressures but 2 weights")]
    fn mean_pressure_power_rejects_mismatched_lengths() {
        mean_pressure_power(&[1.0, 2.0, 3.0], &[0.5, 0.5], 1.0);
    }
}
