//! The fields of a solved micro-sample (2D or 3D), sampled for output (SI):
//! each body on a structured grid of [`SAMPLES`] intervals per element and
//! direction in its deformed configuration, and the interface at the slave
//! control points (2D) or on the sample grid of the slave face (3D); and how
//! the fields of the two phases of the two-phase framework combine into the
//! fields of one load point.

use nalgebra::{Matrix3, Vector3};

use crate::Result;
use crate::geometry::ThbPatch;
use crate::solve::Model;

/// Samples per element and direction.
pub const SAMPLES: usize = 4;

/// One body on its sample grid: `dims = [nx, ny]` (2D) or `[nx, ny, nz]`
/// (3D) points, `x` fastest, then `y`, then `z` (point `i + nx j` or
/// `i + nx (j + ny k)`); the first row (2D) or layer (3D) is the face of
/// the last parameter at 0 (the lower body's bottom, the upper body's rough
/// surface), the last one that parameter at 1 (the height is the last
/// direction).
#[derive(Clone, Debug)]
pub struct BodyFields {
    /// The body's name (`lower`, `upper`).
    pub name: String,
    /// Grid points along each parametric direction.
    pub dims: Vec<usize>,
    /// Deformed positions `x = X + u` (m).
    pub points: Vec<[f64; 3]>,
    /// Displacement `u` (m).
    pub displacement: Vec<[f64; 3]>,
    /// Cauchy stress `σ = P Fᵀ / J` (Pa), row-major 3×3 (in 2D plane strain:
    /// `σzz` is the out-of-plane stress).
    pub cauchy_stress: Vec<[f64; 9]>,
    /// Temperature `θ` (K).
    pub temperature: Vec<f64>,
    /// Spatial heat flux `q = J⁻¹ F q0`, `q0 = −J k(θ) C⁻¹ Grad θ` (5.1) (W/m²).
    pub heat_flux: Vec<[f64; 3]>,
}

/// The contact interface: in 2D at the slave control points (mortar nodes
/// `I`, `dims = [n]`, a polyline); in 3D on the sample grid of the slave
/// face (`dims = [nu, nv]`, the first parameter fastest), every quantity
/// interpolated from the slave control points by the face's basis,
/// `v(ξ) = Σ_I R^I(ξ) v^I` (the position too: `x = Σ_I R^I (X^I + u^I)`).
#[derive(Clone, Debug)]
pub struct InterfaceFields {
    /// Grid points per direction.
    pub dims: Vec<usize>,
    /// The contact force `Σ_I ⟨N^I⟩ pN^I` (N per m of depth in 2D, N), the
    /// normal force on the slave surface.
    pub contact_force: f64,
    /// The heat flow into the slave `Σ_I ⟨N^I⟩ h0^I` (thermal lumped areas;
    /// W per m of depth, W).
    pub heat_flow: f64,
    /// Deformed positions (m).
    pub points: Vec<[f64; 3]>,
    /// Displacement `u` (m).
    pub displacement: Vec<[f64; 3]>,
    /// Lumped contact pressure `pN^I = λN^I − εN gN^I`, clamped at 0 (Pa).
    pub contact_pressure: Vec<f64>,
    /// Weighted gap `gN^I` (4.8) (m).
    pub weighted_gap: Vec<f64>,
    /// Lumped area `⟨N^I⟩` (4.8) of the mechanical contact over the whole
    /// slave surface (m per m of depth in 2D, m² in 3D): `Σ_I ⟨N^I⟩ pN^I` is
    /// the contact force.
    pub lumped_area: Vec<f64>,
    /// Lumped interface heat flux into the slave `h0^I` (W/m²).
    pub interface_heat_flux: Vec<f64>,
    /// Lumped temperature jump `⟨N^I ϑc⟩ / ⟨N^I⟩` (4.1, 4.8) over the whole
    /// slave surface, `ϑc = θ_s − θ_m` the slave's temperature less the
    /// master's at the closest point (K): near zero where a constraint
    /// model conducts, `−h0 / (kθ pN^α)` where the constitutive one does,
    /// and the temperature difference across the gap elsewhere
    /// ([`crate::contact::ContactInterface::surface_jumps`]).
    pub temperature_jump: Vec<f64>,
    /// Lumped area `⟨N^I⟩` of the thermal contact (m per m of depth, m²): over
    /// the contact zone in the thermal phase of the two-phase framework
    /// (where it integrates the thermal contact), else `lumped_area`;
    /// `Σ_I ⟨N^I⟩ h0^I` is the heat flow into the slave.
    pub thermal_lumped_area: Vec<f64>,
}

