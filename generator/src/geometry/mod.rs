//! Knot vectors, NURBS patches (curves, surfaces, volumes), refinement, fitted rough blocks.
//!
//! - [`knots`]: open knot vectors, span search (A2.1), Greville abscissae;
//! - [`nurbs`]: [`NurbsPatch`], one type for curves, surfaces and volumes: evaluation, basis,
//!   elements, faces, curve derivatives (A4.2);
//! - [`patch_quadrature`]: bulk and boundary-face Gauss quadrature with physical gradients,
//!   Jacobians and outward normals;
//! - [`refine`]: knot insertion (A5.4) and degree elevation (A5.9), row-wise on homogeneous
//!   coordinates;
//! - [`shapes`]: exact rectangles, cuboids, circular arcs, the quarter annulus;
//! - [`fit`]: B-spline fit of a rough surface height function and the fitted block (spec §3);
//! - [`hierarchical`]: local refinement by truncated hierarchical B-splines ([`ThbPatch`]).
//!
//! Algorithms follow Piegl & Tiller, *The NURBS Book* (2nd ed.).
pub mod fit;
pub mod hierarchical;
pub mod knots;
pub mod nurbs;
pub mod patch_quadrature;
pub mod refine;
pub mod shapes;

pub use fit::{
    ArealFit, FitMethod, RoughFace, SurfaceFit, fit_height_function, fit_height_map,
    resolve_rough_face, rough_block, try_rough_block, try_rough_volume,
};
pub use hierarchical::{Cell, HierarchicalMesh, ThbPatch};
pub use knots::KnotVector;
pub use nurbs::{Element, NurbsPatch, Side};
pub use patch_quadrature::{ElementQuadrature, FaceElementQuadrature, FaceQuadPoint, QuadPoint};
pub use shapes::{circular_arc, cuboid, quarter_annulus, rectangle};

pub use crate::basis::RationalBasis;
