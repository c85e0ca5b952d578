//! Interpolation, derivatives, extrapolation and query checking of `Law::eval`.

mod common;

use common::*;
use lookup::{Axis, EvalError, EvalOptions, Extrapolation, ExtrapolationPolicy, Law};

fn close(a: f64, b: f64, rel: f64, abs: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()) + abs
}

/// Data linear in (ln p, h, θ) are reproduced exactly, with exact derivatives,
/// inside the table and (policy linear) outside it.
#[test]
fn linear_data_are_reproduced_exactly() {
    let law = law_from(table_axes(7, 4, 3), linear_jump, Extrapolation::Linear);
    let mut rng = Lcg(1);
    let mut worst = 0.0f64;
    for k in 0..2000 {
        // Half inside, half up to a decade / 30 % outside the table.
        let (p, h, t) = if k % 2 == 0 {
            interior_query(&law, &mut rng, 0.0)
        } else {
            (
                10f64.powf(rng.range(2.0, 9.0)),
                rng.range(0.0, 2.6e6),
                rng.range(200.0, 500.0),
            )
        };
        let v = law.eval(p, h, t).unwrap();
        let (j, s) = linear_jump(p, h, t);
        worst = worst.max((v.jump - j).abs() / j);
        assert!(
            close(v.jump, j, 1e-12, 0.0),
            "jump {} vs {j} at {p} {h} {t}",
            v.jump
        );
        assert!(close(v.jump_std, s, 1e-12, 0.0));
        assert!(
            close(v.d_jump_dp, -3.0 / p, 1e-10, 0.0),
            "{} vs {}",
            v.d_jump_dp,
            -3.0 / p
        );
        assert!(close(v.d_jump_dh, 2e-5, 1e-9, 0.0), "{}", v.d_jump_dh);
        assert!(
            close(v.d_jump_dtheta, 0.1, 1e-9, 0.0),
            "{}",
            v.d_jump_dtheta
        );
        assert!(close(v.conductance, h / j, 1e-12, 0.0));
        assert!(close(
            v.d_conductance_dh,
            (1.0 - h * 2e-5 / j) / j,
            1e-9,
            1e-15
        ));
    }
    println!("linear data: worst relative jump error {worst:.2e}");
}

/// Central finite differences of value and conductance match the analytic
/// derivatives to 1e-6 (relative), at random points away from the nodes.
#[test]
fn derivatives_match_central_finite_differences() {
    let law = physical_law(Extrapolation::Clamp);
    let mut rng = Lcg(7);
    let mut worst = 0.0f64;
    for _ in 0..500 {
        let (p, h, t) = interior_query(&law, &mut rng, 0.05);
        let v = law.eval(p, h, t).unwrap();
        let checks = [
            (v.d_jump_dp, v.d_conductance_dp, p, Axis::Pressure),
            (v.d_jump_dh, v.d_conductance_dh, h, Axis::Flux),
            (
                v.d_jump_dtheta,
                v.d_conductance_dtheta,
                t,
                Axis::ContactTemperature,
            ),
        ];
        for (dj, dk, x, axis) in checks {
            let step = 1e-6 * x;
            let at = |dx: f64| {
                let mut q = [p, h, t];
                q[axis as usize] += dx;
                law.eval(q[0], q[1], q[2]).unwrap()
            };
            let (a, b) = (at(step), at(-step));
            let fd_j = (a.jump - b.jump) / (2.0 * step);
            let fd_k = (a.conductance - b.conductance) / (2.0 * step);
            // Scale floor: a derivative that is tiny against value/coordinate.
            let floor_j = 1e-9 * v.jump / x;
            let floor_k = 1e-9 * v.conductance / x;
            worst = worst.max((fd_j - dj).abs() / (dj.abs() + floor_j));
            assert!(
                close(fd_j, dj, 1e-6, floor_j),
                "{axis}: d jump {dj} vs fd {fd_j}"
            );
            assert!(
                close(fd_k, dk, 1e-6, floor_k),
                "{axis}: d k {dk} vs fd {fd_k}"
            );
        }
    }
    println!("finite differences: worst relative derivative error {worst:.2e}");
}

