//! The contact verification catalogue (issue 3; spec §10.2–10.5; paper
//! Sects. 5.1, 5.2, 5.7): every test runs the case function that
//! `tcgen verify` prints and asserts that each of its checks passes.
//!
//! The default tests use the catalogue's meshes (about 5 s each in release
//! on 2 cores; the 3D Hertz case 8 s). The tests named `long_*` refine them
//! (Hertz with p = 2 and 3 on coarse and fine meshes, 3D Hertz on three
//! meshes with its modelling errors, Westergaard and the strips on 128 and 256 elements
//! (raw within 2 %, and Richardson extrapolation), the Sect. 5.7 path on the full meshes of
//! `tables/sinusoid_on_flat.toml` for p = 1, 2, 3 with LN and PR sides, the
//! quadrature study of the non-nested patch tests, the 3D egg box's
//! conductance on three meshes and its adaptive levels against the
//! boundary elements); they run only with `TCGEN_LONG_TESTS=1` (about 2
//! minutes on 2 cores, 3 more for the 3D Hertz runs, 3 more for the egg
//! box on three meshes, 1.2 more for its adaptive levels) and return early
//! otherwise.

use tcgen::sample::case::LateralCondition;
use tcgen::verify::contact::hertz::HertzSetup;
use tcgen::verify::contact::patch::{Interface, PatchSetup, mortar_al, thermal_patch};
use tcgen::verify::contact::wavy::{
    WESTERGAARD_LEVELS, WavySample, constriction_checks, richardson_checks, wavy_rows,
    westergaard_checks, westergaard_relative_checks,
};
use tcgen::verify::contact::{self, HertzTolerances, PATCH_FLUX};
use tcgen::verify::{Check, format_table};

fn assert_pass(checks: &[Check]) {
    print!("{}", format_table(checks));
    let failed: Vec<&Check> = checks.iter().filter(|c| !c.pass).collect();
    assert!(
        failed.is_empty(),
        "failed checks:\n{}",
        format_table(
            &checks
                .iter()
                .filter(|c| !c.pass)
                .cloned()
                .collect::<Vec<_>>()
        )
    );
    assert!(!checks.is_empty());
}

fn long() -> bool {
    std::env::var("TCGEN_LONG_TESTS").is_ok_and(|v| v == "1")
}

#[test]
fn thermal_patch_flat() {
    assert_pass(&contact::thermal_patch_flat().unwrap());
}

#[test]
fn thermal_patch_curved() {
    assert_pass(&contact::thermal_patch_curved().unwrap());
}

#[test]
fn mechanical_patch() {
    assert_pass(&contact::mechanical_patch().unwrap());
}

#[test]
fn patch_tests_3d() {
    assert_pass(&contact::patch_3d().unwrap());
}

/// The 3D egg box on a coarse mesh (6 × 6 × 2 / 5 × 5 × 2, the spots span
/// one or two elements) at 0.1 and 0.3 p* (the default suite) against the
/// boundary-element reference (tamaas): contact fraction −55 / −30 %, mean
/// gap +24 / +24 %, conductance +9 / −17 % (stop 22), area with a gap of
/// at most 0.05 Δ / 0.1 Δ −44 / −39 % and −15 / −9 % (stop 23), the
/// contact zone's conductance −26.8 / −20.0 % (stop 24; tolerance 30 %);
/// the conductance against Barber's analogy of the computed stiffness: 1.1 %
/// and 12.9 % with the smoothed seams (2.2 % and 1.9 % with the C0 seams;
/// the spot sits on the seams' corner, and the catalogue's 8 × 8 × 3 sample
/// with one interface level is within 1.2–2.3 % either way), tolerance
/// 15 %. The catalogue's sample with the JGH asymptotes in the long run.
#[test]
fn egg_box_3d() {
    use tcgen::verify::contact::egg_box::{EggBoxSample, EggBoxTolerances, egg_box_checks};
    let rows = EggBoxSample::coarse().rows(&[0.1, 0.3]).unwrap();
    for r in &rows {
        println!(
            "{r:?}: Barber {:.4e}, Hertz fraction {:.4}",
            r.barber(),
            r.hertz()
        );
    }
    let tol = EggBoxTolerances {
        hertz: 0.5,
        near_full: 0.5,
        barber: 0.15,
        barber_near_full: 0.2,
        bem_contact: 0.6,
        bem_gap: 0.3,
        bem_gap_distribution: 0.5,
        bem_conductance: 0.25,
        bem_conductance_near_full: 1.0,
        bem_zone_conductance: 0.3,
    };
    assert_pass(&egg_box_checks("egg_box_coarse", &rows, tol));
    if long() {
        assert_pass(&contact::egg_box_default().unwrap());
    }
}

