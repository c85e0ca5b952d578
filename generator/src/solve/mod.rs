//! Degrees of freedom, boundary conditions, linear solvers, Newton's method,
//! and the up-front resource estimate.
pub mod dofs;
pub mod golden;
pub mod linear;
pub mod model;
pub mod newton;
pub mod ordering;
pub mod resources;
pub mod scales;

pub use dofs::{Dof, DofMap, DofMapBuilder};
pub use golden::{GoldenSection, golden_search, golden_section};
pub use model::{Body, Model, ModelBuilder};
pub use newton::{
    IterationTimes, LoadStepping, NON_FINITE_RESIDUAL, Newton, NewtonSettings, NonlinearProblem,
    SolveHistory,
};
pub use scales::Scales;
