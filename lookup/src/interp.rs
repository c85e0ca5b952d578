//! One-dimensional interpolation pieces of the tensor-product law:
//! Steffen's monotone cubic Hermite along `x = ln p̄N`, piecewise linear along
//! flux and contact temperature, each with its extrapolation policy.
//!
//! M. Steffen, *A simple method for monotonic interpolation in one dimension*,
//! Astron. Astrophys. 239 (1990) 443–450, Eqs. (11), (13), (26), (27).

use crate::error::{Axis, EvalError};
use crate::info::Extrapolation;

/// Steffen's node slopes `dy/dx` of the monotone C1 cubic Hermite interpolant.
///
/// Guarantees: the interpolant has no extremum between nodes (it stays within
/// the two node values of each interval, so monotone data give a monotone
/// interpolant), and data linear in `x` get the exact slope. At the two end
/// nodes the slope is the end interval's secant slope.
pub(crate) fn steffen_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    debug_assert_eq!(n, y.len());
    match n {
        0 => return Vec::new(),
        1 => return vec![0.0],
        2 => {
            let s = (y[1] - y[0]) / (x[1] - x[0]);
            return vec![s, s];
        }
        _ => {}
    }
    let h: Vec<f64> = x.windows(2).map(|w| w[1] - w[0]).collect();
    let s: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    let mut m = vec![0.0; n];
    for i in 1..n - 1 {
        // Eq. (11): slope of the parabola through the three nodes; Eq. (13): limiter.
        let p = (s[i - 1] * h[i] + s[i] * h[i - 1]) / (h[i - 1] + h[i]);
        m[i] = (sign(s[i - 1]) + sign(s[i])) * s[i - 1].abs().min(s[i].abs()).min(0.5 * p.abs());
    }
    // End conditions: the one-sided secant slope of the end interval (not
    // Steffen's Eqs. (26)–(27), whose limited parabola gives a zero slope
    // where the data bend towards the end, e.g. the flattening jump at the
    // low-pressure end of a law, where the data's slope is clearly not
    // zero). With the interior slopes bounded by 2|s| (Eq. (13)) the end
    // interval stays monotone (Fritsch–Carlson: α = 1, β ≤ 2).
    m[0] = s[0];
    m[n - 1] = s[n - 2];
    m
}

fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// `1 / (x[i+1] − x[i])` for each interval of `x`.
pub(crate) fn inverse_widths(x: &[f64]) -> Vec<f64> {
    x.windows(2).map(|w| 1.0 / (w[1] - w[0])).collect()
}

/// Index `i` of the interval `[nodes[i], nodes[i+1]]` holding `q` (the right
/// interval at interior nodes), for `nodes[0] <= q <= nodes[n-1]`, `n >= 2`.
/// Branch-free binary search: random queries cost no branch mispredictions.
#[inline]
fn interval(nodes: &[f64], q: f64) -> usize {
    // Invariant: the answer (largest i <= n-2 with nodes[i] <= q) is in [base, base + size).
    let mut base = 0usize;
    let mut size = nodes.len() - 1;
    while size > 1 {
        let half = size / 2;
        let mid = base + half;
        base = std::hint::select_unpredictable(nodes[mid] <= q, mid, base);
        size -= half;
    }
    base
}

/// Weights of a piecewise-linear axis at one query: value `w0 f[i0] + w1 f[i1]`,
/// derivative `dw0 f[i0] + dw1 f[i1]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LinearWeights {
    pub i0: usize,
    pub i1: usize,
    pub w0: f64,
    pub w1: f64,
    pub dw0: f64,
    pub dw1: f64,
    /// Coordinate at which the law is evaluated (the clamped one under `Clamp`).
    pub q_eff: f64,
    /// `d q_eff / d q` (0 when clamped).
    pub dq_eff: f64,
    pub extrapolated: bool,
}

/// Bracket `q` on a piecewise-linear axis. A single-node axis is constant: it
/// behaves as `Clamp` unless the policy is `Error`.
#[inline]
pub(crate) fn linear_weights(
    nodes: &[f64],
    inv_width: &[f64],
    q: f64,
    policy: Extrapolation,
    axis: Axis,
) -> Result<LinearWeights, EvalError> {
    let n = nodes.len();
    let (lo, hi) = (nodes[0], nodes[n - 1]);
    let outside = q < lo || q > hi;
    if outside && policy == Extrapolation::Error {
        return Err(EvalError::OutOfRange {
            axis,
            value: q,
            min: lo,
            max: hi,
        });
    }
    if n == 1 {
        return Ok(LinearWeights {
            i0: 0,
            i1: 0,
            w0: 1.0,
            w1: 0.0,
            dw0: 0.0,
            dw1: 0.0,
            q_eff: lo,
            dq_eff: 0.0,
            extrapolated: outside,
        });
    }
    let clamped = |i: usize, at_hi: bool| LinearWeights {
        i0: i,
        i1: i + 1,
        w0: if at_hi { 0.0 } else { 1.0 },
        w1: if at_hi { 1.0 } else { 0.0 },
        dw0: 0.0,
        dw1: 0.0,
        q_eff: if at_hi { hi } else { lo },
        dq_eff: 0.0,
        extrapolated: true,
    };
    let i = if q < lo {
        if policy == Extrapolation::Clamp {
            return Ok(clamped(0, false));
        }
        0
    } else if q > hi {
        if policy == Extrapolation::Clamp {
            return Ok(clamped(n - 2, true));
        }
        n - 2
    } else {
        interval(nodes, q)
    };
    let inv = inv_width[i];
    let t = (q - nodes[i]) * inv;
    let t = if outside { t } else { t.clamp(0.0, 1.0) };
    Ok(LinearWeights {
        i0: i,
        i1: i + 1,
        w0: 1.0 - t,
        w1: t,
        dw0: -inv,
        dw1: inv,
        q_eff: q,
        dq_eff: 1.0,
        extrapolated: outside,
    })
}

