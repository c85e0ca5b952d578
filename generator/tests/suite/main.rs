//! The integration tests of tcgen, linked into one test binary: one link
//! and one executable on disk instead of one per file (each links the whole
//! of tcgen, faer and the rest, about 50 MB). One file's tests:
//! `cargo test --release --test suite <file>::`, e.g. `contact_edges::`.
//!
//! `memory_guard` stays a binary of its own: it sets an environment
//! variable for its whole process.

#[path = "common/bem_reference.rs"]
mod bem_reference;
#[path = "common/westergaard_case.rs"]
mod westergaard;

mod adaptivity;
mod calculix_end_to_end;
mod contact_edges;
mod contact_jacobian;
mod contact_refined;
mod contact_verification;
mod homogenization_verification;
mod iga_basis;
mod iga_fit;
mod iga_fit_3d;
mod iga_hierarchical;
mod iga_quadrature;
mod iga_refine;
mod independent_bem;
mod independent_bem_3d;
mod linalg_assembly;
mod linalg_solver;
mod measured_surface;
mod micro_sample;
mod periodic_seams;
mod sweep_cli;
mod sweep_failures;
mod sweep_reference;
mod sweep_resume;
mod sweep_shards;
mod sweep_support;
mod tangent_symmetry;
mod verification_bulk;
mod vtk_output;
