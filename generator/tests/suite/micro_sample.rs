//! The micro-sample solve (`tcgen solve`): a coarse sinusoid-on-flat sample
//! along a pressure path, by the two-phase identifications.

use std::path::Path;

use tcgen::homogenize::path::PathSolver;
use tcgen::homogenize::solve_case;
use tcgen::sample::Case;

fn case(method: &str, master: &str) -> Case {
    let text = format!(
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
elements_upper = [12, 6]
elements_lower = [10, 5]
[load]
pressures = [2.0e3, 2.0e4, 1.0e5]
flux = 1.0e6
[homogenization]
method = "{method}"
master = "{master}"
"#
    );
    Case::from_toml(&text, Path::new(".")).unwrap()
}

/// Every point converges; the jump falls and the contact fraction grows with pressure.
#[test]
fn pressure_path_converges_with_physical_trends() {
    let c = case("two-phase-self-consistent", "lower");
    let r = solve_case(&c, None, |_| {}).unwrap();
    assert!(r.iter().all(|p| p.converged), "{r:?}");
    for w in r.windows(2) {
        assert!(
            w[1].jump < w[0].jump,
            "jump must fall with pressure: {} then {}",
            w[0].jump,
            w[1].jump
        );
        assert!(w[1].interface.contact_fraction > w[0].interface.contact_fraction);
        assert!(w[1].interface.approach > w[0].interface.approach);
    }
    assert!(
        r.iter()
            .all(|p| p.self_consistency_iterations >= 2 && p.self_consistency_iterations <= 12)
    );
    assert!(
        r.iter()
            .all(|p| (p.conductance - p.flux / p.jump).abs() <= 1e-12 * p.conductance)
    );
}

/// The two-phase framework is algorithmically consistent (Sect. 3.1): the
/// continuous problems for the two master choices differ only by a
/// temperature datum, so their jumps differ only through the discretization
/// (which surface carries the mortar multipliers), and the difference shrinks
/// under refinement (on average over the path; see the figures below).
#[test]
fn two_phase_master_choice_difference_shrinks_under_refinement() {
    let diff = |scale: usize| -> Vec<f64> {
        let run = |master: &str| {
            let mut c = case("two-phase", master);
            c.discretization.elements_upper = [12 * scale, 6 * scale].into();
            c.discretization.elements_lower = [10 * scale, 5 * scale].into();
            solve_case(&c, None, |_| {}).unwrap()
        };
        let (l, u) = (run("lower"), run("upper"));
        l.iter()
            .zip(&u)
            .map(|(a, b)| {
                assert!(a.converged && b.converged, "{a:?} {b:?}");
                (a.jump - b.jump).abs() / a.jump
            })
            .collect()
    };
    // Pre-asymptotic on these meshes (measured 7.8/8.6/19 % -> 6.6/9.0/8.5 %):
    // the mean over the path must shrink.
    let (coarse, fine) = (diff(1), diff(2));
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!(
        mean(&fine) < 0.8 * mean(&coarse),
        "difference did not shrink: {coarse:?} -> {fine:?}"
    );
}

/// The multi-flux solve gives the jumps of separate single-flux solves.
#[test]
fn multi_flux_solve_matches_single_flux_solves() {
    let mut c = case("two-phase-self-consistent", "lower");
    c.load.pressures = vec![2.0e4];
    let fluxes = [2.0e5, 1.0e6];
    let mut s = PathSolver::new(&c).unwrap();
    let multi = s.solve_pressure_fluxes(2.0e4, &fluxes).unwrap();
    for (m, &h) in multi.iter().zip(&fluxes) {
        c.load.flux = h;
        let single = solve_case(&c, None, |_| {}).unwrap();
        let rel = (m.jump - single[0].jump).abs() / single[0].jump;
        // Both stop at the self-consistency tolerance (1e-6 relative).
        assert!(rel < 1e-5, "flux {h}: {} vs {}", m.jump, single[0].jump);
    }
    // Without self-consistency the jump is exactly linear in the flux.
    let mut c2 = case("two-phase", "lower");
    c2.load.pressures = vec![2.0e4];
    let mut s2 = PathSolver::new(&c2).unwrap();
    let r = s2.solve_pressure_fluxes(2.0e4, &fluxes).unwrap();
    let ratio = (r[1].jump / r[0].jump) / (fluxes[1] / fluxes[0]);
    assert!((ratio - 1.0).abs() < 1e-10, "{ratio}");
}

