//! Frictionless Hertz contact of a sphere on a flat in 3D, and the
//! constraint-limit flux through its contact spot (issue 12, item 6; the 3D
//! counterpart of paper Sect. 5.1 and (5.2)–(5.3)).
//!
//! Geometry, by symmetry a quarter: two blocks on `[0, W]²` in x, y, the
//! apex of the sphere at the corner `x = y = 0`. The upper body (slave)
//! lies between the paraboloid `z = (x² + y²)/(2R)` (Hertz's gap; exact: a
//! biquadratic polynomial, so the B-spline geometry has no fit error) and
//! the flat far face `z = H`; the lower body (master) is the flat block
//! `z ∈ [−H, 0]`. Each is a B-spline volume with `x = W u`, `y = W v`
//! exactly, graded by knot insertion ([`breaks`]): uniform over `1.25 a`
//! from the apex in x and y and below (above) the interface, then growing
//! geometrically; the two bodies have different element counts
//! (non-matching).
//!
//! Mechanics, force controlled: `u_x = 0` on `x = 0`, `u_y = 0` on `y = 0`
//! (symmetry, both bodies), the lower far face fixed, a rigid platen pushes
//! the upper far face with `F/4`; the outer lateral faces `x = W`, `y = W`
//! are free ([`LateralFaces::Free`], or normal-fixed for the comparison).
//! `F` gives `a/R = 0.03`. Thermal phase on the frozen configuration
//! (constant conductivity): the upper far face `10 K` above the lower one,
//! adiabatic elsewhere, the constraint model with the augmented Lagrangian
//! (mortar, nodal supports).
//!
//! Checked (closed forms in [`crate::analytical::hertz`]):
//! - the contact radius against `a = (3 F R/(4 E*))^(1/3)`: from the
//!   contact area [`measure`] (the interpolated indicator positive),
//!   `a = √(4 A_c/π)` for the quarter, and from the indicator's zero
//!   crossing along the x axis;
//! - the pressure against `p(r) = p0 √(1 − r²/a²)` over `r/a < 0.8`: the
//!   lumped pressures (multipliers) `pN^I` at the slave control points, the
//!   nodal contact forces per lumped area `⟨N^I p⟩/⟨N^I⟩` (`p = Σ N^J
//!   pN^J`), and the force inside the radius `r`, `F(r)/F = 1 − (1 −
//!   r²/a²)^(3/2)`;
//! - the interface flux against the isothermal spot, (5.2)–(5.3) in 3D:
//!   `h0/h0_min = 1/√(1 − r²/a²)`, `h0_min = Q/(2π a²)` with `Q` the
//!   computed heat flow, as nodal heat flows per lumped area `⟨N^I h0⟩/⟨N^I⟩`
//!   away from the edge (`r/a < 0.5`), and the heat flow through the disc of
//!   radius `r`, `Q(r)/Q = 1 − √(1 − r²/a²)`, for `r/a ≤ 0.8`;
//! - `|γθ^I| ≈ 0` on the active set (the augmented-Lagrangian constraint).
//!
//! Measured (p = 2; `n` = slave elements over `1.25 a`, see
//! [`Hertz3dSetup::new`]; mechanical unknowns; CPU time of the case on the
//! shared 2-core machine):
//!
//! | n | unknowns | a (area) | a (x axis) | `pN^I` | `⟨N^I p⟩/⟨N^I⟩` | `F(r)` | `⟨N^I h0⟩/⟨N^I⟩`, r/a < 0.5 | `Q(r)` | CPU |
//! |---|---|---|---|---|---|---|---|---|---|
//! | 6 | 7 539 | −6.6 % | −7.3 % | 0.75 | 0.049 | 0.022 | 0.39 | 0.028 | 7 s |
//! | 8 | 12 136 | −4.6 % | −4.1 % | 0.40 | 0.026 | 0.0044 | 0.20 | 0.054 | 11 s |
//! | 10 | 18 190 | −3.7 % | −4.2 % | 0.17 | 0.025 | 0.0041 | 0.22 | 0.027 | 29 s |
//! | 12 | 27 473 | −3.0 % | −3.1 % | 0.24 | 0.018 | 0.0023 | 0.22 | 0.047 | 55 s |
//!
//! The radii in the table are the indicator's crossings: their error is
//! first order in the element size (fitted order 1.02 over n = 8, 10, 12;
//! extrapolated −0.1 %), the inward bias of the nodal active set, as in
//! 2D. With the edge fitted to the point gaps outside it
//! (`contact::mortar`'s `edge3d`, stop 23) the radius from the area is
//! −0.23, −1.14, −0.66, −0.54 % on n = 6, 8, 10, 12 (x axis +0.97, −1.49,
//! −1.51, −0.53 %). The lumped multipliers `pN^I` carry a checkerboard mode (the consistent mortar matrix `⟨N^I N^J⟩` of
//! quadratic B-splines damps the alternating mode by `(16/120)² ≈ 1/56` on
//! a surface, against `2/15` on a curve): the nodal forces, the pressure
//! field and `F(r)` are smooth and converge. The thermal multipliers ring
//! around the singular edge flux of the nodal supports (`h0^I` up to ±15
//! `h0_min` near `r/a = 0.8` on every mesh), so the flux is checked through
//! the nodal heat flows per lumped area in the centre and through `Q(r)`,
//! which carries the nodal-support spot's edge (the supports of the outer
//! active nodes conduct up to about one element beyond the mechanical
//! zone) and stays at 3–5 % without converging in max norm.
//!
//! Newton: the mechanical phase starts from first touch with the
//! multipliers seeded by Hertz's pressure ([`Hertz3dSetup::seed`]; 3–5
//! iterations instead of 22 from a single node in contact, the same
//! converged state to 7e−12); the thermal phase takes one iteration.
//!
//! Modelling errors (the change of `a` at n = 8): the closed forms are
//! half-spaces in linear elasticity; here the blocks are `W = H = 10 a`:
//! normal-fixed instead of free lateral faces change `a` by 1.3e−5 `a`,
//! `W = H = 20 a` by 1.1e−4 `a` (finite-body corrections `~(a/W)³`, and
//! the edge fit's change with the mesh); the strains are finite
//! (`p0/E* ≈ a/R`): `a/R = 0.015` instead of 0.03 changes `a` by
//! 6.3e−4 `a`. The paraboloid is exact (no fit error), and
//! the adiabatic lateral faces make the thermal problem a spot in a square
//! flux tube of half-width `10 a`.

