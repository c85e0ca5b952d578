//! The case file of `tcgen solve` (TOML, SI units, Table I defaults); every
//! key is documented in `schemas/case.md`.
//!
//! `[sample] dimension` (2 or 3) decides how the rest reads: the element
//! counts have 2 entries `[nx, nz]` or 3 `[nx, ny, nz]` ([`ElementCounts`]),
//! and the surfaces are profiles `f(x)` ([`SurfaceSpec`]) or areal surfaces
//! `f(x, y)` ([`ArealSpec`]), held as a [`BodySurface`].

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::contact::ContactSettings;
use crate::material::Material;
use crate::solve::{LoadStepping, NewtonSettings};
use crate::surface::{ArealSpec, ArealSurface, SinusoidPattern, Surface, SurfaceSpec};
use crate::{Error, Result};

mod dimension;
#[cfg(test)]
mod tests;

use dimension::check_dimension;
pub use dimension::{BodySurface, DIMENSIONS, ElementCounts};

/// Lateral boundary condition (2.3).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LateralCondition {
    /// PR: periodic displacement and temperature, sliding allowed.
    #[default]
    Periodic,
    /// LN: normal displacement zero, tangentially free, adiabatic.
    Linear,
}

/// Lateral condition of the upper body's top face (the platen, spec §5).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum TopLateral {
    /// Every top control point has `ux = 0`: a laterally rigid platen, no
    /// macroscopic sliding (the bodies slide only through the shear of the
    /// sample; paper Fig. 11).
    #[default]
    Fixed,
    /// The top face is free laterally: with PR its control points share one
    /// lateral displacement whose conjugate equation is the total lateral
    /// force, zero, so that the upper body slides to equilibrium (the net
    /// tangential contact force vanishes). With LN it is what LN implies.
    Free,
}

impl TopLateral {
    /// The key's values, as written in a case file.
    pub const VALUES: [&'static str; 2] = ["fixed", "free"];

    /// The value as written in a case file.
    pub fn as_str(self) -> &'static str {
        match self {
            TopLateral::Fixed => "fixed",
            TopLateral::Free => "free",
        }
    }
}

impl TryFrom<String> for TopLateral {
    type Error = String;
    fn try_from(s: String) -> std::result::Result<Self, String> {
        match s.as_str() {
            "fixed" => Ok(TopLateral::Fixed),
            "free" => Ok(TopLateral::Free),
            _ => Err(format!(
                "sample.top_lateral = \"{s}\": expected \"fixed\" or \"free\""
            )),
        }
    }
}

impl From<TopLateral> for String {
    fn from(t: TopLateral) -> String {
        t.as_str().into()
    }
}

/// `[sample]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SampleSection {
    /// 2 (plane strain, profiles) or 3 (a `W × W` cell, areal surfaces).
    pub dimension: usize,
    /// Sample width `W` (m); in 3D the cell is `W × W` in x and y.
    pub width: f64,
    /// Height `H0` of each body from the mean plane of its surface (m).
    pub height: f64,
    /// Lateral condition.
    pub lateral: LateralCondition,
    /// Lateral condition of the upper body's top face.
    pub top_lateral: TopLateral,
}

impl Default for SampleSection {
    fn default() -> Self {
        SampleSection {
            dimension: 2,
            width: 1.0e-5,
            height: 7.0e-6,
            lateral: LateralCondition::Periodic,
            top_lateral: TopLateral::Fixed,
        }
    }
}

/// `[surface]`: `upper` (body 1) and `lower` (body 2).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SurfaceSection {
    /// Body 1 (upper) surface.
    pub upper: BodySurface,
    /// Body 2 (lower) surface.
    pub lower: BodySurface,
}

/// `[surface]` as read, before the dimension says how to take it.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SurfaceTables {
    upper: toml::Table,
    lower: toml::Table,
}

/// The most levels of local refinement (elements `2^-12` of the coarse ones).
pub const MAX_LEVELS: usize = 12;

/// A target error `t` (`[discretization] target_error`, or a command's
/// flag `field`): a relative error in (0, 1).
pub fn check_target_error(field: &str, t: f64) -> Result<()> {
    if !(t.is_finite() && t > 0.0 && t < 1.0) {
        return Err(Error::invalid(
            field,
            t,
            "a relative error in (0, 1), e.g. 0.01",
        ));
    }
    Ok(())
}

/// A number of adaptive levels `n` (`[discretization] max_levels`, or a
/// command's flag `field`): 1..=[`MAX_LEVELS`].
pub fn check_max_levels(field: &str, n: usize) -> Result<()> {
    if !(1..=MAX_LEVELS).contains(&n) {
        return Err(Error::invalid(
            field,
            n,
            format!("an integer in 1..={MAX_LEVELS}"),
        ));
    }
    Ok(())
}

/// A largest number of unknowns `n` of an adaptive level
/// (`[discretization] max_dofs`, or a command's flag `field`): at least 16.
pub fn check_max_dofs(field: &str, n: usize) -> Result<()> {
    if n < 16 {
        return Err(Error::invalid(field, n, "an integer ≥ 16"));
    }
    Ok(())
}

