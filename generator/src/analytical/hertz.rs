//! Hertz contact and its interface heat flux in the constraint limit:
//! plane-strain cylinders (spec §10.3; paper Sect. 5.1, (5.2)–(5.3)) and the
//! axisymmetric sphere on a flat (issue 12; the 3D counterpart of (5.2)–(5.3)).
//!
//! Mechanics (Johnson, *Contact Mechanics*, 1985, §4.2–4.3 and §5.6): radii
//! `R1`, `R2`, small strain, frictionless; `R = R1 R2/(R1 + R2)`,
//! `1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2`
//! ([`westergaard::effective_modulus`](super::westergaard::effective_modulus)).
//!
//! Cylinders with parallel axes, pressed by the force `F` per unit length (N/m):
//!
//! - half-width `a = √(4 F R/(π E*))`;
//! - pressure `p(x) = (2F/(π a²)) √(a² − x²)`, peak `p0 = 2F/(π a) = √(F E*/(π R))`.
//!
//! The approach of two cylinders in plane strain depends logarithmically on the
//! body size (a 2D half-plane has no finite displacement under a net load), so
//! it is not given here: the spec's Hertz test is displacement-controlled and
//! compares the pressure and flux distributions.
//!
//! Spheres (or a sphere on a flat, `R2 = ∞`), pressed by the force `F` (N),
//! the gap `r²/(2R)` (a paraboloid, Hertz's assumption):
//!
//! - contact radius `a = (3 F R/(4 E*))^(1/3)`;
//! - pressure `p(r) = p0 √(1 − r²/a²)`, `p0 = 3F/(2π a²) = 2 a E*/(π R)`.
//!
//! Thermal, constraint model (`kθ → ∞`: perfect thermal contact on the contact
//! zone, no heat across the gap): the interface flux is that of an isothermal
//! strip (2D) or disc (3D) on a half-space, `r` the distance to the centre:
//!
//! - strip (Comninou, Dundurs & Barber, *Planar Hertz contact with heat
//!   conduction*, J. Appl. Mech. 48, 1981, 549–554; paper (5.2)–(5.3)):
//!   `h0(r) = h0_min / √(1 − (r/a)²)`, `h0_min = Q/(π a)`, `Q` the total heat
//!   flow per unit length (W/m);
//! - disc (the isothermal spot of Carslaw & Jaeger, *Conduction of Heat in
//!   Solids*, 1959, §8.2): `h0(r) = Q/(2π a √(a² − r²)) = h0_min/√(1 − (r/a)²)`,
//!   `h0_min = Q/(2π a²)`, `Q` the heat flow (W); the heat flow through the
//!   disc of radius `r` is `Q(r) = Q (1 − √(1 − r²/a²))`, and the spot's
//!   constriction resistance on one half-space is `1/(4 k a)`.

/// Reduced radius `R = R1 R2/(R1 + R2)` (m); `f64::INFINITY` for a flat. Panics
/// unless both radii are `> 0` and not both infinite.
#[track_caller]
pub fn reduced_radius(r1: f64, r2: f64) -> f64 {
    assert!(
        r1 > 0.0 && r2 > 0.0,
        "hertz::reduced_radius: radii must be > 0 (∞ = flat), got {r1}, {r2}"
    );
    let curvature = 1.0 / r1 + 1.0 / r2;
    assert!(
        curvature > 0.0,
        "hertz::reduced_radius: two flats have no Hertz contact"
    );
    1.0 / curvature
}

/// `√(1 − (r/a)²)` for `|r| < a` (without cancellation near the edge),
/// `None` outside.
fn root(a: f64, r: f64) -> Option<f64> {
    (r.abs() < a).then(|| ((a - r.abs()) * (a + r.abs())).sqrt() / a)
}

#[track_caller]
fn check_positive(name: &str, value: f64) {
    assert!(
        value > 0.0 && value.is_finite(),
        "hertz: {name} must be finite and > 0, got {value}"
    );
}

/// Contact half-width `a = √(4 F R/(π E*))` (m) for the force `F` per unit length (N/m).
#[track_caller]
pub fn contact_half_width(force_per_length: f64, reduced_radius: f64, e_star: f64) -> f64 {
    assert!(
        force_per_length >= 0.0,
        "hertz: force per length must be ≥ 0, got {force_per_length}"
    );
    check_positive("reduced radius", reduced_radius);
    check_positive("E*", e_star);
    (4.0 * force_per_length * reduced_radius / (std::f64::consts::PI * e_star)).sqrt()
}