use crate::Result;
use crate::analytical::hertz;
use crate::bulk::Coupling;
use crate::contact::{ContactSettings, ThermalContact};
use crate::geometry::{KnotVector, NurbsPatch, Side};
use crate::material::Material;
use crate::quadrature::GaussLegendre;
use crate::sample::micro::measure;
use crate::solve::{
    LoadStepping, Model, ModelBuilder, Newton, NewtonSettings, NonlinearProblem, Scales,
};
use crate::verify::record_series;

use super::hertz::breaks;

/// Boundary condition of the outer lateral faces `x = W`, `y = W`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LateralFaces {
    /// Traction free (a finite block).
    Free,
    /// Normal displacement zero, tangentially free.
    FixedNormal,
}

/// Geometry, load and discretization of the 3D Hertz benchmark.
#[derive(Clone, Debug)]
pub struct Hertz3dSetup {
    /// Sphere radius `R` (m) (the reduced radius: the lower body is flat).
    pub radius: f64,
    /// Target `a/R` that sets the force.
    pub a_over_r: f64,
    /// Quarter width `W` in units of Hertz's `a`.
    pub width_over_a: f64,
    /// Depth `H` of each body from the interface plane, in units of `a`.
    pub height_over_a: f64,
    /// NURBS degree (every direction).
    pub degree: usize,
    /// Uniform elements over `[0, 1.25 a]` in x and y, (upper, lower) body;
    /// beyond, they grow by [`Hertz3dSetup::growth`].
    pub contact_elements: [usize; 2],
    /// Uniform elements over the depth `1.25 a` below (above) the
    /// interface, (upper, lower); beyond, they grow by the same factor.
    pub depth_elements: [usize; 2],
    /// Growth factor of the elements beyond the contact zone.
    pub growth: f64,
    /// The outer lateral faces.
    pub lateral: LateralFaces,
    /// Temperature difference between the far faces (K).
    pub temperature_difference: f64,
    /// Seed the contact multipliers with Hertz's pressure at first touch
    /// (a predictor of the active set: the converged state does not depend
    /// on it, Newton's path does).
    pub seed: bool,
    /// The augmentation factor `mechanical_penalty` (`None`: 1).
    pub mechanical_penalty: Option<f64>,
}

