//! Adaptive refinement at the contact edges to a target error of the jump
//! (`[discretization] target_error`, issue 11): the Sect. 5.7 sinusoid on a
//! flat (p = 2, two-phase self-consistent, constraint model) on the coarse
//! 16 × 8 mesh.

use std::path::Path;

use tcgen::geometry::Cell;
use tcgen::homogenize::adapt::{
    Marks, equation_prolongation, keep_transferred_configuration, mark_contact_edges,
    refine_bodies, surface_misfit_marks, transfer_state,
};
use tcgen::homogenize::path::{
    MISFIT_BOUND_MARGIN, PathSolver, PointResult, SELF_CONSISTENCY_ESTIMATE_SHARE,
    level_error_ratio, two_level_estimate,
};
use tcgen::sample::Case;
use tcgen::sample::case::{EdgeNeighbours, Method};
use tcgen::sample::micro::{LOWER, UPPER, case_heights};
use tcgen::solve::{Model, NonlinearProblem};

use crate::westergaard;

fn case(pressures: &str, adaptive: &str) -> Case {
    case_on([16, 8], [13, 6], pressures, adaptive)
}

fn case_on(upper: [usize; 2], lower: [usize; 2], pressures: &str, adaptive: &str) -> Case {
    let sinusoid = "kind = \"sinusoid\"\nrms = 1.0e-6\nwavelength = 1.0e-5";
    case_with(upper, lower, sinusoid, pressures, adaptive)
}

/// The case on a flat with the upper surface `surface` (its table's keys);
/// `extra`: more keys of `[discretization]`, and tables after it.
fn case_with(
    upper: [usize; 2],
    lower: [usize; 2],
    surface: &str,
    pressures: &str,
    extra: &str,
) -> Case {
    case_of_degree(2, upper, lower, surface, pressures, extra)
}

/// [`case_with`] of degree `degree`.
fn case_of_degree(
    degree: usize,
    upper: [usize; 2],
    lower: [usize; 2],
    surface: &str,
    pressures: &str,
    extra: &str,
) -> Case {
    let text = format!(
        r#"
[sample]
width = 1.0e-5
height = 7.0e-6
[surface.upper]
{surface}
[surface.lower]
kind = "flat"
[discretization]
degree = {degree}
elements_upper = {upper:?}
elements_lower = {lower:?}
{extra}
[load]
pressures = {pressures}
flux = 1.0e6
"#
    );
    Case::from_toml(&text, Path::new(".")).unwrap()
}

fn solve(c: &Case) -> Vec<PointResult> {
    tcgen::homogenize::solve_case(c, None, |_| {}).unwrap()
}

/// At 1 kPa (contact 4 % of the width, under one coarse element): the 1 %
/// target is met, the estimate is within the target, and against a deep
/// adaptive reference (target 1e-4) the true error is below 1 % and the
/// effectivity index (estimate / true error) within [0.5, 3]. Observed:
/// 18.965 K ± 0.019 (6 levels, 2388 unknowns) against 18.957 K (3834
/// unknowns): true error 0.047 %, effectivity 2.11 (with the case mesh's
/// fit kept on the refined levels, until stop 25: 18.936 K ± 0.015 against
/// 18.926 K, 0.054 %, 1.48; before the zone's edges were fitted, stop 20:
/// 19.005 K ± 0.129, true error 0.40 %, 1.70).
#[test]
fn sect57_at_one_kpa_meets_one_percent_with_a_faithful_estimate() {
    let r = solve(&case("[1.0e3]", "target_error = 0.01"));
    let deep = solve(&case("[1.0e3]", "target_error = 1.0e-4\nmax_levels = 12"));
    let (r, deep) = (&r[0], &deep[0]);
    assert!(r.converged && deep.converged);
    assert_eq!(r.error_target_met, Some(true));
    assert_eq!(deep.error_target_met, Some(true));
    assert_eq!(r.refinement_stop.as_deref(), Some("target met"));
    let est = r.jump_error.expect("an estimate");
    assert!(est <= 0.01 * r.jump, "estimate {est} K of {} K", r.jump);
    let truth = (r.jump - deep.jump).abs();
    println!(
        "jump {} ± {est} ({} unknowns, levels {:?}), reference {} ({} unknowns): true error {:.3} %, effectivity {:.2}",
        r.jump,
        r.dofs,
        r.levels,
        deep.jump,
        deep.dofs,
        100.0 * truth / deep.jump,
        est / truth
    );
    assert!(truth <= 0.01 * deep.jump, "true error {truth} K");
    assert!(
        (0.5..=3.0).contains(&(est / truth)),
        "effectivity {}",
        est / truth
    );
    // The contact fraction converges with the edge elements.
    let cf = (r.interface.contact_fraction - deep.interface.contact_fraction).abs();
    assert!(
        cf <= 0.05 * deep.interface.contact_fraction,
        "contact fraction {cf}"
    );
    // Far fewer unknowns than the uniform mesh that resolves the zone.
    assert!(r.dofs < 2500, "{} unknowns", r.dofs);
}

/// The bulk-resolution indicator (degree 1; `homogenize::recovery`): from
/// the coarse 16 × 8 mesh at 10 kPa, adaptive to 1 %, the levels also mark
/// the bulk by its recovered gradients until its estimated approach error
/// is within the target. The approach then lands within 0.5 % of degree 2
/// on 64 × 32 and the contact fraction within 1.5 % (measured: −0.21 % and
/// −0.88 %, 2835 unknowns; refined at the contact edges only, the levels
/// ended at −1.30 % and −3.2 % with 1620 unknowns, the target met, the
/// bulk's error unseen).
#[test]
fn degree_one_levels_refine_the_bulk_until_its_approach_error_meets_the_target() {
    let sinusoid = "kind = \"sinusoid\"\nrms = 1.0e-6\nwavelength = 1.0e-5";
    let r = solve(&case_of_degree(
        1,
        [16, 8],
        [14, 7],
        sinusoid,
        "[1.0e4]",
        "target_error = 0.01\nmax_levels = 8",
    ));
    let reference = solve(&case_of_degree(
        2,
        [64, 32],
        [56, 28],
        sinusoid,
        "[1.0e4]",
        "",
    ));
    let (r, reference) = (&r[0], &reference[0]);
    assert!(r.converged && reference.converged);
    assert_eq!(r.error_target_met, Some(true), "{:?}", r.refinement_stop);
    let (a, a_ref) = (r.interface.approach, reference.interface.approach);
    let (c, c_ref) = (
        r.interface.contact_fraction,
        reference.interface.contact_fraction,
    );
    println!(
        "degree 1 adaptive: approach {a:e} m, contact {c}, jump {} K ({} unknowns, levels {:?}); degree 2 on 64 x 32: {a_ref:e} m, {c_ref}, {} K",
        r.jump, r.dofs, r.levels, reference.jump
    );
    assert!(
        (a / a_ref - 1.0).abs() < 0.005,
        "approach {a} against {a_ref}"
    );
    assert!(
        (c / c_ref - 1.0).abs() < 0.015,
        "contact {c} against {c_ref}"
    );
}

/// Degree 1 at 1 kPa from 16 × 8 / 13 × 7, adaptive to 1 %: its sixth level's
/// slave elements are small enough that a breakpoint of the segment-based
/// integration lies below the spacing of doubles, where the bisection
/// recursed without end (a stack overflow until stop 101). Measured: 18.892 K
/// ± 0.42 %, 3771 unknowns, six levels.
#[test]
fn degree_one_levels_at_one_kpa_reach_the_target() {
    let sinusoid = "kind = \"sinusoid\"\nrms = 1.0e-6\nwavelength = 1.0e-5";
    let r = solve(&case_of_degree(
        1,
        [16, 8],
        [13, 7],
        sinusoid,
        "[1.0e3]",
        "target_error = 0.01\nmax_levels = 8",
    ));
    let r = &r[0];
    assert!(r.converged);
    assert_eq!(r.error_target_met, Some(true), "{:?}", r.refinement_stop);
    assert!(r.levels.iter().all(|&l| l >= 5), "{:?}", r.levels);
}

