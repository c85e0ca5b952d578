//! Westergaard's problem: elastic contact of a sinusoid with a flat (spec §10.4).
//!
//! Plane strain, small strain, frictionless, both bodies half-spaces. One
//! surface is `A cos(2πx/λ)`, the other flat (or, equivalently, `A cos(2πx/λ)`
//! is the composite profile of two wavy surfaces). The crests `x = 0 + mλ` touch
//! first; the initial gap is `g0(x) = A (1 − cos 2πx/λ)`. Under the mean
//! pressure `p̄` the contact zone is `|x| < a` in each period, and with
//! `S = sin(πa/λ)` (Westergaard 1939; Johnson, *Contact Mechanics*, 1985, §13.2):
//!
//! - full-contact pressure `p* = π E* A / λ` (flattens the wave: `p = p̄ + p* cos 2πx/λ`);
//! - mean pressure `p̄ = p* S²`, contact fraction `2a/λ`;
//! - pressure `p(x) = 2 p̄ cos(πx/λ) √(S² − sin²(πx/λ)) / S²` in `|x| < a`;
//! - gap `g(x) = 2A [ |s| √(s² − S²) − S² arcosh(|s|/S) ]`, `s = sin(πx/λ)`, in `a ≤ |x| ≤ λ/2`
//!   (derived here from the periodic log kernel, module tests check it by quadrature);
//! - mean gap `ḡ = A (1 − S² + S² ln S²)` (Johnson §13.2: `ḡ = A [1 − (p̄/p*)(1 − ln(p̄/p*))]`);
//! - contact stiffness `−dp̄/dḡ = π E* / (2 λ ln(1/S))` (by differentiating the two above).
//!
//! `1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2`. The surface displacement of the
//! combined half-spaces under a periodic pressure `q(x)` of zero mean is
//! `w(x) = −(2/(π E*)) ∫ q(s) ln|2 sin(π(x − s)/λ)| ds`; the gap is
//! `g = g0 − δ + w` with the approach `δ` fixed by `g(0) = 0`.

use std::f64::consts::PI;

/// `1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2` (Johnson eq. 4.22, plane strain).
///
/// `E = f64::INFINITY` is a rigid body. Panics unless `E > 0` and `−1 < ν ≤ 0.5`,
/// and at least one body is deformable.
#[track_caller]
pub fn effective_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    for (e, nu) in [(e1, nu1), (e2, nu2)] {
        assert!(
            e > 0.0,
            "effective_modulus: Young's modulus must be > 0 (∞ = rigid), got {e}"
        );
        assert!(
            nu > -1.0 && nu <= 0.5,
            "effective_modulus: Poisson ratio must be in (−1, 0.5], got {nu}"
        );
    }
    let compliance = (1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2;
    assert!(compliance > 0.0, "effective_modulus: both bodies are rigid");
    1.0 / compliance
}

#[track_caller]
fn check_wave(e_star: f64, amplitude: f64, wavelength: f64) {
    assert!(
        e_star > 0.0 && e_star.is_finite(),
        "Westergaard: E* must be finite and > 0, got {e_star}"
    );
    assert!(
        amplitude >= 0.0 && amplitude.is_finite(),
        "Westergaard: amplitude must be finite and ≥ 0, got {amplitude}"
    );
    assert!(
        wavelength > 0.0 && wavelength.is_finite(),
        "Westergaard: wavelength must be finite and > 0, got {wavelength}"
    );
}

/// `S = sin(πa/λ)` for `0 ≤ a ≤ λ/2`.
#[track_caller]
fn half_width_sine(wavelength: f64, half_width: f64) -> f64 {
    assert!(
        (0.0..=0.5 * wavelength).contains(&half_width),
        "Westergaard: half-width must be in [0, λ/2] = [0, {}], got {half_width}",
        0.5 * wavelength
    );
    (PI * half_width / wavelength).sin()
}

