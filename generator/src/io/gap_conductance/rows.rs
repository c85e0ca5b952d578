//! The rows of the block: the law sampled in pressure (and temperature) until
//! the solver's piecewise-linear interpolation follows it within the tolerance.

use super::*;
use crate::{Error, Result};
use lookup::{EvalError, Extrapolation, Law};

/// Where the exported flux lies in the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FluxSource {
    /// A flux node of the table.
    Node,
    /// Between two nodes: interpolated by the law (linear in `|h̄|`).
    Interpolated,
    /// Outside the table, under the law's flux extrapolation policy.
    Extrapolated(Extrapolation),
}

/// The rows of a `*GAP CONDUCTANCE` block, in SI.
#[derive(Clone, Debug, PartialEq)]
pub struct GapConductanceRows {
    /// The flux `|h̄|` [W/m²] of every row.
    pub flux: f64,
    /// How the flux relates to the table.
    pub flux_source: FluxSource,
    /// Contact pressures (Pa), ascending, the same at every temperature.
    pub pressures: Vec<f64>,
    /// Contact temperatures (K), ascending (the table's and inserted ones).
    pub temperatures: Vec<f64>,
    /// Conductance [W/(m²·K)], `[temperature][pressure]` row-major.
    pub conductance: Vec<f64>,
    /// The tolerance asked for.
    pub tolerance: f64,
    /// Largest relative deviation of the solver's (bi)linear interpolation of
    /// the rows from the law, sampled on every cell.
    pub max_deviation: f64,
}

impl GapConductanceRows {
    /// Conductance at temperature row `it` and pressure row `ip`.
    pub fn at(&self, it: usize, ip: usize) -> f64 {
        self.conductance[it * self.pressures.len() + ip]
    }

    /// The solver's interpolation of the rows: linear in temperature between
    /// the sets, then linear in pressure, end values held outside.
    pub fn interpolate(&self, p: f64, theta: f64) -> f64 {
        let (ip, tp) = bracket(&self.pressures, p);
        let (it, tt) = bracket(&self.temperatures, theta);
        let along_t = |i: usize| {
            let a = self.at(it, i);
            if tt == 0.0 {
                a
            } else {
                a + tt * (self.at(it + 1, i) - a)
            }
        };
        let a = along_t(ip);
        if tp == 0.0 {
            a
        } else {
            a + tp * (along_t(ip + 1) - a)
        }
    }
}

/// Interval index and fraction of `x` on `nodes`, clamped at the ends
/// (fraction 0 means "at node i", and i + 1 may not exist).
fn bracket(nodes: &[f64], x: f64) -> (usize, f64) {
    let n = nodes.len();
    if n == 1 || x <= nodes[0] {
        return (0, 0.0);
    }
    if x >= nodes[n - 1] {
        return (n - 1, 0.0);
    }
    let i = nodes.partition_point(|&v| v <= x) - 1;
    (i, (x - nodes[i]) / (nodes[i + 1] - nodes[i]))
}

fn law_error(e: EvalError, p: f64, h: f64, theta: f64) -> Error {
    Error::Config(format!(
        "the law at p = {p:e} Pa, |h| = {h:e} W/m^2, θc = {theta} K: {e}"
    ))
}

/// The law's conductance `|h̄| / jump` [W/(m²·K)].
fn conductance(law: &Law, p: f64, h: f64, theta: f64) -> Result<f64> {
    law.eval(p, h, theta)
        .map(|v| v.conductance)
        .map_err(|e| law_error(e, p, h, theta))
}

/// Largest relative deviation of the chord of `k` on `[a, b]` from `k`.
fn chord_deviation(a: f64, b: f64, k: &impl Fn(f64) -> Result<f64>) -> Result<f64> {
    let (ka, kb) = (k(a)?, k(b)?);
    let mut worst: f64 = 0.0;
    for s in 1..SAMPLES {
        let t = s as f64 / SAMPLES as f64;
        let exact = k(a + t * (b - a))?;
        worst = worst.max(((ka + t * (kb - ka) - exact) / exact).abs());
    }
    Ok(worst)
}

