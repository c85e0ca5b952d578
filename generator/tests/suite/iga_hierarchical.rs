//! Truncated hierarchical B-splines (`geometry::hierarchical`): the basis
//! properties the analysis relies on, in 1, 2 and 3 parametric directions and
//! degrees 1–3, on randomly refined meshes: non-negativity and partition of
//! unity, linear independence, exact geometry, exact prolongation to a
//! refinement (nested spaces), traces on faces, and identity with the NURBS
//! patch when unrefined; on dyadic meshes and on meshes whose levels halve the
//! tangential directions and the normal one in turn.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tcgen::basis::{RationalBasis, TensorBasis};
use tcgen::geometry::{
    Cell, HierarchicalMesh, KnotVector, NurbsPatch, Side, ThbPatch, cuboid, quarter_annulus,
};

/// A base patch of `dim` directions and degree `p` on the unit box (a curved quarter
/// annulus for `dim == 2`), `n` elements per direction, degree-elevated and refined.
fn base(dim: usize, p: usize, n: usize) -> NurbsPatch {
    let mut patch = match dim {
        1 => NurbsPatch::bspline(
            vec![KnotVector::open_uniform(1, 1, 0.0, 1.0)],
            vec![[0.0, 0.0, 0.0], [1.0, 0.5, 0.0]],
        )
        .unwrap(),
        2 => quarter_annulus(1.0, 2.0),
        _ => cuboid([0.0; 3], [1.0, 2.0, 0.5]),
    };
    for d in 0..dim {
        let have = patch.knots()[d].degree();
        if have < p {
            patch = patch.elevate_degree(d, p - have);
        }
        patch = patch.refine_uniform(d, n);
    }
    patch
}

/// The THB patch of [`base`]: dyadic, or (`graded`) with levels that halve the directions
/// before the last and then the last in turn (in 1D: none, then the direction; a repeated
/// level as in the face traces of such meshes).
fn start(dim: usize, p: usize, n: usize, graded: bool) -> ThbPatch {
    if graded {
        let pattern = HierarchicalMesh::alternating_pattern(dim, dim - 1);
        ThbPatch::from_nurbs_with_pattern(&base(dim, p, n), pattern)
    } else {
        ThbPatch::from_nurbs(&base(dim, p, n))
    }
}

/// Refines random active cells in `rounds` rounds.
fn random_refinement(patch: &ThbPatch, rounds: usize, rng: &mut ChaCha8Rng) -> ThbPatch {
    let mut p = patch.clone();
    for _ in 0..rounds {
        let cells: Vec<Cell> = p.elements().iter().map(|e| e.cell).collect();
        let k = 1 + cells.len() / 6;
        let marked: Vec<Cell> = (0..k)
            .map(|_| cells[rng.random_range(0..cells.len())])
            .collect();
        p = p.refined(&marked);
    }
    p
}

fn random_xi(dim: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    (0..dim).map(|_| rng.random_range(0.0..1.0)).collect()
}

/// `(dim, p, graded)`: 1 to 3 directions, degrees 1 to 3, dyadic and graded ([`start`]).
fn cases() -> Vec<(usize, usize, bool)> {
    let mut v = Vec::new();
    for graded in [false, true] {
        for dim in 1..=3 {
            for p in 1..=3 {
                v.push((dim, p, graded));
            }
        }
    }
    v
}

