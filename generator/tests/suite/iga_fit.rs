//! Surface fitting (spec §3): polynomial reproduction, convergence rate `p + 1` for a sinusoid,
//! periodic end heights, and the fitted rough block's exact map, faces and area.
#![allow(clippy::needless_range_loop)]

use std::f64::consts::PI;
use tcgen::geometry::{
    FitMethod, RoughFace, Side, fit_height_function, rough_block, try_rough_block,
};

const METHODS: [FitMethod; 2] = [FitMethod::Interpolation, FitMethod::LeastSquares];

/// A polynomial of degree `p` on `[0, 2.5]` with O(1) values.
fn polynomial(p: usize) -> impl Fn(f64) -> f64 {
    move |x: f64| {
        (0..=p)
            .map(|k| (0.7 - 0.3 * k as f64) * (x - 1.1).powi(k as i32))
            .sum()
    }
}

#[test]
fn fit_reproduces_polynomials_of_degree_p() {
    let width = 2.5;
    for p in 1..=4 {
        for n_el in [1, 3, 7] {
            for method in METHODS {
                let f = polynomial(p);
                let fit = fit_height_function(&f, width, p, n_el, method);
                assert_eq!(fit.heights.len(), n_el + p);
                assert!(
                    fit.max_error < 1e-12,
                    "p {p}, {n_el} elements, {method:?}: max error {}",
                    fit.max_error
                );
                assert!(fit.rms_error <= fit.max_error);
                for s in 0..=37 {
                    let x = width * s as f64 / 37.0;
                    assert!((fit.height_at(x) - f(x)).abs() < 1e-12);
                }
                // x(u) = W u exactly: control abscissae are W × Greville.
                let g = fit.knots.greville();
                assert!(
                    fit.x
                        .iter()
                        .zip(&g)
                        .all(|(x, g)| (x - width * g).abs() < 1e-15)
                );
                assert_eq!(fit.width(), width);
                // One degree more is not reproduced (the check can fail).
                let q = polynomial(p + 1);
                let coarse = fit_height_function(&q, width, p, n_el, method);
                assert!(coarse.max_error > 1e-8, "degree p + 1 unexpectedly exact");
            }
        }
    }
}