/// The adaptive limit is that of the surface, not of the case mesh: the
/// refined levels resolve the rough face on the exact surface
/// (`Bodies::resolved`), so deep adaptive solves from the 16 × 8 and the
/// 32 × 16 mesh agree. Observed at 1 kPa: 18.9573 and 18.9576 K (1.6e-5
/// apart); when the refined levels kept the case mesh's fit, 18.926 and
/// 18.955 K (1.5e-3 apart: the 16 × 8 fit's error).
#[test]
fn the_adaptive_limit_does_not_depend_on_the_case_mesh() {
    let deep = "target_error = 1.0e-4\nmax_levels = 12";
    let a = solve(&case_on([16, 8], [13, 7], "[1.0e3]", deep));
    let b = solve(&case_on([32, 16], [27, 14], "[1.0e3]", deep));
    let (a, b) = (&a[0], &b[0]);
    assert!(a.converged && b.converged);
    let gap = (a.jump - b.jump).abs() / b.jump;
    println!(
        "from 16 x 8: {} K ({} unknowns); from 32 x 16: {} K ({} unknowns); {gap:.2e} apart",
        a.jump, a.dofs, b.jump, b.dofs
    );
    assert!(gap < 2.0e-4, "{} vs {} K", a.jump, b.jump);
    // The approach counts from the exact surfaces' first touch on both.
    let (ua, ub) = (a.interface.approach, b.interface.approach);
    println!("approach {ua:e} and {ub:e} m");
    assert!((ua - ub).abs() < 1.0e-4 * ub, "approach {ua:e} vs {ub:e} m");
}

/// A point that cannot reach its target keeps its best jump with its
/// estimate and is flagged (here: `max_dofs` stops after one level).
#[test]
fn a_point_stopped_by_max_dofs_is_flagged_with_its_estimate() {
    let r = solve(&case("[1.0e3]", "target_error = 0.01\nmax_dofs = 1100"));
    let r = &r[0];
    assert!(r.converged);
    assert_eq!(r.error_target_met, Some(false));
    assert_eq!(r.levels, [1, 1]);
    let est = r.jump_error.expect("the one-level estimate");
    assert!(est > 0.01 * r.jump, "{est}");
    // The reason names the limit and the mesh it would have needed.
    let stop = r.refinement_stop.as_deref().unwrap_or_default();
    assert!(stop.starts_with("max_dofs: level 2 would have "), "{stop}");
    // So does a point stopped by max_levels.
    let one = solve(&case("[1.0e3]", "target_error = 0.01\nmax_levels = 1"));
    assert_eq!(
        (one[0].error_target_met, one[0].refinement_stop.as_deref()),
        (Some(false), Some("max_levels"))
    );
    // The level before the one refused stays the last, as if it were the
    // last allowed: the same jump and iterations.
    assert_eq!(
        (r.jump, r.newton_iterations),
        (one[0].jump, one[0].newton_iterations)
    );
    // A fixed mesh reports no estimate.
    let fixed = solve(&case("[1.0e3]", ""));
    assert_eq!(
        (
            fixed[0].jump_error,
            fixed[0].error_target_met,
            fixed[0].refinement_stop.as_deref()
        ),
        (None, None, None)
    );
    assert_eq!(fixed[0].levels, [0, 0]);
}

/// The state carries over exactly: on bodies refined nowhere the carried
/// state is the solved one, and the residual stays at round-off.
#[test]
fn the_state_carries_over_to_refined_bodies() {
    let c = case("[1.0e4]", "");
    let mut s = PathSolver::new(&c).unwrap();
    s.solve_pressure(1.0e4).unwrap();
    let residual = |m: &mut tcgen::solve::Model| {
        m.set_path([1.0e4, 0.0], [1.0e4, 0.0]);
        NonlinearProblem::set_load(m, 1.0);
        NonlinearProblem::prepare(m).unwrap();
        let mut r = vec![0.0; m.n_eq()];
        m.assemble(None, &mut r).unwrap();
        r.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    };
    let coarse = residual(&mut s.model);
    let bodies = refine_bodies(&s.bodies, &Marks::default());
    let mut f = PathSolver::with_bodies(&c, s.geometry.clone(), bodies).unwrap();
    transfer_state(&s.model, &mut f.model);
    let theta = c.load.contact_temperature;
    f.model.set_frozen_temperature(0, theta);
    f.model.set_frozen_temperature(1, theta);
    assert_eq!(f.model.state, s.model.state);
    let fine = residual(&mut f.model);
    assert!(coarse < 1e-12 && fine < 1e-12, "{coarse} {fine}");
}

/// The equation prolongation (the operator of a two-level preconditioner)
/// is what the state transfer does, on equation vectors: on bodies refined
/// at the contact edges, the prolongated coarse values (displacements, a
/// tied group read at one node, contact multipliers) are the transferred
/// fine ones. At 300 kPa the contact spans the periodic seam, whose copies'
/// multipliers are read at their nodes'.
#[test]
fn the_equation_prolongation_carries_the_state_over() {
    let c = case("[3.0e5]", "");
    let mut s = PathSolver::new(&c).unwrap();
    s.solve_pressure(3.0e5).unwrap();
    s.model.prepare_contact().unwrap();
    let marks = mark_contact_edges(&s.model, UPPER, &Default::default(), true).unwrap();
    assert!(!marks.upper.is_empty() && !marks.lower.is_empty());
    let bodies = refine_bodies(&s.bodies, &marks);
    let mut f = PathSolver::with_bodies(&c, s.geometry.clone(), bodies).unwrap();
    transfer_state(&s.model, &mut f.model);
    // Every prescribed value held exactly (a re-solve at the same loads is
    // then one at a constant load).
    assert!(f.model.dofs().prescribed_in(&f.model.state));
    let values = |m: &Model| -> Vec<f64> {
        let nf = m.dim + 1;
        let mut v = vec![f64::NAN; m.n_eq()];
        for node in 0..m.state.len() / nf {
            for field in 0..nf {
                if let Some(e) = m.dofs().eq(node, field)
                    && v[e].is_nan()
                {
                    v[e] = m.state[node * nf + field];
                }
            }
        }
        let contact = m.contact.as_ref().expect("a contact interface");
        let first = m.multiplier_equations().0.expect("mechanical multipliers");
        v[first..first + contact.n_slave()].copy_from_slice(&contact.lambda_n);
        v
    };
    let (coarse, fine) = (values(&s.model), values(&f.model));
    assert!(fine.len() > coarse.len() && fine.iter().all(|v| v.is_finite()));
    let mut prolongated = vec![0.0; fine.len()];
    for (e, k, v) in equation_prolongation(&s.model, &f.model) {
        prolongated[e] += v * coarse[k];
    }
    let first = f.model.multiplier_equations().0.unwrap();
    let scale = |r: std::ops::Range<usize>| fine[r].iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let (u, lambda) = (scale(0..first), scale(first..fine.len()));
    assert!(u > 0.0 && lambda > 0.0, "{u} {lambda}");
    for (e, (p, v)) in prolongated.iter().zip(&fine).enumerate() {
        let s = if e < first { u } else { lambda };
        assert!((p - v).abs() <= 1e-12 * s, "equation {e}: {p} against {v}");
    }
}

/// The two-level estimate in 2D: `max(d_k, d_{k−1}/2, d_{k−2}/4)`.
#[test]
fn the_two_level_estimate_guards_a_lucky_difference() {
    let half = level_error_ratio(2);
    assert_eq!(half, 0.5);
    assert_eq!(two_level_estimate(0.1, &[], half), 0.1);
    assert_eq!(two_level_estimate(0.1, &[0.2], half), 0.1);
    assert_eq!(two_level_estimate(0.01, &[0.2], half), 0.1);
    assert_eq!(two_level_estimate(0.01, &[0.8, 0.02, 0.01], half), 0.01);
    assert_eq!(two_level_estimate(0.001, &[0.8, 0.4, 0.002], half), 0.1);
}

