//! Thermoelastic Hertz contact of two cylinders (paper Sect. 5.1, spec §10.3).
//!
//! Plane strain, two equal cylinders of radius `R` (reduced radius `R/2`),
//! modelled by symmetry as the half `x ≥ 0`: each body is the ruled NURBS
//! patch between a 60° circular arc (exact, apex at the origin) and a straight
//! far face at the distance `H` from the apex. The meshes are uniform over
//! `1.25 a` from the apex along the arc and below the interface, then grow
//! geometrically; the two bodies have different element counts
//! (non-matching). Mechanics, force controlled: the lower body's far face is
//! fixed, a rigid platen pushes the upper one with the force `F/2` per unit
//! length, `u_x = 0` on the symmetry plane, the rest is free; `F` gives
//! `a/R = 0.03` (strains `~p0/E* = a/R`). Thermal phase on the frozen
//! configuration (constant conductivity, as in the paper's linearized Hertz
//! example): the upper far face `10 K` above the lower one, adiabatic
//! elsewhere.
//!
//! Checked: the contact half-width against Hertz, `a = √(4 F R*/(π E*))`
//! (measured by [`measure`]: zero crossing of the augmented-Lagrangian
//! indicator between slave control points); the lumped pressures against
//! `p(x) = p0 √(1 − (x/a)²)`; and the interface flux against the constraint
//! limit (5.2) `h0/h0_min = 1/√(1 − (x/a)²)`, `h0_min = Q/(π a)` (5.3) with
//! `Q` the computed heat flow, for the constitutive model `h0 = −kθ pN ϑc`
//! with growing `kθ` and the constraint model (augmented Lagrangian). Two
//! measures: the lumped nodal fluxes `h0^I` over `|x/a| < 0.8` (and 0.5),
//! which carry the oscillations the `1/√` edge singularity induces in the
//! smooth multiplier space (paper Figs. 6–7: they reach the centre on coarse
//! meshes and for p = 3), and the heat flow through `[−x, x]` of the flux
//! field, `Q(x)/Q`, against (5.2) integrated, `(2/π) arcsin(x/a)`, over
//! `x/a < 0.8`, in which those oscillations cancel. `kθ` in W/(m²·K·Pa),
//! which is also the paper's W/(mm²·K·MPa).
//!
//! Modelling error: the closed forms are half-planes in linear elasticity;
//! here the bodies have the size `~R` (corrections `~(a/R)²`) and finite
//! strains `~a/R`.

use crate::Result;
use crate::analytical::hertz;
use crate::bulk::Coupling;
use crate::contact::{ContactSettings, ThermalContact, ThermalEnforcement, ThermalMethod};
use crate::geometry::{KnotVector, NurbsPatch, Side, shapes};
use crate::material::Material;
use crate::sample::micro::measure;
use crate::solve::{
    LoadStepping, Model, ModelBuilder, Newton, NewtonSettings, NonlinearProblem, Scales,
};
use crate::verify::record_series;

/// Break points in `(0, length)`: `n` equal elements over `[0, fine]`, then
/// elements growing by `growth` (the last one stretched or shrunk to fit).
pub fn breaks(length: f64, fine: f64, n: usize, growth: f64) -> Vec<f64> {
    let h = fine / n as f64;
    let mut v: Vec<f64> = (1..=n).map(|i| i as f64 * h).collect();
    let mut step = h;
    let mut x = fine;
    loop {
        step *= growth;
        if x + 1.5 * step >= length {
            break;
        }
        x += step;
        v.push(x);
    }
    v.retain(|&b| b < length * (1.0 - 1e-9));
    v
}

