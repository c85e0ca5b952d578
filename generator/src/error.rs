//! The crate's one error type.

use thiserror::Error as ThisError;

/// Every failure `tcgen` reports: bad input, numerical failure, I/O.
///
/// Programmer errors (mismatched dimensions, out-of-range indices) panic
/// instead, with `#[track_caller]`.
#[derive(Debug, ThisError)]
pub enum Error {
    /// A user-supplied value is outside its allowed range.
    #[error("invalid input `{field}` = {value}: {expected}")]
    InvalidInput {
        /// The key or field, as the user wrote it (e.g. `material.poisson_ratio`).
        field: String,
        /// The offending value, formatted.
        value: String,
        /// The allowed range or form.
        expected: String,
    },
    /// An ill-formed geometric object (knot vector, patch, projection failure).
    #[error("geometry: {0}")]
    Geometry(String),
    /// The sparse direct solver failed (singular or indefinite matrix, ...).
    #[error("linear solver: {0}")]
    LinearSolver(String),
    /// Newton's method failed within a load step.
    #[error(
        "Newton did not converge in load step {step} (load factor {load_factor:.6}) \
         after {iterations} iterations: {reason}"
    )]
    NewtonDiverged {
        /// Load step counter (0-based).
        step: usize,
        /// The load factor that was attempted.
        load_factor: f64,
        /// Iterations performed.
        iterations: usize,
        /// Which residual failed, and how.
        reason: String,
    },
    /// Adaptive load stepping cut the step below its minimum.
    #[error(
        "load stepping stalled at load factor {load_factor:.6}: step {step_size:.3e} below the minimum; last failure: {last}"
    )]
    LoadStepStalled {
        /// The last converged load factor.
        load_factor: f64,
        /// The step size that failed.
        step_size: f64,
        /// The last Newton failure.
        last: Box<Error>,
    },
    /// An allocation larger than the memory left
    /// ([`crate::solve::resources::memory_left`]), refused before it is made
    /// rather than left to the system's out-of-memory killer.
    #[error(
        "out of memory: {what} needs {} more, {} left ({}); use fewer elements or \
         refinement levels ([discretization] max_levels, max_dofs), or more memory",
        crate::solve::resources::format_bytes(*.needed),
        crate::solve::resources::format_bytes(*.left),
        crate::solve::resources::MEMORY_LEFT_SOURCE
    )]
    OutOfMemory {
        /// What was to be allocated.
        what: String,
        /// Bytes it needed.
        needed: f64,
        /// Bytes left.
        left: f64,
    },
    /// A configuration file could not be read or parsed.
    #[error("config: {0}")]
    Config(String),
    /// Reading or writing a file failed.
    #[error("{path}: {source}")]
    Io {
        /// The file concerned.
        path: String,
        /// The underlying I/O error.
        source: std::io::Error,
    },
}

/// `Result` with the crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Reads a text file; the error names the path.
pub fn read_text(path: &std::path::Path) -> Result<String> {
    std::fs::read_to_string(path).map_err(|e| Error::Io {
        path: path.display().to_string(),
        source: e,
    })
}

impl Error {
    /// Shorthand for [`Error::InvalidInput`].
    pub fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        expected: impl Into<String>,
    ) -> Self {
        Error::InvalidInput {
            field: field.into(),
            value: value.to_string(),
            expected: expected.into(),
        }
    }
}