#[test]
fn basis_is_non_negative_and_a_partition_of_unity() {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for (dim, p, graded) in cases() {
        let n = if dim == 3 { 2 } else { 4 };
        let thb = random_refinement(&start(dim, p, n, graded), 3, &mut rng);
        assert!(
            thb.mesh().n_levels() >= 2,
            "dim {dim} p {p} graded {graded}: refined"
        );
        let (mut scratch, mut b) = (TensorBasis::default(), RationalBasis::default());
        for _ in 0..200 {
            let xi = random_xi(dim, &mut rng);
            // The polynomial THB functions themselves (the rational weighting would
            // normalise any sum to one).
            thb.thb_functions_into(thb.locate(&xi), &xi, 2, &mut scratch, &mut b);
            let sum: f64 = b.values.iter().sum();
            assert!(
                (sum - 1.0).abs() < 1e-13,
                "dim {dim} p {p} graded {graded}: Σ T = {sum}"
            );
            assert!(
                b.values.iter().all(|&v| v >= -1e-15),
                "dim {dim} p {p} graded {graded}"
            );
            for k in 0..dim {
                let s: f64 = b.d1.iter().map(|g| g[k]).sum();
                assert!(
                    s.abs() < 1e-10,
                    "dim {dim} p {p} graded {graded}: Σ ∂T = {s}"
                );
                for l in 0..dim {
                    let s: f64 = b.d2.iter().map(|h| h[k][l]).sum();
                    assert!(
                        s.abs() < 1e-8,
                        "dim {dim} p {p} graded {graded}: Σ ∂²T = {s}"
                    );
                }
            }
        }
    }
}

#[test]
fn derivatives_match_finite_differences() {
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for (dim, p, graded) in cases() {
        let thb = random_refinement(&start(dim, p, 3, graded), 2, &mut rng);
        for _ in 0..40 {
            let xi = random_xi(dim, &mut rng);
            let e = thb.locate(&xi);
            let b = thb.element_basis(e, &xi, 2);
            let h = 1e-6;
            for k in 0..dim {
                let (mut xp, mut xm) = (xi.clone(), xi.clone());
                xp[k] += h;
                xm[k] -= h;
                let (bp, bm) = (thb.element_basis(e, &xp, 1), thb.element_basis(e, &xm, 1));
                for a in 0..b.len() {
                    let fd = (bp.values[a] - bm.values[a]) / (2.0 * h);
                    assert!(
                        (fd - b.d1[a][k]).abs() < 1e-6,
                        "dim {dim} p {p} graded {graded}"
                    );
                    for l in 0..dim {
                        let fd2 = (bp.d1[a][l] - bm.d1[a][l]) / (2.0 * h);
                        assert!(
                            (fd2 - b.d2[a][k][l]).abs() < 1e-4,
                            "dim {dim} p {p} graded {graded}"
                        );
                    }
                }
            }
        }
    }
}

/// The Gram matrix `∫ R_a R_b` over the parameter domain is positive definite.
#[test]
fn basis_is_linearly_independent() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for (dim, p, graded) in cases() {
        let n = if dim == 3 { 2 } else { 3 };
        let thb = random_refinement(&start(dim, p, n, graded), 3, &mut rng);
        let nf = thb.n_control_points();
        let mut gram = nalgebra::DMatrix::<f64>::zeros(nf, nf);
        let rule = tcgen::quadrature::GaussLegendre::new(p + 1);
        let (mut scratch, mut b) = (TensorBasis::default(), RationalBasis::default());
        for (e, el) in thb.elements().iter().enumerate() {
            let m = rule.len().pow(dim as u32);
            let vol: f64 = (0..dim).map(|d| el.upper[d] - el.lower[d]).product();
            for q in 0..m {
                let mut xi = vec![0.0; dim];
                let mut w = vol;
                let mut rest = q;
                for (d, x) in xi.iter_mut().enumerate() {
                    let g = rest % rule.len();
                    rest /= rule.len();
                    *x = el.lower[d] + (el.upper[d] - el.lower[d]) * 0.5 * (1.0 + rule.points[g]);
                    w *= 0.5 * rule.weights[g];
                }
                thb.element_basis_into(e, &xi, 0, &mut scratch, &mut b);
                for (i, &a) in b.indices.iter().enumerate() {
                    for (j, &c) in b.indices.iter().enumerate() {
                        gram[(a, c)] += w * b.values[i] * b.values[j];
                    }
                }
            }
        }
        let eig = gram.symmetric_eigenvalues();
        let (lo, hi) = (eig.min(), eig.max());
        assert!(
            lo > 1e-12 * hi,
            "dim {dim} p {p} graded {graded}: Gram matrix eigenvalues in [{lo:e}, {hi:e}]"
        );
    }
}