/// `[discretization]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default = "DiscretizationSection::unset", deny_unknown_fields)]
pub struct DiscretizationSection {
    /// NURBS degree `p` (both directions, both bodies).
    pub degree: usize,
    /// Elements of the upper body `[nx, nz]` (2D) or `[nx, ny, nz]` (3D).
    pub elements_upper: ElementCounts,
    /// Elements of the lower body.
    pub elements_lower: ElementCounts,
    /// Bulk Gauss points per direction (default `p + 2`; at least `p`, and 2).
    pub bulk_points: Option<usize>,
    /// Levels of local (THB) refinement towards the contact interface: the
    /// elements touching the rough surface are halved this many times, the mesh
    /// graded through the height (admissible of class 2). 0: the tensor mesh.
    pub interface_levels: usize,
    /// Target relative error of the jump: refine adaptively at the contact
    /// edges, per pressure, until the estimate is below it
    /// (`homogenize::adapt`, two-level estimator). `None`: the fixed mesh.
    pub target_error: Option<f64>,
    /// Adaptivity stops before a mesh with more unknowns than this.
    pub max_dofs: usize,
    /// Adaptivity refines at most this many times per pressure.
    pub max_levels: usize,
    /// On which refinement levels adaptivity marks the neighbours of the
    /// contact-edge elements too, on both faces
    /// (`homogenize::adapt::mark_contact_edges`; [`EdgeNeighbours`]). `None`:
    /// by dimension and degree
    /// ([`DiscretizationSection::edge_neighbours_by_default`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub edge_neighbours: Option<EdgeNeighbours>,
    /// Which directions each level of local (THB) refinement halves
    /// ([`RefinementPattern`]; `interface_levels` and the adaptive levels alike).
    #[serde(skip_serializing_if = "RefinementPattern::is_dyadic")]
    pub refinement: RefinementPattern,
}

/// `[discretization] refinement`: which directions the levels of the THB
/// meshes halve (`geometry::hierarchical::mesh`). A marked cell is halved in
/// every direction either way; what differs is the grading that admissibility
/// adds around it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RefinementPattern {
    /// Every level halves every direction (the default).
    #[default]
    Dyadic,
    /// The levels halve the lateral directions and then the direction through
    /// the height in turn, so that a refinement is two levels and the cells
    /// graded below a refined face may stay as tall as their parents. On the 3D
    /// benchmark's egg box at 244.1 kPa: the jumps of levels 4–5 within 0.24 and
    /// 0.07 % of the dyadic ones with 0.86 times the unknowns; the six-level path
    /// took longer, its elements carrying more functions (docs/3d.md, "Stop 101").
    Alternating,
}

impl<'de> Deserialize<'de> for RefinementPattern {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = RefinementPattern;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("\"dyadic\" or \"alternating\"")
            }
            fn visit_str<E: serde::de::Error>(
                self,
                v: &str,
            ) -> std::result::Result<Self::Value, E> {
                match v {
                    "dyadic" => Ok(RefinementPattern::Dyadic),
                    "alternating" => Ok(RefinementPattern::Alternating),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
        }
        d.deserialize_any(Visitor)
    }
}

impl RefinementPattern {
    /// What the levels halve, as a clause after a description of the mesh
    /// (`tcgen check`'s adaptive line, `tcgen bench`'s header); empty when dyadic.
    pub fn clause(self) -> &'static str {
        match self {
            RefinementPattern::Dyadic => "",
            RefinementPattern::Alternating => {
                ", levels halving the lateral directions and the height in turn"
            }
        }
    }

    /// Whether this is the default, [`RefinementPattern::Dyadic`] (left out of a table's
    /// configuration, so that tables built before the key existed keep their hashes).
    pub fn is_dyadic(&self) -> bool {
        *self == RefinementPattern::Dyadic
    }
}

/// `[discretization] edge_neighbours`: on which refinement levels the marks
/// at the contact edges take the edge elements' neighbours too. At p ≥ 2 the
/// edge elements alone are already a band about two elements wide on each
/// side of the edge; the neighbours widen it on both faces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EdgeNeighbours {
    /// On every level (`true`) or on none (`false`).
    Every(bool),
    /// On the first `n` levels only (the marks that build levels 1 to `n`),
    /// not after (an integer in the case file).
    FirstLevels(usize),
}

/// The levels on which the 3D default at p ≥ 2 marks the contact-edge
/// elements' neighbours (since stop 98). On the first levels a small spot is
/// narrower than the band of its edge elements, and without the neighbours
/// the jumps of those levels change irregularly; the changes enter the
/// two-level estimate's older terms and held the benchmark's small spots
/// above 1 % on their fifth levels. With the neighbours on levels 1–2 their
/// fifth levels have the same jumps (within 5e-5) and 1–7 % more unknowns,
/// and the estimates at 1.842 and 3.393 kPa fall from 1.45 and 1.50 % to
/// 0.78 and 0.61 %; on the 3D demo table the 30 kPa point no longer stops
/// on a fourth level whose estimate (0.85 %) under-stated an error of
/// about 2 % (docs/3d.md, "Stop 98"). On every level the neighbours cost
/// about a third of each level's unknowns (docs/3d.md, "Stop 84").
pub const EARLY_EDGE_NEIGHBOUR_LEVELS: usize = 2;

