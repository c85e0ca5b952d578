//! 3D micro-sample geometry (issue 12 item 1): the bivariate B-spline fit of
//! a height function on the periodic cell converges at the interpolation
//! order `p + 1`, reports its error, is periodic and smooth across the seams
//! (the periodic spline interpolant) for periodic surfaces, and
//! the rough NURBS volumes of both bodies (non-matching meshes) carry the
//! fitted surface exactly with a positive Jacobian.

use std::path::Path;

use tcgen::geometry::{RoughFace, fit_height_map, try_rough_volume};
use tcgen::surface::{ArealSpec, SinusoidPattern};

const W: f64 = 1.0e-5;

fn egg_box() -> Box<dyn tcgen::surface::ArealSurface> {
    ArealSpec::Sinusoid {
        rms: 1e-6,
        wavelength: W,
        pattern: SinusoidPattern::EggBox,
        phase: 0.0,
        phase_y: 0.0,
    }
    .build("surface.upper", W, Path::new("."))
    .unwrap()
}

/// Max error ratio on halving the elements: 2^(p+1) (interpolation at the
/// Greville points of a smooth function).
#[test]
fn areal_fit_converges_at_order_p_plus_1() {
    let s = egg_box();
    let f = |x: f64, y: f64| s.height(x, y);
    for p in [1usize, 2, 3] {
        let errors: Vec<f64> = [8usize, 16, 32]
            .iter()
            .map(|&n| fit_height_map(&f, W, p, [n, n + n / 2]).unwrap().max_error)
            .collect();
        let rate = (errors[1] / errors[2]).log2();
        assert!(
            (rate - (p + 1) as f64).abs() < 0.3,
            "p = {p}: rate {rate}, errors {errors:?}"
        );
        assert!(errors[2] < 1e-2 * 2e-6, "p = {p}: {errors:?}");
    }
}

#[test]
fn areal_fit_is_periodic_and_exact_on_the_cell_boundary() {
    let s = egg_box();
    let f = |x: f64, y: f64| s.height(x, y);
    let fit = fit_height_map(&f, W, 2, [12, 9]).unwrap();
    let (nx, ny) = (fit.x.len(), fit.y.len());
    for j in 0..ny {
        assert_eq!(fit.heights[j * nx], fit.heights[j * nx + nx - 1]);
    }
    for i in 0..nx {
        assert_eq!(fit.heights[i], fit.heights[(ny - 1) * nx + i]);
    }
    assert!(fit.rms_error > 0.0 && fit.rms_error < fit.max_error);
    assert!(fit_height_map(&f, W, 0, [4, 4]).is_err());
    // A surface that is not periodic: interpolated at the Greville points,
    // which include the corners.
    let g = |x: f64, y: f64| 1e-7 * (x / W + 2.0 * (y / W).powi(2)) + f(x, y);
    let fit = fit_height_map(&g, W, 2, [5, 4]).unwrap();
    for (x, y) in [(0.0, 0.0), (W, 0.0), (0.0, W), (W, W)] {
        assert!((fit.height_at(x, y) - g(x, y)).abs() < 1e-18, "({x}, {y})");
    }
}

/// A periodic surface on a coarse mesh (5 × 4 elements): the fit is the
/// periodic spline interpolant, C^(p−1) across both seams of the cell (one-
/// sided slopes agree; a clamped interpolant would kink there), and it
/// interpolates at the periodic Greville points (knots for odd p, element
/// mid-points for even p).
#[test]
fn periodic_areal_fit_is_smooth_across_the_seams() {
    let tau = std::f64::consts::TAU;
    let f = |x: f64, y: f64| {
        1e-6 * ((tau * (x + 2.0 * y) / W + 0.7).sin() + 0.5 * (2.0 * tau * y / W - 0.2).cos())
    };
    let n = [5usize, 4];
    for p in [1usize, 2, 3] {
        let fit = fit_height_map(&f, W, p, n).unwrap();
        let offset = if p % 2 == 1 { 0.0 } else { 0.5 };
        for i in 0..n[0] {
            for j in 0..n[1] {
                let (x, y) = (
                    W * (i as f64 + offset) / n[0] as f64,
                    W * (j as f64 + offset) / n[1] as f64,
                );
                let e = (fit.height_at(x, y) - f(x, y)).abs();
                assert!(e < 1e-12 * 1e-6, "p = {p}: error {e} at ({x}, {y})");
            }
        }
        let h = 1e-6 * W;
        for t in [0.13, 0.5, 0.91].map(|t| t * W) {
            let z = |x: f64, y: f64| fit.height_at(x, y);
            let seams = [z(0.0, t) - z(W, t), z(t, 0.0) - z(t, W)];
            assert!(seams.iter().all(|d| d.abs() < 1e-18), "p = {p}: {seams:?}");
            if p == 1 {
                continue;
            }
            // One-sided slopes across the x seam and the y seam.
            let sx = [(z(h, t) - z(0.0, t)) / h, (z(W, t) - z(W - h, t)) / h];
            let sy = [(z(t, h) - z(t, 0.0)) / h, (z(t, W) - z(t, W - h)) / h];
            let scale = 1e-6 * tau / W;
            for s in [sx, sy] {
                assert!((s[0] - s[1]).abs() < 1e-4 * scale, "p = {p}: slopes {s:?}");
            }
        }
    }
}

