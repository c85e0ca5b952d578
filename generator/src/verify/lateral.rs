//! Lateral boundary conditions, paper Sect. 5.3 / Fig. 11, in 2D: LN against
//! PR faces and the top face held (`top_lateral = "fixed"`) or free to slide
//! (`"free"`).
//!
//! - Symmetric cells (a sinusoid on a flat, matched sinusoids): LN and PR give
//!   the same jump.
//! - Mismatched sinusoids (equal RMS 1 μm, wavelength 10 μm, the upper one
//!   shifted by the phase π/2; constraint model, Table I, `p̄N` = 30 kPa,
//!   where a gap remains): PR gives a smaller jump than LN; with the top held
//!   the bodies slide only through the shear of the sample, so the PR gap and
//!   jump shrink as the height grows while LN stays nearly constant ("PR-BCs
//!   deliver smaller and smaller gaps ... LN-BCs ... always the same result
//!   for a unit cell of any given height"); with the top free the upper body
//!   slides to the matched configuration (offset `φλ/2π` mod λ) and the jump
//!   is the matched pair's ("the exact value of ϑc for this setup is zero"),
//!   with a vanishing net tangential contact force.
//!
//! Coarse meshes and heights 3.5, 7, 14 μm by default (about 15 s);
//! `TCGEN_LONG_TESTS=1` adds 28 μm and the paper's resolution.

use std::f64::consts::FRAC_PI_2;

use crate::Result;
use crate::homogenize::path::PathSolver;
use crate::sample::micro::net_lateral_force;
use crate::verify::homogenization::{Sample, flat, long_runs, sinusoid};
use crate::verify::{Case, Check, record_series};

/// Wavelength = width of the cell (m).
const WAVELENGTH: f64 = 1.0e-5;
/// RMS of each sinusoid (m).
const RMS: f64 = 1.0e-6;
/// Phase of the upper sinusoid in the mismatched cell (rad).
const PHASE: f64 = FRAC_PI_2;
/// The pressure of the mismatched cell (Pa): a gap remains at every height.
const PRESSURE: f64 = 3.0e4;

/// All cases of this file.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "lateral_symmetric",
            description: "Sect. 5.3: symmetric cells (sinusoid on flat, matched sinusoids): LN and PR jumps agree",
            run: symmetric,
        },
        Case {
            name: "lateral_mismatched",
            description: "Fig. 11: mismatched sinusoids: PR < LN; held top: PR jump shrinks with height, LN constant; free top: slides to the matched pair",
            run: mismatched,
        },
    ]
}

/// The solved quantities of one cell at one pressure.
#[derive(Clone, Copy, Debug)]
pub struct Outcome {
    /// Jump `|ϑ̄c|` (K).
    pub jump: f64,
    /// Mean gap (m).
    pub mean_gap: f64,
    /// Lateral offset of the upper body (m).
    pub lateral_offset: f64,
    /// Net lateral force on the upper body over `p̄N·W` (free top only).
    pub force_ratio: Option<f64>,
}

/// A cell of height `h` (m) with meshes scaled to keep the element aspect.
fn cell(upper: String, lower: String, lateral: &'static str, h: f64) -> Sample {
    let fine = long_runs();
    let (nu, nl) = if fine {
        ([32, 16], [27, 14])
    } else {
        ([16, 8], [12, 7])
    };
    let z = |n: usize| ((n as f64 * h / 7.0e-6).round() as usize).max(2);
    Sample {
        width: WAVELENGTH,
        height: h,
        lateral,
        upper,
        lower,
        elements: ([nu[0], z(nu[1])], [nl[0], z(nl[1])]),
        pressures: vec![PRESSURE],
        ..Sample::default()
    }
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
    let mut out = None;
    for &p in &case.load.pressures {
        let r = solver.solve_pressure(p)?;
        let force = net_lateral_force(&mut solver.model)?;
        out = Some(Outcome {
            jump: r.jump,
            mean_gap: r.interface.mean_gap,
            lateral_offset: r.interface.lateral_offset,
            force_ratio: force.map(|f| f / (p * case.sample.width)),
        });
    }
    Ok(out.expect("at least one pressure"))
}

