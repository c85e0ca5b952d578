//! What `[sample] dimension` decides: the surfaces of the bodies
//! ([`BodySurface`]: profiles `f(x)` in 2D, areal surfaces `f(x, y)` in 3D,
//! with keys of the other dimension refused by name) and the element counts
//! ([`ElementCounts`]: `[nx, nz]` or `[nx, ny, nz]`).

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::surface::{ArealSpec, RandomSpec, SurfaceSpec};
use crate::{Error, Result};

/// The dimensions a case may have.
pub const DIMENSIONS: [usize; 2] = [2, 3];

/// One body's surface: a profile `f(x)` in 2D, an areal surface `f(x, y)` in 3D.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum BodySurface {
    /// 2D (`[sample] dimension = 2`).
    Profile(SurfaceSpec),
    /// 3D (`[sample] dimension = 3`).
    Areal(ArealSpec),
}

impl From<SurfaceSpec> for BodySurface {
    fn from(s: SurfaceSpec) -> Self {
        BodySurface::Profile(s)
    }
}

impl From<ArealSpec> for BodySurface {
    fn from(s: ArealSpec) -> Self {
        BodySurface::Areal(s)
    }
}

/// The `kind` values of each dimension, as an error message lists them.
fn kinds(dimension: usize) -> &'static str {
    if dimension == 3 {
        "\"flat\", \"sinusoid\", \"random\" or \"heightmap\""
    } else {
        "\"flat\", \"sinusoid\", \"profile\" or \"random\""
    }
}

impl BodySurface {
    /// The dimension of the surface's sample (2 for a profile, 3 for an areal surface).
    pub fn dimension(&self) -> usize {
        match self {
            BodySurface::Profile(_) => 2,
            BodySurface::Areal(_) => 3,
        }
    }

    /// The random spec, in either dimension.
    pub fn random(&self) -> Option<&RandomSpec> {
        match self {
            BodySurface::Profile(SurfaceSpec::Random(r))
            | BodySurface::Areal(ArealSpec::Random(r)) => Some(r),
            _ => None,
        }
    }

    /// The random spec, mutable (sweeps set its seed and sample).
    pub fn random_mut(&mut self) -> Option<&mut RandomSpec> {
        match self {
            BodySurface::Profile(SurfaceSpec::Random(r))
            | BodySurface::Areal(ArealSpec::Random(r)) => Some(r),
            _ => None,
        }
    }

    /// The data file of a measured surface (`kind = "profile"` or
    /// `"heightmap"`) and its pinned SHA-256 (`file_sha256`).
    pub fn data_file(&self) -> Option<(&Path, Option<&str>)> {
        match self {
            BodySurface::Profile(SurfaceSpec::Profile { file, file_sha256 })
            | BodySurface::Areal(ArealSpec::Heightmap { file, file_sha256 }) => {
                Some((file.as_path(), file_sha256.as_deref()))
            }
            _ => None,
        }
    }

    /// [`BodySurface::data_file`], its digest mutable.
    pub fn data_file_mut(&mut self) -> Option<(&Path, &mut Option<String>)> {
        match self {
            BodySurface::Profile(SurfaceSpec::Profile { file, file_sha256 })
            | BodySurface::Areal(ArealSpec::Heightmap { file, file_sha256 }) => {
                Some((file.as_path(), file_sha256))
            }
            _ => None,
        }
    }

    /// The 2D spec, if this is a profile.
    pub fn profile(&self) -> Option<&SurfaceSpec> {
        match self {
            BodySurface::Profile(s) => Some(s),
            BodySurface::Areal(_) => None,
        }
    }

    /// The 3D spec, if this is an areal surface.
    pub fn areal(&self) -> Option<&ArealSpec> {
        match self {
            BodySurface::Areal(s) => Some(s),
            BodySurface::Profile(_) => None,
        }
    }