/// Along pressure the interpolant is C1 at every node: value and slope agree
/// from both sides (checked across each interior node, at every flux and
/// temperature node and between them).
#[test]
fn interpolant_is_c1_along_pressure_at_nodes() {
    let law = physical_law(Extrapolation::Clamp);
    let a = law.axes().clone();
    let delta: f64 = 1e-7; // in ln p
    let mut worst_slope = 0.0f64;
    for &pi in &a.pressure[1..a.pressure.len() - 1] {
        for h in [a.flux[0], 0.5 * (a.flux[2] + a.flux[3]), a.flux[7]] {
            for t in [a.contact_temperature[1], 333.0] {
                let l = law.eval(pi * (-delta).exp(), h, t).unwrap();
                let r = law.eval(pi * delta.exp(), h, t).unwrap();
                // d jump / d ln p on both sides.
                let (sl, sr) = (
                    l.d_jump_dp * pi * (-delta).exp(),
                    r.d_jump_dp * pi * delta.exp(),
                );
                let scale = sl.abs().max(sr.abs());
                worst_slope = worst_slope.max((sl - sr).abs() / scale);
                assert!(
                    (sl - sr).abs() <= 1e-5 * scale,
                    "slope jump at p={pi}: {sl} vs {sr}"
                );
                assert!((l.jump - r.jump).abs() <= 3.0 * delta * scale + 1e-14 * l.jump);
            }
        }
    }
    println!("C1 along pressure: worst relative slope mismatch {worst_slope:.2e}");
}

/// Monotone data along pressure give a monotone interpolant that never leaves
/// the range of the data (no overshoot), also on uneven, steep data.
#[test]
fn monotone_data_give_monotone_interpolant() {
    let mut rng = Lcg(3);
    let axes = table_axes(12, 3, 2);
    // Random decreasing steps (some nearly flat, some steep) per line.
    let steps: Vec<f64> = (0..axes.len()).map(|_| rng.next().powi(4) * 5.0).collect();
    let (nh, nt) = (axes.flux.len(), axes.contact_temperature.len());
    let mut mean = vec![0.0; axes.len()];
    for ih in 0..nh {
        for it in 0..nt {
            let mut acc = 60.0;
            for ip in 0..axes.pressure.len() {
                let i = (ip * nh + ih) * nt + it;
                acc -= steps[i];
                mean[i] = acc.max(0.0) + 0.1;
            }
        }
    }
    let law = Law::from_grid(
        axes.clone(),
        mean.clone(),
        vec![0.0; mean.len()],
        Default::default(),
    )
    .unwrap();
    let (lo, hi) = mean
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    for h in [axes.flux[0], 1.3e5, axes.flux[2]] {
        for t in [axes.contact_temperature[0], 350.0] {
            let mut prev = f64::INFINITY;
            for k in 0..=5000 {
                let p = 1e3 * 1e5f64.powf(k as f64 / 5000.0);
                let v = law.eval(p, h, t).unwrap();
                assert!(v.jump <= prev + 1e-12, "increase at p={p}");
                assert!(v.d_jump_dp <= 1e-15, "positive slope at p={p}");
                assert!(v.jump >= lo - 1e-12 && v.jump <= hi + 1e-12);
                prev = v.jump;
            }
        }
    }
}

