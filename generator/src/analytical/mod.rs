//! Closed-form reference solutions, tested on their own and used by the verification.
pub mod compression;
pub mod manufactured;
