//! The reference table: `tables/reference.toml` rebuilt must reproduce the
//! committed `tables/reference.h5` — the same grid and statuses, and the
//! jump, conductance and mean gap within a relative 1e-6, the contact
//! fraction within 1e-9 (iteration counts are not compared). A difference
//! means the physics changed; if that is intended, regenerate the reference
//! with `TCGEN_BLESS=1 cargo test --release -p tcgen --test suite sweep_reference::`
//! and commit `tables/reference.h5`.

use std::path::Path;

use tcgen::io::{PointStatus, read_table, write_table};
use tcgen::sweep::{ProgressMode, SweepConfig, SweepOptions, run_sweep};

#[test]
fn reference_table_is_reproduced() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let reference_path = root.join("tables/reference.h5");
    let mut cfg = SweepConfig::read(&root.join("tables/reference.toml")).unwrap();
    cfg.source = "tables/reference.toml".into();
    let out =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("reference-{}.h5", std::process::id()));
    let options = SweepOptions {
        progress: ProgressMode::Quiet,
        ..SweepOptions::default()
    };
    let new = run_sweep(&cfg, &out, &options).unwrap().table.unwrap();
    if std::env::var_os("TCGEN_BLESS").is_some() {
        write_table(&new, &reference_path).unwrap();
        eprintln!("wrote {}", reference_path.display());
        return;
    }
    let old = read_table(&reference_path).unwrap();
    let regenerate = "if the change is intended, regenerate with \
        TCGEN_BLESS=1 cargo test --release -p tcgen --test suite sweep_reference:: and commit tables/reference.h5";
    assert_eq!(
        old.info.config_sha256, new.info.config_sha256,
        "tables/reference.toml changed; {regenerate}"
    );
    assert_eq!(
        (
            &old.pressure,
            &old.flux,
            &old.contact_temperature,
            old.samples
        ),
        (
            &new.pressure,
            &new.flux,
            &new.contact_temperature,
            new.samples
        )
    );
    assert!(old.count(PointStatus::Converged) > 0);
    for (i, (a, b)) in old.points.iter().zip(&new.points).enumerate() {
        assert_eq!(
            a.status, b.status,
            "point {i}: status changed; {regenerate}"
        );
        if let (Some(a), Some(b)) = (a.values, b.values) {
            let rel = |x: f64, y: f64| (x - y).abs() / x.abs().max(1e-300);
            for (name, x, y) in [
                ("jump", a.jump, b.jump),
                ("conductance", a.conductance, b.conductance),
                ("mean_gap", a.mean_gap, b.mean_gap),
            ] {
                assert!(
                    rel(x, y) <= 1e-6,
                    "point {i}: {name} {y} vs reference {x} (relative {:e} > 1e-6); {regenerate}",
                    rel(x, y)
                );
            }
            assert!(
                (a.contact_fraction - b.contact_fraction).abs() <= 1e-9,
                "point {i}: contact fraction {} vs reference {}; {regenerate}",
                b.contact_fraction,
                a.contact_fraction
            );
        }
    }
}