/// In 3D the errors fall by `ρ = 2^(−3/2)` per level: a geometric sequence
/// of jumps `J_k = J + e ρ^k` gets its exact error back, and a lucky small
/// difference is guarded by the older ones at `ρ` and `ρ²`.
#[test]
fn the_3d_estimate_assumes_order_three_halves() {
    let rho = level_error_ratio(3);
    assert!((rho - 2f64.powf(-1.5)).abs() < 1e-16);
    let (exact, e0) = (3.0, 1.0);
    let jumps: Vec<f64> = (0..5).map(|k| exact + e0 * rho.powi(k)).collect();
    let d: Vec<f64> = jumps.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    for k in 1..d.len() {
        let e = two_level_estimate(d[k], &d[..k], rho);
        let truth = jumps[k + 1] - exact;
        assert!(
            (e / truth - 1.0).abs() < 1e-12,
            "level {k}: {e} against {truth}"
        );
    }
    let lucky = two_level_estimate(1e-6, &[0.8, 0.4], rho);
    assert_eq!(lucky, 0.4 * rho * rho / (1.0 - rho));
}

/// Inside a wide contact the interface is refined too
/// (`INTERIOR_LEVEL_RATIO`): Westergaard at 0.9 `p*`, adaptive to 1 % from
/// 16 × 8, against a deep solve (1e-4) from 64 × 32. Refined at the edges
/// only, the interior kept the 16-element error, which no difference
/// between levels showed: 0.72 % (0.33409 against 0.33652 K, the rule off
/// in both); observed now 0.024 % (0.33669 against 0.33661 K).
#[test]
fn the_contact_interior_is_refined_with_the_edges() {
    let r = solve(&westergaard::case(
        &[0.9],
        [16, 8],
        [14, 7],
        "target_error = 0.01",
        "",
    ));
    let deep = solve(&westergaard::case(
        &[0.9],
        [64, 32],
        [56, 28],
        "target_error = 1.0e-4\nmax_levels = 12",
        "",
    ));
    let (r, deep) = (&r[0], &deep[0]);
    assert!(r.converged && deep.converged);
    let error = (r.jump - deep.jump).abs() / deep.jump;
    println!(
        "jump {} ± {:?} ({} unknowns), reference {} ± {:?}: {:.3} %",
        r.jump,
        r.jump_error,
        r.dofs,
        deep.jump,
        deep.jump_error,
        100.0 * error
    );
    assert!(error < 2.0e-3, "error {error}");
}

/// Westergaard's wavy contact in the small-strain limit (`A/λ = 5e-4`,
/// `H = λ`, PR, constant conductivity, plain two-phase) adaptive from
/// 16 × 8 at 5–90 % of `p*`: the contact fraction against `2a/λ` and the
/// jump against the closed-form strips of Westergaard's width between
/// layers of the compressed heights (`WavySample::strip_conductance`).
/// Observed at target 0.01: contact within 0.13 %, jump within 0.39 % (the
/// issue's 1 % on both; before the zone's edges were fitted, stop 20:
/// 0.96 % and 1.18 %); at 0.003: 0.24 % and 0.43 % (the model's own
/// distance from the closed forms' assumptions — finite strain, a non-flat
/// surface — is 0.2–0.5 % in the jump).
#[test]
fn westergaard_adaptive_meets_the_closed_forms() {
    use tcgen::analytical::westergaard::contact_half_width;
    use tcgen::verify::contact::wavy::WESTERGAARD_LEVELS;
    let s = westergaard::sample();
    let p_star = s.p_star();
    for (target, tol_contact, tol_jump) in [(0.01, 0.01, 0.01), (0.003, 0.005, 0.01)] {
        let c = westergaard::case(
            &WESTERGAARD_LEVELS,
            [16, 8],
            [14, 7],
            &format!("target_error = {target:e}"),
            "",
        );
        let (mut worst_cf, mut worst_jump) = (0.0f64, 0.0f64);
        for r in solve(&c) {
            assert!(
                r.converged && r.error_target_met == Some(true),
                "{:?}",
                r.status
            );
            let a = contact_half_width(s.e_star(), s.amplitude, s.wavelength, r.pressure);
            let cf = 2.0 * a / s.wavelength;
            let jump = s.flux / s.strip_conductance(r.pressure, a).unwrap();
            let (ecf, ej) = (
                (r.interface.contact_fraction - cf) / cf,
                (r.jump - jump) / jump,
            );
            println!(
                "target {target}: p/p* = {:.2}: contact {:.5} vs {cf:.5} ({:+.2} %), jump {:.5} ± {:.4} vs {jump:.5} K ({:+.2} %), {} unknowns",
                r.pressure / p_star,
                r.interface.contact_fraction,
                100.0 * ecf,
                r.jump,
                r.jump_error.unwrap_or(f64::NAN),
                100.0 * ej,
                r.dofs
            );
            worst_cf = worst_cf.max(ecf.abs());
            worst_jump = worst_jump.max(ej.abs());
        }
        assert!(
            worst_cf <= tol_contact,
            "target {target}: contact fraction {worst_cf}"
        );
        assert!(worst_jump <= tol_jump, "target {target}: jump {worst_jump}");
    }
}

/// The state carried over to refined 3D bodies holds every prescribed value
/// exactly: the prolongation leaves round-off on them (5.6e-22 on a held
/// zero of the 3D dent of docs/adaptivity.md), which made a level's
/// re-solve at the same loads a varying load, cut back on failure eight
/// times to the same non-finite residual. The egg box of
/// `tables/egg_box_on_flat.toml`.
fn egg_box_path() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables/egg_box_on_flat.toml")
}

/// The egg box of `tables/egg_box_on_flat.toml` on 4 × 4 × 2 / 3 × 3 × 2,
/// plain two-phase, at 30 kPa.
fn small_egg_box() -> Case {
    let mut c = Case::read(&egg_box_path()).unwrap();
    let d = &mut c.discretization;
    d.elements_upper = [4, 4, 2].into();
    d.elements_lower = [3, 3, 2].into();
    c.homogenization.method = Method::TwoPhase;
    c.load.pressures = vec![3.0e4];
    c
}

/// `tables/egg_box_on_flat.toml` on 4 × 4 × 2 / 3 × 3 × 2 at 30 kPa,
/// refined twice at its contact edges.
#[test]
fn a_state_carried_over_in_3d_holds_its_prescribed_values() {
    let c = small_egg_box();
    let mut s = PathSolver::new(&c).unwrap();
    s.solve_pressure(3.0e4).unwrap();
    let mut model = s.model;
    let mut bodies = s.bodies;
    for level in 1..=2 {
        model.prepare_contact().unwrap();
        let marks = mark_contact_edges(&model, UPPER, &Default::default(), true).unwrap();
        bodies = refine_bodies(&bodies, &marks);
        let mut f = PathSolver::with_bodies(&c, s.geometry.clone(), bodies.clone()).unwrap();
        transfer_state(&model, &mut f.model);
        assert!(
            f.model.dofs().prescribed_in(&f.model.state),
            "level {level}: a prescribed value not held"
        );
        model = f.model;
    }
}