impl EdgeNeighbours {
    /// Whether the marks that build refinement level `level` (1: the first)
    /// take the neighbours.
    pub fn at(self, level: usize) -> bool {
        match self {
            EdgeNeighbours::Every(marked) => marked,
            EdgeNeighbours::FirstLevels(n) => level <= n,
        }
    }

    /// What the marks take, in words (`tcgen check`'s adaptive line and
    /// `tcgen bench`'s header).
    pub fn describe(self) -> String {
        match self {
            EdgeNeighbours::Every(true) => "the contact-edge elements and their neighbours".into(),
            EdgeNeighbours::Every(false) | EdgeNeighbours::FirstLevels(0) => {
                "the contact-edge elements without their neighbours".into()
            }
            EdgeNeighbours::FirstLevels(1) => {
                "the contact-edge elements, with their neighbours on level 1".into()
            }
            EdgeNeighbours::FirstLevels(n) => {
                format!("the contact-edge elements, with their neighbours on levels 1–{n}")
            }
        }
    }
}

impl Serialize for EdgeNeighbours {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match *self {
            EdgeNeighbours::Every(marked) => s.serialize_bool(marked),
            EdgeNeighbours::FirstLevels(n) => s.serialize_u64(n as u64),
        }
    }
}

impl<'de> Deserialize<'de> for EdgeNeighbours {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = EdgeNeighbours;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("true, false, or a number of levels (an integer ≥ 0)")
            }
            fn visit_bool<E: serde::de::Error>(
                self,
                v: bool,
            ) -> std::result::Result<Self::Value, E> {
                Ok(EdgeNeighbours::Every(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Self::Value, E> {
                usize::try_from(v)
                    .map(EdgeNeighbours::FirstLevels)
                    .map_err(|_| E::invalid_value(serde::de::Unexpected::Signed(v), &self))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Self::Value, E> {
                usize::try_from(v)
                    .map(EdgeNeighbours::FirstLevels)
                    .map_err(|_| E::invalid_value(serde::de::Unexpected::Unsigned(v), &self))
            }
        }
        d.deserialize_any(Visitor)
    }
}

impl Default for DiscretizationSection {
    /// The 2D defaults.
    fn default() -> Self {
        DiscretizationSection::default_for(2)
    }
}

impl DiscretizationSection {
    /// The default element counts `(upper, lower)` of a dimension: `[32, 16]`
    /// and `[27, 14]` in 2D, `[8, 8, 4]` and `[7, 7, 4]` in 3D.
    pub fn default_elements(dimension: usize) -> (ElementCounts, ElementCounts) {
        if dimension == 3 {
            ([8, 8, 4].into(), [7, 7, 4].into())
        } else {
            ([32, 16].into(), [27, 14].into())
        }
    }

    /// The defaults of a dimension.
    pub fn default_for(dimension: usize) -> Self {
        let (elements_upper, elements_lower) = Self::default_elements(dimension);
        DiscretizationSection {
            degree: 2,
            elements_upper,
            elements_lower,
            bulk_points: None,
            interface_levels: 0,
            target_error: None,
            max_dofs: 200_000,
            max_levels: 10,
            edge_neighbours: None,
            refinement: RefinementPattern::Dyadic,
        }
    }

    /// On which levels adaptivity marks the contact-edge elements' neighbours
    /// in `dimension` (`edge_neighbours`, by default
    /// [`DiscretizationSection::edge_neighbours_by_default`]).
    pub fn edge_neighbours_in(&self, dimension: usize) -> EdgeNeighbours {
        self.edge_neighbours
            .unwrap_or_else(|| self.edge_neighbours_by_default(dimension))
    }

    /// The default of `edge_neighbours` in `dimension`: on every level in 2D
    /// and at degree 1 (whose edge band is one element wide: without the
    /// neighbours the 3D p = 1 egg box's second level cycled); in 3D at
    /// p ≥ 2 on the first [`EARLY_EDGE_NEIGHBOUR_LEVELS`] levels, where the
    /// later levels without them have about two thirds of the unknowns for
    /// jumps within their estimates (docs/3d.md, "Stop 84", "Stop 85" and
    /// "Stop 98").
    pub fn edge_neighbours_by_default(&self, dimension: usize) -> EdgeNeighbours {
        if dimension == 2 || self.degree == 1 {
            EdgeNeighbours::Every(true)
        } else {
            EdgeNeighbours::FirstLevels(EARLY_EDGE_NEIGHBOUR_LEVELS)
        }
    }

    /// What adaptivity marks at the contact edges in `dimension`, in words
    /// (`tcgen check`'s adaptive line and `tcgen bench`'s header).
    pub fn edge_marks_in(&self, dimension: usize) -> String {
        self.edge_neighbours_in(dimension).describe()
    }

    /// As read: the element counts empty until the dimension is known.
    fn unset() -> Self {
        DiscretizationSection {
            elements_upper: ElementCounts::empty(),
            elements_lower: ElementCounts::empty(),
            ..Self::default_for(2)
        }
    }
}

/// `[load]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LoadSection {
    /// Macroscopic pressures `p̄N` (Pa), solved in the given order as one path.
    pub pressures: Vec<f64>,
    /// Macroscopic heat flux magnitude `|h̄|` (W/m²), from the upper to the lower body.
    pub flux: f64,
    /// Macroscopic contact temperature `θ̄c` (K).
    pub contact_temperature: f64,
}

