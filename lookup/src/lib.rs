//! # lookup — homogenized thermal contact laws for macroscale codes
//!
//! A dependency-free crate (standard library only) that reads a contact law
//! written by the `tcgen` generator and evaluates it: the macroscopic
//! temperature jump `jump = θ̄ − θ̄c` across a rough interface (Temizer 2014,
//! Eq. (2.6)) as a function of the contact pressure `p̄N`, the flux magnitude
//! `|h̄|` and the contact temperature `θ̄c`, and the contact conductance
//! `k̄c = |h̄| / jump` (Eq. (2.7)), with the partial derivatives a macroscale
//! Newton solver needs for its consistent tangent.
//!
//! - File format: `schemas/law.md` ([`Law::open`], [`Law::write`], [`Law::to_bytes`],
//!   [`Law::from_bytes`]): versioned, self-describing, CRC-32 protected; every
//!   malformed input is an [`Error`], never a panic.
//! - Interpolation: Steffen's monotone C1 cubic in `ln p̄N`, piecewise linear in
//!   `|h̄|` and `θ̄c` (tensor product); exact on data linear in `(ln p̄N, |h̄|, θ̄c)`.
//! - Extrapolation per axis: [`Extrapolation::Error`] (the default),
//!   [`Extrapolation::Clamp`], [`Extrapolation::Linear`] or, along pressure,
//!   [`Extrapolation::Power`] (`k̄c ∝ p̄N^m` from the end cells), from the
//!   file, overridable ([`EvalOptions`]).
//! - Each value carries the ensemble spread and, for tables built to a target
//!   error, the estimated discretization error of the jump
//!   ([`Value::jump_error`]); the law records the statistic it tabulates
//!   ([`Statistic`]) and the bulk materials ([`Law::check_material`]).
//! - [`Law::eval`] (known flux) and [`Law::eval_at_jump`] (known temperatures,
//!   the form of an Abaqus `GAPCON` routine) neither allocate nor lock; [`Law`]
//!   is `Send + Sync`.
//! - A C ABI ([`ffi`], header `include/lookup.h`) for Fortran and C codes.
//!
//! Units: SI (Pa, W/m², K, W/(m²·K)). Signs (spec §2): the flux is the magnitude
//! of the heat flowing from body 1 (slave, upper) to body 2 (master, lower);
//! the tabulated jump is ≥ 0.
//!
//! ```
//! use lookup::{Axes, Law, LawInfo};
//! // jump = 1 mK per (W/m²·1e-3), independent of pressure: conductance 1000 W/(m² K)
//! let axes = Axes { pressure: vec![1e3, 1e6], flux: vec![1e3, 1e4], contact_temperature: vec![300.0] };
//! let mean = vec![1.0, 10.0, 1.0, 10.0];
//! let law = Law::from_grid(axes, mean, vec![0.0; 4], LawInfo::default()).unwrap();
//! let v = law.eval(1e4, 5e3, 300.0).unwrap();
//! assert!((v.jump - 5.0).abs() < 1e-12 && (v.conductance - 1e3).abs() < 1e-9);
//! let back = Law::from_bytes(&law.to_bytes()).unwrap();
//! assert_eq!(back, law);
//! ```
#![warn(missing_docs)]

mod at_jump;
mod checksum;
mod error;
pub mod ffi;
mod format;
mod info;
mod interp;
mod law;

pub use at_jump::FluxValue;
pub use checksum::crc32;
pub use error::{Axis, Error, EvalError};
pub use format::{FORMAT_VERSION, HEADER_BYTES, MAGIC, MAX_FILE_BYTES, OLDEST_READ_VERSION};
pub use info::{BodyMaterial, Extrapolation, ExtrapolationPolicy, LawInfo, LawMaterial, Statistic};
pub use law::{Axes, EvalOptions, Law, Value};

/// Compile-time check: a law can be shared between threads.
const _: () = {
    const fn send_sync<T: Send + Sync>() {}
    send_sync::<Law>();
    send_sync::<Value>();
    send_sync::<FluxValue>();
    send_sync::<EvalError>();
    send_sync::<Error>();
};
