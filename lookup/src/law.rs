//! The law: a validated table `jump(p̄N, |h̄|, θ̄c)` with its spread, and its
//! evaluation with derivatives (value, conductance `k̄c = |h̄| / jump`, paper
//! Eq. (2.7), and their partial derivatives for a consistent Newton tangent).

use crate::error::{Axis, Error, EvalError};
use crate::info::{ExtrapolationPolicy, LawInfo, Statistic, validate_provenance};
use crate::interp::{
    HermiteWeights, LinearWeights, inverse_widths, linear_weights, log_hermite_weights,
    steffen_slopes,
};

/// The three axes of a table, each strictly increasing, in SI units.
#[derive(Clone, Debug, PartialEq)]
pub struct Axes {
    /// Contact pressure `p̄N` \[Pa\], all > 0.
    pub pressure: Vec<f64>,
    /// Flux magnitude `|h̄|` \[W/m²\], all > 0.
    pub flux: Vec<f64>,
    /// Contact temperature `θ̄c` \[K\], all > 0.
    pub contact_temperature: Vec<f64>,
}

impl Axes {
    /// The nodes of one axis.
    pub fn get(&self, axis: Axis) -> &[f64] {
        match axis {
            Axis::Pressure => &self.pressure,
            Axis::Flux => &self.flux,
            Axis::ContactTemperature => &self.contact_temperature,
        }
    }

    /// Number of table entries `n_p · n_h · n_θ`.
    pub fn len(&self) -> usize {
        self.pressure.len() * self.flux.len() * self.contact_temperature.len()
    }

    /// True when some axis is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Caller options of an evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvalOptions {
    /// Extrapolation policy of each axis (the file's by default).
    pub extrapolation: ExtrapolationPolicy,
    /// Cap on the conductance \[W/(m²·K)\]. `None` (default): a vanishing jump is
    /// an error ([`EvalError::VanishingJump`]). `Some(k_max)`: the conductance is
    /// `min(|h̄|/jump, k_max)`, `k_max` also where the jump is ≤ 0; where the cap
    /// is active its derivatives are 0 and [`Value::conductance_capped`] is set.
    pub max_conductance: Option<f64>,
}

/// The law evaluated at one point `(p̄N, |h̄|, θ̄c)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Value {
    /// Flux magnitude `|h̄|` at which the conductance is evaluated \[W/m²\]
    /// (the query, or the table bound when the flux is clamped).
    pub flux: f64,
    /// Temperature jump `θ̄ − θ̄c` \[K\], paper Eq. (2.6): the tabulated statistic, interpolated.
    pub jump: f64,
    /// Standard deviation of the jump over the ensemble \[K\], interpolated (≥ 0).
    pub jump_std: f64,
    /// Estimated discretization error of the tabulated jump \[K\], interpolated
    /// (≥ 0; 0 when the law carries no estimate, see [`Law::error_estimated`]).
    pub jump_error: f64,
    /// ∂ jump / ∂ p̄N \[K/Pa\].
    pub d_jump_dp: f64,
    /// ∂ jump / ∂ |h̄| \[K·m²/W\].
    pub d_jump_dh: f64,
    /// ∂ jump / ∂ θ̄c \[–\].
    pub d_jump_dtheta: f64,
    /// Contact conductance `k̄c = |h̄| / jump` \[W/(m²·K)\], Eq. (2.7).
    pub conductance: f64,
    /// ∂ k̄c / ∂ p̄N.
    pub d_conductance_dp: f64,
    /// ∂ k̄c / ∂ |h̄|.
    pub d_conductance_dh: f64,
    /// ∂ k̄c / ∂ θ̄c.
    pub d_conductance_dtheta: f64,
    /// Whether each axis (indexed by [`Axis`] as `usize`) was outside the table.
    pub extrapolated: [bool; 3],
    /// Whether the conductance is the cap [`EvalOptions::max_conductance`].
    pub conductance_capped: bool,
}

