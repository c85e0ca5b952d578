//! `tcgen law --format calculix|abaqus`: the contact law as a
//! `*GAP CONDUCTANCE` block of a CalculiX or Abaqus input deck — the
//! conductance `k̄c = |h̄| / jump` (Eq. (2.7)) versus contact pressure at each
//! contact temperature, for one flux, in the deck's unit system.
//!
//! Facts about CalculiX 2.20 the block relies on (manual page
//! `*GAP CONDUCTANCE`; source `gapconductances.f`, `materialdata_sp.f`,
//! `plcopy.f`, `plmix.f`, `springforc_f2f_th.f`; checked with runs of `ccx`,
//! see `generator/tests/calculix_end_to_end.rs`):
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

use std::path::Path;

use lookup::{EvalError, Extrapolation, Law};

use crate::io::law::{LawOptions, describe_statistic, law_from_table_with};
use crate::{Error, Result};

/// Most pressure rows per temperature a CalculiX 2.20 face-to-face contact
/// reads correctly (`xiso(20)` in `springforc_f2f_th.f`; a 21-row set
/// returned a pressure as conductance in our runs).
pub const CALCULIX_MAX_PRESSURE_ROWS: usize = 20;

/// Offset of the Celsius scale, θ[°C] = θ[K] − 273.15.
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
    /// Pressures [Pa] the rows must span (`--pressure-range LO:HI`); default:
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

/// Parses `--pressure-range LO:HI` [Pa].
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
    /// Contact pressures [Pa], ascending, the same at every temperature.
    pub pressures: Vec<f64>,
    /// Contact temperatures [K], ascending (the table's and inserted ones).
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

#[cfg(test)]
mod tests {
    use super::*;
    use lookup::{Axes, ExtrapolationPolicy, LawInfo};

    /// A law with a jump ∝ p^(−0.8) at two fluxes and two temperatures.
    fn power_law(policy: ExtrapolationPolicy) -> Law {
        let axes = Axes {
            pressure: vec![1e3, 1e4, 1e5],
            flux: vec![1e5, 1e6],
            contact_temperature: vec![293.15, 393.15],
        };
        let mut jump = Vec::new();
        for &p in &axes.pressure {
            for &h in &axes.flux {
                for &t in &axes.contact_temperature {
                    jump.push(h / 1e5 * (p / 1e3).powf(-0.8) * (t / 293.15));
                }
            }
        }
        let n = jump.len();
        let info = LawInfo {
            extrapolation: policy,
            ..LawInfo::default()
        };
        Law::from_grid(axes, jump, vec![0.0; n], info).unwrap()
    }

    fn error_policy() -> ExtrapolationPolicy {
        ExtrapolationPolicy::uniform(Extrapolation::Error)
    }

    #[test]
    fn unit_factors_follow_from_mm_n_s() {
        let u = DeckUnits::MmNSK;
        // 1 N/mm² = 1 MPa.
        assert_eq!(u.pressure() * 1e6, 1.0);
        // 1 mW/mm² = 1e-3 W / 1e-6 m² = 1e3 W/m².
        assert_eq!(u.flux() * 1e3, 1.0);
        assert_eq!(u.conductance(), u.flux());
        // 1 mW/(mm K) = 1e-3 W / (1e-3 m K) = 1 W/(m K).
        assert_eq!(u.conductivity(), 1.0);
        assert_eq!(u.length(), 1e3);
        let si = DeckUnits::Si;
        assert_eq!(
            [si.pressure(), si.flux(), si.conductance(), si.length()],
            [1.0; 4]
        );
        for (s, v) in [("SI", DeckUnits::Si), ("mm-N-s-K", DeckUnits::MmNSK)] {
            assert_eq!(s.parse::<DeckUnits>().unwrap(), v);
            assert_eq!(v.name(), s);
        }
        let e = "inch".parse::<DeckUnits>().unwrap_err().to_string();
        assert!(e.contains("--units") && e.contains("mm-N-s-K"), "{e}");
        let e = "nastran".parse::<LawFormat>().unwrap_err().to_string();
        assert!(e.contains("--format") && e.contains("calculix"), "{e}");
    }

