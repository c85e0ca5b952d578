//! C ABI (header `include/lookup.h`): an opaque `lookup_law` handle, functions
//! returning a status code (0 on success) and filling caller-owned structs, and
//! a per-thread message of the last failure (`lookup_last_error`). No panic
//! crosses the boundary (each entry point catches unwinding and returns
//! [`LOOKUP_ERR_PANIC`]). Evaluation functions may run concurrently on one
//! handle; `lookup_law_set_*` and `lookup_law_free` must not overlap with other
//! calls on the same handle.

use crate::error::{Error, EvalError};
use crate::info::{Extrapolation, LawInfo, Statistic};
use crate::law::{Axes, Law};
use crate::{Axis, FORMAT_VERSION, FluxValue, Value};
use std::cell::RefCell;
use std::ffi::{CStr, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Success.
pub const LOOKUP_OK: i32 = 0;
/// A required pointer argument is NULL.
pub const LOOKUP_ERR_NULL_ARGUMENT: i32 = 1;
/// The file could not be read or written.
pub const LOOKUP_ERR_IO: i32 = 2;
/// The file is not a valid law file (magic, size, metadata, values).
pub const LOOKUP_ERR_FORMAT: i32 = 3;
/// The file has an unsupported format version.
pub const LOOKUP_ERR_VERSION: i32 = 4;
/// The file is corrupted (checksum mismatch).
pub const LOOKUP_ERR_CHECKSUM: i32 = 5;
/// An argument other than a query is invalid (grid data, axis or policy code, cap).
pub const LOOKUP_ERR_INVALID_ARGUMENT: i32 = 6;
/// A query is NaN or infinite.
pub const LOOKUP_ERR_NON_FINITE: i32 = 7;
/// A query is outside the physical domain (negative pressure, flux or jump, θ ≤ 0).
pub const LOOKUP_ERR_INVALID_QUERY: i32 = 8;
/// A query is outside the table and the extrapolation policy is `error`.
pub const LOOKUP_ERR_OUT_OF_RANGE: i32 = 9;
/// The jump vanishes and no conductance cap is set.
pub const LOOKUP_ERR_VANISHING_JUMP: i32 = 10;
/// The result overflowed.
pub const LOOKUP_ERR_NON_FINITE_RESULT: i32 = 11;
/// An internal panic was caught (a bug: please report it).
pub const LOOKUP_ERR_PANIC: i32 = 12;
/// The caller's material differs from the one the law was built for (or
/// the law records none): `lookup_law_check_material`.
pub const LOOKUP_ERR_MATERIAL_MISMATCH: i32 = 13;

/// Flag bit: the pressure was outside the table.
pub const LOOKUP_FLAG_EXTRAPOLATED_PRESSURE: u32 = 1;
/// Flag bit: the flux was outside the table.
pub const LOOKUP_FLAG_EXTRAPOLATED_FLUX: u32 = 2;
/// Flag bit: the contact temperature was outside the table.
pub const LOOKUP_FLAG_EXTRAPOLATED_CONTACT_TEMPERATURE: u32 = 4;
/// Flag bit: the conductance is the cap.
pub const LOOKUP_FLAG_CONDUCTANCE_CAPPED: u32 = 8;
/// Flag bit: the law carries no discretization-error estimate (`jump_error` is 0).
pub const LOOKUP_FLAG_NO_ERROR_ESTIMATE: u32 = 16;

/// Axis code meaning "every axis" in `lookup_law_set_extrapolation`.
pub const LOOKUP_AXIS_ALL: i32 = -1;

/// Opaque handle of a law (`lookup_law` in C).
pub struct LookupLaw(Law);

/// C mirror of [`Value`] (`lookup_value`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LookupValue {
    /// See [`Value::flux`].
    pub flux: f64,
    /// See [`Value::jump`].
    pub jump: f64,
    /// See [`Value::jump_std`].
    pub jump_std: f64,
    /// See [`Value::jump_error`].
    pub jump_error: f64,
    /// See [`Value::d_jump_dp`].
    pub d_jump_dp: f64,
    /// See [`Value::d_jump_dh`].
    pub d_jump_dh: f64,
    /// See [`Value::d_jump_dtheta`].
    pub d_jump_dtheta: f64,
    /// See [`Value::conductance`].
    pub conductance: f64,
    /// See [`Value::d_conductance_dp`].
    pub d_conductance_dp: f64,
    /// See [`Value::d_conductance_dh`].
    pub d_conductance_dh: f64,
    /// See [`Value::d_conductance_dtheta`].
    pub d_conductance_dtheta: f64,
    /// `LOOKUP_FLAG_*` bits.
    pub flags: u32,
    /// Always 0.
    pub reserved: u32,
}