impl Default for LoadSection {
    fn default() -> Self {
        LoadSection {
            pressures: vec![1.0e3, 1.0e4, 1.0e5],
            flux: 1.0e6,
            contact_temperature: 293.15,
        }
    }
}

/// Identification of the macroscopic jump (spec §8).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Two-phase self-consistent (Sect. 3.3).
    #[default]
    TwoPhaseSelfConsistent,
    /// Two-phase (Sect. 3.1).
    TwoPhase,
    /// Coupled OHP, identification (2.14).
    Coupled,
    /// Coupled OHP, linearized identification (3.4).
    Linearized,
}

/// Which body is the (macroscopic algorithmic) master.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MasterBody {
    /// Body 2 (default).
    #[default]
    Lower,
    /// Body 1.
    Upper,
}

/// `[homogenization]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HomogenizationSection {
    /// Identification method.
    pub method: Method,
    /// Master body.
    pub master: MasterBody,
    /// Relative tolerance of the self-consistency iterations on the jump.
    pub tolerance: f64,
    /// Maximum self-consistency iterations.
    pub max_iterations: usize,
    /// How the next slave temperature of the self-consistency iterations is chosen.
    pub acceleration: Acceleration,
}

/// The update of the self-consistency iterations `ϑ̄c ← F(ϑ̄c)` (Sect. 3.3): `F`
/// maps the jump that sets the slave's frozen temperature `θ̄c + ϑ̄c` to the jump
/// identified by the next mechanical and thermal phases.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Acceleration {
    /// The secant method on `F(ϑ) − ϑ` through the last two iterates (the first
    /// step from the plain two-phase jump with the previous pressure's slope, or
    /// Aitken's Δ² without one), falling back to the plain update where the secant slope
    /// of `F` is not a contraction (`|F'| > 0.9`).
    #[default]
    Secant,
    /// The paper's plain fixed-point iteration `ϑ̄c ← F(ϑ̄c)` (Fig. 14a).
    None,
}

impl Default for HomogenizationSection {
    fn default() -> Self {
        HomogenizationSection {
            method: Method::default(),
            master: MasterBody::Lower,
            tolerance: 1e-6,
            max_iterations: 20,
            acceleration: Acceleration::default(),
        }
    }
}

/// `[solver]`: Newton and load stepping (scaled units).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolverSection {
    /// Newton settings.
    pub newton: NewtonSettings,
    /// Load stepping.
    pub stepping: LoadStepping,
}

impl SolverSection {
    /// Checks the Newton and load-stepping keys; the error names the key.
    pub fn validate(&self) -> Result<()> {
        let (n, st) = (&self.newton, &self.stepping);
        let bad = |key: &str, v: &dyn std::fmt::Display, expected: &str| {
            Err(Error::invalid(format!("solver.{key}"), v, expected))
        };
        if !(1..=10_000).contains(&n.max_iterations) {
            return bad(
                "newton.max_iterations",
                &n.max_iterations,
                "an integer in 1..=10000",
            );
        }
        for (key, v) in [
            ("newton.relative_tolerance", n.relative_tolerance),
            ("newton.absolute_tolerance", n.absolute_tolerance),
        ] {
            if !(v.is_finite() && v > 0.0 && v < 1.0) {
                return bad(key, &v, "a number in (0, 1)");
            }
        }
        if !(n.divergence_factor.is_finite() && n.divergence_factor > 1.0) {
            return bad(
                "newton.divergence_factor",
                &n.divergence_factor,
                "a finite number > 1",
            );
        }
        if !(st.max_step.is_finite() && st.max_step > 0.0 && st.max_step <= 1.0) {
            return bad(
                "stepping.max_step",
                &st.max_step,
                "a load fraction in (0, 1]",
            );
        }
        if !(st.min_step.is_finite() && st.min_step > 0.0 && st.min_step <= st.max_step) {
            return bad(
                "stepping.min_step",
                &st.min_step,
                &format!(
                    "a load fraction in (0, stepping.max_step = {}]",
                    st.max_step
                ),
            );
        }
        if !(st.initial_step >= st.min_step && st.initial_step <= st.max_step) {
            return bad(
                "stepping.initial_step",
                &st.initial_step,
                &format!(
                    "a load fraction in [min_step = {}, max_step = {}]",
                    st.min_step, st.max_step
                ),
            );
        }
        if !(st.growth.is_finite() && st.growth >= 1.0) {
            return bad("stepping.growth", &st.growth, "a finite factor >= 1");
        }
        if !(st.cutback.is_finite() && st.cutback > 0.0 && st.cutback < 1.0) {
            return bad("stepping.cutback", &st.cutback, "a factor in (0, 1)");
        }
        Ok(())
    }
}

