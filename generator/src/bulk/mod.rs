//! Bulk thermoelasticity: element residuals and tangents (local), sparse assembly (global).
pub mod global;
pub mod local;

pub use local::{Coupling, ElementFields};