/// C mirror of [`FluxValue`] (`lookup_flux_value`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LookupFluxValue {
    /// See [`FluxValue::flux`].
    pub flux: f64,
    /// See [`FluxValue::jump_std`].
    pub jump_std: f64,
    /// See [`FluxValue::jump_error`].
    pub jump_error: f64,
    /// See [`FluxValue::conductance`].
    pub conductance: f64,
    /// See [`FluxValue::d_flux_dp`].
    pub d_flux_dp: f64,
    /// See [`FluxValue::d_flux_djump`].
    pub d_flux_djump: f64,
    /// See [`FluxValue::d_flux_dtheta`].
    pub d_flux_dtheta: f64,
    /// See [`FluxValue::d_conductance_dp`].
    pub d_conductance_dp: f64,
    /// See [`FluxValue::d_conductance_djump`].
    pub d_conductance_djump: f64,
    /// See [`FluxValue::d_conductance_dtheta`].
    pub d_conductance_dtheta: f64,
    /// `LOOKUP_FLAG_*` bits.
    pub flags: u32,
    /// Always 0.
    pub reserved: u32,
}

fn flags(extrapolated: [bool; 3], capped: bool, error_estimated: bool) -> u32 {
    let mut f = if error_estimated {
        0
    } else {
        LOOKUP_FLAG_NO_ERROR_ESTIMATE
    };
    for (i, &e) in extrapolated.iter().enumerate() {
        if e {
            f |= 1 << i;
        }
    }
    if capped {
        f |= LOOKUP_FLAG_CONDUCTANCE_CAPPED;
    }
    f
}

impl LookupValue {
    /// The C value of `v` from a law with or without an error estimate.
    pub fn new(v: Value, error_estimated: bool) -> Self {
        LookupValue {
            flux: v.flux,
            jump: v.jump,
            jump_std: v.jump_std,
            jump_error: v.jump_error,
            d_jump_dp: v.d_jump_dp,
            d_jump_dh: v.d_jump_dh,
            d_jump_dtheta: v.d_jump_dtheta,
            conductance: v.conductance,
            d_conductance_dp: v.d_conductance_dp,
            d_conductance_dh: v.d_conductance_dh,
            d_conductance_dtheta: v.d_conductance_dtheta,
            flags: flags(v.extrapolated, v.conductance_capped, error_estimated),
            reserved: 0,
        }
    }
}

impl LookupFluxValue {
    /// The C value of `v` from a law with or without an error estimate.
    pub fn new(v: FluxValue, error_estimated: bool) -> Self {
        LookupFluxValue {
            flux: v.flux,
            jump_std: v.jump_std,
            jump_error: v.jump_error,
            conductance: v.conductance,
            d_flux_dp: v.d_flux_dp,
            d_flux_djump: v.d_flux_djump,
            d_flux_dtheta: v.d_flux_dtheta,
            d_conductance_dp: v.d_conductance_dp,
            d_conductance_djump: v.d_conductance_djump,
            d_conductance_dtheta: v.d_conductance_dtheta,
            flags: flags(v.extrapolated, v.conductance_capped, error_estimated),
            reserved: 0,
        }
    }
}

enum LastError {
    None,
    Eval(EvalError),
    Message(String),
}

thread_local! {
    static LAST_ERROR: RefCell<LastError> = const { RefCell::new(LastError::None) };
}

fn set_last(e: LastError) {
    LAST_ERROR.with(|l| {
        if let Ok(mut l) = l.try_borrow_mut() {
            *l = e;
        }
    });
}

