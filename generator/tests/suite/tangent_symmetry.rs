//! Symmetry of the assembled tangent of real micro-samples per phase, at
//! states with a partial active set: `‖K − Kᵀ‖_F / ‖K‖_F` overall and the
//! largest such ratio over the blocks of field classes (bulk, λN, λθ), so
//! that an asymmetric multiplier coupling is not hidden by the bulk. Where
//! [`Model::symmetric_tangent`] claims symmetry the ratios are round-off and
//! the LDLᵀ (or Cholesky) with nested dissection solves without falling
//! back to LU, as LU does; where it does not (coupled phase, `k(θ)`), they
//! are not.

use std::collections::HashMap;

use tcgen::bulk::Coupling;
use tcgen::bulk::global::Storage;
use tcgen::contact::{ThermalContact, ThermalEnforcement, ThermalMethod};
use tcgen::sample::Case;
use tcgen::sample::case::{LateralCondition, Method, TopLateral};
use tcgen::sample::micro::{ThermalBc, build_model, case_geometry};
use tcgen::solve::linear::{Factorization, LinearSolver};
use tcgen::solve::{LoadStepping, Model, Newton, NewtonSettings, NonlinearProblem};
use tcgen::verify::contact::robustness::sinusoid_case;

/// Round-off bound on the asymmetry ratios where the tangent is symmetric.
const SYMMETRIC: f64 = 1e-13;
/// Lower bound on them where it is not.
const ASYMMETRIC: f64 = 1e-6;

/// The tangent values (on the model's pattern) and the residual at the current state.
fn tangent(model: &mut Model) -> (Vec<f64>, Vec<f64>) {
    model.prepare().unwrap();
    let mut values = vec![0.0; model.pattern().row_idx().len()];
    let mut r = vec![0.0; model.n_eq()];
    model.assemble(Some(&mut values), &mut r).unwrap();
    (values, r)
}

/// `(overall, largest over blocks)` of `‖K − Kᵀ‖_F / ‖K‖_F` at the current state,
/// on the tangent assembled with both triangles; where the model stores the lower
/// one ([`Storage::Lower`]), its entries are checked to be those of the full
/// tangent to the bit, and mirrored back to be the full one (to the symmetry's
/// round-off, [`SYMMETRIC`] of its entries above the diagonal).
fn asymmetry(model: &mut Model) -> (f64, f64) {
    let symmetric_solvers = model.symmetric_solvers();
    model.set_symmetric_solvers(false);
    let (values, _) = tangent(model);
    assert_eq!(model.tangent_storage(), Storage::Full);
    let n = model.n_eq();
    let pattern = model.pattern();
    let mut k = HashMap::new();
    for j in 0..n {
        for p in pattern.col_range(j) {
            *k.entry((pattern.row_idx()[p], j)).or_insert(0.0) += values[p];
        }
    }
    model.set_symmetric_solvers(symmetric_solvers);
    let (stored, _) = tangent(model);
    if model.tangent_storage() == Storage::Lower {
        let pattern = model.pattern();
        for j in 0..n {
            for p in pattern.col_range(j) {
                let i = pattern.row_idx()[p];
                assert_eq!(stored[p].to_bits(), k[&(i, j)].to_bits(), "({i}, {j})");
            }
        }
        assert!(2 * stored.len() < k.len() + 6 * n, "about half the entries");
        // Mirrored back: both triangles, symmetric (the full tangent's to round-off).
        let full = model.full_tangent(&stored);
        assert_eq!(
            full.val().len(),
            k.len(),
            "every entry stored once or mirrored"
        );
        for j in 0..n {
            for p in full.symbolic().col_range(j) {
                let i = full.symbolic().row_idx()[p];
                let (v, t) = (full.val()[p], k[&(i, j)]);
                assert!(
                    (v - t).abs() <= SYMMETRIC * t.abs(),
                    "({i}, {j}): {v} vs {t}"
                );
            }
        }
    }
    let class = model.eq_fields();
    // Squared norms of K and of K − Kᵀ, overall and per block of classes.
    let (mut norm, mut diff) = (0.0, 0.0);
    let mut blocks: HashMap<(usize, usize), (f64, f64)> = HashMap::new();
    for (&(i, j), &v) in &k {
        let t = k.get(&(j, i)).copied().unwrap_or(0.0);
        norm += v * v;
        diff += (v - t) * (v - t);
        let b = blocks.entry((class[i], class[j])).or_default();
        b.0 += v * v;
        b.1 += (v - t) * (v - t);
    }
    let worst = blocks
        .values()
        .filter(|b| b.0 > 0.0)
        .map(|b| (b.1 / b.0).sqrt())
        .fold(0.0, f64::max);
    ((diff / norm).sqrt(), worst)
}

