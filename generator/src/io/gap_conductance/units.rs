//! The deck unit systems and their conversion factors.

use crate::{Error, Result};

/// The unit system of the deck (`--units`). Every conversion of the export
/// goes through these factors: deck value = factor × SI value.
///
/// mm-N-s-K: force N, length mm, time s, so energy N·mm = 10⁻³ J (mJ) and
/// power N·mm/s = 10⁻³ W (mW). Then
/// - pressure: 1 Pa = 1 N/m² = 10⁻⁶ N/mm² (MPa);
/// - heat flux: 1 W/m² = 10⁻³ mW / 10⁶ mm² … = 10⁻³ mW/mm² (N·mm/(s·mm²));
/// - conductance: 1 W/(m²·K) = 10⁻³ mW/(mm²·K);
/// - conductivity: 1 W/(m·K) = 10³ mW / (10³ mm·K) = 1 mW/(mm·K);
/// - length: 1 m = 10³ mm.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DeckUnits {
    /// m, kg, s, K (N, Pa, W): the tables' own units.
    Si,
    /// mm, N, s, K (tonne for mass): the usual CalculiX/Abaqus system.
    MmNSK,
}

impl std::str::FromStr for DeckUnits {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "si" => Ok(DeckUnits::Si),
            "mm-n-s-k" => Ok(DeckUnits::MmNSK),
            _ => Err(Error::invalid(
                "--units",
                s,
                "expected SI (m, Pa, W; default) or mm-N-s-K (mm, N/mm², mW)",
            )),
        }
    }
}

impl DeckUnits {
    /// The name as given to `--units`.
    pub const fn name(self) -> &'static str {
        match self {
            DeckUnits::Si => "SI",
            DeckUnits::MmNSK => "mm-N-s-K",
        }
    }

    /// Deck pressure per Pa.
    pub const fn pressure(self) -> f64 {
        match self {
            DeckUnits::Si => 1.0,
            DeckUnits::MmNSK => 1e-6,
        }
    }

    /// Deck heat flux per W/m² (also deck conductance per W/(m²·K)).
    pub const fn flux(self) -> f64 {
        match self {
            DeckUnits::Si => 1.0,
            DeckUnits::MmNSK => 1e-3,
        }
    }

    /// Deck conductance per W/(m²·K).
    pub const fn conductance(self) -> f64 {
        self.flux()
    }

    /// Deck conductivity per W/(m·K) (a flux times a length per kelvin).
    pub const fn conductivity(self) -> f64 {
        self.flux() * self.length()
    }

    /// Deck length per m.
    pub const fn length(self) -> f64 {
        match self {
            DeckUnits::Si => 1.0,
            DeckUnits::MmNSK => 1e3,
        }
    }

    /// Unit names: pressure, heat flux, conductance.
    pub const fn unit_names(self) -> [&'static str; 3] {
        match self {
            DeckUnits::Si => ["Pa", "W/m^2", "W/(m^2 K)"],
            DeckUnits::MmNSK => ["N/mm^2", "mW/mm^2", "mW/(mm^2 K) = N mm/(s mm^2 K)"],
        }
    }
}