fn file_error(e: Error) -> i32 {
    let code = match &e {
        Error::Io { .. } => LOOKUP_ERR_IO,
        Error::UnsupportedVersion { .. } => LOOKUP_ERR_VERSION,
        Error::Checksum { .. } => LOOKUP_ERR_CHECKSUM,
        Error::Invalid { .. } => LOOKUP_ERR_INVALID_ARGUMENT,
        _ => LOOKUP_ERR_FORMAT,
    };
    set_last(LastError::Message(e.to_string()));
    code
}

fn eval_error(e: EvalError) -> i32 {
    let code = match e {
        EvalError::NonFinite { .. } => LOOKUP_ERR_NON_FINITE,
        EvalError::Invalid { .. } | EvalError::InvalidJump { .. } => LOOKUP_ERR_INVALID_QUERY,
        EvalError::OutOfRange { .. } | EvalError::JumpOutOfRange { .. } => LOOKUP_ERR_OUT_OF_RANGE,
        EvalError::VanishingJump { .. } => LOOKUP_ERR_VANISHING_JUMP,
        EvalError::NonFiniteResult => LOOKUP_ERR_NON_FINITE_RESULT,
    };
    set_last(LastError::Eval(e));
    code
}

fn fail(code: i32, message: &str) -> i32 {
    set_last(LastError::Message(message.to_string()));
    code
}

/// Stores a built law as a new handle in `law`; the status code.
fn into_handle(built: Result<Law, Error>, law: &mut *mut LookupLaw) -> i32 {
    match built {
        Ok(l) => {
            *law = Box::into_raw(Box::new(LookupLaw(l)));
            LOOKUP_OK
        }
        Err(e) => file_error(e),
    }
}

/// Runs `f`, turning a panic into [`LOOKUP_ERR_PANIC`].
fn guard(f: impl FnOnce() -> i32) -> i32 {
    catch_unwind(AssertUnwindSafe(f))
        .unwrap_or_else(|_| fail(LOOKUP_ERR_PANIC, "internal panic in lookup (a bug)"))
}

/// Writes `code` to `status` if it is not NULL.
unsafe fn put_status(status: *mut i32, code: i32) {
    if !status.is_null() {
        // SAFETY: the caller passes NULL or a valid pointer.
        unsafe { *status = code };
    }
}

/// Path argument as a `&str` (UTF-8 required).
unsafe fn path_arg<'a>(path: *const c_char) -> Result<&'a str, i32> {
    if path.is_null() {
        return Err(fail(LOOKUP_ERR_NULL_ARGUMENT, "path is NULL"));
    }
    // SAFETY: the caller passes a NUL-terminated string.
    let c = unsafe { CStr::from_ptr(path) };
    c.to_str()
        .map_err(|_| fail(LOOKUP_ERR_INVALID_ARGUMENT, "path is not valid UTF-8"))
}

fn policy_from_code(code: i32) -> Option<Extrapolation> {
    match code {
        0 => Some(Extrapolation::Error),
        1 => Some(Extrapolation::Clamp),
        2 => Some(Extrapolation::Linear),
        3 => Some(Extrapolation::Power),
        _ => None,
    }
}

/// Opens a law file. Returns NULL on failure; `*status` (if not NULL) gets the status code.
///
/// # Safety
/// `path` is a NUL-terminated string; `status` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_open(path: *const c_char, status: *mut i32) -> *mut LookupLaw {
    let mut law = std::ptr::null_mut();
    let code = guard(|| {
        // SAFETY: forwarded from the caller.
        let path = match unsafe { path_arg(path) } {
            Ok(p) => p,
            Err(code) => return code,
        };
        into_handle(Law::open(path), &mut law)
    });
    // SAFETY: forwarded from the caller.
    unsafe { put_status(status, code) };
    law
}