/// The fields of one load point.
#[derive(Clone, Debug)]
pub struct Fields {
    /// The spatial dimension (2: plane strain, or 3).
    pub dimension: usize,
    /// Every body, in the model's order.
    pub bodies: Vec<BodyFields>,
    /// The contact interface, if the model has one.
    pub interface: Option<InterfaceFields>,
}

impl Fields {
    /// Every field at the model's current state (and current materials).
    pub fn sample(model: &Model) -> Result<Fields> {
        Ok(Fields {
            dimension: model.dim,
            bodies: (0..model.bodies.len())
                .map(|b| sample_body(model, b))
                .collect(),
            interface: sample_interface(model)?,
        })
    }

    /// The fields of a two-phase load point (Sect. 3.1): the deformation,
    /// the stress and the contact pressure and gap of the mechanical phase's
    /// equilibrium state (its displacements at the temperatures it was
    /// solved with); the temperature and the heat fluxes of the thermal
    /// phase on that frozen configuration. The stress is not re-evaluated at
    /// the thermal phase's temperatures: the mechanical phase never balanced
    /// the thermal expansion they would add.
    pub fn two_phase(mechanical: Fields, thermal: Fields) -> Fields {
        let bodies = mechanical
            .bodies
            .into_iter()
            .zip(thermal.bodies)
            .map(|(m, t)| BodyFields {
                temperature: t.temperature,
                heat_flux: t.heat_flux,
                ..m
            })
            .collect();
        let interface = match (mechanical.interface, thermal.interface) {
            (Some(m), Some(t)) => Some(InterfaceFields {
                interface_heat_flux: t.interface_heat_flux,
                temperature_jump: t.temperature_jump,
                thermal_lumped_area: t.thermal_lumped_area,
                heat_flow: t.heat_flow,
                ..m
            }),
            (m, _) => m,
        };
        Fields {
            dimension: mechanical.dimension,
            bodies,
            interface,
        }
    }

    /// The thermal fields of a thermal phase solved at unit flux, at the
    /// flux `flux` (W/m²): with every property frozen the thermal phase is
    /// affine in `h̄` about the uniform `θ̄c`, so `θ = θ̄c + h̄ (θ₁ − θ̄c)` and
    /// the heat fluxes scale with `h̄`. The mechanical fields are unchanged.
    pub fn at_flux(&self, contact_temperature: f64, flux: f64) -> Fields {
        let mut f = self.clone();
        for b in &mut f.bodies {
            for t in &mut b.temperature {
                *t = contact_temperature + flux * (*t - contact_temperature);
            }
            for q in &mut b.heat_flux {
                q.iter_mut().for_each(|v| *v *= flux);
            }
        }
        if let Some(i) = &mut f.interface {
            i.interface_heat_flux.iter_mut().for_each(|v| *v *= flux);
            i.temperature_jump.iter_mut().for_each(|v| *v *= flux);
            i.heat_flow *= flux;
        }
        f
    }
}

/// The sample coordinates along one knot vector: [`SAMPLES`] intervals per element.
fn sample_axis(k: &crate::geometry::KnotVector) -> Vec<f64> {
    let mut v = Vec::new();
    for (n, &sp) in k.element_spans().iter().enumerate() {
        let (a, b) = (k.knots()[sp], k.knots()[sp + 1]);
        let first = if n == 0 { 0 } else { 1 };
        for t in first..=SAMPLES {
            v.push(a + (b - a) * t as f64 / SAMPLES as f64);
        }
    }
    v
}

