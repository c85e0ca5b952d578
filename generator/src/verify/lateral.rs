//! Lateral boundary conditions, paper Sect. 5.3 / Figs. 10–11: LN against
//! PR faces and the top face held (`top_lateral = "fixed"`) or free to slide
//! (`"free"`), in 2D (sinusoids, Fig. 11) and 3D (egg boxes, Fig. 10).
//!
//! - Symmetric cells (a sinusoid or egg box on a flat, matched pairs): LN
//!   and PR give the same jump.
//! - Mismatched cells (equal RMS 1 μm, wavelength 10 μm, the upper surface
//!   shifted by the phase π/2 along x; in 3D with the top free by the phases
//!   (π/2, π/4) along x and y; constraint model, Table I, `p̄N` = 30 kPa,
//!   where a gap remains):
//!   PR gives a smaller jump than LN; with the top held the bodies slide only
//!   through the shear of the sample, so the PR gap and jump shrink as the
//!   height grows while LN stays nearly constant ("PR-BCs deliver smaller and
//!   smaller gaps ... LN-BCs ... always the same result for a unit cell of
//!   any given height"); with the top free the upper body slides to the
//!   matched configuration (offset `φλ/2π` mod λ along each axis) and the
//!   jump is the matched pair's ("the exact value of ϑc for this setup is
//!   zero"), with a vanishing net tangential contact force.
//!
//! 2D: coarse meshes and heights 3.5, 7, 14 μm by default (about 15 s);
//! `TCGEN_LONG_TESTS=1` adds 28 μm and the paper's resolution. 3D: 6 × 6 /
//! 5 × 5 elements laterally, 3 through 7 μm (scaled with the height),
//! heights 7 and 14 μm by default; long: 8 × 8 / 7 × 7 and 28 μm. At
//! 3.5 μm the 3D PR jump is only 1.2 % below LN (measured 9.47 against
//! 9.58 K on the default mesh): the held top leaves the thin cell little
//! shear to slide by, so the 3D cells start at 7 μm.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};

use crate::Result;
use crate::homogenize::path::PathSolver;
use crate::sample::micro::net_lateral_force;
use crate::verify::homogenization::{Sample, egg_box, flat, long_runs, sinusoid};
use crate::verify::{Case, Check, record_series};

/// Wavelength = width of the cell (m).
const WAVELENGTH: f64 = 1.0e-5;
/// RMS of each sinusoid (m).
const RMS: f64 = 1.0e-6;
/// The pressure of the mismatched cell (Pa): a gap remains at every height.
const PRESSURE: f64 = 3.0e4;

/// All cases of this file.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "lateral_symmetric",
            description: "Sect. 5.3: symmetric cells (sinusoid on flat, matched sinusoids): LN and PR jumps agree",
            run: || symmetric(Cells { dimension: 2 }),
        },
        Case {
            name: "lateral_mismatched",
            description: "Fig. 11: mismatched sinusoids: PR < LN; held top: PR jump shrinks with height; free top: slides to the matched pair",
            run: || mismatched(Cells { dimension: 2 }),
        },
        Case {
            name: "lateral_symmetric_3d",
            description: "Fig. 10 in 3D: symmetric cells (egg box on flat, matched egg boxes): LN and PR jumps agree",
            run: || symmetric(Cells { dimension: 3 }),
        },
        Case {
            name: "lateral_mismatched_3d",
            description: "Fig. 10 in 3D: mismatched egg boxes, held top: PR < LN, the PR jump shrinks with height, LN constant",
            run: || mismatched(Cells { dimension: 3 }),
        },
        Case {
            name: "lateral_free_top_3d",
            description: "Free top in 3D: mismatched egg boxes slide in x and y to the matched pair, zero net lateral force",
            run: || free_top(Cells { dimension: 3 }),
        },
    ]
}

/// The cells of one dimension: sinusoids `f(x)` (2D) or egg boxes `f(x, y)` (3D).
#[derive(Clone, Copy, Debug)]
pub struct Cells {
    /// 2 or 3.
    pub dimension: usize,
}

impl Cells {
    /// The catalogue name of case `base` in this dimension.
    fn name(&self, base: &str) -> String {
        match self.dimension {
            3 => format!("{base}_3d"),
            _ => base.to_string(),
        }
    }

    /// The rough surface shifted by the phases `[φx, φy]` (`φy` unused in 2D).
    pub fn surface(&self, phase: [f64; 2]) -> String {
        match self.dimension {
            3 => egg_box(RMS, WAVELENGTH, phase),
            _ => sinusoid(RMS, WAVELENGTH, phase[0]),
        }
    }

