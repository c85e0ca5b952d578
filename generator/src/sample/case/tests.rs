//! Tests of the case file: keys, defaults, errors, both dimensions.

use super::*;

const MINIMAL: &str = r#"
[surface.upper]
kind = "sinusoid"
rms = 1.0e-6
wavelength = 1.0e-5
[surface.lower]
kind = "flat"
"#;

/// Issue 14 item 4: keys that used to pass validation and fail later.
#[test]
fn late_failures_are_validation_errors_naming_the_key() {
    for (extra, key) in [
        ("[load]\nflux = 0.0\n", "load.flux"),
        (
            "[solver.newton]\nmax_iterations = 0\n",
            "solver.newton.max_iterations",
        ),
        (
            "[solver.stepping]\nmin_step = 0.5\nmax_step = 0.1\ninitial_step = 0.1\n",
            "solver.stepping.min_step",
        ),
        (
            "[material]\nconductivity_slope = -0.1\n[load]\ncontact_temperature = 310.0\n",
            "material.upper.conductivity_slope",
        ),
    ] {
        let e = Case::from_toml(&format!("{MINIMAL}\n{extra}"), Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(e.contains(key), "{key}: {e}");
    }
    // A profile file that is missing or malformed.
    let scratch = tempfile::Builder::new()
        .prefix("tcgen-case-profile-")
        .tempdir()
        .unwrap();
    let dir = scratch.path();
    std::fs::write(dir.join("bad.csv"), "x,z\n0.0,abc\n").unwrap();
    for file in ["missing.csv", "bad.csv"] {
        let t = format!(
            "[surface.upper]\nkind = \"profile\"\nfile = \"{file}\"\n[surface.lower]\nkind = \"flat\"\n"
        );
        let e = Case::from_toml(&t, dir).unwrap_err().to_string();
        assert!(
            e.contains("surface.upper.file") || e.contains(file),
            "{file}: {e}"
        );
    }
    // The same slope is fine where k stays positive.
    let ok = "[material]\nconductivity_slope = -0.1\n[load]\ncontact_temperature = 295.0\n";
    assert!(Case::from_toml(&format!("{MINIMAL}\n{ok}"), Path::new(".")).is_ok());
}

#[test]
fn defaults_are_table_i() {
    let c = Case::from_toml(MINIMAL, Path::new(".")).unwrap();
    let (u, l) = c.materials().unwrap();
    assert_eq!(u, Material::default());
    assert_eq!(l, Material::default());
    assert_eq!(c.discretization.degree, 2);
    assert_eq!(c.sample.top_lateral, TopLateral::Fixed);
}

#[test]
fn top_lateral_parses_and_names_the_allowed_values() {
    for v in TopLateral::VALUES {
        let t = format!("{MINIMAL}\n[sample]\ntop_lateral = \"{v}\"\n");
        let c = Case::from_toml(&t, Path::new(".")).unwrap();
        assert_eq!(c.sample.top_lateral.as_str(), v);
    }
    let t = format!("{MINIMAL}\n[sample]\ntop_lateral = \"slide\"\n");
    let e = Case::from_toml(&t, Path::new(".")).unwrap_err().to_string();
    assert!(e.contains("\"fixed\" or \"free\""), "{e}");
}

#[test]
fn per_body_material_overrides() {
    let t = format!(
        "{MINIMAL}\n[material]\nyoungs_modulus = 2.0e6\n[material.lower]\npoisson_ratio = 0.2\n"
    );
    let c = Case::from_toml(&t, Path::new(".")).unwrap();
    let (u, l) = c.materials().unwrap();
    assert_eq!(u.youngs_modulus, 2.0e6);
    assert_eq!(l.youngs_modulus, 2.0e6);
    assert_eq!(u.poisson_ratio, 0.3);
    assert_eq!(l.poisson_ratio, 0.2);
}

const EGG_BOX: &str = r#"
[sample]
dimension = 3
[surface.upper]
kind = "sinusoid"
rms = 1.0e-6
wavelength = 1.0e-5
pattern = "egg-box"
[surface.lower]
kind = "flat"
"#;

fn error(text: &str) -> String {
    Case::from_toml(text, Path::new("."))
        .unwrap_err()
        .to_string()
}

/// `[sample] dimension`: 2 by default, 3 read, anything else an error
/// naming the key and the allowed values.
#[test]
fn dimension_parses_and_names_the_allowed_values() {
    let c = Case::from_toml(MINIMAL, Path::new(".")).unwrap();
    assert_eq!(c.dimension(), 2);
    let c = Case::from_toml(EGG_BOX, Path::new(".")).unwrap();
    assert_eq!(c.dimension(), 3);
    for bad in ["0", "1", "4"] {
        let e = error(&EGG_BOX.replace("dimension = 3", &format!("dimension = {bad}")));
        assert!(
            e.contains("sample.dimension") && e.contains("2 (plane strain") && e.contains("or 3"),
            "{bad}: {e}"
        );
    }
    for bad in ["\"3\"", "-3", "3.0"] {
        let e = error(&EGG_BOX.replace("dimension = 3", &format!("dimension = {bad}")));
        assert!(e.contains("dimension = "), "{bad}: {e}");
    }
}

/// Two counts `[nx, nz]` in 2D, three `[nx, ny, nz]` in 3D, with the
/// defaults of each dimension; a wrong count names the key, the
/// dimension and the expected count.
#[test]
fn element_counts_follow_the_dimension() {
    let c = Case::from_toml(MINIMAL, Path::new(".")).unwrap();
    let d = &c.discretization;
    assert_eq!(d.elements_upper.as_slice(), &[32, 16]);
    assert_eq!(d.elements_lower.as_slice(), &[27, 14]);
    assert_eq!(
        (d.elements_upper.along(0), d.elements_upper.through_height()),
        (32, 16)
    );
    assert_eq!(d.elements_upper.lateral(), &[32]);
    assert_eq!(*d, DiscretizationSection::default());
    let c = Case::from_toml(EGG_BOX, Path::new(".")).unwrap();
    let d = &c.discretization;
    assert_eq!(d.elements_upper.as_slice(), &[8, 8, 4]);
    assert_eq!(d.elements_lower.as_slice(), &[7, 7, 4]);
    assert_eq!(d.elements_lower.scaled(2).as_slice(), &[14, 14, 8]);
    let t = format!("{EGG_BOX}[discretization]\nelements_upper = [6, 5, 3]\n");
    let c = Case::from_toml(&t, Path::new(".")).unwrap();
    let e = &c.discretization.elements_upper;
    assert_eq!((e.along(0), e.along(1), e.through_height()), (6, 5, 3));
    assert_eq!(e.lateral(), &[6, 5]);
    assert_eq!(e.to_string(), "[6, 5, 3]");
    for (text, key, expected) in [
        (
            format!("{EGG_BOX}[discretization]\nelements_upper = [8, 4]\n"),
            "discretization.elements_upper",
            "three element counts [nx, ny, nz] with sample.dimension = 3, each in 1..=4096",
        ),
        (
            format!("{EGG_BOX}[discretization]\nelements_lower = [8, 8, 8, 4]\n"),
            "discretization.elements_lower",
            "three element counts",
        ),
        (
            format!("{EGG_BOX}[discretization]\nelements_lower = [8, 0, 4]\n"),
            "discretization.elements_lower",
            "each in 1..=4096",
        ),
        (
            format!("{MINIMAL}[discretization]\nelements_upper = [8, 8, 4]\n"),
            "discretization.elements_upper",
            "two element counts [nx, nz] with sample.dimension = 2, each in 1..=4096",
        ),
        (
            format!("{MINIMAL}[discretization]\nelements_lower = []\n"),
            "elements_lower",
            "no element counts: expected [nx, nz] in 2D",
        ),
    ] {
        let e = error(&text);
        assert!(e.contains(key) && e.contains(expected), "{key}: {e}");
    }
}

/// Every 3D surface kind builds through `areal_surfaces`; the 2D
/// accessors refuse a 3D case and the 3D ones a 2D case.
#[test]
fn areal_surfaces_build_in_3d() {
    let w = 1.0e-5;
    let c = Case::from_toml(EGG_BOX, Path::new(".")).unwrap();
    let (u, l) = c.areal_surfaces().unwrap();
    assert!((u.height(0.0, 0.0) - 2.0e-6).abs() < 1e-18);
    assert!((u.height(0.25 * w, 0.1 * w)).abs() < 1e-18);
    assert_eq!(l.height(0.3 * w, 0.7 * w), 0.0);
    assert!(c.surface.upper.areal().is_some() && c.surface.upper.profile().is_none());
    let e = c.surfaces().err().unwrap().to_string();
    assert!(e.contains("sample.dimension") && e.contains("areal"), "{e}");
    let two = Case::from_toml(MINIMAL, Path::new(".")).unwrap();
    let e = two.areal_surfaces().err().unwrap().to_string();
    assert!(
        e.contains("sample.dimension") && e.contains("profiles"),
        "{e}"
    );
    // Phases (Sect. 5.3, mismatched cells): the egg box shifted by
    // −φλ/2π along x and y; a zero phase is not serialized.
    let shifted = EGG_BOX.replace(
        "pattern = \"egg-box\"",
        "phase = 1.5707963267948966\nphase_y = 3.141592653589793",
    );
    let c = Case::from_toml(&shifted, Path::new(".")).unwrap();
    let (s, _) = c.areal_surfaces().unwrap();
    for (x, y) in [(0.1 * w, 0.2 * w), (0.6 * w, 0.9 * w)] {
        assert!((s.height(x, y) - u.height(x + 0.25 * w, y + 0.5 * w)).abs() < 1e-18);
    }
    let text = toml::to_string(&c.surface.upper).unwrap();
    assert!(
        text.contains("phase = ") && text.contains("phase_y = "),
        "{text}"
    );
    let text = toml::to_string(
        &Case::from_toml(EGG_BOX, Path::new("."))
            .unwrap()
            .surface
            .upper,
    )
    .unwrap();
    assert!(!text.contains("phase"), "{text}");
    // Ridges, random (with the 2D keys), a height map.
    let ridges = EGG_BOX.replace("egg-box", "ridges");
    let c = Case::from_toml(&ridges, Path::new(".")).unwrap();
    let (u, _) = c.areal_surfaces().unwrap();
    assert_eq!(u.height(0.1 * w, 0.2 * w), u.height(0.1 * w, 0.9 * w));
    let random = "[sample]\ndimension = 3\n[surface.upper]\nkind = \"flat\"\n\
                  [surface.lower]\nkind = \"random\"\nrms = 5.0e-7\nspectrum = \"gaussian\"\n\
                  correlation_length = 2.0e-6\nseed = 2\n";
    let c = Case::from_toml(random, Path::new(".")).unwrap();
    assert!(c.surface.lower.random().is_some());
    let (_, l) = c.areal_surfaces().unwrap();
    assert!(l.height(0.3 * w, 0.6 * w).abs() > 0.0);
    let dir = std::env::temp_dir().join(format!("tcgen-case-map-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let map: String = (0..4)
        .map(|j| format!("0.0,{:e},0.0,-1.0e-7\n", 1.0e-7 * j as f64))
        .collect();
    std::fs::write(dir.join("map.csv"), map).unwrap();
    let t = "[sample]\ndimension = 3\n[surface.upper]\nkind = \"heightmap\"\nfile = \"map.csv\"\n\
             [surface.lower]\nkind = \"flat\"\n";
    let c = Case::from_toml(t, &dir).unwrap();
    let (u, _) = c.areal_surfaces().unwrap();
    assert!(u.height(0.25 * w, 0.5 * w).is_finite());
    // A missing or malformed map is an error at read time naming the key.
    std::fs::write(dir.join("bad.csv"), "0,1e-7\n0,1e-7,3\n").unwrap();
    for file in ["missing.csv", "bad.csv"] {
        let e = Case::from_toml(&t.replace("map.csv", file), &dir)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("surface.upper.file") || e.contains(file),
            "{file}: {e}"
        );
    }
    // A map higher than the body.
    std::fs::write(
        dir.join("high.csv"),
        "0,0,0,0\n0,8e-6,0,0\n0,0,0,0\n0,0,0,0\n",
    )
    .unwrap();
    let e = Case::from_toml(&t.replace("map.csv", "high.csv"), &dir)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("sample.height") && e.contains("|height| of the map"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Keys that belong to the other dimension are errors naming the key
/// and what is allowed.
#[test]
fn keys_of_the_other_dimension_are_errors() {
    let sinusoid_2d = MINIMAL.replace(
        "wavelength = 1.0e-5",
        "wavelength = 1.0e-5\npattern = \"egg-box\"",
    );
    let heightmap_2d = MINIMAL.replace("kind = \"flat\"", "kind = \"heightmap\"\nfile = \"m.csv\"");
    let phase_y_2d = MINIMAL.replace("wavelength = 1.0e-5", "wavelength = 1.0e-5\nphase_y = 0.5");
    let phase_y_ridges = EGG_BOX.replace(
        "pattern = \"egg-box\"",
        "pattern = \"ridges\"\nphase_y = 0.5",
    );
    let profile_3d = EGG_BOX.replace("kind = \"flat\"", "kind = \"profile\"\nfile = \"p.csv\"");
    for (text, key, expected) in [
        (
            &sinusoid_2d,
            "surface.upper.pattern",
            "absent with sample.dimension = 2",
        ),
        (
            &heightmap_2d,
            "surface.lower.kind",
            "\"profile\" or \"random\" with sample.dimension = 2",
        ),
        (
            &heightmap_2d,
            "surface.lower.kind",
            "needs [sample] dimension = 3",
        ),
        (
            &phase_y_2d,
            "surface.upper.phase_y",
            "absent with sample.dimension = 2",
        ),
        (
            &phase_y_ridges,
            "surface.upper.phase_y",
            "absent with pattern = \"ridges\"",
        ),
        (
            &profile_3d,
            "surface.lower.kind",
            "\"random\" or \"heightmap\" with sample.dimension = 3",
        ),
        (
            &EGG_BOX.replace("egg-box", "eggbox"),
            "surface.upper.pattern",
            "\"egg-box\"",
        ),
        (
            &EGG_BOX.replace("egg-box", "eggbox"),
            "surface.upper.pattern",
            "\"ridges\"",
        ),
        (
            &EGG_BOX.replace("kind = \"flat\"", "kind = \"plane\""),
            "surface.lower.kind",
            "one of \"flat\"",
        ),
        (
            &EGG_BOX.replace("kind = \"flat\"", ""),
            "surface.lower.kind",
            "(missing)",
        ),
        (
            &MINIMAL.replace("kind = \"flat\"", "kind = 3"),
            "surface.lower.kind",
            "one of \"flat\"",
        ),
    ] {
        let e = error(text);
        assert!(e.contains(key) && e.contains(expected), "{key}: {e}");
    }
    // Unknown keys of a kind name its table.
    let e = error(&EGG_BOX.replace("pattern = \"egg-box\"", "patern = \"ridges\""));
    assert!(e.contains("[surface.upper]") && e.contains("patern"), "{e}");
    // The range checks of 2D apply in 3D.
    let e = error(&EGG_BOX.replace("wavelength = 1.0e-5", "wavelength = 3.0e-6"));
    assert!(e.contains("surface.upper.wavelength"), "{e}");
    let e = error(&EGG_BOX.replace("rms = 1.0e-6", "rms = 4.0e-6"));
    assert!(
        e.contains("sample.height") && e.contains("2·rms of the egg-box"),
        "{e}"
    );
    // Ridges of the same RMS are lower (√2·rms < 7 μm).
    let ridges = EGG_BOX
        .replace("rms = 1.0e-6", "rms = 4.0e-6")
        .replace("egg-box", "ridges");
    assert!(Case::from_toml(&ridges, Path::new(".")).is_ok());
    let e = error(
        &EGG_BOX.replace(
            "kind = \"flat\"",
            "kind = \"random\"\nrms = 1e-7\ncutoff_wavelength = 1e-8\nspectrum = \"self-affine\"\nhurst = 0.8",
        ),
    );
    assert!(e.contains("surface.lower.cutoff_wavelength"), "{e}");
    // A case built in code with a surface of the other dimension.
    let mut c = Case::from_toml(EGG_BOX, Path::new(".")).unwrap();
    c.surface.upper = SurfaceSpec::Flat.into();
    let e = c.validate().unwrap_err().to_string();
    assert!(
        e.contains("surface.upper") && e.contains("sample.dimension = 3"),
        "{e}"
    );
}

/// The resolved configuration of a 3D case is a case file that reads
/// back to the same case; a 2D one records `dimension = 2`.
#[test]
fn resolved_3d_case_round_trips() {
    for text in [EGG_BOX, MINIMAL] {
        let c = Case::from_toml(text, Path::new(".")).unwrap();
        let resolved = crate::sweep::config::resolved_case(&c).unwrap();
        let back = Case::from_toml(&resolved, Path::new(".")).unwrap();
        assert_eq!(back.surface, c.surface);
        assert_eq!(
            back.discretization.elements_upper,
            c.discretization.elements_upper
        );
        assert_eq!(
            crate::sweep::config::resolved_case(&back).unwrap(),
            resolved
        );
        let t: toml::Table = toml::from_str(&resolved).unwrap();
        assert_eq!(
            t["sample"]["dimension"].as_integer(),
            Some(c.dimension() as i64)
        );
    }
}

#[test]
fn errors_name_the_key() {
    for (extra, key) in [
        ("[material]\npoisson_ratio = 0.7\n", "poisson_ratio"),
        ("[load]\npressures = [-1.0]\n", "load.pressures"),
        ("[discretization]\ndegree = 0\n", "discretization.degree"),
        (
            "[discretization]\nbulk_points = 1\n",
            "discretization.bulk_points",
        ),
        ("[sample]\nwidth = -1.0\n", "sample.width"),
        (
            "[contact]\nthermal = \"constitutive\"\nconductance_coefficient = -1.0\npressure_exponent = 1.0\n",
            "conductance_coefficient",
        ),
        ("[load]\nflux = nan\n", "load.flux"),
        ("[sample]\nwidht = 1.0\n", "widht"),
        ("[sample]\ntop_lateral = \"slide\"\n", "sample.top_lateral"),
    ] {
        let e = Case::from_toml(&format!("{MINIMAL}\n{extra}"), Path::new("."))
            .unwrap_err()
            .to_string();
        assert!(e.contains(key), "{key}: {e}");
    }
}

/// `[discretization] edge_neighbours` reads `true`, `false` or a number of
/// levels: the marks that build levels 1 to `n` take the neighbours, the
/// later ones do not; anything else is refused with the key named.
#[test]
fn edge_neighbours_read_a_number_of_levels() {
    let read = |value: &str| {
        Case::from_toml(
            &format!("{MINIMAL}\n[discretization]\nedge_neighbours = {value}\n"),
            Path::new("."),
        )
    };
    let n = read("2").unwrap().discretization.edge_neighbours.unwrap();
    assert_eq!(n, EdgeNeighbours::FirstLevels(2));
    assert_eq!([1, 2, 3, 4].map(|l| n.at(l)), [true, true, false, false]);
    let none = read("0").unwrap().discretization.edge_neighbours.unwrap();
    assert!(!none.at(1));
    assert_eq!(none.describe(), EdgeNeighbours::Every(false).describe());
    let every = read("true")
        .unwrap()
        .discretization
        .edge_neighbours
        .unwrap();
    assert_eq!(every, EdgeNeighbours::Every(true));
    assert!(every.at(1) && every.at(12));
    for bad in ["-1", "\"yes\"", "1.5"] {
        let e = read(bad).unwrap_err().to_string();
        assert!(e.contains("edge_neighbours"), "{bad}: {e}");
        assert!(e.contains("a number of levels"), "{bad}: {e}");
    }
}

/// `[discretization] refinement` reads `"dyadic"` (the default, left out when
/// the case is written, so that tables keep their hashes) or `"alternating"`;
/// anything else is refused with the key and the values named.
#[test]
fn refinement_reads_dyadic_or_alternating() {
    let read = |value: &str| {
        Case::from_toml(
            &format!("{MINIMAL}\n[discretization]\nrefinement = {value}\n"),
            Path::new("."),
        )
    };
    let written = |c: &Case| toml::to_string(&c.discretization).unwrap();
    let c = read("\"alternating\"").unwrap();
    assert_eq!(c.discretization.refinement, RefinementPattern::Alternating);
    assert!(written(&c).contains("refinement = \"alternating\""));
    let c = read("\"dyadic\"").unwrap();
    assert_eq!(c.discretization.refinement, RefinementPattern::Dyadic);
    assert!(!written(&c).contains("refinement"), "{}", written(&c));
    let c = Case::from_toml(MINIMAL, Path::new(".")).unwrap();
    assert_eq!(c.discretization.refinement, RefinementPattern::Dyadic);
    for bad in ["\"anisotropic\"", "2", "true"] {
        let e = read(bad).unwrap_err().to_string();
        assert!(e.contains("refinement"), "{bad}: {e}");
        assert!(e.contains("alternating"), "{bad}: {e}");
    }
}

/// The bulk rule has at least `p` Gauss points per direction, and 2 at p = 1:
/// fewer leave zero-energy modes (docs/3d.md, "Stop 97"); the error says so.
#[test]
fn bulk_points_below_the_degree_are_refused() {
    let case = |degree: usize, points: usize| {
        Case::from_toml(
            &format!("{MINIMAL}\n[discretization]\ndegree = {degree}\nbulk_points = {points}\n"),
            Path::new("."),
        )
    };
    for (degree, points) in [(1, 2), (2, 2), (3, 3), (2, 16)] {
        assert!(
            case(degree, points).is_ok(),
            "p = {degree}, {points} points"
        );
    }
    for (degree, points, range) in [
        (1, 1, "2..=16"),
        (2, 1, "2..=16"),
        (3, 2, "3..=16"),
        (2, 17, "2..=16"),
    ] {
        let e = case(degree, points).unwrap_err().to_string();
        assert!(
            e.contains("discretization.bulk_points") && e.contains(range),
            "{e}"
        );
        assert!(e.contains("zero-energy modes"), "{e}");
    }
}

/// The cautions of the case `base` with `extra` appended.
fn cautions(extra: &str, base: &str) -> Vec<String> {
    Case::from_toml(&format!("{base}{extra}"), Path::new("."))
        .unwrap()
        .cautions()
}

/// Degree 1 in 3D is valid but known to stall under load with element-based
/// contact points and, adaptive, to need far more unknowns than degree 2,
/// its levels refining the bodies' bulk too (docs/3d.md, "Stop 67", "Stop
/// 73", "Stop 74", "Stop 76"): the case says so before it runs, with the
/// cause; degree 2 and 2D say nothing.
#[test]
fn degree_1_in_3d_comes_with_its_cautions() {
    assert!(cautions("", EGG_BOX).is_empty());
    assert!(cautions("[discretization]\ndegree = 1\n", MINIMAL).is_empty());
    let c = cautions("[discretization]\ndegree = 1\n", EGG_BOX);
    assert_eq!(c.len(), 1, "{c:?}");
    assert!(c[0].contains("integration = \"segment\""), "{c:?}");
    let c = cautions(
        "[discretization]\ndegree = 1\ntarget_error = 0.01\n[contact]\nintegration = \"segment\"\n",
        EGG_BOX,
    );
    assert_eq!(c.len(), 1, "{c:?}");
    assert!(c[0].contains("adaptive refinement"), "{c:?}");
    assert!(c[0].contains("bodies' bulk"), "{c:?}");
    let c = cautions(
        "[discretization]\ndegree = 1\ntarget_error = 0.01\n",
        EGG_BOX,
    );
    assert_eq!(c.len(), 2, "{c:?}");
}

/// A 3D point needs three levels before its estimate may meet the target
/// (`min_adaptive_levels`), a 2D point two: an adaptive case whose
/// `max_levels` is below that says before it runs that every point will be
/// flagged; at the minimum, or without a target, it says nothing.
#[test]
fn too_few_levels_for_the_estimate_come_with_a_caution() {
    let c = cautions(
        "[discretization]\ntarget_error = 0.01\nmax_levels = 2\n",
        EGG_BOX,
    );
    assert_eq!(c.len(), 1, "{c:?}");
    assert!(
        c[0].contains("max_levels = 2") && c[0].contains("from level 3 on"),
        "{c:?}"
    );
    for extra in [
        "[discretization]\ntarget_error = 0.01\nmax_levels = 3\n",
        "[discretization]\nmax_levels = 2\n",
    ] {
        assert!(cautions(extra, EGG_BOX).is_empty(), "{extra}");
    }
    assert!(
        cautions(
            "[discretization]\ntarget_error = 0.01\nmax_levels = 2\n",
            MINIMAL
        )
        .is_empty()
    );
    let c = cautions(
        "[discretization]\ntarget_error = 0.01\nmax_levels = 1\n",
        MINIMAL,
    );
    assert!(c.len() == 1 && c[0].contains("in 2D"), "{c:?}");
}
