//! Knot insertion, degree elevation and uniform refinement leave the geometry of random rational
//! curves, surfaces and volumes unchanged (to 1e-12 at many points) and produce the expected
//! knot vectors.
#![allow(clippy::needless_range_loop)]

use proptest::prelude::*;
use tcgen::geometry::{KnotVector, NurbsPatch};

/// Random open knot vector on `[a, a + len]`: degree 1–4, up to 3 distinct interior knots
/// with multiplicities 1..=p.
fn knot_vector() -> impl Strategy<Value = KnotVector> {
    (
        1usize..=4,
        -2.0f64..2.0,
        0.5f64..3.0,
        prop::collection::vec((0.02f64..0.98, 1usize..=4), 0..=3),
    )
        .prop_map(|(p, a, len, interior)| {
            let mut interior: Vec<(f64, usize)> =
                interior.into_iter().map(|(t, m)| (t, m.min(p))).collect();
            interior.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut knots = vec![a; p + 1];
            let mut last_t = 0.0;
            for (t, m) in interior {
                if t - last_t > 0.03 {
                    knots.extend(std::iter::repeat_n(a + len * t, m));
                    last_t = t;
                }
            }
            knots.extend(std::iter::repeat_n(a + len, p + 1));
            KnotVector::new(p, knots).expect("valid by construction")
        })
}

/// A random rational patch with 1 to 3 directions, control points in [-1, 1]³, weights in [0.3, 3].
fn patch(dims: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = NurbsPatch> {
    prop::collection::vec(knot_vector(), dims).prop_flat_map(|kvs| {
        let n: usize = kvs.iter().map(KnotVector::n_basis).product();
        (
            Just(kvs),
            prop::collection::vec(([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], 0.3f64..3.0), n),
        )
            .prop_map(|(kvs, cw)| {
                let (points, weights) = cw.into_iter().unzip();
                NurbsPatch::new(kvs, points, weights).unwrap()
            })
    })
}

/// Largest distance between the two patches' points at `samples` parameter points (given as
/// fractions of each parameter range; knots and ends included by the fractions 0 and 1).
fn max_deviation(a: &NurbsPatch, b: &NurbsPatch, samples: &[[f64; 3]]) -> f64 {
    let mut worst = 0.0f64;
    for s in samples {
        let xi: Vec<f64> = a
            .knots()
            .iter()
            .enumerate()
            .map(|(d, kv)| kv.first() + s[d] * (kv.last() - kv.first()))
            .collect();
        let (x, y) = (a.point(&xi), b.point(&xi));
        worst = worst.max((0..3).map(|i| (x[i] - y[i]).abs()).fold(0.0, f64::max));
    }
    worst
}

fn samples() -> impl Strategy<Value = Vec<[f64; 3]>> {
    prop::collection::vec([0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.0], 40).prop_map(|mut v| {
        v.push([0.0; 3]);
        v.push([1.0; 3]);
        v
    })
}

/// Knots of `kv` in (first, last) plus `fractions` mapped into the range, and, if possible, one
/// repeated existing interior knot.
fn new_knots(kv: &KnotVector, fractions: &[f64], repeat_existing: bool) -> Vec<f64> {
    let mut x: Vec<f64> = fractions
        .iter()
        .map(|t| kv.first() + t * (kv.last() - kv.first()))
        .collect();
    if repeat_existing
        && let Some(&k) = kv.breaks()[1..kv.breaks().len() - 1]
            .iter()
            .find(|&&k| kv.multiplicity(k) < kv.degree())
    {
        x.push(k);
    }
    x
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]

    /// Knot insertion (A5.4) in a random direction: same geometry, knot vector is the union.
    #[test]
    fn knot_insertion_preserves_geometry(
        p in patch(1..=3),
        dir_pick in 0usize..3,
        fractions in prop::collection::vec(0.01f64..0.99, 1..=4),
        repeat in any::<bool>(),
        s in samples(),
    ) {
        let dir = dir_pick % p.param_dim();
        let kv = &p.knots()[dir];
        let x = new_knots(kv, &fractions, repeat);
        // Skip the rare case of a new value repeated beyond the degree.
        prop_assume!(x.iter().all(|&u| x.iter().filter(|&&v| v == u).count() + kv.multiplicity(u) <= kv.degree()));
        let q = p.insert_knots(dir, &x);
        let mut expected: Vec<f64> = kv.knots().iter().copied().chain(x.iter().copied()).collect();
        expected.sort_by(f64::total_cmp);
        prop_assert_eq!(q.knots()[dir].knots(), &expected[..]);
        prop_assert_eq!(q.n_control_points(), p.n_control_points() / kv.n_basis() * (kv.n_basis() + x.len()));
        prop_assert!(q.weights().iter().all(|&w| w > 0.0));
        let dev = max_deviation(&p, &q, &s);
        prop_assert!(dev < 1e-12, "deviation {dev}");
    }

    /// Degree elevation (A5.9) by 1 or 2 in a random direction: same geometry, degree p + t,
    /// every distinct knot's multiplicity raised by t.
    #[test]
    fn degree_elevation_preserves_geometry(
        p in patch(1..=3),
        dir_pick in 0usize..3,
        t in 1usize..=2,
        s in samples(),
    ) {
        let dir = dir_pick % p.param_dim();
        let kv = &p.knots()[dir];
        let q = p.elevate_degree(dir, t);
        let kq = &q.knots()[dir];
        prop_assert_eq!(kq.degree(), kv.degree() + t);
        prop_assert_eq!(kq.breaks(), kv.breaks());
        for b in kv.breaks() {
            prop_assert_eq!(kq.multiplicity(b), kv.multiplicity(b) + t);
        }
        for d in 0..p.param_dim() {
            if d != dir {
                prop_assert_eq!(&q.knots()[d], &p.knots()[d]);
            }
        }
        prop_assert!(q.weights().iter().all(|&w| w > 0.0));
        let dev = max_deviation(&p, &q, &s);
        prop_assert!(dev < 1e-12, "deviation {dev}");
    }

    /// Uniform refinement: every element split into equal parts, same geometry; combined with
    /// elevation in another direction (k-refinement order does not matter for the geometry).
    #[test]
    fn uniform_refinement_preserves_geometry(
        p in patch(1..=3),
        dir_pick in 0usize..3,
        subdivisions in 1usize..=3,
        s in samples(),
    ) {
        let dir = dir_pick % p.param_dim();
        let q = p.refine_uniform(dir, subdivisions);
        prop_assert_eq!(q.knots()[dir].n_elements(), p.knots()[dir].n_elements() * subdivisions);
        prop_assert_eq!(q.n_elements(), p.n_elements() * subdivisions);
        let dev = max_deviation(&p, &q, &s);
        prop_assert!(dev < 1e-12, "deviation {dev}");
        let other = (dir + 1) % p.param_dim();
        let r = q.elevate_degree(other, 1).refine_uniform(other, 2);
        let dev = max_deviation(&p, &r, &s);
        prop_assert!(dev < 1e-12, "deviation after elevation and refinement {dev}");
    }
}

