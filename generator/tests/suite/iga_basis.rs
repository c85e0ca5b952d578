//! Basis properties over random open knot vectors (degrees 1–4, random interior knots and
//! multiplicities) and random weights: partition of unity, derivatives summing to zero,
//! agreement with central finite differences, `C^(p−m)` continuity across knots of
//! multiplicity `m`, Marsden's identity, and rational curve derivatives (A4.2).
#![allow(clippy::needless_range_loop)]

use proptest::prelude::*;
use tcgen::basis::{basis_ders, nurbs_basis_into};
use tcgen::geometry::{KnotVector, NurbsPatch, RationalBasis};

/// Random open knot vector on `[a, a + len]`: degree 1–4, up to `max_interior` distinct interior
/// knots (separated by ≥ 3% of the range) with multiplicities 1..=p.
fn knot_vector(max_interior: usize) -> impl Strategy<Value = KnotVector> {
    (
        1usize..=4,
        -2.0f64..2.0,
        0.5f64..3.0,
        prop::collection::vec((0.02f64..0.98, 1usize..=4), 0..=max_interior),
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

/// A parameter strictly inside an element: (span, u, element length).
fn inside(kv: &KnotVector, pick: f64, s: f64) -> (usize, f64, f64) {
    let spans = kv.element_spans();
    let span = spans[((pick * spans.len() as f64) as usize).min(spans.len() - 1)];
    let (lo, hi) = (kv.knots()[span], kv.knots()[span + 1]);
    (span, lo + (hi - lo) * s, hi - lo)
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

    /// A2.1: the span brackets u (the last non-empty span at u = last); Greville abscissae
    /// reproduce u; one element per non-empty span.
    #[test]
    fn find_span_brackets_parameter(kv in knot_vector(5), t in 0.0f64..=1.0) {
        let u = kv.first() + t * (kv.last() - kv.first());
        let span = kv.find_span(u);
        let k = kv.knots();
        prop_assert!(kv.degree() <= span && span < kv.n_basis());
        prop_assert!(k[span] < k[span + 1]);
        prop_assert!(k[span] <= u && (u < k[span + 1] || (u == kv.last() && span == kv.n_basis() - 1)));
        prop_assert_eq!(kv.element_spans().len(), kv.n_elements());
        prop_assert_eq!(kv.n_elements() + 1, kv.breaks().len());
        let g = kv.greville();
        prop_assert_eq!(g.len(), kv.n_basis());
        let d = basis_ders(&kv, span, u, 0);
        let lin: f64 = (0..=kv.degree()).map(|j| g[span - kv.degree() + j] * d[0][j]).sum();
        prop_assert!((lin - u).abs() < 1e-13 * (1.0 + u.abs()));
    }

    /// Σ N_i = 1, N_i ≥ 0, Σ N_i' = Σ N_i'' = 0 anywhere, knots included.
    #[test]
    fn bspline_partition_of_unity_holds(kv in knot_vector(5), t in 0.0f64..=1.0) {
        let u = kv.first() + t * (kv.last() - kv.first());
        let d = basis_ders(&kv, kv.find_span(u), u, 2);
        prop_assert!((d[0].iter().sum::<f64>() - 1.0).abs() < 1e-13);
        prop_assert!(d[0].iter().all(|&n| n >= -1e-15));
        for k in 1..=2 {
            prop_assert!(d[k].iter().sum::<f64>().abs() <= 1e-11 * (1.0 + max_abs(&d[k])), "order {k}: {:?}", d[k]);
        }
        // At the knots themselves too.
        for &u in kv.knots() {
            let d = basis_ders(&kv, kv.find_span(u), u, 1);
            prop_assert!((d[0].iter().sum::<f64>() - 1.0).abs() < 1e-13);
        }
    }

    /// First and second derivatives agree with central differences of the lower order.
    #[test]
    fn bspline_derivatives_match_finite_differences(kv in knot_vector(5), pick in 0.0f64..1.0, s in 0.05f64..0.95) {
        let (span, u, len) = inside(&kv, pick, s);
        let h = 1e-5 * len;
        let d = basis_ders(&kv, span, u, 2);
        let dp = basis_ders(&kv, span, u + h, 1);
        let dm = basis_ders(&kv, span, u - h, 1);
        for k in 1..=2 {
            let scale = 1.0 + max_abs(&d[k]);
            for j in 0..=kv.degree() {
                let fd = (dp[k - 1][j] - dm[k - 1][j]) / (2.0 * h);
                prop_assert!((fd - d[k][j]).abs() <= 1e-6 * scale, "order {k}, j {j}: fd {fd} vs {}", d[k][j]);
            }
        }
    }

    /// Across an interior knot of multiplicity m, value and derivatives up to order p − m agree
    /// from the left and the right, and order p − m + 1 jumps.
    #[test]
    fn bspline_is_c_p_minus_m_across_knots(kv in knot_vector(5)) {
        let p = kv.degree();
        let spans = kv.element_spans();
        let n = kv.n_basis();
        for w in spans.windows(2) {
            let (left, right) = (w[0], w[1]);
            let tau = kv.knots()[right];
            let m = kv.multiplicity(tau);
            prop_assert_eq!(right - left, m);
            let dl = basis_ders(&kv, left, tau, p);
            let dr = basis_ders(&kv, right, tau, p);
            let global = |d: &Vec<Vec<f64>>, span: usize, k: usize| {
                let mut g = vec![0.0; n];
                for j in 0..=p {
                    g[span - p + j] = d[k][j];
                }
                g
            };
            for k in 0..=p {
                let (gl, gr) = (global(&dl, left, k), global(&dr, right, k));
                let scale = 1.0 + max_abs(&gl).max(max_abs(&gr));
                let jump = gl.iter().zip(&gr).fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                if k <= p - m {
                    prop_assert!(jump <= 1e-10 * scale, "order {k} jumps by {jump} at {tau} (m = {m}, p = {p})");
                } else if k == p - m + 1 {
                    prop_assert!(jump > 1e-6 * scale, "order {k} should jump at {tau} (m = {m}, p = {p})");
                }
            }
        }
    }

    /// Marsden's identity: (t − u)^p = Σ_i ψ_i(t) N_i(u), ψ_i(t) = Π_{j=1..p} (t − u_{i+j}).
    #[test]
    fn bspline_reproduces_polynomials_marsden(kv in knot_vector(5), s in 0.0f64..=1.0, t in -3.0f64..3.0) {
        let p = kv.degree();
        let u = kv.first() + s * (kv.last() - kv.first());
        let span = kv.find_span(u);
        let d = basis_ders(&kv, span, u, 0);
        let k = kv.knots();
        let mut sum = 0.0;
        let mut scale = 0.0;
        for j in 0..=p {
            let i = span - p + j;
            let psi: f64 = (1..=p).map(|l| t - k[i + l]).product();
            sum += psi * d[0][j];
            scale += (psi * d[0][j]).abs();
        }
        let exact = (t - u).powi(p as i32);
        prop_assert!((sum - exact).abs() <= 1e-12 * (1.0 + scale), "{sum} vs {exact}");
    }
}

/// Random tensor NURBS basis data: knot vectors (1–3 directions) and weights.
fn tensor_setup(
    dim: std::ops::RangeInclusive<usize>,
) -> impl Strategy<Value = (Vec<KnotVector>, Vec<f64>)> {
    prop::collection::vec(knot_vector(3), dim).prop_flat_map(|kvs| {
        let n: usize = kvs.iter().map(KnotVector::n_basis).product();
        (Just(kvs), prop::collection::vec(0.3f64..3.0, n))
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    /// NURBS (1D, 2D, 3D): Σ R = 1, Σ ∂R = Σ ∂²R = 0, derivatives match central differences,
    /// and the values equal w_a B_a / Σ w B computed from the univariate B-splines directly.
    #[test]
    fn nurbs_partition_of_unity_and_derivatives(
        (kvs, weights) in tensor_setup(1..=3),
        picks in prop::collection::vec((0.0f64..1.0, 0.05f64..0.95), 3),
    ) {
        let dim = kvs.len();
        let mut spans = [0usize; 3];
        let mut xi = vec![0.0; dim];
        let mut h = [0.0; 3];
        for d in 0..dim {
            let (s, u, len) = inside(&kvs[d], picks[d].0, picks[d].1);
            spans[d] = s;
            xi[d] = u;
            h[d] = 1e-5 * len;
        }
        let mut b = RationalBasis::default();
        nurbs_basis_into(&kvs, &weights, &spans, &xi, 2, &mut b);
        let local: usize = kvs.iter().map(|k| k.degree() + 1).product();
        prop_assert_eq!(b.len(), local);
        prop_assert!((b.values.iter().sum::<f64>() - 1.0).abs() < 1e-13);
        for k in 0..3 {
            let s1: f64 = b.d1.iter().map(|g| g[k]).sum();
            let sc1 = 1.0 + b.d1.iter().fold(0.0f64, |m, g| m.max(g[k].abs()));
            prop_assert!(s1.abs() <= 1e-11 * sc1);
            for l in 0..3 {
                let s2: f64 = b.d2.iter().map(|g| g[k][l]).sum();
                let sc2 = 1.0 + b.d2.iter().fold(0.0f64, |m, g| m.max(g[k][l].abs()));
                prop_assert!(s2.abs() <= 1e-11 * sc2);
                prop_assert!(b.d2.iter().all(|g| g[k][l] == g[l][k]));
                if k >= dim || l >= dim {
                    prop_assert!(b.d2.iter().all(|g| g[k][l] == 0.0));
                }
            }
        }
        // Direct formula for the values.
        let n_per: Vec<usize> = kvs.iter().map(KnotVector::n_basis).collect();
        let uni: Vec<Vec<Vec<f64>>> = (0..dim).map(|d| basis_ders(&kvs[d], spans[d], xi[d], 0)).collect();
        let mut direct = Vec::new();
        for &a in &b.indices {
            let mut rest = a;
            let mut prod = weights[a];
            for d in 0..dim {
                let i = rest % n_per[d];
                rest /= n_per[d];
                let p = kvs[d].degree();
                prop_assert!(i + p >= spans[d] && i <= spans[d]);
                prod *= uni[d][0][i + p - spans[d]];
            }
            direct.push(prod);
        }
        let total: f64 = direct.iter().sum();
        for (r, dv) in b.values.iter().zip(&direct) {
            prop_assert!((r - dv / total).abs() < 1e-14);
        }
        // Central differences in every direction.
        for k in 0..dim {
            let mut plus = RationalBasis::default();
            let mut minus = RationalBasis::default();
            let mut xp = xi.clone();
            let mut xm = xi.clone();
            xp[k] += h[k];
            xm[k] -= h[k];
            nurbs_basis_into(&kvs, &weights, &spans, &xp, 1, &mut plus);
            nurbs_basis_into(&kvs, &weights, &spans, &xm, 1, &mut minus);
            let sc1 = 1.0 + b.d1.iter().fold(0.0f64, |m, g| m.max(g[k].abs()));
            let sc2 = 1.0 + b.d2.iter().fold(0.0f64, |m, g| m.max(g[k].iter().fold(0.0f64, |a, x| a.max(x.abs()))));
            for a in 0..local {
                let fd = (plus.values[a] - minus.values[a]) / (2.0 * h[k]);
                prop_assert!((fd - b.d1[a][k]).abs() <= 1e-6 * sc1, "dR/dxi_{k}: fd {fd} vs {}", b.d1[a][k]);
                for l in 0..dim {
                    let fd2 = (plus.d1[a][l] - minus.d1[a][l]) / (2.0 * h[k]);
                    prop_assert!((fd2 - b.d2[a][l][k]).abs() <= 1e-6 * sc2, "d2R/dxi_{l}dxi_{k}: fd {fd2} vs {}", b.d2[a][l][k]);
                }
            }
        }
    }

    /// Rational curve derivatives (A4.2) agree with the point evaluation, with Σ R'_a P_a, and
    /// with central differences.
    #[test]
    fn curve_derivatives_match_basis_and_finite_differences(
        kv in knot_vector(4),
        seed in prop::collection::vec((-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0, 0.3f64..3.0), 40),
        pick in 0.0f64..1.0,
        s in 0.05f64..0.95,
    ) {
        let n = kv.n_basis();
        prop_assume!(n <= seed.len());
        let points: Vec<[f64; 3]> = seed[..n].iter().map(|q| [q.0, q.1, q.2]).collect();
        let weights: Vec<f64> = seed[..n].iter().map(|q| q.3).collect();
        let (_, u, len) = inside(&kv, pick, s);
        let curve = NurbsPatch::new(vec![kv], points.clone(), weights).unwrap();
        let c = curve.curve_derivatives(u, 3);
        prop_assert_eq!(c.len(), 4);
        let x = curve.point(&[u]);
        let b = curve.basis(&[u], 2);
        let h = 1e-5 * len;
        let cp = curve.curve_derivatives(u + h, 2);
        let cm = curve.curve_derivatives(u - h, 2);
        for i in 0..3 {
            prop_assert!((c[0][i] - x[i]).abs() < 1e-14);
            let from_basis: f64 = b.indices.iter().enumerate().map(|(a, &g)| b.d1[a][0] * points[g][i]).sum();
            let from_basis2: f64 = b.indices.iter().enumerate().map(|(a, &g)| b.d2[a][0][0] * points[g][i]).sum();
            let scale1 = 1.0 + c[1].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let scale2 = 1.0 + c[2].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let scale3 = 1.0 + c[3].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            prop_assert!((c[1][i] - from_basis).abs() <= 1e-12 * scale1);
            prop_assert!((c[2][i] - from_basis2).abs() <= 1e-11 * scale2);
            for k in 1..=3 {
                let fd = (cp[k - 1][i] - cm[k - 1][i]) / (2.0 * h);
                let scale = [scale1, scale2, scale3][k - 1];
                prop_assert!((fd - c[k][i]).abs() <= 1e-6 * scale, "C^({k}): fd {fd} vs {}", c[k][i]);
            }
        }
    }
}
