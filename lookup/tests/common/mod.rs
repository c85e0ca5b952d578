//! Synthetic laws shared by the integration tests.
#![allow(dead_code)]

use lookup::{Axes, Extrapolation, ExtrapolationPolicy, Law, LawInfo, Statistic};

/// Geometric sequence of `n` values from `a` to `b`.
pub fn geomspace(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| a * (b / a).powf(i as f64 / (n - 1).max(1) as f64))
        .collect()
}

/// Uneven increasing sequence of `n` values from `a` to `b`.
pub fn uneven(a: f64, b: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / (n - 1).max(1) as f64;
            a + (b - a) * (t + 0.15 * (std::f64::consts::PI * t).sin() * (1.0 - t))
        })
        .collect()
}

/// Axes of the size of a typical generated table (40 × 8 × 4).
pub fn table_axes(np: usize, nh: usize, nt: usize) -> Axes {
    Axes {
        pressure: geomspace(1e3, 1e8, np),
        flux: uneven(1e4, 2e6, nh),
        contact_temperature: uneven(280.0, 420.0, nt),
    }
}

/// Tabulates `f(p, h, θ) -> (mean, std)` on `axes`.
pub fn tabulate(axes: &Axes, f: impl Fn(f64, f64, f64) -> (f64, f64)) -> (Vec<f64>, Vec<f64>) {
    let mut mean = Vec::with_capacity(axes.len());
    let mut std = Vec::with_capacity(axes.len());
    for &p in &axes.pressure {
        for &h in &axes.flux {
            for &t in &axes.contact_temperature {
                let (m, s) = f(p, h, t);
                mean.push(m);
                std.push(s);
            }
        }
    }
    (mean, std)
}

/// A smooth, physically shaped jump: conductance rising like p^0.9 with a
/// temperature and a weak flux dependence; jump decreasing in pressure.
pub fn physical_jump(p: f64, h: f64, t: f64) -> (f64, f64) {
    let k = 2e3 * (p / 1e5).powf(0.9) * (1.0 + 2e-3 * (t - 300.0));
    let jump = h / k * (1.0 + 5e-8 * h);
    (jump, 0.05 * jump)
}

/// Data exactly linear in (ln p, h, θ), positive on the tables used.
pub fn linear_jump(p: f64, h: f64, t: f64) -> (f64, f64) {
    (
        200.0 - 3.0 * p.ln() + 2e-5 * h + 0.1 * t,
        1.0 + 0.01 * p.ln() + 1e-7 * h,
    )
}

/// A law over `axes` with data `f` and one policy on every axis.
pub fn law_from(axes: Axes, f: impl Fn(f64, f64, f64) -> (f64, f64), policy: Extrapolation) -> Law {
    let (mean, std) = tabulate(&axes, f);
    let info = LawInfo {
        statistic: Statistic::EnsembleMean { samples: 12 },
        extrapolation: ExtrapolationPolicy::uniform(policy),
        material: None,
        provenance: vec![("generator".into(), "lookup tests".into())],
    };
    Law::from_grid(axes, mean, std, info).expect("valid synthetic law")
}

/// The physical law on a 40 × 8 × 4 table.
pub fn physical_law(policy: Extrapolation) -> Law {
    law_from(table_axes(40, 8, 4), physical_jump, policy)
}

/// Deterministic pseudo-random numbers in [0, 1) (no dependency).
pub struct Lcg(pub u64);

impl Lcg {
    /// Next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

/// A random query strictly inside the table of `law`, away from the nodes of
/// every axis by at least `margin` (fraction of the interval).
pub fn interior_query(law: &Law, rng: &mut Lcg, margin: f64) -> (f64, f64, f64) {
    let pick = |nodes: &[f64], rng: &mut Lcg, log: bool| {
        if nodes.len() == 1 {
            return nodes[0];
        }
        let i = ((rng.next() * (nodes.len() - 1) as f64) as usize).min(nodes.len() - 2);
        let t = rng.range(margin, 1.0 - margin);
        if log {
            (nodes[i].ln() + t * (nodes[i + 1].ln() - nodes[i].ln())).exp()
        } else {
            nodes[i] + t * (nodes[i + 1] - nodes[i])
        }
    };
    let a = law.axes();
    (
        pick(&a.pressure, rng, true),
        pick(&a.flux, rng, false),
        pick(&a.contact_temperature, rng, false),
    )
}

/// The directory holding `file` (`liblookup.a`, `liblookup.so`) of this build:
/// the `deps` directory of the test executable, where cargo writes the lib
/// target on every build (`cargo test` does not refresh the copies in the
/// profile directory `target/<profile>`, which is only the fallback).
pub fn library_dir(file: &str) -> std::path::PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("deps directory");
    for dir in [deps, deps.parent().unwrap_or(deps)] {
        if dir.join(file).is_file() {
            return dir.to_path_buf();
        }
    }
    panic!(
        "{file} not found next to {} (cargo builds it with the lib target)",
        exe.display()
    );
}