/// `[discretization] edge_neighbours = false` marks the contact-edge
/// elements without their neighbours: on the 3D egg box of
/// `tables/egg_box_on_flat.toml` (4 × 4 × 2 / 3 × 3 × 2 at 30 kPa) a strict
/// subset of the cells marked with them, on both bodies. The key is read
/// from a case (`true`, `false` or a number of levels); absent, it is
/// `true` in 2D and at p = 1, the first 2 levels in 3D at p ≥ 2 (since stop
/// 98; `false` in stops 85–97), and the resolved configuration (the tables'
/// hash) writes it unless the neighbours are marked on every level by
/// default, so that the tables built before the key existed keep their
/// hashes where their marks did not change.
#[test]
fn marks_without_the_edge_neighbours_are_a_strict_subset() {
    use tcgen::sweep::config::resolved_case;
    let c = small_egg_box();
    let mut s = PathSolver::new(&c).unwrap();
    s.solve_pressure(3.0e4).unwrap();
    assert_eq!(c.discretization.edge_neighbours, None);
    assert_eq!(
        c.discretization.edge_neighbours_in(3),
        EdgeNeighbours::FirstLevels(2)
    );
    assert_eq!(
        c.discretization.edge_neighbours_in(2),
        EdgeNeighbours::Every(true)
    );
    s.model.prepare_contact().unwrap();
    let with = mark_contact_edges(&s.model, UPPER, &Default::default(), true).unwrap();
    let without = mark_contact_edges(&s.model, UPPER, &Default::default(), false).unwrap();
    let set = |cells: &[_]| {
        cells
            .iter()
            .copied()
            .collect::<std::collections::BTreeSet<_>>()
    };
    for (a, b) in [(&without.upper, &with.upper), (&without.lower, &with.lower)] {
        let (a, b) = (set(a), set(b));
        assert!(!a.is_empty());
        assert!(a.is_subset(&b));
        assert!(a.len() < b.len(), "{} against {}", a.len(), b.len());
    }
    let path = egg_box_path();
    let read = |key: &str, dimension: usize, degree: usize| {
        let text = std::fs::read_to_string(&path)
            .unwrap()
            .replace("[discretization]", &format!("[discretization]\n{key}"))
            .replace("dimension = 3", &format!("dimension = {dimension}"))
            .replace("degree = 2", &format!("degree = {degree}"));
        let text = if dimension == 2 {
            // The 2D sample of the same surfaces: a profile, two counts.
            text.replace("pattern = \"egg-box\"", "")
                .replace("[8, 8, 4]", "[8, 4]")
                .replace("[7, 7, 4]", "[7, 4]")
        } else {
            text
        };
        Case::from_toml(&text, path.parent().unwrap()).unwrap()
    };
    let written = |c: &Case| {
        resolved_case(c)
            .unwrap()
            .lines()
            .find(|l| l.starts_with("edge_neighbours"))
            .map(str::to_string)
    };
    let (t, f) = ("edge_neighbours = true", "edge_neighbours = false");
    let (two, three) = ("edge_neighbours = 2", "edge_neighbours = 3");
    let (every, none) = (EdgeNeighbours::Every(true), EdgeNeighbours::Every(false));
    let first = EdgeNeighbours::FirstLevels;
    for (key, dimension, degree, value, line) in [
        ("", 3, 2, first(2), Some(two)),
        (t, 3, 2, every, Some(t)),
        (f, 3, 2, none, Some(f)),
        (three, 3, 2, first(3), Some(three)),
        ("", 3, 1, every, None),
        (t, 3, 1, every, None),
        (f, 3, 1, none, Some(f)),
        (two, 3, 1, first(2), Some(two)),
        ("", 2, 2, every, None),
        (t, 2, 2, every, None),
        (f, 2, 2, none, Some(f)),
    ] {
        let c = read(key, dimension, degree);
        assert_eq!(c.dimension(), dimension);
        assert_eq!(c.discretization.degree, degree);
        let d = &c.discretization;
        assert_eq!(d.edge_neighbours_in(dimension), value, "{key}");
        assert_eq!(
            written(&c).as_deref(),
            line,
            "{key} in {dimension}D, p = {degree}"
        );
    }
}

/// The 3D thermal phase on the contact zone (`thermal_zone = true`) solves
/// on the first adaptive level of the egg box of `tables/egg_box_on_flat.toml`
/// at 100 kPa (6 × 6 × 2 / 5 × 5 × 2, 4 × 4 points per slave face element,
/// plain two-phase): the zone's fitted
/// edges reach past the supports of the nodes in contact, and before
/// `ZONE_MIN_SHARE` the nodes there carried multipliers on test functions
/// of 0.1–1e-7 of their areas, 22 near-zero pivots, and the level failed
/// (load stepping stalled); now every node with a multiplier covers at
/// least that share and the level converges (2.68 K, contact 0.39).
#[test]
fn the_3d_contact_zone_solves_on_a_refined_egg_box() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables/egg_box_on_flat.toml");
    let mut c = Case::read(&path).unwrap();
    assert_eq!(c.sample.dimension, 3);
    assert_eq!(c.contact.interface_points, 4);
    let d = &mut c.discretization;
    d.elements_upper = [6, 6, 2].into();
    d.elements_lower = [5, 5, 2].into();
    d.target_error = Some(1.0e-4);
    d.max_levels = 1;
    c.contact.thermal_zone = Some(true);
    c.homogenization.method = Method::TwoPhase;
    c.load.pressures = vec![1.0e5];
    let r = &solve(&c)[0];
    println!(
        "zone, level {:?}: jump {:.5} K, contact {:.4}, stop {:?}",
        r.levels, r.jump, r.interface.contact_fraction, r.refinement_stop
    );
    assert!(r.converged, "{:?}", r.status);
    assert_eq!(r.levels, [1, 1], "{:?}", r.refinement_stop);
    assert_eq!(r.refinement_stop.as_deref(), Some("max_levels"));
    assert!(r.jump_error.is_some());
    assert!(
        r.jump > 2.0 && r.jump < 4.0,
        "jump {} K (level 1 of the catalogue's sequence: 2.75 K)",
        r.jump
    );
}

/// On the adaptive levels the self-consistency iterations stop once their
/// change, or their output's distance to the fixed point, is below 1 % of
/// the plain jump's estimate, whatever the case's tolerance (here 1e-12),
/// and the reported estimate carries the distance reached:
/// `E = E_plain |J / J_plain| + max(tolerance |J|, distance)`, with the
/// distance at most `0.01 E_plain` (the map's slope is small), the levels
/// being those of the plain run (they compare plain jumps). Until stop 99
/// the share itself was added; here the iterations end far below it.
#[test]
fn self_consistency_stops_at_a_share_of_the_estimate_and_reports_it() {
    let adaptive = "target_error = 0.01\n[homogenization]\ntolerance = 1.0e-12";
    let sc = solve(&case("[1.0e4]", adaptive));
    let mut plain_case = case("[1.0e4]", adaptive);
    plain_case.homogenization.method = Method::TwoPhase;
    let plain = solve(&plain_case);
    let (sc, plain) = (&sc[0], &plain[0]);
    assert!(sc.converged && plain.converged, "{:?}", sc.status);
    assert_eq!((sc.dofs, &sc.levels), (plain.dofs, &plain.levels));
    let e_plain = plain.jump_error.expect("a plain estimate");
    let e = sc.jump_error.expect("an estimate");
    let bound = e - e_plain * (sc.jump / plain.jump).abs();
    println!(
        "jump {} (plain {}), estimate {e} (plain {e_plain}), the fixed point's bound {bound:.3e} K, {} self-consistency iterations",
        sc.jump, plain.jump, sc.self_consistency_iterations
    );
    assert!(
        bound >= 1e-12 * sc.jump.abs() * (1.0 - 1e-9)
            && bound <= 0.5 * SELF_CONSISTENCY_ESTIMATE_SHARE * e_plain,
        "the fixed point's bound {bound} K against the tolerance's {} K and the share's {} K",
        1e-12 * sc.jump.abs(),
        SELF_CONSISTENCY_ESTIMATE_SHARE * e_plain
    );
    assert!(
        sc.self_consistency_iterations <= 4,
        "{} iterations",
        sc.self_consistency_iterations
    );
    // The contact fraction is measured once, on the last mechanical phase of
    // the iterations (not in their thermal phases, nor in the plain levels):
    // a fraction, near the plain method's on the same mesh (the slave's
    // thermal expansion moves it a little).
    let (f, f_plain) = (
        sc.interface.contact_fraction,
        plain.interface.contact_fraction,
    );
    println!("contact fraction {f} (plain {f_plain})");
    assert!(f > 0.0 && f < 1.0, "contact fraction {f}");
    assert!(
        (f - f_plain).abs() <= 0.02 * f_plain,
        "contact fraction {f} against {f_plain}"
    );
}

