//! Exact NURBS shapes: rectangles, cuboids, circular arcs, the quarter annulus.
//! All parameter ranges are `[0, 1]`.

use super::knots::KnotVector;
use super::nurbs::NurbsPatch;
use std::f64::consts::FRAC_PI_2;

/// The rectangle `[x0, x1] × [y0, y1]` (z = 0): degree 1, one element, dir 0 = x, dir 1 = y.
#[track_caller]
pub fn rectangle(x0: f64, x1: f64, y0: f64, y1: f64) -> NurbsPatch {
    assert!(
        x1 > x0 && y1 > y0,
        "rectangle: need x0 < x1 and y0 < y1, got [{x0}, {x1}] × [{y0}, {y1}]"
    );
    let kv = KnotVector::open_uniform(1, 1, 0.0, 1.0);
    let points = vec![[x0, y0, 0.0], [x1, y0, 0.0], [x0, y1, 0.0], [x1, y1, 0.0]];
    NurbsPatch::from_parts(vec![kv.clone(), kv], points, vec![1.0; 4])
}

/// The box `[lo, hi]`: degree 1, one element, dirs 0, 1, 2 = x, y, z.
#[track_caller]
pub fn cuboid(lo: [f64; 3], hi: [f64; 3]) -> NurbsPatch {
    assert!(
        (0..3).all(|i| hi[i] > lo[i]),
        "cuboid: need lo < hi in every coordinate, got {lo:?}, {hi:?}"
    );
    let kv = KnotVector::open_uniform(1, 1, 0.0, 1.0);
    let mut points = Vec::with_capacity(8);
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..2 {
                let pick = |c: usize, s: usize| if s == 0 { lo[c] } else { hi[c] };
                points.push([pick(0, i), pick(1, j), pick(2, k)]);
            }
        }
    }
    NurbsPatch::from_parts(vec![kv.clone(), kv.clone(), kv], points, vec![1.0; 8])
}

/// Exact quarter annulus `r_inner ≤ r ≤ r_outer`, `0 ≤ θ ≤ π/2` (z = 0): dir 0 angular (degree 2,
/// one element, from +x to +y), dir 1 radial (degree 1, inner to outer). Note: this orientation
/// has a negative Jacobian determinant.
#[track_caller]
pub fn quarter_annulus(r_inner: f64, r_outer: f64) -> NurbsPatch {
    assert!(
        0.0 < r_inner && r_inner < r_outer,
        "quarter_annulus: need 0 < r_inner < r_outer, got {r_inner}, {r_outer}"
    );
    let arc = circular_arc([0.0; 3], 1.0, 0.0, FRAC_PI_2);
    let radial = KnotVector::open_uniform(1, 1, 0.0, 1.0);
    let mut points = Vec::with_capacity(6);
    let mut weights = Vec::with_capacity(6);
    for r in [r_inner, r_outer] {
        for (p, &w) in arc.control_points().iter().zip(arc.weights()) {
            points.push([r * p[0], r * p[1], 0.0]);
            weights.push(w);
        }
    }
    NurbsPatch::from_parts(vec![arc.knots()[0].clone(), radial], points, weights)
}

/// Exact circular arc (param_dim 1, degree 2) of `radius` about `center` in the plane z =
/// `center[2]`, from angle `start` to `end` (radians, counter-clockwise if `end > start`), split
/// into the fewest equal segments of at most 90° (Piegl & Tiller A7.1). Interior knots have
/// multiplicity 2; the parameter range is `[0, 1]`.
///
/// Panics unless `radius > 0` and `0 < |end − start| ≤ 2π`.
#[track_caller]
pub fn circular_arc(center: [f64; 3], radius: f64, start: f64, end: f64) -> NurbsPatch {
    let sweep = end - start;
    assert!(
        radius > 0.0 && radius.is_finite(),
        "circular_arc: radius must be > 0, got {radius}"
    );
    assert!(
        sweep != 0.0 && sweep.abs() <= 2.0 * std::f64::consts::PI * (1.0 + 1e-12),
        "circular_arc: need 0 < |end - start| <= 2π, got {sweep}"
    );
    let n_seg = ((sweep.abs() / FRAC_PI_2) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
    let dtheta = sweep / n_seg as f64;
    let w_mid = (0.5 * dtheta).cos();
    let on_circle = |theta: f64, r: f64| {
        [
            center[0] + r * theta.cos(),
            center[1] + r * theta.sin(),
            center[2],
        ]
    };
    let mut points = Vec::with_capacity(2 * n_seg + 1);
    let mut weights = Vec::with_capacity(2 * n_seg + 1);
    let mut knots = vec![0.0; 3];
    points.push(on_circle(start, radius));
    weights.push(1.0);
    for s in 0..n_seg {
        let theta0 = start + s as f64 * dtheta;
        points.push(on_circle(theta0 + 0.5 * dtheta, radius / w_mid));
        weights.push(w_mid);
        let theta1 = if s + 1 == n_seg { end } else { theta0 + dtheta };
        points.push(on_circle(theta1, radius));
        weights.push(1.0);
        if s + 1 < n_seg {
            let u = (s + 1) as f64 / n_seg as f64;
            knots.extend([u, u]);
        }
    }
    knots.extend([1.0; 3]);
    let kv = KnotVector::new(2, knots).expect("arc knot vector is valid");
    NurbsPatch::from_parts(vec![kv], points, weights)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_points_lie_on_the_circle() {
        for (start, end) in [
            (0.0, 1.0),
            (0.3, 0.3 + 2.0 * std::f64::consts::PI),
            (2.0, -1.5),
        ] {
            let arc = circular_arc([1.0, -2.0, 0.5], 3.0, start, end);
            for i in 0..=50 {
                let x = arc.point(&[i as f64 / 50.0]);
                let r = ((x[0] - 1.0).powi(2) + (x[1] + 2.0).powi(2)).sqrt();
                assert!((r - 3.0).abs() < 1e-13, "r = {r}");
                assert!((x[2] - 0.5).abs() < 1e-15);
            }
            let x1 = arc.point(&[1.0]);
            assert!((x1[0] - (1.0 + 3.0 * end.cos())).abs() < 1e-14);
        }
    }

    #[test]
    fn cuboid_and_rectangle_corners() {
        let c = cuboid([0.0, 1.0, 2.0], [3.0, 4.0, 5.0]);
        assert_eq!(c.point(&[1.0, 0.0, 1.0]), [3.0, 1.0, 5.0]);
        let r = rectangle(-1.0, 2.0, 0.5, 1.5);
        assert_eq!(r.point(&[0.5, 0.5]), [0.5, 1.0, 0.0]);
    }
}
