//! Bulk constitutive model (spec §4): modified entropic thermoelasticity and
//! conduction on the deformed configuration, Eq. (5.1) for `k(θ)`.
//!
//! | file | content |
//! |---|---|
//! | [`parameters`] | [`Material`]: Table I parameters, validation, moduli, `k(θ)`, unit scaling |
//! | [`thermoelastic`] | Helmholtz energy `ψ(F, θ)`, first Piola–Kirchhoff stress `P`, its tangents |
//! | [`conduction`] | referential heat flux `q0 = −J k(θ) C⁻¹ Grad θ` and its tangents |
//!
//! Deformation gradients are always 3×3; plane strain passes `F33 = 1`,
//! `F13 = F23 = F31 = F32 = 0`. Derivatives with respect to `F` are flattened
//! row-major: the entry `F_iJ` has index `3 i + J`.

pub mod conduction;
pub mod parameters;
pub mod thermoelastic;

pub use conduction::HeatFluxTangent;
pub use parameters::Material;
pub use thermoelastic::StressTangent;

/// Index of the entry `(i, J)` of a 3×3 tensor in the row-major 9-vector
/// used by [`StressTangent::dp_df`] and [`HeatFluxTangent::dq_df`].
#[inline]
pub const fn flat_index(i: usize, j: usize) -> usize {
    3 * i + j
}

#[cfg(test)]
pub(crate) mod test_support;