/// Where the plain jump's estimate meets the target but the self-consistent
/// jump's does not (it adds the bound at which the iterations stopped, here
/// the case's loose tolerance), the refinement goes on while another level
/// can lower it: at 30 kPa the plain estimate of level 4 is 0.44 %, below
/// 1 %, so that with the tolerance 1e-6 the point stops there; with 0.008
/// the self-consistent estimate is 1.24 % on level 4, and the point meets
/// the target on a finer level. With a tolerance above the target no level
/// can meet it: the point stops where the plain jump met it, flagged.
#[test]
fn a_self_consistent_estimate_above_the_target_refines_further() {
    let adaptive = |tolerance: &str, discretization: &str| {
        let extra = format!(
            "target_error = 0.01\n{discretization}\n[homogenization]\ntolerance = {tolerance}"
        );
        case("[3.0e4]", &extra)
    };
    let with = |tolerance: &str, discretization: &str| {
        solve(&adaptive(tolerance, discretization)).remove(0)
    };
    let tight = with("1.0e-6", "");
    let (reports, observer) = level_recorder();
    let loose = tcgen::homogenize::solve_case_observed(
        &adaptive("0.008", ""),
        None,
        |_| {},
        Some(observer),
    )
    .unwrap()
    .remove(0);
    let beyond = with("0.02", "");
    // Where the next level exceeds `max_dofs` (level 5 has 2412 unknowns),
    // the level whose plain jump met the target stays, with its
    // self-consistent results, and is flagged.
    let bounded = with("0.008", "max_dofs = 2400");
    for r in [&tight, &loose, &beyond, &bounded] {
        println!(
            "levels {:?}, {} unknowns: jump {:.6} K, estimate {:.3} %, met {:?}, stop {:?}",
            r.levels,
            r.dofs,
            r.jump,
            100.0 * r.jump_error.unwrap_or(f64::NAN) / r.jump,
            r.error_target_met,
            r.refinement_stop
        );
        assert!(r.converged, "{:?}", r.status);
    }
    let relative = |r: &PointResult| r.jump_error.expect("an estimate") / r.jump.abs();
    assert_eq!(tight.error_target_met, Some(true));
    assert!(relative(&tight) <= 0.01);
    // The tight tolerance's level has a plain estimate that a tolerance of
    // 0.008 pushes above the target.
    assert!(relative(&tight) > 0.002, "{}", relative(&tight));
    assert_eq!(
        loose.error_target_met,
        Some(true),
        "{:?}",
        loose.refinement_stop
    );
    assert_eq!(loose.refinement_stop.as_deref(), Some("target met"));
    // The level whose plain jump met the target says why the refinement
    // went on.
    let reports = reports.lock().unwrap().clone();
    let kept = reports
        .iter()
        .find(|l| l.level == tight.levels[0])
        .expect("the tight run's last level");
    let why = kept.goes_on.as_deref().unwrap_or("");
    assert!(
        why.starts_with(&format!(
            "level {}: the plain jump's estimate met the target; the self-consistent jump's is",
            tight.levels[0]
        )) && kept.stop.is_none(),
        "{kept}"
    );
    assert!(relative(&loose) <= 0.01, "{}", relative(&loose));
    assert!(
        loose.levels.iter().max() > tight.levels.iter().max(),
        "levels {:?} against {:?}",
        loose.levels,
        tight.levels
    );
    // The two jumps agree within the loose run's estimate.
    assert!(
        (loose.jump - tight.jump).abs() <= loose.jump_error.unwrap(),
        "{} against {}",
        loose.jump,
        tight.jump
    );
    assert_eq!(beyond.error_target_met, Some(false));
    assert_eq!((beyond.dofs, &beyond.levels), (tight.dofs, &tight.levels));
    let stop = beyond.refinement_stop.as_deref().unwrap_or("");
    assert!(
        stop.starts_with("the plain jump's estimate met the target; the self-consistent jump's is"),
        "{stop}"
    );
    assert_eq!(bounded.error_target_met, Some(false));
    assert_eq!((bounded.dofs, &bounded.levels), (tight.dofs, &tight.levels));
    assert!(relative(&bounded) > 0.01, "{}", relative(&bounded));
    let stop = bounded.refinement_stop.as_deref().unwrap_or("");
    assert!(
        stop.starts_with(&format!(
            "max_dofs: level {} would have ",
            tight.levels[0] + 1
        )) && stop.contains(&format!(
            "(level {}: the plain jump's estimate met the target; the self-consistent jump's is",
            tight.levels[0]
        )),
        "{stop}"
    );
}

/// The relative difference of two converged results' jumps (the secant
/// update's against the plain one's).
fn converged_jump_difference(s: &PointResult, p: &PointResult) -> f64 {
    assert!(
        s.converged && p.converged,
        "{:?} / {:?}",
        s.status,
        p.status
    );
    ((s.jump - p.jump) / p.jump).abs()
}

/// The first self-consistency iteration of the secant update solves its
/// mechanical phase with one Newton increment only
/// ([`tcgen::homogenize::path::PREDICTOR_INCREMENTS`]), and the iterations
/// end on a mechanical phase solved to convergence:
/// - where the predictor's output meets the tolerance (here 0.5, at the
///   path's first pressure, where the first input is the plain jump for
///   both updates), the phase is solved to convergence at the same input:
///   the jump is then the plain iteration's first output to round-off (the
///   predictor's own output is 1e-4 K away, 2e-5 of the jump, on the 3D
///   egg box at 72 kPa);
/// - at a tight tolerance (1e-10) the secant's jumps along a path are the
///   plain iteration's to 1e-8 (the mechanical phases converge to 1e-10 of
///   their residuals), in fewer iterations.
#[test]
fn self_consistency_ends_on_a_converged_mechanical_phase() {
    let loose = "[homogenization]\ntolerance = 0.5";
    let secant = solve(&case("[1.0e4]", loose));
    let plain = solve(&case(
        "[1.0e4]",
        &format!("{loose}\nacceleration = \"none\""),
    ));
    let (s, p) = (&secant[0], &plain[0]);
    assert_eq!(
        (s.self_consistency_iterations, p.self_consistency_iterations),
        (2, 2)
    );
    let difference = ((s.jump - p.jump) / p.jump).abs();
    println!(
        "first iteration: {} K against {} K: {difference:.1e}",
        s.jump, p.jump
    );
    assert!(difference <= 1e-10, "{difference:e}");
    let tight = "[homogenization]\ntolerance = 1.0e-10";
    let pressures = "[3.0e2, 1.0e4, 1.0e5]";
    let secant = solve(&case(pressures, tight));
    let plain = solve(&case(
        pressures,
        &format!("{tight}\nacceleration = \"none\"\nmax_iterations = 60"),
    ));
    for (s, p) in secant.iter().zip(&plain) {
        let difference = converged_jump_difference(s, p);
        println!(
            "{} Pa: jump {} K ({} iterations) against {} K ({}): {difference:.1e}",
            s.pressure,
            s.jump,
            s.self_consistency_iterations,
            p.jump,
            p.self_consistency_iterations
        );
        assert!(difference <= 1e-8, "{difference:e}");
        assert!(s.self_consistency_iterations < p.self_consistency_iterations);
    }
}

/// Where the predictor's state has converged already (its one Newton
/// increment meets Newton's tolerance, here a loose 1e-4) and its output
/// meets the self-consistency tolerance, the iterations end with that output:
/// it is `F` of its input, the plain iteration's first output to round-off,
/// and no second thermal phase is solved, so the secant update takes as many
/// Newton iterations as the plain one (one thermal phase more before stop 59).
#[test]
fn a_converged_predictor_ends_the_iterations_with_its_own_output() {
    let loose = |update: &str| {
        format!(
            "[homogenization]\ntolerance = 0.5\nacceleration = \"{update}\"\n\
             [solver.newton]\nrelative_tolerance = 1.0e-4"
        )
    };
    let secant = solve(&case("[1.0e4]", &loose("secant")));
    let plain = solve(&case("[1.0e4]", &loose("none")));
    let (s, p) = (&secant[0], &plain[0]);
    let difference = converged_jump_difference(s, p);
    println!(
        "jump {} K against {} K: {difference:.1e}; Newton iterations {} against {}",
        s.jump, p.jump, s.newton_iterations, p.newton_iterations
    );
    assert_eq!(
        (s.self_consistency_iterations, p.self_consistency_iterations),
        (2, 2)
    );
    assert!(difference <= 1e-10, "{difference:e}");
    assert_eq!(s.newton_iterations, p.newton_iterations);
}