/// Builds a law from a grid (see `Law::from_grid`): `jump_mean` and `jump_std`
/// hold `n_p·n_h·n_theta` values, contact temperature fastest. `jump_std` may be
/// NULL (all zero). `ensemble_size` 0 means a deterministic law, ≥ 1 an ensemble
/// mean over that many samples. `extrapolation` is the policy code of every axis.
///
/// # Safety
/// Each array pointer is valid for its length; `status` is NULL or writable.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn lookup_law_from_grid(
    n_p: usize,
    pressure: *const f64,
    n_h: usize,
    flux: *const f64,
    n_theta: usize,
    contact_temperature: *const f64,
    jump_mean: *const f64,
    jump_std: *const f64,
    ensemble_size: u32,
    extrapolation: i32,
    status: *mut i32,
) -> *mut LookupLaw {
    let mut law = std::ptr::null_mut();
    let code = guard(|| {
        if pressure.is_null()
            || flux.is_null()
            || contact_temperature.is_null()
            || jump_mean.is_null()
        {
            return fail(
                LOOKUP_ERR_NULL_ARGUMENT,
                "an axis or jump_mean pointer is NULL",
            );
        }
        let Some(n) = n_p.checked_mul(n_h).and_then(|n| n.checked_mul(n_theta)) else {
            return fail(LOOKUP_ERR_INVALID_ARGUMENT, "table size overflows");
        };
        let Some(policy) = policy_from_code(extrapolation) else {
            return fail(
                LOOKUP_ERR_INVALID_ARGUMENT,
                "extrapolation code not in {0, 1, 2}",
            );
        };
        // SAFETY: the caller guarantees the lengths.
        let slice =
            |ptr: *const f64, len: usize| unsafe { std::slice::from_raw_parts(ptr, len) }.to_vec();
        let axes = Axes {
            pressure: slice(pressure, n_p),
            flux: slice(flux, n_h),
            contact_temperature: slice(contact_temperature, n_theta),
        };
        let mean = slice(jump_mean, n);
        let std = if jump_std.is_null() {
            vec![0.0; n]
        } else {
            slice(jump_std, n)
        };
        let info = LawInfo {
            statistic: match ensemble_size {
                0 => Statistic::Deterministic,
                samples => Statistic::EnsembleMean { samples },
            },
            extrapolation: crate::ExtrapolationPolicy::uniform(policy),
            material: None,
            provenance: vec![("generator".into(), "lookup C ABI".into())],
        };
        into_handle(Law::from_grid(axes, mean, std, info), &mut law)
    });
    // SAFETY: forwarded from the caller.
    unsafe { put_status(status, code) };
    law
}

/// Writes the law to a file.
///
/// # Safety
/// `law` is NULL or a live handle; `path` is a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_write(law: *const LookupLaw, path: *const c_char) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(law) = (unsafe { law.as_ref() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law is NULL");
        };
        // SAFETY: forwarded from the caller.
        let path = match unsafe { path_arg(path) } {
            Ok(p) => p,
            Err(code) => return code,
        };
        match law.0.write(path) {
            Ok(()) => LOOKUP_OK,
            Err(e) => file_error(e),
        }
    })
}

/// Evaluates the law at pressure `p` \[Pa\], flux magnitude `h` \[W/m²\] and
/// contact temperature `theta` \[K\]. On failure `*out` is zeroed.
///
/// # Safety
/// `law` is NULL or a live handle; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_eval(
    law: *const LookupLaw,
    p: f64,
    h: f64,
    theta: f64,
    out: *mut LookupValue,
) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or valid pointers.
        let (Some(law), Some(out)) = (unsafe { law.as_ref() }, unsafe { out.as_mut() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law or out is NULL");
        };
        match law.0.eval(p, h, theta) {
            Ok(v) => {
                *out = LookupValue::new(v, law.0.error_estimated());
                LOOKUP_OK
            }
            Err(e) => {
                *out = LookupValue::default();
                eval_error(e)
            }
        }
    })
}

/// Finds the flux magnitude producing the temperature jump `jump` \[K\] at
/// pressure `p` \[Pa\] and contact temperature `theta` \[K\], and the conductance
/// there with its derivatives at fixed jump. On failure `*out` is zeroed.
///
/// # Safety
/// `law` is NULL or a live handle; `out` is NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_eval_at_jump(
    law: *const LookupLaw,
    p: f64,
    jump: f64,
    theta: f64,
    out: *mut LookupFluxValue,
) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or valid pointers.
        let (Some(law), Some(out)) = (unsafe { law.as_ref() }, unsafe { out.as_mut() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law or out is NULL");
        };
        match law.0.eval_at_jump(p, jump, theta) {
            Ok(v) => {
                *out = LookupFluxValue::new(v, law.0.error_estimated());
                LOOKUP_OK
            }
            Err(e) => {
                *out = LookupFluxValue::default();
                eval_error(e)
            }
        }
    })
}