/// Symmetric cells: the LN and PR jumps agree.
fn symmetric() -> Result<Vec<Check>> {
    let case = "lateral_symmetric";
    let h = 7.0e-6;
    let mut checks = Vec::new();
    for (name, upper, lower) in [
        ("sinusoid on flat", sinusoid(RMS, WAVELENGTH, 0.0), flat()),
        (
            "matched sinusoids",
            sinusoid(RMS, WAVELENGTH, 0.0),
            sinusoid(RMS, WAVELENGTH, 0.0),
        ),
    ] {
        let mut sample = cell(upper, lower, "linear", h);
        // The matched pair is in full contact at any load: a pressure that
        // leaves the sinusoid on a flat partly open.
        sample.pressures = vec![1.0e4];
        let ln = solve(&sample, "fixed")?.jump;
        sample.lateral = "periodic";
        let pr = solve(&sample, "fixed")?.jump;
        checks.push(Check::relative(
            case,
            &format!("{name}: PR jump vs LN (rel.)"),
            pr,
            ln,
            1e-6,
        ));
    }
    Ok(checks)
}

/// The mismatched cell of Fig. 11 at several heights.
fn mismatched() -> Result<Vec<Check>> {
    let case = "lateral_mismatched";
    let heights: Vec<f64> = if long_runs() {
        vec![3.5e-6, 7.0e-6, 14.0e-6, 28.0e-6]
    } else {
        vec![3.5e-6, 7.0e-6, 14.0e-6]
    };
    let upper = || sinusoid(RMS, WAVELENGTH, PHASE);
    let lower = || sinusoid(RMS, WAVELENGTH, 0.0);
    let (mut ln, mut pr, mut free, mut matched) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for &h in &heights {
        // Long runs compare the LN jump over heights (3.5–28 μm) at a
        // resolved jump: adaptively to 0.3 % (on the fixed 32-element meshes
        // the thinnest cell alone carries 2.4 % of discretization error).
        let resolved = long_runs().then_some(3e-3);
        ln.push(solve_to(
            &cell(upper(), lower(), "linear", h),
            "fixed",
            resolved,
        )?);
        pr.push(solve(&cell(upper(), lower(), "periodic", h), "fixed")?);
        free.push(solve(&cell(upper(), lower(), "periodic", h), "free")?);
        matched.push(solve(&cell(lower(), lower(), "periodic", h), "fixed")?);
    }
    let um: Vec<f64> = heights.iter().map(|h| h * 1e6).collect();
    for (name, o) in [("LN", &ln), ("PR fixed top", &pr), ("PR free top", &free)] {
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
    let mut checks = Vec::new();
    let n = heights.len();
    for i in 0..n {
        let hu = um[i];
        // PR below LN: the ratio < 0.97.
        checks.push(Check::with_error(
            case,
            &format!("H0 = {hu} um: PR/LN jump ratio"),
            pr[i].jump / ln[i].jump,
            1.0,
            pr[i].jump / ln[i].jump,
            0.97,
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
    // mean). The 3.5 μm cell (0.35 λ) is excluded: with resolved jumps
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
    // Free top: the matched configuration, the matched pair's jump, no net
    // tangential force.
    let shift = PHASE / std::f64::consts::TAU * WAVELENGTH;
    for (i, o) in free.iter().enumerate() {
        let hu = um[i];
        let off = o.lateral_offset.rem_euclid(WAVELENGTH);
        checks.push(Check::absolute(
            case,
            &format!("H0 = {hu} um, free: offset/λ (mod 1)"),
            off / WAVELENGTH,
            shift / WAVELENGTH,
            1e-4,
        ));
        // The free jump is the matched pair's (the surfaces fitted at other
        // positions of the meshes): relative, and against the LN jump.
        let m = matched[i].jump;
        checks.push(Check::relative(
            case,
            &format!("H0 = {hu} um, free: jump vs matched pair"),
            o.jump,
            m,
            2e-2,
        ));
        checks.push(Check::with_error(
            case,
            &format!("H0 = {hu} um, free: |jump − matched| / LN"),
            o.jump,
            m,
            (o.jump - m).abs() / ln[i].jump,
            1e-4,
        ));
        let f = o.force_ratio.unwrap_or(f64::NAN);
        checks.push(Check::with_error(
            case,
            &format!("H0 = {hu} um, free: net lateral force / (pN W)"),
            f,
            0.0,
            f.abs(),
            1e-6,
        ));
    }
    Ok(checks)
}
