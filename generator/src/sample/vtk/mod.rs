//! ParaView output of a pressure path (`tcgen solve --vtk DIR`): per load
//! point `k`, VTK XML UnstructuredGrid files (ASCII; ParaView, VTK and
//! meshio read them):
//!
//! - `pKKK_lower.vtu`, `pKKK_upper.vtu`: each body on a structured grid of
//!   [`SAMPLES`] intervals per element and direction (of the level-0 mesh on
//!   a locally refined one; quadrilateral cells; the field data
//!   `grid_dimensions = [nx, ny]`, points `x` fastest, row 0 the face
//!   `η = 0`), in its deformed configuration, with the point data
//!   `displacement` (m), `cauchy_stress` `σ = P Fᵀ/J` (Pa, 3×3 row-major,
//!   plane strain), `temperature` (K) and `heat_flux`, the spatial flux
//!   `q = J⁻¹ F q0` with `q0 = −J k(θ) C⁻¹ Grad θ` (5.1) (W/m²);
//! - `pKKK_interface.vtu`: the slave control points (mortar nodes `I`) as a
//!   polyline of line cells, with `contact_pressure` `pN^I` (Pa),
//!   `weighted_gap` `gN^I` (4.8) (m), `lumped_area` `⟨N^I⟩` (4.8) (m per m
//!   of depth; `Σ ⟨N^I⟩ pN^I` is the normal contact force),
//!   `interface_heat_flux` `h0^I` (W/m², into the slave) and
//!   `thermal_lumped_area`, the `⟨N^I⟩` the thermal contact is integrated
//!   with (over the contact zone in the two-phase thermal phase; `Σ ⟨N^I⟩
//!   h0^I` is the heat flow into the slave);
//!
//! every file with the field data `applied_pressure` `p̄N` (Pa),
//! `applied_flux` `|h̄|` (W/m²), `contact_temperature` `θ̄c` (K) and
//! `point_index` `k`, repeated (with the method and the phases) in an XML
//! comment at its top; and the collection `series.pvd` listing every file
//! written, `timestep` the pressure (the point index if the pressures do not
//! increase), `part` 0 lower, 1 upper, 2 interface. The collection is
//! rewritten atomically after every point, so an interrupted run leaves a
//! valid one.
//!
//! Which state each field comes from:
//! - `coupled`, `linearized` (one monolithic problem, (2.14), (3.4)): every
//!   field from the converged coupled state.
//! - `two-phase`, `two-phase-self-consistent` (Sect. 3.1, 3.3): the
//!   deformed positions, `displacement`, `cauchy_stress`,
//!   `contact_pressure`, `weighted_gap` and `lumped_area` from the
//!   mechanical phase (i): its equilibrium displacements at the (uniform,
//!   frozen) temperatures it was solved with, `θ̄c`, or for the slave
//!   `θ̄c + ϑ̄c` in the last self-consistent iteration; `temperature`,
//!   `heat_flux`, `interface_heat_flux` and `thermal_lumped_area` from the
//!   thermal phase (ii) on that frozen configuration (conductivities frozen
//!   at the same temperatures) at the case's flux (the plain two-phase
//!   thermal phase is solved at unit flux and scaled, exactly: it is affine
//!   in `h̄`). The stress is *not* re-evaluated at the thermal phase's
//!   temperatures: that mixes the phases, and the thermal expansion it adds
//!   is balanced by nothing (issue 14 item 3).
//!
//! So `σyy` integrated over the top row of the upper body, or the bottom row
//! of the lower, is `−p̄N` times the width, and `q_y` there `−|h̄|` times the
//! width, to the discretization error; the interface's heat flow is
//! `−|h̄|` times the width to the solver tolerance (tested on the written
//! files in `generator/tests/vtk_output.rs`).

mod fields;
pub mod xml;

pub use fields::{BodyFields, Fields, InterfaceFields, SAMPLES};

use std::path::{Path, PathBuf};

use crate::io::atomic::write_atomic;
use crate::sample::case::Method;
use crate::{Error, Result};
use xml::{Array, DataSet, VTK_LINE, VTK_QUAD, Values};

/// The collection file in the output directory.
pub const COLLECTION: &str = "series.pvd";

/// What identifies a load point in its files.
#[derive(Clone, Debug)]
pub struct PointInfo {
    /// The point's index along the path (`k` of `pKKK_*`).
    pub index: usize,
    /// `p̄N` (Pa).
    pub pressure: f64,
    /// `|h̄|` (W/m²).
    pub flux: f64,
    /// `θ̄c` (K).
    pub contact_temperature: f64,
    /// The identification.
    pub method: Method,
}

