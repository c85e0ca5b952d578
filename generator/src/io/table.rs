//! The table of a sweep in memory: the grid, one record per point and
//! sample, the per-sample surface measures and the provenance. Its file form
//! (netCDF-4) is in [`crate::io::netcdf`] and specified in `schemas/table.md`.

use crate::sweep::Shard;
use crate::sweep::ensemble::{EnsembleStatistics, ensemble_statistics};

/// Name of the table schema (global attribute `schema`).
pub const SCHEMA_NAME: &str = "tcgen-table";

/// Version of the table schema (global attribute `schema_version`). It
/// changes with the layout, the meaning of a variable, or the random-surface
/// algorithm ([`crate::surface::random::RANDOM_SURFACE_VERSION`]).
pub const SCHEMA_VERSION: i32 = 2;

/// What became of one grid point of one sample (variable `status`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(i8)]
pub enum PointStatus {
    /// Converged: the values are valid.
    Converged = 0,
    /// The micro-solve failed; `failure_reason` says why; values masked.
    Failed = 1,
    /// Not computed in this file: it belongs to another shard; values masked.
    NotComputed = 2,
}

impl PointStatus {
    /// The status of a stored code.
    pub fn from_code(code: i8) -> Option<Self> {
        match code {
            0 => Some(PointStatus::Converged),
            1 => Some(PointStatus::Failed),
            2 => Some(PointStatus::NotComputed),
            _ => None,
        }
    }

    /// The CF `flag_meanings` word of this status.
    pub fn meaning(self) -> &'static str {
        match self {
            PointStatus::Converged => "converged",
            PointStatus::Failed => "failed",
            PointStatus::NotComputed => "not_computed",
        }
    }
}

/// The values of a converged point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointValues {
    /// Macroscopic jump `|ϑ̄c|` (K), Eq. (2.6).
    pub jump: f64,
    /// Macroscopic conductance `|h̄|/jump` (W/(m² K)), Eq. (2.7).
    pub conductance: f64,
    /// Real contact area fraction.
    pub contact_fraction: f64,
    /// Mean gap over the slave surface (m).
    pub mean_gap: f64,
    /// Self-consistency iterations (Sect. 3.3).
    pub self_consistency_iterations: u32,
    /// Newton iterations of the point (all phases).
    pub newton_iterations: u32,
    /// Estimated discretization error of `jump` (K), with a target error
    /// (adaptive refinement); `None` on a fixed mesh.
    pub jump_error: Option<f64>,
    /// Whether the estimate met the target error (`None`: fixed mesh).
    pub error_target_met: Option<bool>,
    /// Unknowns of the mesh of the jump.
    pub dofs: u32,
}

/// One point of one sample.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRecord {
    /// Status.
    pub status: PointStatus,
    /// Why the point failed (empty when converged).
    pub reason: String,
    /// The values, present exactly when converged.
    pub values: Option<PointValues>,
}

impl PointRecord {
    /// A converged point.
    pub fn converged(values: PointValues) -> Self {
        PointRecord {
            status: PointStatus::Converged,
            reason: String::new(),
            values: Some(values),
        }
    }

    /// A failed point with its reason.
    pub fn failed(reason: impl Into<String>) -> Self {
        PointRecord {
            status: PointStatus::Failed,
            reason: reason.into(),
            values: None,
        }
    }

    /// A point that belongs to another shard.
    pub fn not_computed() -> Self {
        PointRecord {
            status: PointStatus::NotComputed,
            reason: String::new(),
            values: None,
        }
    }
}

/// Measures of one sample's surfaces (the same for every path of the sample).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleSurfaces {
    /// RMS of the upper surface over one period (m).
    pub upper_rms: f64,
    /// RMS of the lower surface over one period (m).
    pub lower_rms: f64,
    /// Largest height error of the upper surface's NURBS fit (m).
    pub upper_fit_error: f64,
    /// Largest height error of the lower surface's NURBS fit (m).
    pub lower_fit_error: f64,
}

/// The sample's spatial dimension (`sample.dimension`, 2 when absent) and
/// its periodic cell, `[W]` (2D) or `[W, W]` (3D) in m (`sample.width`),
/// read from a resolved configuration; `None` when it does not parse.
pub fn sample_cell(config: &str) -> Option<(usize, Vec<f64>)> {
    let t: toml::Table = config.parse().ok()?;
    let sample = t.get("sample")?.as_table()?;
    let dimension = match sample.get("dimension") {
        None => 2,
        Some(v) => usize::try_from(v.as_integer()?).ok()?,
    };
    let width = sample.get("width")?.as_float()?;
    Some((dimension, vec![width; dimension.saturating_sub(1)]))
}

