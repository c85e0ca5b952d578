//! Bulk thermoelasticity: element residuals and tangents (local), sparse assembly (global).
pub mod global;