#[test]
fn geometry_is_exact_after_refinement() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for (dim, p, graded) in cases() {
        let nurbs = base(dim, p, 2);
        let thb = random_refinement(&start(dim, p, 2, graded), 3, &mut rng);
        for _ in 0..100 {
            let xi = random_xi(dim, &mut rng);
            let (a, b) = (nurbs.point(&xi), thb.point(&xi));
            for i in 0..3 {
                assert!(
                    (a[i] - b[i]).abs() < 1e-13,
                    "dim {dim} p {p} graded {graded}: {a:?} vs {b:?}"
                );
            }
        }
    }
    // The quarter annulus's area, by bulk quadrature of the refined patch (8 points per
    // direction: the rational Jacobian's quadrature error below round-off).
    let mut rng = ChaCha8Rng::seed_from_u64(40);
    let thb = random_refinement(&ThbPatch::from_nurbs(&base(2, 2, 2)), 4, &mut rng);
    let area: f64 = (0..thb.n_elements())
        .map(|e| {
            thb.element_quadrature(e, &[8])
                .points
                .iter()
                .map(|q| q.weight)
                .sum::<f64>()
        })
        .sum();
    let exact = std::f64::consts::PI * (4.0 - 1.0) / 4.0;
    assert!((area - exact).abs() < 1e-13, "area {area} vs {exact}");
}

/// Copies that move the control points only (the model's scaled geometry, a fitted
/// surface) share the refined patch's basis and mesh instead of copying them, and
/// evaluate their own points; the quadrature reports the bytes it holds.
#[test]
fn moved_copies_share_the_basis() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let thb = random_refinement(&ThbPatch::from_nurbs(&base(3, 2, 2)), 2, &mut rng);
    let scaled = thb.map_points(|x| [2.0 * x[0], 2.0 * x[1], 2.0 * x[2]]);
    let moved = thb.with_control_points(vec![[0.0; 3]; thb.n_control_points()]);
    for copy in [&scaled, &moved] {
        assert!(
            std::ptr::eq(copy.thb_basis(), thb.thb_basis()),
            "the basis is shared"
        );
        assert!(std::ptr::eq(copy.mesh(), thb.mesh()), "the mesh is shared");
    }
    let xi = random_xi(3, &mut rng);
    let (a, b) = (thb.point(&xi), scaled.point(&xi));
    for i in 0..3 {
        assert!((2.0 * a[i] - b[i]).abs() < 1e-13, "{a:?} vs {b:?}");
    }
    // p = 2 on 3 points per direction: the values are kept and the gradients
    // recovered from them; on 2 points the gradients are stored as well.
    let q = thb.element_quadrature(0, &[3]);
    let functions = q.conn.len();
    let values = 27 * functions * size_of::<f64>();
    assert!(!q.stores_gradients());
    assert!(
        q.storage_bytes() >= values && q.storage_bytes() < 2 * values,
        "{} bytes for 27 points of {functions} functions",
        q.storage_bytes()
    );
    let q = thb.element_quadrature(0, &[2]);
    assert!(q.stores_gradients());
    assert!(q.storage_bytes() >= 8 * functions * 4 * size_of::<f64>());
}

