//! B-spline and NURBS basis functions and derivatives (Piegl & Tiller).
//!
//! - [`bspline`]: univariate B-spline basis functions and derivatives (A2.3);
//! - [`rational`]: tensor-product B-spline functions of an element, and the rational basis
//!   `R_a = w_a B_a / W` of any such functions (NURBS patches, hierarchical elements).
pub mod bspline;
pub mod rational;

pub use bspline::{basis_ders, basis_ders_into};
pub use rational::{
    RationalBasis, TensorBasis, bspline_tensor_into, nurbs_basis_into, rationalize,
};
