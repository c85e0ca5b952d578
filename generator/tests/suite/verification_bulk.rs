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

/// 3D finite-strain thermoelasticity on the warped cube with the reduced rule,
/// `p` = 2 Gauss points per direction instead of the full `p + 1` (the least
/// `bulk_points` accepts; the shipped cases keep 3): the same optimal rates
/// (docs/3d.md, "Stop 97").
#[test]
fn manufactured_thermoelasticity_converges_at_optimal_rates_with_the_reduced_rule_in_3d() {
    run("mms3d_reduced_thermoelastic");
}

/// The zero-energy modes of a free body's stiffness (the mechanical tangent at
/// rest, no boundary condition) with `bulk_points` Gauss points per direction:
/// the eigenvalues below 1e-9 of the largest, and the smallest one above them
/// relative to the largest.
fn zero_energy_modes(patch: tcgen::geometry::ThbPatch, bulk_points: usize) -> (usize, f64) {
    use tcgen::solve::NonlinearProblem;
    let (material, _, _) =
        tcgen::verify::mms::mms_setup(tcgen::verify::mms::MmsKind::Thermoelastic);
    let mut b = tcgen::solve::ModelBuilder::new(3, tcgen::solve::Scales::new(1.0, &material))
        .bulk_points(bulk_points);
    b.add_body("free", patch, &material).unwrap();
    let mut model = b.build(tcgen::bulk::Coupling::Mechanical).unwrap();
    model.set_symmetric_solvers(false);
    model.prepare().unwrap();
    let n = model.n_eq();
    let mut values = vec![0.0; model.pattern().row_idx().len()];
    let mut residual = vec![0.0; n];
    model.assemble(Some(&mut values), &mut residual).unwrap();
    let full = model.full_tangent(&values);
    let mut k = nalgebra::DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        for p in full.symbolic().col_range(j) {
            k[(full.symbolic().row_idx()[p], j)] += full.val()[p];
        }
    }
    let mut eigenvalues: Vec<f64> = ((&k + k.transpose()) * 0.5)
        .symmetric_eigenvalues()
        .iter()
        .map(|e| e.abs())
        .collect();
    eigenvalues.sort_by(f64::total_cmp);
    let largest = eigenvalues[n - 1];
    let zeros = eigenvalues.iter().filter(|&&e| e < 1e-9 * largest).count();
    (zeros, eigenvalues[zeros.min(n - 1)] / largest)
}

/// The least rule `[discretization] bulk_points` accepts at p = 2 (`p` Gauss
/// points per direction, 2 × 2 × 2 per element, the reduced rule) on
/// maximally smooth (C1) splines: a free body's stiffness keeps exactly the
/// six rigid modes, as with the full rule, on the warped cube of 2 and 4
/// elements per direction and with two THB levels graded towards a face
/// (truncated functions). Its smallest nonzero eigenvalue is of the full
/// rule's size (measured 3.4e-3 of the largest against 1.1e-2 on 2 elements,
/// 5.0e-3 on 4, and 3.7e-3 both on the graded mesh). One point per
/// direction, which the case refuses, leaves spurious zero-energy modes, and
/// this check sees them. (Measured once at the other degrees, the bound
/// `max(p, 2)` of the case's check: 46 zero modes at p = 1 with 1 point and 6
/// with 2, on 4 elements; 264 at p = 3 with 2 points and 6 with 3, on 2
/// elements.)
#[test]
fn the_least_accepted_rule_keeps_only_the_rigid_modes() {
    use tcgen::geometry::{Side, ThbPatch};
    use tcgen::verify::mms::warped_cube_mesh;
    let cube = |n| ThbPatch::from_nurbs(&warped_cube_mesh(2, n).unwrap());
    let graded = || cube(2).refined_at_face(2, Side::High, 2);
    for (name, patch, points) in [
        ("2 elements, full rule", cube(2), 3),
        ("2 elements, reduced", cube(2), 2),
        ("4 elements, reduced", cube(4), 2),
        ("graded, full rule", graded(), 3),
        ("graded, reduced", graded(), 2),
    ] {
        let (zeros, smallest) = zero_energy_modes(patch, points);
        assert_eq!(zeros, 6, "{name}: the rigid modes only");
        assert!(smallest > 1e-4, "{name}: {smallest:e}");
    }
    let (zeros, _) = zero_energy_modes(cube(2), 1);
    assert!(zeros > 6, "one point per direction: {zeros} zero modes");
}