#[test]
fn hertz_p2_coarse() {
    assert_pass(&contact::hertz_default().unwrap());
}

#[test]
fn hertz_3d_sphere_on_flat() {
    assert_pass(&contact::hertz_3d_default().unwrap());
}

#[test]
fn westergaard_and_constriction() {
    assert_pass(&contact::wavy_case(&contact::wavy_default_sample()).unwrap());
}

#[test]
fn robustness_half_mesh() {
    assert_pass(&contact::robustness_default().unwrap());
}

#[test]
fn determinism_across_thread_counts() {
    assert_pass(&contact::determinism().unwrap());
}

/// Hertz with p = 2 fine and p = 3 coarse and fine (`TCGEN_LONG_TESTS=1`).
#[test]
fn long_hertz() {
    if !long() {
        return;
    }
    let mut checks = Vec::new();
    for (degree, fine, tol) in [
        (
            2,
            true,
            HertzTolerances {
                half_width: 0.03,
                pressure: 0.02,
                cumulative: 0.05,
            },
        ),
        (
            3,
            false,
            HertzTolerances {
                half_width: 0.07,
                pressure: 0.3,
                cumulative: 0.1,
            },
        ),
        (
            3,
            true,
            HertzTolerances {
                // The half-width is the contact zone's (the NURBS-interpolated
                // indicator's crossing, since f82b25d): measured −3.2 %, the
                // known inward bias of the nodal active set (docs/adaptivity.md);
                // the piecewise-linear crossing used before gave < 3 %.
                half_width: 0.035,
                pressure: 0.02,
                cumulative: 0.03,
            },
        ),
    ] {
        checks.extend(contact::hertz_checks(&HertzSetup::new(degree, fine), tol).unwrap());
    }
    assert_pass(&checks);
}

/// 3D Hertz (sphere on a flat) on n = 8, 10, 12 elements over 1.25 a, the
/// order of the radius error, the modelling errors and the predictor
/// (`TCGEN_LONG_TESTS=1`; about 3 minutes of CPU, 5.2 GB at n = 12).
#[test]
fn long_hertz_3d() {
    if !long() {
        return;
    }
    assert_pass(&contact::hertz_3d_long().unwrap());
}

/// Westergaard and the strips on 128 and 256 elements: the raw contact
/// fraction on 256 elements within 2 % of Westergaard's from 5 % to 90 % of
/// `p*` (spec §10.4), its Richardson extrapolation from 128/256 and the
/// observed order (3/2: 1.39; raw within 0.15 %), and the strip constriction
/// (`TCGEN_LONG_TESTS=1`).
#[test]
fn long_westergaard_richardson() {
    if !long() {
        return;
    }
    let sample = |n: usize| WavySample {
        elements_x: [n, n * 7 / 8],
        ..WavySample::default()
    };
    let (s128, s256) = (sample(128), sample(256));
    let coarse = wavy_rows(&s128, &WESTERGAARD_LEVELS).unwrap();
    let fine = wavy_rows(&s256, &WESTERGAARD_LEVELS).unwrap();
    let mut checks = westergaard_relative_checks("westergaard_256", &fine, 0.02);
    checks.extend(richardson_checks(
        "westergaard_richardson_128_256",
        &coarse,
        &fine,
        1.5,
        0.02,
    ));
    checks.extend(westergaard_checks("westergaard_256", &s256, &fine, 0.75));
    checks.extend(constriction_checks(
        "constriction_256",
        &s256,
        &fine,
        // The strips against the zone: the thermal error at the edges,
        // observed 0.02–0.37 elements on 256 (0.04–0.26 before stop 21);
        // against Westergaard's width with the mechanical edge error
        // (0.01–0.16 elements; 0.56–0.67 before): observed 0.08–0.35
        // (0.37–0.91 before).
        (0.4, 1.0),
    ));
    assert_pass(&checks);
}

