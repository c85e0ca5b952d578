//! B-spline and NURBS basis functions and derivatives (Piegl & Tiller).
//!
//! - [`bspline`]: univariate B-spline basis functions and derivatives (A2.3);
//! - [`rational`]: tensor-product NURBS basis functions `R_a` and their parametric derivatives.
pub mod bspline;
pub mod rational;

pub use bspline::{basis_ders, basis_ders_into};
pub use rational::{RationalBasis, nurbs_basis_into};