/// Full-contact pressure `p* = π E* A / λ` (Pa) (Johnson §13.2).
#[track_caller]
pub fn full_contact_pressure(e_star: f64, amplitude: f64, wavelength: f64) -> f64 {
    check_wave(e_star, amplitude, wavelength);
    PI * e_star * amplitude / wavelength
}

/// Mean pressure `p̄ = p* sin²(πa/λ)` (Pa) that holds the contact half-width `a`.
#[track_caller]
pub fn mean_pressure(e_star: f64, amplitude: f64, wavelength: f64, half_width: f64) -> f64 {
    let s = half_width_sine(wavelength, half_width);
    full_contact_pressure(e_star, amplitude, wavelength) * s * s
}

/// Contact half-width `a = (λ/π) arcsin √(p̄/p*)` (m), the inverse of
/// [`mean_pressure`]; `a = λ/2` (full contact) for `p̄ ≥ p*`.
#[track_caller]
pub fn contact_half_width(e_star: f64, amplitude: f64, wavelength: f64, mean_pressure: f64) -> f64 {
    assert!(
        mean_pressure >= 0.0,
        "Westergaard: mean pressure must be ≥ 0, got {mean_pressure}"
    );
    let p_star = full_contact_pressure(e_star, amplitude, wavelength);
    if mean_pressure >= p_star {
        return 0.5 * wavelength;
    }
    wavelength / PI * (mean_pressure / p_star).sqrt().asin()
}

/// Contact fraction `2a/λ = (2/π) arcsin √(p̄/p*)` (1 for `p̄ ≥ p*`).
#[track_caller]
pub fn contact_fraction(e_star: f64, amplitude: f64, wavelength: f64, mean_pressure: f64) -> f64 {
    2.0 * contact_half_width(e_star, amplitude, wavelength, mean_pressure) / wavelength
}

/// Contact pressure `p(x) = 2 p̄ cos(πx/λ) √(S² − sin²(πx/λ)) / S²` (Pa),
/// `S = sin(πa/λ)`, `p̄ = p* S²` (Johnson eq. 13.11); zero outside `|x| < a`,
/// `x` taken modulo `λ` (crest at `x = 0`). At `a = λ/2` it is `p̄ + p* cos(2πx/λ)`.
#[track_caller]
pub fn pressure(e_star: f64, amplitude: f64, wavelength: f64, half_width: f64, x: f64) -> f64 {
    let s = half_width_sine(wavelength, half_width);
    let p_star = full_contact_pressure(e_star, amplitude, wavelength);
    let xr = x - wavelength * (x / wavelength).round();
    if xr.abs() >= half_width {
        return 0.0;
    }
    // S² − sin²(πx/λ) = sin(π(a − |x|)/λ) sin(π(a + |x|)/λ), free of cancellation at the edge.
    let d = (PI * (half_width - xr.abs()) / wavelength).sin()
        * (PI * (half_width + xr.abs()) / wavelength).sin();
    if s == 0.0 || d <= 0.0 {
        return 0.0;
    }
    // 2 p̄ / S² = 2 p*.
    2.0 * p_star * (PI * xr / wavelength).cos() * d.sqrt()
}

/// Gap `g(x)` (m) between the surfaces at contact half-width `a`:
/// `0` in `|x| ≤ a`, `2A [ |s| √(s² − S²) − S² arcosh(|s|/S) ]` outside,
/// `s = sin(πx/λ)`, `S = sin(πa/λ)`; `x` modulo `λ`. At `a = 0`: `g0 = A (1 − cos 2πx/λ)`.
/// Independent of `E*` for given `a`.
#[track_caller]
pub fn gap(amplitude: f64, wavelength: f64, half_width: f64, x: f64) -> f64 {
    check_wave(1.0, amplitude, wavelength);
    let s_a = half_width_sine(wavelength, half_width);
    let xr = x - wavelength * (x / wavelength).round();
    if xr.abs() <= half_width {
        return 0.0;
    }
    let s = (PI * xr / wavelength).sin().abs();
    if s_a == 0.0 {
        return 2.0 * amplitude * s * s;
    }
    let r = s / s_a;
    if r <= 1.0 {
        return 0.0;
    }
    // arcosh r = ln(r + √(r² − 1)), written with √((r−1)(r+1)) for accuracy near the edge.
    let root = ((r - 1.0) * (r + 1.0)).sqrt();
    2.0 * amplitude * (s * s_a * root - s_a * s_a * (r + root).ln()).max(0.0)
}