/// The Sect. 5.7 sinusoid on the meshes of `tables/sinusoid_on_flat.toml`
/// for p = 1, 2, 3 with LN and PR sides (`TCGEN_LONG_TESTS=1`).
#[test]
fn long_robustness_full_mesh() {
    if !long() {
        return;
    }
    let mut checks = Vec::new();
    for degree in [1, 2, 3] {
        for lateral in [LateralCondition::Periodic, LateralCondition::Linear] {
            let (c, path) =
                contact::robustness_checks(degree, lateral, [32, 16], [27, 14]).unwrap();
            for p in &path {
                println!(
                    "p={degree} {lateral:?}: {:.3e} Pa, contact {:.4}, its {:?}, steps {}, cutbacks {}",
                    p.pressure, p.contact_fraction, p.iterations, p.steps, p.cutbacks
                );
            }
            checks.extend(c);
        }
    }
    assert_pass(&checks);
}

/// The non-nested patch tests converge with the interface quadrature:
/// element-based integration is the only error (`TCGEN_LONG_TESTS=1`).
#[test]
fn long_patch_quadrature_study() {
    if !long() {
        return;
    }
    let mut checks = Vec::new();
    for interface in [Interface::Flat, Interface::Curved] {
        let mut last = f64::INFINITY;
        for points in [8, 16, 32] {
            let mut s = mortar_al();
            s.interface_points = points;
            let r = thermal_patch(&PatchSetup::new(interface), &s, PATCH_FLUX).unwrap();
            checks.push(Check::with_error(
                &format!("patch_quadrature_{interface:?}"),
                &format!("flux dev. with {points} pts < previous"),
                r.flux_deviation,
                last,
                r.flux_deviation / last,
                1.0,
            ));
            last = r.flux_deviation;
        }
    }
    let mut last = f64::INFINITY;
    for points in [8, 16, 32, 64] {
        let r = tcgen::verify::contact::patch::mechanical_patch(
            &PatchSetup::new(Interface::Flat),
            1.0e4,
            points,
            tcgen::contact::Integration::Element,
        )
        .unwrap();
        checks.push(Check::with_error(
            "patch_quadrature_mechanical",
            &format!("pressure dev. with {points} pts < previous"),
            r.pressure_deviation,
            last,
            r.pressure_deviation / last,
            1.0,
        ));
        last = r.pressure_deviation;
    }
    assert_pass(&checks);
}

/// The 3D egg box's conductance against Barber's analogy of the
/// boundary-element stiffness on three one-level meshes (8, 10, 12 upper
/// elements per direction, 3 through the height; surface elements λ/16,
/// λ/20, λ/24; `TCGEN_LONG_TESTS=1`, 3 minutes on 2 cores): the
/// thermal phase on the contact zone (`thermal_zone = true`) lies below the
/// reference and approaches it at 0.05 and 0.1 p* (measured −12.6, −8.9,
/// −7.5 % and −17.1, −11.1, −3.5 %, stop 24); the nodal supports (the 3D
/// default) within the catalogue's 25 % (+19.5, +0.9, +1.9 % and −10.1,
/// +3.8, +8.5 %: their sign changes from mesh to mesh). At 0.3 p* neither
/// converges monotonically on these meshes (docs/3d.md, "The 3D thermal
/// contact zone"): not run.
#[test]
fn long_egg_box_conductance_on_three_meshes() {
    use tcgen::verify::contact::egg_box::{EggBoxSample, bem_reference};
    if !long() {
        return;
    }
    let ratios = [0.05, 0.1];
    let bem = bem_reference();
    let reference = |ratio: f64| {
        bem.iter()
            .find(|b| (b.ratio - ratio).abs() < 1e-9)
            .expect("a reference row")
            .barber_conductance
    };
    // Per ratio, the zone's relative errors on the meshes in order.
    let mut zone = vec![Vec::new(); ratios.len()];
    let mut checks = Vec::new();
    for n in [8, 10, 12] {
        let sample = EggBoxSample {
            elements: n,
            elements_height: 3,
            interface_levels: 1,
        };
        for (k, r) in sample.rows(&ratios).unwrap().iter().enumerate() {
            let c = reference(r.ratio);
            let name = format!("egg_box_{n}x{n}x3");
            checks.push(Check::relative(
                &name,
                &format!("{:.2} p*: conductance vs BEM's Barber", r.ratio),
                r.conductance,
                c,
                0.25,
            ));
            zone[k].push(r.conductance_zone / c - 1.0);
        }
    }
    for (ratio, errors) in ratios.iter().zip(&zone) {
        println!("{ratio} p*: zone's conductance errors {errors:?}");
        for (i, e) in errors.iter().enumerate() {
            checks.push(Check::with_error(
                "egg_box_zone_meshes",
                &format!("{ratio:.2} p*: zone below the reference, mesh {i}"),
                *e,
                0.0,
                e.max(0.0),
                1e-12,
            ));
            if i > 0 {
                checks.push(Check::with_error(
                    "egg_box_zone_meshes",
                    &format!("{ratio:.2} p*: zone's |error| falls, mesh {i} / {}", i - 1),
                    e.abs(),
                    errors[i - 1].abs(),
                    e.abs() / errors[i - 1].abs(),
                    1.0,
                ));
            }
        }
    }
    assert_pass(&checks);
}