/// Overrides the extrapolation policy of `axis` (0 pressure, 1 flux, 2 contact
/// temperature, -1 all) with `policy` (0 error, 1 clamp, 2 linear, 3 power:
/// pressure only).
///
/// # Safety
/// `law` is NULL or a live handle not used concurrently.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_set_extrapolation(
    law: *mut LookupLaw,
    axis: i32,
    policy: i32,
) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(law) = (unsafe { law.as_mut() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law is NULL");
        };
        let Some(policy) = policy_from_code(policy) else {
            return fail(
                LOOKUP_ERR_INVALID_ARGUMENT,
                "extrapolation code not in {0, 1, 2, 3}",
            );
        };
        let mut p = law.0.options().extrapolation;
        if axis == LOOKUP_AXIS_ALL {
            p = crate::ExtrapolationPolicy::uniform(policy);
        } else if let Some(a) = usize::try_from(axis).ok().and_then(Axis::from_index) {
            p.set(a, policy);
        } else {
            return fail(
                LOOKUP_ERR_INVALID_ARGUMENT,
                "axis code not in {-1, 0, 1, 2}",
            );
        }
        match law.0.set_extrapolation(p) {
            Ok(()) => LOOKUP_OK,
            Err(e) => file_error(e),
        }
    })
}

/// Checks the caller's material of `body` (1: body 1, slave, upper; 2: body
/// 2, master, lower) against the one the law was built for. `properties`
/// holds 6 values in SI: Young's modulus E \[Pa\], Poisson's ratio ν,
/// thermal expansion α0 \[1/K\], conductivity k0 \[W/(m·K)\], conductivity
/// slope k1 \[W/(m·K²)\], reference temperature θ0 \[K\]. Returns
/// `LOOKUP_ERR_MATERIAL_MISMATCH` (the message names the property) when one
/// differs by more than `rel_tol` relative, or when the law records no material.
///
/// # Safety
/// `law` is NULL or a live handle; `properties` is NULL or readable for 6 doubles.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_check_material(
    law: *const LookupLaw,
    body: i32,
    properties: *const f64,
    rel_tol: f64,
) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(law) = (unsafe { law.as_ref() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law is NULL");
        };
        if properties.is_null() {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "properties is NULL");
        }
        let name = match body {
            1 => "upper",
            2 => "lower",
            _ => return fail(LOOKUP_ERR_INVALID_ARGUMENT, "body code not in {1, 2}"),
        };
        if !(rel_tol.is_finite() && rel_tol >= 0.0) {
            return fail(
                LOOKUP_ERR_INVALID_ARGUMENT,
                "rel_tol: expected finite and >= 0",
            );
        }
        let mut v = [0.0; 6];
        // SAFETY: the caller passes 6 readable doubles.
        v.copy_from_slice(unsafe { std::slice::from_raw_parts(properties, 6) });
        match law
            .0
            .check_material(name, &crate::BodyMaterial::from_values(v), rel_tol)
        {
            Ok(()) => LOOKUP_OK,
            Err(e) => {
                set_last(LastError::Message(e.to_string()));
                LOOKUP_ERR_MATERIAL_MISMATCH
            }
        }
    })
}

/// Sets the conductance cap `k_max` \[W/(m²·K)\] (finite, > 0), or removes it when `k_max == 0`.
///
/// # Safety
/// `law` is NULL or a live handle not used concurrently.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_set_max_conductance(law: *mut LookupLaw, k_max: f64) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(law) = (unsafe { law.as_mut() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law is NULL");
        };
        let cap = if k_max == 0.0 { None } else { Some(k_max) };
        match law.0.set_max_conductance(cap) {
            Ok(()) => LOOKUP_OK,
            Err(e) => file_error(e),
        }
    })
}

