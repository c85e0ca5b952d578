//! The options of a `*GAP CONDUCTANCE` export and their checks.

use super::*;
use crate::{Error, Result};

/// The options of a `*GAP CONDUCTANCE` export.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GapConductanceOptions {
    /// The solver's keyword syntax.
    pub deck: GapDeck,
    /// The deck's unit system.
    pub units: DeckUnits,
    /// Temperatures in °C instead of K (`--celsius`).
    pub celsius: bool,
    /// The flux `|h̄|` [W/m²] (`--flux`); required when the table has several.
    pub flux: Option<f64>,
    /// Largest relative deviation of the solver's piecewise-linear
    /// interpolation from the law (`--tolerance`).
    pub tolerance: f64,
    /// Pressures (Pa) the rows must span (`--pressure-range LO:HI`); default:
    /// the table's. Beyond the table only under a pressure extrapolation policy.
    pub pressure_range: Option<[f64; 2]>,
}

impl Default for GapConductanceOptions {
    fn default() -> Self {
        GapConductanceOptions {
            deck: GapDeck::Calculix,
            units: DeckUnits::Si,
            celsius: false,
            flux: None,
            tolerance: 1e-3,
            pressure_range: None,
        }
    }
}

/// Parses `--pressure-range LO:HI` (Pa).
pub fn parse_pressure_range(s: &str) -> Result<[f64; 2]> {
    let bad = || {
        Error::invalid(
            "--pressure-range",
            s,
            "expected LO:HI in Pa with 0 < LO < HI, e.g. 500:2e5",
        )
    };
    let (lo, hi) = s.split_once(':').ok_or_else(bad)?;
    let (lo, hi): (f64, f64) = (
        lo.trim().parse().map_err(|_| bad())?,
        hi.trim().parse().map_err(|_| bad())?,
    );
    if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi) {
        return Err(bad());
    }
    Ok([lo, hi])
}

impl GapConductanceOptions {
    /// Checks the tolerance and the range (messages name the option).
    pub fn validate(&self) -> Result<()> {
        if !(self.tolerance.is_finite() && self.tolerance >= 1e-8 && self.tolerance <= 0.5) {
            return Err(Error::invalid(
                "--tolerance",
                self.tolerance,
                "must be 1e-8 ≤ tolerance ≤ 0.5 (relative deviation of the deck's linear interpolation from the law)",
            ));
        }
        if let Some(h) = self.flux
            && !(h.is_finite() && h > 0.0)
        {
            return Err(Error::invalid(
                "--flux",
                h,
                "must be a flux magnitude |h| > 0 in W/m^2",
            ));
        }
        if let Some([lo, hi]) = self.pressure_range
            && !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo < hi)
        {
            return Err(Error::invalid(
                "--pressure-range",
                format!("{lo:e}:{hi:e}"),
                "expected LO:HI in Pa with 0 < LO < HI",
            ));
        }
        Ok(())
    }
}