impl Hertz3dSetup {
    /// The mesh with `n` slave elements over `1.25 a` in x and y (`n − 1`
    /// on the master; through the depth `n/2 + 1` and `n/2`), p = 2,
    /// growth 2, `W = H = 10 a`, free lateral faces, `a/R = 0.03`.
    pub fn new(n: usize) -> Self {
        Hertz3dSetup {
            radius: 1.0e-5,
            a_over_r: 0.03,
            width_over_a: 10.0,
            height_over_a: 10.0,
            degree: 2,
            contact_elements: [n, n - 1],
            depth_elements: [n / 2 + 1, n / 2],
            growth: 2.0,
            lateral: LateralFaces::Free,
            temperature_difference: 10.0,
            seed: true,
            mechanical_penalty: None,
        }
    }

    /// Table I with a constant conductivity.
    pub fn material() -> Material {
        super::benchmark_material()
    }

    /// `E*` of the two equal bodies.
    pub fn e_star(&self) -> f64 {
        super::benchmark_e_star()
    }

    /// Hertz's contact radius `a` targeted (m).
    pub fn hertz_radius(&self) -> f64 {
        self.a_over_r * self.radius
    }

    /// The total force `F` (N) (the quarter carries `F/4`).
    pub fn force(&self) -> f64 {
        hertz::sphere_force(self.hertz_radius(), self.radius, self.e_star())
    }

    /// Quarter width `W` (m).
    pub fn width(&self) -> f64 {
        self.width_over_a * self.hertz_radius()
    }

    /// Depth `H` (m).
    pub fn height(&self) -> f64 {
        self.height_over_a * self.hertz_radius()
    }

    /// One body as a B-spline volume: x = W u, y = W v; `upper`: between the
    /// paraboloid (its bottom face, dir 2 Low) and `z = H`, else the block
    /// `[−H, 0]` (its top face, dir 2 High); graded towards the apex and the
    /// interface.
    pub fn body(&self, upper: bool) -> NurbsPatch {
        let (w, h, r) = (self.width(), self.height(), self.radius);
        let quadratic =
            KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("one quadratic span");
        let linear = KnotVector::open_uniform(1, 1, 0.0, 1.0);
        // Bézier coefficients of x = W u and of u² (so x² = W² u²).
        let xs = [0.0, 0.5 * w, w];
        let sq = [0.0, 0.0, 1.0];
        let mut points = Vec::new();
        for k in 0..2 {
            for j in 0..3 {
                for i in 0..3 {
                    let surface = w * w * (sq[i] + sq[j]) / (2.0 * r);
                    let z = match (upper, k) {
                        (true, 0) => surface,
                        (true, _) => h,
                        (false, 0) => -h,
                        (false, _) => 0.0,
                    };
                    points.push([xs[i], xs[j], z]);
                }
            }
        }
        let n_points = points.len();
        let mut g = NurbsPatch::new(
            vec![quadratic.clone(), quadratic, linear],
            points,
            vec![1.0; n_points],
        )
        .expect("valid Bézier block");
        let p = self.degree;
        if p > 2 {
            g = g.elevate_degree(0, p - 2).elevate_degree(1, p - 2);
        }
        if p > 1 {
            g = g.elevate_degree(2, p - 1);
        }
        let n = self.contact_elements[usize::from(!upper)];
        let a = self.hertz_radius();
        let lateral: Vec<f64> = breaks(w, 1.25 * a, n, self.growth)
            .iter()
            .map(|x| x / w)
            .collect();
        // Through the depth: z is linear in the third parameter on every
        // vertical line, and the paraboloid is within (1.25 a)²/(2R) = 0.02 a
        // of z = 0 over the uniform zone.
        let nd = self.depth_elements[usize::from(!upper)];
        let depth: Vec<f64> = breaks(h, 1.25 * a, nd, self.growth)
            .iter()
            .map(|&d| if upper { d / h } else { 1.0 - d / h })
            .collect();
        g.insert_knots(0, &lateral)
            .insert_knots(1, &lateral)
            .insert_knots(2, &depth)
    }