    /// Reads the table `[key]` (e.g. `surface.upper`) of a case of `dimension`:
    /// keys of the other dimension are errors naming the key.
    pub(super) fn from_table(key: &str, table: toml::Table, dimension: usize) -> Result<Self> {
        let allowed = kinds(dimension);
        let kind = match table.get("kind") {
            None => {
                return Err(Error::invalid(
                    format!("{key}.kind"),
                    "(missing)",
                    format!("one of {allowed} (sample.dimension = {dimension})"),
                ));
            }
            Some(toml::Value::String(k)) => k.clone(),
            Some(v) => {
                return Err(Error::invalid(
                    format!("{key}.kind"),
                    v,
                    format!("one of {allowed} (sample.dimension = {dimension})"),
                ));
            }
        };
        let wrong_kind = |why: &str| {
            Err(Error::invalid(
                format!("{key}.kind"),
                format!("\"{kind}\""),
                format!("one of {allowed} with sample.dimension = {dimension}{why}"),
            ))
        };
        match (dimension, kind.as_str()) {
            (2, "heightmap") => {
                return wrong_kind(" (a height map f(x, y) needs [sample] dimension = 3)");
            }
            (3, "profile") => {
                return wrong_kind(
                    " (a profile f(x) is 2D; a measured areal surface is kind = \"heightmap\")",
                );
            }
            (2, "flat" | "sinusoid" | "profile" | "random")
            | (3, "flat" | "sinusoid" | "random" | "heightmap") => {}
            _ => return wrong_kind(""),
        }
        if kind == "sinusoid" {
            if dimension == 2 {
                if let Some(v) = table.get("pattern") {
                    return Err(Error::invalid(
                        format!("{key}.pattern"),
                        v,
                        "absent with sample.dimension = 2 (egg-box and ridges are areal patterns of [sample] dimension = 3; a 2D sinusoid takes phase)",
                    ));
                }
                if let Some(v) = table.get("phase_y") {
                    return Err(Error::invalid(
                        format!("{key}.phase_y"),
                        v,
                        "absent with sample.dimension = 2 (a profile f(x) has one phase, phase; phase_y shifts an egg-box of [sample] dimension = 3 along y)",
                    ));
                }
            } else {
                if let Some(v) = table.get("pattern")
                    && !matches!(v.as_str(), Some("egg-box" | "ridges"))
                {
                    return Err(Error::invalid(
                        format!("{key}.pattern"),
                        v,
                        "\"egg-box\" (2·rms·cos(2πx/λ)·cos(2πy/λ), the default) or \"ridges\" (√2·rms·cos(2πx/λ))",
                    ));
                }
            }
        }
        let value = toml::Value::Table(table);
        let parse_err = |e: toml::de::Error| Error::Config(format!("[{key}]: {}", e.message()));
        Ok(if dimension == 3 {
            BodySurface::Areal(value.try_into().map_err(parse_err)?)
        } else {
            BodySurface::Profile(value.try_into().map_err(parse_err)?)
        })
    }
}

/// The element counts of one body: `[nx, nz]` in 2D, `[nx, ny, nz]` in 3D
/// (the lateral directions, then through the height).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "Vec<usize>", into = "Vec<usize>")]
pub struct ElementCounts(Vec<usize>);

impl TryFrom<Vec<usize>> for ElementCounts {
    type Error = String;
    /// Any non-empty list (the count is checked against the dimension later).
    fn try_from(v: Vec<usize>) -> std::result::Result<Self, String> {
        if v.is_empty() {
            return Err(
                "no element counts: expected [nx, nz] in 2D, [nx, ny, nz] in 3D".to_string(),
            );
        }
        Ok(ElementCounts(v))
    }
}

impl<const N: usize> From<[usize; N]> for ElementCounts {
    fn from(v: [usize; N]) -> Self {
        ElementCounts(v.to_vec())
    }
}

impl From<ElementCounts> for Vec<usize> {
    fn from(e: ElementCounts) -> Self {
        e.0
    }
}

impl std::fmt::Display for ElementCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:?}", self.0)
    }
}

impl ElementCounts {
    /// No entries: a section read before its dimension gives the defaults.
    pub(super) fn empty() -> Self {
        ElementCounts(Vec::new())
    }

    /// The number of entries (the dimension of a valid case).
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether there are no entries (a section not yet given its defaults).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Elements along the lateral axis `axis` (0: x; 1: y in 3D).
    #[track_caller]
    pub fn along(&self, axis: usize) -> usize {
        assert!(
            axis + 1 < self.0.len(),
            "ElementCounts::along({axis}) of {self}: lateral axes are 0..{}",
            self.0.len().saturating_sub(1)
        );
        self.0[axis]
    }

    /// Elements through the height (the last entry).
    #[track_caller]
    pub fn through_height(&self) -> usize {
        *self.0.last().expect("ElementCounts: no entries")
    }

    /// Every count multiplied by `factor` (a uniformly refined case mesh).
    pub fn scaled(&self, factor: usize) -> Self {
        ElementCounts(self.0.iter().map(|n| n * factor).collect())
    }

    /// The lateral counts multiplied by `factor`, those through the height
    /// kept (a case mesh refined along the surfaces).
    pub fn laterally_scaled(&self, factor: usize) -> Self {
        let last = self.0.len().saturating_sub(1);
        ElementCounts(
            self.0
                .iter()
                .enumerate()
                .map(|(i, n)| if i < last { n * factor } else { *n })
                .collect(),
        )
    }

    /// The lateral counts (`[nx]` in 2D, `[nx, ny]` in 3D).
    pub fn lateral(&self) -> &[usize] {
        &self.0[..self.0.len().saturating_sub(1)]
    }

    /// Every entry, as written.
    pub fn as_slice(&self) -> &[usize] {
        &self.0
    }
}

/// `sample.dimension` is 2 or 3.
pub(super) fn check_dimension(dim: usize) -> Result<()> {
    if DIMENSIONS.contains(&dim) {
        Ok(())
    } else {
        Err(Error::invalid(
            "sample.dimension",
            dim,
            "2 (plane strain: profiles f(x), elements [nx, nz]) or 3 (a W × W cell: areal surfaces f(x, y), elements [nx, ny, nz])",
        ))
    }
}