/// Force per unit length `F = π E* a²/(4R)` (N/m) that opens the half-width `a`
/// (the inverse of [`contact_half_width`]).
#[track_caller]
pub fn force_per_length(half_width: f64, reduced_radius: f64, e_star: f64) -> f64 {
    assert!(
        half_width >= 0.0,
        "hertz: half-width must be ≥ 0, got {half_width}"
    );
    check_positive("reduced radius", reduced_radius);
    check_positive("E*", e_star);
    std::f64::consts::PI * e_star * half_width * half_width / (4.0 * reduced_radius)
}

/// Peak pressure `p0 = 2F/(π a)` (Pa).
#[track_caller]
pub fn peak_pressure(force_per_length: f64, half_width: f64) -> f64 {
    check_positive("half-width", half_width);
    2.0 * force_per_length / (std::f64::consts::PI * half_width)
}

/// Pressure `p(x) = (2F/(π a²)) √(a² − x²)` (Pa) in `|x| < a`, 0 outside.
#[track_caller]
pub fn pressure(force_per_length: f64, half_width: f64, x: f64) -> f64 {
    check_positive("half-width", half_width);
    root(half_width, x).map_or(0.0, |s| {
        2.0 * force_per_length / (std::f64::consts::PI * half_width) * s
    })
}

/// Minimum interface flux `h0_min = Q/(π a)` (W/m²), Eq. (5.3), `Q` the total
/// heat flow per unit length (W/m) (its sign is kept).
#[track_caller]
pub fn constraint_limit_min_flux(total_flux: f64, half_width: f64) -> f64 {
    check_positive("half-width", half_width);
    total_flux / (std::f64::consts::PI * half_width)
}

/// Interface flux in the constraint limit, `h0(r) = h0_min / √(1 − (r/a)²)`
/// (W/m²), Eq. (5.2), for `|r| < a`; 0 outside (integrable singularity at `|r| = a`).
#[track_caller]
pub fn constraint_limit_flux(total_flux: f64, half_width: f64, r: f64) -> f64 {
    let h_min = constraint_limit_min_flux(total_flux, half_width);
    root(half_width, r).map_or(0.0, |s| h_min / s)
}

/// Contact radius of spheres `a = (3 F R/(4 E*))^(1/3)` (m) for the force `F` (N).
#[track_caller]
pub fn sphere_contact_radius(force: f64, reduced_radius: f64, e_star: f64) -> f64 {
    assert!(force >= 0.0, "hertz: force must be ≥ 0, got {force}");
    check_positive("reduced radius", reduced_radius);
    check_positive("E*", e_star);
    (3.0 * force * reduced_radius / (4.0 * e_star)).cbrt()
}

/// Force `F = 4 E* a³/(3R)` (N) that opens the contact radius `a` of spheres
/// (the inverse of [`sphere_contact_radius`]).
#[track_caller]
pub fn sphere_force(contact_radius: f64, reduced_radius: f64, e_star: f64) -> f64 {
    assert!(
        contact_radius >= 0.0,
        "hertz: contact radius must be ≥ 0, got {contact_radius}"
    );
    check_positive("reduced radius", reduced_radius);
    check_positive("E*", e_star);
    4.0 * e_star * contact_radius.powi(3) / (3.0 * reduced_radius)
}

/// Peak pressure of spheres `p0 = 3F/(2π a²)` (Pa).
#[track_caller]
pub fn sphere_peak_pressure(force: f64, contact_radius: f64) -> f64 {
    check_positive("contact radius", contact_radius);
    3.0 * force / (2.0 * std::f64::consts::PI * contact_radius * contact_radius)
}

/// Pressure of spheres `p(r) = p0 √(1 − r²/a²)` (Pa) in `r < a`, 0 outside.
#[track_caller]
pub fn sphere_pressure(force: f64, contact_radius: f64, r: f64) -> f64 {
    let p0 = sphere_peak_pressure(force, contact_radius);
    root(contact_radius, r).map_or(0.0, |s| p0 * s)
}

/// Fraction of the force of spheres carried inside the radius `r`,
/// `F(r)/F = 1 − (1 − r²/a²)^(3/2)` (1 for `r ≥ a`).
#[track_caller]
pub fn sphere_force_fraction(contact_radius: f64, r: f64) -> f64 {
    check_positive("contact radius", contact_radius);
    root(contact_radius, r).map_or(1.0, |s| 1.0 - s.powi(3))
}