/// Each policy on each axis: error names the axis and range, clamp freezes the
/// law at the bound, linear continues linearly in the interpolation variable.
#[test]
fn extrapolation_policies_behave_as_documented() {
    let mut law = physical_law(Extrapolation::Error);
    let a = law.axes().clone();
    let mid = [3e5, 5e5, 330.0];
    let below = [
        a.pressure[0] / 3.0,
        a.flux[0] / 2.0,
        a.contact_temperature[0] - 10.0,
    ];
    let above = [
        a.pressure[39] * 3.0,
        a.flux[7] * 1.5,
        a.contact_temperature[3] + 10.0,
    ];
    for axis in Axis::ALL {
        let i = axis as usize;
        for q in [below[i], above[i]] {
            let mut x = mid;
            x[i] = q;
            match law.eval(x[0], x[1], x[2]) {
                Err(EvalError::OutOfRange {
                    axis: e,
                    value,
                    min,
                    max,
                }) => {
                    assert_eq!((e, value), (axis, q));
                    assert_eq!((min, max), (a.get(axis)[0], *a.get(axis).last().unwrap()));
                }
                other => panic!("{axis}: expected OutOfRange, got {other:?}"),
            }
        }
    }
    // Caller override: clamp.
    law.set_extrapolation(ExtrapolationPolicy::uniform(Extrapolation::Clamp))
        .unwrap();
    for axis in Axis::ALL {
        let i = axis as usize;
        for (q, bound) in [
            (below[i], a.get(axis)[0]),
            (above[i], *a.get(axis).last().unwrap()),
        ] {
            let mut x = mid;
            x[i] = q;
            let v = law.eval(x[0], x[1], x[2]).unwrap();
            x[i] = bound;
            let b = law.eval(x[0], x[1], x[2]).unwrap();
            assert_eq!(v.jump, b.jump, "{axis}");
            assert_eq!(
                v.conductance, b.conductance,
                "{axis}: conductance at the bound"
            );
            assert!(v.extrapolated[i] && !b.extrapolated[i]);
            let d = [v.d_jump_dp, v.d_jump_dh, v.d_jump_dtheta][i];
            assert_eq!(d, 0.0, "{axis}: derivative beyond a clamped bound");
        }
    }
    // Zero flux under clamp: the conductance of the smallest tabulated flux.
    let v = law.eval(mid[0], 0.0, mid[2]).unwrap();
    let b = law.eval(mid[0], a.flux[0], mid[2]).unwrap();
    assert_eq!(v.conductance, b.conductance);
    // Zero pressure under clamp is accepted (clamped to the smallest pressure).
    assert!(law.eval(0.0, mid[1], mid[2]).is_ok());
    // Linear: collinear in (ln p, h, θ) outside, slope continuous at the bound.
    law.set_extrapolation(ExtrapolationPolicy::uniform(Extrapolation::Linear))
        .unwrap();
    for axis in Axis::ALL {
        let i = axis as usize;
        let coord = |q: f64| if axis == Axis::Pressure { q.ln() } else { q };
        let bound = a.get(axis)[0];
        let pts = [bound, 0.8 * bound, 0.5 * bound];
        let vals: Vec<_> = pts
            .iter()
            .map(|&q| {
                let mut x = mid;
                x[i] = q;
                law.eval(x[0], x[1], x[2]).unwrap()
            })
            .collect();
        let s1 = (vals[1].jump - vals[0].jump) / (coord(pts[1]) - coord(pts[0]));
        let s2 = (vals[2].jump - vals[1].jump) / (coord(pts[2]) - coord(pts[1]));
        assert!(
            close(s1, s2, 1e-9, 1e-15),
            "{axis}: not linear ({s1} vs {s2})"
        );
        let d_at_bound = [
            vals[0].d_jump_dp * bound,
            vals[0].d_jump_dh,
            vals[0].d_jump_dtheta,
        ][i];
        assert!(
            close(s1, d_at_bound, 1e-6, 1e-15),
            "{axis}: slope {s1} vs {d_at_bound}"
        );
        assert!(vals[2].extrapolated[i]);
    }
    // A subnormal pressure overflows d/dp: an error, not an infinite derivative.
    assert!(matches!(
        law.eval(1e-320, mid[1], mid[2]),
        Err(EvalError::NonFiniteResult)
    ));
    // Zero pressure cannot be extrapolated linearly in ln p.
    assert!(matches!(
        law.eval(0.0, mid[1], mid[2]),
        Err(EvalError::Invalid {
            axis: Axis::Pressure,
            ..
        })
    ));
}

/// NaN and infinite queries, negative pressure or flux and non-positive
/// temperatures are errors naming the axis, under every policy.
#[test]
fn non_finite_and_unphysical_queries_are_errors() {
    for policy in [
        Extrapolation::Error,
        Extrapolation::Clamp,
        Extrapolation::Linear,
    ] {
        let law = physical_law(policy);
        let mid = [3e5, 5e5, 330.0];
        for axis in Axis::ALL {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut x = mid;
                x[axis as usize] = bad;
                assert!(
                    matches!(law.eval(x[0], x[1], x[2]), Err(EvalError::NonFinite { axis: a, .. }) if a == axis),
                    "{axis} {bad} {policy}"
                );
                let r = law.eval_at_jump(x[0], 1.0, x[2]);
                if axis != Axis::Flux {
                    assert!(matches!(r, Err(EvalError::NonFinite { .. })));
                }
            }
            let mut x = mid;
            x[axis as usize] = -1.0;
            let e = law.eval(x[0], x[1], x[2]).unwrap_err();
            assert!(
                matches!(e, EvalError::Invalid { axis: a, .. } if a == axis),
                "{e}"
            );
            assert!(e.to_string().contains(axis.name()));
        }
        for bad in [f64::NAN, f64::INFINITY, -1.0] {
            assert!(matches!(
                law.eval_at_jump(3e5, bad, 330.0),
                Err(EvalError::InvalidJump { .. })
            ));
        }
    }
}