    /// The phases of the upper surface of the mismatched cell: π/2 along x.
    pub fn mismatch(&self) -> [f64; 2] {
        [FRAC_PI_2, 0.0]
    }

    /// The phases of the upper surface of the free-top cell: those of
    /// [`Cells::mismatch`] in 2D; in 3D (π/2, π/4), so that the upper body
    /// slides along both axes. (With these phases and the top held, PR
    /// stalled at 80 % of the load before the seams were smoothed, Newton
    /// cycling at a projection that jumps; the held-top cases keep
    /// (π/2, 0).)
    pub fn free_mismatch(&self) -> [f64; 2] {
        match self.dimension {
            3 => [FRAC_PI_2, FRAC_PI_4],
            _ => self.mismatch(),
        }
    }

    /// The heights of the 3D free-top cell (m): 7 μm; long runs add 14 μm.
    fn free_heights(&self) -> Vec<f64> {
        if long_runs() {
            vec![7.0e-6, 14.0e-6]
        } else {
            vec![7.0e-6]
        }
    }

    /// The heights of the mismatched cell (m).
    fn heights(&self) -> Vec<f64> {
        match (self.dimension, long_runs()) {
            (3, true) => vec![7.0e-6, 14.0e-6, 28.0e-6],
            (3, false) => vec![7.0e-6, 14.0e-6],
            (_, true) => vec![3.5e-6, 7.0e-6, 14.0e-6, 28.0e-6],
            (_, false) => vec![3.5e-6, 7.0e-6, 14.0e-6],
        }
    }

    /// A cell of height `h` (m) with meshes scaled to keep the element
    /// aspect. 3D: the load stepping starts at a quarter of the pressure (a
    /// full first step overshoots into a deeply penetrated state whose
    /// closest-point searches over the periodic images took 34 of the 41 s
    /// of one PR solve; the path's end is the same to 1e-8).
    pub fn cell(&self, upper: String, lower: String, lateral: &'static str, h: f64) -> Sample {
        let fine = long_runs();
        let (nu, nl, solver) = match (self.dimension, fine) {
            (3, true) => ([8, 4], [7, 4], STEPPING_3D),
            (3, false) => ([6, 3], [5, 3], STEPPING_3D),
            (_, true) => ([32, 16], [27, 14], ""),
            (_, false) => ([16, 8], [12, 7], ""),
        };
        let z = |n: usize| ((n as f64 * h / 7.0e-6).round() as usize).max(2);
        Sample {
            width: WAVELENGTH,
            height: h,
            lateral,
            upper,
            lower,
            dimension: self.dimension,
            elements: ([nu[0], z(nu[1])], [nl[0], z(nl[1])]),
            pressures: vec![PRESSURE],
            solver: solver.into(),
            ..Sample::default()
        }
    }

    /// 2D: LN and PR agree to 1e−6 on symmetric cells (identical in
    /// practice), the free top slides to λ/4 within 1e−4 λ (measured 8e−6)
    /// and its jump is the matched pair's within 2 % (1e−4 of the LN jump).
    ///
    /// 3D (6 × 6 / 5 × 5 elements; long runs 8 × 8 / 7 × 7): on symmetric
    /// cells the PR and LN jumps agree to the digits of
    /// `docs/validation/checks.md` on the default mesh (9.227361 K on a flat,
    /// 9.596988e−3 K matched; earlier meshes and seams differed by 5.3e−6
    /// (1.3e−5) of the jump on a flat and 8.6e−8 matched): within 5e−5;
    /// their contact fractions agree to the last digit (stop 24; before,
    /// the 3D edge check counted samples off an LN face as keeping their
    /// sign and fitted the spots cut by the face: 0.033 against 0.015 at
    /// 10 kPa, 0.41 against 0.19 at 100 kPa).
    /// Both solutions are mirror-symmetric to 1e−9 Pa and differ by 5 Pa of
    /// 1e5 Pa in the interface pressure; the cause is not identified. The
    /// free top slides to (λ/4, λ/8) within 8.7e−5 λ and 1.6e−4 λ (4.2e−5 λ,
    /// 3.2e−5 λ; the elastic correction of the coarse fits, mean top
    /// displacement): within 5e−4 λ. Its jump is the matched pair's within
    /// 4.0e−5 (1.5e−4) of the LN jump: within 5e−4; relatively they differ by
    /// 5 % (11 %; both about 0.01 K: the gaps of the fits at other positions
    /// of the meshes), reported only.
    fn tolerances(&self) -> Tolerances {
        match self.dimension {
            // PR/LN at 7 μm: 0.976 on the default mesh with the smoothed
            // seams, 0.721 on the long runs' (mesh-bound; 0.664 and 0.795
            // with C0 seams, docs/3d.md).
            3 => Tolerances {
                symmetric: 5e-5,
                offset: 5e-4,
                matched: f64::INFINITY,
                matched_over_ln: 5e-4,
                pr_below_ln: 0.99,
            },
            _ => Tolerances {
                symmetric: 1e-6,
                offset: 1e-4,
                matched: 2e-2,
                matched_over_ln: 1e-4,
                pr_below_ln: 0.97,
            },
        }
    }
}

