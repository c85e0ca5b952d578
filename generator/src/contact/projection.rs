//! Closest-point projection of a slave point onto the master curve (spec §6),
//! a THB (or NURBS) curve in the current configuration ([`MasterCurve`]): the
//! minimum distance over candidate elements (those near the previous
//! projection and near the closest samples of the curve, and their
//! neighbours), each by Newton on `φ(η) = (x_s − x_m(η))·x_m'(η) = 0`
//! clamped to the element; the periodic images of the master (PR conditions).
//!
//! Where the closest point is a C0 corner of the master (always the case
//! between the segments of a degree-1 master, and at the seam of a periodic
//! one) and the slave point lies in the corner's normal cone, no orthogonal
//! projection exists: the projection is the corner itself ([`Projection::vertex`]),
//! and the gap is the signed distance to it, which joins the gaps of the two
//! segments with a continuous normal (so Newton does not alternate between
//! the two segments).

use crate::basis::{RationalBasis, TensorBasis};
use crate::contact::pieces::FacePieces;
use crate::geometry::ThbPatch;
use crate::{Error, Result};

/// The master curve in the current configuration: the reference face patch (its
/// mesh, basis and weights) with current control points. Its elements are
/// ordered along the curve.
#[derive(Clone, Copy, Debug)]
pub struct MasterCurve<'a> {
    /// The master face (reference configuration).
    pub face: &'a ThbPatch,
    /// Current control points, in the face's numbering.
    pub points: &'a [[f64; 3]],
    /// The polynomial pieces of `face` at `points`, if built
    /// ([`FacePieces::new`]): [`MasterCurve::eval`] then reads them instead
    /// of the THB basis.
    pub pieces: Option<&'a FacePieces>,
}

impl MasterCurve<'_> {
    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.face.n_elements()
    }

    /// Parameter interval of element `e`.
    pub fn bounds(&self, e: usize) -> (f64, f64) {
        let el = &self.face.elements()[e];
        (el.lower[0], el.upper[0])
    }

    /// The element containing `eta`.
    pub fn locate(&self, eta: f64) -> usize {
        self.face.locate(&[eta])
    }

    /// The current point at `eta`.
    pub fn point(&self, eta: f64) -> [f64; 3] {
        let p = self.eval(self.locate(eta), eta)[0];
        [p[0], p[1], 0.0]
    }

    /// Position and first two parametric derivatives of element `e`'s polynomial
    /// (rational) piece at `eta` (one-sided at the element's ends).
    pub fn eval(&self, e: usize, eta: f64) -> [[f64; 2]; 3] {
        if let Some(s) = self.pieces.and_then(|p| p.at(self.face, e, &[eta])) {
            return [
                [s.x[0], s.x[1]],
                [s.a[0][0], s.a[0][1]],
                [s.aa[0][0][0], s.aa[0][0][1]],
            ];
        }
        let mut t = TensorBasis::default();
        let mut b = RationalBasis::default();
        self.face.element_basis_into(e, &[eta], 2, &mut t, &mut b);
        let mut out = [[0.0; 2]; 3];
        for (a, &g) in b.indices.iter().enumerate() {
            for c in 0..2 {
                out[0][c] += b.values[a] * self.points[g][c];
                out[1][c] += b.d1[a][0] * self.points[g][c];
                out[2][c] += b.d2[a][0][0] * self.points[g][c];
            }
        }
        out
    }
}

/// Result of a projection.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Projection {
    /// Master curve parameter.
    pub eta: f64,
    /// Master element whose polynomial piece holds the projection (for a
    /// projection at an element boundary, the side on which it is orthogonal).
    pub element: usize,
    /// Shift `k·W` added to the master's x coordinates (periodic image).
    pub shift: f64,
    /// The projection stopped at an end of a non-periodic master.
    pub clamped: bool,
    /// The closest point is a corner of the master (no orthogonal projection).
    pub vertex: bool,
    /// Distance to the projected point.
    pub distance: f64,
}

fn dist2(x: [f64; 2], c: [f64; 2]) -> f64 {
    (x[0] - c[0]).powi(2) + (x[1] - c[1]).powi(2)
}

