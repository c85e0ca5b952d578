//! Internal O(1) scaling of the solver's unknowns (spec §2).
//!
//! Lengths are divided by a length scale (the sample width), stresses by
//! Young's modulus, temperatures by the reference temperature θ0 and
//! conductivities by k0. Every derived unit follows, so that penalty
//! parameters and tolerances inside the solver do not depend on the unit
//! system of the input.

use crate::material::Material;

/// Reference magnitudes that make the solver's quantities O(1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    /// Length scale `L` (m).
    pub length: f64,
    /// Stress scale `σs` (Pa).
    pub stress: f64,
    /// Temperature scale `Θs` (K).
    pub temperature: f64,
    /// Conductivity scale `ks` (W/(m·K)).
    pub conductivity: f64,
}

impl Scales {
    /// Scales from a characteristic length and a material: `L`, `E`, `θ0`, `k0`.
    pub fn new(length: f64, material: &Material) -> Self {
        Scales {
            length,
            stress: material.youngs_modulus,
            temperature: material.reference_temperature,
            conductivity: material.thermal_conductivity,
        }
    }

    /// Heat flux scale `ks Θs / L` (W/m²).
    pub fn flux(&self) -> f64 {
        self.conductivity * self.temperature / self.length
    }

    /// The material in scaled units.
    pub fn material(&self, m: &Material) -> Material {
        m.scaled(self.stress, self.temperature, self.conductivity)
    }

    /// Scaled length.
    pub fn len(&self, x: f64) -> f64 {
        x / self.length
    }

    /// Scaled temperature.
    pub fn temp(&self, theta: f64) -> f64 {
        theta / self.temperature
    }

    /// Scaled pressure or stress.
    pub fn pres(&self, p: f64) -> f64 {
        p / self.stress
    }

    /// Scaled heat flux.
    pub fn heat(&self, h: f64) -> f64 {
        h / self.flux()
    }
}