/// The model's factorization (with its ordering) against LU on the current
/// tangent: no fallback, and the same increment to 1e-10. Returns the kind
/// and its LDLᵀ pivots of the unexpected sign.
fn solves_like_lu(model: &mut Model) -> (Factorization, usize) {
    let (values, r) = tangent(model);
    let kind = model.factorization();
    // LU on both triangles; the model's kind on what its assembly stores.
    let full = model.full_tangent(&values);
    let solve = |kind: Factorization| {
        let ordering = model.ordering(&kind);
        let (pattern, values) = match kind {
            Factorization::Lu => (full.symbolic(), full.val()),
            _ => (model.pattern(), values.as_slice()),
        };
        let mut s = LinearSolver::new(pattern, kind, ordering).unwrap();
        s.factorize(values).unwrap();
        let mut x = r.clone();
        s.solve_in_place(&mut x).unwrap();
        assert_eq!(s.fallback(), None, "{:?}", s.kind());
        (x, s.sign_mismatches())
    };
    let ((x, mismatches), (y, _)) = (solve(kind.clone()), solve(Factorization::Lu));
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let e = x
        .iter()
        .zip(&y)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / scale;
    assert!(e < 1e-10, "{kind:?} vs LU: {e:e}");
    (kind, mismatches)
}

fn kind_name(kind: &Factorization) -> &'static str {
    match kind {
        Factorization::Lu => "LU",
        Factorization::Cholesky => "Cholesky",
        Factorization::Ldlt { .. } => "LDLT",
    }
}

/// The Sect. 5.7 sinusoid on a flat (coarse) with degree `p` and lateral conditions.
fn case(degree: usize, lateral: LateralCondition, top: TopLateral) -> Case {
    let mut c = sinusoid_case(
        degree,
        lateral,
        [12, 6],
        [10, 5],
        vec![1.0e4],
        Method::TwoPhase,
    );
    c.sample.top_lateral = top;
    c
}

/// The mechanical phase solved at `pressure` (Pa), with a partial active set.
pub(crate) fn mechanical(case: &Case, pressure: f64) -> Model {
    let (mu, ml) = case.materials().unwrap();
    let geo = case_geometry(case).unwrap();
    let bc = ThermalBc {
        master_face_temperature: case.load.contact_temperature,
        flux: 1.0,
    };
    let mut model = build_model(case, &geo, (&mu, &ml), bc, Coupling::Mechanical).unwrap();
    model.set_path([0.0, 0.0], [pressure, 0.0]);
    Newton::new(NewtonSettings::default(), LoadStepping::default())
        .solve(&mut model)
        .unwrap();
    let c = model.contact.as_ref().unwrap();
    let active = (0..c.n_slave()).filter(|&i| c.is_active(i)).count();
    assert!(
        active > 1 && active < c.n_slave(),
        "partial contact: {active}"
    );
    model
}

/// The thermal phase on the mechanical state (conductivity frozen at θ̄c),
/// solved under the flux `h` (W/m²) so that the temperatures vary.
pub(crate) fn thermal(model: &mut Model, pressure: f64, h: f64) {
    model.set_coupling(Coupling::Thermal).unwrap();
    model.freeze_conductivity(293.15);
    model.set_path([pressure, 0.0], [pressure, h]);
    Newton::new(NewtonSettings::default(), LoadStepping::default())
        .solve(model)
        .unwrap();
}

/// Measures one phase, prints it, checks the claim and the factorization.
fn check(label: &str, model: &mut Model, symmetric: bool, expected: &str) {
    let (overall, blocks) = asymmetry(model);
    let (kind, mismatches) = if symmetric {
        solves_like_lu(model)
    } else {
        (model.factorization(), 0)
    };
    println!(
        "{label:<44} ‖K−Kᵀ‖/‖K‖ = {overall:.1e}, worst block {blocks:.1e}, n = {}: {} \
         ({mismatches} pivots of the other sign)",
        model.n_eq(),
        kind_name(&kind)
    );
    assert_eq!(model.symmetric_tangent(), symmetric, "{label}");
    assert_eq!(kind_name(&kind), expected, "{label}");
    if symmetric {
        assert!(
            overall < SYMMETRIC && blocks < SYMMETRIC,
            "{label}: {overall:e} {blocks:e}"
        );
    } else {
        assert!(overall > ASYMMETRIC, "{label}: {overall:e}");
    }
}

