//! The fields of a solved micro-sample, sampled for output (SI): each body
//! on a structured grid of [`SAMPLES`] intervals per element and direction in
//! its deformed configuration, and the interface at the slave control
//! points; and how the fields of the two phases of the two-phase framework
//! combine into the fields of one load point.

use nalgebra::Vector3;

use crate::solve::Model;

/// Samples per element and direction.
pub const SAMPLES: usize = 4;

/// One body on its sample grid: `dims = [nx, ny]` points, `x` fastest
/// (point `i + nx j`); row `j = 0` is the face `η = 0` (the lower body's
/// bottom, the upper body's rough surface), row `ny − 1` the face `η = 1`.
#[derive(Clone, Debug)]
pub struct BodyFields {
    /// The body's name (`lower`, `upper`).
    pub name: String,
    /// Grid points along `ξ` and `η`.
    pub dims: [usize; 2],
    /// Deformed positions `x = X + u` (m).
    pub points: Vec<[f64; 3]>,
    /// Displacement `u` (m).
    pub displacement: Vec<[f64; 3]>,
    /// Cauchy stress `σ = P Fᵀ / J` (Pa), row-major 3×3 (plane strain).
    pub cauchy_stress: Vec<[f64; 9]>,
    /// Temperature `θ` (K).
    pub temperature: Vec<f64>,
    /// Spatial heat flux `q = J⁻¹ F q0`, `q0 = −J k(θ) C⁻¹ Grad θ` (5.1) (W/m²).
    pub heat_flux: Vec<[f64; 3]>,
}

/// The contact interface at the slave control points (mortar nodes `I`).
#[derive(Clone, Debug)]
pub struct InterfaceFields {
    /// Deformed control point positions (m).
    pub points: Vec<[f64; 3]>,
    /// Lumped contact pressure `pN^I = λN^I − εN gN^I`, clamped at 0 (Pa).
    pub contact_pressure: Vec<f64>,
    /// Weighted gap `gN^I` (4.8) (m).
    pub weighted_gap: Vec<f64>,
    /// Lumped area `⟨N^I⟩` (4.8) of the mechanical contact (m per m of depth):
    /// `Σ_I ⟨N^I⟩ pN^I` is the contact force.
    pub lumped_area: Vec<f64>,
    /// Lumped interface heat flux into the slave `h0^I` (W/m²).
    pub interface_heat_flux: Vec<f64>,
    /// Lumped area `⟨N^I⟩` of the thermal contact (m per m of depth): over
    /// the contact zone in the thermal phase of the two-phase framework
    /// (where it integrates the thermal contact), else `lumped_area`;
    /// `Σ_I ⟨N^I⟩ h0^I` is the heat flow into the slave.
    pub thermal_lumped_area: Vec<f64>,
}

/// The fields of one load point.
#[derive(Clone, Debug)]
pub struct Fields {
    /// Every body, in the model's order.
    pub bodies: Vec<BodyFields>,
    /// The contact interface, if the model has one.
    pub interface: Option<InterfaceFields>,
}

impl Fields {
    /// Every field at the model's current state (and current materials).
    pub fn sample(model: &Model) -> Fields {
        Fields {
            bodies: (0..model.bodies.len())
                .map(|b| sample_body(model, b))
                .collect(),
            interface: sample_interface(model),
        }
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
                thermal_lumped_area: t.thermal_lumped_area,
                ..m
            }),
            (m, _) => m,
        };
        Fields { bodies, interface }
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

fn sample_body(model: &Model, index: usize) -> BodyFields {
    let body = &model.bodies[index];
    let s = model.scales;
    let nf = model.dim + 1;
    let axes: Vec<Vec<f64>> = body.patch.knots().iter().map(sample_axis).collect();
    let dims = [axes[0].len(), axes[1].len()];
    let n = dims[0] * dims[1];
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
    for &eta in &axes[1] {
        for &xi in &axes[0] {
            let b = body.patch.basis(&[xi, eta], 1);
            // Reference position and Jacobian.
            let (mut x, mut jac) = ([0.0; 2], [[0.0; 2]; 2]);
            let (mut u, mut th) = ([0.0; 2], 0.0);
            for (a, &c) in b.indices.iter().enumerate() {
                let xa = body.patch.control_points()[c];
                let st = node(c);
                for i in 0..2 {
                    x[i] += b.values[a] * xa[i];
                    u[i] += b.values[a] * st[i];
                    for k in 0..2 {
                        jac[i][k] += xa[i] * b.d1[a][k];
                    }
                }
                th += b.values[a] * st[2];
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            let inv = [
                [jac[1][1] / det, -jac[0][1] / det],
                [-jac[1][0] / det, jac[0][0] / det],
            ];
            // Nodal displacements and dR/dX_j = Σ_k dR/dξ_k (J⁻¹)_kj.
            let mut gt = [0.0; 2];
            let (mut ua, mut dn) = (Vec::with_capacity(b.indices.len()), Vec::new());
            for (a, &c) in b.indices.iter().enumerate() {
                let st = node(c);
                let dx = [
                    b.d1[a][0] * inv[0][0] + b.d1[a][1] * inv[1][0],
                    b.d1[a][0] * inv[0][1] + b.d1[a][1] * inv[1][1],
                ];
                for i in 0..2 {
                    gt[i] += st[2] * dx[i];
                }
                ua.push([st[0], st[1], 0.0]);
                dn.push([dx[0], dx[1], 0.0]);
            }
            let f = crate::bulk::local::deformation_gradient(2, &ua, &dn);
            let m = &body.material;
            let sigma = m.cauchy_stress(&f, th) * s.stress;
            let q0 = m.heat_flux(&f, th, &Vector3::new(gt[0], gt[1], 0.0));
            let q = f * q0 / f.determinant() * s.flux();
            out.points
                .push([(x[0] + u[0]) * s.length, (x[1] + u[1]) * s.length, 0.0]);
            out.displacement
                .push([u[0] * s.length, u[1] * s.length, 0.0]);
            out.cauchy_stress
                .push(std::array::from_fn(|k| sigma[(k / 3, k % 3)]));
            out.temperature.push(th * s.temperature);
            out.heat_flux.push([q[0], q[1], 0.0]);
        }
    }
    out
}

fn sample_interface(model: &Model) -> Option<InterfaceFields> {
    let c = model.contact.as_ref()?;
    let s = model.scales;
    let ns = c.n_slave();
    let mut out = InterfaceFields {
        points: Vec::with_capacity(ns),
        contact_pressure: Vec::with_capacity(ns),
        weighted_gap: Vec::with_capacity(ns),
        lumped_area: Vec::with_capacity(ns),
        interface_heat_flux: Vec::with_capacity(ns),
        thermal_lumped_area: Vec::with_capacity(ns),
    };
    for i in 0..ns {
        let node = c.slave_nodes[i];
        let x = model.node_reference(node);
        out.points.push([
            x[0] * s.length + model.displacement(node, 0),
            x[1] * s.length + model.displacement(node, 1),
            0.0,
        ]);
        out.contact_pressure.push(c.pressure(i).max(0.0) * s.stress);
        out.weighted_gap.push(c.weighted_gap(i) * s.length);
        out.lumped_area.push(c.surface_area(i) * s.length);
        out.interface_heat_flux.push(c.heat_flux(i) * s.flux());
        out.thermal_lumped_area.push(c.lumped_area[i] * s.length);
    }
    Some(out)
}