/// The sample grid of a patch (a body, or a 3D slave face): the points per
/// parametric direction and the parameters of every point, the first
/// direction fastest.
fn sample_grid(patch: &ThbPatch) -> (Vec<usize>, Vec<Vec<f64>>) {
    let axes: Vec<Vec<f64>> = patch.knots().iter().map(sample_axis).collect();
    let dims: Vec<usize> = axes.iter().map(Vec::len).collect();
    let n: usize = dims.iter().product();
    let params = (0..n)
        .map(|mut p| {
            axes.iter()
                .map(|axis| {
                    let t = axis[p % axis.len()];
                    p /= axis.len();
                    t
                })
                .collect()
        })
        .collect();
    (dims, params)
}

fn sample_body(model: &Model, index: usize) -> BodyFields {
    let body = &model.bodies[index];
    let s = model.scales;
    let (dim, nf) = (model.dim, model.dim + 1);
    let (dims, params) = sample_grid(&body.patch);
    let n = params.len();
    let mut out = BodyFields {
        name: body.name.clone(),
        dims,
        points: Vec::with_capacity(n),
        displacement: Vec::with_capacity(n),
        cauchy_stress: Vec::with_capacity(n),
        temperature: Vec::with_capacity(n),
        heat_flux: Vec::with_capacity(n),
    };
    let node = |c: usize| &model.state[(c + body.node_offset) * nf..][..nf];
    // The spatial components of a vector (0 beyond `dim`: plane strain).
    let spatial =
        |v: [f64; 3], scale: f64| std::array::from_fn(|i| if i < dim { v[i] * scale } else { 0.0 });
    for xi in &params {
        let b = body.patch.basis(xi, 1);
        // Reference position, displacement, temperature and the Jacobian
        // `∂X/∂ξ` (identity beyond `dim`).
        let (mut x, mut u, mut th) = ([0.0; 3], [0.0; 3], 0.0);
        let mut jac = Matrix3::identity();
        for i in 0..dim {
            jac[(i, i)] = 0.0;
        }
        for (a, &c) in b.indices.iter().enumerate() {
            let xa = body.patch.control_points()[c];
            let st = node(c);
            for i in 0..dim {
                x[i] += b.values[a] * xa[i];
                u[i] += b.values[a] * st[i];
                for k in 0..dim {
                    jac[(i, k)] += xa[i] * b.d1[a][k];
                }
            }
            th += b.values[a] * st[dim];
        }
        let inv = jac
            .try_inverse()
            .unwrap_or_else(|| Matrix3::from_element(f64::NAN));
        // Nodal displacements and dR/dX_j = Σ_k dR/dξ_k (J⁻¹)_kj.
        let mut gt = Vector3::zeros();
        let (mut ua, mut dn) = (Vec::with_capacity(b.len()), Vec::with_capacity(b.len()));
        for (a, &c) in b.indices.iter().enumerate() {
            let st = node(c);
            let dx = Vector3::from(b.d1[a]).tr_mul(&inv);
            gt += st[dim] * dx.transpose();
            ua.push(std::array::from_fn(|i| if i < dim { st[i] } else { 0.0 }));
            dn.push([dx[0], dx[1], dx[2]]);
        }
        let f = crate::bulk::local::deformation_gradient(dim, &ua, &dn);
        let m = &body.material;
        let sigma = m.cauchy_stress(&f, th) * s.stress;
        let q = f * m.heat_flux(&f, th, &gt) / f.determinant() * s.flux();
        out.points
            .push(spatial(std::array::from_fn(|i| x[i] + u[i]), s.length));
        out.displacement.push(spatial(u, s.length));
        out.cauchy_stress
            .push(std::array::from_fn(|k| sigma[(k / 3, k % 3)]));
        out.temperature.push(th * s.temperature);
        out.heat_flux.push(spatial([q[0], q[1], q[2]], 1.0));
    }
    out
}

