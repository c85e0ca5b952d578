//! A measured surface (`kind = "heightmap"`) end to end: the example of
//! `tables/heightmap_example.toml` is a sample of `tables/nightly_random_3d.toml`
//! written as a height map, so that both inputs must give the same jumps.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::{Arc, Mutex};

use tcgen::homogenize::{LevelObserver, LevelReport, solve_case, solve_case_observed};
use tcgen::sample::Case;
use tcgen::sample::case::{BodySurface, Method};
use tcgen::surface::ArealSpec;
use tcgen::sweep::SweepConfig;

fn tables() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables")
}

/// The committed map is what its header's command writes: sample 0 of the
/// nightly random surface on a 32 × 32 grid (`tcgen surface --exact`).
#[test]
fn the_example_height_map_is_the_nightly_random_sample() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("map.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_tcgen"))
        .args(["surface", "--exact", "--points", "32", "-o"])
        .arg(&out)
        .arg(tables().join("nightly_random_3d.toml"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let written = std::fs::read(&out).unwrap();
    let committed = std::fs::read(tables().join("heightmap_example.csv")).unwrap();
    assert!(
        written == committed,
        "tables/heightmap_example.csv is not the nightly surface's sample 0"
    );
}

/// The height map and the random surface it samples give the same jump and
/// contact fraction, on the case mesh and on two refined levels, which
/// resolve their faces on the surfaces themselves. The fits collocate at
/// the elements' mid-points (p = 2): on the case mesh and level 1 (elements
/// of W/8 and W/16) nodes of the 32 × 32 map, where its bicubic spline
/// interpolates the heights; on level 2 (W/32) mid-way between them, where
/// the spline stands for the surface. Plain two-phase at 3.162 kPa. On the
/// case mesh, the map with its columns shifted by one node, its rows
/// reversed or its heights negated gives jumps 16, 19 and 62 % off (a
/// transposed map is the cell's mirror image: the same jump; docs/3d.md,
/// "Stop 104").
#[test]
fn a_height_map_gives_the_jump_of_the_surface_it_samples() {
    let case = |file: &str, adaptive: bool| -> Case {
        let mut c = SweepConfig::read(&tables().join(file))
            .unwrap()
            .path_case(0, 0, 0);
        c.homogenization.method = Method::TwoPhase;
        c.load.pressures = vec![3.162e3];
        let d = &mut c.discretization;
        d.target_error = adaptive.then_some(0.01);
        d.max_levels = 2;
        c
    };
    for adaptive in [false, true] {
        let solve = |file| {
            let r = solve_case(&case(file, adaptive), None, |_| {}).unwrap();
            assert!(r[0].converged, "{file}");
            (r[0].jump, r[0].interface.contact_fraction, r[0].levels)
        };
        let map = solve("heightmap_example.toml");
        let random = solve("nightly_random_3d.toml");
        println!("adaptive {adaptive}: height map {map:?}, random surface {random:?}");
        assert_eq!(map.2, random.2);
        assert_eq!(map.2, if adaptive { [2, 2] } else { [0, 0] });
        assert!(
            ((map.0 - random.0) / random.0).abs() < 1e-4,
            "adaptive {adaptive}: jumps {} and {} K",
            map.0,
            random.0
        );
        assert!(
            (map.1 - random.1).abs() < 2e-4 * random.1,
            "adaptive {adaptive}: contact fractions {} and {}",
            map.1,
            random.1
        );
    }
}

/// A measured surface that is not periodic (a crop of a larger scan) steps
/// across the cell's edges: `tcgen check`, `solve` and `sweep` caution, naming
/// the file and the seam; a periodic map or profile gets no such caution.
/// 3D: the example map, its 24 × 24 corner (stepping across its seams by
/// 9.6 and 7.6 times its steps inside) and the map tilted along x; 2D: a
/// sine profile and the same with a ramp.
#[test]
fn a_measured_surface_that_is_not_periodic_is_cautioned() {
    let dir = tempfile::tempdir().unwrap();
    let seam_cautions = |text: &str| -> Vec<String> {
        Case::from_toml(text, dir.path())
            .unwrap()
            .cautions()
            .into_iter()
            .filter(|c| c.contains("not periodic across its seam"))
            .collect()
    };
    let map = std::fs::read_to_string(tables().join("heightmap_example.csv")).unwrap();
    let corner: Vec<String> = map
        .lines()
        .take(24)
        .map(|l| l.split(',').take(24).collect::<Vec<_>>().join(","))
        .collect();
    std::fs::write(dir.path().join("map.csv"), &map).unwrap();
    std::fs::write(dir.path().join("corner.csv"), corner.join("\n")).unwrap();
    let areal = |file: &str| {
        format!(
            "[sample]\ndimension = 3\n[surface.upper]\nkind = \"heightmap\"\nfile = \"{file}\"\n\
             [surface.lower]\nkind = \"flat\"\n[discretization]\nelements_upper = [8, 8, 4]\n\
             elements_lower = [7, 7, 4]\n"
        )
    };
    assert!(seam_cautions(&areal("map.csv")).is_empty());
    let c = seam_cautions(&areal("corner.csv"));
    assert_eq!(c.len(), 2, "{c:?}");
    assert!(
        c[0].starts_with("surface.upper.file") && c[0].contains("x = W"),
        "{c:?}"
    );
    assert!(
        c[1].contains("y = W") && c[1].contains("7.6 times"),
        "{c:?}"
    );
    // The periodic map tilted by 0.5 μm across the cell in x (a scan whose
    // plane was not removed): its seam at x = W steps, the other not.
    let tilted: Vec<String> = map
        .lines()
        .map(|l| {
            let row: Vec<f64> = l.split(',').map(|v| v.parse().unwrap()).collect();
            let n = row.len() as f64;
            row.iter()
                .enumerate()
                .map(|(i, z)| format!("{:e}", z + 5.0e-7 * i as f64 / n))
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect();
    std::fs::write(dir.path().join("tilted.csv"), tilted.join("\n")).unwrap();
    let c = seam_cautions(&areal("tilted.csv"));
    assert_eq!(c.len(), 1, "{c:?}");
    assert!(
        c[0].contains("x = W") && c[0].contains("best-fit plane"),
        "{c:?}"
    );
    let w = 1.0e-5;
    for (ramp, cautioned) in [(0.0, false), (1.0e-6, true)] {
        let mut csv = String::from("x,z\n");
        for i in 0..64 {
            let x = w * i as f64 / 64.0;
            let z = 2.0e-7 * (std::f64::consts::TAU * x / w).sin() + ramp * x / w;
            csv += &format!("{x:e},{z:e}\n");
        }
        std::fs::write(dir.path().join("profile.csv"), csv).unwrap();
        let c = seam_cautions(
            "[surface.upper]\nkind = \"flat\"\n[surface.lower]\nkind = \"profile\"\nfile = \"profile.csv\"\n",
        );
        assert_eq!(c.len(), usize::from(cautioned), "ramp {ramp}: {c:?}");
        if cautioned {
            assert!(c[0].starts_with("surface.lower.file") && c[0].contains("x = W"));
        }
    }
}

/// A steep height map's first refined level at a moderate pressure starts
/// from the state carried over from the case mesh (`TCGEN_LONG_TESTS=1`;
/// about 2.5 minutes and 3 GB on 2 cores). The map
/// (`tests/data/steep_heightmap.csv`, written by `scripts/steep_heightmap.py`:
/// eight plane waves, RMS 0.5 μm, RMS slope 1.34, largest 3.2) on
/// `[32, 32, 4]` / `[28, 28, 4]` (its fit within 1.3 % of the RMS) at
/// 30 kPa, plain two-phase, one level (84 168 unknowns). Before stop 105
/// Newton from the carried-over state wandered among active sets of 251–259
/// nodes at 45–630 times its tolerance until it gave up, and so did the
/// start from the configuration solved; the level was solved again from
/// rest along the pressure path, 613 s, to the plain jump 5.62874 K. With
/// an increment that raises the residual searched along
/// (`solve::newton::RISE_SEARCH_FACTOR`) it converges from the carried-over
/// state, to the same jump (docs/3d.md, "Stop 105").
#[test]
fn long_a_steep_height_maps_level_starts_from_its_carried_over_state() {
    if std::env::var("TCGEN_LONG_TESTS").map_or(true, |v| v != "1") {
        return;
    }
    // The example's case (the egg box's material and cell, p = 2), on the
    // steep map.
    let mut case = SweepConfig::read(&tables().join("heightmap_example.toml"))
        .unwrap()
        .path_case(0, 0, 0);
    case.surface.upper = BodySurface::Areal(ArealSpec::Heightmap {
        file: Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/steep_heightmap.csv"),
        file_sha256: None,
    });
    case.homogenization.method = Method::TwoPhase;
    case.load.pressures = vec![3.0e4];
    let d = &mut case.discretization;
    d.elements_upper = [32, 32, 4].into();
    d.elements_lower = [28, 28, 4].into();
    d.max_levels = 1;
    let reports = Arc::new(Mutex::new(Vec::<LevelReport>::new()));
    let seen = reports.clone();
    let observer: LevelObserver =
        Arc::new(move |r: &LevelReport| seen.lock().unwrap().push(r.clone()));
    let results = solve_case_observed(&case, None, |_| {}, Some(observer)).unwrap();
    assert!(results[0].converged, "{:?}", results[0].status);
    let reports = reports.lock().unwrap();
    let level = reports
        .iter()
        .find(|r| r.level == 1)
        .expect("level 1 reported");
    assert_eq!(level.started, None, "{level}");
    let (jump, _) = level.jump.expect("level 1 solved");
    assert!((jump - 5.62874).abs() < 1e-4 * jump, "{level}");
    assert_eq!(results[0].levels, [1, 1]);
}