/// A profile that a coarse case mesh cannot resolve: a gentle sinusoid
/// (amplitude 0.283 μm, period W = 10 μm) with a narrow asperity (a
/// Gaussian dent of depth 0.35 μm and width σ = 0.2 μm at x = 2.5 μm) that
/// reaches below its trough, so that the exact surfaces first touch at the
/// asperity. The case mesh's fit (16 elements of 0.625 μm) keeps about a
/// tenth of it. Written as a CSV (`kind = "profile"`) into a directory of
/// its own, removed when the returned guard drops; returns it with the
/// surface table.
fn asperity_profile(name: &str, depth: f64) -> (tempfile::TempDir, String) {
    let dir = tempfile::Builder::new()
        .prefix(&format!("tcgen-{name}-"))
        .tempdir()
        .unwrap();
    let file = dir.path().join("profile.csv");
    let (w, n) = (1.0e-5, 1000);
    let text: String = (0..n)
        .map(|i| {
            let x = i as f64 * w / n as f64;
            let z = 2.83e-7 * (std::f64::consts::TAU * x / w).cos()
                - depth * (-((x - ASPERITY_X) / ASPERITY_WIDTH).powi(2)).exp();
            format!("{x:e},{z:e}\n")
        })
        .collect();
    std::fs::write(&file, text).unwrap();
    let table = format!("kind = \"profile\"\nfile = \"{}\"", file.display());
    (dir, table)
}

const ASPERITY_X: f64 = 2.5e-6;
const ASPERITY_WIDTH: f64 = 2.0e-7;

fn asperity_case(
    upper: [usize; 2],
    lower: [usize; 2],
    surface: &str,
    pressures: &str,
    adaptive: &str,
) -> Case {
    let extra = format!("{adaptive}\n[homogenization]\nmethod = \"two-phase\"");
    case_with(upper, lower, surface, pressures, &extra)
}

/// The slave face elements that the surface-resolution indicator marks on
/// the case mesh of `c` solved at 1 kPa, as their corners' lateral
/// coordinates `(lower, upper)` (m).
fn misfit_marks_at_one_kpa(c: &Case) -> Vec<([f64; 3], [f64; 3])> {
    let mut s = PathSolver::new(c).unwrap();
    s.solve_pressure(1.0e3).unwrap();
    s.model.prepare_contact().unwrap();
    let heights = case_heights(c).unwrap();
    let bound =
        MISFIT_BOUND_MARGIN * (s.geometry.fit_upper.max_error() + s.geometry.fit_lower.max_error());
    let marks = surface_misfit_marks(&s.model, UPPER, &heights, s.geometry.g0, bound).unwrap();
    let face = s.model.contact.as_ref().unwrap().slave_face();
    let (l, dims) = (s.model.scales.length, face.param_dim());
    marks
        .iter()
        .map(|&e| {
            let el = &face.elements()[e];
            let corner = |xi: &[f64; 3]| face.point(&xi[..dims]).map(|v| v * l);
            (corner(&el.lower), corner(&el.upper))
        })
        .collect()
}

/// The surface-resolution indicator (`adapt::surface_misfit_marks`) marks
/// the slave face elements out of contact whose gap is below the faces'
/// height error: on the coarse case mesh at 1 kPa, those over the narrow
/// asperity that its fit flattens (the contact sits at the sinusoid's
/// trough there), and none on the same sinusoid without the asperity.
#[test]
fn the_surface_indicator_marks_an_asperity_the_fit_flattens() {
    let marked = |depth: f64| -> Vec<[f64; 2]> {
        let (_dir, surface) = asperity_profile(&format!("indicator-{depth}"), depth);
        let c = asperity_case([16, 8], [14, 7], &surface, "[1.0e3]", "");
        misfit_marks_at_one_kpa(&c)
            .iter()
            .map(|(a, b)| [a[0], b[0]])
            .collect()
    };
    let with = marked(3.5e-7);
    assert!(!with.is_empty(), "the asperity is not marked");
    for [a, b] in &with {
        let (a, b) = (a.min(*b), a.max(*b));
        assert!(
            b > ASPERITY_X - 2.0 * ASPERITY_WIDTH && a < ASPERITY_X + 2.0 * ASPERITY_WIDTH,
            "an element [{a:e}, {b:e}] m away from the asperity"
        );
    }
    assert!(marked(0.0).is_empty());
}

/// Found and solved: adaptive to 1 % from the coarse case mesh, the jump
/// with the asperity against the same case on a case mesh 4× finer (which
/// resolves it from the start). At 1 kPa the asperity carries the whole
/// load (contact fraction 0.7 %); without the indicator the levels refined
/// the trough's spot only and met the target at 12.89 K ± 0.02 K, 64 % below
/// the finer mesh's 35.49 K. The levels that bring the asperity into contact
/// start from a carried-over state that overlaps it by most of its depth,
/// whose first increments invert elements: they are solved again from the
/// configuration the coarser level solved, or from rest should that fail too
/// (without either, the first such level failed and each point kept the level
/// before it, flagged). Observed (stop 69, the same in stop 70): 35.530 K ± 0.086 (8 levels, stopped by
/// `max_levels`: the fitted regime began late) and 8.1384 K ± 0.0064
/// (target met) against 35.494 and 8.1362 K, and 35.524 and 8.1374 K on a
/// case mesh 8× finer adaptive to 0.1 %.
#[test]
fn an_asperity_the_case_fit_flattens_is_found_and_resolved() {
    let (_dir, surface) = asperity_profile("resolved", 3.5e-7);
    let adaptive = "target_error = 0.01\nmax_levels = 8";
    let r = solve(&asperity_case(
        [16, 8],
        [14, 7],
        &surface,
        "[1.0e3, 3.0e3]",
        adaptive,
    ));
    let fine = solve(&asperity_case(
        [64, 32],
        [56, 28],
        &surface,
        "[1.0e3, 3.0e3]",
        adaptive,
    ));
    for (r, f) in r.iter().zip(&fine) {
        println!(
            "{} Pa: {} K ± {:?} ({} unknowns, contact {}, {:?}) against {} K ({} unknowns, contact {})",
            r.pressure,
            r.jump,
            r.jump_error,
            r.dofs,
            r.interface.contact_fraction,
            r.refinement_stop,
            f.jump,
            f.dofs,
            f.interface.contact_fraction
        );
        assert!(r.converged && f.converged);
        assert!(
            (r.jump - f.jump).abs() < 0.01 * f.jump,
            "{} Pa: {} K against {} K",
            r.pressure,
            r.jump,
            f.jump
        );
    }
    assert_eq!(
        r[1].error_target_met,
        Some(true),
        "{:?}",
        r[1].refinement_stop
    );
}

