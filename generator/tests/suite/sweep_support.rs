//! Shared helpers of the `sweep_*` integration tests (`crate::sweep_support`);
//! its own tests check that the tiny configurations parse.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use tcgen::io::Table;
use tcgen::sweep::SweepConfig;

/// A symmetric sinusoid on a flat at a coarse resolution: each micro-solve
/// takes about a second. `extra` is appended (e.g. solver settings).
pub fn sinusoid_sweep(pressures: &str, fluxes: &str, temperatures: &str, extra: &str) -> String {
    format!(
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
degree = 2
elements_upper = [8, 4]
elements_lower = [7, 4]
{extra}
[sweep]
pressures = {pressures}
fluxes = {fluxes}
contact_temperatures = {temperatures}
continuation = false
"#
    )
}

/// Two-sided random surfaces whose micro-solves fail at once (one Newton
/// iteration, no load-step cut-back): fast sweeps that exercise failure
/// masking and the per-sample surface measures.
pub fn failing_random_sweep(samples: usize) -> String {
    format!(
        r#"
[sample]
width = 1.0e-5
height = 7.0e-6
[surface.upper]
kind = "random"
rms = 5.0e-7
spectrum = "self-affine"
hurst = 0.7
cutoff_wavelength = 1.25e-6
[surface.lower]
kind = "random"
rms = 5.0e-7
spectrum = "gaussian"
correlation_length = 2.5e-6
[discretization]
degree = 2
elements_upper = [8, 4]
elements_lower = [7, 4]
[solver.newton]
max_iterations = 1
[solver.stepping]
min_step = 0.9
[sweep]
pressures = [1.0e3, 1.0e4]
fluxes = [1.0e5, 1.0e6]
contact_temperatures = 293.15
samples = {samples}
seed = 1
"#
    )
}

/// A fresh directory under the target directory.
pub fn scratch(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes a configuration and reads it back.
pub fn config(dir: &Path, name: &str, text: &str) -> (PathBuf, SweepConfig) {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    let c = SweepConfig::read(&p).unwrap();
    (p, c)
}

/// The file bytes of a table with the run-dependent attributes (creation
/// time, wall time, threads) blanked: equal bytes mean equal data and equal
/// provenance otherwise.
pub fn normalized(t: &Table) -> Vec<u8> {
    let mut t = t.clone();
    t.info.created = String::new();
    t.info.wall_time = 0.0;
    t.info.threads = vec![0];
    tcgen::io::table_to_bytes(&t).unwrap()
}

#[test]
fn tiny_configurations_parse() {
    let d = scratch("sweep-support");
    config(
        &d,
        "a.toml",
        &sinusoid_sweep("[1.0e3]", "1.0e5", "293.15", ""),
    );
    config(&d, "b.toml", &failing_random_sweep(2));
}