    /// The model at first touch, mechanical phase.
    pub fn model(&self) -> Result<Model> {
        let m = Self::material();
        let w = self.width();
        let mut b = ModelBuilder::new(3, Scales::new(w, &m));
        let lo = b.add_body("lower", &self.body(false), &m)?;
        let up = b.add_body("upper", &self.body(true), &m)?;
        for body in [lo, up] {
            b.fix_face(body, 0, Side::Low, 0, 0.0);
            b.fix_face(body, 1, Side::Low, 1, 0.0);
            if self.lateral == LateralFaces::FixedNormal {
                b.fix_face(body, 0, Side::High, 0, 0.0);
                b.fix_face(body, 1, Side::High, 1, 0.0);
            }
        }
        for f in 0..3 {
            b.fix_face(lo, 2, Side::Low, f, 0.0);
        }
        b.platen(up, 2, Side::High, 2, 0.25 * self.force() / (w * w));
        let theta0 = m.reference_temperature;
        b.fix_face(lo, 2, Side::Low, 3, theta0);
        b.fix_face(up, 2, Side::High, 3, theta0 + self.temperature_difference);
        b.initial_temperature(theta0);
        b.contact(
            (up, 2, Side::Low),
            (lo, 2, Side::High),
            &settings(self.mechanical_penalty),
            None,
        )?;
        let mut model = b.build(Coupling::Mechanical)?;
        model.touch(up, 2)?;
        Ok(model)
    }
}

/// The paper's mortar method with nodal supports (as the 2D benchmark), the
/// constraint model with the augmented Lagrangian; the augmentation factor
/// `mechanical_penalty`.
fn settings(mechanical_penalty: Option<f64>) -> ContactSettings {
    ContactSettings {
        thermal: ThermalContact::default(),
        thermal_zone: Some(false),
        mechanical_penalty,
        ..ContactSettings::default()
    }
}

/// A nodal quantity against its closed form over the slave control points:
/// `max |v^I − exact(r_I)|` over `r_I/a < 0.8` and over `r_I/a < 0.5`.
#[derive(Clone, Copy, Debug, Default)]
pub struct NodalError {
    /// Over `r_I/a < 0.8`.
    pub interior: f64,
    /// Over `r_I/a < 0.5`.
    pub centre: f64,
}

impl NodalError {
    fn new(points: &[(f64, f64)], exact: impl Fn(f64) -> f64) -> Self {
        let within = |limit: f64| {
            points
                .iter()
                .filter(|(r, _)| *r < limit)
                .map(|&(r, v)| (v - exact(r)).abs())
                .fold(0.0, f64::max)
        };
        NodalError {
            interior: within(0.8),
            centre: within(0.5),
        }
    }
}

