//! Contact patch tests (paper Sect. 5.2 and Fig. 9, spec §10.2): two bodies
//! with non-matching discretizations whose union is the block `[0, W] × [0,
//! H]` (2D) or `[0, W]² × [0, H]` (3D, [`PatchSetup::dimension`]), so that
//! the exact fields are those of one homogeneous block. In 3D each body is
//! the 2D body extruded along y (the interface a flat plane or a circular
//! cylinder), with as many elements and the same degree along y as along x;
//! the height is the last direction (z).
//!
//! - **Thermal** (zero pressure): the thermal phase on the undeformed
//!   configuration with every slave control point in the (frozen) active set,
//!   the bottom at `θ0`, the flux `h̄` into the top, adiabatic sides, constant
//!   conductivity. Exact: `θ = θ0 + h̄ y/k`, no jump, interface flux `h̄`
//!   everywhere. Flat and curved interfaces: the curved one is a 90° circular
//!   arc, exact as a NURBS, shared by both bodies (each body is the ruled
//!   surface between the arc and a straight outer face in the same spline
//!   space), then refined differently (knot insertion and degree elevation
//!   preserve the geometry and its parametrization).
//! - **Mechanical** (flat): platen pressure `p̄` on top, bottom fixed, LN sides
//!   on both bodies, so the exact solution is homogeneous uniaxial strain and
//!   every lumped contact pressure is `pN^I = p̄`.
//!
//! Measured: the lumped interface flux `h0^I = λθ^I − εθ γθ^I` (mortar) or the
//! pointwise flux `−εθ ϑc` at the slave integration points (continuum), the
//! lumped jumps `γθ^I` and the pointwise jumps `ϑc`, the temperature error at
//! the control points (isoparametric NURBS reproduce linear fields exactly:
//! the exact control values are the linear field at the control points), and
//! the lumped pressures.

use crate::Result;
use crate::analytical::compression::platen_stretch;
use crate::bulk::Coupling;
use crate::contact::{
    ContactSettings, Integration, ThermalContact, ThermalEnforcement, ThermalMethod,
};
use crate::geometry::{KnotVector, NurbsPatch, Side, ThbPatch, shapes};
use crate::material::Material;
use crate::sample::case::RefinementPattern;
use crate::sample::micro::interface_refined;
use crate::solve::{LoadStepping, Model, ModelBuilder, Newton, NewtonSettings, Scales};

/// The three control points of a degree-2 curve with one span.
type Curve = [[f64; 3]; 3];

/// Interface shape of a patch test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interface {
    /// `y = H1`.
    Flat,
    /// A 90° circular arc through `(0, H1)` and `(W, H1)`, bulging upwards.
    Curved,
}

/// Refinement of one body: degree elevation and uniform knot insertion per
/// direction (along the interface, through the height).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Refinement {
    /// Final degree along the interface (≥ 2).
    pub degree: usize,
    /// Elements along the interface.
    pub elements: usize,
    /// Final degree through the height (≥ 1).
    pub degree_y: usize,
    /// Elements through the height.
    pub elements_y: usize,
    /// Levels of local (THB) refinement at the interface (0: the tensor mesh).
    pub interface_levels: usize,
}

/// The patch-test geometry and discretizations.
#[derive(Clone, Debug)]
pub struct PatchSetup {
    /// Width `W` (m).
    pub width: f64,
    /// Height of the lower body at its sides (m).
    pub height_lower: f64,
    /// Height of the upper body at its sides (m).
    pub height_upper: f64,
    /// Interface shape.
    pub interface: Interface,
    /// Lower body (master) refinement.
    pub lower: Refinement,
    /// Upper body (slave) refinement.
    pub upper: Refinement,
    /// Bulk Gauss points per direction (default `p + 2`).
    pub bulk_points: Option<usize>,
    /// Spatial dimension: 2 (plane strain) or 3 (extruded along y).
    pub dimension: usize,
}

