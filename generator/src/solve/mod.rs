//! Degrees of freedom, boundary conditions, linear solvers and Newton's method.
pub mod linear;
pub mod ordering;
