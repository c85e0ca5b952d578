//! Ensemble statistics over the surface samples (paper Sect. 5.8): for every
//! `(pressure, flux, contact temperature)`, over the converged samples only.

use crate::io::table::{PointStatus, Table};

/// The quantile levels tabulated (coordinate `quantile`).
pub const QUANTILES: [f64; 5] = [0.05, 0.25, 0.5, 0.75, 0.95];

/// Statistics of one set of sample values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Summary {
    /// Number of values `n` ≥ 1.
    pub count: usize,
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (`n − 1` normalisation; NaN for `n = 1`:
    /// one sample has no spread to estimate).
    pub std: f64,
    /// Standard error of the mean, `std/√n` (NaN for `n = 1`).
    pub sem: f64,
    /// Quantiles at [`QUANTILES`], linear interpolation between order
    /// statistics at `(n − 1)·q` (Hyndman–Fan type 7, numpy's default).
    pub quantiles: [f64; QUANTILES.len()],
}

/// The summary of `values` (`None` when empty). Sums run in the given order.
pub fn summarize(values: &[f64]) -> Option<Summary> {
    let n = values.len();
    if n == 0 {
        return None;
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let std = if n > 1 {
        (values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1) as f64).sqrt()
    } else {
        f64::NAN
    };
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let quantiles = QUANTILES.map(|q| {
        let h = (n - 1) as f64 * q;
        let lo = h.floor() as usize;
        let hi = (lo + 1).min(n - 1);
        sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
    });
    Some(Summary {
        count: n,
        mean,
        std,
        sem: std / (n as f64).sqrt(),
        quantiles,
    })
}

/// Statistics of a table, indexed `[pressure][flux][contact_temperature]`.
#[derive(Clone, Debug, PartialEq)]
pub struct EnsembleStatistics {
    /// Converged samples per grid point.
    pub converged: Vec<usize>,
    /// Statistics of the jump (`None` where no sample converged).
    pub jump: Vec<Option<Summary>>,
    /// Statistics of the conductance.
    pub conductance: Vec<Option<Summary>>,
    /// Discretization error of `jump.mean` (K): the mean of the converged
    /// samples' estimates (a bound, the error of a mean being at most the
    /// mean of the errors); `None` where a sample has no estimate.
    pub jump_discretization_error: Vec<Option<f64>>,
}

/// Computes the statistics of a table over its converged samples.
pub fn ensemble_statistics(table: &Table) -> EnsembleStatistics {
    let ns = table.samples;
    let cells = table.points.len() / ns.max(1);
    let mut out = EnsembleStatistics {
        converged: Vec::with_capacity(cells),
        jump: Vec::with_capacity(cells),
        conductance: Vec::with_capacity(cells),
        jump_discretization_error: Vec::with_capacity(cells),
    };
    for cell in table.points.chunks(ns.max(1)) {
        let values: Vec<_> = cell
            .iter()
            .filter(|p| p.status == PointStatus::Converged)
            .filter_map(|p| p.values)
            .collect();
        out.converged.push(values.len());
        out.jump.push(summarize(
            &values.iter().map(|v| v.jump).collect::<Vec<_>>(),
        ));
        out.conductance.push(summarize(
            &values.iter().map(|v| v.conductance).collect::<Vec<_>>(),
        ));
        let errors: Option<Vec<f64>> = values.iter().map(|v| v.jump_error).collect();
        out.jump_discretization_error.push(
            errors
                .filter(|e| !e.is_empty())
                .map(|e| e.iter().sum::<f64>() / e.len() as f64),
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn summary_matches_hand_values() {
        let s = summarize(&[4.0, 1.0, 3.0, 2.0]).unwrap();
        assert_eq!(s.mean, 2.5);
        assert!((s.std - (5.0f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((s.sem - s.std / 2.0).abs() < 1e-15);
        // numpy.quantile([1, 2, 3, 4], [0.05, 0.25, 0.5, 0.75, 0.95])
        let q = [1.15, 1.75, 2.5, 3.25, 3.85];
        for (a, b) in s.quantiles.iter().zip(q) {
            assert!((a - b).abs() < 1e-14, "{a} {b}");
        }
        let one = summarize(&[7.0]).unwrap();
        assert!(one.std.is_nan() && one.sem.is_nan() && one.quantiles == [7.0; 5]);
        assert!(summarize(&[]).is_none());
    }
}
