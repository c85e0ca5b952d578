//! ParaView output of a pressure path (`tcgen solve --vtk DIR`), 2D (plane
//! strain) and 3D alike: per load point `k`, VTK XML UnstructuredGrid files
//! (ASCII; ParaView, VTK and meshio read them):
//!
//! - `pKKK_lower.vtu`, `pKKK_upper.vtu`: each body on a structured grid of
//!   [`SAMPLES`] intervals per element and direction (of the level-0 mesh on
//!   a locally refined one; the field data `grid_dimensions` = `[nx, ny]` in
//!   2D, `[nx, ny, nz]` in 3D; points `x` fastest, then `y`, then `z`; the
//!   first row (2D) or layer (3D) is the face of the last parameter at 0,
//!   the height being the last direction), quadrilateral cells (VTK type 9)
//!   in 2D, hexahedra (VTK type 12) in 3D, in its deformed configuration,
//!   with the point data `displacement` (m, 3 components; `u_z = 0` in 2D),
//!   `cauchy_stress` `σ = P Fᵀ/J` (Pa, 3×3 row-major; in 2D plane strain,
//!   `σzz` out of plane), `temperature` (K) and `heat_flux`, the spatial
//!   flux `q = J⁻¹ F q0` with `q0 = −J k(θ) C⁻¹ Grad θ` (5.1) (W/m², 3
//!   components);
//! - `pKKK_interface.vtu`: the slave surface with `displacement` (m),
//!   `contact_pressure` `pN^I` (Pa), `weighted_gap` `gN^I` (4.8) (m),
//!   `lumped_area` `⟨N^I⟩` (4.8) (m per m of depth in 2D, m² in 3D, over
//!   the whole slave surface), `interface_heat_flux` `h0^I` (W/m², into the
//!   slave) and `thermal_lumped_area`, the `⟨N^I⟩` the thermal contact is
//!   integrated with (over the contact zone in the two-phase thermal
//!   phase), and `temperature_jump`, the local jump `ϑc = θ_s − θ_m` (4.1)
//!   (K; the slave's temperature less the master's at its closest point)
//!   lumped over each node's whole support, `⟨N^I ϑc⟩ / ⟨N^I⟩`: near zero
//!   where a constraint model conducts, the temperature difference across
//!   the gap elsewhere (its mean over the slave surface, weighted by
//!   `lumped_area`, was 0.88–0.96 of the macroscopic jump on the case
//!   meshes of `tables/sinusoid_on_flat.toml` and
//!   `tables/egg_box_on_flat.toml`: the macroscopic jump is read off the
//!   bodies' far fields, not the surfaces');
//!   and the field data `contact_force` `Σ ⟨N^I⟩ pN^I` (the normal
//!   contact force; N/m in 2D, N in 3D) and `interface_heat_flow`
//!   `Σ ⟨N^I⟩ h0^I` (thermal lumped areas; the heat flow into the slave,
//!   W/m or W). In 2D the points are the slave control points (mortar nodes
//!   `I`) themselves, a polyline of line cells (VTK type 3), each quantity
//!   its nodal value. In 3D (the slave control points of a THB surface need
//!   not form a grid) the points are the sample grid of the slave face
//!   ([`SAMPLES`] intervals per element and direction, `grid_dimensions` =
//!   `[nu, nv]`, quadrilateral cells), each nodal quantity (the position
//!   and displacement too) interpolated from the slave control points by
//!   the face's basis, `v(ξ) = Σ_I R^I(ξ) v^I`: so `∫ pN dA` over the
//!   reference slave surface is `Σ ⟨N^I⟩ pN^I` (the cells give it to their
//!   sampling error; the point values of `lumped_area` are interpolated
//!   nodal areas, not a density); `interface_heat_flux` likewise from each
//!   node's heat flow per its whole lumped area, `h0^I ⟨N^I⟩_thermal /
//!   ⟨N^I⟩`, so that its integral is the heat flow also where the thermal
//!   phase integrates over the contact zone (a flux density spread over
//!   the supports, as the pressure, not the zone's own);
//!
//! every file with the field data `applied_pressure` `p̄N` (Pa),
//! `applied_flux` `|h̄|` (W/m²), `contact_temperature` `θ̄c` (K),
//! `point_index` `k`, `dimension` (2 or 3) and `grid_dimensions`, the
//! first four repeated (with the method and the phases) in an XML comment
//! at its top; and the collection `series.pvd` listing every file
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
//!   `contact_pressure`, `weighted_gap`, `lumped_area` and `contact_force`
//!   from the mechanical phase (i): its equilibrium displacements at the
//!   (uniform, frozen) temperatures it was solved with, `θ̄c`, or for the
//!   slave `θ̄c + ϑ̄c` in the last self-consistent iteration;
//!   `temperature`, `heat_flux`, `interface_heat_flux`,
//!   `thermal_lumped_area`, `temperature_jump` and `interface_heat_flow`
//!   from the thermal
//!   phase (ii) on that frozen configuration (conductivities frozen
//!   at the same temperatures) at the case's flux (the plain two-phase
//!   thermal phase is solved at unit flux and scaled, exactly: it is affine
//!   in `h̄`). The stress is *not* re-evaluated at the thermal phase's
//!   temperatures: that mixes the phases, and the thermal expansion it adds
//!   is balanced by nothing (issue 14 item 3).
//!
//! So the height component of the stress (`σyy` in 2D, `σzz` in 3D)
//! integrated over the top row (layer) of the upper body, or the bottom one
//! of the lower, is `−p̄N` times the width (the cell area `W²` in 3D), and
//! `q_y` (`q_z`) there `−|h̄|` times it, to the discretization error; the
//! interface's heat flow is `−|h̄|` times it to the solver tolerance (tested
//! on the written files in `generator/tests/suite/vtk_output.rs`, with the
//! measured errors).

