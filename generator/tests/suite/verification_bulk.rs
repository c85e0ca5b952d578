//! The bulk verification catalogue (spec §10.1, issue 2): every check that
//! `tcgen verify` prints for these cases must pass.

fn run(prefix: &str) {
    if let Err(report) = tcgen::verify::run_selected(|n| n.starts_with(prefix)) {
        panic!("{prefix}:\n{report}");
    }
}

/// Nonlinear conduction with k(θ) on the curved annulus: L2 rate p+1, H1 rate p, p = 1..3.
#[test]
fn manufactured_conduction_converges_at_optimal_rates() {
    run("mms_conduction");
}

/// Finite-strain thermoelasticity on the annulus: L2 rate p+1, H1 rate p for u and θ, p = 1..3.
#[test]
fn manufactured_thermoelasticity_converges_at_optimal_rates() {
    run("mms_thermoelastic");
}

/// Newton's method converges quadratically on a finite-strain case.
#[test]
fn newton_converges_quadratically() {
    run("newton_quadratic");
}

/// Homogeneous platen compression (LN and PR sides) matches the closed form.
#[test]
fn platen_compression_matches_closed_form() {
    run("platen_compression");
}

/// Homogeneous compression under a uniform dead traction matches the closed form.
#[test]
fn traction_compression_matches_closed_form() {
    run("traction_compression");
}

/// The accompanying bar problem (frozen and coupled) matches its closed forms.
#[test]
fn accompanying_bar_matches_closed_form() {
    run("abp_conduction");
}

/// SI and mm-MPa-mW inputs give the same results.
#[test]
fn results_do_not_depend_on_the_unit_system() {
    run("unit_invariance");
}

/// 3D (issue 12 item 2): k(θ) conduction on the warped cube, L2 rate p+1,
/// H1 rate p, p = 1..3 (rates of the two finest meshes, within 0.25).
#[test]
fn manufactured_conduction_converges_at_optimal_rates_in_3d() {
    run("mms3d_conduction");
}

/// 3D finite-strain thermoelasticity on the warped cube, p = 1, 2 (p = 3,
/// 50 s, mostly the coupled 3D assembly, under TCGEN_LONG_TESTS=1).
#[test]
fn manufactured_thermoelasticity_converges_at_optimal_rates_in_3d() {
    run("mms3d_thermoelastic_p1");
    run("mms3d_thermoelastic_p2");
    if std::env::var("TCGEN_LONG_TESTS").is_ok_and(|v| v == "1") {
        run("mms3d_thermoelastic_p3");
    }
}