/// Results of the 3D Hertz benchmark.
#[derive(Clone, Debug)]
pub struct Hertz3dResult {
    /// Contact radius from the contact area, `√(4 A_c/π)` (m).
    pub radius: f64,
    /// Contact radius from the indicator's zero crossing along the x axis (m).
    pub axis_radius: f64,
    /// Hertz's contact radius (m).
    pub hertz_radius: f64,
    /// The lumped pressures (multipliers) `pN^I/p0` against `p(r)/p0`.
    pub pressure: NodalError,
    /// The nodal contact forces per lumped area, `⟨N^I p⟩/⟨N^I⟩/p0` with
    /// `p = Σ_J N^J pN^J` (the active `J`), against `p(r)/p0`.
    pub nodal_traction: NodalError,
    /// `max |F(r)/F − (1 − (1 − r²/a²)^(3/2))|` over `r/a = 0.05, 0.1, …, 0.8`:
    /// the force inside the radius `r` of the pressure field `Σ N^J pN^J`.
    pub force_error: f64,
    /// The lumped fluxes (AL) `h0^I/h0_min` against `1/√(1 − r²/a²)`, active nodes.
    pub flux: NodalError,
    /// The nodal heat flows per lumped area `⟨N^I h0⟩/⟨N^I⟩/h0_min`, `h0 =
    /// Σ_J N^J h0^J`, against `1/√(1 − r²/a²)`, active nodes.
    pub nodal_flux: NodalError,
    /// `max |Q(r)/Q − (1 − √(1 − r²/a²))|` over `r/a = 0.05, 0.1, …, 0.8`.
    pub cumulative_error: f64,
    /// `max |γθ^I|` over the active set (K).
    pub max_jump: f64,
    /// Heat flow `Q` through the whole interface (four quarters, W).
    pub heat_flow: f64,
    /// Newton iterations of the mechanical and the thermal phase.
    pub iterations: [usize; 2],
    /// Unknowns of the mechanical and the thermal phase.
    pub unknowns: [usize; 2],
    /// Wall time of the mechanical and the thermal phase (s).
    pub seconds: [f64; 2],
}

/// The ratios `r/a = 0.05 k`, `k = 1, …, RADII`, at which the cumulative
/// force and heat flow are evaluated (compared up to 0.8, plotted to 1.2).
const RADII: usize = 24;