/// A contact law: the tabulated jump and its spread on a `(p̄N, |h̄|, θ̄c)` grid,
/// interpolated with Steffen's monotone C1 cubic in `ln p̄N` and linearly in
/// `|h̄|` and `θ̄c` (tensor product). Immutable once built except for the
/// caller options; `Send + Sync`; [`Law::eval`] neither allocates nor locks.
#[derive(Clone, Debug, PartialEq)]
pub struct Law {
    pub(crate) axes: Axes,
    pub(crate) log_pressure: Vec<f64>,
    /// `1 / width` of each interval of `ln p`, flux and contact temperature.
    pub(crate) inv_widths: [Vec<f64>; 3],
    pub(crate) jump_mean: Vec<f64>,
    pub(crate) jump_std: Vec<f64>,
    /// Estimated discretization error of each entry (zeros when not estimated).
    pub(crate) jump_error: Vec<f64>,
    pub(crate) error_estimated: bool,
    /// Per entry: `[jump, d jump/d ln p, std, d std/d ln p, error, d error/d ln p]`
    /// (Steffen slopes).
    pub(crate) nodes: Vec<[f64; 6]>,
    pub(crate) info: LawInfo,
    pub(crate) options: EvalOptions,
}

fn check_axis(axis: Axis, v: &[f64]) -> Result<(), Error> {
    let name = axis.name();
    if v.is_empty() {
        return Err(Error::invalid(
            name,
            "axis has no node; expected at least 1",
        ));
    }
    if v.len() > u32::MAX as usize {
        return Err(Error::invalid(name, "axis has more than 2^32 - 1 nodes"));
    }
    for (i, &x) in v.iter().enumerate() {
        if !(x.is_finite() && x > 0.0) {
            return Err(Error::invalid(
                format!("{name}[{i}]"),
                format!("{x} {}: expected finite and > 0", axis.unit()),
            ));
        }
        if i > 0 && x <= v[i - 1] {
            return Err(Error::invalid(
                format!("{name}[{i}]"),
                format!(
                    "{x} <= {name}[{}] = {}: axis must be strictly increasing",
                    i - 1,
                    v[i - 1]
                ),
            ));
        }
    }
    Ok(())
}

fn check_values(field: &str, v: &[f64], expected_len: usize) -> Result<(), Error> {
    if v.len() != expected_len {
        return Err(Error::invalid(
            field,
            format!(
                "{} entries; the axes need n_p·n_h·n_θ = {expected_len}",
                v.len()
            ),
        ));
    }
    for (i, &x) in v.iter().enumerate() {
        if !(x.is_finite() && x >= 0.0) {
            return Err(Error::invalid(
                format!("{field}[{i}]"),
                format!("{x} K: expected finite and >= 0"),
            ));
        }
    }
    Ok(())
}

impl Law {
    /// Builds a law from its grid: `jump_mean` and `jump_std` \[K\] in row-major
    /// order `[pressure][flux][contact_temperature]` (contact temperature
    /// fastest), `n_p · n_h · n_θ` entries each, finite and ≥ 0.
    ///
    /// The options are the file defaults: `info.extrapolation`, no conductance cap.
    /// The law carries no discretization-error estimate
    /// ([`Law::from_grid_with_error`] gives one).
    pub fn from_grid(
        axes: Axes,
        jump_mean: Vec<f64>,
        jump_std: Vec<f64>,
        info: LawInfo,
    ) -> Result<Law, Error> {
        Law::from_grid_with_error(axes, jump_mean, jump_std, None, info)
    }