/// The adaptive 3D levels against the boundary elements
/// (`TCGEN_LONG_TESTS=1`; about a minute and 4 GB on 2 cores): the
/// catalogue's egg box at 0.1 p*, shifted by a quarter wavelength, adaptive
/// from 8 × 8 × 3 / 7 × 7 × 3 to three levels (38 924 unknowns; 53 780 with
/// the edge elements' neighbours marked, before stop 85), the thermal phase
/// on the contact zone and on the nodal supports. The third level's
/// conductance is within 2 % of Barber's analogy of the boundary-element
/// stiffness (measured: zone +1.61 %, supports −0.45 % in jump; with the
/// neighbours +1.52 and −0.29 %, level 4 +0.49 and −0.08 %), and the
/// two-level estimate of order 3/2 (`level_error_ratio(3)`) bounds the
/// error and stays below 5 % of the jump (2.85 and 4.40 %; with the
/// neighbours 3.9 and 4.6 %; the first-order estimate gave 10.1 and
/// 11.8 %); the zone's effectivity is within 0.5–3 (1.80).
#[test]
fn long_adaptive_egg_box_against_boundary_elements() {
    use tcgen::verify::contact::egg_box::bem_reference;
    if !long() {
        return;
    }
    let ratio = 0.1;
    let bem = bem_reference();
    let row = bem
        .iter()
        .find(|b| (b.ratio - ratio).abs() < 1e-9)
        .expect("a reference row");
    let mut checks = Vec::new();
    for zone in [true, false] {
        let name = if zone {
            "egg_box_adaptive_zone"
        } else {
            "egg_box_adaptive_supports"
        };
        let (jump, error, estimate) =
            adaptive_egg_box_against(row, 3, zone, name, 0.02, &mut checks);
        checks.push(Check::with_error(
            name,
            "level 3: estimate below 5 % of the jump",
            estimate / jump,
            0.0,
            estimate / jump,
            0.05,
        ));
        if zone {
            checks.push(Check::with_error(
                name,
                "level 3: effectivity within 0.5-3",
                estimate / error,
                1.75,
                (estimate / error - 1.75).abs(),
                1.25,
            ));
        }
    }
    assert_pass(&checks);
}

