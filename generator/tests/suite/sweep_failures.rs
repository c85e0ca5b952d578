//! Failure masking and random-surface determinism in sweeps. The sweep's
//! micro-solves fail at once (one Newton iteration allowed), so every point
//! is recorded as failed with its reason and masked by `_FillValue` (never
//! NaN); the exit status is 1 unless `--allow-failures`; `tcgen law` refuses
//! the table. The random surfaces of each sample (two-sided: self-affine
//! upper, Gaussian lower) are the same whatever the thread count and shard
//! split, and are those of `RandomSpec::generate` for `(seed, sample)`.

use crate::sweep_support as support;

use std::process::Command;

use support::*;
use tcgen::io::netcdf::FILL_DOUBLE;
use tcgen::io::{PointStatus, read_table};
use tcgen::sample::case::BodySurface;
use tcgen::surface::SurfaceSpec;
use tcgen::sweep::{ProgressMode, Shard, SweepOptions, merge_tables, run_sweep};

#[test]
fn failed_points_are_masked_counted_and_refused_by_law() {
    let dir = scratch("sweep-failures");
    let (cfg_path, cfg) = config(&dir, "fail.toml", &failing_random_sweep(3));
    let out = dir.join("t.h5");
    let tcgen = env!("CARGO_BIN_EXE_tcgen");
    let o = Command::new(tcgen)
        .args(["sweep", "--progress", "quiet", "-o"])
        .arg(&out)
        .arg(&cfg_path)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("0 converged, 12 failed points"), "{stdout}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("--allow-failures"));

    let t = read_table(&out).unwrap();
    assert_eq!(t.count(PointStatus::Failed), 12);
    assert!(
        t.points
            .iter()
            .all(|p| !p.reason.is_empty() && p.values.is_none())
    );
    // Raw values: the fill value, never NaN.
    let f = netcdf_reader::NcFile::open(&out).unwrap();
    for name in [
        "jump",
        "conductance",
        "contact_fraction",
        "mean_gap",
        "jump_mean",
        "jump_std",
    ] {
        let v = f.read_variable::<f64>(name).unwrap();
        assert!(v.iter().all(|x| *x == FILL_DOUBLE), "{name}");
    }
    let conv = f.read_variable::<i32>("converged_samples").unwrap();
    assert!(conv.iter().all(|&n| n == 0));
    // Surfaces were built and measured although the solves failed.
    assert!(t.surfaces.iter().all(|s| s.is_some()));

    // --allow-failures: exit 0 (after deleting nothing: the table is rewritten).
    let o = Command::new(tcgen)
        .args(["sweep", "--allow-failures", "--progress", "quiet", "-o"])
        .arg(&out)
        .arg(&cfg_path)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0));

    let law = dir.join("t.tclaw");
    let o = Command::new(tcgen)
        .args(["law", "-o"])
        .arg(&law)
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("12 masked point(s)") && err.contains("failed"),
        "{err}"
    );
    assert!(!law.exists());

    // The surfaces of every sample are those of (seed, sample), on any split.
    for s in 0..3 {
        let case = cfg.path_case(s, 0, 0);
        let rms = |spec: &BodySurface, key: &str| match spec.profile() {
            Some(SurfaceSpec::Random(r)) => r.generate(key, 1.0e-5).rms(),
            _ => unreachable!(),
        };
        let m = t.surfaces[s].unwrap();
        let (u, l) = (
            rms(&case.surface.upper, "surface.upper"),
            rms(&case.surface.lower, "surface.lower"),
        );
        assert!((m.upper_rms / u - 1.0).abs() < 1e-9, "{} {u}", m.upper_rms);
        assert!((m.lower_rms / l - 1.0).abs() < 1e-9, "{} {l}", m.lower_rms);
        assert_ne!(m.upper_rms, m.lower_rms);
    }
    let quiet = |threads, shard| SweepOptions {
        threads: Some(threads),
        shard,
        progress: ProgressMode::Quiet,
        ..SweepOptions::default()
    };
    let one = run_sweep(&cfg, &dir.join("one.h5"), &quiet(1, Shard::ALL))
        .unwrap()
        .table
        .unwrap();
    assert_eq!(normalized(&one), normalized(&t));
    let shards: Vec<_> = (0..2)
        .map(|i| {
            let p = dir.join(format!("s{i}.h5"));
            run_sweep(&cfg, &p, &quiet(2, Shard::new(i, 2).unwrap())).unwrap();
            read_table(&p).unwrap()
        })
        .collect();
    let merged = merge_tables(&shards).unwrap();
    assert_eq!(normalized(&merged), normalized(&t));
}
