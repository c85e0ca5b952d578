//! Mortar-based frictionless mechanical and thermal contact (paper Sect. 4, spec §6).
//!
//! - [`projection`]: closest-point projection onto the master curve (2D), periodic images;
//! - [`projection3d`]: closest-point projection onto the master surface (3D),
//!   periodic images in x and y, C0 edges and vertices;
//! - [`kinematics`]: gap and temperature jump with exact AD derivatives (2D);
//! - [`kinematics3d`]: the same on master surfaces (3D), closed-form derivatives;
//! - [`mortar`]: lumped mortar integrals (4.8), augmented Lagrangian (4.9)–(4.10),
//!   constitutive thermal contact, continuum option;
//! - [`pieces`]: the master face's polynomial pieces, evaluated by the projections;
//! - [`segments`]: segment-based integration of the mortar integrals.

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

pub mod kinematics;
pub mod kinematics3d;
pub mod mortar;
pub mod pieces;
pub mod projection;
pub mod projection3d;
pub mod segments;

pub use mortar::{ContactInterface, Unknowns};

#[cfg(test)]
pub(crate) mod testing {
    /// A deterministic pseudo-random number generator on [0, 1) (LCG).
    pub fn rng(seed: u64) -> impl FnMut() -> f64 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}

/// Thermal contact model: the dissipation potential `H(ϑc, pN)` of (4.2).
#[derive(Clone, Debug, PartialEq)]
pub enum ThermalContact {
    /// `H = −εθ ϑc²/2`: temperature continuity across the real contact area.
    Constraint {
        /// Penalty (4.7) or augmented Lagrangian (4.9)–(4.10).
        enforcement: ThermalEnforcement,
        /// Penalty εθ in W/(m²·K); default: automatic, `10 k0 / h` with `h` the slave element size.
        penalty: Option<f64>,
    },
    /// `H = −kθ pN^α ϑc²/2`: microscale contact resistance, `h0 = −kθ pN^α ϑc`.
    Constitutive {
        /// `kθ` in W/(m²·K·Pa^α).
        conductance_coefficient: f64,
        /// `α` (dimensionless).
        pressure_exponent: f64,
    },
}

impl Default for ThermalContact {
    fn default() -> Self {
        ThermalContact::Constraint {
            enforcement: ThermalEnforcement::AugmentedLagrangian,
            penalty: None,
        }
    }
}

/// How the thermal constraint is enforced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ThermalEnforcement {
    /// Penalty only: `h0^I = −εθ γθ^I` (4.7); the thermal phase is SPD.
    Penalty,
    /// Augmented Lagrangian with multipliers as unknowns (4.9)–(4.10).
    #[default]
    AugmentedLagrangian,
}

/// Discretization of the thermal contact terms.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ThermalMethod {
    /// Lumped mortar (4.8) (the paper's method).
    #[default]
    Mortar,
    /// Pointwise at the slave integration points (for comparison, Sects. 5.1–5.2).
    Continuum,
}

/// How the mortar integrals (4.8) are integrated on the slave surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Integration {
    /// Gauss points per slave element, fixed in the slave (the paper's choice).
    Element,
    /// Slave elements split where the projection changes master piece; exact
    /// on C0 masters ([`segments`]); in 3D clipped by the master elements'
    /// preimages, split at the bisectors of C0 creases.
    Segment,
    /// Segment-based where the master has C0 corners (degree 1, repeated
    /// knots), element-based otherwise; element-based in 3D.
    #[default]
    Auto,
}

/// Contact settings (`[contact]` of the case file; see `schemas/case.md`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ContactKeys", into = "ContactKeys")]
pub struct ContactSettings {
    /// Thermal contact model.
    pub thermal: ThermalContact,
    /// Mortar or continuum thermal contact.
    pub thermal_method: ThermalMethod,
    /// Gauss points per slave interface element (paper: 8).
    pub interface_points: usize,
    /// Normal penalty factor: εN = factor · E / h (h the slave element size); default 1.
    pub mechanical_penalty: Option<f64>,
    /// Integration of the mortar integrals.
    pub integration: Integration,
    /// Thermal constraint models in the thermal phase of the two-phase
    /// methods: integrate over the contact zone where the interpolated
    /// pressure indicator is positive (edges inside elements) instead of
    /// over the supports of the nodal active set (`mortar::ContactZone`).
    /// `None`: the dimension's default ([`ContactSettings::thermal_zone_in`]).
    pub thermal_zone: Option<bool>,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            thermal: ThermalContact::default(),
            thermal_method: ThermalMethod::Mortar,
            interface_points: 8,
            mechanical_penalty: None,
            integration: Integration::Auto,
            thermal_zone: None,
        }
    }
}

/// The keys of `[contact]` as written in TOML.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
struct ContactKeys {
    thermal: String,
    enforcement: ThermalEnforcement,
    #[serde(skip_serializing_if = "Option::is_none")]
    penalty: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    conductance_coefficient: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pressure_exponent: Option<f64>,
    method: ThermalMethod,
    interface_points: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    mechanical_penalty: Option<f64>,
    integration: Integration,
    #[serde(skip_serializing_if = "Option::is_none")]
    thermal_zone: Option<bool>,
}