    /// [`Law::from_grid`] with the estimated discretization error of each
    /// entry \[K\] (same layout, finite, ≥ 0), or `None` when not estimated.
    pub fn from_grid_with_error(
        axes: Axes,
        jump_mean: Vec<f64>,
        jump_std: Vec<f64>,
        jump_error: Option<Vec<f64>>,
        info: LawInfo,
    ) -> Result<Law, Error> {
        for axis in Axis::ALL {
            check_axis(axis, axes.get(axis))?;
        }
        let len = axes
            .pressure
            .len()
            .checked_mul(axes.flux.len())
            .and_then(|n| n.checked_mul(axes.contact_temperature.len()))
            .ok_or_else(|| Error::invalid("axes", "table size overflows"))?;
        check_values("jump_mean", &jump_mean, len)?;
        check_values("jump_std", &jump_std, len)?;
        let error_estimated = jump_error.is_some();
        let jump_error = jump_error.unwrap_or_else(|| vec![0.0; len]);
        check_values("jump_error", &jump_error, len)?;
        if info.statistic.samples() == 0 {
            return Err(Error::invalid("ensemble_size", "0: expected >= 1"));
        }
        if let Statistic::EnsembleQuantile { percent, .. } = info.statistic
            && !(1..=99).contains(&percent)
        {
            return Err(Error::invalid(
                "statistic.percent",
                format!("{percent}: expected 1..=99"),
            ));
        }
        info.extrapolation.validate()?;
        if info.statistic.samples() == 1
            && let Some(i) = jump_std.iter().position(|&s| s != 0.0)
        {
            return Err(Error::invalid(
                format!("jump_std[{i}]"),
                format!("{}: a single sample has zero spread", jump_std[i]),
            ));
        }
        validate_provenance(&info.provenance)?;

        let log_pressure: Vec<f64> = axes.pressure.iter().map(|p| p.ln()).collect();
        let (np, stride) = (axes.pressure.len(), len / axes.pressure.len());
        let mut nodes = vec![[0.0; 6]; len];
        let mut line = vec![0.0; np];
        for offset in 0..stride {
            for (data, field) in [(&jump_mean, 0), (&jump_std, 2), (&jump_error, 4)] {
                let slope = field + 1;
                for (i, l) in line.iter_mut().enumerate() {
                    *l = data[i * stride + offset];
                }
                let m = steffen_slopes(&log_pressure, &line);
                for i in 0..np {
                    nodes[i * stride + offset][field] = line[i];
                    nodes[i * stride + offset][slope] = m[i];
                }
            }
        }
        let options = EvalOptions {
            extrapolation: info.extrapolation,
            max_conductance: None,
        };
        let inv_widths = [
            inverse_widths(&log_pressure),
            inverse_widths(&axes.flux),
            inverse_widths(&axes.contact_temperature),
        ];
        Ok(Law {
            axes,
            log_pressure,
            inv_widths,
            jump_mean,
            jump_std,
            jump_error,
            error_estimated,
            nodes,
            info,
            options,
        })
    }

    /// The estimated discretization error of each entry \[K\], same layout
    /// (zeros when [`Law::error_estimated`] is false).
    pub fn jump_error(&self) -> &[f64] {
        &self.jump_error
    }

    /// Whether the law carries a discretization-error estimate (tables built
    /// with `[discretization] target_error`).
    pub fn error_estimated(&self) -> bool {
        self.error_estimated
    }

    /// Checks the caller's material of body `"upper"` (1, slave) or
    /// `"lower"` (2, master) against the one recorded in the law: an error
    /// names the first property differing by more than `rel_tol`, or says
    /// that the law records no material.
    pub fn check_material(
        &self,
        body: &str,
        material: &crate::BodyMaterial,
        rel_tol: f64,
    ) -> Result<(), Error> {
        let Some(recorded) = self.info.material.as_ref() else {
            return Err(Error::invalid(
                "material",
                "the law records no material (built by hand or a version-1 file)",
            ));
        };
        let Some(law) = recorded.body(body) else {
            return Err(Error::invalid(
                "body",
                format!("{body:?}: expected \"upper\" or \"lower\""),
            ));
        };
        match law.mismatch(material, rel_tol) {
            None => Ok(()),
            Some((name, a, b)) => Err(Error::invalid(
                format!("material.{body}.{name}"),
                format!(
                    "the law was built for {a}, the caller has {b} (relative tolerance {rel_tol})"
                ),
            )),
        }
    }

    /// The axes.
    pub fn axes(&self) -> &Axes {
        &self.axes
    }

    /// The tabulated jump statistic \[K\], row-major `[pressure][flux][contact_temperature]`.
    pub fn jump_mean(&self) -> &[f64] {
        &self.jump_mean
    }

    /// The tabulated standard deviation of the jump \[K\], same layout.
    pub fn jump_std(&self) -> &[f64] {
        &self.jump_std
    }

    /// What the file says besides the numbers (statistic, default extrapolation, provenance).
    pub fn info(&self) -> &LawInfo {
        &self.info
    }

    /// The options [`Law::eval`] uses.
    pub fn options(&self) -> EvalOptions {
        self.options
    }