/// Degree elevation of a Bézier curve matches the closed form
/// `Q_i = (i/(p+1)) P_{i−1} + (1 − i/(p+1)) P_i` (on homogeneous points).
#[test]
fn bezier_degree_elevation_matches_closed_form() {
    let kv = KnotVector::open_uniform(3, 1, 0.0, 1.0);
    let points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 2.0, 0.0],
        [3.0, -1.0, 1.0],
        [4.0, 0.5, 0.0],
    ];
    let weights = vec![1.0, 2.0, 0.5, 1.0];
    let curve = NurbsPatch::new(vec![kv], points.clone(), weights.clone()).unwrap();
    let up = curve.elevate_degree(0, 1);
    assert_eq!(
        up.knots()[0].knots(),
        &[0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0]
    );
    let hom = |i: usize| {
        [
            weights[i] * points[i][0],
            weights[i] * points[i][1],
            weights[i] * points[i][2],
            weights[i],
        ]
    };
    for i in 0..=4 {
        let a = i as f64 / 4.0;
        let mut q = [0.0; 4];
        for c in 0..4 {
            let prev = if i > 0 { hom(i - 1)[c] } else { 0.0 };
            let cur = if i < 4 { hom(i)[c] } else { 0.0 };
            q[c] = a * prev + (1.0 - a) * cur;
        }
        assert!((up.weights()[i] - q[3]).abs() < 1e-15);
        for c in 0..3 {
            assert!((up.control_points()[i][c] - q[c] / q[3]).abs() < 1e-14);
        }
    }
}

/// Inserting an existing knot up to multiplicity p makes the curve C^0 there and keeps it.
#[test]
fn knot_insertion_to_full_multiplicity_interpolates_curve_point() {
    let kv = KnotVector::open_uniform(3, 2, 0.0, 1.0);
    let points: Vec<[f64; 3]> = (0..5)
        .map(|i| [i as f64, ((i * 7) % 3) as f64, 0.0])
        .collect();
    let curve = NurbsPatch::new(vec![kv], points, vec![1.0, 0.7, 1.3, 0.9, 1.0]).unwrap();
    let c = curve.point(&[0.5]);
    let q = curve.insert_knots(0, &[0.5, 0.5]);
    assert_eq!(q.knots()[0].multiplicity(0.5), 3);
    // With multiplicity p the curve passes through control point span - p.
    let span = q.knots()[0].find_span(0.5);
    let cp = q.control_points()[span - 3];
    for i in 0..3 {
        assert!((cp[i] - c[i]).abs() < 1e-14);
    }
}
