//! The inverse query a macroscale code needs when it knows the two surface
//! temperatures rather than the flux: given `p̄N`, the jump `θ̄ − θ̄c` and `θ̄c`,
//! find the flux magnitude `|h̄|` with `jump(p̄N, |h̄|, θ̄c) = jump`, and the
//! conductance `k̄c = |h̄| / jump` (paper Eq. (2.7)) with its derivatives at
//! fixed jump (the tangent of a `GAPCON`-style routine).
//!
//! Along flux the law is piecewise linear, so the inverse is exact: the first
//! flux interval (from the smallest flux) whose jump range holds the query.

use crate::error::{Axis, EvalError};
use crate::info::Extrapolation;
use crate::law::{EvalOptions, Law};

/// The law evaluated at a given jump.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FluxValue {
    /// Flux magnitude `|h̄|` \[W/m²\] producing the jump (`k̄c · jump`).
    pub flux: f64,
    /// Standard deviation of the jump over the ensemble at that flux \[K\].
    pub jump_std: f64,
    /// Estimated discretization error of the jump there \[K\] (0 when the law
    /// carries no estimate).
    pub jump_error: f64,
    /// Conductance `k̄c = |h̄| / jump` \[W/(m²·K)\].
    pub conductance: f64,
    /// ∂|h̄|/∂p̄N at fixed jump and θ̄c.
    pub d_flux_dp: f64,
    /// ∂|h̄|/∂jump at fixed p̄N and θ̄c (the thermal tangent of the interface).
    pub d_flux_djump: f64,
    /// ∂|h̄|/∂θ̄c at fixed p̄N and jump.
    pub d_flux_dtheta: f64,
    /// ∂k̄c/∂p̄N at fixed jump and θ̄c (Abaqus `GAPCON`'s `AK(3)`).
    pub d_conductance_dp: f64,
    /// ∂k̄c/∂jump at fixed p̄N and θ̄c.
    pub d_conductance_djump: f64,
    /// ∂k̄c/∂θ̄c at fixed p̄N and jump.
    pub d_conductance_dtheta: f64,
    /// Whether each axis (indexed by [`Axis`] as `usize`) was outside the table.
    pub extrapolated: [bool; 3],
    /// Whether the conductance is the cap [`EvalOptions::max_conductance`].
    pub conductance_capped: bool,
}

/// Jump at one flux node, interpolated in pressure and temperature.
#[derive(Clone, Copy, Default)]
struct Node {
    g: f64,
    g_x: f64,
    g_theta: f64,
    std: f64,
    error: f64,
}

impl Law {
    /// [`Law::eval_at_jump_with`] with the law's options.
    pub fn eval_at_jump(&self, p: f64, jump: f64, theta: f64) -> Result<FluxValue, EvalError> {
        self.eval_at_jump_with(p, jump, theta, &self.options)
    }

