//! Provenance of generated files: generator version, git revision, UTC time.

/// `tcgen <version>`.
pub fn generator() -> String {
    format!("tcgen {}", env!("CARGO_PKG_VERSION"))
}

/// The git revision of the generator: `TCGEN_GIT_REVISION` at build time (set
/// by `scripts/nightly.sh` and CI), else `git describe` of the source tree the
/// binary was built from, asked at run time (marked so), else `"unknown"`.
pub fn git_revision() -> String {
    if let Some(r) = option_env!("TCGEN_GIT_REVISION").filter(|r| !r.is_empty()) {
        return r.to_string();
    }
    let out = std::process::Command::new("git")
        .args(["describe", "--always", "--dirty", "--abbrev=12"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stderr(std::process::Stdio::null())
        .output();
    match out {
        Ok(o) if o.status.success() => format!(
            "{} (source tree at run time)",
            String::from_utf8_lossy(&o.stdout).trim()
        ),
        _ => "unknown".into(),
    }
}

/// The current UTC time as ISO 8601, `YYYY-MM-DDTHH:MM:SSZ`.
pub fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    utc_iso8601(secs)
}

/// Seconds since the Unix epoch as ISO 8601 UTC (proleptic Gregorian calendar).
pub fn utc_iso8601(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    // Civil from days (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        (rem / 60) % 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn iso8601_of_known_instants() {
        assert_eq!(utc_iso8601(0), "1970-01-01T00:00:00Z");
        assert_eq!(utc_iso8601(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(utc_iso8601(1_700_000_000), "2023-11-14T22:13:20Z");
    }
}
