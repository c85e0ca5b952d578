//! An independent code in 3D (issue 12 item 6): the boundary-element
//! solution by tamaas (`scripts/tamaas_reference_3d.py`, `basic_2d`,
//! committed in `random_areal_tamaas.csv`) of the fitted random areal
//! surface of `generator/tests/data/random_areal.toml` (RMS 10 nm, Gaussian
//! correlation length 2 μm, 10 μm cell, small-strain limit) on a flat. Until
//! the 3D contact exists this checks the data: computed for this very
//! surface and material, well formed, physically sane (contact fraction
//! rising with pressure, mean gap falling, K = −dp̄/dḡ > 0, Barber's
//! conductance `k K / E*`).

use std::path::Path;

use tcgen::analytical::constriction::barber_conductance_from_stiffness;
use tcgen::geometry::fit_height_map;
use tcgen::sample::Case;

#[path = "common/bem_reference.rs"]
mod bem_reference;
use bem_reference::Reference;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");

#[test]
fn random_areal_reference_is_the_case_surface_and_sane() {
    let text = std::fs::read_to_string(format!("{DATA}random_areal.toml")).unwrap();
    let case = Case::from_toml(&text, Path::new(DATA)).unwrap();
    assert_eq!(case.dimension(), 3);
    let reference = Reference::read("random_areal_tamaas.csv");
    let header = |key: &str| reference.header(key);
    // The material and cell of the case.
    let (upper, lower) = case.materials().unwrap();
    assert_eq!(upper, lower);
    let e_star = upper.youngs_modulus / (2.0 * (1.0 - upper.poisson_ratio.powi(2)));
    assert!(reference.text().starts_with("# tamaas ") && reference.text().contains(" basic_2d "));
    for (key, value) in [
        ("width", case.sample.width),
        ("e_star", e_star),
        ("conductivity", upper.thermal_conductivity),
    ] {
        assert!(
            (header(key) / value - 1.0).abs() < 1e-8,
            "{key}: {} vs the case's {value}",
            header(key)
        );
    }
    assert_eq!(upper.conductivity_slope, 0.0);
    // The surface: the case's NURBS fit on the reference grid (the random
    // stream and the fit unchanged).
    let n = header("grid") as usize;
    let w = case.sample.width;
    let (surface, _) = case.areal_surfaces().unwrap();
    let d = &case.discretization;
    let f = |x: f64, y: f64| surface.height(x, y);
    let counts = [d.elements_upper.along(0), d.elements_upper.along(1)];
    let fit = fit_height_map(&f, w, d.degree, counts).unwrap();
    let z: Vec<f64> = (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            fit.height_at(w * i as f64 / n as f64, w * j as f64 / n as f64)
        })
        .collect();
    reference.assert_surface(&z, "surface");
    let lowest = z.iter().copied().fold(f64::INFINITY, f64::min);
    // The rows: the case's pressures, increasing contact, closing gap.
    let rows = reference.rows();
    assert!(
        reference
            .text()
            .contains("\npressure,contact_fraction,mean_gap,stiffness,barber_conductance\n")
    );
    assert_eq!(rows.len(), case.load.pressures.len());
    let highest = z.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    for (k, (row, &p)) in rows.iter().zip(&case.load.pressures).enumerate() {
        let [pressure, fraction, gap, stiffness, barber] = row[..] else {
            panic!("row {k}: five columns expected, got {row:?}");
        };
        assert_eq!(pressure, p);
        assert!(
            (0.01..0.3).contains(&fraction),
            "{p} Pa: contact {fraction}"
        );
        assert!(
            gap > 0.0 && gap < highest - lowest,
            "{p} Pa: mean gap {gap}"
        );
        assert!(stiffness > 0.0, "{p} Pa: K = {stiffness}");
        let c = barber_conductance_from_stiffness(
            upper.thermal_conductivity,
            lower.thermal_conductivity,
            e_star,
            stiffness,
        );
        assert!((barber / c - 1.0).abs() < 1e-6, "{p} Pa: {barber} vs {c}");
        if k > 0 {
            let before = &rows[k - 1];
            assert!(fraction > before[1], "contact fraction rises at {p} Pa");
            assert!(gap < before[2], "mean gap falls at {p} Pa");
            assert!(stiffness > before[3], "stiffness rises at {p} Pa");
            // K = −dp̄/dḡ: the secant between neighbouring pressures lies
            // between the two tangents (the gap is convex in p̄).
            let secant = (p - before[0]) / (before[2] - gap);
            assert!(
                before[3] < secant && secant < stiffness,
                "secant {secant} outside [{}, {stiffness}] at {p} Pa",
                before[3]
            );
        }
    }
}
