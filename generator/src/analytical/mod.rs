//! Closed-form reference solutions, tested on their own and used by the verification.
pub mod compression;
pub mod constriction;
pub mod egg_box;
pub mod hertz;
pub mod manufactured;
pub mod size_effects;
pub mod westergaard;
