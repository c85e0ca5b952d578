//! B-spline and NURBS basis functions with derivatives (Piegl & Tiller).
