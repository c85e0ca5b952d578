//! Closest-point projection of a slave point onto the master NURBS curve
//! (spec §6): global search over samples of the curve for a starting guess,
//! Newton on `φ(η) = (x_s − x_m(η))·x_m'(η) = 0`, clamping at the ends of a
//! non-periodic master, and the periodic images of the master (PR conditions).

use crate::geometry::NurbsPatch;
use crate::{Error, Result};

/// Result of a projection.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Projection {
    /// Master curve parameter.
    pub eta: f64,
    /// Shift `k·W` added to the master's x coordinates (periodic image).
    pub shift: f64,
    /// The projection stopped at an end of a non-periodic master.
    pub clamped: bool,
    /// Distance to the projected point.
    pub distance: f64,
}

/// Newton from `eta0` on one image; returns `(η, clamped, distance²)`.
fn newton(curve: &NurbsPatch, x: [f64; 2], eta0: f64, lo: f64, hi: f64) -> (f64, bool, f64) {
    let mut eta = eta0.clamp(lo, hi);
    let mut clamped = false;
    for _ in 0..40 {
        let d = curve.curve_derivatives(eta, 2);
        let r = [x[0] - d[0][0], x[1] - d[0][1]];
        let phi = r[0] * d[1][0] + r[1] * d[1][1];
        let dphi = -(d[1][0] * d[1][0] + d[1][1] * d[1][1]) + r[0] * d[2][0] + r[1] * d[2][1];
        // Fall back to a gradient-like step where the curve is locally concave toward x.
        let step = if dphi < 0.0 {
            -phi / dphi
        } else {
            phi / (d[1][0] * d[1][0] + d[1][1] * d[1][1])
        };
        let next = eta + step;
        if next <= lo || next >= hi {
            let e = next.clamp(lo, hi);
            if (e - eta).abs() < 1e-15 * (hi - lo) {
                clamped = true;
                eta = e;
                break;
            }
            eta = e;
            clamped = true;
            continue;
        }
        clamped = false;
        let done = (next - eta).abs() < 1e-15 * (hi - lo);
        eta = next;
        if done {
            break;
        }
    }
    let c = curve.point(&[eta]);
    let d2 = (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2);
    (eta, clamped, d2)
}

/// Newton on the periodic extension of the master: `x_m(η + k·L) = x_m(η) + k·W`
/// (`L` the parameter range, `W` the period), so a projection may cross the
/// seam freely. Returns `(η ∈ [lo, hi), shift, distance²)`.
fn newton_periodic(
    curve: &NurbsPatch,
    x: [f64; 2],
    eta0: f64,
    lo: f64,
    hi: f64,
    w: f64,
) -> (f64, f64, f64) {
    let range = hi - lo;
    let wrap = |e: f64| -> (f64, f64) {
        let k = ((e - lo) / range).floor();
        let mut r = e - k * range;
        if r >= hi {
            r = lo;
        }
        (r, k * w)
    };
    let mut eta = eta0;
    for _ in 0..60 {
        let (e, shift) = wrap(eta);
        let d = curve.curve_derivatives(e, 2);
        let r = [x[0] - d[0][0] - shift, x[1] - d[0][1]];
        let phi = r[0] * d[1][0] + r[1] * d[1][1];
        let t2 = d[1][0] * d[1][0] + d[1][1] * d[1][1];
        let dphi = -t2 + r[0] * d[2][0] + r[1] * d[2][1];
        let mut step = if dphi < 0.0 { -phi / dphi } else { phi / t2 };
        // Limit a step to one element-sized fraction of the range.
        step = step.clamp(-0.25 * range, 0.25 * range);
        eta += step;
        if step.abs() < 1e-15 * range {
            break;
        }
    }
    let (e, shift) = wrap(eta);
    let c = curve.point(&[e]);
    (
        e,
        shift,
        (x[0] - c[0] - shift).powi(2) + (x[1] - c[1]).powi(2),
    )
}

/// Points of the master curve at 4 parameters per element: the candidates
/// for the starting guesses of the projections (computed once per evaluation).
pub struct MasterSamples {
    samples: Vec<(f64, [f64; 3])>,
}