/// Minimum flux of the isothermal disc `h0_min = Q/(2π a²)` (W/m²), the 3D
/// counterpart of (5.3), `Q` the heat flow (W) (its sign is kept).
#[track_caller]
pub fn spot_min_flux(heat_flow: f64, contact_radius: f64) -> f64 {
    check_positive("contact radius", contact_radius);
    heat_flow / (2.0 * std::f64::consts::PI * contact_radius * contact_radius)
}

/// Flux of the isothermal disc `h0(r) = Q/(2π a √(a² − r²))` (W/m²), the 3D
/// counterpart of (5.2), for `r < a`; 0 outside (integrable at `r = a`).
#[track_caller]
pub fn spot_flux(heat_flow: f64, contact_radius: f64, r: f64) -> f64 {
    let h_min = spot_min_flux(heat_flow, contact_radius);
    root(contact_radius, r).map_or(0.0, |s| h_min / s)
}

/// Fraction of the isothermal disc's heat flow through the disc of radius
/// `r`, `Q(r)/Q = 1 − √(1 − r²/a²)` (1 for `r ≥ a`).
#[track_caller]
pub fn spot_heat_flow_fraction(contact_radius: f64, r: f64) -> f64 {
    check_positive("contact radius", contact_radius);
    root(contact_radius, r).map_or(1.0, |s| 1.0 - s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytical::westergaard::{
        effective_modulus,
        tests::{graded_gauss, tanh_sinh},
    };
    use std::f64::consts::PI;

    const A: f64 = 2.0e-6;

    /// `∫_{−a}^{a} f(x) dx` with `x = a sin ψ` (removes the edge square roots).
    fn over_contact(f: impl Fn(f64) -> f64) -> f64 {
        let g = |psi: f64| f(A * psi.sin()) * A * psi.cos();
        graded_gauss(g, 0.0, 0.5 * PI, 40) - graded_gauss(g, 0.0, -0.5 * PI, 40)
    }

    /// `∫_{−a}^{a} f(s) ln|x − s| ds`, `|x| < a`, graded at the log singularity.
    fn log_potential(f: impl Fn(f64) -> f64, x: f64) -> f64 {
        let psi_x = (x / A).asin();
        let g = |psi: f64| {
            let s = A * psi.sin();
            if s == x {
                0.0
            } else {
                f(s) * A * psi.cos() * (x - s).abs().ln()
            }
        };
        graded_gauss(g, psi_x, 0.5 * PI, 80) - graded_gauss(g, psi_x, -0.5 * PI, 80)
    }

    #[test]
    fn half_width_and_force_round_trip() {
        let r = reduced_radius(1.0e-4, 3.0e-4);
        assert!((r - 0.75e-4).abs() < 1e-18);
        assert_eq!(r, reduced_radius(3.0e-4, 1.0e-4));
        assert_eq!(reduced_radius(1.0e-4, f64::INFINITY), 1.0e-4);
        let e_star = effective_modulus(1.0e6, 0.3, 1.0e6, 0.3);
        for force in [1e-3, 0.1, 10.0] {
            let a = contact_half_width(force, r, e_star);
            assert!((force_per_length(a, r, e_star) / force - 1.0).abs() < 1e-14);
            let p0 = peak_pressure(force, a);
            assert!((p0 / (force * e_star / (PI * r)).sqrt() - 1.0).abs() < 1e-14);
            assert!((pressure(force, a, 0.0) / p0 - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn pressure_carries_the_force_and_vanishes_at_the_edges() {
        let force = 0.37;
        let total = over_contact(|x| pressure(force, A, x));
        assert!((total / force - 1.0).abs() < 1e-14, "{total}");
        for x in [-A, A, 1.5 * A] {
            assert_eq!(pressure(force, A, x), 0.0);
        }
        assert_eq!(pressure(force, A, 0.3 * A), pressure(force, A, -0.3 * A));
    }

    /// The pressure indents the combined half-planes by `w(x) = −(2/(π E*)) ∫ p(s) ln|x − s| ds`;
    /// inside the contact `w(0) − w(x) = x²/(2R)` (the profile is filled exactly).
    #[test]
    fn pressure_fills_the_parabolic_profile() {
        let e_star = effective_modulus(1.0e6, 0.3, 2.0e6, 0.25);
        let r = 5.0e-5;
        let force = force_per_length(A, r, e_star);
        let w = |x: f64| -2.0 / (PI * e_star) * log_potential(|s| pressure(force, A, s), x);
        let w0 = w(0.0);
        for f in [0.2, 0.5, 0.8, 0.97] {
            let x = f * A;
            let filled = w0 - w(x);
            let profile = x * x / (2.0 * r);
            assert!(
                (filled - profile).abs() < 1e-12 * A * A / (2.0 * r),
                "x/a = {f}: {filled:e} vs {profile:e}"
            );
        }
    }

    #[test]
    fn constraint_flux_carries_q_and_is_minimal_at_the_centre() {
        let q = 3.2e-2;
        let total = over_contact(|x| constraint_limit_flux(q, A, x));
        assert!((total / q - 1.0).abs() < 1e-13, "{total}");
        let h_min = constraint_limit_min_flux(q, A);
        assert!((constraint_limit_flux(q, A, 0.0) / h_min - 1.0).abs() < 1e-15);
        for f in [0.1, 0.5, 0.9, 0.999] {
            let h = constraint_limit_flux(q, A, f * A);
            assert!(h > h_min);
            assert_eq!(h, constraint_limit_flux(q, A, -f * A));
            assert!((h / h_min - 1.0 / (1.0 - f * f).sqrt()).abs() < 1e-12 * h / h_min);
        }
        assert_eq!(constraint_limit_flux(q, A, A), 0.0);
        assert_eq!(constraint_limit_flux(q, A, -2.0 * A), 0.0);
    }

    /// On a half-plane of conductivity `k` the surface temperature under the flux
    /// `h0` is `T(x) = −(1/(π k)) ∫ h0(s) ln|x − s| ds` (+ const): the constraint
    /// flux makes the whole contact zone isothermal, `T = −Q ln(a/2)/(π k)`
    /// (`∫ ln|x − s| ds/√(a² − s²) = π ln(a/2)`), as perfect thermal contact requires.
    #[test]
    fn constraint_flux_makes_the_contact_isothermal() {
        let (q, k) = (1.5, 2.0);
        let expected = -q * (0.5 * A).ln() / (PI * k);
        for f in [0.0, 0.3, 0.6, 0.9, 0.99] {
            let t = -log_potential(|s| constraint_limit_flux(q, A, s), f * A) / (PI * k);
            assert!(
                (t / expected - 1.0).abs() < 1e-12,
                "x/a = {f}: {t} vs {expected}"
            );
        }
    }

    /// `∫∫_disc f dA/ρ` seen from `(x, 0)`, `|x| < A`, in polar coordinates
    /// about the point (the `1/ρ` removed): `inner(φ, ρmax, ρ₋)` integrates
    /// `f` along the ray `φ` to the circle at `ρmax`, where `A² − |s|² =
    /// (ρmax − ρ)(ρ + ρ₋)`; the smooth periodic outer integral by the
    /// trapezoidal rule.
    fn disc_potential(inner: impl Fn(f64, f64, f64) -> f64, x: f64) -> f64 {
        let n = 256;
        (0..n)
            .map(|k| {
                let phi = 2.0 * PI * k as f64 / n as f64;
                let root = (A * A - x * x * phi.sin().powi(2)).sqrt();
                inner(phi, root - x * phi.cos(), root + x * phi.cos())
            })
            .sum::<f64>()
            * 2.0
            * PI
            / n as f64
    }

    /// `∫_0^r 2π s f(s) ds` with `s = r sin ψ` (the edge square roots of
    /// `f` at `r = A` removed), 80-point Gauss–Legendre in `ψ`.
    fn over_disc(f: impl Fn(f64) -> f64, r: f64) -> f64 {
        let g = crate::quadrature::GaussLegendre::new(80);
        let half = 0.25 * PI;
        g.points
            .iter()
            .zip(&g.weights)
            .map(|(&t, &w)| {
                let psi = half * (t + 1.0);
                w * half * 2.0 * PI * r * psi.sin() * f(r * psi.sin()) * r * psi.cos()
            })
            .sum()
    }

    #[test]
    fn sphere_radius_and_force_round_trip() {
        let r = reduced_radius(1.0e-5, f64::INFINITY);
        let e_star = effective_modulus(1.0e6, 0.3, 1.0e6, 0.3);
        for force in [1e-9, 1e-6, 1e-3] {
            let a = sphere_contact_radius(force, r, e_star);
            assert!((sphere_force(a, r, e_star) / force - 1.0).abs() < 1e-14);
            let p0 = sphere_peak_pressure(force, a);
            assert!((p0 / (2.0 * a * e_star / (PI * r)) - 1.0).abs() < 1e-14);
            assert!((sphere_pressure(force, a, 0.0) / p0 - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn sphere_pressure_carries_the_force() {
        let force = 2.5e-4;
        let total = over_disc(|r| sphere_pressure(force, A, r), A);
        assert!((total / force - 1.0).abs() < 1e-13, "{total}");
        for r in [A, 1.5 * A] {
            assert_eq!(sphere_pressure(force, A, r), 0.0);
            assert_eq!(sphere_force_fraction(A, r), 1.0);
        }
        for f in [0.1, 0.5, 0.8, 0.999] {
            let rr = f * A;
            let partial = over_disc(|s| sphere_pressure(force, A, s), rr);
            let fraction = sphere_force_fraction(A, rr);
            assert!((partial / force - fraction).abs() < 1e-12, "r/a = {f}");
        }
    }

    /// Boussinesq: the pressure indents the two half-spaces by
    /// `w(x) = (1/(π E*)) ∫∫ p dA/|x − s|`; inside the contact
    /// `w(0) − w(r) = r²/(2R)` (Hertz's paraboloid filled exactly), and
    /// `∫∫ p dA/ρ = π² p0 (2a² − r²)/(4a)` (Johnson (3.40)).
    #[test]
    fn sphere_pressure_fills_the_paraboloid() {
        let e_star = effective_modulus(1.0e6, 0.3, 2.0e6, 0.25);
        let r = 4.0e-5;
        let force = sphere_force(A, r, e_star);
        let p0 = sphere_peak_pressure(force, A);
        let w = |x: f64| {
            let i = disc_potential(
                |_, rho_max, rho_minus| {
                    tanh_sinh(
                        |rho, _, db| p0 / A * (db * (rho + rho_minus)).sqrt(),
                        0.0,
                        rho_max,
                    )
                },
                x,
            );
            let closed = PI * PI * p0 * (2.0 * A * A - x * x) / (4.0 * A);
            assert!((i / closed - 1.0).abs() < 1e-12, "x/a = {}", x / A);
            i / (PI * e_star)
        };
        let w0 = w(0.0);
        for f in [0.2, 0.5, 0.8, 0.97] {
            let x = f * A;
            let profile = x * x / (2.0 * r);
            assert!(
                ((w0 - w(x)) / profile - 1.0).abs() < 1e-11,
                "r/a = {f}: {:e} vs {profile:e}",
                w0 - w(x)
            );
        }
    }

    #[test]
    fn spot_flux_carries_q_and_its_partial_flows() {
        let q = 4.0e-3;
        let total = over_disc(|r| spot_flux(q, A, r), A);
        assert!((total / q - 1.0).abs() < 1e-12, "{total}");
        let h_min = spot_min_flux(q, A);
        assert!((spot_flux(q, A, 0.0) / h_min - 1.0).abs() < 1e-15);
        for f in [0.1, 0.5, 0.8, 0.999] {
            let h = spot_flux(q, A, f * A);
            assert!((h / h_min - 1.0 / (1.0 - f * f).sqrt()).abs() < 1e-12 * h / h_min);
            let rr = f * A;
            let partial = over_disc(|s| spot_flux(q, A, s), rr);
            let fraction = spot_heat_flow_fraction(A, rr);
            assert!(
                (partial / q - fraction).abs() < 1e-12,
                "r/a = {f}: {} vs {fraction}",
                partial / q
            );
        }
        assert_eq!(spot_flux(q, A, A), 0.0);
        assert_eq!(spot_heat_flow_fraction(A, 1.2 * A), 1.0);
        assert_eq!(spot_heat_flow_fraction(A, 0.0), 0.0);
    }

    /// On a half-space of conductivity `k` the surface temperature under the
    /// flux `h0` is `T(x) = (1/(2π k)) ∫∫ h0 dA/|x − s|`: the disc's flux
    /// makes the whole spot isothermal, `T = Q/(4 k a)` (the constriction
    /// resistance of one half-space), as perfect thermal contact requires.
    #[test]
    fn spot_flux_makes_the_disc_isothermal() {
        let (q, k) = (1.5e-3, 2.0);
        let expected = q / (4.0 * k * A);
        let c = q / (2.0 * PI * A);
        for f in [0.0, 0.3, 0.6, 0.9, 0.99] {
            let i = disc_potential(
                |_, rho_max, rho_minus| {
                    tanh_sinh(
                        |rho, _, db| c / (db * (rho + rho_minus)).sqrt(),
                        0.0,
                        rho_max,
                    )
                },
                f * A,
            );
            let t = i / (2.0 * PI * k);
            assert!(
                (t / expected - 1.0).abs() < 1e-11,
                "r/a = {f}: {t} vs {expected}"
            );
        }
    }
}