impl PatchSetup {
    /// The paper's 10 μm edge; non-matching, non-nested meshes (p = 2 with 3
    /// elements below, p = 3 with 4 elements above).
    pub fn new(interface: Interface) -> Self {
        PatchSetup {
            width: 1.0e-5,
            height_lower: 5.0e-6,
            height_upper: 5.0e-6,
            interface,
            lower: Refinement {
                degree: 2,
                elements: 3,
                degree_y: 2,
                elements_y: 3,
                interface_levels: 0,
            },
            upper: Refinement {
                degree: 3,
                elements: 4,
                degree_y: 1,
                elements_y: 4,
                interface_levels: 0,
            },
            bulk_points: None,
            dimension: 2,
        }
    }

    /// [`PatchSetup::new`] in 3D.
    pub fn new_3d(interface: Interface) -> Self {
        PatchSetup {
            dimension: 3,
            ..PatchSetup::new(interface)
        }
    }

    /// The interface curve and the two outer faces, each a degree-2 NURBS
    /// with the knots and weights of the arc (a flat interface uses unit
    /// weights): `(bottom, interface, top)` control points and the weights.
    fn curves(&self) -> (Curve, Curve, Curve, [f64; 3]) {
        let (w, h1, h) = (
            self.width,
            self.height_lower,
            self.height_lower + self.height_upper,
        );
        let line = |y: f64| [[0.0, y, 0.0], [0.5 * w, y, 0.0], [w, y, 0.0]];
        match self.interface {
            Interface::Flat => (line(0.0), line(h1), line(h), [1.0; 3]),
            Interface::Curved => {
                let r = w / (2.0 * std::f64::consts::FRAC_PI_4.sin());
                let centre = [0.5 * w, h1 - r * std::f64::consts::FRAC_PI_4.cos(), 0.0];
                let arc = shapes::circular_arc(
                    centre,
                    r,
                    3.0 * std::f64::consts::FRAC_PI_4,
                    std::f64::consts::FRAC_PI_4,
                );
                let p = arc.control_points();
                let wt = arc.weights();
                (
                    line(0.0),
                    [p[0], p[1], p[2]],
                    line(h),
                    [wt[0], wt[1], wt[2]],
                )
            }
        }
    }

    /// The (lower, upper) patches.
    pub fn patches(&self) -> (NurbsPatch, NurbsPatch) {
        let (bottom, middle, top, wt) = self.curves();
        let ruled = |a: Curve, b: Curve, r: &Refinement| {
            let kx =
                KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("one quadratic span");
            let ky = KnotVector::open_uniform(1, 1, 0.0, 1.0);
            let mut pts = a.to_vec();
            pts.extend(b);
            let weights = [wt, wt].concat();
            let mut g = NurbsPatch::new(vec![kx, ky], pts, weights).expect("valid ruled patch");
            if r.degree > 2 {
                g = g.elevate_degree(0, r.degree - 2);
            }
            if r.degree_y > 1 {
                g = g.elevate_degree(1, r.degree_y - 1);
            }
            g = g
                .refine_uniform(0, r.elements)
                .refine_uniform(1, r.elements_y);
            if self.dimension == 3 {
                g = extruded(&g, self.width, r.degree, r.elements);
            }
            g
        };
        (
            ruled(bottom, middle, &self.lower),
            ruled(middle, top, &self.upper),
        )
    }

    /// The height direction (and the vertical displacement component).
    pub fn height_dir(&self) -> usize {
        self.dimension - 1
    }

    /// The (lower, upper) bodies as analysed: [`Self::patches`] with their
    /// interface refinement ([`Refinement::interface_levels`]).
    pub fn bodies(&self) -> (ThbPatch, ThbPatch) {
        let (lower, upper) = self.patches();
        (
            interface_refined(
                &lower,
                Side::High,
                self.lower.interface_levels,
                false,
                RefinementPattern::Dyadic,
            ),
            interface_refined(
                &upper,
                Side::Low,
                self.upper.interface_levels,
                false,
                RefinementPattern::Dyadic,
            ),
        )
    }