/// Both bodies of a 3D sample, non-matching (different element counts):
/// the rough faces carry the fitted surfaces, the outer faces are flat, the
/// Jacobian is positive everywhere sampled, and a fold is an error.
#[test]
fn rough_volumes_of_both_bodies() {
    let s = egg_box();
    let f = |x: f64, y: f64| s.height(x, y);
    let height = 7e-6;
    for (n, face, z_shift, z_flat) in [
        ([8, 8], RoughFace::Bottom, 0.0, height),
        ([6, 7], RoughFace::Top, 0.0, -height),
    ] {
        let fit = fit_height_map(&f, W, 2, n).unwrap();
        let patch = try_rough_volume(&fit, z_shift, z_flat, face, 2, 4).unwrap();
        assert_eq!(patch.param_dim(), 3);
        let rough_w = if face == RoughFace::Bottom { 0.0 } else { 1.0 };
        let flat_w = 1.0 - rough_w;
        for k in 0..7 {
            for l in 0..5 {
                let (u, v) = (k as f64 / 6.0, l as f64 / 4.0);
                let p = patch.point(&[u, v, rough_w]);
                assert!((p[0] - W * u).abs() < 1e-18 && (p[1] - W * v).abs() < 1e-18);
                assert!((p[2] - fit.height_at(p[0], p[1])).abs() < 1e-18, "{p:?}");
                let q = patch.point(&[u, v, flat_w]);
                assert!((q[2] - z_flat).abs() < 1e-18);
                for w in [0.0, 0.3, 1.0] {
                    let (_, j) = patch.jacobian(&[u, v, w]);
                    let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
                        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
                        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
                    assert!(det > 0.0, "det {det} at {u} {v} {w}");
                }
            }
        }
    }
    let fit = fit_height_map(&f, W, 2, [8, 8]).unwrap();
    let e = try_rough_volume(&fit, 0.0, 1e-6, RoughFace::Bottom, 2, 4).unwrap_err();
    assert!(e.to_string().contains("not strictly below"), "{e}");
}

/// Refined rough volumes resolve the surface instead of keeping the case
/// mesh's fit (`resolve_rough_face`): refined uniformly at the rough face, the
/// face's height error falls at the order `p + 1` of the finer level, while
/// the lateral map, the flat face and the periodic seams stay as they were.
#[test]
fn refined_rough_volumes_resolve_the_surface() {
    use tcgen::geometry::{Side, ThbPatch, resolve_rough_face};
    let s = egg_box();
    let f = |x: f64, y: f64| s.height(x, y);
    let (height, z_shift) = (7e-6, 2e-6);
    let fit = fit_height_map(&f, W, 2, [6, 6]).unwrap();
    let block = try_rough_volume(&fit, z_shift, height + z_shift, RoughFace::Bottom, 2, 3).unwrap();
    let coarse = ThbPatch::from_nurbs(&block).periodic(0).periodic(1);
    let face_error = |patch: &ThbPatch| {
        let mut worst = 0.0f64;
        for k in 0..=48 {
            for l in 0..=48 {
                let (u, v) = (k as f64 / 48.0, l as f64 / 48.0);
                let p = patch.point(&[u, v, 0.0]);
                assert!((p[0] - W * u).abs() < 1e-18 && (p[1] - W * v).abs() < 1e-18);
                let q = patch.point(&[u, v, 1.0]);
                assert!(
                    (q[2] - height - z_shift).abs() < 1e-18,
                    "flat face moved: {q:?}"
                );
                worst = worst.max((p[2] - f(p[0], p[1]) - z_shift).abs());
            }
        }
        worst
    };
    let fit_error = face_error(&coarse);
    let mut errors = Vec::new();
    for levels in 1..=3 {
        let refined = coarse.refined_at_face(2, Side::Low, levels);
        let resolved = resolve_rough_face(&refined, RoughFace::Bottom, z_shift, f).unwrap();
        errors.push(face_error(&resolved));
        // The seams: the face's heights at u = 0 and u = 1 (v = 0 and 1) agree.
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            for (a, b) in [([0.0, t], [1.0, t]), ([t, 0.0], [t, 1.0])] {
                let (pa, pb) = (
                    resolved.point(&[a[0], a[1], 0.0]),
                    resolved.point(&[b[0], b[1], 0.0]),
                );
                assert!((pa[2] - pb[2]).abs() < 1e-20, "seam: {pa:?} {pb:?}");
            }
        }
    }
    let rate = (errors[1] / errors[2]).log2();
    println!("fit error {fit_error:e}; resolved on 1, 2, 3 levels: {errors:?}, rate {rate:.2}");
    assert!(errors[0] < fit_error, "{errors:?} vs the fit's {fit_error}");
    assert!(rate > 2.5, "rate {rate}: {errors:?}");
    // An unrefined block is moved onto the quasi-interpolant of the surface:
    // of the fit's order, not worse.
    let same = resolve_rough_face(&coarse, RoughFace::Bottom, z_shift, f).unwrap();
    assert!(face_error(&same) < 2.0 * fit_error);
}