/// Closest point of element `e` = `[a, b]` to `x`: Newton from `eta0` clamped
/// to the element, compared with the element's ends. Returns `(η, distance²)`.
fn element_minimum(curve: &MasterCurve, e: usize, x: [f64; 2], eta0: f64) -> (f64, f64) {
    let (a, b) = curve.bounds(e);
    let mut eta = eta0.clamp(a, b);
    for _ in 0..40 {
        let d = curve.eval(e, eta);
        let r = [x[0] - d[0][0], x[1] - d[0][1]];
        let t2 = d[1][0] * d[1][0] + d[1][1] * d[1][1];
        let phi = r[0] * d[1][0] + r[1] * d[1][1];
        let dphi = -t2 + r[0] * d[2][0] + r[1] * d[2][1];
        // Fall back to a gradient-like step where the curve is locally concave toward x.
        let step = if dphi < 0.0 { -phi / dphi } else { phi / t2 };
        let next = (eta + step).clamp(a, b);
        let done = (next - eta).abs() <= 1e-15 * (b - a);
        eta = next;
        if done {
            break;
        }
    }
    let mut best = (eta, dist2(x, curve.eval(e, eta)[0]));
    for end in [a, b] {
        let d = dist2(x, curve.eval(e, end)[0]);
        if d < best.1 {
            best = (end, d);
        }
    }
    best
}

/// The closest point of one element (image `shift`) to `x`, if it is an
/// orthogonal projection inside the element.
pub fn project_on_element(
    curve: &MasterCurve,
    x: [f64; 2],
    element: usize,
    shift: f64,
) -> Option<Projection> {
    let (a, b) = curve.bounds(element);
    let (eta, d2) = element_minimum(curve, element, [x[0] - shift, x[1]], 0.5 * (a + b));
    (eta > a && eta < b).then_some(Projection {
        eta,
        element,
        shift,
        clamped: false,
        vertex: false,
        distance: d2.sqrt(),
    })
}

/// Points of the master curve at 4 parameters per element: the candidates
/// for the starting guesses of the projections (computed once per evaluation).
pub struct MasterSamples {
    /// `(element index, η, point)`.
    samples: Vec<(usize, f64, [f64; 2])>,
}

impl MasterSamples {
    /// Samples `curve`.
    pub fn new(curve: &MasterCurve) -> Self {
        let mut samples = Vec::new();
        for e in 0..curve.n_elements() {
            let (a, b) = curve.bounds(e);
            for t in 0..4 {
                let eta = a + (b - a) * (t as f64 + 0.5) / 4.0;
                samples.push((e, eta, curve.eval(e, eta)[0]));
            }
        }
        MasterSamples { samples }
    }
}