/// A whole case file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "CaseFile")]
pub struct Case {
    /// `[sample]`.
    pub sample: SampleSection,
    /// `[surface]`.
    pub surface: SurfaceSection,
    /// `[material]` with optional `[material.upper]` / `[material.lower]` overrides.
    pub material: toml::Table,
    /// `[discretization]`.
    pub discretization: DiscretizationSection,
    /// `[contact]`.
    pub contact: ContactSettings,
    /// `[load]`.
    pub load: LoadSection,
    /// `[homogenization]`.
    pub homogenization: HomogenizationSection,
    /// `[solver]`.
    pub solver: SolverSection,
    /// Directory that relative paths in the case refer to (not a key).
    #[serde(skip)]
    pub base_dir: PathBuf,
}

/// A case file as read: the surfaces and element counts wait for `dimension`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CaseFile {
    #[serde(default)]
    sample: SampleSection,
    surface: SurfaceTables,
    #[serde(default)]
    material: toml::Table,
    #[serde(default = "DiscretizationSection::unset")]
    discretization: DiscretizationSection,
    #[serde(default)]
    contact: ContactSettings,
    #[serde(default)]
    load: LoadSection,
    #[serde(default)]
    homogenization: HomogenizationSection,
    #[serde(default)]
    solver: SolverSection,
}

impl TryFrom<CaseFile> for Case {
    type Error = Error;
    /// Takes the surfaces and element counts by `sample.dimension` (not validated).
    fn try_from(f: CaseFile) -> Result<Case> {
        let dim = f.sample.dimension;
        check_dimension(dim)?;
        let mut discretization = f.discretization;
        let (upper, lower) = DiscretizationSection::default_elements(dim);
        if discretization.elements_upper.is_empty() {
            discretization.elements_upper = upper;
        }
        if discretization.elements_lower.is_empty() {
            discretization.elements_lower = lower;
        }
        Ok(Case {
            surface: SurfaceSection {
                upper: BodySurface::from_table("surface.upper", f.surface.upper, dim)?,
                lower: BodySurface::from_table("surface.lower", f.surface.lower, dim)?,
            },
            sample: f.sample,
            material: f.material,
            discretization,
            contact: f.contact,
            load: f.load,
            homogenization: f.homogenization,
            solver: f.solver,
            base_dir: PathBuf::new(),
        })
    }
}

fn positive(key: &str, v: f64, unit: &str) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            key,
            v,
            format!("a finite number > 0 ({unit})"),
        ))
    }
}

/// The materials of the (upper, lower) bodies from a `[material]` table:
/// Table I defaults, then its keys, then its `upper` / `lower` sub-tables.
pub fn body_materials(material: &toml::Table) -> Result<(Material, Material)> {
    let mut base = material.clone();
    let upper = base.remove("upper");
    let lower = base.remove("lower");
    let resolve = |over: Option<toml::Value>, key: &str| -> Result<Material> {
        let mut t = base.clone();
        match over {
            Some(toml::Value::Table(o)) => t.extend(o),
            Some(v) => return Err(Error::invalid(key, v, "a table of material keys")),
            None => {}
        }
        let m: Material = toml::Value::Table(t)
            .try_into()
            .map_err(|e: toml::de::Error| Error::Config(format!("[{key}]: {e}")))?;
        m.validate(key)?;
        Ok(m)
    };
    Ok((
        resolve(upper, "material.upper")?,
        resolve(lower, "material.lower")?,
    ))
}

impl Case {
    /// Parses TOML text; `base_dir` resolves relative paths.
    pub fn from_toml(text: &str, base_dir: &Path) -> Result<Self> {
        let f: CaseFile = toml::from_str(text).map_err(|e| Error::Config(e.to_string()))?;
        let mut c = Case::try_from(f)?;
        c.base_dir = base_dir.to_path_buf();
        c.validate()?;
        Ok(c)
    }

    /// Reads the case keys of a parsed TOML table, without validating them
    /// (a sweep sets the loads first); `base_dir` resolves relative paths.
    pub fn from_table(table: toml::Table, base_dir: &Path) -> Result<Self> {
        let f: CaseFile = toml::Value::Table(table)
            .try_into()
            .map_err(|e: toml::de::Error| Error::Config(e.to_string()))?;
        let mut c = Case::try_from(f)?;
        c.base_dir = base_dir.to_path_buf();
        Ok(c)
    }

    /// The dimension, 2 or 3 (`[sample] dimension`).
    pub fn dimension(&self) -> usize {
        self.sample.dimension
    }

