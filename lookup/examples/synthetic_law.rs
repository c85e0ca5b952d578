//! Writes a synthetic law file (a smooth, physically shaped jump on a
//! `n_p × n_h × n_θ` grid) and prints one evaluation: a stand-in for
//! `tcgen law TABLE.h5 -o LAW` when trying the library, the C ABI or the
//! Fortran examples.
//!
//! ```text
//! cargo run -p lookup --example synthetic_law -- OUT.tclaw [n_p n_h n_theta]
//! ```

use lookup::{Axes, Extrapolation, ExtrapolationPolicy, Law, LawInfo, Statistic};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(out) = args.first() else {
        return Err("usage: synthetic_law OUT.tclaw [n_p n_h n_theta]".into());
    };
    let dim = |i: usize, default: usize| -> Result<usize, Box<dyn std::error::Error>> {
        Ok(args
            .get(i)
            .map(|s| s.parse())
            .transpose()?
            .unwrap_or(default))
    };
    let (np, nh, nt) = (dim(1, 40)?, dim(2, 8)?, dim(3, 4)?);
    let span = |a: f64, b: f64, n: usize, log: bool| -> Vec<f64> {
        (0..n)
            .map(|i| {
                let t = i as f64 / (n.max(2) - 1) as f64;
                if log {
                    a * (b / a).powf(t)
                } else {
                    a + (b - a) * t
                }
            })
            .collect()
    };
    let axes = Axes {
        pressure: span(1e3, 1e8, np, true),
        flux: span(1e4, 2e6, nh, false),
        contact_temperature: span(280.0, 420.0, nt, false),
    };
    // Conductance rising like p^0.9, weakly temperature and flux dependent.
    let (mut mean, mut std) = (Vec::new(), Vec::new());
    for &p in &axes.pressure {
        for &h in &axes.flux {
            for &t in &axes.contact_temperature {
                let k = 2e3 * (p / 1e5).powf(0.9) * (1.0 + 2e-3 * (t - 300.0));
                let jump = h / k * (1.0 + 5e-8 * h);
                mean.push(jump);
                std.push(0.05 * jump);
            }
        }
    }
    let info = LawInfo {
        statistic: Statistic::EnsembleMean { samples: 16 },
        extrapolation: ExtrapolationPolicy {
            pressure: Extrapolation::Power,
            flux: Extrapolation::Clamp,
            contact_temperature: Extrapolation::Linear,
        },
        material: None,
        provenance: vec![
            ("generator".into(), "lookup synthetic_law example".into()),
            (
                "surface".into(),
                "synthetic: k = 2e3 (p/1e5 Pa)^0.9 (1 + 2e-3 (θ - 300 K))".into(),
            ),
        ],
    };
    let law = Law::from_grid(axes, mean, std, info)?;
    law.write(out)?;
    let v = law.eval(1e5, 1e5, 300.0)?;
    println!(
        "wrote {out} ({np} x {nh} x {nt}); at p = 1e5 Pa, |h| = 1e5 W/m^2, θc = 300 K: \
         jump = {:.6} K, conductance = {:.3} W/(m^2 K)",
        v.jump, v.conductance
    );
    Ok(())
}