/// The load stepping of the 3D cells (see [`Cells::cell`]).
const STEPPING_3D: &str = "[solver.stepping]\ninitial_step = 0.25\n";

/// The solved quantities of one cell at one pressure.
#[derive(Clone, Copy, Debug)]
pub struct Outcome {
    /// Jump `|ϑ̄c|` (K).
    pub jump: f64,
    /// Mean gap (m).
    pub mean_gap: f64,
    /// Contact fraction (the reported area).
    pub contact_fraction: f64,
    /// Lateral offset of the upper body along x and y (m; y zero in 2D).
    pub lateral_offset: [f64; 2],
    /// The largest net lateral force component on the upper body over
    /// `p̄N·W^(d−1)` (free top only).
    pub force_ratio: Option<f64>,
}

/// Solves a cell with the top face `top_lateral` (`"fixed"` or `"free"`).
pub fn solve(sample: &Sample, top_lateral: &'static str) -> Result<Outcome> {
    solve_to(sample, top_lateral, None)
}

/// [`solve`], refined adaptively to the relative error `target` if given.
fn solve_to(sample: &Sample, top_lateral: &'static str, target: Option<f64>) -> Result<Outcome> {
    let mut case = Sample {
        top_lateral,
        ..sample.clone()
    }
    .case()?;
    case.discretization.target_error = target;
    let mut solver = PathSolver::new(&case)?;
    let area = case.sample.width.powi(case.dimension() as i32 - 1);
    let mut out = None;
    for &p in &case.load.pressures {
        let r = solver.solve_pressure(p)?;
        let force = net_lateral_force(&mut solver.model)?;
        out = Some(Outcome {
            jump: r.jump,
            mean_gap: r.interface.mean_gap,
            contact_fraction: r.interface.contact_fraction,
            lateral_offset: [r.interface.lateral_offset, r.interface.lateral_offset_y],
            force_ratio: force.map(|f| f.iter().fold(0.0f64, |m, f| m.max(f.abs())) / (p * area)),
        });
    }
    Ok(out.expect("at least one pressure"))
}

/// The tolerances of a dimension's checks (measured figures in the docs of
/// [`Cells::tolerances`]).
#[derive(Clone, Copy, Debug)]
struct Tolerances {
    /// Symmetric cells: `|PR − LN|` over the LN jump of the rough surface on a flat.
    symmetric: f64,
    /// Free top: the offset along each axis against `φλ/2π`, over λ.
    offset: f64,
    /// Free top: the jump against the matched pair's, relative.
    matched: f64,
    /// Free top: `|jump − matched|` over the LN jump.
    matched_over_ln: f64,
    /// Largest PR/LN jump ratio of the mismatched cell (PR below LN).
    pr_below_ln: f64,
}

/// Symmetric cells: the LN and PR jumps agree.
fn symmetric(cells: Cells) -> Result<Vec<Check>> {
    let case = &cells.name("lateral_symmetric");
    let h = 7.0e-6;
    let tol = cells.tolerances();
    let rough = || cells.surface([0.0; 2]);
    let names = match cells.dimension {
        3 => ["egg box on flat", "matched egg boxes"],
        _ => ["sinusoid on flat", "matched sinusoids"],
    };
    let mut checks = Vec::new();
    // The scale of the differences: the LN jump of the rough surface on a
    // flat (the matched pair's jump is nearly zero, the paper's exact value:
    // relative to itself its differences would be those of round-off gaps).
    let mut scale = None;
    for (name, upper, lower) in [(names[0], rough(), flat()), (names[1], rough(), rough())] {
        let mut sample = cells.cell(upper, lower, "linear", h);
        // The matched pair is in full contact at any load: a pressure that
        // leaves the rough surface on a flat partly open.
        sample.pressures = vec![1.0e4];
        let ln = solve(&sample, "fixed")?;
        sample.lateral = "periodic";
        let pr = solve(&sample, "fixed")?;
        let s = *scale.get_or_insert(ln.jump);
        checks.push(Check::with_error(
            case,
            &format!("{name}: |PR − LN| jump / LN on flat"),
            pr.jump,
            ln.jump,
            (pr.jump - ln.jump).abs() / s,
            tol.symmetric,
        ));
        checks.push(Check::relative(
            case,
            &format!("{name}: PR vs LN contact fraction"),
            pr.contact_fraction,
            ln.contact_fraction,
            tol.symmetric,
        ));
    }
    Ok(checks)
}

