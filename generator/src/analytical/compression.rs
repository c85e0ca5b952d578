//! Homogeneous compression of a block under a rigid platen, and 1D conduction through it (the accompanying bar problem).
//!
//! **Compression.** The block has LN lateral faces (no lateral displacement) and
//! uniform temperature `θ`; the platen imposes the pressure `p` (positive in
//! compression). The deformation is homogeneous, `F = diag(1, λ, 1)` in plane
//! strain (vertical axis `y`) or `F = diag(1, 1, λ)` in 3D (vertical axis `z`);
//! both give the same axial stress by the isotropy of `ψ`. With `J = λ`,
//! `tr C = 2 + λ²` and `Δθ = θ − θ0`, the stresses of spec §4 are
//!
//! `P_yy = (θ/θ0) μ 2/3 (λ^(1/3) − λ^(−5/3)) + κ ln λ / λ − 3 α0 κ Δθ (1 − ln λ)/λ²`,
//! `P_xx = P_zz = (θ/θ0) μ λ^(−2/3) (1 − λ²)/3 + κ ln λ − 3 α0 κ Δθ (1 − ln λ)/λ`,
//!
//! and `λ(p, θ)` solves `−P_yy(λ, θ) = p`.
//!
//! **Conduction (the accompanying bar).** Reference height `H`, bottom
//! temperature `θ_b` at `Y = 0`, a flux of magnitude `h` (W/m²) entering at the
//! top and leaving at the bottom (per reference area = per current area, the
//! lateral faces do not move). With `F = diag(1, λ, 1)`,
//! `q0_Y = −J k C⁻¹_YY dθ/dY = −(k/λ) dθ/dY = −h`, so `k(θ) dθ/dY = h λ`.
//! Frozen configuration (constant `λ`): `K(θ) − K(θ_b) = h λ Y` with
//! `K(θ) = k0 (θ−θ0) + k1/2 (θ−θ0)²`. Fully coupled (the stretch follows the
//! local temperature at fixed pressure): `dY/dθ = k(θ) / (h λ(p, θ))`.

use nalgebra::{Matrix3, Vector3};

use crate::material::Material;
use crate::{Error, Result};

/// The homogeneous platen deformation: `diag(1, λ, 1)` for `dimension = 2`
/// (plane strain, vertical `y`), `diag(1, 1, λ)` for `dimension = 3` (vertical `z`).
#[track_caller]
pub fn platen_deformation_gradient(stretch: f64, dimension: usize) -> Matrix3<f64> {
    match dimension {
        2 => Matrix3::from_diagonal(&Vector3::new(1.0, stretch, 1.0)),
        3 => Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, stretch)),
        _ => panic!("platen_deformation_gradient: dimension must be 2 or 3, got {dimension}"),
    }
}

/// Axial (vertical) stress `P_yy(λ, θ)` of the platen compression (module doc).
pub fn platen_axial_stress(m: &Material, stretch: f64, theta: f64) -> f64 {
    let (mu, kappa, theta0) = (m.shear_modulus(), m.bulk_modulus(), m.reference_temperature);
    let l = stretch;
    let ln = l.ln();
    theta / theta0 * mu * 2.0 / 3.0 * (l.cbrt() - l.powf(-5.0 / 3.0)) + kappa * ln / l
        - 3.0 * m.thermal_expansion * kappa * (theta - theta0) * (1.0 - ln) / (l * l)
}

/// `dP_yy/dλ` at fixed `θ` (the axial stiffness of the block per unit reference height).
pub fn platen_axial_stiffness(m: &Material, stretch: f64, theta: f64) -> f64 {
    let (mu, kappa, theta0) = (m.shear_modulus(), m.bulk_modulus(), m.reference_temperature);
    let l = stretch;
    let ln = l.ln();
    theta / theta0 * mu * 2.0 / 9.0 * (l.powf(-2.0 / 3.0) + 5.0 * l.powf(-8.0 / 3.0))
        + kappa * (1.0 - ln) / (l * l)
        + 3.0 * m.thermal_expansion * kappa * (theta - theta0) * (3.0 - 2.0 * ln) / (l * l * l)
}