/// The adaptive egg box (the catalogue's, shifted by a quarter wavelength,
/// from 8 × 8 × 3 / 7 × 7 × 3 elements) at the pressure of the boundary
/// elements' `row`, to `levels` levels, the thermal phase on the contact
/// zone or on the nodal supports: pushes to `checks` (case `name`) that its
/// jump is within `tolerance` of Barber's analogy of the boundary-element
/// stiffness and that its estimate bounds the error; returns the jump, the
/// error and the estimate (K).
fn adaptive_egg_box_against(
    row: &tcgen::verify::contact::egg_box::BemRow,
    levels: usize,
    zone: bool,
    name: &str,
    tolerance: f64,
    checks: &mut Vec<Check>,
) -> (f64, f64, f64) {
    use tcgen::homogenize::path::solve_case;
    use tcgen::verify::contact::egg_box::{EggBoxSample, p_star};
    let sample = EggBoxSample {
        elements: 8,
        elements_height: 3,
        interface_levels: 0,
    };
    let case = sample
        .adaptive_case(row.ratio * p_star(), levels, zone)
        .unwrap();
    let r = &solve_case(&case, None, |_| {}).unwrap()[0];
    assert!(r.converged, "{:?}", r.status);
    assert_eq!(r.levels, [levels, levels], "{:?}", r.refinement_stop);
    let reference = case.load.flux / row.barber_conductance;
    let error = (r.jump - reference).abs();
    let estimate = r.jump_error.expect("an estimate");
    println!(
        "{name}: {} unknowns, jump {:.5} K against {reference:.5} K ({:+.3} %), estimate {estimate:.4} K ({:.2} %, effectivity {:.2})",
        r.dofs,
        r.jump,
        100.0 * (r.jump / reference - 1.0),
        100.0 * estimate / r.jump,
        estimate / error
    );
    checks.push(Check::relative(
        name,
        &format!("level {levels}: jump vs BEM's Barber"),
        r.jump,
        reference,
        tolerance,
    ));
    checks.push(Check::with_error(
        name,
        &format!("level {levels}: estimate bounds the error"),
        estimate,
        error,
        (error - estimate).max(0.0),
        1e-12,
    ));
    (r.jump, error, estimate)
}

/// The adaptive 3D levels at small spots against the boundary elements
/// (`TCGEN_LONG_TESTS=1`; about 2 minutes and 3 GB on 2 cores): the egg
/// box of the test above at 0.002 and
/// 0.01 `p*` (contact fractions 1.2 and 3.7 %, as at the benchmark egg
/// box's lowest pressures; `bem_reference_small_spots`, within about 0.2 %
/// of its grid limit), adaptive to four levels, the thermal phase on the
/// nodal supports (the 3D default). The fourth level's jump is within
/// 1.5 % of Barber's analogy of the boundary-element stiffness (measured:
/// −0.49 and +0.12 %; 22 884 and 34 924 unknowns; with the edge elements'
/// neighbours marked, before stop 85, −0.68 and +0.16 % on 37 492 and
/// 50 996), and the estimate bounds the error (measured: 6.61 and 1.76 % of
/// the jump; docs/3d.md, "Small spots against the boundary elements" and
/// "Stop 85").
#[test]
fn long_adaptive_egg_box_small_spots_against_boundary_elements() {
    adaptive_egg_box_supports_at(
        tcgen::verify::contact::egg_box::bem_reference_small_spots,
        &[0.002, 0.01],
        4,
        0.015,
        "egg_box_small_spots",
    );
}

/// With `TCGEN_LONG_TESTS=1`: [`adaptive_egg_box_against`] on the nodal
/// supports at each of `ratios` (of `p*`) among the boundary elements'
/// `rows`, to `levels` levels; the cases named `{prefix}_{ratio}`; asserts
/// the checks.
fn adaptive_egg_box_supports_at(
    rows: fn() -> Vec<tcgen::verify::contact::egg_box::BemRow>,
    ratios: &[f64],
    levels: usize,
    tolerance: f64,
    prefix: &str,
) {
    if !long() {
        return;
    }
    let mut checks = Vec::new();
    for row in rows()
        .iter()
        .filter(|b| ratios.iter().any(|r| (b.ratio - r).abs() < 1e-9))
    {
        let name = format!("{prefix}_{}", row.ratio);
        adaptive_egg_box_against(row, levels, false, &name, tolerance, &mut checks);
    }
    assert_eq!(checks.len(), 2 * ratios.len());
    assert_pass(&checks);
}

