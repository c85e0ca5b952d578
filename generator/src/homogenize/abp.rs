//! The accompanying bar problem (ABP, paper Sect. 2.2.2, (2.10), Fig. 2):
//! two flat bars of the samples' heights under the same `p̄N` and `h̄`, with
//! `θ̄c` imposed on the contact surfaces and `h̄` on the external faces. Gives
//! `θ_ABP(1)` (top of the upper bar) and `θ_ABP(2)` (bottom of the lower bar)
//! in closed form (the 1D solutions of `analytical::compression`).

use crate::analytical::compression::{coupled_bar_top_temperature, platen_stretch};
use crate::material::Material;
use crate::{Error, Result};

/// Temperatures of the external faces of the ABP.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AbpTemperatures {
    /// `θ_ABP(1)`: top of the upper bar (K).
    pub upper: f64,
    /// `θ_ABP(2)`: bottom of the lower bar (K).
    pub lower: f64,
}

/// How the ABP's temperature-dependent properties are evaluated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AbpProperties {
    /// Fully coupled (the coupled OHP's counterpart).
    Coupled,
    /// Frozen at the given temperatures (upper, lower) (two-phase framework).
    Frozen([f64; 2]),
}

/// Solves the ABP for `pressure` (Pa), flux magnitude `flux` (W/m², from the
/// upper to the lower bar), contact temperature `theta_c` and bar `height`.
pub fn accompanying_bar(
    upper: &Material,
    lower: &Material,
    pressure: f64,
    flux: f64,
    theta_c: f64,
    height: f64,
    props: AbpProperties,
) -> Result<AbpTemperatures> {
    match props {
        AbpProperties::Frozen([tu, tl]) => {
            // Constant k and stretch at the evaluation temperatures: θ' = hλ/k.
            let bar = |m: &Material, t: f64| -> Result<f64> {
                let lambda = platen_stretch(m, pressure, t)?;
                let (k, _) = m.conductivity(t);
                Ok(flux * lambda * height / k)
            };
            Ok(AbpTemperatures {
                upper: theta_c + bar(upper, tu)?,
                lower: theta_c - bar(lower, tl)?,
            })
        }
        AbpProperties::Coupled => {
            let top = coupled_bar_top_temperature(upper, pressure, theta_c, flux, height)?;
            // Lower bar: find its bottom temperature whose top reaches θ̄c.
            let f = |tb: f64| -> Result<f64> {
                Ok(coupled_bar_top_temperature(lower, pressure, tb, flux, height)? - theta_c)
            };
            let lambda = platen_stretch(lower, pressure, theta_c)?;
            let (k, _) = lower.conductivity(theta_c);
            let mut t0 = theta_c - flux * lambda * height / k;
            let mut f0 = f(t0)?;
            let mut t1 = t0 - f0;
            for _ in 0..100 {
                let f1 = f(t1)?;
                if f1.abs() <= 1e-13 * theta_c {
                    return Ok(AbpTemperatures {
                        upper: top,
                        lower: t1,
                    });
                }
                let t2 = t1 - f1 * (t1 - t0) / (f1 - f0);
                (t0, f0, t1) = (t1, f1, t2);
            }
            Err(Error::Geometry(
                "accompanying bar: the lower bar's bottom temperature did not converge".into(),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytical::compression::bar_top_temperature as top;

    #[test]
    fn frozen_bar_is_linear_and_symmetric() {
        let m = Material::default();
        let t = accompanying_bar(
            &m,
            &m,
            1e5,
            1e6,
            300.0,
            7e-6,
            AbpProperties::Frozen([300.0, 300.0]),
        )
        .unwrap();
        assert!(((t.upper - 300.0) + (t.lower - 300.0)).abs() < 1e-12);
        assert!(t.upper > 300.0);
    }

    #[test]
    fn coupled_lower_bar_reaches_the_contact_temperature() {
        let m = Material {
            thermal_expansion: 1e-3,
            ..Material::default()
        };
        let t = accompanying_bar(&m, &m, 1e5, 1e6, 300.0, 7e-6, AbpProperties::Coupled).unwrap();
        let back = coupled_bar_top_temperature(&m, 1e5, t.lower, 1e6, 7e-6).unwrap();
        assert!((back - 300.0).abs() < 1e-9);
        // With a frozen stretch the upper bar agrees to first order.
        let lambda = platen_stretch(&m, 1e5, 300.0).unwrap();
        let f = top(&m, lambda, 300.0, 1e6, 7e-6).unwrap();
        assert!((f - t.upper).abs() < 1e-2 * (t.upper - 300.0));
    }
}