/// The state carried over to a level whose faces resolve the asperity that
/// the case mesh's fit flattens (three levels over it at once): transferred
/// as displacements, the resolved asperity overlaps the flat by a fifth of
/// its depth (in the adaptive levels the first increments from such a state
/// invert an element); with the change of the reference taken into the
/// displacements (`adapt::keep_transferred_configuration`) every point is
/// where the coarse level solved it, and the weighted gaps are the coarse
/// level's (the asperity out of contact). Observed (stop 70), the smallest
/// weighted gap in units of the depth: −0.222 transferred, −2.1e-6 kept,
/// 4.9e-18 on the coarse level.
#[test]
fn a_kept_configuration_leaves_the_gaps_the_coarse_level_solved() {
    let depth = 3.5e-7;
    let (_dir, surface) = asperity_profile("kept", depth);
    let c = asperity_case([16, 8], [14, 7], &surface, "[1.0e3]", "");
    let mut s = PathSolver::new(&c).unwrap();
    s.solve_pressure(1.0e3).unwrap();
    s.model.prepare_contact().unwrap();
    let heights = case_heights(&c).unwrap();
    let g0 = s.geometry.g0;
    // Three levels at once over the asperity (|x − x_a| < 2.5 σ, the two
    // element layers at the face), as the adaptive levels refine it.
    let mut refined = s.bodies.clone();
    for level in 0..3 {
        let n = 16u32 << level;
        let from = ((ASPERITY_X - 2.5 * ASPERITY_WIDTH) / 1.0e-5 * f64::from(n)).floor() as u32;
        let to = ((ASPERITY_X + 2.5 * ASPERITY_WIDTH) / 1.0e-5 * f64::from(n)).ceil() as u32;
        let upper = (from..to)
            .flat_map(|i| {
                (0..2).map(move |k| Cell {
                    level,
                    index: [i, k, 0],
                })
            })
            .collect();
        refined = refine_bodies(
            &refined,
            &Marks {
                lower: Vec::new(),
                upper,
            },
        );
    }
    assert_eq!(refined.levels(), [0, 3]);
    let unresolved = [LOWER, UPPER].map(|k| refined.get(k).control_points().to_vec());
    let resolved = refined.resolved(&heights, g0).unwrap();
    // The smallest weighted gap over the slave nodes, in units of the depth.
    let smallest_gap = |m: &mut Model| -> f64 {
        m.prepare_contact().unwrap();
        let c = m.contact.as_ref().unwrap();
        let g = (0..c.n_slave())
            .map(|i| c.weighted_gap(i))
            .fold(f64::INFINITY, f64::min);
        g / m.scales.len(depth)
    };
    let coarse = smallest_gap(&mut s.model);
    let mut next = PathSolver::with_bodies(&c, s.geometry.clone(), resolved).unwrap();
    transfer_state(&s.model, &mut next.model);
    let transferred = smallest_gap(&mut next.model);
    keep_transferred_configuration(&mut next.model, &unresolved);
    let kept = smallest_gap(&mut next.model);
    println!(
        "smallest weighted gap / depth: coarse {coarse:.3e}, transferred {transferred:.3e}, kept {kept:.3e}"
    );
    assert!(transferred < -0.1, "transferred: {transferred}");
    assert!(
        kept > coarse - 1.0e-4,
        "kept: {kept}, coarse level: {coarse}"
    );
}

/// The indicator in 3D (the same code, face elements sampled on 8 × 8
/// points): a height map (`kind = "heightmap"`, 64 × 64 nodes) of a low egg
/// box (peak 0.2 μm) with a narrow dent (depth 0.35 μm, σ = 0.3 μm) at
/// `(W/4, W/4)`, where the egg box is at mid-height, so that the exact
/// surfaces first touch at the dent; on the 8 × 8 × 2 case mesh (elements of
/// 1.25 μm, whose fit flattens the dent) at 1 kPa the slave elements over the
/// dent are marked (observed: the four that meet at its centre, and no
/// other), and without the dent none is.
#[test]
fn the_surface_indicator_marks_an_asperity_in_3d() {
    let marked = |depth: f64| -> Vec<[f64; 4]> {
        let dir = tempfile::Builder::new()
            .prefix(&format!("tcgen-dent3d-{depth}-"))
            .tempdir()
            .unwrap();
        let file = dir.path().join("heights.csv");
        let (w, n) = (1.0e-5, 64);
        let q = std::f64::consts::TAU / w;
        let rows: Vec<String> = (0..n)
            .map(|j| {
                let y = j as f64 * w / n as f64;
                (0..n)
                    .map(|i| {
                        let x = i as f64 * w / n as f64;
                        let r2 = (x - w / 4.0).powi(2) + (y - w / 4.0).powi(2);
                        let z = 2.0e-7 * (q * x).cos() * (q * y).cos()
                            - depth * (-r2 / 3.0e-7f64.powi(2)).exp();
                        format!("{z:e}")
                    })
                    .collect::<Vec<_>>()
                    .join(",")
            })
            .collect();
        std::fs::write(&file, rows.join("\n") + "\n").unwrap();
        let text = format!(
            r#"
[sample]
dimension = 3
width = 1.0e-5
height = 7.0e-6
[surface.upper]
kind = "heightmap"
file = "{}"
[surface.lower]
kind = "flat"
[discretization]
degree = 2
elements_upper = [8, 8, 2]
elements_lower = [7, 7, 2]
bulk_points = 3
[contact]
interface_points = 4
[load]
pressures = [1.0e3]
flux = 1.0e6
[homogenization]
method = "two-phase"
"#,
            file.display()
        );
        let c = Case::from_toml(&text, Path::new(".")).unwrap();
        misfit_marks_at_one_kpa(&c)
            .iter()
            .map(|(a, b)| [a[0], b[0], a[1], b[1]])
            .collect()
    };
    let with = marked(3.5e-7);
    println!("marked slave elements (x0, x1, y0, y1 in m): {with:?}");
    let over_the_dent = |[x0, x1, y0, y1]: &[f64; 4]| {
        let (c, tol) = (2.5e-6, 1e-12);
        x0.min(*x1) <= c + tol
            && x0.max(*x1) >= c - tol
            && y0.min(*y1) <= c + tol
            && y0.max(*y1) >= c - tol
    };
    assert!(
        with.iter().any(over_the_dent),
        "the dent is not marked: {with:?}"
    );
    assert!(marked(0.0).is_empty());
}

/// The 3D default at p ≥ 2 marks the contact-edge elements' neighbours on
/// the first two levels only (`EARLY_EDGE_NEIGHBOUR_LEVELS`): on the egg
/// box of `coarse_adaptive_egg_box` at 30 kPa its first two levels are
/// those of `edge_neighbours = true`, and its third has fewer unknowns than
/// that rule's third and more than the third of `edge_neighbours = false`.
#[test]
fn the_3d_default_marks_the_edge_neighbours_on_the_first_two_levels() {
    use tcgen::homogenize::solve_case_observed;
    assert_eq!(tcgen::sample::case::EARLY_EDGE_NEIGHBOUR_LEVELS, 2);
    let unknowns = |rule: Option<EdgeNeighbours>| -> Vec<usize> {
        // A target below reach: every level up to `max_levels` is solved.
        let mut c = coarse_adaptive_egg_box(vec![3.0e4], 1e-9, 3);
        c.discretization.edge_neighbours = rule;
        let (reports, observer) = level_recorder();
        solve_case_observed(&c, None, |_| {}, Some(observer)).unwrap();
        let reports = reports.lock().unwrap();
        reports.iter().map(|r| r.dofs).collect()
    };
    let default = unknowns(None);
    let every = unknowns(Some(EdgeNeighbours::Every(true)));
    let none = unknowns(Some(EdgeNeighbours::Every(false)));
    assert_eq!(default.len(), 3, "{default:?}");
    assert_eq!(default[..2], every[..2], "{default:?} against {every:?}");
    assert!(none[0] < default[0], "{none:?} against {default:?}");
    assert!(
        none[2] < default[2] && default[2] < every[2],
        "{none:?}, {default:?}, {every:?}"
    );
}

/// The egg box of `tables/egg_box_on_flat.toml` on `[4, 4, 2]` / `[3, 3,
/// 2]`, plain two-phase, adaptive to `target` with at most `max_levels`
/// levels at `pressures` (Pa).
fn coarse_adaptive_egg_box(pressures: Vec<f64>, target: f64, max_levels: usize) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables/egg_box_on_flat.toml");
    let mut c = Case::read(&path).unwrap();
    let d = &mut c.discretization;
    d.elements_upper = [4, 4, 2].into();
    d.elements_lower = [3, 3, 2].into();
    d.target_error = Some(target);
    d.max_levels = max_levels;
    c.homogenization.method = Method::TwoPhase;
    c.load.pressures = pressures;
    c
}

/// An observer of adaptive levels that keeps every report.
fn level_recorder() -> (
    std::sync::Arc<std::sync::Mutex<Vec<tcgen::homogenize::LevelReport>>>,
    tcgen::homogenize::LevelObserver,
) {
    let reports = std::sync::Arc::<std::sync::Mutex<Vec<_>>>::default();
    let kept = std::sync::Arc::clone(&reports);
    let observer: tcgen::homogenize::LevelObserver =
        std::sync::Arc::new(move |r: &tcgen::homogenize::LevelReport| {
            kept.lock().unwrap().push(r.clone())
        });
    (reports, observer)
}