/// Coefficients of the cubic Hermite interpolant along `x = ln p` at one query:
/// value `c · [f0, m0, f1, m1]`, `d/dx` value `dc · [f0, m0, f1, m1]`, where
/// `f0, m0` are the value and slope at node `i0`, `f1, m1` at node `i1`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct HermiteWeights {
    pub i0: usize,
    pub i1: usize,
    pub c: [f64; 4],
    pub dc: [f64; 4],
    /// `dx/dp = 1/p` (0 when clamped or on a single-node axis).
    pub dx_dp: f64,
    pub extrapolated: bool,
    /// Power continuation beyond the upper (`Some(true)`) or lower end:
    /// `c[0] = x − x_end`, `c[1] = x_end − x_other` (see `Law::line`).
    pub power: Option<bool>,
}

/// Bracket `p > 0` (or `p = 0` under `Clamp`) on the pressure axis, nodes
/// `p_nodes`, their logarithms `x_nodes` and `1 / (x[i+1] − x[i])` in `inv_width`.
#[inline]
pub(crate) fn log_hermite_weights(
    p_nodes: &[f64],
    x_nodes: &[f64],
    inv_width: &[f64],
    p: f64,
    policy: Extrapolation,
) -> Result<HermiteWeights, EvalError> {
    let n = p_nodes.len();
    let (lo, hi) = (p_nodes[0], p_nodes[n - 1]);
    let outside = p < lo || p > hi;
    if outside && policy == Extrapolation::Error {
        return Err(EvalError::OutOfRange {
            axis: Axis::Pressure,
            value: p,
            min: lo,
            max: hi,
        });
    }
    let constant = |i0: usize, i1: usize, c: [f64; 4]| HermiteWeights {
        i0,
        i1,
        c,
        dc: [0.0; 4],
        dx_dp: 0.0,
        extrapolated: outside,
        power: None,
    };
    if n == 1 {
        return Ok(constant(0, 0, [1.0, 0.0, 0.0, 0.0]));
    }
    if outside && policy == Extrapolation::Clamp {
        return Ok(if p < lo {
            constant(0, 1, [1.0, 0.0, 0.0, 0.0])
        } else {
            constant(n - 2, n - 1, [0.0, 0.0, 1.0, 0.0])
        });
    }
    // p is finite here (checked by the caller); zero or negative has no log.
    if p <= 0.0 {
        return Err(EvalError::Invalid {
            axis: Axis::Pressure,
            value: p,
            expected: "p > 0 for linear or power extrapolation in ln p",
        });
    }
    let x = p.ln();
    if outside && policy == Extrapolation::Power {
        let upper = p > hi;
        let (i0, e, o) = if upper {
            (n - 2, n - 1, n - 2)
        } else {
            (0, 0, 1)
        };
        return Ok(HermiteWeights {
            i0,
            i1: i0 + 1,
            c: [x - x_nodes[e], x_nodes[e] - x_nodes[o], 0.0, 0.0],
            dc: [0.0; 4],
            dx_dp: 1.0 / p,
            extrapolated: true,
            power: Some(upper),
        });
    }
    if p < lo {
        return Ok(HermiteWeights {
            i0: 0,
            i1: 1,
            c: [1.0, x - x_nodes[0], 0.0, 0.0],
            dc: [0.0, 1.0, 0.0, 0.0],
            dx_dp: 1.0 / p,
            extrapolated: true,
            power: None,
        });
    }
    if p > hi {
        return Ok(HermiteWeights {
            i0: n - 2,
            i1: n - 1,
            c: [0.0, 0.0, 1.0, x - x_nodes[n - 1]],
            dc: [0.0, 0.0, 0.0, 1.0],
            dx_dp: 1.0 / p,
            extrapolated: true,
            power: None,
        });
    }
    let i = interval(p_nodes, p);
    let inv = inv_width[i];
    let d = x_nodes[i + 1] - x_nodes[i];
    let t = ((x - x_nodes[i]) * inv).clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    Ok(HermiteWeights {
        i0: i,
        i1: i + 1,
        c: [
            2.0 * t3 - 3.0 * t2 + 1.0,
            d * (t3 - 2.0 * t2 + t),
            -2.0 * t3 + 3.0 * t2,
            d * (t3 - t2),
        ],
        dc: [
            (6.0 * t2 - 6.0 * t) * inv,
            3.0 * t2 - 4.0 * t + 1.0,
            (6.0 * t - 6.0 * t2) * inv,
            3.0 * t2 - 2.0 * t,
        ],
        dx_dp: 1.0 / p,
        extrapolated: false,
        power: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hermite(x: &[f64], y: &[f64], m: &[f64], q: f64) -> (f64, f64) {
        let p: Vec<f64> = x.iter().map(|v| v.exp()).collect();
        let w =
            log_hermite_weights(&p, x, &inverse_widths(x), q.exp(), Extrapolation::Linear).unwrap();
        let f = [y[w.i0], m[w.i0], y[w.i1], m[w.i1]];
        let dot = |c: [f64; 4]| c.iter().zip(f).map(|(a, b)| a * b).sum::<f64>();
        (dot(w.c), dot(w.dc))
    }

    /// Data that bend towards an end (issue 13 item 4): the end slope is the
    /// end interval's secant slope, not zero (Steffen's Eqs. (26)–(27) gave
    /// 0 here), and the end interval stays monotone.
    #[test]
    fn end_slopes_are_the_one_sided_secants() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [10.0, 9.9, 1.0, 0.9];
        let m = steffen_slopes(&x, &y);
        assert!((m[0] + 0.1).abs() < 1e-12, "lower end slope {}", m[0]);
        assert!((m[3] + 0.1).abs() < 1e-12, "upper end slope {}", m[3]);
        let mut last = f64::INFINITY;
        for k in 0..=300 {
            let q = 3.0 * k as f64 / 300.0;
            let (v, d) = hermite(&x, &y, &m, q);
            assert!(v <= last + 1e-12 && d <= 1e-12, "monotone at {q}: {v}, {d}");
            last = v;
        }
    }

    #[test]
    fn steffen_slopes_are_exact_on_linear_data() {
        let x = [0.0, 0.3, 1.0, 1.1, 2.5];
        let y: Vec<f64> = x.iter().map(|v| 2.0 - 3.0 * v).collect();
        for m in steffen_slopes(&x, &y) {
            assert!((m + 3.0).abs() < 1e-12, "{m}");
        }
    }

    #[test]
    fn steffen_has_zero_slope_at_extrema_and_flat_parts() {
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let y = [0.0, 1.0, 0.5, 0.5, 2.0];
        let m = steffen_slopes(&x, &y);
        assert_eq!(m[1], 0.0);
        assert_eq!(m[2], 0.0);
        assert_eq!(m[3], 0.0);
    }

    #[test]
    fn hermite_interpolant_stays_between_node_values() {
        let x = [0.0, 0.5, 2.0, 2.2, 4.0];
        let y = [1.0, 1.1, 5.0, 5.01, 9.0];
        let m = steffen_slopes(&x, &y);
        let mut prev = f64::NEG_INFINITY;
        for k in 0..=4000 {
            let q = 4.0 * k as f64 / 4000.0;
            let (v, d) = hermite(&x, &y, &m, q);
            assert!(v >= prev - 1e-12, "not monotone at {q}");
            assert!(d >= -1e-12);
            prev = v;
        }
    }

    #[test]
    fn interval_finds_the_right_interval() {
        for n in 2..12usize {
            let nodes: Vec<f64> = (0..n).map(|i| (i * i) as f64).collect();
            for k in 0..=(4 * (n - 1) * (n - 1)) {
                let q = k as f64 / 4.0;
                let expected = nodes
                    .partition_point(|&v| v <= q)
                    .saturating_sub(1)
                    .min(n - 2);
                assert_eq!(interval(&nodes, q), expected, "n {n} q {q}");
            }
        }
    }

    #[test]
    fn linear_weights_follow_the_policy() {
        let nodes = [1.0, 2.0, 4.0];
        let inv = inverse_widths(&nodes);
        let w = linear_weights(&nodes, &inv, 3.0, Extrapolation::Error, Axis::Flux).unwrap();
        assert_eq!((w.i0, w.w0, w.w1), (1, 0.5, 0.5));
        assert!(linear_weights(&nodes, &inv, 5.0, Extrapolation::Error, Axis::Flux).is_err());
        let w = linear_weights(&nodes, &inv, 5.0, Extrapolation::Clamp, Axis::Flux).unwrap();
        assert_eq!((w.q_eff, w.w1, w.dw1, w.dq_eff), (4.0, 1.0, 0.0, 0.0));
        let w = linear_weights(&nodes, &inv, 5.0, Extrapolation::Linear, Axis::Flux).unwrap();
        assert_eq!((w.i0, w.w1, w.q_eff), (1, 1.5, 5.0));
        let w = linear_weights(&nodes, &inv, 0.0, Extrapolation::Linear, Axis::Flux).unwrap();
        assert_eq!((w.i0, w.w0, w.w1), (0, 2.0, -1.0));
    }
}