/// Solves the mechanical phase, then the thermal phase (constraint model,
/// augmented Lagrangian) on the frozen configuration.
pub fn hertz_3d(setup: &Hertz3dSetup) -> Result<Hertz3dResult> {
    let start = std::time::Instant::now();
    let mut model = setup.model()?;
    if setup.seed {
        seed_hertz(&mut model, setup);
    }
    let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
    let mechanical_unknowns = model.n_eq();
    let mechanical_iterations = newton.solve(&mut model)?.total_iterations();
    let mechanical_seconds = start.elapsed().as_secs_f64();
    let s = model.scales;
    let (a, force) = (setup.hertz_radius(), setup.force());
    let p0 = hertz::sphere_peak_pressure(force, a);
    let w = setup.width();
    let meas = measure(&model, 1.0)?;
    let radius = (4.0 * meas.contact_fraction * w * w / std::f64::consts::PI).sqrt();
    let axis_radius = axis_crossing(&model, w)?;
    let c = model.contact.as_ref().expect("contact set above");
    let face = Face::new(c, w / s.length);
    // r/a of the slave control points (reference).
    let rs: Vec<f64> = c
        .slave_nodes
        .iter()
        .map(|&n| {
            let x = model.node_reference(n);
            x[0].hypot(x[1]) * s.length / a
        })
        .collect();
    let exact_p = |r: f64| hertz::sphere_pressure(force, a, r * a) / p0;
    // The pressure field's coefficients: the multipliers of the active nodes.
    let pn: Vec<f64> = (0..c.n_slave())
        .map(|i| {
            if c.is_active(i) {
                c.pressure(i) * s.stress / p0
            } else {
                0.0
            }
        })
        .collect();
    let nodal_p: Vec<(f64, f64)> = (0..c.n_slave()).map(|i| (rs[i], pn[i])).collect();
    let smoothed_p = face.nodal_averages(c, &pn);
    let traction_p: Vec<(f64, f64)> = (0..c.n_slave()).map(|i| (rs[i], smoothed_p[i])).collect();
    let pressure = NodalError::new(&nodal_p, exact_p);
    let nodal_traction = NodalError::new(&traction_p, exact_p);
    let total_force = face.total(c, &pn);
    let force_curve: Vec<f64> = (1..=RADII)
        .map(|k| face.disc(&pn, 0.05 * k as f64 * a / s.length) / total_force)
        .collect();
    let force_error = curve_error(&force_curve, |f| hertz::sphere_force_fraction(1.0, f));
    let label = format!(
        "p={}, {}/{} el.",
        setup.degree, setup.contact_elements[0], setup.contact_elements[1]
    );
    // Nodal values against r/a, up to r/a = 1.3, for the plots.
    let record_near = |name: String, quantity: &str, v: &[(f64, f64)]| {
        let (x, y): (Vec<f64>, Vec<f64>) = v.iter().copied().filter(|p| p.0 < 1.3).unzip();
        record_series("contact_hertz_3d", &name, ("r/a", quantity), &x, &y);
    };
    record_near(format!("pN^I {label}"), "pN/p0", &nodal_p);
    record_near(format!("⟨N^I p⟩/⟨N^I⟩ {label}"), "pN/p0", &traction_p);

    // Thermal phase on the frozen configuration.
    let start = std::time::Instant::now();
    model.set_coupling(Coupling::Thermal)?;
    model.set_path([1.0, 0.0], [1.0, 1.0]);
    let thermal_unknowns = model.n_eq();
    let thermal_iterations = newton.solve(&mut model)?.total_iterations();
    let thermal_seconds = start.elapsed().as_secs_f64();
    let c = model.contact.as_ref().expect("contact set above");
    // Lumped fluxes out of the slave (heat flows down), scaled.
    let h0: Vec<f64> = (0..c.n_slave()).map(|i| -c.heat_flux(i)).collect();
    let quarter = face.total(c, &h0);
    let heat_flow = 4.0 * quarter * s.flux() * s.length * s.length;
    // h0_min = Q/(2π a²) in scaled units (the quarter carries Q/4).
    let h_min = 4.0 * quarter / (2.0 * std::f64::consts::PI * (a / s.length).powi(2));
    let active: Vec<usize> = (0..c.n_slave()).filter(|&i| c.is_active(i)).collect();
    let exact_h = |r: f64| 1.0 / (1.0 - r * r).sqrt();
    let nodal_h: Vec<(f64, f64)> = active.iter().map(|&i| (rs[i], h0[i] / h_min)).collect();
    let smoothed_h = face.nodal_averages(c, &h0);
    let traction_h: Vec<(f64, f64)> = active
        .iter()
        .map(|&i| (rs[i], smoothed_h[i] / h_min))
        .collect();
    let flux = NodalError::new(&nodal_h, exact_h);
    let nodal_flux = NodalError::new(&traction_h, exact_h);
    let heat_curve: Vec<f64> = (1..=RADII)
        .map(|k| face.disc(&h0, 0.05 * k as f64 * a / s.length) / quarter)
        .collect();
    let cumulative_error = curve_error(&heat_curve, |f| hertz::spot_heat_flow_fraction(1.0, f));
    let max_jump = active
        .iter()
        .map(|&i| c.weighted_jump(i).abs())
        .fold(0.0, f64::max)
        * s.temperature;
    record_near(format!("h0^I {label}"), "h0/h0_min", &nodal_h);
    record_near(format!("⟨N^I h0⟩/⟨N^I⟩ {label}"), "h0/h0_min", &traction_h);
    let radii: Vec<f64> = (1..=RADII).map(|k| 0.05 * k as f64).collect();
    record_series(
        "contact_hertz_3d",
        &label,
        ("r/a", "Q(r)/Q"),
        &radii,
        &heat_curve,
    );
    record_series(
        "contact_hertz_3d",
        &label,
        ("r/a", "F(r)/F"),
        &radii,
        &force_curve,
    );
    Ok(Hertz3dResult {
        radius,
        axis_radius,
        hertz_radius: a,
        pressure,
        nodal_traction,
        force_error,
        flux,
        nodal_flux,
        cumulative_error,
        max_jump,
        heat_flow,
        iterations: [mechanical_iterations, thermal_iterations],
        unknowns: [mechanical_unknowns, thermal_unknowns],
        seconds: [mechanical_seconds, thermal_seconds],
    })
}