/// The platen pressure `p = −P_yy(λ, θ)` that holds the stretch `λ` at temperature `θ`.
pub fn platen_pressure(m: &Material, stretch: f64, theta: f64) -> f64 {
    -platen_axial_stress(m, stretch, theta)
}

/// Lateral stress `P_xx = P_zz` (the reaction of the LN lateral faces; `σ_xx = P_xx/λ`).
pub fn platen_lateral_stress(m: &Material, stretch: f64, theta: f64) -> f64 {
    let (mu, kappa, theta0) = (m.shear_modulus(), m.bulk_modulus(), m.reference_temperature);
    let l = stretch;
    let ln = l.ln();
    theta / theta0 * mu * l.powf(-2.0 / 3.0) * (1.0 - l * l) / 3.0 + kappa * ln
        - 3.0 * m.thermal_expansion * kappa * (theta - theta0) * (1.0 - ln) / l
}

/// The stretch `λ` with `−P_yy(λ, θ) = pressure` (pressure > 0 compresses;
/// tension allowed), by bracketing from `λ = 1` and a safeguarded Newton–bisection
/// to machine precision.
///
/// Below `θ0` the coupling term `−3 α0 κ Δθ ln J / J` dominates as `J → 0`, so
/// `−P_yy(λ)` has a maximum: a pressure above it (only reachable for extreme
/// `α0 |Δθ|` or pressures far above `E`) is reported as an error.
pub fn platen_stretch(m: &Material, pressure: f64, theta: f64) -> Result<f64> {
    m.validate("material")?;
    if !pressure.is_finite() {
        return Err(Error::invalid("pressure", pressure, "must be finite [Pa]"));
    }
    if !(theta.is_finite() && theta > 0.0) {
        return Err(Error::invalid(
            "temperature",
            theta,
            "must be finite and > 0 [K]",
        ));
    }
    // g(λ) = −P_yy − p decreases with λ on the physical branch.
    let g = |l: f64| platen_pressure(m, l, theta) - pressure;
    let no_solution = || {
        Error::invalid(
            "pressure",
            pressure,
            format!("no platen stretch in [2^-60, 2^60] balances it at θ = {theta} K"),
        )
    };
    let g1 = g(1.0);
    if g1 == 0.0 {
        return Ok(1.0);
    }
    let (mut lo, mut hi) = (1.0, 1.0);
    let mut found = false;
    for _ in 0..60 {
        if g1 < 0.0 {
            hi = lo;
            lo *= 0.5;
            let v = g(lo);
            if v.is_nan() {
                return Err(no_solution());
            }
            if v >= 0.0 {
                found = true;
                break;
            }
        } else {
            lo = hi;
            hi *= 2.0;
            let v = g(hi);
            if v.is_nan() {
                return Err(no_solution());
            }
            if v <= 0.0 {
                found = true;
                break;
            }
        }
    }
    if !found {
        return Err(no_solution());
    }
    // Invariant: g(lo) ≥ 0 ≥ g(hi).
    // Newton while it stays inside the bracket, bisection otherwise; after 50
    // iterations (rounding jitter) bisection alone, which ends in ~60 more.
    let mut l = 0.5 * (lo + hi);
    for iteration in 0..200 {
        let v = g(l);
        if v == 0.0 {
            return Ok(l);
        }
        if v > 0.0 {
            lo = l;
        } else {
            hi = l;
        }
        let slope = -platen_axial_stiffness(m, l, theta);
        let newton = l - v / slope;
        let next = if iteration < 50 && slope < 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - l).abs() <= 4.0 * f64::EPSILON * l || hi - lo <= 4.0 * f64::EPSILON * hi {
            return Ok(next);
        }
        l = next;
    }
    Err(no_solution())
}

#[track_caller]
fn check_bar_inputs(m: &Material, theta_bottom: f64, flux: f64) -> Result<f64> {
    m.validate("material")?;
    if !(theta_bottom.is_finite() && theta_bottom > 0.0) {
        return Err(Error::invalid(
            "theta_bottom",
            theta_bottom,
            "must be finite and > 0 [K]",
        ));
    }
    if !flux.is_finite() {
        return Err(Error::invalid("flux", flux, "must be finite [W/m^2]"));
    }
    let (k_bottom, _) = m.conductivity(theta_bottom);
    if k_bottom <= 0.0 {
        return Err(Error::invalid(
            "theta_bottom",
            theta_bottom,
            format!("must give k(θ) = k0 + k1 (θ − θ0) > 0, got {k_bottom}"),
        ));
    }
    Ok(k_bottom)
}