/// Number of nodes and range of one axis (0 pressure, 1 flux, 2 contact temperature).
///
/// # Safety
/// `law` is NULL or a live handle; `n`, `min`, `max` are NULL or writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_axis(
    law: *const LookupLaw,
    axis: i32,
    n: *mut usize,
    min: *mut f64,
    max: *mut f64,
) -> i32 {
    guard(|| {
        // SAFETY: the caller passes NULL or a live handle.
        let Some(law) = (unsafe { law.as_ref() }) else {
            return fail(LOOKUP_ERR_NULL_ARGUMENT, "law is NULL");
        };
        let Some(a) = usize::try_from(axis).ok().and_then(Axis::from_index) else {
            return fail(LOOKUP_ERR_INVALID_ARGUMENT, "axis code not in {0, 1, 2}");
        };
        let nodes = law.0.axes().get(a);
        // SAFETY: each pointer is NULL or writable.
        unsafe {
            if let Some(n) = n.as_mut() {
                *n = nodes.len();
            }
            if let Some(min) = min.as_mut() {
                *min = nodes[0];
            }
            if let Some(max) = max.as_mut() {
                *max = nodes[nodes.len() - 1];
            }
        }
        LOOKUP_OK
    })
}

/// Frees a law (NULL is ignored).
///
/// # Safety
/// `law` is NULL or a handle from `lookup_law_open`/`lookup_law_from_grid`, not yet freed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_law_free(law: *mut LookupLaw) {
    if !law.is_null() {
        // SAFETY: the handle came from Box::into_raw and is freed once.
        let _ = catch_unwind(AssertUnwindSafe(|| drop(unsafe { Box::from_raw(law) })));
    }
}

/// Copies the message of the last failing call in this thread into `buf`
/// (NUL-terminated, truncated to `len − 1` bytes) and returns the full message
/// length in bytes (without NUL), like `snprintf`. Returns 0 if no call failed.
///
/// # Safety
/// `buf` is NULL (then `len` must be 0) or writable for `len` bytes.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn lookup_last_error(buf: *mut c_char, len: usize) -> usize {
    catch_unwind(AssertUnwindSafe(|| {
        let message = LAST_ERROR.with(|l| match &*l.borrow() {
            LastError::None => String::new(),
            LastError::Eval(e) => e.to_string(),
            LastError::Message(m) => m.clone(),
        });
        if !buf.is_null() && len > 0 {
            let k = message.len().min(len - 1);
            // SAFETY: buf is writable for len bytes, k < len.
            unsafe {
                std::ptr::copy_nonoverlapping(message.as_ptr(), buf.cast::<u8>(), k);
                *buf.add(k) = 0;
            }
        }
        message.len()
    }))
    .unwrap_or(0)
}

/// A static name of a status code (e.g. `"LOOKUP_ERR_OUT_OF_RANGE"`).
#[unsafe(no_mangle)]
pub extern "C" fn lookup_status_name(status: i32) -> *const c_char {
    let s: &'static CStr = match status {
        LOOKUP_OK => c"LOOKUP_OK",
        LOOKUP_ERR_NULL_ARGUMENT => c"LOOKUP_ERR_NULL_ARGUMENT",
        LOOKUP_ERR_IO => c"LOOKUP_ERR_IO",
        LOOKUP_ERR_FORMAT => c"LOOKUP_ERR_FORMAT",
        LOOKUP_ERR_VERSION => c"LOOKUP_ERR_VERSION",
        LOOKUP_ERR_CHECKSUM => c"LOOKUP_ERR_CHECKSUM",
        LOOKUP_ERR_INVALID_ARGUMENT => c"LOOKUP_ERR_INVALID_ARGUMENT",
        LOOKUP_ERR_NON_FINITE => c"LOOKUP_ERR_NON_FINITE",
        LOOKUP_ERR_INVALID_QUERY => c"LOOKUP_ERR_INVALID_QUERY",
        LOOKUP_ERR_OUT_OF_RANGE => c"LOOKUP_ERR_OUT_OF_RANGE",
        LOOKUP_ERR_VANISHING_JUMP => c"LOOKUP_ERR_VANISHING_JUMP",
        LOOKUP_ERR_NON_FINITE_RESULT => c"LOOKUP_ERR_NON_FINITE_RESULT",
        LOOKUP_ERR_PANIC => c"LOOKUP_ERR_PANIC",
        LOOKUP_ERR_MATERIAL_MISMATCH => c"LOOKUP_ERR_MATERIAL_MISMATCH",
        _ => c"LOOKUP_UNKNOWN_STATUS",
    };
    s.as_ptr()
}

/// The law file format version this library reads and writes.
#[unsafe(no_mangle)]
pub extern "C" fn lookup_format_version() -> u32 {
    FORMAT_VERSION
}