/// A 3D point's estimate may end the refinement from level 3 on
/// (`min_adaptive_levels`; its level-2 estimates fell below the error at 5 of
/// 21 levels measured against boundary elements): the egg box of
/// `tables/egg_box_on_flat.toml` on `[4, 4, 2]` / `[3, 3, 2]` at 30 kPa,
/// plain two-phase, target 20 %. Level 2's estimate (17.7 %, measured) meets
/// the target, and the point goes on to level 3 (6.3 %), where it stops;
/// with `max_levels = 2` it is flagged, its reason naming the rule.
#[test]
fn a_3d_point_needs_three_levels_before_its_estimate_meets_the_target() {
    use tcgen::homogenize::solve_case_observed;
    let c = coarse_adaptive_egg_box(vec![3.0e4], 0.2, 4);
    let (reports, observer) = level_recorder();
    let r = solve_case_observed(&c, None, |_| {}, Some(observer)).unwrap();
    let r = &r[0];
    let reports = reports.lock().unwrap().clone();
    let level_2 = reports.iter().find(|l| l.level == 2).expect("level 2");
    let (_, estimate_2) = level_2.jump.expect("level 2 solved");
    assert!(estimate_2 <= 0.2, "level 2's estimate {estimate_2}");
    assert!(level_2.stop.is_none(), "{level_2}");
    // The level says why the refinement goes on.
    let why = "level 2's jump estimate met the target; a 3D estimate may end the refinement from level 3 on";
    assert_eq!(level_2.goes_on.as_deref(), Some(why), "{level_2}");
    assert!(
        level_2.to_string().ends_with(&format!("; goes on: {why}")),
        "{level_2}"
    );
    assert_eq!(r.levels, [3, 3], "{:?}", r.refinement_stop);
    assert_eq!(r.refinement_stop.as_deref(), Some("target met"));
    assert_eq!(r.error_target_met, Some(true));
    // With two levels allowed, the point is flagged, and says why.
    let two = solve(&coarse_adaptive_egg_box(vec![3.0e4], 0.2, 2));
    assert_eq!(
        (two[0].error_target_met, two[0].refinement_stop.as_deref()),
        (
            Some(false),
            Some(
                "max_levels (level 2's jump estimate met the target; a 3D estimate may end the refinement from level 3 on)"
            )
        )
    );
}

/// A 3D adaptive path reports each level as it ends and each point before
/// the next one is refined (`solve_case_observed`): the egg box of
/// `tables/egg_box_on_flat.toml` on `[4, 4, 2]` / `[3, 3, 2]`, plain
/// two-phase, at 30 and 100 kPa, two levels at most. Each pressure's reports
/// are its levels in order with growing unknowns, the last one's the
/// point's unknowns, jump and relative estimate, and a stop where the
/// refinement stopped; a point arrives after its own levels and before the
/// next pressure's.
#[test]
fn a_3d_path_reports_its_levels_and_points_as_they_end() {
    use tcgen::homogenize::{LevelReport, solve_case_observed};
    let c = coarse_adaptive_egg_box(vec![3.0e4, 1.0e5], 0.01, 2);
    let (reports, observer) = level_recorder();
    // The levels seen when each point arrived.
    let mut seen_at_point = Vec::new();
    let results = solve_case_observed(
        &c,
        None,
        |r| seen_at_point.push((r.pressure, reports.lock().unwrap().len())),
        Some(observer),
    )
    .unwrap();
    let reports = reports.lock().unwrap().clone();
    assert_eq!(results.len(), 2);
    let mut seen = 0;
    for (k, r) in results.iter().enumerate() {
        assert!(r.converged, "{:?}", r.status);
        let own: Vec<&LevelReport> = reports
            .iter()
            .filter(|l| l.pressure == r.pressure)
            .collect();
        assert!(!own.is_empty(), "no level reported at {} Pa", r.pressure);
        for (i, l) in own.iter().enumerate() {
            assert_eq!(l.level, i + 1);
            assert_eq!(l.max_levels, 2);
            assert!(l.seconds > 0.0);
            if i > 0 {
                assert!(l.dofs > own[i - 1].dofs, "{l}");
            }
            assert_eq!(l.stop.is_some(), i + 1 == own.len(), "{l}");
            assert!(l.stop.is_none() || l.goes_on.is_none(), "{l}");
        }
        let last = own.last().unwrap();
        assert_eq!(last.dofs, r.dofs);
        let (jump, estimate) = last.jump.expect("a solved level");
        assert_eq!(jump, r.jump);
        let relative = r.jump_error.unwrap() / r.jump.abs();
        assert!(
            (estimate - relative).abs() <= 1e-12 * relative,
            "{estimate} {relative}"
        );
        let stop = r.refinement_stop.as_deref().unwrap();
        assert!(
            last.stop.as_deref() == Some(stop),
            "{last} against the point's stop {stop}"
        );
        // Streamed: the point came after its own levels, before the next's.
        seen += own.len();
        assert_eq!(seen_at_point[k], (r.pressure, seen), "point {k}");
        // And the line says what a user needs.
        let line = last.to_string();
        assert!(line.contains("unknowns") && line.contains("jump"), "{line}");
    }
    assert_eq!(seen, reports.len());
    // The process's peak memory where Linux gives it (`VmHWM`, which the
    // kernel updates lazily: a later reading may be a little lower).
    if std::path::Path::new("/proc/self/status").exists() {
        for l in &reports {
            assert!(l.peak_memory.is_some_and(|b| b > 1 << 20), "{l}");
            assert!(l.to_string().contains(", peak memory "), "{l}");
        }
    }
}

/// `[discretization] refinement = "alternating"`: the levels halve the
/// lateral directions and then the height in turn, so a marked cell is still
/// halved in every direction (over two THB levels) while the cells that
/// admissibility grades below and around it may stay as tall as their
/// parents. On the egg box of `coarse_adaptive_egg_box` at 30 kPa (every
/// level up to the third solved) the levels are counted as the dyadic ones,
/// the refined levels have fewer unknowns, and their jumps are those of the
/// dyadic levels within a small share of the change between levels.
#[test]
fn alternating_levels_refine_alike_with_fewer_unknowns() {
    use tcgen::homogenize::solve_case_observed;
    use tcgen::sample::case::RefinementPattern;
    let levels = |refinement| -> (Vec<(usize, f64)>, [usize; 2]) {
        let mut c = coarse_adaptive_egg_box(vec![3.0e4], 1e-9, 3);
        c.discretization.refinement = refinement;
        let (reports, observer) = level_recorder();
        let r = solve_case_observed(&c, None, |_| {}, Some(observer)).unwrap();
        let reports = reports.lock().unwrap();
        let per_level = reports
            .iter()
            .map(|l| (l.dofs, l.jump.expect("solved").0))
            .collect();
        (per_level, r[0].levels)
    };
    let (dyadic, dyadic_depth) = levels(RefinementPattern::Dyadic);
    let (alternating, depth) = levels(RefinementPattern::Alternating);
    // Measured: unknowns 2044, 6400, 12 768 against 2044, 6336, 11 504; the
    // jumps of level 3 11.11528 and 11.11290 K, 2.3 % of the change onto it.
    println!("dyadic {dyadic:?}\nalternating {alternating:?}");
    assert_eq!((dyadic_depth, depth), ([3, 3], [3, 3]));
    assert_eq!((dyadic.len(), alternating.len()), (3, 3));
    for k in 1..3 {
        let (d, a) = (dyadic[k], alternating[k]);
        assert!(
            a.0 < d.0,
            "level {}: {} unknowns against {}",
            k + 1,
            a.0,
            d.0
        );
        let change = (d.1 - dyadic[k - 1].1).abs();
        assert!(
            (a.1 - d.1).abs() <= 0.05 * change,
            "level {}: jump {} K against {} K (change onto the level {change} K)",
            k + 1,
            a.1,
            d.1
        );
    }
}
