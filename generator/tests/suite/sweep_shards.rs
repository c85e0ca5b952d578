//! Shards and merge: the shards of a sweep merged give the table of a single
//! run, bit for bit (the file bytes, with the creation time, wall time and
//! thread count blanked), whatever the thread count or the shard split
//! (an empty shard included).

use crate::sweep_support as support;

use support::*;
use tcgen::io::{PointStatus, read_table};
use tcgen::sweep::{ProgressMode, Shard, SweepOptions, merge_tables, run_sweep};

fn options(threads: usize, shard: Shard) -> SweepOptions {
    SweepOptions {
        threads: Some(threads),
        shard,
        progress: ProgressMode::Quiet,
        ..SweepOptions::default()
    }
}

#[test]
fn merged_shards_equal_a_single_run_bit_for_bit() {
    let dir = scratch("sweep-shards");
    // 2 fluxes × 2 temperatures = 4 paths of 2 pressures.
    let (_, cfg) = config(
        &dir,
        "tiny.toml",
        &sinusoid_sweep("[1.0e3, 4.0e3]", "[1.0e5, 1.0e6]", "[293.15, 313.15]", ""),
    );
    let single = dir.join("single.h5");
    let r = run_sweep(&cfg, &single, &options(2, Shard::ALL)).unwrap();
    let whole = r.table.unwrap();
    assert_eq!(whole.count(PointStatus::Converged), 8, "{:?}", whole.points);
    assert!(!tcgen::sweep::checkpoint::checkpoint_path(&single).exists());
    // The file reads back as written.
    assert_eq!(read_table(&single).unwrap(), whole);

    // Shards of 3: the two (sample, temperature) groups of 2 fluxes, and an empty shard.
    let mut shards = Vec::new();
    for i in [2, 0, 1] {
        let out = dir.join(format!("shard{i}.h5"));
        let r = run_sweep(&cfg, &out, &options(1, Shard::new(i, 3).unwrap())).unwrap();
        assert_eq!(r.shard_paths, if i == 2 { 0 } else { 2 });
        shards.push(read_table(&out).unwrap());
    }
    let merged = merge_tables(&shards).unwrap();
    assert_eq!(merged.points, whole.points);
    assert_eq!(normalized(&merged), normalized(&whole));

    // The binary's merge writes the same file.
    let out = dir.join("merged.h5");
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_tcgen"))
        .args(["merge", "-o"])
        .arg(&out)
        .args((0..3).map(|i| dir.join(format!("shard{i}.h5"))))
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(normalized(&read_table(&out).unwrap()), normalized(&whole));

    // A missing shard is refused.
    let e = merge_tables(&shards[..2]).unwrap_err().to_string();
    assert!(e.contains("missing shard(s) 1/3"), "{e}");
}