/// `u` with `f(u) = x` for an increasing `f` on `[0, 1]` (bisection).
fn invert(f: &dyn Fn(f64) -> f64, x: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if f(mid) < x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Geometry, load and discretization of the Hertz benchmark.
#[derive(Clone, Debug)]
pub struct HertzSetup {
    /// Cylinder radius `R` (m).
    pub radius: f64,
    /// Distance `H` from the apex to the far face (m).
    pub height: f64,
    /// Target `a/R` that sets the force.
    pub a_over_r: f64,
    /// NURBS degree.
    pub degree: usize,
    /// Uniform elements over `[0, 1.25 a]` along the arc and over the depth
    /// `1.25 a` below the interface, (upper, lower) body; beyond, the
    /// elements grow geometrically by [`HertzSetup::growth`].
    pub contact_elements: [usize; 2],
    /// Growth factor of the elements beyond the contact zone.
    pub growth: f64,
    /// Temperature difference between the far faces (K).
    pub temperature_difference: f64,
}

impl HertzSetup {
    /// The coarse mesh of degree `p` (`fine`: twice the elements per direction).
    pub fn new(degree: usize, fine: bool) -> Self {
        let f = if fine { 2 } else { 1 };
        HertzSetup {
            radius: 1.0e-5,
            height: 1.0e-5,
            a_over_r: 0.03,
            degree,
            contact_elements: [8 * f, 7 * f],
            growth: 1.3,
            temperature_difference: 10.0,
        }
    }

    /// Table I with a constant conductivity.
    pub fn material() -> Material {
        super::benchmark_material()
    }

    /// `E*` of the two (equal, plane-strain) bodies.
    pub fn e_star(&self) -> f64 {
        super::benchmark_e_star()
    }

    /// Reduced radius `R/2`.
    pub fn reduced_radius(&self) -> f64 {
        hertz::reduced_radius(self.radius, self.radius)
    }

    /// Half-width of the model (the far faces' width): `R sin 60°`.
    pub fn half_span(&self) -> f64 {
        self.radius * (std::f64::consts::PI / 3.0).sin()
    }

    /// The total force per unit length `F` (N/m) of the target `a/R`.
    pub fn force(&self) -> f64 {
        hertz::force_per_length(
            self.a_over_r * self.radius,
            self.reduced_radius(),
            self.e_star(),
        )
    }

    /// Hertz's half-width for [`HertzSetup::force`].
    pub fn hertz_half_width(&self) -> f64 {
        hertz::contact_half_width(self.force(), self.reduced_radius(), self.e_star())
    }

    /// One body: the ruled patch between the arc (centre `(0, ±R)`, from the
    /// apex over 60°) and the far face `y = ∓H`, refined. `upper`: the arc is
    /// its bottom face (dir 1 Low), else its top face (dir 1 High).
    fn body(&self, upper: bool) -> NurbsPatch {
        let (r, h) = (self.radius, self.height);
        let phi = std::f64::consts::PI / 3.0;
        let (centre, start, end, far) = if upper {
            (
                [0.0, r, 0.0],
                1.5 * std::f64::consts::PI,
                1.5 * std::f64::consts::PI + phi,
                h,
            )
        } else {
            (
                [0.0, -r, 0.0],
                0.5 * std::f64::consts::PI,
                0.5 * std::f64::consts::PI - phi,
                -h,
            )
        };
        let arc = shapes::circular_arc(centre, r, start, end);
        // The far face: the arc's x control coordinates and weights on y = far,
        // a straight line with the arc's parametrization in x (vertical rulings).
        let line: Vec<[f64; 3]> = arc
            .control_points()
            .iter()
            .map(|p| [p[0], far, 0.0])
            .collect();
        let (bottom, top) = if upper {
            (arc.control_points().to_vec(), line)
        } else {
            (line, arc.control_points().to_vec())
        };
        let mut pts = bottom;
        pts.extend(top);
        let weights = [arc.weights(), arc.weights()].concat();
        let ky = KnotVector::open_uniform(1, 1, 0.0, 1.0);
        let mut g = NurbsPatch::new(vec![arc.knots()[0].clone(), ky], pts, weights)
            .expect("valid ruled patch");
        let p = self.degree;
        if p > 2 {
            g = g.elevate_degree(0, p - 2);
        }
        if p > 1 {
            g = g.elevate_degree(1, p - 1);
        }
        let n = self.contact_elements[usize::from(!upper)];
        let a = self.a_over_r * r;
        // Along the arc: knots where the arc's x takes the break positions.
        let xs = breaks(self.half_span(), 1.25 * a, n, self.growth);
        let arc_x = |u: f64| g.point(&[u, 0.0])[0];
        let ux: Vec<f64> = xs.iter().map(|&x| invert(&arc_x, x)).collect();
        // Through the height: v is linear in y on every ruling.
        let ys = breaks(h, 1.25 * a, n, self.growth);
        let vy: Vec<f64> = ys
            .iter()
            .map(|&y| if upper { y / h } else { 1.0 - y / h })
            .collect();
        g.insert_knots(0, &ux).insert_knots(1, &vy)
    }

    /// The model at zero load, mechanical phase.
    pub fn model(&self) -> Result<Model> {
        let m = Self::material();
        let mut b = ModelBuilder::new(2, Scales::new(self.radius, &m));
        let lo = b.add_body("lower", &self.body(false), &m)?;
        let up = b.add_body("upper", &self.body(true), &m)?;
        b.fix_face(lo, 1, Side::Low, 0, 0.0);
        b.fix_face(lo, 1, Side::Low, 1, 0.0);
        b.fix_face(lo, 0, Side::Low, 0, 0.0);
        b.fix_face(up, 0, Side::Low, 0, 0.0);
        b.platen(up, 1, Side::High, 1, 0.5 * self.force() / self.half_span());
        let theta0 = m.reference_temperature;
        b.fix_face(lo, 1, Side::Low, 2, theta0);
        b.fix_face(up, 1, Side::High, 2, theta0 + self.temperature_difference);
        b.initial_temperature(theta0);
        b.contact(
            (up, 1, Side::Low),
            (lo, 1, Side::High),
            &ContactSettings::default(),
            None,
        )?;
        let mut model = b.build(Coupling::Mechanical)?;
        model.touch(up, 1)?;
        Ok(model)
    }
}

/// The interface flux of one thermal model, normalized.
#[derive(Clone, Debug)]
pub struct FluxProfile {
    /// The thermal contact model.
    pub model: ThermalModel,
    /// `(x/a, h0/h0_min)` at the active slave control points (Greville abscissae).
    pub points: Vec<(f64, f64)>,
    /// `max |h0^I/h0_min − 1/√(1 − (x_I/a)²)|` over `|x_I/a| < 0.8`.
    pub max_error: f64,
    /// The same over `|x_I/a| < 0.5`.
    pub max_error_centre: f64,
    /// `max |Q(x)/Q − (2/π) arcsin(x/a)|` over `x/a < 0.8`: the computed heat
    /// flow through `[−x, x]` (the flux field `Σ N^I h0^I` integrated at the
    /// slave integration points) against (5.2) integrated.
    pub cumulative_error: f64,
    /// Heat flow `Q` through the interface (W/m, both halves).
    pub heat_flow: f64,
}

/// Results of the Hertz benchmark.
#[derive(Clone, Debug)]
pub struct HertzResult {
    /// Computed contact half-width (m).
    pub half_width: f64,
    /// Hertz's half-width (m).
    pub hertz_half_width: f64,
    /// `max |pN^I − p(x_I)| / p0` over `|x_I/a| < 0.8`.
    pub pressure_error: f64,
    /// The same over `|x_I/a| < 0.5`.
    pub pressure_error_centre: f64,
    /// One profile per thermal model.
    pub fluxes: Vec<FluxProfile>,
    /// Newton iterations of the mechanical phase.
    pub iterations: usize,
}

/// One thermal contact model of the benchmark.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalModel {
    /// `Some(kθ)`: constitutive with `α = 1`; `None`: constraint model
    /// (augmented Lagrangian for the mortar method, penalty for the continuum).
    pub conductance_coefficient: Option<f64>,
    /// Mortar or continuum.
    pub method: ThermalMethod,
}

