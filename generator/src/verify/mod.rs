//! The verification catalogue (spec §10), printed by `tcgen verify`.
//!
//! Every case compares a computed quantity with a reference (closed form,
//! manufactured solution, or an expected convergence rate) and states its
//! tolerance. The same functions back the integration tests, so the table
//! printed for a user is the evidence the test suite checks.

use serde::Serialize;

use crate::Result;

pub mod bulk;
pub mod contact;
pub mod homogenization;
pub mod lateral;
pub mod mms;

/// One line of the verification table.
#[derive(Clone, Debug, Serialize)]
pub struct Check {
    /// Case name (group of checks).
    pub case: String,
    /// What is compared.
    pub quantity: String,
    /// Computed value.
    pub computed: f64,
    /// Reference value.
    pub reference: f64,
    /// Error measure (absolute or relative, as `quantity` says).
    pub error: f64,
    /// Tolerance on `error` (or on the rate deviation for rate checks).
    pub tolerance: f64,
    /// Observed convergence rate, when the check is a rate.
    pub rate: Option<f64>,
    /// Whether the check passed.
    pub pass: bool,
}

impl Check {
    /// A check of `computed` against `reference` with relative error
    /// `|c − r| / max(|r|, floor)`.
    pub fn relative(
        case: &str,
        quantity: &str,
        computed: f64,
        reference: f64,
        tolerance: f64,
    ) -> Self {
        let error = (computed - reference).abs() / reference.abs().max(1e-300);
        Check::with_error(case, quantity, computed, reference, error, tolerance)
    }

    /// A check of `computed` against `reference` with absolute error.
    pub fn absolute(
        case: &str,
        quantity: &str,
        computed: f64,
        reference: f64,
        tolerance: f64,
    ) -> Self {
        let error = (computed - reference).abs();
        Check::with_error(case, quantity, computed, reference, error, tolerance)
    }

    /// A check with an error computed by the caller (`error <= tolerance` passes).
    pub fn with_error(
        case: &str,
        quantity: &str,
        computed: f64,
        reference: f64,
        error: f64,
        tolerance: f64,
    ) -> Self {
        Check {
            case: case.into(),
            quantity: quantity.into(),
            computed,
            reference,
            error,
            tolerance,
            rate: None,
            pass: error.is_finite() && error <= tolerance,
        }
    }

    /// A convergence-rate check: observed `rate` against `expected` within `tolerance`.
    pub fn rate(
        case: &str,
        quantity: &str,
        finest_error: f64,
        rate: f64,
        expected: f64,
        tolerance: f64,
    ) -> Self {
        let dev = (rate - expected).abs();
        Check {
            case: case.into(),
            quantity: quantity.into(),
            computed: finest_error,
            reference: expected,
            error: dev,
            tolerance,
            rate: Some(rate),
            pass: rate.is_finite() && dev <= tolerance,
        }
    }
}

/// A curve computed by a verification case, for the plots of
/// `docs/validation.md`: `y(x)` with axis labels (units included).
#[derive(Clone, Debug, Serialize)]
pub struct Series {
    /// Case name (as in [`Check::case`]).
    pub case: String,
    /// Curve name, unique within the case (e.g. `"PR, jump vs height"`).
    pub name: String,
    /// Abscissa label with units.
    pub x_label: String,
    /// Ordinate label with units.
    pub y_label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates.
    pub y: Vec<f64>,
}

static SERIES: std::sync::Mutex<Vec<Series>> = std::sync::Mutex::new(Vec::new());

/// Records a curve computed by a case (collected by [`take_series`]; costs
/// nothing else, so cases record what they compute unconditionally).
pub fn record_series(case: &str, name: &str, labels: (&str, &str), x: &[f64], y: &[f64]) {
    assert_eq!(
        x.len(),
        y.len(),
        "series {case}/{name}: x and y lengths differ"
    );
    let s = Series {
        case: case.into(),
        name: name.into(),
        x_label: labels.0.into(),
        y_label: labels.1.into(),
        x: x.to_vec(),
        y: y.to_vec(),
    };
    SERIES.lock().unwrap_or_else(|e| e.into_inner()).push(s);
}

/// Takes every series recorded so far (in recording order).
pub fn take_series() -> Vec<Series> {
    std::mem::take(&mut *SERIES.lock().unwrap_or_else(|e| e.into_inner()))
}

/// A verification case: a name and the function that runs it.
pub struct Case {
    /// Name (also the filter key).
    pub name: &'static str,
    /// What it verifies, one line.
    pub description: &'static str,
    /// Runs the case.
    pub run: fn() -> Result<Vec<Check>>,
}

/// All cases of the catalogue, in order.
pub fn catalogue() -> Vec<Case> {
    let mut v = Vec::new();
    v.extend(mms::cases());
    v.extend(bulk::cases());
    v.extend(contact::cases());
    v.extend(homogenization::cases());
    v.extend(lateral::cases());
    v
}

/// Runs the cases whose name satisfies `select`; `Ok(number of checks)` if
/// every check passed, otherwise the failed checks (or errors) as a table.
pub fn run_selected(select: impl Fn(&str) -> bool) -> std::result::Result<usize, String> {
    let cases: Vec<Case> = catalogue().into_iter().filter(|c| select(c.name)).collect();
    if cases.is_empty() {
        return Err("no case selected".into());
    }
    let mut n = 0;
    let mut report = String::new();
    for c in cases {
        match (c.run)() {
            Ok(checks) if checks.is_empty() => report.push_str(&format!("{}: no checks\n", c.name)),
            Ok(checks) => {
                n += checks.len();
                let failed: Vec<Check> = checks.into_iter().filter(|c| !c.pass).collect();
                if !failed.is_empty() {
                    report.push_str(&format_table(&failed));
                }
            }
            Err(e) => report.push_str(&format!("{}: {e}\n", c.name)),
        }
    }
    if report.is_empty() {
        Ok(n)
    } else {
        Err(report)
    }
}

/// Least-squares slope of `log(e)` against `log(h)`.
pub fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Formats checks as an aligned text table.
pub fn format_table(checks: &[Check]) -> String {
    let mut s = format!(
        "{:<28} {:<40} {:>13} {:>13} {:>10} {:>9} {:>6}  {}\n",
        "case", "quantity", "computed", "reference", "error", "tolerance", "rate", "result"
    );
    for c in checks {
        let rate = c.rate.map(|r| format!("{r:.3}")).unwrap_or_default();
        s.push_str(&format!(
            "{:<28} {:<40} {:>13.6e} {:>13.6e} {:>10.2e} {:>9.1e} {:>6}  {}\n",
            c.case,
            c.quantity,
            c.computed,
            c.reference,
            c.error,
            c.tolerance,
            rate,
            if c.pass { "pass" } else { "FAIL" }
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fitted_rate_recovers_a_power_law() {
        let h = [0.5, 0.25, 0.125, 0.0625];
        let e: Vec<f64> = h.iter().map(|h: &f64| 3.0 * h.powf(2.7)).collect();
        assert!((fitted_rate(&h, &e) - 2.7).abs() < 1e-12);
    }

    #[test]
    fn checks_fail_on_nan() {
        assert!(!Check::relative("c", "q", f64::NAN, 1.0, 1.0).pass);
        assert!(!Check::rate("c", "q", 1.0, f64::NAN, 2.0, 0.1).pass);
    }
}