/// Temperature at height `Y` of the frozen bar (constant stretch `λ`):
/// the stable root of `K(θ) − K(θ_b) = h λ Y`,
/// `θ = θ_b + 2 h λ Y / (k(θ_b) + √(k(θ_b)² + 2 k1 h λ Y))`.
///
/// `flux` is the magnitude `h` entering at the top (negative: heat leaves at the top).
/// Errors if `k(θ)` would vanish on the way, or `θ` drop to 0 K.
pub fn bar_temperature(
    m: &Material,
    stretch: f64,
    theta_bottom: f64,
    flux: f64,
    y: f64,
) -> Result<f64> {
    let k_bottom = check_bar_inputs(m, theta_bottom, flux)?;
    if !(stretch.is_finite() && stretch > 0.0) {
        return Err(Error::invalid("stretch", stretch, "must be finite and > 0"));
    }
    if !(y.is_finite() && y >= 0.0) {
        return Err(Error::invalid("y", y, "must be finite and >= 0 [m]"));
    }
    let r = flux * stretch * y;
    let k_squared = k_bottom * k_bottom + 2.0 * m.conductivity_slope * r;
    if k_squared <= 0.0 {
        return Err(Error::invalid(
            "flux",
            flux,
            format!(
                "too large: k(θ) would vanish below Y = {y} m (k(θ_b)² + 2 k1 h λ Y = {k_squared})"
            ),
        ));
    }
    let theta = theta_bottom + 2.0 * r / (k_bottom + k_squared.sqrt());
    if theta <= 0.0 {
        return Err(Error::invalid(
            "flux",
            flux,
            format!("too large: θ would drop to {theta} K at Y = {y} m"),
        ));
    }
    Ok(theta)
}

/// Top temperature `θ(H)` of the frozen bar ([`bar_temperature`] at `Y = H`).
pub fn bar_top_temperature(
    m: &Material,
    stretch: f64,
    theta_bottom: f64,
    flux: f64,
    height: f64,
) -> Result<f64> {
    if !(height.is_finite() && height > 0.0) {
        return Err(Error::invalid(
            "height",
            height,
            "must be finite and > 0 [m]",
        ));
    }
    bar_temperature(m, stretch, theta_bottom, flux, height)
}

/// Gauss–Legendre nodes and weights on `[−1, 1]` (the crate's rule).
fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let g = crate::quadrature::GaussLegendre::new(n);
    (g.points, g.weights)
}

/// Height `Y(θ) = ∫_{θ_b}^{θ} k(t) / (h λ(p, t)) dt` at which the fully coupled bar
/// reaches the temperature `θ` (composite 16-point Gauss–Legendre, refined until
/// two successive sums agree to 4e−15 relative).
pub fn coupled_bar_height(
    m: &Material,
    pressure: f64,
    theta_bottom: f64,
    flux: f64,
    theta: f64,
) -> Result<f64> {
    check_bar_inputs(m, theta_bottom, flux)?;
    if flux == 0.0 {
        return Err(Error::invalid(
            "flux",
            flux,
            "must be nonzero for the coupled bar profile",
        ));
    }
    if !(theta.is_finite() && theta > 0.0) {
        return Err(Error::invalid(
            "temperature",
            theta,
            "must be finite and > 0 [K]",
        ));
    }
    let rule = gauss_legendre(16);
    let integrand = |t: f64| -> Result<f64> {
        Ok(m.conductivity(t).0 / (flux * platen_stretch(m, pressure, t)?))
    };
    let composite = |pieces: usize| -> Result<f64> {
        let width = (theta - theta_bottom) / pieces as f64;
        let mut sum = 0.0;
        for piece in 0..pieces {
            let mid = theta_bottom + (piece as f64 + 0.5) * width;
            for (x, w) in rule.0.iter().zip(&rule.1) {
                sum += w * integrand(mid + 0.5 * width * x)?;
            }
        }
        Ok(0.5 * width * sum)
    };
    let mut pieces = 1;
    let mut previous = composite(pieces)?;
    loop {
        pieces *= 2;
        let current = composite(pieces)?;
        if (current - previous).abs() <= 4e-15 * current.abs() || pieces >= 64 {
            return Ok(current);
        }
        previous = current;
    }
}

