//! The bulk verification catalogue (spec §10.1, issue 2): every check that
//! `tcgen verify` prints for these cases must pass.

use tcgen::verify::{Case, catalogue, format_table};

fn run(prefix: &str) {
    let cases: Vec<Case> = catalogue()
        .into_iter()
        .filter(|c| c.name.starts_with(prefix))
        .collect();
    assert!(!cases.is_empty(), "no case named {prefix}*");
    for c in cases {
        let checks = (c.run)().unwrap_or_else(|e| panic!("{}: {e}", c.name));
        assert!(!checks.is_empty(), "{} produced no checks", c.name);
        let failed: Vec<_> = checks.iter().filter(|c| !c.pass).cloned().collect();
        assert!(
            failed.is_empty(),
            "{} failed:\n{}",
            c.name,
            format_table(&failed)
        );
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