/// Inserts points (at `split(a, b)`) into the ascending `nodes` until
/// `deviation(a, b) ≤ tol` on every interval.
fn refine(
    nodes: &[f64],
    tol: f64,
    split: fn(f64, f64) -> f64,
    deviation: &impl Fn(f64, f64) -> Result<f64>,
) -> Result<Vec<f64>> {
    /// More rows than any solver takes: the law cannot be followed.
    const MAX_ROWS: usize = 4096;
    let mut out = vec![nodes[0]];
    for w in nodes.windows(2) {
        let mut stack = vec![(w[0], w[1])];
        while let Some((a, b)) = stack.pop() {
            if deviation(a, b)? <= tol {
                out.push(b);
            } else {
                let m = split(a, b);
                stack.push((m, b));
                stack.push((a, m));
            }
            if out.len() + stack.len() > MAX_ROWS {
                return Err(Error::Config(format!(
                    "more than {MAX_ROWS} rows would be needed for a relative tolerance {tol:e}"
                )));
            }
        }
    }
    Ok(out)
}

/// Sampled largest relative deviation of the bilinear interpolation of the
/// rows from the law, over every cell of the (pressure × temperature) grid.
fn max_deviation(law: &Law, rows: &GapConductanceRows) -> Result<f64> {
    let (ps, ts) = (&rows.pressures, &rows.temperatures);
    // Temperatures at which to compare: the one set, or samples of each interval.
    let mut thetas = vec![ts[0]];
    for tw in ts.windows(2) {
        let k = SAMPLES / 4;
        thetas.extend((1..=k).map(|r| tw[0] + (tw[1] - tw[0]) * r as f64 / k as f64));
    }
    let mut worst: f64 = 0.0;
    for pw in ps.windows(2) {
        for s in 0..=SAMPLES {
            let p = pw[0] + (pw[1] - pw[0]) * s as f64 / SAMPLES as f64;
            for &theta in &thetas {
                let exact = conductance(law, p, rows.flux, theta)?;
                worst = worst.max((rows.interpolate(p, theta) / exact - 1.0).abs());
            }
        }
    }
    Ok(worst)
}