/// `max_k |curve_k − exact(r_k/a)|` over `r_k/a = 0.05 k ≤ 0.8`.
fn curve_error(curve: &[f64], exact: impl Fn(f64) -> f64) -> f64 {
    curve
        .iter()
        .take(16)
        .enumerate()
        .map(|(k, v)| (v - exact(0.05 * (k + 1) as f64)).abs())
        .fold(0.0, f64::max)
}

/// Fields `Σ N^J v^J` on the slave surface (scaled units): nodal averages,
/// totals and integrals over discs about the apex.
struct Face {
    face: crate::geometry::ThbPatch,
    /// `W` (scaled): `x = W u`, `y = W v` on the slave face.
    width: f64,
}

impl Face {
    fn new(c: &crate::contact::ContactInterface, width: f64) -> Self {
        Face {
            face: c.slave_face().clone(),
            width,
        }
    }

    /// `⟨N^I f⟩/⟨N^I⟩` of `f = Σ N^J v^J` at the integration points.
    fn nodal_averages(&self, c: &crate::contact::ContactInterface, v: &[f64]) -> Vec<f64> {
        let mut sums = vec![0.0; c.n_slave()];
        for sp in &c.points {
            let f: f64 = sp.conn.iter().zip(&sp.basis).map(|(&j, n)| n * v[j]).sum();
            for (&i, n) in sp.conn.iter().zip(&sp.basis) {
                sums[i] += sp.weight * n * f;
            }
        }
        sums.iter()
            .zip(&c.lumped_area)
            .map(|(s, a)| s / a)
            .collect()
    }

    /// `∫ Σ N^J v^J dA` over the slave surface (integration points).
    fn total(&self, c: &crate::contact::ContactInterface, v: &[f64]) -> f64 {
        c.points
            .iter()
            .map(|sp| {
                sp.weight
                    * sp.conn
                        .iter()
                        .zip(&sp.basis)
                        .map(|(&j, n)| n * v[j])
                        .sum::<f64>()
            })
            .sum()
    }

    /// `f = Σ N^J v^J` per projected area (the reference area element
    /// `|x_u × x_v| du dv` over `dx dy`) at the projected point `(x, y)`.
    fn density(&self, v: &[f64], x: f64, y: f64) -> f64 {
        let b = self.face.basis(&[x / self.width, y / self.width], 1);
        let mut d = [[0.0; 3]; 2];
        let mut f = 0.0;
        for (k, &i) in b.indices.iter().enumerate() {
            f += b.values[k] * v[i];
            let p = self.face.control_points()[i];
            for (l, dl) in d.iter_mut().enumerate() {
                for (m, dm) in dl.iter_mut().enumerate() {
                    *dm += b.d1[k][l] * p[m];
                }
            }
        }
        let n = [
            d[0][1] * d[1][2] - d[0][2] * d[1][1],
            d[0][2] * d[1][0] - d[0][0] * d[1][2],
            d[0][0] * d[1][1] - d[0][1] * d[1][0],
        ];
        f * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() / (self.width * self.width)
    }

