//! Mortar contact on locally refined (THB) meshes: the patch tests of the
//! catalogue with both bodies refined at the interface to different levels
//! (non-matching, non-nested hierarchical meshes), and the Sect. 5.7 sample
//! refined at the interface against the uniform mesh of the same interface
//! resolution.

use tcgen::contact::{ContactSettings, Integration};
use tcgen::sample::case::Case;
use tcgen::verify::contact::patch::{
    Interface, PatchSetup, mechanical_patch, mortar_al, thermal_patch,
};

fn refined(interface: Interface, lower: usize, upper: usize) -> PatchSetup {
    let mut s = PatchSetup::new(interface);
    s.lower.interface_levels = lower;
    s.upper.interface_levels = upper;
    s
}

#[test]
fn mechanical_patch_test_passes_on_refined_non_matching_meshes() {
    for (lower, upper) in [(2, 1), (1, 3)] {
        let r = mechanical_patch(
            &refined(Interface::Flat, lower, upper),
            1.0e4,
            4,
            Integration::Segment,
        )
        .unwrap();
        assert!(
            r.pressure_deviation < 1e-8 && r.gap < 1e-8 && r.displacement_error < 1e-8,
            "levels ({lower}, {upper}): {r:?}"
        );
    }
}

/// Mortar AL (the paper's method, Fig. 9): no jump on refined non-matching,
/// non-nested meshes; the interface flux is uniform to the quadrature error
/// of element-based integration (the integrand's kinks at master element
/// boundaries), as on tensor meshes: the tolerances of the catalogue's
/// non-nested patch test (8 and 32 points per slave element).
#[test]
fn thermal_patch_test_passes_on_refined_meshes() {
    for interface in [Interface::Flat, Interface::Curved] {
        let setup = refined(interface, 2, 1);
        let r = thermal_patch(&setup, &mortar_al(), 1.0e6).unwrap();
        assert!(
            r.lumped_jump < 1e-6 && r.flux_deviation < 2e-4,
            "{interface:?}: {r:?}"
        );
        let many = ContactSettings {
            interface_points: 32,
            ..mortar_al()
        };
        let r = thermal_patch(&setup, &many, 1.0e6).unwrap();
        assert!(
            r.lumped_jump < 1e-6 && r.pointwise_jump < 1e-6 && r.flux_deviation < 1e-6,
            "{interface:?}, 32 points: {r:?}"
        );
    }
    // Penalty: a jump, but uniform flux through the refined interface.
    let r = thermal_patch(
        &refined(Interface::Flat, 1, 2),
        &ContactSettings {
            thermal: tcgen::contact::ThermalContact::Constraint {
                enforcement: tcgen::contact::ThermalEnforcement::Penalty,
                penalty: None,
            },
            ..ContactSettings::default()
        },
        1.0e6,
    )
    .unwrap();
    assert!(r.flux_deviation < 2e-4 && r.lumped_jump > 1e-3, "{r:?}");
}

/// The Sect. 5.7 sinusoid on a flat, p = 2, two-phase: a coarse mesh refined
/// twice at the interface gives the jump and contact fraction of the uniform
/// mesh with the same interface elements (4× as many along x and through the
/// height), with a fraction of the unknowns.
#[test]
fn interface_refinement_matches_the_uniform_mesh() {
    let text = |upper: [usize; 2], lower: [usize; 2], levels: usize| {
        format!(
            r#"
[sample]
width = 1.0e-5
height = 7.0e-6
[surface.upper]
kind = "sinusoid"
rms = 1.0e-6
wavelength = 1.0e-5
[surface.lower]
kind = "flat"
[discretization]
elements_upper = {upper:?}
elements_lower = {lower:?}
interface_levels = {levels}
[load]
pressures = [1.0e3, 3.0e4]
[homogenization]
method = "two-phase"
"#
        )
    };
    let solve = |t: String| {
        let case = Case::from_toml(&t, std::path::Path::new(".")).unwrap();
        let mut unknowns = 0;
        let mut out = Vec::new();
        let mut solver = tcgen::homogenize::path::PathSolver::new(&case).unwrap();
        for &p in &case.load.pressures {
            out.push(solver.solve_pressure(p).unwrap());
        }
        for b in &solver.model.bodies {
            unknowns += b.patch.n_control_points();
        }
        (out, unknowns)
    };
    let (local, n_local) = solve(text([8, 4], [7, 4], 2));
    let (uniform, n_uniform) = solve(text([32, 16], [28, 16], 0));
    assert!(
        3 * n_local < n_uniform,
        "{n_local} vs {n_uniform} control points"
    );
    for (a, b) in local.iter().zip(&uniform) {
        let rel = (a.jump - b.jump).abs() / b.jump;
        assert!(
            rel < 0.01,
            "{} Pa: jump {} vs {} ({rel:e})",
            a.pressure,
            a.jump,
            b.jump
        );
        let df = (a.interface.contact_fraction - b.interface.contact_fraction).abs();
        assert!(df < 0.01, "{} Pa: contact fraction {df}", a.pressure);
    }
}