/// The paper's configuration (p = 2, PR, augmented Lagrangian thermal
/// constraint): mechanical and thermal phases symmetric (LDLᵀ), the thermal
/// phase with `k(θ)` and the coupled problem not (LU).
#[test]
fn phases_with_multipliers_have_symmetric_tangents() {
    for pressure in [1.0e4, 1.0e5] {
        let c = case(2, LateralCondition::Periodic, TopLateral::Fixed);
        let mut model = mechanical(&c, pressure);
        check(
            &format!("p=2 PR mechanical {pressure:e} Pa"),
            &mut model,
            true,
            "LDLT",
        );
        thermal(&mut model, pressure, 1.0e6);
        check(
            &format!("p=2 PR thermal (AL, k frozen) {pressure:e} Pa"),
            &mut model,
            true,
            "LDLT",
        );
        model.prepare().unwrap();
        assert_eq!(model.tangent_storage(), Storage::Lower);
        // Restored k(θ): both triangles at once, for LU.
        model.restore_materials();
        model.prepare().unwrap();
        assert_eq!(model.tangent_storage(), Storage::Full);
        assert!(matches!(model.factorization(), Factorization::Lu));
        check(
            &format!("p=2 PR thermal (AL, k(θ)) {pressure:e} Pa"),
            &mut model,
            false,
            "LU",
        );
        model.set_coupling(Coupling::Coupled).unwrap();
        check(
            &format!("p=2 PR coupled {pressure:e} Pa"),
            &mut model,
            false,
            "LU",
        );
    }
}

/// Segment-based integration (p = 1, moving breakpoints), linear lateral
/// conditions, and a sliding platen (free top, PR): symmetric mechanical
/// phases.
#[test]
fn mechanical_variants_have_symmetric_tangents() {
    for (label, c) in [
        (
            "p=1 PR (segments) mechanical",
            case(1, LateralCondition::Periodic, TopLateral::Fixed),
        ),
        (
            "p=2 LN mechanical",
            case(2, LateralCondition::Linear, TopLateral::Fixed),
        ),
        (
            "p=2 PR sliding platen mechanical",
            case(2, LateralCondition::Periodic, TopLateral::Free),
        ),
    ] {
        let mut model = mechanical(&c, 1.0e5);
        check(label, &mut model, true, "LDLT");
        if label.starts_with("p=1") {
            thermal(&mut model, 1.0e5, 1.0e6);
            check("p=1 PR (segments) thermal (AL)", &mut model, true, "LDLT");
        }
    }
}

/// The thermal phase of the other thermal contact models (no multipliers):
/// penalty, constitutive with frozen pressures, and the continuum method;
/// symmetric positive definite (Cholesky).
#[test]
fn thermal_models_without_multipliers_have_symmetric_tangents() {
    let models = [
        (
            "penalty",
            ThermalContact::Constraint {
                enforcement: ThermalEnforcement::Penalty,
                penalty: None,
            },
            ThermalMethod::Mortar,
        ),
        (
            "constitutive",
            ThermalContact::Constitutive {
                conductance_coefficient: 1.0,
                pressure_exponent: 0.95,
            },
            ThermalMethod::Mortar,
        ),
        (
            "continuum constraint",
            ThermalContact::default(),
            ThermalMethod::Continuum,
        ),
    ];
    for (name, thermal_model, method) in models {
        let mut c = case(2, LateralCondition::Periodic, TopLateral::Fixed);
        c.contact.thermal = thermal_model;
        c.contact.thermal_method = method;
        let mut model = mechanical(&c, 1.0e5);
        thermal(&mut model, 1.0e5, 1.0e6);
        check(
            &format!("p=2 PR thermal ({name})"),
            &mut model,
            true,
            "Cholesky",
        );
    }
}

/// A model whose caches were released ([`Model::release_caches`]: the bulk quadrature and the
/// assemblies of both phases, as an adaptive level's while the next one solves) rebuilds them
/// once and assembles the same tangent and residual to the bit, in its phase and after a
/// change of phase.
#[test]
fn released_caches_come_back_the_same() {
    let c = case(2, LateralCondition::Periodic, TopLateral::Fixed);
    let mut model = mechanical(&c, 1.0e4);
    let kept = tangent(&mut model);
    let (assemblies, quadratures) = (model.assembly_builds(), model.quadrature_builds());
    model.release_caches();
    assert!(model.bodies.iter().all(|b| b.quadrature.is_empty()));
    assert!(
        tangent(&mut model) == kept,
        "mechanical phase after release"
    );
    assert_eq!(
        model.assembly_builds(),
        assemblies + 1,
        "the assembly rebuilt"
    );
    assert_eq!(
        model.quadrature_builds(),
        quadratures + 1,
        "the quadrature rebuilt"
    );
    assert!(tangent(&mut model) == kept);
    assert_eq!(model.quadrature_builds(), quadratures + 1, "rebuilt once");
    let (mut released, mut twin) = (mechanical(&c, 1.0e4), mechanical(&c, 1.0e4));
    for (m, release) in [(&mut released, true), (&mut twin, false)] {
        thermal(m, 1.0e4, 1.0e6);
        if release {
            m.release_caches();
        }
        m.set_coupling(Coupling::Mechanical).unwrap();
    }
    assert!(
        tangent(&mut released) == tangent(&mut twin),
        "mechanical phase after a thermal one"
    );
}

