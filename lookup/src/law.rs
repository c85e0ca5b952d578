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
    /// Per entry: `[jump, d jump/d ln p, std, d std/d ln p]` (Steffen slopes).
    pub(crate) nodes: Vec<[f64; 4]>,
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
    pub fn from_grid(
        axes: Axes,
        jump_mean: Vec<f64>,
        jump_std: Vec<f64>,
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
        if let Statistic::EnsembleMean { samples: 0 } = info.statistic {
            return Err(Error::invalid("ensemble_size", "0: expected >= 1"));
        }
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
        let mut nodes = vec![[0.0; 4]; len];
        let mut line = vec![0.0; np];
        for offset in 0..stride {
            for (field, slope) in [(0, 1), (2, 3)] {
                let data = if field == 0 { &jump_mean } else { &jump_std };
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
            nodes,
            info,
            options,
        })
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

    /// Overrides the extrapolation policy.
    pub fn set_extrapolation(&mut self, policy: ExtrapolationPolicy) {
        self.options.extrapolation = policy;
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
            d_jump_dp: corners.d_dx * wp.dx_dp,
            d_jump_dh: corners.d_dh,
            d_jump_dtheta: corners.d_dtheta,
            extrapolated: [wp.extrapolated, wh.extrapolated, wt.extrapolated],
            ..Value::default()
        };
        let jump_part = [
            v.jump,
            v.jump_std,
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

    /// Jump along the pressure line at flux node `ih` and temperature node `it`:
    /// `(value, d/d ln p, std)`.
    #[inline]
    pub(crate) fn line(&self, wp: &HermiteWeights, ih: usize, it: usize) -> (f64, f64, f64) {
        let (nh, nt) = (self.axes.flux.len(), self.axes.contact_temperature.len());
        let a = &self.nodes[(wp.i0 * nh + ih) * nt + it];
        let b = &self.nodes[(wp.i1 * nh + ih) * nt + it];
        let (c, dc) = (&wp.c, &wp.dc);
        (
            c[0] * a[0] + c[1] * a[1] + c[2] * b[0] + c[3] * b[1],
            dc[0] * a[0] + dc[1] * a[1] + dc[2] * b[0] + dc[3] * b[1],
            c[0] * a[2] + c[1] * a[3] + c[2] * b[2] + c[3] * b[3],
        )
    }

    /// Tensor-product combination of the four pressure lines around the query.
    #[inline]
    fn corners(&self, wp: &HermiteWeights, wh: &LinearWeights, wt: &LinearWeights) -> Corners {
        let mut r = Corners::default();
        for (ih, w_h, dw_h) in [(wh.i0, wh.w0, wh.dw0), (wh.i1, wh.w1, wh.dw1)] {
            for (it, w_t, dw_t) in [(wt.i0, wt.w0, wt.dw0), (wt.i1, wt.w1, wt.dw1)] {
                let (f, df, s) = self.line(wp, ih, it);
                r.value += w_h * w_t * f;
                r.d_dx += w_h * w_t * df;
                r.d_dh += dw_h * w_t * f;
                r.d_dtheta += w_h * dw_t * f;
                r.std += w_h * w_t * s;
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
}
