//! The homogenized bar problem (HBP, paper Sect. 2.2.2, Fig. 2): two flat,
//! fully coupled bars of the samples' heights under `p̄N` and `|h̄|`, joined
//! by the macroscopic interface law — the identified jump `ϑ̄c` between the
//! lower bar's top and the upper bar's bottom. With the bottom of the lower
//! bar at the temperature `θ(2)` of the original heterogeneous problem (OHP),
//! an accurate homogenization gives `θ_HBP(1) = θ(1)` at the top (validation
//! of Fig. 16b). Closed form: the 1D coupled bar of `analytical::compression`
//! twice.

use crate::Result;
use crate::analytical::compression::coupled_bar_top_temperature;
use crate::material::Material;

/// Temperatures of the HBP (K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HbpTemperatures {
    /// Top of the lower bar (its side of the macroscopic interface).
    pub lower_top: f64,
    /// Bottom of the upper bar: `lower_top + ϑ̄c`.
    pub upper_bottom: f64,
    /// `θ_HBP(1)`: top of the upper bar.
    pub upper_top: f64,
}

/// Solves the HBP: lower bar (`lower`, height `height`) from `theta_bottom`
/// (K) at its bottom, the jump `jump` (K, magnitude, the upper side hotter)
/// across the interface, then the upper bar; pressure `pressure` (Pa), flux
/// magnitude `flux` (W/m², from the upper to the lower bar).
pub fn homogenized_bar(
    upper: &Material,
    lower: &Material,
    pressure: f64,
    flux: f64,
    theta_bottom: f64,
    height: f64,
    jump: f64,
) -> Result<HbpTemperatures> {
    let lower_top = coupled_bar_top_temperature(lower, pressure, theta_bottom, flux, height)?;
    let upper_bottom = lower_top + jump;
    let upper_top = coupled_bar_top_temperature(upper, pressure, upper_bottom, flux, height)?;
    Ok(HbpTemperatures {
        lower_top,
        upper_bottom,
        upper_top,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_conductivity_bars_add_the_jump_to_two_linear_drops() {
        let m = Material {
            conductivity_slope: 0.0,
            thermal_expansion: 0.0,
            youngs_modulus: 1.0e12,
            ..Material::default()
        };
        let (flux, h, jump) = (1.0e6, 3.0e-5, 2.5);
        let t = homogenized_bar(&m, &m, 1.0e3, flux, 290.0, h, jump).unwrap();
        let drop = flux * h / m.thermal_conductivity;
        assert!((t.lower_top - 290.0 - drop).abs() < 1e-6 * drop);
        assert!((t.upper_top - (290.0 + 2.0 * drop + jump)).abs() < 1e-6 * drop);
    }

    #[test]
    fn a_larger_jump_raises_the_top_temperature_at_least_by_the_difference() {
        // k(θ) grows with θ (k1 > 0): the hotter upper bar conducts better, so
        // the top rises by the extra jump minus a smaller bulk drop.
        let m = Material::default();
        let a = homogenized_bar(&m, &m, 1.0e4, 1.0e6, 293.15, 3.0e-5, 1.0).unwrap();
        let b = homogenized_bar(&m, &m, 1.0e4, 1.0e6, 293.15, 3.0e-5, 2.0).unwrap();
        let rise = b.upper_top - a.upper_top;
        assert!(rise > 0.0 && rise < 1.0, "{rise}");
        assert_eq!(a.lower_top, b.lower_top);
    }
}