    /// Finds the flux magnitude that produces `jump` \[K\] at pressure `p` \[Pa\] and
    /// contact temperature `theta` \[K\], and the conductance there.
    ///
    /// Outside the jump range covered by the flux axis, the flux policy decides:
    /// `error` fails with [`EvalError::JumpOutOfRange`]; `clamp` uses the
    /// conductance at the nearest flux bound (constant conductance, so
    /// `jump = 0` gives flux 0 and a finite conductance); `linear` continues the
    /// end segment (fails if no flux ≥ 0 reproduces the jump). The jump must be
    /// finite and ≥ 0. Never allocates.
    pub fn eval_at_jump_with(
        &self,
        p: f64,
        jump: f64,
        theta: f64,
        options: &EvalOptions,
    ) -> Result<FluxValue, EvalError> {
        if !(jump.is_finite() && jump >= 0.0) {
            return Err(EvalError::InvalidJump { value: jump });
        }
        let (wp, _, wt) = self.weights(p, self.axes.flux[0], theta, options)?;
        let node = |ih: usize| {
            let mut n = Node::default();
            for (it, w, dw) in [(wt.i0, wt.w0, wt.dw0), (wt.i1, wt.w1, wt.dw1)] {
                let l = self.line(&wp, ih, it);
                n.g += w * l.value;
                n.g_x += w * l.d_dx;
                n.g_theta += dw * l.value;
                n.std += w * l.std;
                n.error += w * l.error;
            }
            n
        };
        let flux = &self.axes.flux;
        let nh = flux.len();
        let mut out = FluxValue {
            extrapolated: [wp.extrapolated, false, wt.extrapolated],
            ..FluxValue::default()
        };

        // A single flux node: the law does not depend on flux; conductance h0/g0.
        let first = node(0);
        if nh == 1 {
            if jump != first.g {
                out.extrapolated[Axis::Flux as usize] = true;
                if options.extrapolation.flux == Extrapolation::Error {
                    return Err(EvalError::JumpOutOfRange {
                        jump,
                        min: first.g,
                        max: first.g,
                    });
                }
            }
            return self.clamped(out, flux[0], first, wp.dx_dp, jump, options);
        }

        // Locate the flux interval (or the end) that produces the jump.
        let mut found = None;
        let mut a = first;
        let mut last = first;
        for j in 0..nh - 1 {
            let b = node(j + 1);
            if a.g.min(b.g) <= jump && jump <= a.g.max(b.g) {
                found = Some((j, a, b));
                break;
            }
            a = b;
            last = b;
        }
        let (j, a, b, t) = match found {
            Some((j, a, b)) => {
                let t = if b.g == a.g {
                    0.0
                } else {
                    (jump - a.g) / (b.g - a.g)
                };
                (j, a, b, t)
            }
            None => {
                out.extrapolated[Axis::Flux as usize] = true;
                let low = (jump - first.g).abs() <= (jump - last.g).abs();
                match options.extrapolation.flux {
                    Extrapolation::Error => {
                        return Err(EvalError::JumpOutOfRange {
                            jump,
                            min: first.g,
                            max: last.g,
                        });
                    }
                    Extrapolation::Clamp => {
                        let (h_b, n) = if low {
                            (flux[0], first)
                        } else {
                            (flux[nh - 1], last)
                        };
                        return self.clamped(out, h_b, n, wp.dx_dp, jump, options);
                    }
                    // `power` is not allowed along flux (validated); as linear.
                    Extrapolation::Linear | Extrapolation::Power => {}
                }
                let (j, a, b) = if low {
                    (0, first, node(1))
                } else {
                    (nh - 2, node(nh - 2), last)
                };
                let t = (jump - a.g) / (b.g - a.g);
                let h = flux[j] + t * (flux[j + 1] - flux[j]);
                if !(t.is_finite() && h >= 0.0) {
                    return Err(EvalError::JumpOutOfRange {
                        jump,
                        min: first.g,
                        max: last.g,
                    });
                }
                (j, a, b, t)
            }
        };

        let dh = flux[j + 1] - flux[j];
        let h = flux[j] + t * dh;
        let lerp = |u: f64, v: f64| (1.0 - t) * u + t * v;
        let j_h = (b.g - a.g) / dh;
        let j_p = lerp(a.g_x, b.g_x) * wp.dx_dp;
        let j_theta = lerp(a.g_theta, b.g_theta);
        out.flux = h;
        out.jump_std = lerp(a.std, b.std).max(0.0);
        out.jump_error = lerp(a.error, b.error).max(0.0);
        out.d_flux_djump = 1.0 / j_h;
        out.d_flux_dp = -j_p / j_h;
        out.d_flux_dtheta = -j_theta / j_h;
        let k = h / jump;
        let dk = [
            out.d_flux_dp / jump,
            (out.d_flux_djump - k) / jump,
            out.d_flux_dtheta / jump,
        ];
        let derivs_ok = [out.d_flux_djump, out.d_flux_dp, out.d_flux_dtheta]
            .iter()
            .chain(&dk)
            .all(|x| x.is_finite());
        if !(h.is_finite() && derivs_ok) && jump > 0.0 {
            return Err(EvalError::NonFiniteResult);
        }
        let computable = jump > 0.0 && k.is_finite();
        self.finish(out, (k, dk, computable), jump, jump, options)
    }

    /// Conductance constant beyond the flux bound `h_b` where the jump is `n.g`.
    fn clamped(
        &self,
        mut out: FluxValue,
        h_b: f64,
        n: Node,
        dx_dp: f64,
        jump: f64,
        options: &EvalOptions,
    ) -> Result<FluxValue, EvalError> {
        out.jump_std = n.std.max(0.0);
        out.jump_error = n.error.max(0.0);
        let k = h_b / n.g;
        let dk = [-k * n.g_x * dx_dp / n.g, 0.0, -k * n.g_theta / n.g];
        let computable = n.g > 0.0 && k.is_finite();
        if computable && !dk.iter().all(|x| x.is_finite()) {
            return Err(EvalError::NonFiniteResult);
        }
        if computable {
            out.flux = k * jump;
            out.d_flux_dp = jump * dk[0];
            out.d_flux_djump = k;
            out.d_flux_dtheta = jump * dk[2];
        }
        self.finish(out, (k, dk, computable), jump, n.g, options)
    }

    /// Applies the conductance cap (or reports the vanishing jump
    /// `vanishing`) to the conductance `k`, its derivatives `dk` and whether
    /// they could be computed.
    fn finish(
        &self,
        mut out: FluxValue,
        (k, dk, computable): (f64, [f64; 3], bool),
        jump: f64,
        vanishing: f64,
        options: &EvalOptions,
    ) -> Result<FluxValue, EvalError> {
        match options.max_conductance {
            Some(k_max) if !computable || k > k_max => {
                out.conductance = k_max;
                out.conductance_capped = true;
                out.d_conductance_dp = 0.0;
                out.d_conductance_djump = 0.0;
                out.d_conductance_dtheta = 0.0;
                out.flux = k_max * jump;
                out.d_flux_dp = 0.0;
                out.d_flux_djump = k_max;
                out.d_flux_dtheta = 0.0;
            }
            _ if !computable => return Err(EvalError::VanishingJump { jump: vanishing }),
            _ => {
                out.conductance = k;
                [
                    out.d_conductance_dp,
                    out.d_conductance_djump,
                    out.d_conductance_dtheta,
                ] = dk;
            }
        }
        let all = [
            out.flux,
            out.jump_std,
            out.conductance,
            out.d_flux_dp,
            out.d_flux_djump,
            out.d_flux_dtheta,
            out.d_conductance_dp,
            out.d_conductance_djump,
            out.d_conductance_dtheta,
        ];
        if all.iter().all(|x| x.is_finite()) {
            Ok(out)
        } else {
            Err(EvalError::NonFiniteResult)
        }
    }
}
