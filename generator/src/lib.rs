//! # tcgen — thermal contact resistance by computational homogenization
//!
//! Computes the macroscopic temperature jump `jump(p̄N, h̄, θ̄c)` across a rough
//! contact interface by solving isogeometric micro-samples of the two boundary
//! layers, following Temizer (2014), *Multiscale thermomechanical contact:
//! computational homogenization with isogeometric analysis*, IJNME 97:582–607
//! ("the paper"). The specification distilled from it is `shared/spec/physics.md`.
//!
//! The modules mirror the physics pipeline:
//!
//! | module | content |
//! |---|---|
//! | [`geometry`] | knot vectors, NURBS patches, refinement, surface fitting |
//! | [`basis`] | B-spline and NURBS basis functions and derivatives |
//! | [`quadrature`] | Gauss–Legendre rules |
//! | [`material`] | modified entropic thermoelasticity and conduction (spec §4) |
//! | [`bulk`] | element residuals and tangents (local), sparse assembly (global) |
//! | [`contact`] | mortar mechanical and thermal contact (paper Sect. 4) |
//! | [`solve`] | degrees of freedom and boundary conditions, linear solvers, Newton |
//! | [`homogenize`] | ABP, OHP, HBP, identifications, two-phase self-consistent |
//! | [`surface`] | rough surface families |
//! | [`sweep`] | parameter grids and ensembles |
//! | [`io`] | tables, VTK |
//! | [`sample`] | the micro-sample case file and its solve |
//! | [`analytical`] | closed-form reference solutions used by the verification |
//! | [`verify`] | the verification catalogue (spec §10), run by `tcgen verify` |
//!
//! Units: SI in every file and API (m, Pa, K, W/m², W/(m·K)). Inside the solver
//! quantities are scaled to O(1) by [`solve::Scales`] (spec §2).
#![warn(missing_docs)]
// Tensor and element code indexes several arrays with one index; loops over
// index ranges say that more plainly than zipped iterators.
#![allow(clippy::needless_range_loop)]

pub mod analytical;
pub mod basis;
pub mod bench;
pub mod bulk;
pub mod contact;
pub mod error;
pub mod geometry;
pub mod homogenize;
pub mod io;
pub mod material;
pub mod quadrature;
pub mod sample;
pub mod solve;
pub mod surface;
pub mod sweep;
pub mod verify;

pub use error::{Error, Result};