mod fields;
pub mod xml;

pub use fields::{BodyFields, Fields, InterfaceFields, SAMPLES};

use std::path::{Path, PathBuf};

use crate::io::atomic::write_atomic;
use crate::sample::case::Method;
use crate::{Error, Result};
use xml::{Array, DataSet, VTK_HEXAHEDRON, VTK_LINE, VTK_QUAD, Values};

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

/// The cells of a structured grid of `dims` points (the first direction
/// fastest) and their VTK type: lines (one direction), quadrilaterals (two)
/// or hexahedra (three), their vertices in VTK's order (counter-clockwise in
/// the first two directions, then the same one step along the third).
pub fn grid_cells(dims: &[usize]) -> (Vec<Vec<usize>>, u8) {
    let strides: Vec<usize> = dims
        .iter()
        .scan(1, |s, &d| {
            let r = *s;
            *s *= d;
            Some(r)
        })
        .collect();
    // Vertex `v` of a cell: its offsets along each direction.
    let corners: Vec<usize> = (0..1usize << dims.len())
        .map(|v| {
            let bit = |k: usize| (v >> k) & 1;
            let steps = [bit(0) ^ bit(1), bit(1), bit(2)];
            (0..dims.len()).map(|k| steps[k] * strides[k]).sum()
        })
        .collect();
    let n_cells: usize = dims.iter().map(|d| d.saturating_sub(1)).product();
    let cells = (0..n_cells)
        .map(|mut c| {
            let base: usize = dims
                .iter()
                .zip(&strides)
                .map(|(&d, &s)| {
                    let i = c % (d - 1);
                    c /= d - 1;
                    i * s
                })
                .sum();
            corners.iter().map(|&o| base + o).collect()
        })
        .collect();
    let cell_type = match dims.len() {
        1 => VTK_LINE,
        2 => VTK_QUAD,
        _ => VTK_HEXAHEDRON,
    };
    (cells, cell_type)
}

/// The field data of a file: the point's and the grid's.
fn field_data(info: &PointInfo, dimension: usize, dims: &[usize]) -> Vec<Array<'static>> {
    let mut field = info.field_data();
    field.push(Array {
        name: "dimension",
        components: 1,
        values: Values::Int(vec![dimension as i64]),
    });
    field.push(Array {
        name: "grid_dimensions",
        components: dims.len(),
        values: Values::Int(dims.iter().map(|&d| d as i64).collect()),
    });
    field
}

fn body_file(info: &PointInfo, dimension: usize, b: &BodyFields) -> String {
    let (cells, cell_type) = grid_cells(&b.dims);
    xml::unstructured_grid(
        &info.comment(&format!("micro-sample body {}", b.name)),
        &field_data(info, dimension, &b.dims),
        &b.points,
        &cells,
        cell_type,
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

fn interface_file(info: &PointInfo, dimension: usize, c: &InterfaceFields) -> String {
    let (cells, cell_type) = grid_cells(&c.dims);
    let scalar = |name, v: &Vec<f64>| Array {
        name,
        components: 1,
        values: Values::Float(v.clone()),
    };
    let what = if dimension == 2 {
        "contact interface (slave control points)"
    } else {
        "contact interface (slave face sampled, interpolated from its control points)"
    };
    let mut field = field_data(info, dimension, &c.dims);
    for (name, v) in [
        ("contact_force", c.contact_force),
        ("interface_heat_flow", c.heat_flow),
    ] {
        field.push(Array {
            name,
            components: 1,
            values: Values::Float(vec![v]),
        });
    }
    xml::unstructured_grid(
        &info.comment(what),
        &field,
        &c.points,
        &cells,
        cell_type,
        &[
            Array {
                name: "displacement",
                components: 3,
                values: flat(&c.displacement),
            },
            scalar("contact_pressure", &c.contact_pressure),
            scalar("weighted_gap", &c.weighted_gap),
            scalar("lumped_area", &c.lumped_area),
            scalar("interface_heat_flux", &c.interface_heat_flux),
            scalar("thermal_lumped_area", &c.thermal_lumped_area),
            scalar("temperature_jump", &c.temperature_jump),
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
            .map(|b| {
                (
                    format!("p{k:03}_{}.vtu", b.name),
                    body_file(info, fields.dimension, b),
                )
            })
            .collect();
        if let Some(c) = &fields.interface {
            files.push((
                format!("p{k:03}_interface.vtu"),
                interface_file(info, fields.dimension, c),
            ));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_cells_are_lines_quadrilaterals_and_hexahedra_in_vtk_order() {
        assert_eq!(grid_cells(&[3]), (vec![vec![0, 1], vec![1, 2]], VTK_LINE));
        assert_eq!(
            grid_cells(&[3, 2]),
            (vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]], VTK_QUAD)
        );
        let (cells, t) = grid_cells(&[2, 3, 2]);
        assert_eq!(t, VTK_HEXAHEDRON);
        assert_eq!(
            cells,
            vec![vec![0, 1, 3, 2, 6, 7, 9, 8], vec![2, 3, 5, 4, 8, 9, 11, 10]]
        );
        assert_eq!(grid_cells(&[4, 1]).0.len(), 0);
    }
}