/// The prolongation (and its matrix) reproduces the coarse field.
#[test]
fn prolongation_is_exact() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for (dim, p, graded) in cases() {
        let coarse = random_refinement(&start(dim, p, 2, graded), 2, &mut rng);
        let fine = random_refinement(&coarse, 2, &mut rng);
        let u: Vec<f64> = (0..coarse.n_control_points() * 2)
            .map(|_| rng.random_range(-1.0..1.0))
            .collect();
        let v = coarse.prolongate(&fine, &u, 2);
        // Its matrix gives the same coefficients.
        let mut w = vec![0.0; v.len()];
        for (a, g, x) in coarse.prolongation_entries(&fine) {
            w[2 * a] += x * u[2 * g];
            w[2 * a + 1] += x * u[2 * g + 1];
        }
        for (x, y) in v.iter().zip(&w) {
            assert!(
                (x - y).abs() < 1e-13,
                "dim {dim} p {p} graded {graded}: matrix {y} vs {x}"
            );
        }
        let field = |patch: &ThbPatch, c: &[f64], xi: &[f64]| {
            let b = patch.element_basis(patch.locate(xi), xi, 0);
            let mut s = [0.0; 2];
            for (&a, &r) in b.indices.iter().zip(&b.values) {
                s[0] += r * c[2 * a];
                s[1] += r * c[2 * a + 1];
            }
            s
        };
        for _ in 0..100 {
            let xi = random_xi(dim, &mut rng);
            let (a, b) = (field(&coarse, &u, &xi), field(&fine, &v, &xi));
            assert!(
                (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12,
                "dim {dim} p {p} graded {graded}: {a:?} vs {b:?}"
            );
        }
    }
}

#[test]
fn unrefined_patch_is_the_nurbs_patch() {
    for (dim, p, _) in cases().into_iter().filter(|c| c.0 >= 2 && !c.2) {
        let nurbs = base(dim, p, 3);
        let thb = ThbPatch::from_nurbs(&nurbs);
        assert_eq!(thb.n_control_points(), nurbs.n_control_points());
        let els = nurbs.elements();
        assert_eq!(thb.n_elements(), els.len());
        for (e, el) in els.iter().enumerate() {
            let (a, b) = (
                nurbs.element_quadrature(el, &[p + 1]),
                thb.element_quadrature(e, &[p + 1]),
            );
            assert_eq!(a.conn, b.conn);
            let (mut sa, mut sb) = (Vec::new(), Vec::new());
            let (ga, gb) = (a.gradients(&mut sa), b.gradients(&mut sb));
            for (q, (qa, qb)) in a.points.iter().zip(&b.points).enumerate() {
                assert!((qa.weight - qb.weight).abs() < 1e-14);
                for (ra, rb) in a.values(q).iter().zip(b.values(q)) {
                    assert!((ra - rb).abs() < 1e-14);
                }
            }
            for (da, db) in ga.iter().zip(gb) {
                for i in 0..dim {
                    assert!((da[i] - db[i]).abs() < 1e-11, "{da:?} vs {db:?}");
                }
            }
        }
        for dir in 0..dim {
            for side in [Side::Low, Side::High] {
                let (fa, fb) = (
                    nurbs.face_quadrature(dir, side, 3),
                    thb.face_quadrature(dir, side, 3),
                );
                assert_eq!(fa.len(), fb.len());
                for (a, b) in fa.iter().zip(&fb) {
                    assert_eq!(a.conn, b.conn);
                    for (qa, qb) in a.points.iter().zip(&b.points) {
                        assert!((qa.weight - qb.weight).abs() < 1e-13);
                        for i in 0..3 {
                            assert!((qa.normal[i] - qb.normal[i]).abs() < 1e-13);
                        }
                        for (ra, rb) in qa.r.iter().zip(&qb.r) {
                            assert!((ra - rb).abs() < 1e-13);
                        }
                    }
                }
                assert_eq!(nurbs.face(dir, side).1, thb.face(dir, side).1);
            }
        }
    }
}