fn sample_interface(model: &Model) -> Result<Option<InterfaceFields>> {
    let Some(c) = model.contact.as_ref() else {
        return Ok(None);
    };
    let s = model.scales;
    let dim = model.dim;
    // Lumped areas are lengths (per unit depth) in 2D, areas in 3D.
    let area = s.length.powi(dim as i32 - 1);
    // The values at the slave control points (mortar nodes `I`).
    let ns = c.n_slave();
    let jumps = c.surface_jumps(&model.state)?;
    // Per node: position (3), pN, gN, ⟨N⟩, h0, thermal ⟨N⟩, displacement
    // (3), ϑc.
    let nodal: Vec<[f64; 12]> = (0..ns)
        .map(|i| {
            let node = c.slave_nodes[i];
            let x = model.node_reference(node);
            let u = |k: usize| {
                if k < dim {
                    model.displacement(node, k)
                } else {
                    0.0
                }
            };
            let pos = |k: usize| if k < dim { x[k] * s.length + u(k) } else { 0.0 };
            [
                pos(0),
                pos(1),
                pos(2),
                c.pressure(i).max(0.0) * s.stress,
                c.weighted_gap(i) * s.length,
                // A periodic copy shows its node's (merged) areas.
                c.surface_area(c.copy_of(i)) * area,
                c.heat_flux(i) * s.flux(),
                c.lumped_area[c.copy_of(i)] * area,
                u(0),
                u(1),
                u(2),
                jumps[i] * s.temperature,
            ]
        })
        .collect();
    // The output points as combinations of the slave control points: in 2D
    // the control points themselves, in 3D the sample grid of the slave
    // face, interpolated by its basis `Σ_I R^I v^I`.
    let (dims, weights): (Vec<usize>, Vec<Vec<(usize, f64)>>) = if dim == 2 {
        (vec![ns], (0..ns).map(|i| vec![(i, 1.0)]).collect())
    } else {
        let face = c.slave_face();
        let (dims, params) = sample_grid(face);
        let weights = params
            .iter()
            .map(|xi| {
                let b = face.basis(xi, 0);
                b.indices.into_iter().zip(b.values).collect()
            })
            .collect();
        (dims, weights)
    };
    // In 3D the heat flux is interpolated as each node's heat flow per its
    // whole lumped area, `h0^I ⟨N^I⟩_thermal / ⟨N^I⟩`, like the contact
    // pressure: its integral over the surface is then the heat flow also
    // where the thermal phase integrates over the contact zone only.
    let interpolated = |i: usize, k: usize| {
        let v = &nodal[i];
        if dim == 3 && k == 6 && v[5] > 0.0 {
            v[6] * v[7] / v[5]
        } else {
            v[k]
        }
    };
    let values: Vec<[f64; 12]> = weights
        .iter()
        .map(|w| std::array::from_fn(|k| w.iter().map(|&(i, r)| r * interpolated(i, k)).sum()))
        .collect();
    let column = |k: usize| values.iter().map(|v| v[k]).collect();
    let owned = nodal
        .iter()
        .enumerate()
        .filter(|&(i, _)| !c.is_copy(i))
        .map(|(_, v)| v);
    Ok(Some(InterfaceFields {
        dims,
        // Each tie group once (a periodic copy shows its node's areas).
        contact_force: owned.clone().map(|v| v[3] * v[5]).sum(),
        heat_flow: owned.map(|v| v[6] * v[7]).sum(),
        points: values.iter().map(|v| [v[0], v[1], v[2]]).collect(),
        displacement: values.iter().map(|v| [v[8], v[9], v[10]]).collect(),
        contact_pressure: column(3),
        weighted_gap: column(4),
        lumped_area: column(5),
        interface_heat_flux: column(6),
        thermal_lumped_area: column(7),
        temperature_jump: column(11),
    }))
}