/// Log–log least-squares slope of `errors` against `h = 1/n`.
fn rate(n: &[usize], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = n.iter().map(|&k| (1.0 / k as f64).ln()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (
        xs.iter().sum::<f64>() / xs.len() as f64,
        ys.iter().sum::<f64>() / ys.len() as f64,
    );
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[test]
fn sinusoid_fit_error_converges_at_rate_p_plus_1() {
    // Paper default: period 10 μm, RMS 1 μm.
    let lambda = 10e-6;
    let amplitude = 2f64.sqrt() * 1e-6;
    let f = move |x: f64| amplitude * (2.0 * PI * x / lambda).cos();
    let n = [8, 16, 32, 64];
    for p in 1..=4 {
        for method in METHODS {
            let fits: Vec<_> = n
                .iter()
                .map(|&k| fit_height_function(&f, lambda, p, k, method))
                .collect();
            let max: Vec<f64> = fits.iter().map(|s| s.max_error).collect();
            let rms: Vec<f64> = fits.iter().map(|s| s.rms_error).collect();
            let (r_max, r_rms) = (rate(&n, &max), rate(&n, &rms));
            println!(
                "p {p} {method:?}: max errors {:?} rate {r_max:.2}; rms rate {r_rms:.2}",
                max.iter().map(|e| format!("{e:.2e}")).collect::<Vec<_>>()
            );
            let target = (p + 1) as f64;
            assert!(
                (r_max - target).abs() < 0.4,
                "p {p} {method:?}: max-error rate {r_max:.2}, expected {target}"
            );
            assert!(
                (r_rms - target).abs() < 0.4,
                "p {p} {method:?}: rms-error rate {r_rms:.2}, expected {target}"
            );
            assert!(max.windows(2).all(|w| w[1] < w[0]));
        }
    }
}

#[test]
fn periodic_sinusoid_gives_equal_end_heights() {
    let lambda = 10e-6;
    let f = |x: f64| 1e-6 * (2.0 * PI * x / lambda + 0.3).sin();
    for method in METHODS {
        for p in 1..=3 {
            let fit = fit_height_function(&f, 3.0 * lambda, p, 25, method);
            assert_eq!(fit.heights[0], fit.heights[fit.heights.len() - 1]);
            assert!((fit.heights[0] - f(0.0)).abs() < 1e-18);
        }
        // Not periodic over the width: ends differ.
        let fit = fit_height_function(&f, 0.7 * lambda, 2, 10, method);
        assert!((fit.heights[0] - fit.heights[fit.heights.len() - 1]).abs() > 1e-8);
    }
}

#[test]
fn rough_block_maps_onto_fitted_surface_and_flat_face() {
    let width = 10e-6;
    let f = |x: f64| 1e-6 * (2.0 * PI * x / width).cos() + 0.3e-6 * (4.0 * PI * x / width).sin();
    let fit = fit_height_function(&f, width, 3, 12, FitMethod::Interpolation);
    let p = fit.knots.degree();
    let k = fit.knots.knots();
    // ∫_0^W z dx of the fitted curve = W Σ h_i (u_{i+p+1} − u_i)/(p + 1).
    let integral: f64 = width
        * (0..fit.heights.len())
            .map(|i| fit.heights[i] * (k[i + p + 1] - k[i]) / (p + 1) as f64)
            .sum::<f64>();
    for (face, z_shift, z_flat) in [
        (RoughFace::Top, 0.2e-6, -20e-6),
        (RoughFace::Bottom, 2.5e-6, 22.5e-6),
    ] {
        let block = rough_block(&fit, z_shift, z_flat, face, 2, 3);
        assert_eq!(block.param_dim(), 2);
        assert_eq!(block.knots()[0], fit.knots);
        assert_eq!(block.knots()[1].n_elements(), 3);
        let (v_rough, v_flat) = match face {
            RoughFace::Top => (1.0, 0.0),
            RoughFace::Bottom => (0.0, 1.0),
        };
        for s in 0..=40 {
            let u = s as f64 / 40.0;
            let rough = block.point(&[u, v_rough]);
            let flat = block.point(&[u, v_flat]);
            let z = fit.height_at(width * u) + z_shift;
            assert!(
                (rough[0] - width * u).abs() < 1e-18 && (rough[1] - z).abs() < 1e-18,
                "{rough:?} vs {z}"
            );
            assert!((flat[1] - z_flat).abs() < 1e-18 && rough[2] == 0.0);
            for t in [0.1, 0.5, 0.77] {
                let x = block.point(&[u, t]);
                let (bottom, top) = if face == RoughFace::Top {
                    (z_flat, z)
                } else {
                    (z, z_flat)
                };
                assert!((x[1] - (bottom + t * (top - bottom))).abs() < 1e-18);
                let (_, jac) = block.jacobian(&[u, t]);
                assert!(jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0] > 0.0);
            }
        }
        // Area by element quadrature; the integrand is polynomial.
        let area: f64 = block
            .elements()
            .iter()
            .flat_map(|el| block.element_quadrature(el, &[5, 4]).points)
            .map(|q| q.weight)
            .sum();
        let expected = match face {
            RoughFace::Top => integral + width * (z_shift - z_flat),
            RoughFace::Bottom => width * (z_flat - z_shift) - integral,
        };
        assert!(
            (area - expected).abs() < 1e-12 * expected,
            "area {area} vs {expected}"
        );
        // The rough face's outward normal points out of the block: up for Top, down for Bottom.
        let sign = if face == RoughFace::Top { 1.0 } else { -1.0 };
        assert_eq!(
            face.side(),
            if face == RoughFace::Top {
                Side::High
            } else {
                Side::Low
            }
        );
        for fe in block.face_quadrature(1, face.side(), 4) {
            for q in &fe.points {
                assert!(sign * q.normal[1] > 0.5);
                assert!((q.x[1] - (fit.height_at(q.x[0]) + z_shift)).abs() < 1e-18);
            }
        }
    }
}

#[test]
fn folded_rough_block_is_rejected() {
    let f = |x: f64| (2.0 * PI * x).cos();
    let fit = fit_height_function(&f, 1.0, 2, 8, FitMethod::LeastSquares);
    let err = try_rough_block(&fit, 0.0, 0.5, RoughFace::Top, 1, 2).unwrap_err();
    assert!(err.to_string().contains("not strictly above"), "{err}");
    assert!(try_rough_block(&fit, 0.0, 0.5, RoughFace::Bottom, 1, 2).is_err());
    assert!(try_rough_block(&fit, 0.0, -1.5, RoughFace::Top, 1, 2).is_ok());
    assert!(try_rough_block(&fit, 0.0, 1.5, RoughFace::Bottom, 0, 2).is_err());
}
