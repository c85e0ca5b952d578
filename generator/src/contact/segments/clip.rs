//! Polygons in a slave element's parameter plane (3D segment-based
//! integration): clipping by the element's box (Sutherland–Hodgman),
//! clean-up, triangulation and the collapsed Gauss rule on triangles.

use crate::quadrature::GaussLegendre;

/// A point of the parameter plane.
pub type Point = [f64; 2];

/// Twice the signed area of the triangle `(a, b, c)`.
fn cross(a: Point, b: Point, c: Point) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether `p` lies inside the simple polygon `poly` (crossing number).
pub fn contains(poly: &[Point], p: Point) -> bool {
    let mut inside = false;
    for (i, &a) in poly.iter().enumerate() {
        let b = poly[(i + 1) % poly.len()];
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
        {
            inside = !inside;
        }
    }
    inside
}

/// Signed area (positive counter-clockwise), by the shoelace formula.
pub fn signed_area(poly: &[Point]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (p, q) = (poly[i], poly[(i + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        * 0.5
}

/// The part of `poly` inside the box `[lo, hi]` (Sutherland–Hodgman: one
/// half-plane after the other; the box is convex, the polygon need not be).
pub fn clip_to_box(poly: &[Point], lo: Point, hi: Point) -> Vec<Point> {
    let mut out = poly.to_vec();
    for (d, bound, above) in [
        (0, lo[0], true),
        (0, hi[0], false),
        (1, lo[1], true),
        (1, hi[1], false),
    ] {
        let input = std::mem::take(&mut out);
        let n = input.len();
        let inside = |p: &Point| if above { p[d] >= bound } else { p[d] <= bound };
        let crossing = |p: Point, q: Point| {
            let t = (bound - p[d]) / (q[d] - p[d]);
            let mut x = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
            x[d] = bound;
            x
        };
        for i in 0..n {
            let (p, q) = (input[i], input[(i + 1) % n]);
            match (inside(&p), inside(&q)) {
                (true, true) => out.push(q),
                (true, false) => out.push(crossing(p, q)),
                (false, true) => {
                    out.push(crossing(p, q));
                    out.push(q);
                }
                (false, false) => {}
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

/// `poly` without repeated vertices (closer than `tol`) and without
/// vertices on the line through their neighbours (within `tol` of it):
/// the straight preimages of a flat interface come out as the few corners
/// they have, whatever the number of samples along the master's edges.
pub fn simplify(mut poly: Vec<Point>, tol: f64) -> Vec<Point> {
    loop {
        let n = poly.len();
        if n < 3 {
            return Vec::new();
        }
        let drop = (0..n).find(|&i| {
            let (a, b, c) = (poly[(i + n - 1) % n], poly[i], poly[(i + 1) % n]);
            let ac = (c[0] - a[0]).hypot(c[1] - a[1]);
            let ab = (b[0] - a[0]).hypot(b[1] - a[1]);
            // `b` repeats `a`, or lies within `tol` of the line `a c`
            // (`a = c`: a spike, of no area).
            ab <= tol || (ac > tol && cross(a, b, c).abs() <= tol * ac) || ac <= tol
        });
        match drop {
            Some(i) => {
                poly.remove(i);
            }
            None => return poly,
        }
    }
}

/// The fan of triangles from the area centroid of the counter-clockwise
/// polygon `poly` to its edges. Where the polygon is star-shaped from there
/// (every convex one) they cover it without overlap; elsewhere some are
/// clockwise, and their rules' negative weights take off what the others
/// count twice, so a polynomial is still integrated exactly over the
/// polygon (Green's theorem), and an integrand that is smooth across the
/// polygon's boundary to within its notches. The fan follows the polygon
/// continuously, also where clipping adds or removes a vertex (two
/// coincident vertices add a triangle of no area) or a vertex turns
/// reflex, so the rule's error does not jump as the configuration moves.
pub fn triangles(poly: &[Point]) -> Vec<[Point; 3]> {
    let n = poly.len();
    if n < 3 {
        return Vec::new();
    }
    let a = signed_area(poly);
    let mut c = [0.0; 2];
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let w = p[0] * q[1] - q[0] * p[1];
        c = [c[0] + (p[0] + q[0]) * w, c[1] + (p[1] + q[1]) * w];
    }
    let c = [c[0] / (6.0 * a), c[1] / (6.0 * a)];
    (0..n).map(|i| [c, poly[i], poly[(i + 1) % n]]).collect()
}

/// The collapsed (Duffy) Gauss rule on triangle `t` (counter-clockwise):
/// `rule` in both directions of the unit square mapped by
/// `x = t0 + u ((1 − v)(t1 − t0) + v (t2 − t0))`, Jacobian `2 |T| u`;
/// exact for polynomials of total degree `2n − 2` (`n` points of `rule`).
pub fn triangle_points(
    t: [Point; 3],
    rule: &GaussLegendre,
) -> impl Iterator<Item = (Point, f64)> + '_ {
    let twice_area = cross(t[0], t[1], t[2]);
    rule.on_interval(0.0, 1.0).flat_map(move |(u, wu)| {
        rule.on_interval(0.0, 1.0).map(move |(v, wv)| {
            let x = [0, 1]
                .map(|k| t[0][k] + u * ((1.0 - v) * (t[1][k] - t[0][k]) + v * (t[2][k] - t[0][k])));
            (x, wu * wv * u * twice_area)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_inside_a_non_convex_polygon_are_told_from_those_outside() {
        // An L: the unit square without its upper right quarter.
        let l = [
            [0.0, 0.0],
            [1.0, 0.0],
            [1.0, 0.5],
            [0.5, 0.5],
            [0.5, 1.0],
            [0.0, 1.0],
        ];
        for (p, inside) in [
            ([0.25, 0.25], true),
            ([0.75, 0.25], true),
            ([0.25, 0.75], true),
            ([0.75, 0.75], false),
            ([1.5, 0.25], false),
            ([-0.1, 0.5], false),
        ] {
            assert_eq!(contains(&l, p), inside, "{p:?}");
        }
    }

    #[test]
    fn a_tilted_square_clipped_by_the_unit_box_has_the_area_of_the_overlap() {
        // A square of side 1 turned by 45° about (1, 0.5), sampled with
        // 3 points per edge: its overlap with the box [0, 1] × [−1, 2] is
        // the triangle left of x = 1, half of it.
        let r = std::f64::consts::FRAC_1_SQRT_2;
        let corners = [
            [1.0 - r, 0.5],
            [1.0, 0.5 - r],
            [1.0 + r, 0.5],
            [1.0, 0.5 + r],
        ];
        let mut poly = Vec::new();
        for i in 0..4 {
            let (a, b) = (corners[i], corners[(i + 1) % 4]);
            for k in 0..3 {
                let t = k as f64 / 3.0;
                poly.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            }
        }
        let clipped = simplify(clip_to_box(&poly, [0.0, -1.0], [1.0, 2.0]), 1e-12);
        assert!((signed_area(&clipped) - 0.5).abs() < 1e-14, "{clipped:?}");
        assert_eq!(clipped.len(), 3, "{clipped:?}");
        // Outside the box: nothing.
        assert!(clip_to_box(&poly, [3.0, 3.0], [4.0, 4.0]).is_empty());
    }

    #[test]
    fn the_triangle_rule_is_exact_to_its_degree_and_fans_cover_the_polygon() {
        let rule = GaussLegendre::new(4);
        // ∫ x^a y^b over the triangle (0,0), (1,0), (0,1) = a! b! / (a + b + 2)!.
        let f = |n: u32| (1..=n).map(f64::from).product::<f64>();
        for (a, b) in [(0, 0), (3, 2), (6, 0), (1, 5)] {
            let q: f64 = triangle_points([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &rule)
                .map(|(x, w)| w * x[0].powi(a) * x[1].powi(b))
                .sum();
            let exact = f(a as u32) * f(b as u32) / f(a as u32 + b as u32 + 2);
            assert!((q - exact).abs() < 1e-15, "{a} {b}: {q} {exact}");
        }
        // A square with a dented edge (not convex, star-shaped from its
        // centroid): the centroid fan; its area and ∫ x.
        let dented = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 1.8], [0.0, 2.0]];
        let tris = triangles(&dented);
        assert_eq!(tris.len(), 5);
        let integrals = |tris: &[[Point; 3]]| -> (f64, f64) {
            tris.iter()
                .flat_map(|&t| triangle_points(t, &rule))
                .fold((0.0, 0.0), |(s, m), (x, w)| (s + w, m + w * x[0] * x[1]))
        };
        let (area, mxy) = integrals(&tris);
        // ∫ xy = 1 (bottom 2 × 1.8 rectangle: 3.24) + the dented top's.
        let top: f64 = {
            // Over x in [0, 2] and y from 1.8 to the dent 2 - 0.2 (1 - |x - 1|).
            let q = GaussLegendre::new(6);
            q.on_interval(0.0, 1.0)
                .chain(q.on_interval(1.0, 2.0))
                .map(|(x, w)| {
                    let y1 = 1.8 + 0.2 * (x - 1.0).abs();
                    w * x * 0.5 * (y1 * y1 - 1.8 * 1.8)
                })
                .sum()
        };
        assert!((area - 3.8).abs() < 1e-14, "{area}");
        assert!((mxy - (3.24 + top)).abs() < 1e-13, "{mxy} {}", 3.24 + top);
        // A polygon that is not star-shaped from its centroid: some of the
        // fan's triangles are clockwise, and the signed rule is still exact
        // for polynomials: area 10 + 9 × 0.2 = 11.8, ∫ xy = 25 + 0.2² 100 / 4 - 0.2² / 4.
        let comb = [
            [0.0, 0.0],
            [10.0, 0.0],
            [10.0, 1.0],
            [0.2, 1.0],
            [0.2, 10.0],
            [0.0, 10.0],
        ];
        let tris = triangles(&comb);
        assert!(
            tris.iter().any(|t| cross(t[0], t[1], t[2]) < 0.0),
            "not star-shaped"
        );
        let (area, mxy) = integrals(&tris);
        let exact = 25.0 + 0.04 * (100.0 - 1.0) / 4.0;
        assert!((area - 11.8).abs() < 1e-12, "{area}");
        assert!((mxy - exact).abs() < 1e-11, "{mxy} {exact}");
        // Collinear samples and repeated points go.
        let square = vec![
            [0.0, 0.0],
            [0.5, 0.0],
            [1.0, 0.0],
            [1.0, 0.0],
            [1.0, 1.0],
            [0.0, 1.0],
        ];
        assert_eq!(simplify(square, 1e-12).len(), 4);
    }
}