/// Mean gap `ḡ = A (1 − S² + S² ln S²)` (m), `S = sin(πa/λ)`
/// (Johnson §13.2 with `S² = p̄/p*`); `A` at first touch, `0` at full contact.
#[track_caller]
pub fn mean_gap(amplitude: f64, wavelength: f64, half_width: f64) -> f64 {
    check_wave(1.0, amplitude, wavelength);
    let s2 = half_width_sine(wavelength, half_width).powi(2);
    if s2 == 0.0 {
        return amplitude;
    }
    // 1 − S² = cos²(πa/λ), computed directly for accuracy near full contact.
    let c2 = (PI * half_width / wavelength).cos().powi(2);
    amplitude * (c2 + s2 * (-c2).ln_1p()).max(0.0)
}

/// Approach of the mean planes from first touch, `δ̄ = A − ḡ` (m).
#[track_caller]
pub fn approach(amplitude: f64, wavelength: f64, half_width: f64) -> f64 {
    amplitude - mean_gap(amplitude, wavelength, half_width)
}

/// Incremental contact stiffness per unit area `dp̄/dδ̄ = −dp̄/dḡ = π E* / (2 λ ln(1/S))`
/// (Pa/m), `S = sin(πa/λ)`; `0` at `a = 0`, `∞` at full contact. Independent of `A`.
#[track_caller]
pub fn contact_stiffness(e_star: f64, wavelength: f64, half_width: f64) -> f64 {
    check_wave(e_star, 0.0, wavelength);
    let s = half_width_sine(wavelength, half_width);
    PI * e_star / (2.0 * wavelength * (1.0 / s).ln())
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// Tanh–sinh quadrature of `f` over `[a, b]`, to ~1e−15 relative for
    /// integrands analytic inside with algebraic or logarithmic endpoint
    /// singularities. `f(x, x − a, b − x)` receives the distances to both ends
    /// computed without cancellation.
    pub(in crate::analytical) fn tanh_sinh(
        f: impl Fn(f64, f64, f64) -> f64,
        a: f64,
        b: f64,
    ) -> f64 {
        let r = 0.5 * (b - a);
        let half_pi = 0.5 * PI;
        let t_max = 4.5;
        let mut h = 0.5;
        let mut previous = f64::NAN;
        let eval = |t: f64| -> f64 {
            let u = half_pi * t.sinh();
            let weight = r * half_pi * t.cosh() / u.cosh().powi(2);
            // distance to the near end: r (1 − tanh|u|) = 2r / (e^{2|u|} + 1)
            let near = 2.0 * r / ((2.0 * u.abs()).exp() + 1.0);
            if near == 0.0 || weight == 0.0 {
                return 0.0;
            }
            let far = 2.0 * r - near;
            let (x, da, db) = if u < 0.0 {
                (a + near, near, far)
            } else {
                (b - near, far, near)
            };
            weight * f(x, da, db)
        };
        let mut sum = eval(0.0);
        let mut k = 1;
        while k as f64 * h <= t_max {
            let t = k as f64 * h;
            sum += eval(t) + eval(-t);
            k += 1;
        }
        let mut estimate = sum * h;
        for _level in 0..9 {
            h *= 0.5;
            let mut k = 1;
            while k as f64 * h <= t_max {
                let t = k as f64 * h;
                sum += eval(t) + eval(-t);
                k += 2;
            }
            estimate = sum * h;
            if (estimate - previous).abs() <= 1e-15 * estimate.abs().max(1e-300) {
                break;
            }
            previous = estimate;
        }
        estimate
    }

    /// Gauss–Legendre nodes and weights on `[−1, 1]` (the crate's rule).
    fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
        let g = crate::quadrature::GaussLegendre::new(n);
        (g.points, g.weights)
    }

    /// `n`-point Gauss–Legendre quadrature of `f` over `[from, to]` (either
    /// order) after the grading `x = from + (to − from) u⁶`, which makes a
    /// logarithmic singularity at `from` harmless (error ~ n⁻¹²). Unlike
    /// [`tanh_sinh`] its nodes stay ~1/n² away from `to`, so `f` may be
    /// evaluated at rounded abscissae there.
    pub(in crate::analytical) fn graded_gauss(
        f: impl Fn(f64) -> f64,
        from: f64,
        to: f64,
        n: usize,
    ) -> f64 {
        let (nodes, weights) = gauss_legendre(n);
        let span = to - from;
        nodes
            .iter()
            .zip(&weights)
            .map(|(&t, &w)| {
                let u = 0.5 * (t + 1.0);
                let x = from + span * u.powi(6);
                // A node that rounds onto the singular end carries a negligible weight ~u⁵.
                if x == from {
                    0.0
                } else {
                    0.5 * w * f(x) * 6.0 * span * u.powi(5)
                }
            })
            .sum()
    }

    #[test]
    fn graded_gauss_integrates_a_log_singularity() {
        // ∫_0^1 ln x dx = −1 (singular end first), ∫_2^0 ln(2 − x) dx = 2 − 2 ln 2 reversed.
        assert!((graded_gauss(|x| x.ln(), 0.0, 1.0, 60) + 1.0).abs() < 1e-13);
        let reversed = graded_gauss(|x| (2.0 - x).ln(), 2.0, 0.0, 60);
        assert!(
            (reversed - (2.0 - 2.0 * 2f64.ln())).abs() < 1e-13,
            "{reversed}"
        );
    }

    #[test]
    fn tanh_sinh_integrates_endpoint_singularities() {
        // ∫_0^1 ln x dx = −1; ∫_{−1}^{1} dx/√(1−x²) = π; ∫_0^1 √x dx = 2/3.
        assert!((tanh_sinh(|_, da, _| da.ln(), 0.0, 1.0) + 1.0).abs() < 1e-14);
        assert!((tanh_sinh(|_, da, db| 1.0 / (da * db).sqrt(), -1.0, 1.0) - PI).abs() < 1e-13);
        assert!((tanh_sinh(|x, _, _| x.sqrt(), 0.0, 1.0) - 2.0 / 3.0).abs() < 1e-14);
    }

    const E_STAR: f64 = 1.0e6 / (1.0 - 0.09);
    const A: f64 = 1.0e-6 * std::f64::consts::SQRT_2; // RMS 1 μm
    const LAMBDA: f64 = 1.0e-5;

    fn half_widths() -> Vec<f64> {
        [0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.45, 0.49]
            .iter()
            .map(|f| f * LAMBDA)
            .collect()
    }

    #[test]
    fn effective_modulus_limits_and_symmetry() {
        let (e1, nu1, e2, nu2) = (2.1e11, 0.3, 7.0e10, 0.33);
        let es = effective_modulus(e1, nu1, e2, nu2);
        assert_eq!(es, effective_modulus(e2, nu2, e1, nu1));
        assert!(es < e1 / (1.0 - nu1 * nu1) && es < e2 / (1.0 - nu2 * nu2));
        // Rigid flat: E* = E/(1 − ν²); identical bodies: E/(2(1 − ν²)).
        let rigid = effective_modulus(1.0e6, 0.3, f64::INFINITY, 0.3);
        assert!((rigid - 1.0e6 / 0.91).abs() < 1e-9 * rigid);
        let same = effective_modulus(1.0e6, 0.3, 1.0e6, 0.3);
        assert!((same - 1.0e6 / 1.82).abs() < 1e-9 * same);
    }

    #[test]
    #[should_panic(expected = "both bodies are rigid")]
    fn effective_modulus_rejects_two_rigid_bodies() {
        effective_modulus(f64::INFINITY, 0.3, f64::INFINITY, 0.3);
    }

    #[test]
    fn half_width_round_trips_through_mean_pressure() {
        let p_star = full_contact_pressure(E_STAR, A, LAMBDA);
        assert!((p_star - PI * E_STAR * A / LAMBDA).abs() < 1e-12 * p_star);
        let mut last_fraction = 0.0;
        for a in half_widths() {
            let p = mean_pressure(E_STAR, A, LAMBDA, a);
            let back = contact_half_width(E_STAR, A, LAMBDA, p);
            assert!((back - a).abs() < 1e-12 * LAMBDA, "a = {a}, back = {back}");
            let fraction = contact_fraction(E_STAR, A, LAMBDA, p);
            assert!((fraction - 2.0 * a / LAMBDA).abs() < 1e-12);
            assert!(fraction > last_fraction);
            last_fraction = fraction;
        }
        assert_eq!(contact_half_width(E_STAR, A, LAMBDA, 0.0), 0.0);
        assert_eq!(contact_fraction(E_STAR, A, LAMBDA, p_star), 1.0);
        assert_eq!(contact_fraction(E_STAR, A, LAMBDA, 2.0 * p_star), 1.0);
        assert!((mean_pressure(E_STAR, A, LAMBDA, 0.5 * LAMBDA) - p_star).abs() < 1e-12 * p_star);
    }

    #[test]
    fn pressure_integrates_to_mean_pressure_and_vanishes_at_the_edges() {
        for a in half_widths() {
            let p_bar = mean_pressure(E_STAR, A, LAMBDA, a);
            let force = tanh_sinh(|x, _, _| pressure(E_STAR, A, LAMBDA, a, x), -a, a);
            assert!(
                (force - p_bar * LAMBDA).abs() < 1e-12 * p_bar * LAMBDA,
                "a/λ = {}: {force} vs {}",
                a / LAMBDA,
                p_bar * LAMBDA
            );
            let p0 = pressure(E_STAR, A, LAMBDA, a, 0.0);
            for edge in [-a, a, a * (1.0 + 1e-9), -0.5 * (a + 0.5 * LAMBDA)] {
                assert_eq!(pressure(E_STAR, A, LAMBDA, a, edge), 0.0);
            }
            // square-root edge: p(a − ε) ∝ √ε; symmetric; periodic in λ
            let near = |eps: f64| pressure(E_STAR, A, LAMBDA, a, a - eps * a);
            let ratio = near(1e-6) / near(1e-8);
            assert!(
                (ratio - 10.0).abs() < 1e-3,
                "a/λ = {}: edge ratio {ratio}",
                a / LAMBDA
            );
            for x in [0.3 * a, a * (1.0 - 1e-7)] {
                let p = pressure(E_STAR, A, LAMBDA, a, x);
                assert!(p > 0.0 && p < p0);
                assert_eq!(p, pressure(E_STAR, A, LAMBDA, a, -x));
                assert!((pressure(E_STAR, A, LAMBDA, a, x + 3.0 * LAMBDA) - p).abs() < 1e-6 * p0);
            }
        }
        // full contact: p̄ + p* cos(2πx/λ)
        let p_star = full_contact_pressure(E_STAR, A, LAMBDA);
        for x in [0.0, 0.1, 0.25, 0.37, 0.49].map(|f| f * LAMBDA) {
            let exact = p_star * (1.0 + (2.0 * PI * x / LAMBDA).cos());
            assert!((pressure(E_STAR, A, LAMBDA, 0.5 * LAMBDA, x) - exact).abs() < 1e-12 * p_star);
        }
    }

    /// The gap by quadrature of the periodic log kernel: `g = g0 + w(x) − w(0)`,
    /// `w(x) = −(2/(π E*)) ∫ p(s) ln|2 sin(π(x − s)/λ)| ds`.
    fn gap_by_quadrature(a: f64, x: f64) -> f64 {
        let w = |x: f64| -> f64 {
            let log_kernel = |s: f64, d: f64| {
                pressure(E_STAR, A, LAMBDA, a, s) * (2.0 * (PI * d / LAMBDA).sin().abs()).ln()
            };
            let integral = if x.abs() < a {
                tanh_sinh(|s, _, db| log_kernel(s, db), -a, x)
                    + tanh_sinh(|s, da, _| log_kernel(s, da), x, a)
            } else {
                tanh_sinh(|s, _, _| log_kernel(s, x - s), -a, a)
            };
            -2.0 / (PI * E_STAR) * integral
        };
        A * (1.0 - (2.0 * PI * x / LAMBDA).cos()) + w(x) - w(0.0)
    }

    #[test]
    fn pressure_closes_the_gap_in_contact_and_gap_matches_quadrature_outside() {
        for a in [0.05, 0.2, 0.35, 0.45].map(|f| f * LAMBDA) {
            for f in [0.1, 0.5, 0.9, 0.999] {
                let x = f * a;
                let g = gap_by_quadrature(a, x);
                assert!(
                    g.abs() < 1e-12 * A,
                    "a/λ = {}, x/a = {f}: interior gap {g}",
                    a / LAMBDA
                );
                assert_eq!(gap(A, LAMBDA, a, x), 0.0);
            }
            for f in [0.001, 0.1, 0.5, 0.9, 1.0] {
                let x = a + f * (0.5 * LAMBDA - a);
                let g = gap_by_quadrature(a, x);
                let closed = gap(A, LAMBDA, a, x);
                assert!(
                    (g - closed).abs() < 1e-11 * A,
                    "a/λ = {}, x = {x}: {g} vs {closed}",
                    a / LAMBDA
                );
                assert!(closed > 0.0);
                assert_eq!(closed, gap(A, LAMBDA, a, -x));
            }
        }
        // no contact: the initial gap
        for x in [0.1, 0.3].map(|f| f * LAMBDA) {
            assert!(
                (gap(A, LAMBDA, 0.0, x) - A * (1.0 - (2.0 * PI * x / LAMBDA).cos())).abs()
                    < 1e-15 * A
            );
        }
    }

    #[test]
    fn mean_gap_matches_quadrature_of_the_gap() {
        for a in half_widths() {
            let integral =
                2.0 * tanh_sinh(|x, _, _| gap(A, LAMBDA, a, x), a, 0.5 * LAMBDA) / LAMBDA;
            let closed = mean_gap(A, LAMBDA, a);
            assert!(
                (integral - closed).abs() < 1e-13 * A,
                "a/λ = {}: {integral} vs {closed}",
                a / LAMBDA
            );
            assert!((approach(A, LAMBDA, a) - (A - closed)).abs() < 1e-15 * A);
        }
        assert_eq!(mean_gap(A, LAMBDA, 0.0), A);
        assert!(mean_gap(A, LAMBDA, 0.5 * LAMBDA).abs() < 1e-15 * A);
    }

    #[test]
    fn contact_stiffness_is_the_derivative_of_pressure_with_respect_to_approach() {
        for a in half_widths() {
            // central differences in a, Richardson-extrapolated
            let slope = |h: f64| {
                let dp = mean_pressure(E_STAR, A, LAMBDA, a + h)
                    - mean_pressure(E_STAR, A, LAMBDA, a - h);
                dp / (mean_gap(A, LAMBDA, a - h) - mean_gap(A, LAMBDA, a + h))
            };
            let h = 1e-3 * a.min(0.5 * LAMBDA - a);
            let fd = (4.0 * slope(0.5 * h) - slope(h)) / 3.0;
            let k = contact_stiffness(E_STAR, LAMBDA, a);
            assert!(
                (fd - k).abs() < 1e-9 * k,
                "a/λ = {}: {fd} vs {k}",
                a / LAMBDA
            );
        }
        assert_eq!(contact_stiffness(E_STAR, LAMBDA, 0.0), 0.0);
        assert_eq!(
            contact_stiffness(E_STAR, LAMBDA, 0.5 * LAMBDA),
            f64::INFINITY
        );
    }
}
