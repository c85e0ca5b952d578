//! The crate has no dependencies (dev-dependencies allowed): its manifest
//! declares no `[dependencies]`, `[build-dependencies]` or target-specific ones.

#[test]
fn manifest_declares_no_dependencies() {
    let manifest =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml")).unwrap();
    for line in manifest.lines().map(str::trim) {
        let forbidden = line.starts_with("[dependencies")
            || line.starts_with("[build-dependencies")
            || (line.starts_with("[target.") && line.contains("dependencies"))
            || line.starts_with("dependencies.");
        assert!(!forbidden, "lookup must stay dependency-free: {line}");
    }
    assert!(
        manifest.contains("[dev-dependencies]"),
        "manifest not read as expected"
    );
}