    /// Table I with a constant conductivity.
    pub fn material() -> Material {
        Material {
            conductivity_slope: 0.0,
            ..Material::default()
        }
    }

    /// A model builder of the dimension with both bodies added (lower
    /// first), `bulk_points` Gauss points per direction if given; returns
    /// the builder, the material and the body indices.
    fn builder(
        &self,
        bulk_points: Option<usize>,
    ) -> Result<(ModelBuilder, Material, usize, usize)> {
        let m = PatchSetup::material();
        let (lower, upper) = self.bodies();
        let mut b = ModelBuilder::new(self.dimension, Scales::new(self.width, &m));
        if let Some(n) = bulk_points {
            b = b.bulk_points(n);
        }
        let lo = b.add_body("lower", lower, &m)?;
        let up = b.add_body("upper", upper, &m)?;
        Ok((b, m, lo, up))
    }
}

/// The 2D patch `g` (x along the interface, y through the height) extruded
/// over `[0, width]` along a new y, which becomes direction 1, the height
/// direction 2; degree `degree` and `elements` elements along the new y.
fn extruded(g: &NurbsPatch, width: f64, degree: usize, elements: usize) -> NurbsPatch {
    let kv = g.knots();
    let (n0, n1) = (kv[0].n_basis(), kv[1].n_basis());
    let ky = KnotVector::open_uniform(1, 1, 0.0, 1.0);
    let (mut points, mut weights) = (Vec::new(), Vec::new());
    for k in 0..n1 {
        for y in [0.0, width] {
            for i in 0..n0 {
                let x = g.control_points()[k * n0 + i];
                points.push([x[0], y, x[1]]);
                weights.push(g.weights()[k * n0 + i]);
            }
        }
    }
    let mut e = NurbsPatch::new(vec![kv[0].clone(), ky, kv[1].clone()], points, weights)
        .expect("valid extruded patch");
    if degree > 1 {
        e = e.elevate_degree(1, degree - 1);
    }
    e.refine_uniform(1, elements)
}

/// Index of the lower body (master).
const LOWER: usize = 0;
/// Index of the upper body (slave).
const UPPER: usize = 1;

/// Figures of a thermal patch test.
#[derive(Clone, Copy, Debug)]
pub struct ThermalPatch {
    /// Interface flux: the largest imbalance of a slave node's mortar flux
    /// against the trace `h̄ n_y` of the exact bulk flux, relative to `h̄ ⟨N^J⟩`.
    pub flux_deviation: f64,
    /// `max | |q| − h̄ | / h̄` over the bulk quadrature points of both bodies.
    pub bulk_flux_deviation: f64,
    /// `max |γθ^I|` (K).
    pub lumped_jump: f64,
    /// `max |ϑc|` over the slave integration points (K).
    pub pointwise_jump: f64,
    /// `max |θ − θ_exact|` over the control points (K).
    pub temperature_error: f64,
    /// Temperature rise across the block (K), for scale.
    pub rise: f64,
    /// The thermal penalty εθ in use (W/(m²K)).
    pub penalty: f64,
    /// Newton iterations.
    pub iterations: usize,
}

