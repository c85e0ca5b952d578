//! Gauss–Legendre exactness, exact areas, volumes and perimeters of NURBS geometries by
//! element, face and curve quadrature (also after refinement and degree elevation), outward
//! face normals, consistency of bulk gradients with face quadrature (divergence theorem), and
//! face patches.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;
use tcgen::geometry::{KnotVector, NurbsPatch, Side, circular_arc, cuboid, quarter_annulus};
use tcgen::quadrature::GaussLegendre;

/// Annulus `ri ≤ r ≤ ro` as one patch: dir 0 the full circle (4 segments), dir 1 radial.
fn full_annulus(ri: f64, ro: f64) -> NurbsPatch {
    let circle = circular_arc([0.0; 3], 1.0, 0.0, 2.0 * PI);
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for r in [ri, ro] {
        for (p, &w) in circle.control_points().iter().zip(circle.weights()) {
            points.push([r * p[0], r * p[1], 0.0]);
            weights.push(w);
        }
    }
    let radial = KnotVector::open_uniform(1, 1, 0.0, 1.0);
    NurbsPatch::new(vec![circle.knots()[0].clone(), radial], points, weights).unwrap()
}

/// The quarter annulus extruded to `0 ≤ z ≤ height` (3D NURBS volume).
fn quarter_annulus_slab(ri: f64, ro: f64, height: f64) -> NurbsPatch {
    let base = quarter_annulus(ri, ro);
    let mut points = Vec::new();
    let mut weights = Vec::new();
    for z in [0.0, height] {
        for (p, &w) in base.control_points().iter().zip(base.weights()) {
            points.push([p[0], p[1], z]);
            weights.push(w);
        }
    }
    let mut knots = base.knots().to_vec();
    knots.push(KnotVector::open_uniform(1, 1, 0.0, 1.0));
    NurbsPatch::new(knots, points, weights).unwrap()
}

/// A smoothly distorted unit cube, cubic in every direction with 2 elements.
fn distorted_cube() -> NurbsPatch {
    let mut cube = cuboid([0.0; 3], [1.0; 3]);
    for d in 0..3 {
        cube = cube.elevate_degree(d, 2).refine_uniform(d, 2);
    }
    cube.map_points(|[x, y, z]| {
        [
            x + 0.05 * (3.0 * y).sin() * z,
            y + 0.04 * (2.0 * x + z).cos(),
            z + 0.06 * x * y * (1.0 - x),
        ]
    })
}

