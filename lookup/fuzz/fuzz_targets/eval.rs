//! Arbitrary queries (any f64 bit pattern, any policy, any cap) on a fixed law:
//! an error or finite results, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use lookup::{Axes, EvalOptions, Extrapolation, ExtrapolationPolicy, Law, LawInfo};
use std::sync::OnceLock;

fn law() -> &'static Law {
    static LAW: OnceLock<Law> = OnceLock::new();
    LAW.get_or_init(|| {
        let axes = Axes {
            pressure: vec![1e3, 1e4, 1e5, 1e6, 1e7],
            flux: vec![1e4, 1e5, 1e6],
            contact_temperature: vec![280.0, 350.0],
        };
        let mut mean = Vec::new();
        for &p in &axes.pressure {
            for &h in &axes.flux {
                for &t in &axes.contact_temperature {
                    // Vanishes at the highest pressure (full contact).
                    mean.push(if p >= 1e7 {
                        0.0
                    } else {
                        h / (1e3 * (p / 1e3f64).powf(0.8)) * t / 300.0
                    });
                }
            }
        }
        let n = mean.len();
        Law::from_grid(axes, mean, vec![0.0; n], LawInfo::default()).unwrap()
    })
}

fn policy(b: u8) -> Extrapolation {
    match b % 3 {
        0 => Extrapolation::Error,
        1 => Extrapolation::Clamp,
        _ => Extrapolation::Linear,
    }
}

fuzz_target!(|data: [u8; 36]| {
    let f = |i: usize| f64::from_le_bytes(data[i..i + 8].try_into().unwrap());
    let (p, h, t, k) = (f(0), f(8), f(16), f(24));
    let options = EvalOptions {
        extrapolation: ExtrapolationPolicy {
            pressure: if data[32] % 4 == 3 {
                Extrapolation::Power
            } else {
                policy(data[32])
            },
            flux: policy(data[33]),
            contact_temperature: policy(data[34]),
        },
        max_conductance: (data[35] & 1 == 1 && k.is_finite() && k > 0.0).then_some(k),
    };
    if let Ok(v) = law().eval_with(p, h, t, &options) {
        for x in [
            v.jump,
            v.jump_std,
            v.d_jump_dp,
            v.d_jump_dh,
            v.d_jump_dtheta,
            v.conductance,
            v.d_conductance_dp,
            v.d_conductance_dh,
            v.d_conductance_dtheta,
        ] {
            assert!(x.is_finite(), "non-finite result at {p} {h} {t}: {v:?}");
        }
    }
    if let Ok(w) = law().eval_at_jump_with(p, h, t, &options) {
        for x in [
            w.flux,
            w.jump_std,
            w.conductance,
            w.d_flux_dp,
            w.d_flux_djump,
            w.d_flux_dtheta,
            w.d_conductance_dp,
            w.d_conductance_djump,
            w.d_conductance_dtheta,
        ] {
            assert!(x.is_finite(), "non-finite result at {p} {h} {t}: {w:?}");
        }
    }
});
