//! Sparse direct solvers behind one small interface: analyse once, refactorize per Newton step, solve.
