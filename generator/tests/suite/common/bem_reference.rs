//! The committed boundary-element references (`tests/data/*_tamaas.csv`,
//! written by `scripts/tamaas_reference*.py`): `# key = value` header
//! lines, a column line, then one row of numbers per pressure. Used by the
//! `independent_bem*` tests (`crate::bem_reference`).
#![allow(dead_code)]

/// A reference file's text.
pub struct Reference(String);

impl Reference {
    /// Reads `tests/data/<name>`.
    pub fn read(name: &str) -> Self {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/").to_string() + name;
        Reference(std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}")))
    }

    /// The whole text.
    pub fn text(&self) -> &str {
        &self.0
    }

    /// The value of the header line `# key = value`.
    pub fn header(&self, key: &str) -> f64 {
        self.0
            .lines()
            .find_map(|l| l.strip_prefix(&format!("# {key} = ")))
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or_else(|| panic!("{key} in the reference header"))
    }

    /// The rows of numbers (after the header and the column line).
    pub fn rows(&self) -> Vec<Vec<f64>> {
        self.0
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("pressure"))
            .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
            .collect()
    }

    /// Asserts that the heights `z` are those the reference was computed
    /// for: their RMS and lowest value match `# {prefix}_rms` and
    /// `# {prefix}_lowest` to 1e-6 (the random stream and the fit unchanged).
    pub fn assert_surface(&self, z: &[f64], prefix: &str) {
        let n = z.len() as f64;
        let mean = z.iter().sum::<f64>() / n;
        let rms = (z.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
        let lowest = z.iter().copied().fold(f64::INFINITY, f64::min);
        let rms_ref = self.header(&format!("{prefix}_rms"));
        let lowest_ref = self.header(&format!("{prefix}_lowest"));
        assert!(
            (rms / rms_ref - 1.0).abs() < 1e-6,
            "{prefix} rms {rms} vs {rms_ref}"
        );
        assert!(
            (lowest / lowest_ref - 1.0).abs() < 1e-6,
            "{prefix} minimum {lowest} vs {lowest_ref}"
        );
    }
}
