//! Rendering the `*GAP CONDUCTANCE` block with its header.

use super::*;
use lookup::{Extrapolation, Law};

/// What the header of the block says about its source.
#[derive(Clone, Debug, PartialEq)]
pub struct DeckSource {
    /// The table's path as given.
    pub table: String,
    /// SHA-256 of the table file.
    pub sha256: String,
    /// The statistic of the law, in words.
    pub statistic: String,
}

/// A number for an input deck: at most 20 characters (CalculiX reads
/// `f20.0` fields: a longer number is an input error), 11 significant digits.
pub fn deck_number(x: f64) -> String {
    format!("{x:.10E}")
}

/// The `*GAP CONDUCTANCE` block: `**` comments (source, checksum,
/// statistic, flux, units, rows, behaviour outside the table), the keyword
/// line and `conductance, pressure, temperature` lines, one set per
/// temperature, pressures ascending.
pub fn render_deck(
    law: &Law,
    rows: &GapConductanceRows,
    o: &GapConductanceOptions,
    source: &DeckSource,
) -> String {
    let u = o.units;
    let [pu, fu, ku] = u.unit_names();
    let tu = if o.celsius { "degC" } else { "K" };
    let temp = |t: f64| if o.celsius { t - CELSIUS_OFFSET } else { t };
    let axes = law.axes();
    let policy = law.info().extrapolation;
    let (np, nt) = (rows.pressures.len(), rows.temperatures.len());
    let (lo, hi) = (rows.pressures[0], rows.pressures[np - 1]);
    let (t_lo, t_hi) = (rows.temperatures[0], rows.temperatures[nt - 1]);
    let (p_lo, p_hi) = (axes.pressure[0], axes.pressure[axes.pressure.len() - 1]);
    let solver = o.deck.solver();
    let mut s = String::new();
    let mut line = |text: String| {
        s.push_str("** ");
        s.push_str(&text);
        s.push('\n');
    };
    line(format!(
        "{} written by {} (tcgen law --format {})",
        o.deck.keyword_line(),
        crate::io::provenance::generator(),
        match o.deck {
            GapDeck::Calculix => "calculix",
            GapDeck::Abaqus => "abaqus",
        }
    ));
    line(format!("source table: {}", source.table));
    line(format!("source table SHA-256: {}", source.sha256));
    line(format!("statistic: {}", source.statistic));
    line(format!(
        "flux |h| = {:e} W/m^2 = {} {fu} ({}); the conductance |h|/jump(p, |h|, T) holds for this flux only",
        rows.flux,
        deck_number(rows.flux * u.flux()),
        match rows.flux_source {
            FluxSource::Node => "a node of the table".to_string(),
            FluxSource::Interpolated => "inside the table, interpolated by the law".to_string(),
            FluxSource::Extrapolated(e) => format!("outside the table, law policy {e}"),
        }
    ));
    line(format!(
        "units {}: conductance {ku} (= {:e} x W/(m^2 K)), contact pressure {pu} (= {:e} x Pa), temperature {tu}",
        u.name(),
        u.conductance(),
        u.pressure()
    ));
    line("data lines: conductance, contact pressure, temperature".into());
    line(format!(
        "rows: {np} pressures x {nt} temperature(s); {solver}'s linear interpolation in pressure \
         (and temperature) stays within {:.1e} of the law (monotone cubic in ln p), sampled maximum {:.2e}",
        rows.tolerance, rows.max_deviation
    ));
    line(format!(
        "pressures of the rows: [{}, {}] {pu}; of the table: [{}, {}] {pu}",
        deck_number(lo * u.pressure()),
        deck_number(hi * u.pressure()),
        deck_number(p_lo * u.pressure()),
        deck_number(p_hi * u.pressure())
    ));
    match policy.pressure {
        Extrapolation::Error => line(format!(
            "OUTSIDE the pressures of the rows {} \
             while the law is undefined there (law policy error): keep contact pressures inside \
             [{}, {}] {pu}, or export with --extrapolate pressure=clamp|power --pressure-range LO:HI",
            o.deck.outside_rows(),
            deck_number(lo * u.pressure()),
            deck_number(hi * u.pressure())
        )),
        e => line(format!(
            "beyond the table the rows follow the law's pressure policy {e}; outside the rows {}",
            o.deck.outside_rows()
        )),
    }
    line(format!(
        "temperature: {solver} uses the mean of the slave and master surface temperatures \
         (theta_c + jump/2 in the law's terms), linear between sets, end sets held outside \
         [{}, {}] {tu}{}",
        deck_number(temp(t_lo)),
        deck_number(temp(t_hi)),
        if nt == 1 {
            " (one set: no temperature dependence)"
        } else {
            ""
        }
    ));
    if let Some(max) = o.deck.max_pressure_rows() {
        line(format!(
            "CalculiX face-to-face contact reads at most {max} pressure rows per temperature"
        ));
    }
    line(
        "include after *SURFACE INTERACTION and *SURFACE BEHAVIOR, e.g. *INCLUDE, INPUT=<this file>"
            .into(),
    );
    s.push_str(o.deck.keyword_line());
    s.push('\n');
    for (it, &t) in rows.temperatures.iter().enumerate() {
        for (ip, &p) in rows.pressures.iter().enumerate() {
            s.push_str(&format!(
                "{}, {}, {}\n",
                deck_number(rows.at(it, ip) * u.conductance()),
                deck_number(p * u.pressure()),
                deck_number(temp(t))
            ));
        }
    }
    s
}