    /// Replaces the options [`Law::eval`] uses (the caller's override of the file's policy).
    pub fn set_options(&mut self, options: EvalOptions) -> Result<(), Error> {
        options.extrapolation.validate()?;
        if let Some(k) = options.max_conductance
            && !(k.is_finite() && k > 0.0)
        {
            return Err(Error::invalid(
                "max_conductance",
                format!("{k} W/(m^2 K): expected finite and > 0"),
            ));
        }
        self.options = options;
        Ok(())
    }

    /// Overrides the extrapolation policy (`power` is allowed on pressure only).
    pub fn set_extrapolation(&mut self, policy: ExtrapolationPolicy) -> Result<(), Error> {
        policy.validate()?;
        self.options.extrapolation = policy;
        Ok(())
    }

    /// Sets or removes the conductance cap (see [`EvalOptions::max_conductance`]).
    pub fn set_max_conductance(&mut self, k_max: Option<f64>) -> Result<(), Error> {
        self.set_options(EvalOptions {
            max_conductance: k_max,
            ..self.options
        })
    }

    /// Evaluates the law at contact pressure `p` \[Pa\], flux magnitude `h` \[W/m²\]
    /// and contact temperature `theta` \[K\] with the law's options.
    #[inline]
    pub fn eval(&self, p: f64, h: f64, theta: f64) -> Result<Value, EvalError> {
        self.eval_with(p, h, theta, &self.options)
    }

    /// Evaluates the law with explicit options. Errors: non-finite queries,
    /// `p < 0`, `h < 0`, `theta <= 0`, out of range under policy `error`, a
    /// vanishing jump without a conductance cap. Never allocates.
    ///
    /// The law is C1 along pressure and C0 along flux and temperature: at an
    /// interior flux or temperature node the derivative along that axis is the
    /// one of the interval above the node.
    #[inline]
    pub fn eval_with(
        &self,
        p: f64,
        h: f64,
        theta: f64,
        options: &EvalOptions,
    ) -> Result<Value, EvalError> {
        let (wp, wh, wt) = self.weights(p, h, theta, options)?;
        let corners = self.corners(&wp, &wh, &wt);
        let jump = corners.value;
        let mut v = Value {
            flux: wh.q_eff,
            jump,
            jump_std: corners.std.max(0.0),
            jump_error: corners.error.max(0.0),
            d_jump_dp: corners.d_dx * wp.dx_dp,
            d_jump_dh: corners.d_dh,
            d_jump_dtheta: corners.d_dtheta,
            extrapolated: [wp.extrapolated, wh.extrapolated, wt.extrapolated],
            ..Value::default()
        };
        let jump_part = [
            v.jump,
            v.jump_std,
            v.jump_error,
            v.d_jump_dp,
            v.d_jump_dh,
            v.d_jump_dtheta,
        ];
        if !jump_part.iter().all(|x| x.is_finite()) {
            return Err(EvalError::NonFiniteResult);
        }
        let inv_jump = 1.0 / jump;
        let k = wh.q_eff * inv_jump;
        let d = [
            -k * v.d_jump_dp * inv_jump,
            (wh.dq_eff - k * v.d_jump_dh) * inv_jump,
            -k * v.d_jump_dtheta * inv_jump,
        ];
        let computable = jump > 0.0 && k.is_finite() && d.iter().all(|x| x.is_finite());
        match options.max_conductance {
            Some(k_max) if !computable || k > k_max => {
                v.conductance = k_max;
                v.conductance_capped = true;
            }
            _ if !computable => return Err(EvalError::VanishingJump { jump }),
            _ => {
                v.conductance = k;
                [
                    v.d_conductance_dp,
                    v.d_conductance_dh,
                    v.d_conductance_dtheta,
                ] = d;
            }
        }
        Ok(v)
    }