    /// Known limits that this configuration meets, one sentence each, for
    /// `tcgen check`, `solve` and `sweep` to print before they start: a
    /// valid case that the code is known to solve poorly or not at all.
    pub fn cautions(&self) -> Vec<String> {
        use crate::contact::Integration;
        let d = &self.discretization;
        let mut out = Vec::new();
        let least = crate::homogenize::path::min_adaptive_levels(self.dimension());
        if d.target_error.is_some() && d.max_levels < least {
            let why = match self.dimension() {
                3 => {
                    " (its level-2 estimates fell below the error at 5 of 21 levels measured \
                     against boundary elements; docs/adaptivity.md)"
                }
                _ => "",
            };
            out.push(format!(
                "max_levels = {} with target_error: in {}D the estimate may meet the target \
                 from level {least} on{why}, so every point will be flagged \
                 (error_target_met = false) with its estimate",
                d.max_levels,
                self.dimension()
            ));
        }
        if self.dimension() == 3 && d.degree == 1 {
            if self.contact.integration != Integration::Segment {
                out.push(
                    "degree 1 in 3D: the contact's element-based points can stall under load \
                     over the master's C0 creases (the egg box of tables/egg_box_on_flat.toml: \
                     [12, 12, 6] at 60 kPa, [20, 20, 10] at 91 kPa); [contact] integration = \
                     \"segment\" solves some of these meshes ([12, 12, 6]; on [8, 8, 4], \
                     which both solve, it took 5 times as long; docs/3d.md, \"3D contact at \
                     degree 1 under load\"); degree 2, the default, is not concerned"
                        .to_string(),
                );
            }
            if d.target_error.is_some() {
                out.push(
                    "degree 1 in 3D: adaptive refinement (target_error) needs far more \
                     unknowns than degree 2: the trilinear elements of the case mesh are too \
                     stiff, so the levels refine the bodies' bulk too until its estimated \
                     approach error meets the target (the egg box of \
                     tables/egg_box_on_flat.toml from [8, 8, 4] at 11.5 kPa: level 4 with \
                     70 264 unknowns has the approach 0.8 % and the contact area 4.5 % short \
                     of degrees 2 and 3 and the jump 0.6-1.2 % above them, its bulk estimate \
                     1.3 %, and level 5 exceeds the default max_dofs: flagged, not met; \
                     refined at the contact edges only, the levels met the target 2.4 % \
                     off); with the segment cells its third level does not converge (the \
                     second's result is kept, flagged; docs/3d.md, \"Stop 73\", \"Stop \
                     74\", \"Stop 76\"); degree 2 for adaptive runs"
                        .to_string(),
                );
            }
        }
        out.extend(self.seam_cautions());
        out
    }

    /// A measured surface (a 2D profile, a 3D height map) that is not
    /// periodic: its heights step across the cell's edges by more than
    /// [`SeamSteps::RATIO`](crate::surface::SeamSteps::RATIO) times their
    /// steps inside ([`crate::surface::SeamSteps`]). A file that cannot be
    /// read is left to [`Case::validate`].
    fn seam_cautions(&self) -> Vec<String> {
        let w = self.sample.width;
        let mut out = Vec::new();
        for (key, spec) in [
            ("surface.upper", &self.surface.upper),
            ("surface.lower", &self.surface.lower),
        ] {
            let Some((file, pinned)) = spec.data_file() else {
                continue;
            };
            let Ok((path, text)) =
                crate::surface::read_data_file(key, file, pinned, &self.base_dir)
            else {
                continue;
            };
            let seams = match spec {
                BodySurface::Profile(_) => crate::surface::Profile::parse(&text, &path, w, key)
                    .map(|p| vec![("x = W", p.seam_steps())]),
                BodySurface::Areal(_) => crate::surface::HeightMap::parse(&text, &path, w, key)
                    .map(|m| {
                        let [x, y] = m.seam_steps();
                        vec![("x = W", x), ("y = W", y)]
                    }),
            }
            .unwrap_or_default();
            for (seam, s) in seams.into_iter().filter(|(_, s)| !s.is_periodic()) {
                let times = if s.inside > 0.0 {
                    format!("{:.1} times", s.across / s.inside)
                } else {
                    "more than".into()
                };
                out.push(format!(
                    "{key}.file is not periodic across its seam at {seam}: its heights step there \
                     by {:.3e} m RMS, {times} their steps between neighbouring points inside \
                     ({:.3e} m), so the periodic cell has a ridge or trench along that edge that \
                     is not in the surface, where contact may start; make the data periodic \
                     before use (a tilted scan: subtract its best-fit plane; a crop: mirror it, \
                     or taper it to a common edge)",
                    s.across, s.inside
                ));
            }
        }
        out
    }

    /// Reads and validates a case file.
    pub fn read(path: &Path) -> Result<Self> {
        let text = crate::error::read_text(path)?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Case::from_toml(&text, &dir).map_err(|e| match e {
            Error::Config(m) => Error::Config(format!("{}: {m}", path.display())),
            other => other,
        })
    }