/// The adaptive 3D levels at high contact fractions against the boundary
/// elements (`TCGEN_LONG_TESTS=1`; about 4 minutes and 9.2 GB on 2 cores):
/// the egg box of the tests above at 0.5 and 0.7 `p*` (contact fractions 70
/// and 84 %, the benchmark egg box's at 244 kPa and above), adaptive to four
/// levels, the thermal phase on the nodal supports. The fourth level's jump
/// is within 1.5 % of Barber's analogy of the boundary-element stiffness
/// (measured with the 3D default marks of stop 98, the edge elements'
/// neighbours on levels 1–2: +0.43 and −1.35 %; 115 752 and 88 344
/// unknowns; estimates 1.20 and 2.09 %), and the estimate bounds the error
/// (docs/3d.md, "Adaptive levels against the boundary elements", "Stop 85"
/// and "Stop 98"). Without the neighbours (stops 85–97) level 4 was +0.38
/// and −0.75 % on 120 336 and 84 300 unknowns (estimates 0.92 and 2.10 %),
/// level 3 −1.31 and +0.37 %; with them on every level (before stop 85)
/// level 3 +0.45 and −0.15 %, level 4 +0.26 and −1.33 %. Level 4's
/// estimate at 0.7 `p*` does not claim 1 %; the point would refine on.
#[test]
fn long_adaptive_egg_box_high_contact_against_boundary_elements() {
    adaptive_egg_box_supports_at(
        tcgen::verify::contact::egg_box::bem_reference,
        &[0.5, 0.7],
        4,
        0.015,
        "egg_box_high_contact",
    );
}

/// Degree 1's adaptive levels refine the bulk (`TCGEN_LONG_TESTS=1`; about
/// 30 s on 2 cores): the benchmark's egg box (`tables/egg_box_on_flat.toml`)
/// at degree 1 and 11.5 kPa, plain two-phase, adaptive to 1 % from
/// `[8, 8, 4]`. Refined at the contact edges only, its levels met the
/// target with the approach 4.7 % short of degrees 2 and 3 and the jump
/// 2.4 % above degree 2's (docs/3d.md, "Stop 74"); with the bulk-resolution
/// indicator the fourth level's approach is within 1.5 % of degree 2's level
/// 5 (0.74106 μm; measured −0.83 %), its contact fraction within 6 % of
/// 0.0650 (−4.5 %) and its jump within 1.5 % of degree 3's level 4
/// (20.165 K; +0.62 %); the bulk's estimated approach error (1.29 %) asks
/// for a fifth level past the default `max_dofs`, so the point is flagged,
/// and its `refinement_stop` names the bulk (docs/adaptivity.md, "The
/// bulk-resolution indicator").
#[test]
fn long_degree_one_egg_box_levels_refine_the_bulk() {
    use tcgen::homogenize::path::solve_case;
    if !long() {
        return;
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let text = std::fs::read_to_string(root.join("tables/egg_box_on_flat.toml"))
        .unwrap()
        .replace(
            "degree = 2",
            "degree = 1\ntarget_error = 0.01\nmax_levels = 5",
        )
        .replace(
            "method = \"two-phase-self-consistent\"",
            "method = \"two-phase\"",
        );
    let text = text
        .lines()
        .map(|l| {
            if l.starts_with("pressures = ") {
                "pressures = [1.151e4]"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let case = tcgen::sample::Case::from_toml(&text, &root).unwrap();
    let r = &solve_case(&case, None, |_| {}).unwrap()[0];
    println!(
        "degree 1, levels {:?}, {} unknowns: approach {:e} m, contact {}, jump {} K ± {:?}, {:?}",
        r.levels,
        r.dofs,
        r.interface.approach,
        r.interface.contact_fraction,
        r.jump,
        r.jump_error,
        r.refinement_stop
    );
    assert!(r.converged, "{:?}", r.status);
    let checks = vec![
        Check::relative(
            "egg_box_degree_1",
            "approach vs degree 2's level 5",
            r.interface.approach,
            0.74106e-6,
            0.015,
        ),
        Check::relative(
            "egg_box_degree_1",
            "contact fraction vs degree 2's level 5",
            r.interface.contact_fraction,
            0.0650,
            0.06,
        ),
        Check::relative(
            "egg_box_degree_1",
            "jump vs degree 3's level 4",
            r.jump,
            20.165,
            0.015,
        ),
    ];
    assert_pass(&checks);
    assert_eq!(r.error_target_met, Some(false), "{:?}", r.refinement_stop);
    // The reason names the limit and the indicator that kept the refinement
    // going past a level whose jump estimate met the target.
    let stop = r.refinement_stop.as_deref().unwrap_or_default();
    assert!(
        stop.starts_with("max_dofs: level 5 would have ")
            && stop.contains(
                "(level 4's jump estimate met the target; the bulk's estimated approach error"
            ),
        "{stop}"
    );
}
