//! The C ABI: compiles `tests/c/test_lookup.c` with `cc` against the static
//! and the shared library that cargo built next to this test, runs it, and
//! checks its output against the Rust API (struct sizes, status codes, and
//! the values it printed, bit for bit).

mod common;

use common::library_dir;
use lookup::Law;
use lookup::ffi::{self, LookupFluxValue, LookupValue};
use std::path::{Path, PathBuf};
use std::process::Command;

fn compile(manifest: &Path, out: &Path, link: &[String]) -> PathBuf {
    let status = Command::new("cc")
        .args([
            "-std=c99",
            "-Wall",
            "-Wextra",
            "-Werror",
            "-pedantic",
            "-O1",
        ])
        .arg("-I")
        .arg(manifest.join("include"))
        .arg(manifest.join("tests/c/test_lookup.c"))
        .args(link)
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(out)
        .status()
        .expect("run cc (a C compiler is needed for this test)");
    assert!(status.success(), "cc failed for {}", out.display());
    out.to_path_buf()
}

fn run(exe: &Path, dir: &Path) -> String {
    let output = Command::new(exe).arg(dir).output().expect("run the C test");
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    println!("{stdout}{}", String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "C test failed:\n{stdout}");
    stdout
}

fn field<'a>(out: &'a str, prefix: &str) -> &'a str {
    out.lines()
        .find_map(|l| l.strip_prefix(prefix))
        .unwrap_or_else(|| panic!("no line {prefix:?} in output"))
        .trim()
}

fn check_output(out: &str, dir: &Path) {
    assert_eq!(
        field(out, "sizeof lookup_value "),
        size_of::<LookupValue>().to_string()
    );
    assert_eq!(
        field(out, "sizeof lookup_flux_value "),
        size_of::<LookupFluxValue>().to_string()
    );
    assert_eq!(
        field(out, "format_version "),
        lookup::FORMAT_VERSION.to_string()
    );
    assert_eq!(
        field(out, "status LOOKUP_ERR_OUT_OF_RANGE "),
        format!("{} LOOKUP_ERR_OUT_OF_RANGE", ffi::LOOKUP_ERR_OUT_OF_RANGE)
    );
    assert_eq!(
        field(out, "status LOOKUP_ERR_PANIC "),
        format!("{} LOOKUP_ERR_PANIC", ffi::LOOKUP_ERR_PANIC)
    );
    assert!(field(out, "message corrupted ").contains("CRC-32"));
    let summary = field(out, "c-abi: ");
    assert!(
        summary.ends_with(" 0 failed") && !summary.starts_with("0 passed"),
        "{summary}"
    );

    // The file the C program wrote, evaluated here with the same override.
    let mut law = Law::open(dir.join("c_written.tclaw")).expect("C-written law");
    let mut policy = law.options().extrapolation;
    policy.pressure = lookup::Extrapolation::Clamp;
    law.set_extrapolation(policy).unwrap();
    let mut values = 0;
    for line in out.lines().filter_map(|l| l.strip_prefix("value ")) {
        let f: Vec<&str> = line.split_whitespace().collect();
        let num = |i: usize| f[i].parse::<f64>().unwrap();
        let status: i32 = f[3].parse().unwrap();
        match law.eval(num(0), num(1), num(2)) {
            Ok(v) => {
                assert_eq!(status, ffi::LOOKUP_OK, "{line}");
                let c = LookupValue::new(v, law.error_estimated());
                let expect = [
                    c.jump,
                    c.d_jump_dp,
                    c.d_jump_dh,
                    c.conductance,
                    c.d_conductance_dp,
                ];
                for (k, e) in expect.iter().enumerate() {
                    assert_eq!(num(4 + k).to_bits(), e.to_bits(), "{line}: field {k}");
                }
                assert_eq!(f[9], c.flags.to_string());
            }
            Err(_) => assert_ne!(status, ffi::LOOKUP_OK, "{line}"),
        }
        values += 1;
    }
    assert_eq!(values, 4);
}

#[test]
fn c_program_uses_the_static_and_shared_library() {
    let manifest = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let tmp = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("c_abi");
    std::fs::create_dir_all(&tmp).unwrap();

    let dir = library_dir("liblookup.a");
    let exe = compile(
        &manifest,
        &tmp.join("test_lookup_static"),
        &[dir.join("liblookup.a").display().to_string()],
    );
    let out_static = tmp.join("static");
    std::fs::create_dir_all(&out_static).unwrap();
    check_output(&run(&exe, &out_static), &out_static);

    let so = if cfg!(target_os = "macos") {
        "liblookup.dylib"
    } else {
        "liblookup.so"
    };
    let dir = library_dir(so);
    let exe = compile(
        &manifest,
        &tmp.join("test_lookup_shared"),
        &[
            dir.join(so).display().to_string(),
            format!("-Wl,-rpath,{}", dir.display()),
        ],
    );
    let out_shared = tmp.join("shared");
    std::fs::create_dir_all(&out_shared).unwrap();
    check_output(&run(&exe, &out_shared), &out_shared);
}