/// Top temperature of the fully coupled bar (the stretch follows the local
/// temperature at the fixed platen pressure): the root of `Y(θ) = H`
/// ([`coupled_bar_height`]) by safeguarded Newton (`dY/dθ = k/(h λ)`) to 1e−12 relative.
pub fn coupled_bar_top_temperature(
    m: &Material,
    pressure: f64,
    theta_bottom: f64,
    flux: f64,
    height: f64,
) -> Result<f64> {
    check_bar_inputs(m, theta_bottom, flux)?;
    if !(height.is_finite() && height > 0.0) {
        return Err(Error::invalid(
            "height",
            height,
            "must be finite and > 0 [m]",
        ));
    }
    if flux == 0.0 {
        return Ok(theta_bottom);
    }
    // Along the path, t = |θ − θ_b| ≥ 0 and φ(t) = Y(θ) − H increases while k > 0.
    let direction = flux.signum();
    let theta_at = |t: f64| theta_bottom + direction * t;
    let mut t_max = f64::INFINITY;
    if let Some(theta_zero) = m.zero_conductivity_temperature()
        && (theta_zero - theta_bottom) * direction > 0.0
    {
        t_max = (theta_zero - theta_bottom).abs();
    }
    if direction < 0.0 {
        t_max = t_max.min(theta_bottom);
    }
    let stretch_bottom = platen_stretch(m, pressure, theta_bottom)?;
    let guess = bar_top_temperature(m, stretch_bottom, theta_bottom, flux, height)
        .map(|theta| (theta - theta_bottom).abs())
        .unwrap_or(0.5 * t_max);
    let (mut lo, mut hi) = (0.0, t_max);
    let mut t = if guess < t_max { guess } else { 0.5 * t_max };
    for _ in 0..200 {
        let theta = theta_at(t);
        let phi = coupled_bar_height(m, pressure, theta_bottom, flux, theta)? - height;
        if phi < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let slope =
            direction * m.conductivity(theta).0 / (flux * platen_stretch(m, pressure, theta)?);
        let newton = t - phi / slope;
        let next = if slope > 0.0 && newton > lo && newton < hi {
            newton
        } else if hi.is_finite() {
            0.5 * (lo + hi)
        } else {
            2.0 * t.max(1.0)
        };
        if (next - t).abs() <= 1e-13 * theta_at(next).abs() {
            return Ok(theta_at(next));
        }
        if t_max.is_finite() && t_max - lo <= 1e-12 * theta_at(t_max).abs().max(1.0) {
            break;
        }
        t = next;
    }
    Err(Error::invalid(
        "flux",
        flux,
        format!(
            "too large for height {height} m: k(θ) would vanish or θ reach 0 K before the top of the coupled bar"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn materials() -> Vec<Material> {
        vec![
            Material::default(),
            Material {
                conductivity_slope: 0.0,
                ..Material::default()
            },
            Material {
                thermal_expansion: 1e-3,
                poisson_ratio: 0.45,
                ..Material::default()
            },
            Material {
                youngs_modulus: 2.0e11,
                conductivity_slope: -0.002,
                thermal_conductivity: 50.0,
                ..Material::default()
            },
        ]
    }

    #[test]
    fn closed_form_stresses_match_the_material_model() {
        for m in materials() {
            for theta in [250.0, m.reference_temperature, 400.0] {
                for stretch in [0.3, 0.8, 0.999, 1.0, 1.2, 2.5] {
                    for dim in [2, 3] {
                        let f = platen_deformation_gradient(stretch, dim);
                        let t = m.stress_tangent(&f, theta);
                        let axial = dim - 1;
                        let scale = t.p.amax().max(m.youngs_modulus * 1e-12);
                        assert!(
                            (t.p[(axial, axial)] - platen_axial_stress(&m, stretch, theta)).abs()
                                < 1e-13 * scale
                        );
                        assert!(
                            (t.p[(0, 0)] - platen_lateral_stress(&m, stretch, theta)).abs()
                                < 1e-13 * scale
                        );
                        let other = if dim == 2 { 2 } else { 1 };
                        assert!(
                            (t.p[(other, other)] - platen_lateral_stress(&m, stretch, theta)).abs()
                                < 1e-13 * scale
                        );
                        let n = 4 * axial;
                        let stiffness = platen_axial_stiffness(&m, stretch, theta);
                        assert!(
                            (t.dp_df[(n, n)] - stiffness).abs() < 1e-12 * t.dp_df.amax(),
                            "{stretch} {theta}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn platen_stretch_round_trips_to_machine_precision() {
        for m in materials() {
            for theta in [250.0, m.reference_temperature, 400.0] {
                for rel_pressure in [-0.2, -1e-6, 0.0, 1e-9, 1e-3, 0.1, 0.5, 2.0, 20.0] {
                    if rel_pressure > 2.0 && m.thermal_expansion > 1e-4 {
                        continue; // see platen_stretch_reports_unreachable_pressure
                    }
                    let pressure = rel_pressure * m.youngs_modulus;
                    let stretch = platen_stretch(&m, pressure, theta).unwrap();
                    let back = platen_pressure(&m, stretch, theta);
                    // Residual at the level of the rounding of P_yy near λ.
                    let scale = m.bulk_modulus() * 1e-14 + pressure.abs() * 1e-14;
                    assert!(
                        (back - pressure).abs() <= 4.0 * scale,
                        "{rel_pressure}: {back} vs {pressure}"
                    );
                    if rel_pressure > 0.0 {
                        assert!(
                            stretch
                                < 1.0
                                    + 3.0
                                        * m.thermal_expansion
                                        * (theta - m.reference_temperature).abs()
                        );
                    }
                }
                // Stretch → pressure → stretch, on the stable branch (stiffness > 0
                // between λ and 1).
                for stretch in [0.2, 0.7, 0.99, 1.05] {
                    let stable = (0..=100).all(|n| {
                        let l = stretch + (1.0 - stretch) * n as f64 / 100.0;
                        platen_axial_stiffness(&m, l, theta) > 0.0
                    });
                    if !stable {
                        assert!(m.thermal_expansion * (theta - m.reference_temperature) < -0.01);
                        continue;
                    }
                    let p = platen_pressure(&m, stretch, theta);
                    let back = platen_stretch(&m, p, theta).unwrap();
                    assert!(
                        (back - stretch).abs() < 1e-13 * stretch,
                        "{back} vs {stretch}"
                    );
                }
            }
        }
    }

    /// Small strain: `λ − 1 ≈ −p/(λ_L + 2μ)` (the constrained modulus) and, at zero
    /// pressure, the free axial expansion `λ − 1 ≈ 3 κ α0 Δθ/(κ + 4/3 μ θ/θ0)`
    /// (the entropic shear modulus is `μ θ/θ0`).
    #[test]
    fn platen_stretch_small_strain_limit_is_the_constrained_modulus() {
        let m = Material::default();
        let constrained = m.lame_lambda() + 2.0 * m.shear_modulus();
        let p = 1e-6 * m.youngs_modulus;
        let strain = platen_stretch(&m, p, m.reference_temperature).unwrap() - 1.0;
        assert!((strain * constrained / -p - 1.0).abs() < 1e-5);
        let dt = 10.0;
        let strain = platen_stretch(&m, 0.0, m.reference_temperature + dt).unwrap() - 1.0;
        let theta = m.reference_temperature + dt;
        let constrained =
            m.bulk_modulus() + 4.0 / 3.0 * m.shear_modulus() * theta / m.reference_temperature;
        let expected = 3.0 * m.bulk_modulus() * m.thermal_expansion * dt / constrained;
        assert!(
            (strain / expected - 1.0).abs() < 1e-3,
            "{strain} vs {expected}"
        );
        let at_reference = 3.0 * m.bulk_modulus() * m.thermal_expansion * dt
            / (m.lame_lambda() + 2.0 * m.shear_modulus());
        assert!(
            (strain / at_reference - 1.0).abs() > 1e-3,
            "the entropic stiffening is visible"
        );
    }

    /// With `α0 |Δθ| = 0.043` (cooling), `−P_yy(λ)` peaks below `20 E`.
    #[test]
    fn platen_stretch_reports_unreachable_pressure() {
        let m = Material {
            thermal_expansion: 1e-3,
            poisson_ratio: 0.45,
            ..Material::default()
        };
        let peak = (1..2000)
            .map(|n| platen_pressure(&m, n as f64 / 2000.0, 250.0))
            .fold(f64::MIN, f64::max);
        assert!(peak < 20.0 * m.youngs_modulus);
        let err = platen_stretch(&m, 20.0 * m.youngs_modulus, 250.0)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("pressure") && err.contains("no platen stretch"),
            "{err}"
        );
        let reachable = platen_stretch(&m, 0.9 * peak, 250.0).unwrap();
        assert!((platen_pressure(&m, reachable, 250.0) / (0.9 * peak) - 1.0).abs() < 1e-13);
    }

    #[test]
    fn platen_stretch_rejects_bad_input() {
        let m = Material::default();
        assert!(platen_stretch(&m, f64::NAN, 300.0).is_err());
        assert!(platen_stretch(&m, 1e5, -1.0).is_err());
        assert!(
            platen_stretch(
                &Material {
                    poisson_ratio: 0.7,
                    ..m
                },
                1e5,
                300.0
            )
            .is_err()
        );
    }

    #[test]
    fn bar_is_linear_by_hand_when_k1_vanishes() {
        let m = Material {
            conductivity_slope: 0.0,
            thermal_conductivity: 2.0,
            ..Material::default()
        };
        let (stretch, theta_b, h, y) = (0.9, 300.0, 1.0e4, 1e-3);
        let theta = bar_temperature(&m, stretch, theta_b, h, y).unwrap();
        // θ = θ_b + h λ Y / k0 = 300 + 1e4 · 0.9 · 1e-3 / 2.
        assert!((theta - (theta_b + 4.5)).abs() < 1e-12);
        assert_eq!(
            bar_top_temperature(&m, stretch, theta_b, h, y).unwrap(),
            theta
        );
    }

    /// The frozen profile satisfies `K(θ) − K(θ_b) = h λ Y` and the ODE
    /// `k(θ) dθ/dY = h λ` (central differences).
    #[test]
    fn bar_temperature_solves_the_conduction_ode() {
        for m in materials() {
            for (stretch, theta_b, h) in [
                (0.9, 293.15, 1.0e5),
                (0.7, 350.0, -2.0e4),
                (1.0, 260.0, 3.0e5),
            ] {
                let h = h * m.thermal_conductivity;
                let big_k = |t: f64| {
                    let u = t - m.reference_temperature;
                    m.thermal_conductivity * u + m.conductivity_slope / 2.0 * u * u
                };
                for y in [0.0, 1e-4, 5e-4, 1e-3] {
                    let theta = bar_temperature(&m, stretch, theta_b, h, y).unwrap();
                    let residual = big_k(theta) - big_k(theta_b) - h * stretch * y;
                    assert!(
                        residual.abs() < 1e-12 * big_k(theta).abs().max(h * stretch * 1e-3),
                        "{residual}"
                    );
                    let dy = 1e-6;
                    let y0 = y.max(2.0 * dy);
                    let at = |y: f64| bar_temperature(&m, stretch, theta_b, h, y).unwrap();
                    let slope = (at(y0 - 2.0 * dy) - at(y0 + 2.0 * dy)
                        + 8.0 * (at(y0 + dy) - at(y0 - dy)))
                        / (12.0 * dy);
                    let theta0 = bar_temperature(&m, stretch, theta_b, h, y0).unwrap();
                    let ode = m.conductivity(theta0).0 * slope / (h * stretch);
                    assert!(
                        (ode - 1.0).abs() < 1e-7,
                        "{ode} {m:?} {stretch} {theta_b} {h} {y} {theta0}"
                    );
                }
            }
        }
    }

    #[test]
    fn bar_rejects_vanishing_conductivity() {
        let m = Material::default(); // k = 0 at θ = 193.15 K
        // Cooling upwards (negative flux) from 293.15 K: K drops by at most k0²/(2 k1) = 50 W/m.
        assert!(bar_temperature(&m, 1.0, 293.15, -4.0e4, 1e-3).is_ok());
        let err = bar_temperature(&m, 1.0, 293.15, -6.0e4, 1e-3)
            .unwrap_err()
            .to_string();
        assert!(err.contains("flux") && err.contains("vanish"), "{err}");
        assert!(bar_temperature(&m, 1.0, 150.0, 1.0, 1e-3).is_err());
        assert!(bar_top_temperature(&m, 1.0, 300.0, 1.0, 0.0).is_err());
        assert!(coupled_bar_top_temperature(&m, 1e4, 293.15, -6.0e4, 1e-3).is_err());
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        let (x, w) = gauss_legendre(16);
        for degree in 0..32 {
            let sum: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(degree)).sum();
            let exact = if degree % 2 == 1 {
                0.0
            } else {
                2.0 / (degree as f64 + 1.0)
            };
            assert!(
                (sum - exact).abs() < 1e-14,
                "degree {degree}: {sum} vs {exact}"
            );
        }
    }

    /// Without thermal expansion and pressure the stretch is 1 at every temperature
    /// (under pressure it is not: the entropic shear modulus `μ θ/θ0` stiffens
    /// the block as it heats), and the coupled bar is the frozen one.
    #[test]
    fn coupled_bar_without_expansion_is_the_frozen_bar() {
        let m = Material {
            thermal_expansion: 0.0,
            ..Material::default()
        };
        let (p, theta_b, h, height) = (0.0, 293.15, 1.0e6, 1e-3);
        let stretch = platen_stretch(&m, p, theta_b).unwrap();
        let frozen = bar_top_temperature(&m, stretch, theta_b, h, height).unwrap();
        let coupled = coupled_bar_top_temperature(&m, p, theta_b, h, height).unwrap();
        assert!(
            (coupled - frozen).abs() < 1e-12 * frozen,
            "{coupled} vs {frozen}"
        );
    }

    /// RK4 on `dθ/dY = h λ(p, θ) / k(θ)`, Richardson-checked, against the quadrature + root.
    #[test]
    fn coupled_bar_matches_runge_kutta_and_the_ode() {
        for m in [
            Material::default(),
            Material {
                thermal_expansion: 1e-3,
                ..Material::default()
            },
        ] {
            for (p, theta_b, h, height) in
                [(2.0e5, 293.15, 1.0e6, 1e-3), (5.0e4, 330.0, -2.0e4, 2e-3)]
            {
                let rate = |theta: f64| {
                    h * platen_stretch(&m, p, theta).unwrap() / m.conductivity(theta).0
                };
                let rk4 = |steps: usize| {
                    let dy = height / steps as f64;
                    let mut theta = theta_b;
                    for _ in 0..steps {
                        let k1 = rate(theta);
                        let k2 = rate(theta + 0.5 * dy * k1);
                        let k3 = rate(theta + 0.5 * dy * k2);
                        let k4 = rate(theta + dy * k3);
                        theta += dy / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                    }
                    theta
                };
                let (coarse, fine) = (rk4(400), rk4(800));
                let reference = fine + (fine - coarse) / 15.0;
                let top = coupled_bar_top_temperature(&m, p, theta_b, h, height).unwrap();
                assert!(
                    (top - reference).abs() < 1e-11 * top,
                    "{top} vs {reference}"
                );
                // Inverse consistency and dθ_top/dH = h λ(θ_top)/k(θ_top).
                let y = coupled_bar_height(&m, p, theta_b, h, top).unwrap();
                assert!((y - height).abs() < 1e-12 * height);
                let dh = 1e-6 * height;
                let slope = (coupled_bar_top_temperature(&m, p, theta_b, h, height + dh).unwrap()
                    - coupled_bar_top_temperature(&m, p, theta_b, h, height - dh).unwrap())
                    / (2.0 * dh);
                assert!(
                    (slope / rate(top) - 1.0).abs() < 1e-6,
                    "{slope} vs {}",
                    rate(top)
                );
                // Thermal expansion makes the coupled bar differ from the frozen one.
                let frozen = bar_top_temperature(
                    &m,
                    platen_stretch(&m, p, theta_b).unwrap(),
                    theta_b,
                    h,
                    height,
                )
                .unwrap();
                assert!((top - frozen).abs() > 0.0);
            }
        }
    }
}