/// Runs the thermal patch test with the flux `flux` (W/m²) and the thermal
/// contact `settings`.
pub fn thermal_patch(
    setup: &PatchSetup,
    settings: &ContactSettings,
    flux: f64,
) -> Result<ThermalPatch> {
    let (dim, hd) = (setup.dimension, setup.height_dir());
    let (mut b, m, lo, up) = setup.builder(setup.bulk_points)?;
    let theta0 = m.reference_temperature;
    b.fix_face(lo, hd, Side::Low, dim, theta0);
    b.flux(up, hd, Side::High, flux);
    b.initial_temperature(theta0);
    b.contact((up, hd, Side::Low), (lo, hd, Side::High), settings, None)?;
    let mut model = b.build(Coupling::Thermal)?;
    // Zero pressure: every slave point in contact, the configuration undeformed.
    let c = model.contact.as_mut().expect("contact set above");
    c.frozen = Some((vec![0.0; c.n_slave()], vec![true; c.n_slave()]));
    let hist = newton().solve(&mut model)?;
    let s = model.scales;
    let c = model.contact.as_ref().expect("contact set above");
    // The interface flux into the slave, h0 = h̄ n_y (n the slave's outward
    // normal), as the mortar sees it: slave node J's balance
    // Σ_I h0^I ⟨N^I N^J⟩ = ⟨N^J h̄ n_y⟩ (flat: h0^I = −h̄), relative to h̄ ⟨N^J⟩.
    let h_bar = s.heat(flux);
    // −⟨N^J h̄ n_y⟩ on the slave face's own Gauss points (the contact
    // integrals may be segment-based).
    let mut balance = vec![0.0; c.n_slave()];
    let upper = &model.bodies[UPPER].patch;
    let (_, face_nodes) = upper.face(hd, Side::Low);
    for fe in upper.face_quadrature(hd, Side::Low, settings.interface_points) {
        for qp in &fe.points {
            for (&g, r) in fe.conn.iter().zip(&qp.r) {
                let j = face_nodes.iter().position(|&n| n == g).expect("face node");
                balance[j] -= qp.weight * r * h_bar * qp.normal[hd];
            }
        }
    }
    for (q, sp) in c.points.iter().enumerate() {
        let h0 = if settings.thermal_method == ThermalMethod::Mortar {
            let nodal = |i: usize| match settings.thermal {
                ThermalContact::Constraint {
                    enforcement: ThermalEnforcement::AugmentedLagrangian,
                    ..
                } => c.lambda_t[i] - c.eps_t * c.weighted_jump(i),
                _ => -c.eps_t * c.weighted_jump(i),
            };
            sp.conn
                .iter()
                .zip(&sp.basis)
                .map(|(&i, n)| n * nodal(i))
                .sum::<f64>()
        } else {
            -c.eps_t * c.state[q].jump.value
        };
        for (&j, n) in sp.conn.iter().zip(&sp.basis) {
            balance[j] += sp.weight * n * h0;
        }
    }
    let flux_deviation = balance
        .iter()
        .zip(&c.lumped_area)
        .map(|(b, a)| b.abs() / (h_bar * a))
        .fold(0.0, f64::max);
    // The bulk flux |q| = k |∇θ| at every bulk quadrature point (paper Fig. 9: FLX).
    let k_scaled = model.bodies[0].material.thermal_conductivity;
    let mut bulk_flux_deviation: f64 = 0.0;
    for body in &model.bodies {
        for eq in &body.quadrature {
            let mut scratch = Vec::new();
            for (_, _, dr) in eq.points_with_basis(&mut scratch) {
                let mut g = [0.0; 3];
                for (a, &cn) in eq.conn.iter().enumerate() {
                    let th = model.state[(cn + body.node_offset) * (dim + 1) + dim];
                    for (d, gd) in g.iter_mut().enumerate().take(dim) {
                        *gd += dr[a][d] * th;
                    }
                }
                let q = k_scaled * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
                bulk_flux_deviation = bulk_flux_deviation.max((q - h_bar).abs() / h_bar);
            }
        }
    }
    let lumped_jump = (0..c.n_slave())
        .map(|i| c.weighted_jump(i).abs())
        .fold(0.0, f64::max)
        * s.temperature;
    let pointwise_jump = c
        .state
        .iter()
        .map(|st| st.jump.value.abs())
        .fold(0.0, f64::max)
        * s.temperature;
    let k = m.thermal_conductivity;
    let mut temperature_error: f64 = 0.0;
    for body in [LOWER, UPPER] {
        let bd = &model.bodies[body];
        for (i, x) in bd.patch.control_points().iter().enumerate() {
            let exact = theta0 + flux * x[hd] * s.length / k;
            let t = model.temperature(bd.node_offset + i);
            temperature_error = temperature_error.max((t - exact).abs());
        }
    }
    Ok(ThermalPatch {
        flux_deviation,
        bulk_flux_deviation,
        lumped_jump,
        pointwise_jump,
        temperature_error,
        rise: flux * (setup.height_lower + setup.height_upper) / k,
        penalty: c.eps_t * s.conductivity / s.length,
        iterations: hist.total_iterations(),
    })
}