/// Solves the cells with the upper surface shifted by `phase` at `heights`
/// with the top face `top_lateral` and the lateral faces `lateral`.
fn solve_cells(
    cells: Cells,
    phase: [f64; 2],
    heights: &[f64],
    lateral: &'static str,
    top_lateral: &'static str,
) -> Result<Vec<Outcome>> {
    heights
        .iter()
        .map(|&h| {
            let sample = cells.cell(cells.surface(phase), cells.surface([0.0; 2]), lateral, h);
            // Long runs compare the 2D LN jump over heights (3.5–28 μm) at a
            // resolved jump: adaptively to 0.3 % (on the fixed 32-element
            // meshes the thinnest cell alone carries 2.4 % of discretization
            // error). Adaptivity is not verified in 3D: fixed meshes there.
            let resolved =
                (long_runs() && cells.dimension == 2 && lateral == "linear").then_some(3e-3);
            solve_to(&sample, top_lateral, resolved)
        })
        .collect()
}

/// Records the jump and the mean gap of each set of outcomes against the height.
fn record_heights(case: &str, heights: &[f64], sets: &[(&str, &[Outcome])]) {
    let um: Vec<f64> = heights.iter().map(|h| h * 1e6).collect();
    for (name, o) in sets {
        let jumps: Vec<f64> = o.iter().map(|o| o.jump).collect();
        let gaps: Vec<f64> = o.iter().map(|o| o.mean_gap * 1e6).collect();
        record_series(
            case,
            &format!("{name}, jump"),
            ("H0/um", "jump/K"),
            &um,
            &jumps,
        );
        record_series(
            case,
            &format!("{name}, mean gap"),
            ("H0/um", "mean gap/um"),
            &um,
            &gaps,
        );
    }
}

/// The mismatched cell of Figs. 10/11 at several heights: LN and PR with the
/// top held, and (2D) the top free; 3D: the free top is [`free_top`].
fn mismatched(cells: Cells) -> Result<Vec<Check>> {
    let case = &cells.name("lateral_mismatched");
    let heights = cells.heights();
    let phase = cells.mismatch();
    let ln = solve_cells(cells, phase, &heights, "linear", "fixed")?;
    let pr = solve_cells(cells, phase, &heights, "periodic", "fixed")?;
    let mut sets = vec![("LN", &ln[..]), ("PR fixed top", &pr[..])];
    let free = if cells.dimension == 2 {
        solve_cells(cells, phase, &heights, "periodic", "free")?
    } else {
        Vec::new()
    };
    if !free.is_empty() {
        sets.push(("PR free top", &free[..]));
    }
    record_heights(case, &heights, &sets);
    let um: Vec<f64> = heights.iter().map(|h| h * 1e6).collect();
    let mut checks = Vec::new();
    let n = heights.len();
    for i in 0..n {
        let hu = um[i];
        // PR below LN: the ratio < 0.97 (3D: 0.99).
        checks.push(Check::with_error(
            case,
            &format!("H0 = {hu} um: PR/LN jump ratio"),
            pr[i].jump / ln[i].jump,
            1.0,
            pr[i].jump / ln[i].jump,
            cells.tolerances().pr_below_ln,
        ));
        if i > 0 {
            // Held top: the PR gap and jump shrink with the height.
            for (what, a, b) in [
                ("jump", pr[i].jump, pr[i - 1].jump),
                ("mean gap", pr[i].mean_gap, pr[i - 1].mean_gap),
            ] {
                checks.push(Check::with_error(
                    case,
                    &format!("PR {what} ratio H0 {} -> {hu} um", um[i - 1]),
                    a / b,
                    1.0,
                    a / b,
                    0.95,
                ));
            }
        }
    }
    // LN: the same jump at every height (the paper: "for a unit cell of any
    // given height") once the cell is taller than the constriction field,
    // which decays over λ/2π = 1.6 μm: over H0 ≥ λ/2 (max deviation from the
    // mean). The 2D 3.5 μm cell (0.35 λ) is excluded: with resolved jumps
    // (adaptive to 0.3 %, long runs) it is 5.8 % above the taller ones
    // (10.09 against 9.66, 9.54, 9.54 K at 7, 14, 28 μm), a physical
    // finite-height effect that the fixed coarse meshes had hidden within
    // their discretization error.
    let tall: Vec<f64> = ln
        .iter()
        .zip(&heights)
        .filter(|(_, h)| **h >= 0.5 * WAVELENGTH)
        .map(|(o, _)| o.jump)
        .collect();
    let mean = tall.iter().sum::<f64>() / tall.len() as f64;
    let dev = tall
        .iter()
        .map(|j| (j / mean - 1.0).abs())
        .fold(0.0, f64::max);
    checks.push(Check::absolute(
        case,
        "LN jump: max rel. deviation over heights >= λ/2",
        dev,
        0.0,
        0.02,
    ));
    if !free.is_empty() {
        let matched = solve_cells(cells, [0.0; 2], &heights, "periodic", "fixed")?;
        checks.extend(free_checks(
            case, cells, phase, &heights, &free, &matched, &ln,
        ));
    }
    Ok(checks)
}