impl PointInfo {
    fn field_data(&self) -> Vec<Array<'static>> {
        let one = |name, v| Array {
            name,
            components: 1,
            values: Values::Float(vec![v]),
        };
        vec![
            one("applied_pressure", self.pressure),
            one("applied_flux", self.flux),
            one("contact_temperature", self.contact_temperature),
            Array {
                name: "point_index",
                components: 1,
                values: Values::Int(vec![self.index as i64]),
            },
        ]
    }

    fn comment(&self, what: &str) -> String {
        let method = serde_json::to_value(self.method)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
            .unwrap_or_default();
        let phases = match self.method {
            Method::Coupled | Method::Linearized => "every field from the coupled state",
            Method::TwoPhase | Method::TwoPhaseSelfConsistent => {
                "deformation, stress, contact pressure and gap from the mechanical phase; \
                 temperature and heat fluxes from the thermal phase"
            }
        };
        format!(
            "tcgen {what}, point {}: applied_pressure {:e} Pa, applied_flux {:e} W/m2, \
             contact_temperature {:e} K, method {method} ({phases}); deformed configuration, SI",
            self.index, self.pressure, self.flux, self.contact_temperature
        )
    }
}

fn flat<const N: usize>(v: &[[f64; N]]) -> Values {
    Values::Float(v.iter().flatten().copied().collect())
}

fn body_file(info: &PointInfo, b: &BodyFields) -> String {
    let [nx, ny] = b.dims;
    let cells: Vec<Vec<usize>> = (0..ny.saturating_sub(1))
        .flat_map(|j| {
            (0..nx.saturating_sub(1)).map(move |i| {
                let p = i + nx * j;
                vec![p, p + 1, p + 1 + nx, p + nx]
            })
        })
        .collect();
    let mut field = info.field_data();
    field.push(Array {
        name: "grid_dimensions",
        components: 2,
        values: Values::Int(vec![nx as i64, ny as i64]),
    });
    xml::unstructured_grid(
        &info.comment(&format!("micro-sample body {}", b.name)),
        &field,
        &b.points,
        &cells,
        VTK_QUAD,
        &[
            Array {
                name: "displacement",
                components: 3,
                values: flat(&b.displacement),
            },
            Array {
                name: "cauchy_stress",
                components: 9,
                values: flat(&b.cauchy_stress),
            },
            Array {
                name: "temperature",
                components: 1,
                values: Values::Float(b.temperature.clone()),
            },
            Array {
                name: "heat_flux",
                components: 3,
                values: flat(&b.heat_flux),
            },
        ],
    )
}

fn interface_file(info: &PointInfo, c: &InterfaceFields) -> String {
    let cells: Vec<Vec<usize>> = (1..c.points.len()).map(|i| vec![i - 1, i]).collect();
    let scalar = |name, v: &Vec<f64>| Array {
        name,
        components: 1,
        values: Values::Float(v.clone()),
    };
    xml::unstructured_grid(
        &info.comment("contact interface (slave control points)"),
        &info.field_data(),
        &c.points,
        &cells,
        VTK_LINE,
        &[
            scalar("contact_pressure", &c.contact_pressure),
            scalar("weighted_gap", &c.weighted_gap),
            scalar("lumped_area", &c.lumped_area),
            scalar("interface_heat_flux", &c.interface_heat_flux),
            scalar("thermal_lumped_area", &c.thermal_lumped_area),
        ],
    )
}

/// The files of a pressure path in one directory, and their collection.
pub struct VtkSeries {
    dir: PathBuf,
    timesteps: Vec<f64>,
    datasets: Vec<DataSet>,
}

impl VtkSeries {
    /// Creates `dir` (if missing) and an empty collection in it, for the
    /// path `pressures` (Pa): the time step of point `k` is `pressures[k]`
    /// if they increase strictly, `k` otherwise.
    pub fn create(dir: &Path, pressures: &[f64]) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(|e| Error::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
        let increasing = pressures.windows(2).all(|w| w[0] < w[1]);
        let series = VtkSeries {
            dir: dir.to_path_buf(),
            timesteps: (0..pressures.len())
                .map(|k| if increasing { pressures[k] } else { k as f64 })
                .collect(),
            datasets: Vec::new(),
        };
        series.write_collection()?;
        Ok(series)
    }

    /// The collection file.
    pub fn collection_path(&self) -> PathBuf {
        self.dir.join(COLLECTION)
    }

    fn write_collection(&self) -> Result<()> {
        write_atomic(
            &self.collection_path(),
            xml::collection(&self.datasets).as_bytes(),
        )
    }

    /// Writes the files of one load point and adds them to the collection.
    pub fn write_point(&mut self, info: &PointInfo, fields: &Fields) -> Result<()> {
        let k = info.index;
        let timestep = self.timesteps.get(k).copied().unwrap_or(k as f64);
        let mut files: Vec<(String, String)> = fields
            .bodies
            .iter()
            .map(|b| (format!("p{k:03}_{}.vtu", b.name), body_file(info, b)))
            .collect();
        if let Some(c) = &fields.interface {
            files.push((format!("p{k:03}_interface.vtu"), interface_file(info, c)));
        }
        for (part, (name, text)) in files.into_iter().enumerate() {
            write_atomic(&self.dir.join(&name), text.as_bytes())?;
            self.datasets.retain(|d| d.file != name);
            self.datasets.push(DataSet {
                timestep,
                part,
                file: name,
            });
        }
        self.datasets
            .sort_by(|a, b| a.timestep.total_cmp(&b.timestep).then(a.part.cmp(&b.part)));
        self.write_collection()
    }
}