/// The rows of the block for `law` (SI): the flux, the pressures and
/// temperatures, the conductances, refined to the tolerance.
pub fn gap_conductance_rows(law: &Law, o: &GapConductanceOptions) -> Result<GapConductanceRows> {
    o.validate()?;
    let axes = law.axes();
    let policy = law.info().extrapolation;
    let (fluxes, temps, table_p) = (&axes.flux, &axes.contact_temperature, &axes.pressure);
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let flux = match (o.flux, fluxes.len()) {
        (Some(h), _) => h,
        (None, 1) => fluxes[0],
        (None, n) => {
            return Err(Error::invalid(
                "--flux",
                "(missing)",
                format!(
                    "the table has {n} fluxes ({} W/m^2): choose one with --flux VALUE \
                     (a node, or a value inside the range, interpolated by the law)",
                    list(fluxes)
                ),
            ));
        }
    };
    let (h_lo, h_hi) = (fluxes[0], fluxes[fluxes.len() - 1]);
    let flux_source = if fluxes.contains(&flux) {
        FluxSource::Node
    } else if flux > h_lo && flux < h_hi {
        FluxSource::Interpolated
    } else if policy.flux == Extrapolation::Error {
        return Err(Error::invalid(
            "--flux",
            flux,
            format!(
                "outside the table's fluxes [{h_lo:e}, {h_hi:e}] W/m^2 (nodes {}) and the law's flux policy is error: \
                 choose a flux inside, or add --extrapolate flux=clamp|linear",
                list(fluxes)
            ),
        ));
    } else {
        FluxSource::Extrapolated(policy.flux)
    };
    let (p_lo, p_hi) = (table_p[0], table_p[table_p.len() - 1]);
    let [lo, hi] = o.pressure_range.unwrap_or([p_lo, p_hi]);
    if (lo < p_lo || hi > p_hi) && policy.pressure == Extrapolation::Error {
        return Err(Error::invalid(
            "--pressure-range",
            format!("{lo:e}:{hi:e}"),
            format!(
                "beyond the table's pressures [{p_lo:e}, {p_hi:e}] Pa while the law's pressure policy is error: \
                 narrow the range, or add --extrapolate pressure=clamp|power|linear"
            ),
        ));
    }
    let mut p0 = vec![lo];
    p0.extend(table_p.iter().copied().filter(|&p| p > lo && p < hi));
    p0.push(hi);
    if lo == hi {
        p0.pop();
    }

    let geometric = |a: f64, b: f64| (a * b).sqrt();
    let arithmetic = |a: f64, b: f64| 0.5 * (a + b);
    let mut tol = o.tolerance;
    for _ in 0..8 {
        // Temperatures: the chord along θ at dense probe pressures.
        let probes = densify(&p0, 4);
        let temperatures = if temps.len() > 1 {
            refine(temps, tol, arithmetic, &|a, b| {
                let mut worst: f64 = 0.0;
                for &p in &probes {
                    worst = worst.max(chord_deviation(a, b, &|t| conductance(law, p, flux, t))?);
                }
                Ok(worst)
            })?
        } else {
            temps.clone()
        };
        // Pressures: the chord along p at every temperature row.
        let pressures = refine(&p0, tol, geometric, &|a, b| {
            let mut worst: f64 = 0.0;
            for &t in &temperatures {
                worst = worst.max(chord_deviation(a, b, &|p| conductance(law, p, flux, t))?);
            }
            Ok(worst)
        })?;
        let mut conductance_rows = Vec::with_capacity(pressures.len() * temperatures.len());
        for &t in &temperatures {
            for &p in &pressures {
                conductance_rows.push(conductance(law, p, flux, t)?);
            }
        }
        let mut rows = GapConductanceRows {
            flux,
            flux_source,
            pressures,
            temperatures,
            conductance: conductance_rows,
            tolerance: o.tolerance,
            max_deviation: 0.0,
        };
        rows.max_deviation = max_deviation(law, &rows)?;
        if rows.max_deviation <= o.tolerance {
            return Ok(rows);
        }
        // The bilinear cell error exceeds the two chord errors: tighten both.
        tol *= 0.5 * o.tolerance / rows.max_deviation;
    }
    Err(Error::Config(format!(
        "could not reach the relative tolerance {:e} (--tolerance)",
        o.tolerance
    )))
}

/// `nodes` with `k − 1` geometric points inserted in every interval.
fn densify(nodes: &[f64], k: usize) -> Vec<f64> {
    let mut out = vec![nodes[0]];
    for w in nodes.windows(2) {
        for j in 1..=k {
            out.push(w[0] * (w[1] / w[0]).powf(j as f64 / k as f64));
        }
    }
    out
}

/// The rows for `law`, checked against the solver's row limit: past it, the
/// error names the tolerance that fits.
pub fn gap_conductance_rows_for_deck(
    law: &Law,
    o: &GapConductanceOptions,
) -> Result<GapConductanceRows> {
    let rows = gap_conductance_rows(law, o)?;
    let Some(max) = o.deck.max_pressure_rows() else {
        return Ok(rows);
    };
    if rows.pressures.len() <= max {
        return Ok(rows);
    }
    // The smallest tolerance on a 1.25× ladder from 0.5 down whose rows fit
    // (coarse tolerances are cheap to try).
    let fits = |tol: f64| {
        gap_conductance_rows(
            law,
            &GapConductanceOptions {
                tolerance: tol,
                ..*o
            },
        )
        .is_ok_and(|r| r.pressures.len() <= max)
    };
    let mut fit = 0.5;
    while fit / 1.25 > o.tolerance && fits(fit / 1.25) {
        fit /= 1.25;
    }
    Err(Error::invalid(
        "--tolerance",
        o.tolerance,
        format!(
            "needs {} pressure rows per temperature; {} reads at most {max} \
             (face-to-face contact, springforc_f2f_th.f; more corrupt its lookup silently): \
             use --tolerance {fit:.2e} or larger, or a narrower --pressure-range",
            rows.pressures.len(),
            o.deck.solver()
        ),
    ))
}
