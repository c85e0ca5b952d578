//! Local refinement: truncated hierarchical B-splines (THB) over the parameter
//! domain of a NURBS patch, in 1 to 3 parametric directions — the same code
//! for curves (interfaces in 2D), surfaces (interfaces in 3D, bodies in 2D)
//! and volumes (bodies in 3D).
//!
//! - [`mesh`]: [`HierarchicalMesh`], nested dyadic refinements, admissible of
//!   class 2, periodic directions, the trace mesh on a face;
//! - [`basis`]: [`ThbBasis`], the active functions and each element's
//!   extraction onto its level's B-splines (truncation), and the exact
//!   prolongation of coefficients to a refined mesh;
//! - [`patch`]: [`ThbPatch`], the rational THB patch with the exact geometry
//!   of the NURBS patch it refines: element basis, quadrature, faces.
//!
//! THB functions keep what the analysis relies on: exact geometry, any degree,
//! non-negativity and the partition of unity (so every slave function has a
//! positive lumped mortar area `⟨N^I⟩ > 0`, paper (4.8)), linear independence,
//! and nested spaces (a solution transfers exactly to a refined mesh).
//! References: Giannelli, Jüttler & Speleers, *THB-splines: the truncated
//! basis for hierarchical splines*, CAGD 29 (2012); Garau & Vázquez,
//! *Algorithms for the implementation of adaptive isogeometric methods using
//! hierarchical B-splines*, Appl. Numer. Math. 123 (2018); Bracco, Buffa,
//! Giannelli & Vázquez, *Adaptive isogeometric methods with hierarchical
//! splines: an overview*, DCDS 39 (2019).
pub mod basis;
pub mod mesh;
pub mod patch;

pub use basis::{ThbBasis, ThbElement, prolongate};
pub use mesh::{Cell, HierarchicalMesh};
pub use patch::{SeamPoint, SeamSide, ThbPatch};