    /// Checks the query and brackets it on the three axes.
    #[inline]
    pub(crate) fn weights(
        &self,
        p: f64,
        h: f64,
        theta: f64,
        options: &EvalOptions,
    ) -> Result<(HermiteWeights, LinearWeights, LinearWeights), EvalError> {
        for (axis, value) in [
            (Axis::Pressure, p),
            (Axis::Flux, h),
            (Axis::ContactTemperature, theta),
        ] {
            if !value.is_finite() {
                return Err(EvalError::NonFinite { axis, value });
            }
        }
        if p < 0.0 {
            return Err(EvalError::Invalid {
                axis: Axis::Pressure,
                value: p,
                expected: "p >= 0 (compression positive)",
            });
        }
        if h < 0.0 {
            return Err(EvalError::Invalid {
                axis: Axis::Flux,
                value: h,
                expected: "h >= 0 (the flux magnitude)",
            });
        }
        if theta <= 0.0 {
            return Err(EvalError::Invalid {
                axis: Axis::ContactTemperature,
                value: theta,
                expected: "theta > 0 K (absolute temperature)",
            });
        }
        let policy = &options.extrapolation;
        let [inv_p, inv_h, inv_t] = &self.inv_widths;
        let wp = log_hermite_weights(
            &self.axes.pressure,
            &self.log_pressure,
            inv_p,
            p,
            policy.pressure,
        )?;
        let wh = linear_weights(&self.axes.flux, inv_h, h, policy.flux, Axis::Flux)?;
        let wt = linear_weights(
            &self.axes.contact_temperature,
            inv_t,
            theta,
            policy.contact_temperature,
            Axis::ContactTemperature,
        )?;
        Ok((wp, wh, wt))
    }

    /// Jump along the pressure line at flux node `ih` and temperature node `it`.
    #[inline]
    pub(crate) fn line(&self, wp: &HermiteWeights, ih: usize, it: usize) -> LinePoint {
        let (nh, nt) = (self.axes.flux.len(), self.axes.contact_temperature.len());
        let a = &self.nodes[(wp.i0 * nh + ih) * nt + it];
        let b = &self.nodes[(wp.i1 * nh + ih) * nt + it];
        let (c, dc) = (&wp.c, &wp.dc);
        if let Some(upper) = wp.power {
            // Power continuation `f_e (p/p_e)^s`, s the log-log secant of the
            // end cell: c[0] = ln p − ln p_e, c[1] = ln p_e − ln p_other.
            let (e, o) = if upper { (b, a) } else { (a, b) };
            let s = if e[0] > 0.0 && o[0] > 0.0 {
                (e[0] / o[0]).ln() / c[1]
            } else {
                0.0
            };
            let r = (s * c[0]).exp();
            return LinePoint {
                value: e[0] * r,
                d_dx: s * e[0] * r,
                std: e[2] * r,
                error: e[4] * r,
            };
        }
        let dot =
            |k: usize, w: &[f64; 4]| w[0] * a[k] + w[1] * a[k + 1] + w[2] * b[k] + w[3] * b[k + 1];
        LinePoint {
            value: dot(0, c),
            d_dx: dot(0, dc),
            std: dot(2, c),
            error: dot(4, c),
        }
    }

    /// Tensor-product combination of the four pressure lines around the query.
    #[inline]
    fn corners(&self, wp: &HermiteWeights, wh: &LinearWeights, wt: &LinearWeights) -> Corners {
        let mut r = Corners::default();
        for (ih, w_h, dw_h) in [(wh.i0, wh.w0, wh.dw0), (wh.i1, wh.w1, wh.dw1)] {
            for (it, w_t, dw_t) in [(wt.i0, wt.w0, wt.dw0), (wt.i1, wt.w1, wt.dw1)] {
                let l = self.line(wp, ih, it);
                r.value += w_h * w_t * l.value;
                r.d_dx += w_h * w_t * l.d_dx;
                r.d_dh += dw_h * w_t * l.value;
                r.d_dtheta += w_h * dw_t * l.value;
                r.std += w_h * w_t * l.std;
                r.error += w_h * w_t * l.error;
            }
        }
        r
    }
}

#[derive(Default)]
struct Corners {
    value: f64,
    d_dx: f64,
    d_dh: f64,
    d_dtheta: f64,
    std: f64,
    error: f64,
}

/// The law on one pressure line at the query pressure.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct LinePoint {
    /// The jump.
    pub value: f64,
    /// d jump / d ln p.
    pub d_dx: f64,
    /// Spread of the jump.
    pub std: f64,
    /// Discretization error of the jump.
    pub error: f64,
}