impl MasterSamples {
    /// Samples `curve`.
    pub fn new(curve: &NurbsPatch) -> Self {
        let kv = &curve.knots()[0];
        let mut samples = Vec::new();
        for s in kv.element_spans() {
            let (a, b) = (kv.knots()[s], kv.knots()[s + 1]);
            for t in 0..4 {
                let eta = a + (b - a) * (t as f64 + 0.5) / 4.0;
                samples.push((eta, curve.point(&[eta])));
            }
        }
        MasterSamples { samples }
    }
}

/// Projects `x` onto `curve` (a 2D NURBS curve in the current configuration).
/// `guess`: the parameter found at the previous evaluation, if any.
/// `period`: the sample width when the master repeats periodically in x.
pub fn project(
    curve: &NurbsPatch,
    x: [f64; 2],
    guess: Option<f64>,
    period: Option<f64>,
    samples: &MasterSamples,
) -> Result<Projection> {
    let kv = &curve.knots()[0];
    let (lo, hi) = (kv.first(), kv.last());
    let shifts: Vec<f64> = match period {
        None => vec![0.0],
        Some(w) => {
            let x0 = curve.point(&[lo])[0];
            let k = ((x[0] - x0) / w).floor();
            vec![k * w, (k - 1.0) * w, (k + 1.0) * w]
        }
    };
    let mut best: Option<Projection> = None;
    for &shift in &shifts {
        let xs = [x[0] - shift, x[1]];
        let mut starts: Vec<f64> = Vec::new();
        if let Some(g) = guess {
            starts.push(g);
        }
        // The two nearest samples.
        let (mut b1, mut b2) = ((f64::INFINITY, lo), (f64::INFINITY, lo));
        for &(t, c) in &samples.samples {
            let d = (xs[0] - c[0]).powi(2) + (xs[1] - c[1]).powi(2);
            if d < b1.0 {
                b2 = b1;
                b1 = (d, t);
            } else if d < b2.0 {
                b2 = (d, t);
            }
        }
        starts.push(b1.1);
        starts.push(b2.1);
        for s in starts {
            let cand = match period {
                Some(w) => {
                    let (eta, extra, d2) = newton_periodic(curve, xs, s, lo, hi, w);
                    Projection {
                        eta,
                        shift: shift + extra,
                        clamped: false,
                        distance: d2.sqrt(),
                    }
                }
                None => {
                    let (eta, clamped, d2) = newton(curve, xs, s, lo, hi);
                    Projection {
                        eta,
                        shift,
                        clamped,
                        distance: d2.sqrt(),
                    }
                }
            };
            if best.is_none_or(|b| cand.distance < b.distance - 1e-14) {
                best = Some(cand);
            }
        }
        if period.is_some() {
            // The periodic Newton reaches every image from the first shift.
            break;
        }
    }
    best.ok_or_else(|| {
        Error::Geometry(format!(
            "no projection of the point ({}, {}) onto the master surface",
            x[0], x[1]
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shapes;

    #[test]
    fn projects_onto_a_circle_exactly() {
        let c = shapes::circular_arc([0.0, 0.0, 0.0], 2.0, 0.0, std::f64::consts::FRAC_PI_2);
        let x = [3.0 * 0.6, 3.0 * 0.8];
        let p = project(&c, x, None, None, &MasterSamples::new(&c)).unwrap();
        assert!((p.distance - 1.0).abs() < 1e-12);
        let y = c.point(&[p.eta]);
        assert!((y[0] - 1.2).abs() < 1e-12 && (y[1] - 1.6).abs() < 1e-12);
    }

    #[test]
    fn clamps_beyond_the_end_and_wraps_periodic_images() {
        let line = shapes::rectangle(0.0, 1.0, 0.0, 1.0)
            .face(1, crate::geometry::Side::Low)
            .0;
        let s = MasterSamples::new(&line);
        let p = project(&line, [1.3, 0.2], None, None, &s).unwrap();
        assert!(p.clamped && (p.eta - 1.0).abs() < 1e-15);
        let q = project(&line, [1.3, 0.2], None, Some(1.0), &s).unwrap();
        assert!(!q.clamped && (q.shift - 1.0).abs() < 1e-15 && (q.eta - 0.3).abs() < 1e-12);
        assert!((q.distance - 0.2).abs() < 1e-12);
    }
}