impl ThermalModel {
    /// Mortar with `kθ` (`None`: constraint, augmented Lagrangian).
    pub fn mortar(kt: Option<f64>) -> Self {
        ThermalModel {
            conductance_coefficient: kt,
            method: ThermalMethod::Mortar,
        }
    }

    fn settings(&self) -> ContactSettings {
        let thermal = match (self.conductance_coefficient, self.method) {
            (Some(k), _) => ThermalContact::Constitutive {
                conductance_coefficient: k,
                pressure_exponent: 1.0,
            },
            (None, ThermalMethod::Mortar) => ThermalContact::default(),
            (None, ThermalMethod::Continuum) => ThermalContact::Constraint {
                enforcement: ThermalEnforcement::Penalty,
                penalty: None,
            },
        };
        // The paper's mortar method (nodal supports): the flux profile of
        // (5.2)–(5.3) is measured from the lumped nodal fluxes Σ N^I h0^I over
        // the whole slave surface, which is that method's flux field (the
        // contact-zone integration of the two-phase thermal phase,
        // `thermal_zone`, has its own checks: Westergaard, Sect. 5.7).
        ContactSettings {
            thermal,
            thermal_method: self.method,
            thermal_zone: Some(false),
            ..ContactSettings::default()
        }
    }
}

/// Solves the mechanical phase, then a thermal phase per entry of `models`.
pub fn hertz(setup: &HertzSetup, models: &[ThermalModel]) -> Result<HertzResult> {
    let mut model = setup.model()?;
    let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
    let iterations = newton.solve(&mut model)?.total_iterations();
    let s = model.scales;
    let (a_hertz, force) = (setup.hertz_half_width(), setup.force());
    let p0 = hertz::peak_pressure(force, a_hertz);
    let meas = measure(&model, 1.0)?;
    let c = model.contact.as_ref().expect("contact set above");
    let xs: Vec<f64> = c
        .slave_nodes
        .iter()
        .map(|&n| model.node_x(n) * s.length)
        .collect();
    let extent = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - xs.iter().cloned().fold(f64::INFINITY, f64::min);
    let half_width = meas.contact_fraction * extent;
    let pressure_error_within = |limit: f64| {
        (0..c.n_slave())
            .filter(|&i| xs[i].abs() < limit * a_hertz)
            .map(|i| (c.pressure(i) * s.stress - hertz::pressure(force, a_hertz, xs[i])).abs() / p0)
            .fold(0.0, f64::max)
    };
    let (pressure_error, pressure_error_centre) =
        (pressure_error_within(0.8), pressure_error_within(0.5));
    let saved = model.save();
    let mut fluxes = Vec::new();
    for tm in models {
        let settings = tm.settings();
        model.restore(&saved);
        model.contact.as_mut().expect("contact set above").settings = settings.scaled(&s);
        model.set_coupling(Coupling::Thermal)?;
        model.set_path([1.0, 0.0], [1.0, 1.0]);
        newton.solve(&mut model)?;
        let c = model.contact.as_ref().expect("contact set above");
        // Lumped nodal fluxes into the slave (mortar), and the flux field at
        // the slave integration points: `Σ N^I h0^I` (mortar) or pointwise (continuum).
        let nodal = |i: usize| -> f64 {
            if !c.is_active(i) {
                return 0.0;
            }
            let v = match c.settings.thermal {
                ThermalContact::Constitutive {
                    conductance_coefficient: k,
                    pressure_exponent: alpha,
                } => -k * c.pressure(i).max(0.0).powf(alpha) * c.weighted_jump(i),
                _ if tm.method == ThermalMethod::Continuum => -c.eps_t * c.weighted_jump(i),
                _ => c.lambda_t[i] - c.eps_t * c.weighted_jump(i),
            };
            v * s.flux()
        };
        let h0: Vec<f64> = (0..c.n_slave()).map(nodal).collect();
        let field_at = |q: usize| -> f64 {
            let sp = &c.points[q];
            if tm.method == ThermalMethod::Mortar {
                return sp.conn.iter().zip(&sp.basis).map(|(&j, n)| n * h0[j]).sum();
            }
            if !sp.conn.iter().any(|&j| c.is_active(j)) {
                return 0.0;
            }
            let pn: f64 = sp
                .conn
                .iter()
                .zip(&sp.basis)
                .map(|(&j, n)| n * c.pressure(j).max(0.0))
                .sum();
            let coefficient = match c.settings.thermal {
                ThermalContact::Constitutive {
                    conductance_coefficient: k,
                    pressure_exponent: alpha,
                } => k * pn.powf(alpha),
                _ => c.eps_t,
            };
            -coefficient * c.state[q].jump.value * s.flux()
        };
        // Q (both halves), flux into the slave is negative (heat flows down).
        let heat_flow = -2.0
            * (0..c.points.len())
                .map(|q| c.points[q].weight * s.length * field_at(q))
                .sum::<f64>();
        let h_min = hertz::constraint_limit_min_flux(heat_flow, a_hertz);
        let points: Vec<(f64, f64)> = (0..c.n_slave())
            .filter(|&i| c.is_active(i))
            .map(|i| (xs[i] / a_hertz, -h0[i] / h_min))
            .collect();
        let err = |limit: f64| {
            points
                .iter()
                .filter(|(r, _)| r.abs() < limit)
                .map(|(r, h)| (h - 1.0 / (1.0 - r * r).sqrt()).abs())
                .fold(0.0, f64::max)
        };
        // Heat flow through [0, x] from the flux field at the slave points.
        let mut field: Vec<(f64, f64)> = c
            .points
            .iter()
            .enumerate()
            .map(|(q, sp)| {
                let x: f64 = sp.conn.iter().zip(&sp.basis).map(|(&j, n)| n * xs[j]).sum();
                (x, sp.weight * s.length * field_at(q))
            })
            .collect();
        field.sort_by(|a, b| a.0.total_cmp(&b.0));
        let total: f64 = field.iter().map(|v| v.1).sum();
        let mut acc = 0.0;
        let mut cumulative_error: f64 = 0.0;
        let mut cumulative = (Vec::new(), Vec::new());
        for (x, q) in &field {
            // The point's own weight half counted (midpoint of its cell).
            let at = (acc + 0.5 * q) / total;
            acc += q;
            let r = x / a_hertz;
            if r <= 1.2 {
                cumulative.0.push(r);
                cumulative.1.push(at);
            }
            if r < 0.8 {
                let exact = 2.0 / std::f64::consts::PI * r.min(1.0).asin();
                cumulative_error = cumulative_error.max((at - exact).abs());
            }
        }
        let (max_error, max_error_centre) = (err(0.8), err(0.5));
        // The profile of the plots (docs/validation.md), against (5.2).
        let label = format!(
            "{} {} (p={}, {} el.)",
            match tm.method {
                ThermalMethod::Mortar => "mortar",
                ThermalMethod::Continuum => "continuum",
            },
            match tm.conductance_coefficient {
                Some(k) => format!("kθ={k:e}"),
                None => "constraint".into(),
            },
            setup.degree,
            setup.contact_elements[0]
        );
        let (rx, ry): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
        record_series("contact_hertz", &label, ("x/a", "h0/h0_min"), &rx, &ry);
        let (cx, cy) = cumulative;
        record_series("contact_hertz", &label, ("x/a", "Q(x)/Q"), &cx, &cy);
        fluxes.push(FluxProfile {
            model: *tm,
            points,
            max_error,
            max_error_centre,
            cumulative_error,
            heat_flow,
        });
        model.restore(&saved);
        model.set_coupling(Coupling::Mechanical)?;
    }
    Ok(HertzResult {
        half_width,
        hertz_half_width: a_hertz,
        pressure_error,
        pressure_error_centre,
        fluxes,
        iterations,
    })
}