/// A vanishing jump (full contact) is an error unless a conductance cap is set;
/// then the conductance is the cap with zero derivatives, never NaN or inf.
#[test]
fn vanishing_jump_is_an_error_or_the_cap() {
    let axes = table_axes(5, 2, 1);
    let f = |p: f64, h: f64, _t: f64| {
        (
            if p >= 1e7 {
                0.0
            } else {
                h * 1e-5 * (1e7 / p).ln()
            },
            0.0,
        )
    };
    let mut law = law_from(axes, f, Extrapolation::Clamp);
    let e = law.eval(1e8, 1e5, 300.0).unwrap_err();
    assert!(
        matches!(e, EvalError::VanishingJump { jump } if jump == 0.0),
        "{e}"
    );
    assert!(law.set_max_conductance(Some(f64::NAN)).is_err());
    assert!(law.set_max_conductance(Some(-1.0)).is_err());
    law.set_max_conductance(Some(1e9)).unwrap();
    let v = law.eval(1e8, 1e5, 300.0).unwrap();
    assert!(v.conductance_capped && v.conductance == 1e9 && v.d_conductance_dp == 0.0);
    // Below the cap the law is untouched.
    let v = law.eval(1e4, 1e5, 300.0).unwrap();
    assert!(!v.conductance_capped && v.conductance < 1e9);
    let w = law.eval_at_jump(1e8, 0.5, 300.0).unwrap();
    assert!(w.conductance_capped && w.conductance == 1e9 && w.flux == 0.5e9);
    let opts = EvalOptions {
        max_conductance: None,
        ..law.options()
    };
    assert!(law.eval_at_jump_with(1e8, 0.5, 300.0, &opts).is_err());
}

/// `eval_at_jump` inverts `eval` along flux, and its derivatives at fixed jump
/// match central finite differences.
#[test]
fn eval_at_jump_inverts_eval_with_consistent_derivatives() {
    let law = physical_law(Extrapolation::Clamp);
    let mut rng = Lcg(11);
    for _ in 0..300 {
        let (p, h, t) = interior_query(&law, &mut rng, 0.05);
        let v = law.eval(p, h, t).unwrap();
        let w = law.eval_at_jump(p, v.jump, t).unwrap();
        assert!(close(w.flux, h, 1e-9, 0.0), "flux {} vs {h}", w.flux);
        assert!(close(w.conductance, v.conductance, 1e-9, 0.0));
        assert!(close(w.d_flux_djump, 1.0 / v.d_jump_dh, 1e-9, 0.0));
        let q = [p, v.jump, t];
        let derivs = [
            (w.d_flux_dp, w.d_conductance_dp),
            (w.d_flux_djump, w.d_conductance_djump),
            (w.d_flux_dtheta, w.d_conductance_dtheta),
        ];
        for (i, (dh, dk)) in derivs.into_iter().enumerate() {
            let step = 1e-6 * q[i];
            let at = |dx: f64| {
                let mut x = q;
                x[i] += dx;
                law.eval_at_jump(x[0], x[1], x[2]).unwrap()
            };
            let (a, b) = (at(step), at(-step));
            let fd_h = (a.flux - b.flux) / (2.0 * step);
            let fd_k = (a.conductance - b.conductance) / (2.0 * step);
            assert!(
                close(fd_h, dh, 1e-6, 1e-9 * w.flux / q[i]),
                "{i}: dh {dh} vs {fd_h}"
            );
            assert!(
                close(fd_k, dk, 1e-6, 1e-9 * w.conductance / q[i]),
                "{i}: dk {dk} vs {fd_k}"
            );
        }
    }
    // Jump 0 under clamp: zero flux, the conductance of the smallest flux.
    let w = law.eval_at_jump(3e5, 0.0, 330.0).unwrap();
    let b = law.eval(3e5, law.axes().flux[0], 330.0).unwrap();
    assert_eq!(w.flux, 0.0);
    assert!(close(w.conductance, b.conductance, 1e-12, 0.0) && w.extrapolated[1]);
    // A jump so large that the flux overflows is an error, not an infinite flux
    // (found by the `eval` fuzz target).
    assert!(matches!(
        law.eval_at_jump(3e5, 1e307, 330.0),
        Err(EvalError::NonFiniteResult)
    ));
    // Error policy: a jump beyond the flux range is out of range.
    let law = physical_law(Extrapolation::Error);
    assert!(matches!(
        law.eval_at_jump(3e5, 1e9, 330.0),
        Err(EvalError::JumpOutOfRange { .. })
    ));
}

/// One law evaluated from several threads gives the same values (Send + Sync).
#[test]
fn law_is_shared_between_threads() {
    let law = physical_law(Extrapolation::Clamp);
    let reference: Vec<f64> = (0..100)
        .map(|i| law.eval(1e4 * (1 + i) as f64, 5e5, 300.0).unwrap().jump)
        .collect();
    std::thread::scope(|s| {
        for _ in 0..2 {
            s.spawn(|| {
                for (i, r) in reference.iter().enumerate() {
                    assert_eq!(law.eval(1e4 * (1 + i) as f64, 5e5, 300.0).unwrap().jump, *r);
                }
            });
        }
    });
}