/// `tcgen solve` prints one row per pressure; with a sliding top face
/// (`top_lateral = "free"`) the table has the `offset/m` column, and its
/// values are the JSON `lateral_offset`.
#[test]
fn solve_table_shows_the_lateral_offset_of_a_sliding_top() {
    let dir = std::env::temp_dir().join(format!("tcgen-solve-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |top: &str, json: bool| {
        let text = format!(
            "[sample]\nwidth = 1.0e-5\nheight = 7.0e-6\ntop_lateral = \"{top}\"\n\
             [surface.upper]\nkind = \"sinusoid\"\nrms = 1.0e-6\nwavelength = 1.0e-5\nphase = 0.3\n\
             [surface.lower]\nkind = \"sinusoid\"\nrms = 5.0e-7\nwavelength = 5.0e-6\n\
             [discretization]\nelements_upper = [12, 6]\nelements_lower = [10, 5]\n\
             [load]\npressures = [5.0e3, 2.0e4]\nflux = 1.0e6\n\
             [homogenization]\nmethod = \"two-phase\"\n"
        );
        let path = dir.join(format!("{top}.toml"));
        std::fs::write(&path, text).unwrap();
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_tcgen"));
        cmd.arg("solve").arg(&path);
        if json {
            cmd.arg("--json");
        }
        let o = cmd.output().unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let fixed = run("fixed", false);
    assert!(
        !fixed.lines().next().unwrap().contains("offset/m"),
        "{fixed}"
    );
    let free = run("free", false);
    let mut lines = free.lines();
    let header: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
    let col = header
        .iter()
        .position(|h| *h == "offset/m")
        .expect("offset column");
    let offsets: Vec<f64> = lines
        .map(|l| l.split_whitespace().nth(col).unwrap().parse().unwrap())
        .collect();
    let json: Vec<f64> = run("free", true)
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            v["lateral_offset"].as_f64().unwrap()
        })
        .collect();
    assert_eq!(offsets.len(), 2);
    for (t, j) in offsets.iter().zip(&json) {
        // Printed with 5 significant digits.
        assert!((t - j).abs() <= 1e-4 * j.abs() + 1e-18, "{t} vs {j}");
    }
    // Mismatched surfaces: the body slides.
    assert!(json.iter().any(|j| j.abs() > 1e-9), "{json:?}");
    std::fs::remove_dir_all(&dir).ok();
}

/// `tcgen bench --only micro` runs the Sect. 5.7 path and reports every part
/// of a Newton iteration in both phases; too few pressures are refused. Its
/// LDLᵀ path (both phases) gives the jumps of the LU path, without falling
/// back to LU, and analyses each pattern once.
#[test]
fn micro_sample_bench_reports_the_iteration_parts() {
    let b = tcgen::bench::micro_sample_bench(2).unwrap();
    assert_eq!(b.newton_iterations.len(), 2);
    assert!(b.wall_s > 0.0 && b.newton_iterations.iter().all(|&n| n > 0));
    assert!(
        b.jump_difference < 1e-9,
        "LDLT vs LU: {:e}",
        b.jump_difference
    );
    assert_eq!(b.linear_fallbacks, 0);
    let iterations: usize = b.newton_iterations.iter().sum();
    assert!(
        b.analyses > 0 && 4 * b.analyses < iterations,
        "{} analyses",
        b.analyses
    );
    assert_eq!([b.iteration[0].kind, b.iteration[1].kind], ["LDLT + ND"; 2]);
    // Mechanical: displacements and multipliers; thermal: temperatures.
    assert!(b.iteration[0].n_eq > b.iteration[1].n_eq && b.iteration[1].n_eq > 0);
    for c in &b.iteration {
        for (name, t) in c.parts() {
            assert!(t > 0.0 && t.is_finite(), "{name}: {t}");
        }
    }
    let text = tcgen::bench::format_micro_bench(&b);
    assert!(text.contains("factorization and solve") && text.contains("mechanical"));
    let e = tcgen::bench::micro_sample_bench(1).unwrap_err().to_string();
    assert!(
        e.contains("bench.pressures") && e.contains("at least 2"),
        "{e}"
    );
}

/// Roughness taller than its body (issue 14 item 1): a sinusoid is refused
/// up front naming `sample.height` and the amplitude; a random surface that
/// reaches through its body fails the point with that error, not a panic.
#[test]
fn roughness_taller_than_the_body_is_a_clear_error() {
    let sinusoid = r#"
[sample]
width = 1.0e-5
height = 7.0e-6
[surface.upper]
kind = "sinusoid"
rms = 8.0e-6
wavelength = 1.0e-5
[surface.lower]
kind = "flat"
"#;
    let e = Case::from_toml(sinusoid, Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("sample.height") && e.contains("1.131"),
        "names the key and the amplitude √2·rms: {e}"
    );
    let random = r#"
[sample]
width = 1.0e-5
height = 1.0e-6
[surface.upper]
kind = "random"
rms = 8.0e-7
spectrum = "gaussian"
correlation_length = 2.0e-6
[surface.lower]
kind = "flat"
[discretization]
elements_upper = [12, 2]
elements_lower = [10, 2]
[load]
pressures = [1.0e4]
"#;
    let c = Case::from_toml(random, Path::new(".")).unwrap();
    let e = PathSolver::new(&c)
        .err()
        .expect("the body is folded")
        .to_string();
    assert!(e.contains("sample.height"), "{e}");
}