/// Projects `x` onto `curve` (a 2D curve in the current configuration).
/// `guess`: the parameter found at the previous evaluation, if any.
/// `period`: the sample width when the master repeats periodically in x
/// (`x_m(η) + k·W` is then the image `k`).
pub fn project(
    curve: &MasterCurve,
    x: [f64; 2],
    guess: Option<f64>,
    period: Option<f64>,
    samples: &MasterSamples,
) -> Result<Projection> {
    let m = curve.n_elements();
    let shifts: Vec<f64> = match period {
        None => vec![0.0],
        Some(w) => {
            let x0 = curve.eval(0, curve.bounds(0).0)[0][0];
            let k = ((x[0] - x0) / w).floor();
            vec![k * w, (k - 1.0) * w, (k + 1.0) * w]
        }
    };
    // Candidate (element, shift) pairs: the 3 closest samples over the images
    // and the previous projection's element on every image, with neighbours.
    let mut near: Vec<(f64, usize, f64, f64)> = Vec::with_capacity(4);
    for &s in &shifts {
        for &(e, eta, c) in &samples.samples {
            let d = dist2([x[0] - s, x[1]], [c[0], c[1]]);
            if near.len() < 3 || d < near[near.len() - 1].0 {
                let at = near.partition_point(|n| n.0 <= d);
                near.insert(at, (d, e, s, eta));
                near.truncate(3);
            }
        }
    }
    let mut seeds: Vec<(usize, f64, f64)> = near.iter().map(|n| (n.1, n.2, n.3)).collect();
    if let Some(g) = guess {
        let e = curve.locate(g);
        for &s in &shifts {
            seeds.push((e, s, g));
        }
    }
    let neighbour = |e: usize, s: f64, step: i64| -> Option<(usize, f64)> {
        let j = e as i64 + step;
        match period {
            _ if (0..m as i64).contains(&j) => Some((j as usize, s)),
            Some(w) if j < 0 => Some((m - 1, s - w)),
            Some(w) => Some((0, s + w)),
            None => None,
        }
    };
    let mut candidates: Vec<(usize, f64, f64)> = Vec::with_capacity(3 * seeds.len());
    for &(e, s, eta) in &seeds {
        for step in [0, -1, 1] {
            if let Some((f, t)) = neighbour(e, s, step) {
                let start = if step == 0 { eta } else { f64::NAN };
                if !candidates
                    .iter()
                    .any(|c| c.0 == f && (c.1 - t).abs() <= 1e-9 * (1.0 + t.abs()))
                {
                    candidates.push((f, t, start));
                }
            }
        }
    }
    // The closest point over the candidates (ties keep the first found).
    let mut best: Option<(usize, f64, f64, f64)> = None;
    for &(e, s, start) in &candidates {
        let (a, b) = curve.bounds(e);
        let eta0 = if start.is_finite() {
            start
        } else {
            0.5 * (a + b)
        };
        let (eta, d2) = element_minimum(curve, e, [x[0] - s, x[1]], eta0);
        if best.is_none_or(|bb| d2 < bb.3 * (1.0 - 1e-13)) {
            best = Some((e, s, eta, d2));
        }
    }
    let (e, shift, eta, d2) = best.ok_or_else(|| {
        Error::Geometry(format!(
            "no projection of the point ({}, {}) onto the master surface",
            x[0], x[1]
        ))
    })?;
    let mut pr = Projection {
        eta,
        element: e,
        shift,
        clamped: false,
        vertex: false,
        distance: d2.sqrt(),
    };
    let mut e = e;
    // At an end of its element, the projection may continue into the next one
    // (a candidate's neighbour not searched yet): follow it.
    for _ in 0..m {
        match end_kind(curve, x, e, period, &pr) {
            End::Interior => {}
            End::Clamped => pr.clamped = true,
            End::Vertex => pr.vertex = true,
            End::Other(f, s, eta_other) => {
                pr.eta = eta_other;
                pr.element = f;
                pr.shift = s;
            }
            End::Descend(f, s, eta_other) => {
                let (eta, d2) = element_minimum(curve, f, [x[0] - s, x[1]], eta_other);
                pr = Projection {
                    eta,
                    element: f,
                    shift: s,
                    distance: d2.sqrt(),
                    ..pr
                };
                e = f;
                continue;
            }
        }
        break;
    }
    Ok(pr)
}

/// What a projection found by an element search is.
enum End {
    /// Inside its element (or orthogonal at its end): a regular projection.
    Interior,
    /// At an end of a non-periodic master.
    Clamped,
    /// At a corner, the point in its normal cone.
    Vertex,
    /// Orthogonal at the element boundary on the other side's element `(element, shift, η)`.
    Other(usize, f64, f64),
    /// The distance falls into the other side's element: search it from `η`.
    Descend(usize, f64, f64),
}

