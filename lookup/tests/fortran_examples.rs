//! The Fortran examples (`examples/lookup_c.f`, `examples/calculix_gapcon.f`,
//! `examples/abaqus_gapcon.f`): compiled with `gfortran` against the static
//! library, driven like CalculiX and Abaqus would call them, and their
//! conductance compared with `Law::eval_at_jump`. Needs `gfortran`; where it
//! is not installed the test says so and checks nothing else.

mod common;

use common::*;
use lookup::{Extrapolation, Law};
use std::path::{Path, PathBuf};
use std::process::Command;

fn gfortran_available() -> bool {
    Command::new("gfortran")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

fn build(manifest: &Path, tmp: &Path, example: &str, driver: &str, name: &str) -> PathBuf {
    let lib = library_dir("liblookup.a").join("liblookup.a");
    let exe = tmp.join(name);
    let status = Command::new("gfortran")
        .current_dir(tmp)
        .args(["-fopenmp", "-I."])
        .arg(manifest.join("examples/lookup_c.f"))
        .arg(manifest.join("examples").join(example))
        .arg(manifest.join("tests/fortran").join(driver))
        .arg(&lib)
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(&exe)
        .status()
        .expect("run gfortran");
    assert!(status.success(), "gfortran failed for {example}");
    exe
}

fn run(exe: &Path, law: &Path, q: [f64; 3]) -> (bool, String) {
    let out = Command::new(exe)
        .current_dir(exe.parent().unwrap())
        .env("TCGEN_LAW", law)
        .args(q.map(|x| format!("{x:e}")))
        .output()
        .expect("run the Fortran driver");
    let text =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    (out.status.success(), text)
}

fn numbers(text: &str, prefix: &str) -> Vec<f64> {
    let line = text
        .lines()
        .find_map(|l| l.trim().strip_prefix(prefix))
        .unwrap_or_else(|| panic!("no {prefix:?} in {text}"));
    line.split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect()
}

#[test]
fn fortran_gapcon_examples_match_the_library() {
    if !gfortran_available() {
        println!("gfortran not found: the Fortran examples were not compiled");
        return;
    }
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fortran");
    std::fs::create_dir_all(&tmp).unwrap();
    std::fs::write(
        tmp.join("ABA_PARAM.INC"),
        "      implicit real*8(a-h,o-z)\n",
    )
    .unwrap();
    let law_path = tmp.join("law.tclaw");
    let mut law = physical_law(Extrapolation::Clamp);
    law.write(&law_path).unwrap();
    law.set_max_conductance(Some(1e9)).unwrap(); // as the examples do
    let corrupt = tmp.join("corrupt.tclaw");
    let mut bytes = law.to_bytes();
    let i = bytes.len() - 50;
    bytes[i] ^= 1;
    std::fs::write(&corrupt, bytes).unwrap();

    let ccx = build(
        &manifest,
        &tmp,
        "calculix_gapcon.f",
        "calculix_driver.f90",
        "ccx_driver",
    );
    let abq = build(
        &manifest,
        &tmp,
        "abaqus_gapcon.f",
        "abaqus_driver.f90",
        "abaqus_driver",
    );
    // (pressure, slave temperature, master temperature)
    let queries = [
        [3e5, 320.0, 310.0],
        [2e7, 300.5, 300.0],
        [5e3, 290.0, 350.0],
        [1e6, 300.0, 300.0],
    ];
    for q in queries {
        let w = law.eval_at_jump(q[0], (q[1] - q[2]).abs(), q[2]).unwrap();
        let (ok, text) = run(&ccx, &law_path, q);
        assert!(ok, "{text}");
        let ak = numbers(&text, "ak1 ");
        assert!(
            (ak[0] - w.conductance).abs() <= 1e-14 * w.conductance,
            "ccx {q:?}: {text} vs {w:?}"
        );
        let (ok, text) = run(&abq, &law_path, q);
        assert!(ok, "{text}");
        let ak = numbers(&text, "ak1 ak3 ");
        assert!(
            (ak[0] - w.conductance).abs() <= 1e-14 * w.conductance,
            "abaqus {q:?}: {text}"
        );
        assert!(
            (ak[1] - w.d_conductance_dp).abs() <= 1e-14 * w.d_conductance_dp.abs(),
            "abaqus AK(3) {q:?}: {text}"
        );
    }
    // Inside the table: no warning. Outside, under the clamp policy: the
    // conductance of the bound, and a warning naming the query.
    let (ok, text) = run(&ccx, &law_path, queries[0]);
    assert!(ok && !text.contains("WARNING"), "{text}");
    let lo = law.axes().pressure[0];
    let outside = [lo / 10.0, 320.0, 310.0];
    let w = law.eval_at_jump(outside[0], 10.0, 310.0).unwrap();
    assert!(w.extrapolated[0]);
    let (ok, text) = run(&ccx, &law_path, outside);
    assert!(
        ok && text.contains("*WARNING in gapcon: element 1")
            && text.contains("outside the law table"),
        "{text}"
    );
    assert!((numbers(&text, "ak1 ")[0] - w.conductance).abs() <= 1e-14 * w.conductance);
    let _ = std::fs::remove_file(tmp.join("fort.7"));
    let (ok, text) = run(&abq, &law_path, outside);
    let msg = std::fs::read_to_string(tmp.join("fort.7")).unwrap_or_default();
    assert!(
        ok && text.contains("STDB_ABQERR -1") && msg.contains("outside the law table"),
        "{text} / {msg}"
    );
    // The same law under the default policy 'error': the analysis stops
    // with the library's out-of-range message.
    let strict = tmp.join("strict.tclaw");
    physical_law(Extrapolation::Error).write(&strict).unwrap();
    let (ok, text) = run(&ccx, &strict, outside);
    assert!(!ok && text.contains("outside"), "{text}");
    // No contact pressure: no conductance.
    let (ok, text) = run(&ccx, &law_path, [0.0, 320.0, 310.0]);
    assert!(ok && numbers(&text, "ak1 ")[0] == 0.0, "{text}");
    // A corrupted law stops the analysis with the library's message.
    let (ok, text) = run(&ccx, &corrupt, [3e5, 320.0, 310.0]);
    assert!(!ok && text.contains("CRC-32"), "{text}");
    let _ = std::fs::remove_file(tmp.join("fort.7"));
    let (ok, text) = run(&abq, &corrupt, [3e5, 320.0, 310.0]);
    let msg = std::fs::read_to_string(tmp.join("fort.7")).unwrap_or_default();
    assert!(
        !ok && text.contains("STDB_ABQERR -3") && msg.contains("CRC-32"),
        "{text} / {msg}"
    );
    let _ = Law::open(&law_path).unwrap();
}