/// 3D free top (`top_lateral = "free"`, PR): the egg box shifted by
/// [`Cells::free_mismatch`] slides back along x and y to the matched pair,
/// from the rigid pre-slide ([`crate::sample::micro::rigid_sliding_offset`])
/// and Newton; checked as in 2D against the matched pair and, for scale, the
/// LN jump of the same cell.
fn free_top(cells: Cells) -> Result<Vec<Check>> {
    let case = &cells.name("lateral_free_top");
    let heights = cells.free_heights();
    let phase = cells.free_mismatch();
    let ln = solve_cells(cells, phase, &heights, "linear", "fixed")?;
    let free = solve_cells(cells, phase, &heights, "periodic", "free")?;
    let matched = solve_cells(cells, [0.0; 2], &heights, "periodic", "fixed")?;
    record_heights(
        case,
        &heights,
        &[
            ("LN", &ln),
            ("PR free top", &free),
            ("matched pair", &matched),
        ],
    );
    Ok(free_checks(
        case, cells, phase, &heights, &free, &matched, &ln,
    ))
}

/// Free top: the matched configuration (the offset `φλ/2π` mod λ along each
/// axis), the matched pair's jump, no net tangential force.
fn free_checks(
    case: &str,
    cells: Cells,
    phase: [f64; 2],
    heights: &[f64],
    free: &[Outcome],
    matched: &[Outcome],
    ln: &[Outcome],
) -> Vec<Check> {
    let tol = cells.tolerances();
    let mut checks = Vec::new();
    for (i, o) in free.iter().enumerate() {
        let hu = heights[i] * 1e6;
        for (a, axis) in ["x", "y"].iter().enumerate().take(cells.dimension - 1) {
            let shift = phase[a] / std::f64::consts::TAU * WAVELENGTH;
            let off = o.lateral_offset[a].rem_euclid(WAVELENGTH);
            let quantity = match cells.dimension {
                3 => format!("H0 = {hu} um, free: offset {axis}/λ (mod 1)"),
                _ => format!("H0 = {hu} um, free: offset/λ (mod 1)"),
            };
            checks.push(Check::absolute(
                case,
                &quantity,
                off / WAVELENGTH,
                shift / WAVELENGTH,
                tol.offset,
            ));
        }
        // The free jump is the matched pair's (the surfaces fitted at other
        // positions of the meshes): relative, and against the LN jump.
        let m = matched[i].jump;
        checks.push(Check::relative(
            case,
            &format!("H0 = {hu} um, free: jump vs matched pair"),
            o.jump,
            m,
            tol.matched,
        ));
        checks.push(Check::with_error(
            case,
            &format!("H0 = {hu} um, free: |jump − matched| / LN"),
            o.jump,
            m,
            (o.jump - m).abs() / ln[i].jump,
            tol.matched_over_ln,
        ));
        let f = o.force_ratio.unwrap_or(f64::NAN);
        let quantity = match cells.dimension {
            3 => format!("H0 = {hu} um, free: max net lateral force / (pN W²)"),
            _ => format!("H0 = {hu} um, free: net lateral force / (pN W)"),
        };
        checks.push(Check::with_error(case, &quantity, f, 0.0, f.abs(), 1e-6));
    }
    checks
}