/// The face patch's functions are the traces of the volume functions it names; the
/// volume functions it does not name vanish on the face.
#[test]
fn face_basis_is_the_trace_of_the_volume_basis() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for (dim, p, graded) in cases().into_iter().filter(|c| c.0 >= 2) {
        let thb = random_refinement(&start(dim, p, 3, graded), 3, &mut rng);
        for dir in 0..dim {
            for side in [Side::Low, Side::High] {
                let (face, idx) = thb.face(dir, side);
                let end = if side == Side::Low { 0.0 } else { 1.0 };
                for _ in 0..50 {
                    let fxi = random_xi(dim - 1, &mut rng);
                    let mut xi = Vec::new();
                    let mut k = 0;
                    for d in 0..dim {
                        if d == dir {
                            xi.push(end);
                        } else {
                            xi.push(fxi[k]);
                            k += 1;
                        }
                    }
                    let vb = thb.element_basis(thb.locate(&xi), &xi, 0);
                    let fb = face.element_basis(face.locate(&fxi), &fxi, 0);
                    for (a, &g) in vb.indices.iter().enumerate() {
                        let on_face = fb.indices.iter().position(|&f| idx[f] == g);
                        let trace = on_face.map_or(0.0, |f| fb.values[f]);
                        assert!(
                            (vb.values[a] - trace).abs() < 1e-13,
                            "dim {dim} p {p} graded {graded} face ({dir}, {side:?}): {} vs {trace}",
                            vb.values[a]
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn periodic_directions_have_matching_face_bases() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    for (dim, graded) in [(2, false), (3, false), (2, true), (3, true)] {
        let start = start(dim, 2, 4, graded);
        let mut mesh = start.mesh().clone();
        mesh.set_periodic(0);
        let thb0 = start.with_mesh(mesh);
        let thb = random_refinement(&thb0, 3, &mut rng);
        let (lo, _) = thb.face(0, Side::Low);
        let (hi, _) = thb.face(0, Side::High);
        assert_eq!(lo.n_control_points(), hi.n_control_points());
        for a in 0..lo.n_control_points() {
            assert_eq!(lo.thb_basis().function(a), hi.thb_basis().function(a));
        }
    }
}

/// `Σ_a c_a T_a(ξ)` in the polynomial THB functions.
fn thb_sum(patch: &ThbPatch, c: &[f64], xi: &[f64]) -> f64 {
    let (mut scratch, mut b) = (TensorBasis::default(), RationalBasis::default());
    patch.thb_functions_into(patch.locate(xi), xi, 0, &mut scratch, &mut b);
    b.indices
        .iter()
        .zip(&b.values)
        .map(|(&a, &t)| c[a] * t)
        .sum()
}

/// The hierarchical quasi-interpolant reproduces every function of the THB space
/// (its coefficients are returned exactly) on randomly refined meshes, and
/// approximates a smooth function at order `p + 1` under uniform refinement.
#[test]
fn quasi_interpolant_reproduces_the_space_and_converges() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for (dim, p, graded) in cases() {
        let thb = random_refinement(&start(dim, p, 2, graded), 3, &mut rng);
        let c: Vec<f64> = (0..thb.n_control_points())
            .map(|_| rng.random_range(-1.0..1.0))
            .collect();
        let q = thb.quasi_interpolate(|xi| thb_sum(&thb, &c, &xi[..dim]));
        let worst = c
            .iter()
            .zip(&q)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-11,
            "dim {dim} p {p} graded {graded}: coefficients off by {worst:e}"
        );
    }
    // Order p + 1 for g = sin(3ξ + 1) cos(2η) on uniformly refined 2D meshes.
    let g = |xi: [f64; 3]| (3.0 * xi[0] + 1.0).sin() * (2.0 * xi[1]).cos();
    for p in 1..=3 {
        let mut thb = ThbPatch::from_nurbs(&base(2, p, 2));
        let mut errors = Vec::new();
        for _ in 0..4 {
            let q = thb.quasi_interpolate(g);
            let mut worst = 0.0f64;
            for i in 0..=40 {
                for j in 0..=40 {
                    let xi = [i as f64 / 40.0, j as f64 / 40.0];
                    worst = worst.max((thb_sum(&thb, &q, &xi) - g([xi[0], xi[1], 0.0])).abs());
                }
            }
            errors.push(worst);
            let cells: Vec<Cell> = thb.elements().iter().map(|e| e.cell).collect();
            thb = thb.refined(&cells);
        }
        let rate = (errors[2] / errors[3]).log2();
        assert!(
            rate > p as f64 + 0.7,
            "p {p}: errors {errors:?}, observed rate {rate:.2}"
        );
    }
}
