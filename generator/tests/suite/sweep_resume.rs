//! Interruption and resume: a run stopped after a task, or killed,
//! leaves its checkpoint and no table at the output path; `--resume` then
//! gives the same file as an uninterrupted run.

use crate::sweep_support as support;

use std::time::{Duration, Instant};

use support::*;
use tcgen::io::read_table;
use tcgen::sweep::checkpoint::checkpoint_path;
use tcgen::sweep::{ProgressMode, SweepOptions, run_sweep};

fn tiny() -> String {
    sinusoid_sweep("[1.0e3, 4.0e3]", "[1.0e5, 3.0e5, 1.0e6]", "293.15", "")
}

#[test]
fn a_stopped_run_resumes_to_the_same_table() {
    let dir = scratch("sweep-resume");
    let (_, cfg) = config(&dir, "tiny.toml", &tiny());
    let quiet = SweepOptions {
        threads: Some(2),
        progress: ProgressMode::Quiet,
        ..SweepOptions::default()
    };
    let reference = run_sweep(&cfg, &dir.join("ref.h5"), &quiet)
        .unwrap()
        .table
        .unwrap();

    let out = dir.join("t.h5");
    let stopped = run_sweep(
        &cfg,
        &out,
        &SweepOptions {
            max_tasks: Some(1),
            threads: Some(1),
            ..quiet.clone()
        },
    )
    .unwrap();
    assert!(stopped.table.is_none());
    assert_eq!(stopped.micro_solves, 3);
    assert!(!out.exists() && checkpoint_path(&out).exists());

    // Without --resume the checkpoint is not overwritten.
    let e = run_sweep(&cfg, &out, &quiet).unwrap_err().to_string();
    assert!(e.contains("--resume"), "{e}");

    let resumed = run_sweep(
        &cfg,
        &out,
        &SweepOptions {
            resume: true,
            ..quiet.clone()
        },
    )
    .unwrap();
    assert_eq!((resumed.reused_micro_solves, resumed.micro_solves), (3, 3));
    assert!(!checkpoint_path(&out).exists());
    assert_eq!(
        normalized(&read_table(&out).unwrap()),
        normalized(&reference)
    );
}

/// Kills `tcgen sweep` once a path is in the checkpoint: no file at the
/// output path; `--resume` completes it to the uninterrupted table.
#[test]
fn a_killed_run_leaves_no_table_and_resumes() {
    let dir = scratch("sweep-kill");
    let (cfg_path, cfg) = config(&dir, "tiny.toml", &tiny());
    let out = dir.join("t.h5");
    let ckpt = checkpoint_path(&out);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_tcgen"))
        .args(["sweep", "--threads", "1", "--progress", "quiet", "-o"])
        .arg(&out)
        .arg(&cfg_path)
        .stdout(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        let lines = std::fs::read_to_string(&ckpt).map_or(0, |t| t.lines().count());
        if lines >= 2 {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(300),
            "no path finished"
        );
        if let Some(s) = child.try_wait().unwrap() {
            panic!("tcgen sweep ended before the kill: {s}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!out.exists(), "a killed run left a file at the output path");
    assert!(ckpt.exists());

    let status = std::process::Command::new(env!("CARGO_BIN_EXE_tcgen"))
        .args(["sweep", "--resume", "--progress", "log", "-o"])
        .arg(&out)
        .arg(&cfg_path)
        .stdout(std::process::Stdio::null())
        .status()
        .unwrap();
    assert!(status.success());
    assert!(!ckpt.exists());
    let reference = run_sweep(
        &cfg,
        &dir.join("ref.h5"),
        &SweepOptions {
            progress: ProgressMode::Quiet,
            ..SweepOptions::default()
        },
    )
    .unwrap()
    .table
    .unwrap();
    let mut resumed = read_table(&out).unwrap();
    // The binary records the path it was given; the reference, the same file.
    resumed.info.source = reference.info.source.clone();
    assert_eq!(normalized(&resumed), normalized(&reference));
}
