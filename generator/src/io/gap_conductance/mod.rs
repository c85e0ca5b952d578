//! `tcgen law --format calculix|abaqus`: the contact law as a
//! `*GAP CONDUCTANCE` block of a CalculiX or Abaqus input deck — the
//! conductance `k̄c = |h̄| / jump` (Eq. (2.7)) versus contact pressure at each
//! contact temperature, for one flux, in the deck's unit system.
//!
//! Facts about CalculiX 2.20 the block relies on (manual page
//! `*GAP CONDUCTANCE`; source `gapconductances.f`, `materialdata_sp.f`,
//! `plcopy.f`, `plmix.f`, `springforc_f2f_th.f`; checked with runs of `ccx`,
//! see `generator/tests/suite/calculix_end_to_end.rs`):
//! - data lines are `conductance, contact pressure, temperature`, one set of
//!   lines per temperature, each number read from a field of at most 20
//!   characters;
//! - the conductance is interpolated **linearly in pressure**, and linearly
//!   in temperature between the sets; the temperature is the **mean of the
//!   slave and master surface temperatures**;
//! - outside the pressures (and temperatures) of the deck ccx **holds the end
//!   values** (constant continuation), without a warning;
//! - face-to-face (`SURFACE TO SURFACE`) penalty contact copies a set into
//!   arrays of 20 entries (`springforc_f2f_th.f`): a 21st pressure row
//!   corrupts the lookup silently, so a CalculiX block has at most
//!   [`CALCULIX_MAX_PRESSURE_ROWS`] rows per temperature.
//!
//! The law is a monotone cubic in `ln p̄N` (Steffen), so the writer inserts
//! pressures (and temperatures) evaluated with the law until the solver's
//! piecewise-linear interpolation stays within a relative tolerance of the
//! law everywhere inside the deck's range.

mod deck;
mod options;
mod rows;
#[cfg(test)]
mod tests;
mod units;

pub use deck::{DeckSource, deck_number, render_deck};
pub use options::{GapConductanceOptions, parse_pressure_range};
pub use rows::{
    FluxSource, GapConductanceRows, gap_conductance_rows, gap_conductance_rows_for_deck,
};
pub use units::DeckUnits;

use std::path::Path;

use crate::io::law::{LawOptions, describe_statistic, law_from_table_with};
use crate::{Error, Result};

/// Most pressure rows per temperature a CalculiX 2.20 face-to-face contact
/// reads correctly (`xiso(20)` in `springforc_f2f_th.f`; a 21-row set
/// returned a pressure as conductance in our runs).
pub const CALCULIX_MAX_PRESSURE_ROWS: usize = 20;

/// Offset of the Celsius scale, `θ[°C] = θ[K] − 273.15`.
pub const CELSIUS_OFFSET: f64 = 273.15;

/// Samples per interval when measuring the deviation of a chord from the law.
const SAMPLES: usize = 32;

/// Which solver's keyword syntax the block follows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GapDeck {
    /// CalculiX: `*GAP CONDUCTANCE` (pressure dependence is implied).
    Calculix,
    /// Abaqus/Standard: `*GAP CONDUCTANCE, PRESSURE` (without `PRESSURE` the
    /// second column would be a clearance).
    Abaqus,
}

impl GapDeck {
    /// The keyword line.
    pub const fn keyword_line(self) -> &'static str {
        match self {
            GapDeck::Calculix => "*GAP CONDUCTANCE",
            GapDeck::Abaqus => "*GAP CONDUCTANCE, PRESSURE",
        }
    }

    /// The solver's name in messages and comments.
    pub const fn solver(self) -> &'static str {
        match self {
            GapDeck::Calculix => "CalculiX",
            GapDeck::Abaqus => "Abaqus",
        }
    }

    /// What the solver does outside the rows, and how we know.
    pub const fn outside_rows(self) -> &'static str {
        match self {
            GapDeck::Calculix => {
                "CalculiX holds the end values (constant, no warning; source and runs of ccx 2.20)"
            }
            GapDeck::Abaqus => {
                "Abaqus holds the end values (its documented rule for tabular data; not run here)"
            }
        }
    }

    /// Most pressure rows per temperature the solver reads correctly.
    pub const fn max_pressure_rows(self) -> Option<usize> {
        match self {
            GapDeck::Calculix => Some(CALCULIX_MAX_PRESSURE_ROWS),
            GapDeck::Abaqus => None,
        }
    }
}

/// What `tcgen law` writes (`--format`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LawFormat {
    /// The binary law for `lookup` (`schemas/law.md`), the default.
    Tclaw,
    /// A `*GAP CONDUCTANCE` block.
    Deck(GapDeck),
}

impl std::str::FromStr for LawFormat {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "tclaw" => Ok(LawFormat::Tclaw),
            "calculix" => Ok(LawFormat::Deck(GapDeck::Calculix)),
            "abaqus" => Ok(LawFormat::Deck(GapDeck::Abaqus)),
            _ => Err(Error::invalid(
                "--format",
                s,
                "expected tclaw (the binary law, default), calculix or abaqus (a *GAP CONDUCTANCE block)",
            )),
        }
    }
}

/// Reads a table, builds its law and writes the `*GAP CONDUCTANCE` block to
/// `output` atomically. Returns the rows.
pub fn write_gap_conductance(
    table: &Path,
    output: &Path,
    law_options: &LawOptions,
    o: &GapConductanceOptions,
) -> Result<GapConductanceRows> {
    o.validate()?;
    let bytes = std::fs::read(table).map_err(|e| Error::Io {
        path: table.display().to_string(),
        source: e,
    })?;
    let t = crate::io::read_table(table)?;
    let source = table.display().to_string();
    let law = law_from_table_with(&t, &source, law_options)?;
    let rows = gap_conductance_rows_for_deck(&law, o)?;
    let deck = render_deck(
        &law,
        &rows,
        o,
        &DeckSource {
            table: source,
            sha256: crate::io::hash::sha256_hex(&bytes),
            statistic: describe_statistic(law.info().statistic),
        },
    );
    crate::io::atomic::write_atomic(output, deck.as_bytes())?;
    Ok(rows)
}
