//! Material parameters (Table I of the paper), their validation, the derived
//! moduli, the conductivity law (5.1) and the change of units used by the
//! solver's O(1) scaling.

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// Parameters of the bulk thermoelastic and conductive model (spec §4), in SI.
///
/// The keys are those of the `[material]` table of a case file. `Default` is
/// Table I of the paper.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Material {
    /// Young's modulus `E` (Pa) (Table I: 1.0 MPa).
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν` (-) (Table I: 0.3).
    pub poisson_ratio: f64,
    /// Coefficient of linear thermal expansion `α0` (1/K) (Table I: 1e−5).
    pub thermal_expansion: f64,
    /// Conductivity at the reference temperature `k0` (W/(m·K)) (Table I: 1), Eq. (5.1).
    pub thermal_conductivity: f64,
    /// Slope of the conductivity `k1` (W/(m·K²)) (Table I: 0.01), Eq. (5.1).
    pub conductivity_slope: f64,
    /// Reference temperature `θ0` (K) (Table I: 293.15): stress-free at `F = I`.
    pub reference_temperature: f64,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            youngs_modulus: 1.0e6,
            poisson_ratio: 0.3,
            thermal_expansion: 1.0e-5,
            thermal_conductivity: 1.0,
            conductivity_slope: 0.01,
            reference_temperature: 293.15,
        }
    }
}

impl Material {
    /// Checks every parameter; `prefix` names the table in error messages
    /// (e.g. `"material"` gives `material.poisson_ratio`; `""` gives the bare key).
    ///
    /// Bounds: `E > 0`, `−1 < ν < 0.5`, `α0 ≥ 0`, `k0 > 0`, `k1` finite, `θ0 > 0`,
    /// all finite.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        let field = |name: &str| {
            if prefix.is_empty() {
                name.to_string()
            } else {
                format!("{prefix}.{name}")
            }
        };
        let check = |name: &str, value: f64, ok: bool, expected: &str| -> Result<()> {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(Error::invalid(
                    field(name),
                    value,
                    format!("must be {expected}"),
                ))
            }
        };
        check(
            "youngs_modulus",
            self.youngs_modulus,
            self.youngs_modulus > 0.0,
            "finite and > 0 [Pa]",
        )?;
        check(
            "poisson_ratio",
            self.poisson_ratio,
            self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5,
            "in (-1, 0.5)",
        )?;
        check(
            "thermal_expansion",
            self.thermal_expansion,
            self.thermal_expansion >= 0.0,
            "finite and >= 0 [1/K]",
        )?;
        check(
            "thermal_conductivity",
            self.thermal_conductivity,
            self.thermal_conductivity > 0.0,
            "finite and > 0 [W/(m K)]",
        )?;
        check(
            "conductivity_slope",
            self.conductivity_slope,
            true,
            "finite [W/(m K^2)]",
        )?;
        check(
            "reference_temperature",
            self.reference_temperature,
            self.reference_temperature > 0.0,
            "finite and > 0 [K]",
        )?;
        Ok(())
    }

    /// Shear modulus `μ = E / (2(1+ν))`.
    #[inline]
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }

    /// Bulk modulus `κ = E / (3(1−2ν))`.
    #[inline]
    pub fn bulk_modulus(&self) -> f64 {
        self.youngs_modulus / (3.0 * (1.0 - 2.0 * self.poisson_ratio))
    }

    /// Lamé's first parameter `λ = κ − 2μ/3` (small-strain limit).
    #[inline]
    pub fn lame_lambda(&self) -> f64 {
        self.bulk_modulus() - 2.0 / 3.0 * self.shear_modulus()
    }

    /// Conductivity and its temperature derivative, `(k, dk/dθ)` with
    /// `k(θ) = k0 + k1 (θ − θ0)`, Eq. (5.1). Not clipped: the caller keeps `k > 0`.
    #[inline]
    pub fn conductivity(&self, theta: f64) -> (f64, f64) {
        let k = self.thermal_conductivity
            + self.conductivity_slope * (theta - self.reference_temperature);
        (k, self.conductivity_slope)
    }

    /// The temperature at which `k(θ)` vanishes, `θ0 − k0/k1`, if `k1 ≠ 0`.
    pub fn zero_conductivity_temperature(&self) -> Option<f64> {
        (self.conductivity_slope != 0.0).then(|| {
            self.reference_temperature - self.thermal_conductivity / self.conductivity_slope
        })
    }

    /// The same material in other units of stress (`σs`), temperature (`Θs`)
    /// and conductivity (`ks`), for the solver's O(1) scaling (spec §2):
    /// `E/σs`, `k0/ks`, `θ0/Θs`, `α0·Θs`, `k1·Θs/ks`; `ν` is unchanged.
    ///
    /// Then `ψ'(F, θ/Θs) = ψ(F, θ)/σs`, `P'(F, θ/Θs) = P(F, θ)/σs` and, with a
    /// length scale `Ls` (which enters only through `G = Grad θ`),
    /// `q0'(F, θ/Θs, G Ls/Θs) = q0(F, θ, G) / (ks Θs/Ls)`.
    pub fn scaled(
        &self,
        stress_scale: f64,
        temperature_scale: f64,
        conductivity_scale: f64,
    ) -> Material {
        Material {
            youngs_modulus: self.youngs_modulus / stress_scale,
            poisson_ratio: self.poisson_ratio,
            thermal_expansion: self.thermal_expansion * temperature_scale,
            thermal_conductivity: self.thermal_conductivity / conductivity_scale,
            conductivity_slope: self.conductivity_slope * temperature_scale / conductivity_scale,
            reference_temperature: self.reference_temperature / temperature_scale,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_is_table_one_and_valid() {
        let m = Material::default();
        m.validate("material").unwrap();
        assert_eq!(m.youngs_modulus, 1.0e6);
        assert_eq!(m.reference_temperature, 293.15);
        // μ and κ from E and ν, and back: E = 9κμ/(3κ+μ), ν = (3κ−2μ)/(2(3κ+μ)).
        let (mu, kappa) = (m.shear_modulus(), m.bulk_modulus());
        assert!((9.0 * kappa * mu / (3.0 * kappa + mu) / m.youngs_modulus - 1.0).abs() < 1e-14);
        assert!(
            ((3.0 * kappa - 2.0 * mu) / (2.0 * (3.0 * kappa + mu)) - m.poisson_ratio).abs() < 1e-14
        );
    }

    #[test]
    fn validate_names_the_field_and_the_bound() {
        let bad = Material {
            poisson_ratio: 0.5,
            ..Material::default()
        };
        let msg = bad.validate("material").unwrap_err().to_string();
        assert!(
            msg.contains("material.poisson_ratio") && msg.contains("(-1, 0.5)"),
            "{msg}"
        );
        for m in [
            Material {
                youngs_modulus: 0.0,
                ..Material::default()
            },
            Material {
                youngs_modulus: f64::NAN,
                ..Material::default()
            },
            Material {
                poisson_ratio: -1.0,
                ..Material::default()
            },
            Material {
                thermal_expansion: -1e-6,
                ..Material::default()
            },
            Material {
                thermal_conductivity: 0.0,
                ..Material::default()
            },
            Material {
                conductivity_slope: f64::INFINITY,
                ..Material::default()
            },
            Material {
                reference_temperature: -1.0,
                ..Material::default()
            },
        ] {
            assert!(m.validate("").is_err(), "{m:?}");
        }
        let msg = Material {
            thermal_expansion: -1.0,
            ..Material::default()
        }
        .validate("")
        .unwrap_err()
        .to_string();
        assert!(msg.contains("`thermal_expansion`"), "{msg}");
    }

    #[test]
    fn toml_keys_and_defaults() {
        let m: Material =
            toml::from_str("youngs_modulus = 2.0e6\nconductivity_slope = 0.0").unwrap();
        assert_eq!(
            m,
            Material {
                youngs_modulus: 2.0e6,
                conductivity_slope: 0.0,
                ..Material::default()
            }
        );
        assert!(toml::from_str::<Material>("young = 1.0").is_err());
        let back: Material = toml::from_str(&toml::to_string(&m).unwrap()).unwrap();
        assert_eq!(back, m);
    }

    #[test]
    fn conductivity_is_eq_5_1() {
        let m = Material::default();
        let (k, dk) = m.conductivity(393.15);
        assert!((k - 2.0).abs() < 1e-12 && dk == 0.01);
        assert!((m.zero_conductivity_temperature().unwrap() - 193.15).abs() < 1e-12);
        assert!(
            m.conductivity(m.zero_conductivity_temperature().unwrap())
                .0
                .abs()
                < 1e-12
        );
    }

    #[test]
    fn scaling_changes_units_consistently() {
        let m = Material::default();
        let (ss, ts, ks) = (1.0e6, 300.0, 2.0);
        let s = m.scaled(ss, ts, ks);
        let theta = 350.0;
        let (k, dk) = m.conductivity(theta);
        let (k_s, dk_s) = s.conductivity(theta / ts);
        assert!((k_s - k / ks).abs() < 1e-14 && (dk_s - dk * ts / ks).abs() < 1e-14);
        assert!((s.shear_modulus() - m.shear_modulus() / ss).abs() < 1e-14);
        // Thermal stress `3 α0 κ Δθ` scales as a stress.
        let thermal = |m: &Material, dt: f64| 3.0 * m.thermal_expansion * m.bulk_modulus() * dt;
        assert!(
            (thermal(&s, (theta - m.reference_temperature) / ts)
                - thermal(&m, theta - m.reference_temperature) / ss)
                .abs()
                < 1e-14
        );
        // The documented identities for ψ, P and q0.
        let f = nalgebra::Matrix3::new(1.1, 0.2, 0.0, -0.1, 0.9, 0.05, 0.03, 0.1, 1.2);
        let grad = nalgebra::Vector3::new(3.0e3, -1.0e3, 2.0e3);
        let psi = m.energy(&f, theta);
        assert!((s.energy(&f, theta / ts) - psi / ss).abs() < 1e-13 * (psi / ss).abs());
        let p = m.stress(&f, theta);
        assert!((s.stress(&f, theta / ts) - p / ss).amax() < 1e-13 * (p / ss).amax());
        let q = m.heat_flux(&f, theta, &grad);
        let ls = 1e-3;
        let q_scale = ks * ts / ls;
        let q_s = s.heat_flux(&f, theta / ts, &(grad * ls / ts));
        assert!((q_s - q / q_scale).amax() < 1e-13 * (q / q_scale).amax());
        s.validate("scaled").unwrap();
    }
}