/// Provenance and configuration of a table.
#[derive(Clone, Debug, PartialEq)]
pub struct TableInfo {
    /// The resolved sweep configuration (TOML, every key explicit).
    pub config: String,
    /// SHA-256 of `config`.
    pub config_sha256: String,
    /// The file the configuration was read from.
    pub source: String,
    /// The ensemble seed `k`.
    pub seed: u64,
    /// The identification of the jump (`homogenization.method`).
    pub identification: String,
    /// Generator name and version.
    pub generator: String,
    /// Git revision of the generator.
    pub git_revision: String,
    /// Creation time (UTC, ISO 8601).
    pub created: String,
    /// Wall time of the run (s); the sum over the shards for a merged table.
    pub wall_time: f64,
    /// Worker threads of the run (one entry per shard for a merged table).
    pub threads: Vec<i32>,
    /// The shard this file holds, `None` for a complete table.
    pub shard: Option<Shard>,
    /// The case's known limits ([`crate::sample::Case::cautions`]), which
    /// `tcgen sweep` printed before it ran; empty where there are none.
    pub cautions: Vec<String>,
}

/// A sweep's table: `points` is indexed `[pressure][flux][contact_temperature][sample]`
/// (sample fastest), see [`Table::index`].
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Pressures `p̄N` (Pa), increasing.
    pub pressure: Vec<f64>,
    /// Flux magnitudes `|h̄|` (W/m²), increasing.
    pub flux: Vec<f64>,
    /// Contact temperatures `θ̄c` (K), increasing.
    pub contact_temperature: Vec<f64>,
    /// Number of surface samples.
    pub samples: usize,
    /// One record per grid point and sample.
    pub points: Vec<PointRecord>,
    /// Surface measures per sample (`None` where no path of the sample was computed).
    pub surfaces: Vec<Option<SampleSurfaces>>,
    /// Provenance.
    pub info: TableInfo,
}

impl Table {
    /// The grid shape `[n_p, n_h, n_θ, n_s]`.
    pub fn shape(&self) -> [usize; 4] {
        [
            self.pressure.len(),
            self.flux.len(),
            self.contact_temperature.len(),
            self.samples,
        ]
    }

    /// The index of `(pressure, flux, contact temperature, sample)` in `points`.
    #[track_caller]
    pub fn index(&self, ip: usize, ih: usize, it: usize, is: usize) -> usize {
        let [np, nh, nt, ns] = self.shape();
        assert!(
            ip < np && ih < nh && it < nt && is < ns,
            "Table::index: ({ip}, {ih}, {it}, {is}) outside {np}×{nh}×{nt}×{ns}"
        );
        ((ip * nh + ih) * nt + it) * ns + is
    }

    /// The record of one point.
    pub fn point(&self, ip: usize, ih: usize, it: usize, is: usize) -> &PointRecord {
        &self.points[self.index(ip, ih, it, is)]
    }

    /// Number of points with the given status.
    pub fn count(&self, status: PointStatus) -> usize {
        self.points.iter().filter(|p| p.status == status).count()
    }

    /// Ensemble statistics over the samples of every `(pressure, flux, contact temperature)`.
    pub fn statistics(&self) -> EnsembleStatistics {
        ensemble_statistics(self)
    }

    /// Checks the internal consistency (sizes, statuses, values); a table read
    /// from a file or merged from shards passes it.
    pub fn check(&self) -> crate::Result<()> {
        let n: usize = self.shape().iter().product();
        let bad = |what: String| Err(crate::Error::Config(format!("inconsistent table: {what}")));
        if self.points.len() != n {
            return bad(format!("{} points for a grid of {n}", self.points.len()));
        }
        if self.surfaces.len() != self.samples {
            return bad(format!(
                "{} surface entries for {} samples",
                self.surfaces.len(),
                self.samples
            ));
        }
        for (name, axis) in [
            ("pressure", &self.pressure),
            ("flux", &self.flux),
            ("contact_temperature", &self.contact_temperature),
        ] {
            if axis.is_empty()
                || axis.windows(2).any(|w| w[0] >= w[1])
                || axis.iter().any(|v| !v.is_finite())
            {
                return bad(format!("{name} is not a finite increasing axis"));
            }
        }
        for (i, p) in self.points.iter().enumerate() {
            if (p.status == PointStatus::Converged) != p.values.is_some() {
                return bad(format!(
                    "point {i}: status {:?} with values {:?}",
                    p.status, p.values
                ));
            }
            if let Some(v) = p.values
                && [v.jump, v.contact_fraction, v.mean_gap]
                    .iter()
                    .any(|x| !x.is_finite())
            {
                return bad(format!("point {i}: non-finite values {v:?}"));
            }
        }
        Ok(())
    }
}