    /// `∫ Σ N^J v^J dA` over the quarter disc of radius `r` (scaled) about
    /// the apex: composite Gauss in polar coordinates (8 × 8 pieces of 8
    /// points each).
    fn disc(&self, v: &[f64], r: f64) -> f64 {
        let gauss = GaussLegendre::new(8);
        let pieces = 8;
        let quarter = 0.5 * std::f64::consts::PI;
        let mut sum = 0.0;
        for pa in 0..pieces {
            for (ta, wa) in gauss.points.iter().zip(&gauss.weights) {
                let phi = quarter * (pa as f64 + 0.5 * (ta + 1.0)) / pieces as f64;
                let wphi = 0.5 * wa * quarter / pieces as f64;
                for pr in 0..pieces {
                    for (tr, wr) in gauss.points.iter().zip(&gauss.weights) {
                        let rho = r * (pr as f64 + 0.5 * (tr + 1.0)) / pieces as f64;
                        let wrho = 0.5 * wr * r / pieces as f64;
                        sum +=
                            wphi * wrho * rho * self.density(v, rho * phi.cos(), rho * phi.sin());
                    }
                }
            }
        }
        sum
    }
}

/// Seeds the normal multipliers of the slave nodes inside Hertz's contact
/// radius so that their pressure indicator `λN^I − εN g^I` is Hertz's
/// pressure at first touch: Newton starts from (nearly) the final active set
/// instead of a single node in contact.
fn seed_hertz(model: &mut Model, setup: &Hertz3dSetup) {
    let s = model.scales;
    let (a, force) = (setup.hertz_radius(), setup.force());
    let rs: Vec<f64> = {
        let c = model.contact.as_ref().expect("contact set above");
        c.slave_nodes
            .iter()
            .map(|&n| {
                let x = model.node_reference(n);
                x[0].hypot(x[1]) * s.length
            })
            .collect()
    };
    let c = model.contact.as_mut().expect("contact set above");
    for (i, &r) in rs.iter().enumerate() {
        if r < a {
            let p = hertz::sphere_pressure(force, a, r) / s.stress;
            c.lambda_n[i] = p + c.eps_n * c.weighted_gap(i).max(0.0);
        }
    }
}

/// The first zero crossing of the interpolated pressure indicator along the
/// x axis (the slave face's edge `y = 0`), at its deformed x (m).
fn axis_crossing(model: &Model, w: f64) -> Result<f64> {
    let c = model.contact.as_ref().expect("contact set above");
    let s = model.scales;
    let face = c.slave_face();
    let ind: Vec<f64> = (0..c.n_slave()).map(|i| c.indicator(i)).collect();
    let ux: Vec<f64> = c
        .slave_nodes
        .iter()
        .map(|&n| model.displacement(n, 0) / s.length)
        .collect();
    // The contact area's level (the edges fitted as for the area).
    let state = &model.state;
    let level = c.contact_level_3d(ind, state);
    let eval = |u: f64| -> (f64, f64) {
        let b = face.basis(&[u, 0.0], 0);
        let x: f64 = b
            .indices
            .iter()
            .zip(&b.values)
            .map(|(&i, n)| n * (face.control_points()[i][0] + ux[i]))
            .sum();
        let v = c.contact_level_at(&level, state, face.locate(&[u, 0.0]), [u, 0.0]);
        (v, x)
    };
    let samples = 2000;
    let mut left = 0.0;
    if eval(left).0 <= 0.0 {
        return Err(crate::Error::Geometry(
            "3D Hertz: the apex is not in contact".into(),
        ));
    }
    for k in 1..=samples {
        let right = k as f64 / samples as f64;
        if eval(right).0 <= 0.0 {
            let (mut lo, mut hi) = (left, right);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if eval(m).0 > 0.0 {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            return Ok(eval(0.5 * (lo + hi)).1 * s.length);
        }
        left = right;
    }
    Ok(w)
}
