//! Knot vectors, NURBS patches (curves, surfaces, volumes), refinement, fitted rough blocks.