fn measure(patch: &NurbsPatch, n_gauss: usize) -> f64 {
    patch
        .elements()
        .iter()
        .flat_map(|el| patch.element_quadrature(el, &[n_gauss]).points)
        .map(|q| q.weight)
        .sum()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn gauss_legendre_is_exact_to_degree_2n_minus_1() {
    for n in 1..=12 {
        let g = GaussLegendre::new(n);
        let integrate = |k: i32| {
            g.points
                .iter()
                .zip(&g.weights)
                .map(|(x, w)| w * x.powi(k))
                .sum::<f64>()
        };
        let exact = |k: i32| {
            if k % 2 == 1 {
                0.0
            } else {
                2.0 / (k as f64 + 1.0)
            }
        };
        for k in 0..2 * n as i32 {
            let err = (integrate(k) - exact(k)).abs();
            assert!(err < 1e-14, "n = {n}, x^{k}: error {err}");
        }
        // Degree 2n is not integrated exactly: the rule is sharp.
        let k = 2 * n as i32;
        assert!(
            (integrate(k) - exact(k)).abs() > 1e-10,
            "n = {n}: x^{k} unexpectedly exact"
        );
        // Mapped rule: ∫_1^3 x^(2n-1) dx.
        let mapped: f64 = g
            .on_interval(1.0, 3.0)
            .map(|(x, w)| w * x.powi(2 * n as i32 - 1))
            .sum();
        let m = 2.0 * n as f64;
        assert!(rel(mapped, (3f64.powf(m) - 1.0) / m) < 1e-14);
    }
}

#[test]
fn quarter_annulus_area_is_exact_after_refinement_and_elevation() {
    let (ri, ro) = (0.7, 2.3);
    let exact = PI * (ro * ro - ri * ri) / 4.0;
    let base = quarter_annulus(ri, ro);
    let variants = [
        ("base", base.clone()),
        ("h-refined", base.refine_uniform(0, 3).refine_uniform(1, 2)),
        ("p-elevated", base.elevate_degree(0, 1).elevate_degree(1, 2)),
        (
            "k-refined",
            base.elevate_degree(0, 2)
                .refine_uniform(0, 4)
                .elevate_degree(1, 1)
                .refine_uniform(1, 3),
        ),
        (
            "inserted",
            base.insert_knots(0, &[0.3, 0.3, 0.8])
                .insert_knots(1, &[0.25]),
        ),
    ];
    for (name, patch) in &variants {
        let area = measure(patch, 12);
        println!(
            "{name:>10}: area {area:.16} (error {:.2e})",
            rel(area, exact)
        );
        assert!(rel(area, exact) < 1e-12, "{name}: area {area} vs {exact}");
    }
    let annulus = full_annulus(ri, ro);
    assert!(rel(measure(&annulus, 12), 4.0 * exact) < 1e-12);
}

#[test]
fn element_quadrature_reproduces_linear_fields() {
    let patch = quarter_annulus(0.5, 1.5)
        .elevate_degree(1, 1)
        .refine_uniform(0, 2)
        .refine_uniform(1, 2);
    let cp = patch.control_points();
    for el in patch.elements() {
        let eq = patch.element_quadrature(&el, &[3, 4]);
        assert_eq!(eq.points.len(), 12);
        let mut scratch = Vec::new();
        let dr_dx = eq.gradients(&mut scratch);
        let n = eq.conn.len();
        for (iq, q) in eq.points.iter().enumerate() {
            let (rq, dq) = (eq.values(iq), &dr_dx[iq * n..(iq + 1) * n]);
            assert!((rq.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            let r = (q.x[0] * q.x[0] + q.x[1] * q.x[1]).sqrt();
            assert!((0.5..=1.5).contains(&r));
            for i in 0..2 {
                let x: f64 = eq.conn.iter().zip(rq).map(|(&a, r)| r * cp[a][i]).sum();
                assert!((x - q.x[i]).abs() < 1e-14);
                for j in 0..3 {
                    // Σ_a x_a,i ∂R_a/∂x_j = δ_ij.
                    let g: f64 = eq.conn.iter().zip(dq).map(|(&a, d)| cp[a][i] * d[j]).sum();
                    let expected = if i == j { 1.0 } else { 0.0 };
                    assert!((g - expected).abs() < 1e-12, "grad x_{i}/x_{j} = {g}");
                }
            }
        }
    }
}

/// ∫_Ω ∂R_a/∂x_i dΩ = ∮_∂Ω R_a n_i dΓ for every basis function: checks bulk gradients, face
/// weights, normals, face basis values and connectivity against each other.
fn check_divergence_theorem(patch: &NurbsPatch, n_gauss: usize, tol: f64) {
    let dim = patch.param_dim();
    let n = patch.n_control_points();
    let mut bulk = vec![[0.0; 3]; n];
    for el in patch.elements() {
        let eq = patch.element_quadrature(&el, &[n_gauss]);
        let mut scratch = Vec::new();
        let dr_dx = eq.gradients(&mut scratch);
        for (iq, q) in eq.points.iter().enumerate() {
            for (k, &a) in eq.conn.iter().enumerate() {
                for i in 0..dim {
                    bulk[a][i] += q.weight * dr_dx[iq * eq.conn.len() + k][i];
                }
            }
        }
    }
    let mut boundary = vec![[0.0; 3]; n];
    for dir in 0..dim {
        for side in [Side::Low, Side::High] {
            for fe in patch.face_quadrature(dir, side, n_gauss) {
                for q in &fe.points {
                    for (k, &a) in fe.conn.iter().enumerate() {
                        for i in 0..dim {
                            boundary[a][i] += q.weight * q.r[k] * q.normal[i];
                        }
                    }
                }
            }
        }
    }
    let scale = bulk.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = bulk
        .iter()
        .flatten()
        .zip(boundary.iter().flatten())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!("divergence theorem: worst {worst:.2e}, scale {scale:.2e}");
    assert!(
        worst <= tol * scale,
        "divergence theorem violated: {worst} (scale {scale})"
    );
}

#[test]
fn divergence_theorem_holds_2d() {
    let patch = quarter_annulus(0.6, 1.9)
        .elevate_degree(0, 1)
        .refine_uniform(0, 3)
        .refine_uniform(1, 2);
    check_divergence_theorem(&patch, 12, 1e-12);
    check_divergence_theorem(&full_annulus(1.0, 2.0).refine_uniform(1, 2), 12, 1e-12);
}

#[test]
fn divergence_theorem_holds_3d() {
    check_divergence_theorem(
        &quarter_annulus_slab(0.6, 1.9, 0.4).refine_uniform(2, 2),
        12,
        1e-12,
    );
    check_divergence_theorem(&distorted_cube(), 10, 1e-9);
}

#[test]
fn circle_perimeter_by_curve_and_face_quadrature() {
    let (ri, ro) = (0.8, 1.7);
    let rule = GaussLegendre::new(12);
    for (start, sweep) in [(0.0, 2.0 * PI), (0.4, 2.5), (1.0, -1.2)] {
        let arc = circular_arc([0.3, -0.2, 0.0], ro, start, start + sweep);
        let kv = &arc.knots()[0];
        let mut length = 0.0;
        for span in kv.element_spans() {
            for (u, w) in rule.on_interval(kv.knots()[span], kv.knots()[span + 1]) {
                let d = arc.curve_derivatives(u, 1)[1];
                length += w * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            }
        }
        assert!(
            rel(length, ro * sweep.abs()) < 1e-12,
            "arc length {length} vs {}",
            ro * sweep.abs()
        );
    }
    let annulus = full_annulus(ri, ro);
    for (side, r, sign) in [(Side::Low, ri, -1.0), (Side::High, ro, 1.0)] {
        let faces = annulus.face_quadrature(1, side, 12);
        assert_eq!(faces.len(), 4);
        let mut perimeter = 0.0;
        for fe in &faces {
            for q in &fe.points {
                perimeter += q.weight;
                let rad = (q.x[0] * q.x[0] + q.x[1] * q.x[1]).sqrt();
                assert!((rad - r).abs() < 1e-13);
                for i in 0..2 {
                    assert!(
                        (q.normal[i] - sign * q.x[i] / rad).abs() < 1e-13,
                        "normal {:?} at {:?}",
                        q.normal,
                        q.x
                    );
                }
                assert_eq!(q.normal[2], 0.0);
            }
        }
        assert!(
            rel(perimeter, 2.0 * PI * r) < 1e-12,
            "perimeter {perimeter} vs {}",
            2.0 * PI * r
        );
    }
}

#[test]
fn quarter_annulus_face_normals_point_outward() {
    let (ri, ro) = (0.5, 2.0);
    let patch = quarter_annulus(ri, ro)
        .refine_uniform(0, 2)
        .elevate_degree(1, 1)
        .refine_uniform(1, 3);
    let straight = ro - ri;
    let cases: [(usize, Side, f64); 4] = [
        (0, Side::Low, straight),
        (0, Side::High, straight),
        (1, Side::Low, PI * ri / 2.0),
        (1, Side::High, PI * ro / 2.0),
    ];
    for (dir, side, expected_length) in cases {
        let mut length = 0.0;
        for fe in patch.face_quadrature(dir, side, 12) {
            for q in &fe.points {
                length += q.weight;
                let rad = (q.x[0] * q.x[0] + q.x[1] * q.x[1]).sqrt();
                let expected = match (dir, side) {
                    (0, Side::Low) => [0.0, -1.0],
                    (0, Side::High) => [-1.0, 0.0],
                    (1, Side::Low) => [-q.x[0] / rad, -q.x[1] / rad],
                    _ => [q.x[0] / rad, q.x[1] / rad],
                };
                assert!(
                    (q.normal[0] - expected[0]).abs() < 1e-13
                        && (q.normal[1] - expected[1]).abs() < 1e-13
                );
                assert!((q.r.iter().sum::<f64>() - 1.0).abs() < 1e-14);
                let cp = patch.control_points();
                for i in 0..3 {
                    let x: f64 = fe.conn.iter().zip(&q.r).map(|(&a, r)| r * cp[a][i]).sum();
                    assert!((x - q.x[i]).abs() < 1e-13);
                }
            }
        }
        assert!(
            rel(length, expected_length) < 1e-12,
            "dir {dir} {side:?}: {length} vs {expected_length}"
        );
    }
}

#[test]
fn cuboid_faces_have_outward_normals_and_exact_areas() {
    let (lo, hi) = ([0.0, -1.0, 2.0], [3.0, 1.5, 2.5]);
    let patch = cuboid(lo, hi)
        .elevate_degree(0, 1)
        .refine_uniform(0, 2)
        .refine_uniform(2, 3);
    let volume: f64 = (0..3).map(|i| hi[i] - lo[i]).product();
    assert!(rel(measure(&patch, 3), volume) < 1e-14);
    for dir in 0..3 {
        for (side, sign) in [(Side::Low, -1.0), (Side::High, 1.0)] {
            let mut area = 0.0;
            for fe in patch.face_quadrature(dir, side, 2) {
                for q in &fe.points {
                    area += q.weight;
                    for i in 0..3 {
                        let expected = if i == dir { sign } else { 0.0 };
                        assert!((q.normal[i] - expected).abs() < 1e-14);
                    }
                    let face_coord = if side == Side::Low { lo[dir] } else { hi[dir] };
                    assert!((q.x[dir] - face_coord).abs() < 1e-14);
                }
            }
            assert!(rel(area, volume / (hi[dir] - lo[dir])) < 1e-14);
        }
    }
}

#[test]
fn slab_volume_and_lateral_areas_are_exact() {
    let (ri, ro, h) = (0.7, 1.6, 0.35);
    let slab = quarter_annulus_slab(ri, ro, h)
        .elevate_degree(2, 1)
        .refine_uniform(0, 2);
    assert!(rel(measure(&slab, 12), h * PI * (ro * ro - ri * ri) / 4.0) < 1e-12);
    let outer: f64 = slab
        .face_quadrature(1, Side::High, 12)
        .iter()
        .flat_map(|f| &f.points)
        .map(|q| q.weight)
        .sum();
    assert!(rel(outer, h * PI * ro / 2.0) < 1e-12);
    for fe in slab.face_quadrature(2, Side::High, 6) {
        for q in &fe.points {
            assert!((q.normal[2] - 1.0).abs() < 1e-14 && (q.x[2] - h).abs() < 1e-14);
        }
    }
}

#[test]
fn face_patch_matches_patch_on_its_face() {
    let slab = quarter_annulus_slab(0.5, 1.0, 0.2)
        .elevate_degree(1, 1)
        .refine_uniform(0, 2);
    for dir in 0..3 {
        for side in [Side::Low, Side::High] {
            let (face, indices) = slab.face(dir, side);
            assert_eq!(face.param_dim(), 2);
            assert_eq!(indices.len(), face.n_control_points());
            for (k, &a) in indices.iter().enumerate() {
                assert_eq!(face.control_points()[k], slab.control_points()[a]);
                assert_eq!(face.weights()[k], slab.weights()[a]);
            }
            for s in 0..=6 {
                for t in 0..=6 {
                    let eta = [s as f64 / 6.0, t as f64 / 6.0];
                    let mut xi = vec![0.0; 3];
                    let mut m = 0;
                    for d in 0..3 {
                        xi[d] = if d == dir {
                            if side == Side::Low { 0.0 } else { 1.0 }
                        } else {
                            m += 1;
                            eta[m - 1]
                        };
                    }
                    let (a, b) = (face.point(&eta), slab.point(&xi));
                    assert!((0..3).all(|i| (a[i] - b[i]).abs() < 1e-14));
                }
            }
        }
    }
}
