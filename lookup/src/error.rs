//! Error types: [`Error`] for reading, writing and building a law (may allocate),
//! [`EvalError`] for evaluating one (plain data, `Copy`, never allocates).

use std::fmt;
use std::path::PathBuf;

/// One of the three axes of a law table, in storage order (pressure slowest).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Axis {
    /// Macroscopic contact pressure `p̄N` \[Pa\], interpolated in `ln p̄N`.
    Pressure = 0,
    /// Magnitude of the macroscopic normal heat flux `|h̄|` \[W/m²\].
    Flux = 1,
    /// Macroscopic contact temperature `θ̄c` \[K\] (the master side, paper Eq. (2.6)).
    ContactTemperature = 2,
}

impl Axis {
    /// The three axes in storage order.
    pub const ALL: [Axis; 3] = [Axis::Pressure, Axis::Flux, Axis::ContactTemperature];

    /// The axis name used in law files and messages.
    pub const fn name(self) -> &'static str {
        match self {
            Axis::Pressure => "pressure",
            Axis::Flux => "flux",
            Axis::ContactTemperature => "contact_temperature",
        }
    }

    /// The SI unit of the axis, as written in law files.
    pub const fn unit(self) -> &'static str {
        match self {
            Axis::Pressure => "Pa",
            Axis::Flux => "W/m^2",
            Axis::ContactTemperature => "K",
        }
    }

    /// The axis with index `i` (0 pressure, 1 flux, 2 contact temperature).
    pub const fn from_index(i: usize) -> Option<Axis> {
        match i {
            0 => Some(Axis::Pressure),
            1 => Some(Axis::Flux),
            2 => Some(Axis::ContactTemperature),
            _ => None,
        }
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Failure to read, write or build a law. Every message names what is wrong.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The file could not be read or written.
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The file is larger than [`crate::MAX_FILE_BYTES`].
    TooLarge {
        /// Size of the file in bytes.
        size: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// The file does not start with the law magic bytes.
    BadMagic {
        /// The first bytes found (at most 8).
        found: [u8; 8],
    },
    /// The file has a format version this reader does not support.
    UnsupportedVersion {
        /// Version found in the file.
        found: u32,
        /// Newest version this reader supports (it reads versions 1 to this one).
        supported: u32,
    },
    /// The file is shorter than its header declares.
    Truncated {
        /// Bytes the header declares (or the fixed minimum).
        expected: u64,
        /// Bytes present.
        actual: u64,
    },
    /// The file is longer than its header declares.
    TrailingBytes {
        /// Bytes the header declares.
        expected: u64,
        /// Bytes present.
        actual: u64,
    },
    /// The stored CRC-32 does not match the content: the file is corrupted.
    Checksum {
        /// Checksum stored in the file.
        stored: u32,
        /// Checksum computed from the content.
        computed: u32,
    },
    /// The metadata text is malformed (line numbers start at 1).
    Metadata {
        /// Line of the metadata text (0 when the problem is not on one line).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A field (axis, array entry, metadata value or argument) is out of its allowed range.
    Invalid {
        /// The field, e.g. `pressure[3]`, `jump_mean[17]`, `max_conductance`.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

impl Error {
    pub(crate) fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Invalid {
            field: field.into(),
            message: message.into(),
        }
    }

    pub(crate) fn metadata(line: usize, message: impl Into<String>) -> Self {
        Error::Metadata {
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Io { path, source } => write!(f, "{}: {source}", path.display()),
            Error::TooLarge { size, limit } => {
                write!(f, "law file too large: {size} bytes (limit {limit})")
            }
            Error::BadMagic { found } => write!(
                f,
                "not a law file: bad magic bytes {found:02x?} (expected {:02x?})",
                crate::format::MAGIC
            ),
            Error::UnsupportedVersion { found, supported } => write!(
                f,
                "unsupported law format version {found} (this reader supports versions 1 to {supported})"
            ),
            Error::Truncated { expected, actual } => write!(
                f,
                "truncated law file: {actual} bytes, the header declares {expected}"
            ),
            Error::TrailingBytes { expected, actual } => write!(
                f,
                "law file has trailing bytes: {actual} bytes, the header declares {expected}"
            ),
            Error::Checksum { stored, computed } => write!(
                f,
                "corrupted law file: CRC-32 mismatch (stored {stored:#010x}, computed {computed:#010x})"
            ),
            Error::Metadata { line: 0, message } => write!(f, "law metadata: {message}"),
            Error::Metadata { line, message } => {
                write!(f, "law metadata, line {line}: {message}")
            }
            Error::Invalid { field, message } => write!(f, "invalid {field}: {message}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Failure to evaluate a law at one query point. Plain data: creating it never allocates.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum EvalError {
    /// A query coordinate is NaN or infinite.
    NonFinite {
        /// The axis of the coordinate.
        axis: Axis,
        /// The value given.
        value: f64,
    },
    /// A query coordinate is outside the physical domain (negative pressure or flux,
    /// non-positive temperature, zero pressure with linear extrapolation in `ln p`).
    Invalid {
        /// The axis of the coordinate.
        axis: Axis,
        /// The value given.
        value: f64,
        /// The allowed range.
        expected: &'static str,
    },
    /// A query coordinate is outside the table and the policy is [`crate::Extrapolation::Error`].
    OutOfRange {
        /// The axis of the coordinate.
        axis: Axis,
        /// The value given.
        value: f64,
        /// Smallest tabulated value.
        min: f64,
        /// Largest tabulated value.
        max: f64,
    },
    /// The jump given to [`crate::Law::eval_at_jump`] is NaN, infinite or negative.
    InvalidJump {
        /// The value given.
        value: f64,
    },
    /// The jump given to [`crate::Law::eval_at_jump`] is outside the range the
    /// tabulated flux range produces, and the flux policy is `Error`, or no
    /// non-negative flux reproduces it.
    JumpOutOfRange {
        /// The value given.
        jump: f64,
        /// Jump at the smallest tabulated flux.
        min: f64,
        /// Jump at the largest tabulated flux.
        max: f64,
    },
    /// The interpolated jump is zero, negative or so small that the conductance
    /// `|h̄| / jump` overflows, and no conductance cap is set
    /// ([`crate::EvalOptions::max_conductance`]).
    VanishingJump {
        /// The interpolated jump \[K\].
        jump: f64,
    },
    /// The result overflowed (extreme linear extrapolation, subnormal pressure),
    /// or, in [`crate::Law::eval_at_jump`], the jump does not depend on flux over
    /// the interval that holds it, so the flux is not determined.
    NonFiniteResult,
}

impl fmt::Display for EvalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            EvalError::NonFinite { axis, value } => {
                write!(f, "{axis} query is not finite ({value})")
            }
            EvalError::Invalid {
                axis,
                value,
                expected,
            } => write!(
                f,
                "{axis} query {value} {} is invalid: expected {expected}",
                axis.unit()
            ),
            EvalError::OutOfRange {
                axis,
                value,
                min,
                max,
            } => write!(
                f,
                "{axis} query {value} {unit} is outside the table [{min}, {max}] {unit} \
                 and the extrapolation policy is 'error'",
                unit = axis.unit()
            ),
            EvalError::InvalidJump { value } => {
                write!(
                    f,
                    "jump query {value} K is invalid: expected finite and >= 0"
                )
            }
            EvalError::JumpOutOfRange { jump, min, max } => write!(
                f,
                "jump query {jump} K is not produced by any admissible flux \
                 (jump over the tabulated flux range: {min} to {max} K)"
            ),
            EvalError::VanishingJump { jump } => write!(
                f,
                "interpolated jump {jump} K is not positive (or too small): the conductance \
                 |h|/jump is unbounded; set a conductance cap to get a finite value"
            ),
            EvalError::NonFiniteResult => {
                write!(f, "the evaluation overflowed (extreme extrapolation)")
            }
        }
    }
}

impl std::error::Error for EvalError {}
