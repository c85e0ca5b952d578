//! Gauss–Legendre quadrature rules.