impl Default for ContactKeys {
    fn default() -> Self {
        ContactSettings::default().into()
    }
}

impl From<ContactSettings> for ContactKeys {
    fn from(c: ContactSettings) -> Self {
        let mut k = ContactKeys {
            thermal: String::new(),
            enforcement: ThermalEnforcement::default(),
            penalty: None,
            conductance_coefficient: None,
            pressure_exponent: None,
            method: c.thermal_method,
            interface_points: c.interface_points,
            mechanical_penalty: c.mechanical_penalty,
            integration: c.integration,
            thermal_zone: c.thermal_zone,
        };
        match c.thermal {
            ThermalContact::Constraint {
                enforcement,
                penalty,
            } => {
                k.thermal = "constraint".into();
                k.enforcement = enforcement;
                k.penalty = penalty;
            }
            ThermalContact::Constitutive {
                conductance_coefficient,
                pressure_exponent,
            } => {
                k.thermal = "constitutive".into();
                k.conductance_coefficient = Some(conductance_coefficient);
                k.pressure_exponent = Some(pressure_exponent);
            }
        }
        k
    }
}

impl TryFrom<ContactKeys> for ContactSettings {
    type Error = String;
    fn try_from(k: ContactKeys) -> std::result::Result<Self, String> {
        let thermal = match k.thermal.as_str() {
            "constraint" => {
                if k.conductance_coefficient.is_some() || k.pressure_exponent.is_some() {
                    return Err("contact.conductance_coefficient and contact.pressure_exponent belong to thermal = \"constitutive\"".into());
                }
                ThermalContact::Constraint { enforcement: k.enforcement, penalty: k.penalty }
            }
            "constitutive" => ThermalContact::Constitutive {
                conductance_coefficient: k
                    .conductance_coefficient
                    .ok_or("contact.conductance_coefficient (kθ, W/(m² K Pa^α)) is required with thermal = \"constitutive\"")?,
                pressure_exponent: k.pressure_exponent.unwrap_or(1.0),
            },
            other => return Err(format!("contact.thermal = {other:?}: expected \"constraint\" or \"constitutive\"")),
        };
        Ok(ContactSettings {
            thermal,
            thermal_method: k.method,
            interface_points: k.interface_points,
            mechanical_penalty: k.mechanical_penalty,
            integration: k.integration,
            thermal_zone: k.thermal_zone,
        })
    }
}

impl ContactSettings {
    /// Whether the thermal phase integrates over the contact zone in
    /// dimension `dim`: `thermal_zone` where given, otherwise in 2D only.
    /// In 3D the zone's conductance converges from below but was further
    /// from the boundary elements' than the nodal supports' on the meshes
    /// measured (docs/3d.md, "The 3D thermal contact zone").
    pub fn thermal_zone_in(&self, dim: usize) -> bool {
        self.thermal_zone.unwrap_or(dim == 2)
    }

    /// Checks ranges; names the key in the error.
    pub fn validate(&self) -> Result<()> {
        if !(1..=64).contains(&self.interface_points) {
            return Err(Error::invalid(
                "contact.interface_points",
                self.interface_points,
                "an integer in 1..=64",
            ));
        }
        if let Some(f) = self.mechanical_penalty
            && !(f.is_finite() && f > 0.0)
        {
            return Err(Error::invalid(
                "contact.mechanical_penalty",
                f,
                "a finite number > 0",
            ));
        }
        match self.thermal {
            ThermalContact::Constraint {
                penalty: Some(e), ..
            } if !(e.is_finite() && e > 0.0) => Err(Error::invalid(
                "contact.penalty",
                e,
                "a finite number > 0 (W/(m² K))",
            )),
            ThermalContact::Constitutive {
                conductance_coefficient: k,
                pressure_exponent: a,
            } => {
                if !(k.is_finite() && k > 0.0) {
                    Err(Error::invalid(
                        "contact.conductance_coefficient",
                        k,
                        "a finite number > 0",
                    ))
                } else if !(a.is_finite() && (0.0..=10.0).contains(&a)) {
                    Err(Error::invalid(
                        "contact.pressure_exponent",
                        a,
                        "a number in [0, 10]",
                    ))
                } else {
                    Ok(())
                }
            }
            _ => Ok(()),
        }
    }

    /// The settings in the solver's scaled units: the thermal penalty by
    /// `k/L`, `kθ` by `k / (L σ^α)`.
    pub fn scaled(&self, s: &crate::solve::Scales) -> ContactSettings {
        let mut c = self.clone();
        match &mut c.thermal {
            ThermalContact::Constraint {
                penalty: Some(e), ..
            } => *e *= s.length / s.conductivity,
            ThermalContact::Constitutive {
                conductance_coefficient: k,
                pressure_exponent: a,
            } => {
                *k *= s.stress.powf(*a) * s.length / s.conductivity;
            }
            _ => {}
        }
        c
    }

    /// Whether the thermal multipliers λθ are unknowns.
    pub fn thermal_multipliers(&self) -> bool {
        self.thermal_method == ThermalMethod::Mortar
            && matches!(
                self.thermal,
                ThermalContact::Constraint {
                    enforcement: ThermalEnforcement::AugmentedLagrangian,
                    ..
                }
            )
    }
}