/// Classifies a projection at an end of its element `e`.
fn end_kind(
    curve: &MasterCurve,
    x: [f64; 2],
    e: usize,
    period: Option<f64>,
    pr: &Projection,
) -> End {
    let m = curve.n_elements();
    let (a, b) = curve.bounds(e);
    let at_start = pr.eta == a;
    if !at_start && pr.eta != b {
        return End::Interior;
    }
    // The other side of the knot: (element, shift, parameter there).
    let other = match (at_start, period) {
        (true, _) if e > 0 => Some((e - 1, pr.shift, a)),
        (false, _) if e + 1 < m => Some((e + 1, pr.shift, b)),
        (true, Some(w)) => Some((m - 1, pr.shift - w, curve.bounds(m - 1).1)),
        (false, Some(w)) => Some((0, pr.shift + w, curve.bounds(0).0)),
        _ => None,
    };
    let Some((f, s_other, eta_other)) = other else {
        return End::Clamped;
    };
    let here = curve.eval(e, pr.eta);
    let r = [x[0] - pr.shift - here[0][0], x[1] - here[0][1]];
    let rn = r[0].hypot(r[1]);
    let there = curve.eval(f, eta_other);
    // Cosines of the angles between the vector to the point and the tangent
    // (along increasing η) on this side and on the other side of the knot.
    let cosine = |t: [f64; 2]| (r[0] * t[0] + r[1] * t[1]) / (rn * t[0].hypot(t[1]));
    let (c_here, c_there) = (cosine(here[1]), cosine(there[1]));
    let tol = 1e-10;
    let h = here[1][0].hypot(here[1][1]) * (b - a);
    if rn <= 1e-12 * h || c_here.abs() <= tol {
        return End::Interior;
    }
    if c_there.abs() <= tol {
        return End::Other(f, s_other, eta_other);
    }
    // Entering the other element (backward from the start, forward from the
    // end) shortens the distance if the point lies ahead along its tangent.
    let descends = if at_start {
        c_there < 0.0
    } else {
        c_there > 0.0
    };
    if descends {
        End::Descend(f, s_other, eta_other)
    } else {
        End::Vertex
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{NurbsPatch, shapes};

    fn curve(c: &ThbPatch) -> MasterCurve<'_> {
        MasterCurve {
            face: c,
            pieces: None,
            points: c.control_points(),
        }
    }

    /// The polynomial pieces are the curve: position and derivatives as the
    /// THB basis gives them on a locally refined (truncated) curve of
    /// degrees 1–3, the same projections; rational elements (the arc) are
    /// left to the basis.
    #[test]
    fn polynomial_pieces_evaluate_the_curve() {
        use crate::geometry::KnotVector;
        let mut rnd = crate::contact::testing::rng(11);
        for (p, n) in [(1, 6), (2, 5), (3, 4)] {
            let kv = KnotVector::open_uniform(p, n, 0.0, 1.0);
            let points: Vec<[f64; 3]> = kv
                .greville()
                .iter()
                .map(|&g| [g, 0.1 * (2.0 * rnd() - 1.0), 0.0])
                .collect();
            let m = points.len();
            let coarse = ThbPatch::from(&NurbsPatch::new(vec![kv], points, vec![1.0; m]).unwrap());
            let mut mesh = coarse.mesh().clone();
            mesh.refine_where(|_, lo, _| lo[0] < 0.45);
            let c = coarse.with_mesh(mesh);
            assert!(c.n_elements() > n, "refined");
            let moved: Vec<[f64; 3]> = c
                .control_points()
                .iter()
                .map(|x| [x[0] + 0.01 * rnd(), x[1] + 0.02 * rnd(), 0.0])
                .collect();
            let pieces = FacePieces::new(&c, &moved);
            assert!(pieces.coefficients.iter().all(|v| v.is_some()));
            let plain = MasterCurve {
                face: &c,
                points: &moved,
                pieces: None,
            };
            let fast = MasterCurve {
                pieces: Some(&pieces),
                ..plain
            };
            for e in 0..c.n_elements() {
                let (a, b) = plain.bounds(e);
                for _ in 0..5 {
                    let eta = a + rnd() * (b - a);
                    let (u, v) = (plain.eval(e, eta), fast.eval(e, eta));
                    let scale = u.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
                    for (x, y) in u.iter().flatten().zip(v.iter().flatten()) {
                        assert!(
                            (x - y).abs() < 1e-12 * scale,
                            "p = {p}, element {e}: {x} vs {y}"
                        );
                    }
                }
            }
            let (sa, sb) = (MasterSamples::new(&plain), MasterSamples::new(&fast));
            for _ in 0..40 {
                let x = [1.2 * rnd() - 0.1, 0.4 * rnd() - 0.2];
                for period in [None, Some(1.0)] {
                    let (u, v) = (
                        project(&plain, x, None, period, &sa).unwrap(),
                        project(&fast, x, None, period, &sb).unwrap(),
                    );
                    assert!((u.distance - v.distance).abs() < 1e-12, "{u:?} {v:?}");
                    assert_eq!(u.element, v.element);
                }
            }
        }
        let arc = ThbPatch::from(&shapes::circular_arc([0.0; 3], 2.0, 0.0, 1.0));
        let pieces = FacePieces::new(&arc, arc.control_points());
        assert!(pieces.coefficients.iter().all(|v| v.is_none()));
    }

    #[test]
    fn projects_onto_a_circle_exactly() {
        let c = ThbPatch::from(&shapes::circular_arc(
            [0.0, 0.0, 0.0],
            2.0,
            0.0,
            std::f64::consts::FRAC_PI_2,
        ));
        let c = curve(&c);
        let x = [3.0 * 0.6, 3.0 * 0.8];
        let p = project(&c, x, None, None, &MasterSamples::new(&c)).unwrap();
        assert!((p.distance - 1.0).abs() < 1e-12);
        let y = c.point(p.eta);
        assert!((y[0] - 1.2).abs() < 1e-12 && (y[1] - 1.6).abs() < 1e-12);
    }

    #[test]
    fn clamps_beyond_the_end_and_wraps_periodic_images() {
        let line = ThbPatch::from(
            &shapes::rectangle(0.0, 1.0, 0.0, 1.0)
                .face(1, crate::geometry::Side::Low)
                .0,
        );
        let line = curve(&line);
        let s = MasterSamples::new(&line);
        let p = project(&line, [1.3, 0.2], None, None, &s).unwrap();
        assert!(p.clamped && (p.eta - 1.0).abs() < 1e-15);
        let q = project(&line, [1.3, 0.2], None, Some(1.0), &s).unwrap();
        assert!(!q.clamped && (q.shift - 1.0).abs() < 1e-15 && (q.eta - 0.3).abs() < 1e-12);
        assert!((q.distance - 0.2).abs() < 1e-12);
    }

    /// A degree-1 "Λ" polyline (0,0)–(1,1)–(2,0).
    fn roof() -> ThbPatch {
        let kv = crate::geometry::KnotVector::new(1, vec![0.0, 0.0, 0.5, 1.0, 1.0]).unwrap();
        ThbPatch::from(
            &NurbsPatch::new(
                vec![kv],
                vec![[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [2.0, 0.0, 0.0]],
                vec![1.0; 3],
            )
            .unwrap(),
        )
    }

    #[test]
    fn a_point_in_the_normal_cone_of_a_corner_projects_onto_the_corner() {
        let c = roof();
        let c = curve(&c);
        let s = MasterSamples::new(&c);
        let p = project(&c, [1.0, 2.0], None, None, &s).unwrap();
        assert!(p.vertex && !p.clamped);
        assert!((p.eta - 0.5).abs() < 1e-15 && (p.distance - 1.0).abs() < 1e-14);
        // Beside the corner: the orthogonal projection onto a segment.
        let q = project(&c, [0.5, 1.0], Some(0.9), None, &s).unwrap();
        assert!(!q.vertex && !q.clamped && q.element == 0);
        assert!((q.eta - 0.375).abs() < 1e-14, "{q:?}");
        assert!((q.distance - 0.125f64.sqrt()).abs() < 1e-14);
    }

    #[test]
    fn projection_distance_is_the_minimum_over_the_curve() {
        // The roof and its periodic images (period 2): distance against a
        // dense sampling, from every kind of starting guess.
        let c = roof();
        let c = curve(&c);
        let s = MasterSamples::new(&c);
        let dense: Vec<[f64; 3]> = (0..=20000).map(|k| c.point(k as f64 / 20000.0)).collect();
        let mut rnd = crate::contact::testing::rng(3);
        for _ in 0..400 {
            let x = [-1.0 + 4.0 * rnd(), -1.0 + 3.0 * rnd()];
            let guess = (rnd() < 0.5).then(&mut rnd);
            for period in [None, Some(2.0)] {
                let p = project(&c, x, guess, period, &s).unwrap();
                let shifts: &[f64] = if period.is_some() {
                    &[-4.0, -2.0, 0.0, 2.0, 4.0]
                } else {
                    &[0.0]
                };
                let brute = shifts
                    .iter()
                    .flat_map(|&sh| {
                        dense
                            .iter()
                            .map(move |d| (x[0] - d[0] - sh).hypot(x[1] - d[1]))
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    p.distance <= brute + 1e-12 && p.distance >= brute - 1e-4,
                    "{x:?} {period:?}: {} vs {brute}",
                    p.distance
                );
                let y = c.point(p.eta);
                let d = (x[0] - y[0] - p.shift).hypot(x[1] - y[1]);
                assert!((d - p.distance).abs() < 1e-12);
            }
        }
    }
}
