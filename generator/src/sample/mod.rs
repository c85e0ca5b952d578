//! The micro-sample of spec §3 and §5: two rough bodies in contact under a
//! platen, the case file, and the pressure path solve behind `tcgen solve`.

pub mod case;
pub mod micro;
pub mod vtk;

pub use case::Case;