/// Figures of the mechanical patch test.
#[derive(Clone, Copy, Debug)]
pub struct MechanicalPatch {
    /// `max |pN^I − p̄| / p̄`.
    pub pressure_deviation: f64,
    /// `max |g^I|` over the slave control points, relative to the platen displacement.
    pub gap: f64,
    /// Platen displacement error relative to the two compressed bars.
    pub displacement_error: f64,
    /// Newton iterations.
    pub iterations: usize,
}

/// Runs the mechanical patch test (flat interface) at the platen pressure
/// `pressure` (Pa) with `interface_points` Gauss points per slave element
/// (or per segment, with segment-based `integration`).
pub fn mechanical_patch(
    setup: &PatchSetup,
    pressure: f64,
    interface_points: usize,
    integration: Integration,
) -> Result<MechanicalPatch> {
    let m = PatchSetup::material();
    let mut model = mechanical_model(setup, pressure, interface_points, integration)?;
    let hist = newton().solve(&mut model)?;
    let s = model.scales;
    let c = model.contact.as_ref().expect("contact set above");
    let pressure_deviation = (0..c.n_slave())
        .map(|i| (c.pressure(i) * s.stress - pressure).abs() / pressure)
        .fold(0.0, f64::max);
    let stretch = platen_stretch(&m, pressure, m.reference_temperature)?;
    let exact = (stretch - 1.0) * (setup.height_lower + setup.height_upper);
    let pl = &model.platens()[0];
    let u = model.displacement(pl.nodes[0], pl.field);
    let gap = (0..c.n_slave())
        .map(|i| c.weighted_gap(i).abs())
        .fold(0.0, f64::max)
        * s.length
        / exact.abs();
    Ok(MechanicalPatch {
        pressure_deviation,
        gap,
        displacement_error: (u - exact).abs() / exact.abs(),
        iterations: hist.total_iterations(),
    })
}

/// The model of the mechanical patch test at first touch, unsolved (the
/// platen pressure at load factor 1).
pub fn mechanical_model(
    setup: &PatchSetup,
    pressure: f64,
    interface_points: usize,
    integration: Integration,
) -> Result<Model> {
    let (dim, hd) = (setup.dimension, setup.height_dir());
    let (mut b, m, lo, up) = setup.builder(None)?;
    for f in 0..dim {
        b.fix_face(lo, hd, Side::Low, f, 0.0);
    }
    for d in 0..hd {
        b.linear_lateral(lo, d, d);
        b.linear_lateral(up, d, d);
    }
    b.platen(up, hd, Side::High, hd, pressure);
    b.initial_temperature(m.reference_temperature);
    b.contact(
        (up, hd, Side::Low),
        (lo, hd, Side::High),
        &ContactSettings {
            interface_points,
            integration,
            ..ContactSettings::default()
        },
        None,
    )?;
    let mut model = b.build(Coupling::Mechanical)?;
    model.touch(up, hd)?;
    Ok(model)
}

fn newton() -> Newton {
    Newton::new(NewtonSettings::default(), LoadStepping::default())
}

/// Mortar thermal contact with the augmented Lagrangian (the paper's method).
pub fn mortar_al() -> ContactSettings {
    ContactSettings::default()
}

/// Continuum (pointwise) penalty thermal contact, default penalty `10 k/h`.
pub fn continuum_penalty() -> ContactSettings {
    ContactSettings {
        thermal: ThermalContact::Constraint {
            enforcement: ThermalEnforcement::Penalty,
            penalty: None,
        },
        thermal_method: ThermalMethod::Continuum,
        ..ContactSettings::default()
    }
}
