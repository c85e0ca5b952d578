//! The full tangent of a micro-sample in partial contact (bulk, mortar
//! contact with the multipliers, platen) against central finite differences
//! of the residual (issue 3: consistent linearization, including the
//! projection and, with segment-based integration, the moving breakpoints).

use tcgen::bulk::Coupling;
use tcgen::contact::Integration;
use tcgen::sample::case::{LateralCondition, Method};
use tcgen::sample::micro::{ThermalBc, build_model, case_geometry};
use tcgen::solve::{LoadStepping, Model, Newton, NewtonSettings, NonlinearProblem};
use tcgen::verify::contact::patch::{Interface, PatchSetup, mechanical_model};
use tcgen::verify::contact::robustness::sinusoid_case;

/// The Sect. 5.7 sinusoid with degree `p` at `pressure` (Pa), solved by the
/// mechanical phase.
fn loaded(degree: usize, pressure: f64) -> Model {
    let case = sinusoid_case(
        degree,
        LateralCondition::Periodic,
        [12, 6],
        [10, 5],
        vec![pressure],
        Method::TwoPhase,
    );
    let (mu, ml) = case.materials().unwrap();
    let geo = case_geometry(&case).unwrap();
    let bc = ThermalBc {
        master_face_temperature: case.load.contact_temperature,
        flux: case.load.flux,
    };
    let mut model = build_model(&case, &geo, (&mu, &ml), bc, Coupling::Mechanical).unwrap();
    model.set_path([0.0, 0.0], [pressure, 0.0]);
    Newton::new(NewtonSettings::default(), LoadStepping::default())
        .solve(&mut model)
        .unwrap();
    model
}

fn residual(model: &mut Model) -> Vec<f64> {
    model.prepare().unwrap();
    let mut r = vec![0.0; model.n_eq()];
    model.assemble(None, &mut r).unwrap();
    r
}

/// `max |K v − (R(x + h v) − R(x − h v)) / 2h| / max |K v|` at a state moved
/// off equilibrium by `offset` (so that the multipliers and gaps are generic).
fn tangent_error(model: &mut Model, offset: &[f64], v: &[f64], h: f64) -> f64 {
    model.update(offset);
    model.prepare().unwrap();
    let n = model.n_eq();
    let nnz = model.pattern().row_idx().len();
    let mut values = vec![0.0; nnz];
    let mut r = vec![0.0; n];
    model.assemble(Some(&mut values), &mut r).unwrap();
    let pattern = model.pattern();
    let mut kv = vec![0.0; n];
    for (j, vj) in v.iter().enumerate() {
        for k in pattern.col_ptr()[j]..pattern.col_ptr()[j + 1] {
            kv[pattern.row_idx()[k]] += values[k] * vj;
        }
    }
    let saved = model.save();
    let step: Vec<f64> = v.iter().map(|x| h * x).collect();
    model.update(&step);
    let rp = residual(model);
    model.restore(&saved);
    let back: Vec<f64> = step.iter().map(|x| -x).collect();
    model.update(&back);
    let rm = residual(model);
    model.restore(&saved);
    let scale = kv.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    kv.iter()
        .zip(rp.iter().zip(&rm))
        .map(|(k, (p, m))| (k - (p - m) / (2.0 * h)).abs())
        .fold(0.0, f64::max)
        / scale
}

/// A deterministic pseudo-random vector in [−1, 1].
fn direction(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

#[test]
fn contact_tangent_matches_finite_differences() {
    // p = 1: segment-based integration over a master with corners;
    // p = 2: element-based integration (the paper's).
    for degree in [1, 2] {
        let mut model = loaded(degree, 1.0e5);
        let c = model.contact.as_ref().unwrap();
        let active = (0..c.n_slave()).filter(|&i| c.is_active(i)).count();
        assert!(
            active > 2 && active < c.n_slave(),
            "partial contact: {active}"
        );
        let n = model.n_eq();
        let offset: Vec<f64> = direction(n, 7).iter().map(|x| 1e-7 * x).collect();
        let v = direction(n, 11);
        let e = tangent_error(&mut model, &offset, &v, 1e-7);
        println!("p = {degree}: relative tangent error {e:.2e} ({active} active)");
        assert!(e < 1e-5, "p = {degree}: tangent error {e:.2e}");
    }
}

/// 3D: the curved (cylindrical) non-matching patch under a platen, moved
/// off equilibrium until part of the interface opens; mechanical phase and
/// the monolithic coupling (gap and jump to second order, the projection
/// moving with the master surface).
#[test]
fn contact_tangent_matches_finite_differences_3d() {
    // Segment-based (clipped) integration re-clips the slave elements at
    // every configuration; the cells' motion is not differentiated, which
    // is exact over a C1 master (degree 2 here).
    let cases = [
        (Coupling::Mechanical, Integration::Element),
        (Coupling::Coupled, Integration::Element),
        (Coupling::Mechanical, Integration::Segment),
        (Coupling::Coupled, Integration::Segment),
    ];
    for (coupling, integration) in cases {
        let setup = PatchSetup::new_3d(Interface::Curved);
        let mut model = mechanical_model(&setup, 1.0e4, 4, integration).unwrap();
        Newton::new(NewtonSettings::default(), LoadStepping::default())
            .solve(&mut model)
            .unwrap();
        model.set_coupling(coupling).unwrap();
        let n = model.n_eq();
        let offset: Vec<f64> = direction(n, 5).iter().map(|x| 4e-3 * x).collect();
        model.update(&offset);
        model.prepare().unwrap();
        let c = model.contact.as_ref().unwrap();
        let active = (0..c.n_slave()).filter(|&i| c.is_active(i)).count();
        assert!(
            active > 2 && active < c.n_slave(),
            "partial contact: {active} of {}",
            c.n_slave()
        );
        let v = direction(n, 13);
        if integration == Integration::Segment {
            // The blocks' y faces are free and widen differently: the
            // slave's elements at y = 0 reach past the master's end there
            // (clamped projections) and keep element-based points (6–8 of
            // the 16 slave elements).
            let clipping = c.clipping();
            assert!(
                clipping.clipped >= 8 && clipping.element_based <= 8,
                "{clipping:?}"
            );
        }
        let e = tangent_error(&mut model, &vec![0.0; n], &v, 1e-7);
        println!(
            "3D {coupling:?} {integration:?}: relative tangent error {e:.2e} ({active} active)"
        );
        assert!(
            e < 1e-5,
            "3D {coupling:?} {integration:?}: tangent error {e:.2e}"
        );
    }
}