    /// Every row is |h|/jump of the law, the table's nodes are rows, and the
    /// solver's interpolation stays within the tolerance (checked on a grid
    /// 8 times finer than the writer's own sampling).
    #[test]
    fn rows_are_the_law_and_follow_it_within_the_tolerance() {
        let law = power_law(error_policy());
        for tol in [1e-2, 1e-3, 1e-4] {
            let o = GapConductanceOptions {
                flux: Some(1e5),
                tolerance: tol,
                deck: GapDeck::Abaqus,
                ..Default::default()
            };
            let rows = gap_conductance_rows(&law, &o).unwrap();
            for p in [1e3, 1e4, 1e5] {
                assert!(rows.pressures.contains(&p), "{p}");
            }
            for (it, &t) in rows.temperatures.iter().enumerate() {
                for (ip, &p) in rows.pressures.iter().enumerate() {
                    let v = law.eval(p, 1e5, t).unwrap();
                    assert_eq!(rows.at(it, ip), v.conductance);
                    assert!((v.conductance * v.jump / 1e5 - 1.0).abs() < 1e-15);
                }
            }
            let mut worst: f64 = 0.0;
            let n = 4000;
            for i in 0..=n {
                let p = 1e3 * 100f64.powf(i as f64 / n as f64);
                for t in [293.15, 310.0, 343.15, 393.15] {
                    let exact = law.eval(p, 1e5, t).unwrap().conductance;
                    worst = worst.max((rows.interpolate(p, t) / exact - 1.0).abs());
                }
            }
            assert!(worst <= tol, "tol {tol}: {worst}");
            assert!(rows.max_deviation <= tol);
            println!(
                "tol {tol:e}: {} pressures x {} temperatures, worst {worst:.3e}",
                rows.pressures.len(),
                rows.temperatures.len()
            );
        }
    }

    /// Ten times tighter costs about √10 times the rows (the chord error of
    /// a smooth curve is O(Δ²)).
    #[test]
    fn row_count_grows_like_the_inverse_square_root_of_the_tolerance() {
        let law = power_law(error_policy());
        let count = |tol: f64| {
            let o = GapConductanceOptions {
                flux: Some(1e6),
                tolerance: tol,
                ..Default::default()
            };
            gap_conductance_rows(&law, &o).unwrap().pressures.len() as f64
        };
        let (a, b) = (count(1e-3), count(1e-5));
        let ratio = (b - 1.0) / (a - 1.0);
        assert!(ratio > 5.0 && ratio < 20.0, "{a} -> {b}: {ratio}");
    }

    #[test]
    fn deck_lines_are_converted_and_readable_by_calculix() {
        let law = power_law(error_policy());
        let o = GapConductanceOptions {
            flux: Some(1e5),
            units: DeckUnits::MmNSK,
            celsius: true,
            tolerance: 5e-2,
            ..Default::default()
        };
        let rows = gap_conductance_rows_for_deck(&law, &o).unwrap();
        let source = DeckSource {
            table: "t.h5".into(),
            sha256: "ab".repeat(32),
            statistic: "deterministic".into(),
        };
        let deck = render_deck(&law, &rows, &o, &source);
        let data: Vec<&str> = deck
            .lines()
            .skip_while(|l| *l != "*GAP CONDUCTANCE")
            .skip(1)
            .collect();
        assert_eq!(data.len(), rows.pressures.len() * rows.temperatures.len());
        let first: Vec<f64> = data[0]
            .split(',')
            .map(|f| f.trim().parse().unwrap())
            .collect();
        assert!((first[0] / (1e-3 * rows.at(0, 0)) - 1.0).abs() < 1e-10);
        assert!((first[1] - 1e3 * 1e-6).abs() < 1e-15);
        assert!((first[2] - 20.0).abs() < 1e-9);
        for l in &data {
            assert!(l.split(',').all(|f| f.trim().len() <= 20), "{l}");
        }
        for needle in [
            "t.h5",
            &"ab".repeat(32),
            "statistic: deterministic",
            "|h| = 1e5 W/m^2",
            "mW/(mm^2 K)",
            "OUTSIDE",
            "degC",
        ] {
            assert!(deck.contains(needle), "{needle}\n{deck}");
        }
        assert!(
            deck.lines()
                .all(|l| l.starts_with("**") || !l.contains("**"))
        );
        let abaqus = render_deck(
            &law,
            &rows,
            &GapConductanceOptions {
                deck: GapDeck::Abaqus,
                ..o
            },
            &source,
        );
        assert!(abaqus.contains("\n*GAP CONDUCTANCE, PRESSURE\n"));
    }

