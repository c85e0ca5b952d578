//! Bulk constitutive model (spec §4): modified entropic thermoelasticity and
//! conduction on the deformed configuration, Eq. (5.1) for `k(θ)`.