    /// The materials of the (upper, lower) bodies: Table I defaults, then
    /// `[material]`, then `[material.upper]` / `[material.lower]`.
    pub fn materials(&self) -> Result<(Material, Material)> {
        body_materials(&self.material)
    }

    /// Checks that both bodies conduct (`k(θ) = k0 + k1 (θ − θ0) > 0`) at
    /// the contact temperatures `thetas` (K) of a case or sweep.
    pub fn check_conductivity_at(&self, thetas: &[f64]) -> Result<()> {
        let (upper, lower) = self.materials()?;
        for (key, m) in [("material.upper", upper), ("material.lower", lower)] {
            for &t in thetas {
                let k =
                    m.thermal_conductivity + m.conductivity_slope * (t - m.reference_temperature);
                if k.is_nan() || k <= 0.0 {
                    return Err(Error::invalid(
                        format!("{key}.conductivity_slope"),
                        m.conductivity_slope,
                        format!(
                            "a slope that keeps k = k0 + k1 (θ − θ0) > 0 at the contact temperature {t} K (gives {k:e} W/(m K))"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Pins the content of each measured surface's data file: its SHA-256
    /// into `file_sha256` (a digest the case already gives is checked against
    /// the file first), so that a configuration's hash identifies the heights
    /// and the surfaces built later are those of that content
    /// ([`crate::surface::read_data_file`]).
    pub fn pin_data_files(&mut self) -> Result<()> {
        let base = self.base_dir.clone();
        for (key, spec) in [
            ("surface.upper", &mut self.surface.upper),
            ("surface.lower", &mut self.surface.lower),
        ] {
            if let Some((file, digest)) = spec.data_file_mut() {
                let (_, text) =
                    crate::surface::read_data_file(key, file, digest.as_deref(), &base)?;
                *digest = Some(crate::io::hash::sha256_hex(text.as_bytes()));
            }
        }
        Ok(())
    }

    /// Builds the upper and lower profiles of a 2D case (an error names the key).
    pub fn surfaces(&self) -> Result<(Box<dyn Surface>, Box<dyn Surface>)> {
        let w = self.sample.width;
        let build = |key: &str, s: &BodySurface| match s {
            BodySurface::Profile(p) if self.dimension() == 2 => p.build(key, w, &self.base_dir),
            _ => Err(Error::invalid(
                "sample.dimension",
                self.dimension(),
                format!("2 for the profiles f(x) of {key} (a 3D case has areal surfaces f(x, y))"),
            )),
        };
        Ok((
            build("surface.upper", &self.surface.upper)?,
            build("surface.lower", &self.surface.lower)?,
        ))
    }

    /// Builds the upper and lower areal surfaces of a 3D case (an error names the key).
    pub fn areal_surfaces(&self) -> Result<(Box<dyn ArealSurface>, Box<dyn ArealSurface>)> {
        let w = self.sample.width;
        let build = |key: &str, s: &BodySurface| match s {
            BodySurface::Areal(a) if self.dimension() == 3 => a.build(key, w, &self.base_dir),
            _ => Err(Error::invalid(
                "sample.dimension",
                self.dimension(),
                format!("3 for the areal surfaces f(x, y) of {key} (a 2D case has profiles f(x))"),
            )),
        };
        Ok((
            build("surface.upper", &self.surface.upper)?,
            build("surface.lower", &self.surface.lower)?,
        ))
    }

    /// Checks the surfaces against the dimension and the sample, and reads
    /// their files (profiles, height maps) now, not after a table header is
    /// written; the error names the key.
    fn validate_surfaces(&self) -> Result<()> {
        let (w, h, dim) = (self.sample.width, self.sample.height, self.dimension());
        for (key, spec) in [
            ("surface.upper", &self.surface.upper),
            ("surface.lower", &self.surface.lower),
        ] {
            if spec.dimension() != dim {
                return Err(Error::invalid(
                    key,
                    if dim == 3 {
                        "a profile f(x)"
                    } else {
                        "an areal surface f(x, y)"
                    },
                    format!(
                        "{} with sample.dimension = {dim}",
                        if dim == 3 {
                            "an areal surface f(x, y)"
                        } else {
                            "a profile f(x)"
                        }
                    ),
                ));
            }
            // The highest crest of a deterministic surface (random surfaces
            // are checked when generated).
            let crest = match spec {
                BodySurface::Profile(p) => {
                    p.validate(key, w)?;
                    match p {
                        SurfaceSpec::Profile { .. } => {
                            p.build(key, w, &self.base_dir)?;
                            None
                        }
                        SurfaceSpec::Sinusoid { rms, .. } => {
                            Some((std::f64::consts::SQRT_2 * rms, "the amplitude √2·rms"))
                        }
                        _ => None,
                    }
                }
                BodySurface::Areal(a) => {
                    a.validate(key, w)?;
                    match a {
                        ArealSpec::Heightmap { file, file_sha256 } => {
                            let (path, text) = crate::surface::read_data_file(
                                key,
                                file,
                                file_sha256.as_deref(),
                                &self.base_dir,
                            )?;
                            let map = crate::surface::HeightMap::parse(
                                &text,
                                &path,
                                w,
                                &format!("{key}.file"),
                            )?;
                            Some((map.largest_height(), "the largest |height| of the map"))
                        }
                        ArealSpec::Sinusoid {
                            rms,
                            pattern: SinusoidPattern::EggBox,
                            ..
                        } => Some((2.0 * rms, "the amplitude 2·rms of the egg-box")),
                        ArealSpec::Sinusoid {
                            rms,
                            pattern: SinusoidPattern::Ridges,
                            ..
                        } => Some((
                            std::f64::consts::SQRT_2 * rms,
                            "the amplitude √2·rms of the ridges",
                        )),
                        _ => None,
                    }
                }
            };
            if let Some((a, what)) = crest
                && a >= h
            {
                return Err(Error::invalid(
                    "sample.height",
                    format!("{h:e} m"),
                    format!(
                        "more than {what} = {a:e} m of {key} (its crest would reach through the body)"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Checks every key's range; the error names the key.
    pub fn validate(&self) -> Result<()> {
        check_dimension(self.dimension())?;
        positive("sample.width", self.sample.width, "m")?;
        positive("sample.height", self.sample.height, "m")?;
        self.validate_surfaces()?;
        self.materials()?;
        let d = &self.discretization;
        if !(1..=5).contains(&d.degree) {
            return Err(Error::invalid(
                "discretization.degree",
                d.degree,
                "an integer in 1..=5",
            ));
        }
        let dim = self.dimension();
        for (key, e) in [
            ("discretization.elements_upper", &d.elements_upper),
            ("discretization.elements_lower", &d.elements_lower),
        ] {
            if e.len() != dim || e.as_slice().iter().any(|&n| !(1..=4096).contains(&n)) {
                let form = if dim == 3 {
                    "three element counts [nx, ny, nz]"
                } else {
                    "two element counts [nx, nz]"
                };
                return Err(Error::invalid(
                    key,
                    e,
                    format!("{form} with sample.dimension = {dim}, each in 1..=4096"),
                ));
            }
        }
        // Fewer Gauss points per direction than the degree (than 2 at p = 1)
        // leave zero-energy (hourglass) modes in the bulk stiffness; `max(p, 2)`
        // keep only the rigid ones on these smooth splines (measured at p = 1,
        // 2, 3; test `the_least_accepted_rule_keeps_only_the_rigid_modes`,
        // docs/3d.md, "Stop 97").
        let least_points = d.degree.max(2);
        if let Some(n) = d.bulk_points
            && !(least_points..=16).contains(&n)
        {
            return Err(Error::invalid(
                "discretization.bulk_points",
                n,
                format!(
                    "an integer in {least_points}..=16 (fewer Gauss points per direction than max(p, 2), p = {} the degree, leave zero-energy modes in the bulk stiffness)",
                    d.degree
                ),
            ));
        }
        if d.interface_levels > MAX_LEVELS {
            return Err(Error::invalid(
                "discretization.interface_levels",
                d.interface_levels,
                format!("an integer in 0..={MAX_LEVELS}"),
            ));
        }
        if let Some(t) = d.target_error {
            check_target_error("discretization.target_error", t)?;
        }
        if d.target_error.is_some()
            && matches!(
                self.homogenization.method,
                Method::Coupled | Method::Linearized
            )
        {
            return Err(Error::invalid(
                "discretization.target_error",
                d.target_error.unwrap_or_default(),
                "absent with homogenization.method = \"coupled\" or \"linearized\" (adaptivity runs the two-phase methods)",
            ));
        }
        check_max_dofs("discretization.max_dofs", d.max_dofs)?;
        check_max_levels("discretization.max_levels", d.max_levels)?;
        self.contact.validate()?;
        if self.load.pressures.is_empty() {
            return Err(Error::invalid(
                "load.pressures",
                "[]",
                "at least one pressure (Pa)",
            ));
        }
        for p in &self.load.pressures {
            positive("load.pressures", *p, "Pa")?;
        }
        // The identifications divide by the flux: a zero flux has no jump.
        positive("load.flux", self.load.flux, "W/m²")?;
        positive(
            "load.contact_temperature",
            self.load.contact_temperature,
            "K",
        )?;
        self.check_conductivity_at(&[self.load.contact_temperature])?;
        self.solver.validate()?;
        let h = &self.homogenization;
        if !(h.tolerance.is_finite() && h.tolerance > 0.0 && h.tolerance < 1.0) {
            return Err(Error::invalid(
                "homogenization.tolerance",
                h.tolerance,
                "a number in (0, 1)",
            ));
        }
        if !(1..=1000).contains(&h.max_iterations) {
            return Err(Error::invalid(
                "homogenization.max_iterations",
                h.max_iterations,
                "an integer in 1..=1000",
            ));
        }
        Ok(())
    }
}