    #[test]
    fn flux_and_range_are_checked() {
        let law = power_law(error_policy());
        let o = GapConductanceOptions::default();
        let e = gap_conductance_rows(&law, &o).unwrap_err().to_string();
        assert!(e.contains("--flux") && e.contains("2 fluxes"), "{e}");
        for bad in [2e6, 1e4, -1.0] {
            let e = gap_conductance_rows(
                &law,
                &GapConductanceOptions {
                    flux: Some(bad),
                    ..o
                },
            )
            .unwrap_err()
            .to_string();
            assert!(e.contains("--flux"), "{e}");
        }
        // Inside: interpolated by the law.
        let r = gap_conductance_rows(
            &law,
            &GapConductanceOptions {
                flux: Some(4e5),
                tolerance: 1e-2,
                ..o
            },
        )
        .unwrap();
        assert_eq!(r.flux_source, FluxSource::Interpolated);
        let v = law.eval(1e4, 4e5, 293.15).unwrap();
        let i = r.pressures.iter().position(|&p| p == 1e4).unwrap();
        assert_eq!(r.at(0, i), v.conductance);
        // Beyond the table only under a pressure policy.
        let wide = GapConductanceOptions {
            flux: Some(1e5),
            pressure_range: Some([100.0, 1e6]),
            tolerance: 1e-2,
            ..o
        };
        let e = gap_conductance_rows(&law, &wide).unwrap_err().to_string();
        assert!(
            e.contains("--pressure-range") && e.contains("pressure=clamp"),
            "{e}"
        );
        let mut clamp = error_policy();
        clamp.pressure = Extrapolation::Clamp;
        let r = gap_conductance_rows(&power_law(clamp), &wide).unwrap();
        // Explicit end rows, constant beyond the table.
        assert_eq!(r.pressures[0], 100.0);
        assert_eq!(*r.pressures.last().unwrap(), 1e6);
        assert_eq!(r.at(0, 0), r.at(0, 1));
        let mut power = error_policy();
        power.pressure = Extrapolation::Power;
        let r = gap_conductance_rows(&power_law(power), &wide).unwrap();
        // k ∝ p^0.8 continued: 10× the pressure, 10^0.8 × the conductance.
        let k_hi = r.at(0, r.pressures.len() - 1);
        let k_1e5 = r.at(0, r.pressures.iter().position(|&p| p == 1e5).unwrap());
        assert!((k_hi / k_1e5 / 10f64.powf(0.8) - 1.0).abs() < 1e-9);
        assert!(parse_pressure_range("1e3:1e2").is_err());
        assert_eq!(parse_pressure_range("1e2:1e3").unwrap(), [1e2, 1e3]);
    }

    #[test]
    fn calculix_row_limit_names_a_tolerance_that_fits() {
        let law = power_law(error_policy());
        let o = GapConductanceOptions {
            flux: Some(1e5),
            tolerance: 1e-4,
            ..Default::default()
        };
        let e = gap_conductance_rows_for_deck(&law, &o)
            .unwrap_err()
            .to_string();
        assert!(e.contains("--tolerance") && e.contains("at most 20"), "{e}");
        let fit: f64 = e
            .split("use --tolerance ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        let r = gap_conductance_rows_for_deck(
            &law,
            &GapConductanceOptions {
                tolerance: fit,
                ..o
            },
        )
        .unwrap();
        assert!(r.pressures.len() <= CALCULIX_MAX_PRESSURE_ROWS);
    }
}