/// A Newton solve whose factorizations free the bulk quadrature first
/// ([`Newton::set_factor_bytes_releasing_caches`], here before every one; by
/// default only those of factors of 1 GiB and more) rebuilds it once per
/// factorization and ends in the same state to the bit as one that keeps it.
#[test]
fn factorizations_that_free_the_quadrature_solve_the_same() {
    let c = case(2, LateralCondition::Periodic, TopLateral::Fixed);
    let solve = |release: bool| {
        let (mu, ml) = c.materials().unwrap();
        let geo = case_geometry(&c).unwrap();
        let bc = ThermalBc {
            master_face_temperature: c.load.contact_temperature,
            flux: 1.0,
        };
        let mut model = build_model(&c, &geo, (&mu, &ml), bc, Coupling::Mechanical).unwrap();
        model.set_path([0.0, 0.0], [1.0e4, 0.0]);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        if release {
            newton.set_factor_bytes_releasing_caches(0);
        }
        newton.solve(&mut model).unwrap();
        (
            model.save(),
            model.quadrature_builds(),
            newton.linear_solves().0,
        )
    };
    let (kept, kept_builds, _) = solve(false);
    let (freed, freed_builds, factorizations) = solve(true);
    assert_eq!(kept_builds, 0);
    assert!(factorizations > 1);
    assert_eq!(
        freed_builds, factorizations,
        "one rebuild per factorization"
    );
    assert!(freed == kept, "the same state to the bit");
}

/// Changes of equations before the next preparation build the assembly once,
/// when it is needed, and the same as one built at each change: a mechanical
/// phase switched to the thermal one and back without being prepared builds
/// nothing (it keeps its own), and its tangent is its twin's to the bit; the
/// thermal phase builds its own at its preparation.
#[test]
fn an_assembly_out_of_date_is_built_once_when_needed() {
    let c = case(2, LateralCondition::Periodic, TopLateral::Fixed);
    let (mut model, mut twin) = (mechanical(&c, 1.0e4), mechanical(&c, 1.0e4));
    let before = model.assembly_builds();
    assert!(before >= 1);
    model.set_coupling(Coupling::Thermal).unwrap();
    model.set_coupling(Coupling::Mechanical).unwrap();
    assert_eq!(
        model.assembly_builds(),
        before,
        "built before it was needed"
    );
    assert!(
        tangent(&mut model) == tangent(&mut twin),
        "mechanical phase after an unprepared change of phase"
    );
    assert_eq!(model.assembly_builds(), before, "its own assembly reused");
    model.set_coupling(Coupling::Thermal).unwrap();
    model.prepare().unwrap();
    assert_eq!(model.assembly_builds(), before + 1, "the thermal phase's");
}

/// The self-consistent iterations alternate the phases: back from a thermal
/// phase, the mechanical phase reuses its own kept assembly although the
/// change of phase reset the contact pattern to the nodes in contact and
/// their neighbours, where its Newton iterations had grown that pattern
/// past the reset one (here by unloading from 100 to 3 kPa: the pattern
/// keeps the nodes that left the contact;
/// [`tcgen::contact::ContactInterface::cover_at_least`]); its tangent is
/// its twin's to the bit.
#[test]
fn a_mechanical_phase_after_a_thermal_one_reuses_its_assembly() {
    let c = case(2, LateralCondition::Periodic, TopLateral::Fixed);
    let unloaded = || {
        let mut m = mechanical(&c, 1.0e5);
        m.set_path([1.0e5, 0.0], [3.0e3, 0.0]);
        Newton::new(NewtonSettings::default(), LoadStepping::default())
            .solve(&mut m)
            .unwrap();
        m
    };
    let (mut model, mut twin) = (unloaded(), unloaded());
    let coverage = |m: &Model| m.contact.as_ref().unwrap().coverage().to_vec();
    let grown = coverage(&model);
    // The thermal phase on the mechanical state, as the two-phase solve runs it.
    let saved = model.save();
    thermal(&mut model, 3.0e3, 1.0e6);
    let reset = coverage(&model);
    assert!(
        reset != grown && reset.iter().zip(&grown).all(|(&r, &g)| g || !r),
        "the mechanical Newton iterations grew the pattern past the thermal phase's"
    );
    model.restore_materials();
    model.restore(&saved);
    let before = model.assembly_builds();
    model.set_coupling(Coupling::Mechanical).unwrap();
    assert_eq!(coverage(&model), grown);
    assert!(
        tangent(&mut model) == tangent(&mut twin),
        "mechanical phase after a thermal one"
    );
    assert_eq!(model.assembly_builds(), before, "its kept assembly reused");
}
