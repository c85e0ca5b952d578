//! Westergaard's wavy contact (spec §10.4) and the thermal constriction of
//! its contact strips with Barber's analogy (spec §10.5), in the small-strain
//! limit.
//!
//! The micro-sample of spec §3 and §5 with a small-amplitude sinusoid
//! `A cos(2πx/λ)` (body 1, slave; `A/λ = 0.002`) on a flat (body 2, master),
//! one wavelength wide, PR sides, both bodies of height `H = λ` and of the
//! Table I material with a constant conductivity; the meshes are uniform
//! along x (non-matching: 8:7) and graded towards the interface through the
//! height. At every pressure of the path:
//!
//! - **mechanical phase**: the contact fraction by [`measure`], the
//!   projected length of the contact zone, whose edges are fitted to the
//!   near-edge asymptotics of the lumped pressures and weighted gaps
//!   (`ContactInterface::locate_edge`, docs/adaptivity.md), against
//!   `2a/λ = (2/π) arcsin √(p̄/p*)`, `p* = π E* A/λ`, `1/E* = 2(1 − ν²)/E`
//!   (plane strain, both bodies deformable). On 32 elements the edges lie
//!   0.02–0.25 elements from Westergaard's from 5 % to 70 % of `p*` and 0.52
//!   at 90 % (before stop 21, at the crossings of the indicator
//!   `λN − εN g`: −0.42 to −0.53 elements on 32 to 256 elements, first
//!   order);
//! - **incremental stiffness** `dp̄/dδ̄` of the interface: the derivative of
//!   the computed pressure–approach curve, from one linear solve with the
//!   converged consistent tangent (active set fixed, as in the thermal phase),
//!   less the compliance of the two homogeneously compressed bars (exact
//!   finite-strain platen stretch);
//! - **thermal phase** on the frozen configuration: the conductance
//!   `h̄/jump`, jump by (3.4) (far-face difference less the bulk drops of the
//!   compressed bars). It is compared with Barber's analogy
//!   `C = (k_s/E*) dp̄/dδ̄` with the computed stiffness, and with the
//!   closed-form periodic strips between layers of the actual (deformed)
//!   heights and far-face conditions (slave: uniform flux, master:
//!   isothermal), [`strip_conductance_layers`]: the constriction is that of
//!   strips whose width is within a fraction of an element of the active
//!   set's (lumped) width. Both the conductance and the stiffness jump with
//!   the number of active control points (the paper's non-smooth pressure
//!   curves, Sect. 5.7), so a pointwise comparison with the closed forms at
//!   Westergaard's width only converges in that element-wise sense.
//!
//! Modelling error: the closed forms are linear elasticity and conduction in
//! half-spaces with a flat interface; the sample has finite strains
//! (`~p/E* < 1 %`), a surface that deviates from the plane by `~A`, and
//! heights whose corrections decay like `e^(−4πH/λ)` (kept in the thermal
//! reference).

use crate::Result;
use crate::analytical::compression::platen_stretch;
use crate::analytical::constriction::{
    FarFace, StripLayer, barber_conductance_from_stiffness, strip_conductance_layers,
};
use crate::analytical::westergaard;
use crate::bulk::Coupling;
use crate::contact::ContactSettings;
use crate::geometry::{FitMethod, RoughFace, Side, fit_height_function, rough_block};
use crate::material::Material;
use crate::sample::micro::{InterfaceMeasures, UPPER, measure};
use crate::solve::linear::LinearSolver;
use crate::solve::{
    LoadStepping, Model, ModelBuilder, Newton, NewtonSettings, NonlinearProblem, Scales,
};
use crate::verify::{Check, record_series};

/// The wavy micro-sample of the small-strain benchmarks.
#[derive(Clone, Debug)]
pub struct WavySample {
    /// Wavelength λ = sample width (m).
    pub wavelength: f64,
    /// Amplitude `A` of the sinusoid (m).
    pub amplitude: f64,
    /// Height `H` of each body (m).
    pub height: f64,
    /// NURBS degree.
    pub degree: usize,
    /// Elements along x (upper, lower): non-matching.
    pub elements_x: [usize; 2],
    /// Elements through the height of each body, geometrically graded
    /// towards the interface.
    pub elements_y: usize,
    /// Ratio of the largest to the smallest vertical element.
    pub grading: f64,
    /// Macroscopic flux of the thermal phase (W/m²).
    pub flux: f64,
}

impl Default for WavySample {
    /// λ = 10 μm, `A/λ = 0.002`, `H = λ`, p = 2, 64/56 elements along x.
    fn default() -> Self {
        WavySample {
            wavelength: 1.0e-5,
            amplitude: 2.0e-8,
            height: 1.0e-5,
            degree: 2,
            elements_x: [64, 56],
            elements_y: 16,
            grading: 20.0,
            flux: 1.0e6,
        }
    }
}

/// Interior knots on `[0, 1]` of `n` elements whose sizes grow
/// geometrically by the factor `ratio^(1/(n−1))` from `v = 0` (or shrink
/// towards `v = 1` when `fine_at_high`).
pub fn graded_knots(n: usize, ratio: f64, fine_at_high: bool) -> Vec<f64> {
    let r = if n > 1 {
        ratio.powf(1.0 / (n - 1) as f64)
    } else {
        1.0
    };
    let sizes: Vec<f64> = (0..n).map(|i| r.powi(i as i32)).collect();
    let total: f64 = sizes.iter().sum();
    let mut knots = Vec::with_capacity(n.saturating_sub(1));
    let mut acc = 0.0;
    for h in &sizes[..n.saturating_sub(1)] {
        acc += h / total;
        knots.push(if fine_at_high { 1.0 - acc } else { acc });
    }
    knots
}

/// The state of the wavy sample after one pressure.
#[derive(Clone, Debug)]
pub struct WavyPoint {
    /// Platen pressure (Pa).
    pub pressure: f64,
    /// Interface measurements of the mechanical phase.
    pub interface: InterfaceMeasures,
    /// Lumped area of the active set over the total, `Σ_{I∈A} ⟨N^I⟩ / Σ_I ⟨N^I⟩`.
    pub active_fraction: f64,
    /// Conductance `h̄/jump` of the thermal phase (W/(m²K)), jump by (3.4).
    pub conductance: f64,
    /// Incremental stiffness of the interface `dp̄/dδ̄` (Pa/m): the platen
    /// compliance of the converged tangent (the active set of the thermal
    /// phase) less that of the two compressed bars.
    pub stiffness: f64,
    /// Newton iterations (both phases).
    pub newton_iterations: usize,
}

impl WavySample {
    /// Table I with a constant conductivity.
    pub fn material() -> Material {
        super::benchmark_material()
    }

    /// `E*` of the two (equal, plane-strain) bodies.
    pub fn e_star(&self) -> f64 {
        super::benchmark_e_star()
    }

    /// Full-contact pressure `p* = π E* A/λ`.
    pub fn p_star(&self) -> f64 {
        westergaard::full_contact_pressure(self.e_star(), self.amplitude, self.wavelength)
    }

    /// The micro-sample model (spec §5, PR sides, master = lower body) with
    /// vertically graded meshes, at first touch. Thermal conditions of the
    /// θ̄c-projection: the lower body's bottom at `θ0`, the flux `h̄` into the
    /// upper body's top (nominal load, applied in the thermal phase).
    pub fn model(&self) -> Result<Model> {
        let (w, h, p) = (self.wavelength, self.height, self.degree);
        let m = Self::material();
        let (a, l) = (self.amplitude, self.wavelength);
        let upper = move |x: f64| a * (std::f64::consts::TAU * x / l).cos();
        let fit_u = fit_height_function(&upper, w, p, self.elements_x[0], FitMethod::Interpolation);
        let fit_l =
            fit_height_function(&|_| 0.0, w, p, self.elements_x[1], FitMethod::Interpolation);
        // First touch: the fitted crest (at x = λ/2, a Greville point for
        // even element counts, else within the fit error of A).
        let g0 = (0..=2000)
            .map(|i| -fit_u.height_at(w * i as f64 / 2000.0))
            .fold(f64::NEG_INFINITY, f64::max);
        let n = self.elements_y;
        let lower = rough_block(&fit_l, 0.0, -h, RoughFace::Top, p, 1)
            .insert_knots(1, &graded_knots(n, self.grading, true));
        let upper = rough_block(&fit_u, g0, h + g0, RoughFace::Bottom, p, 1)
            .insert_knots(1, &graded_knots(n, self.grading, false));
        let mut mb = ModelBuilder::new(2, Scales::new(w, &m));
        let lo = mb.add_body("lower", &lower, &m)?;
        let up = mb.add_body("upper", &upper, &m)?;
        mb.fix_face(lo, 1, Side::Low, 0, 0.0);
        mb.fix_face(lo, 1, Side::Low, 1, 0.0);
        mb.platen(up, 1, Side::High, 1, 1.0);
        mb.periodic(lo, 0);
        mb.periodic(up, 0);
        let top = mb.bodies()[up].face_nodes(1, Side::High)[0];
        mb.fix_node(top, 0, 0.0);
        mb.fix_face(lo, 1, Side::Low, 2, m.reference_temperature);
        mb.flux(up, 1, Side::High, self.flux);
        mb.initial_temperature(m.reference_temperature);
        mb.contact(
            (up, 1, Side::Low),
            (lo, 1, Side::High),
            &ContactSettings::default(),
            Some(w),
        )?;
        let mut model = mb.build(Coupling::Mechanical)?;
        model.touch(up, 1)?;
        Ok(model)
    }

    /// Drives the sample along `pressures` (increasing): at each, the
    /// mechanical phase, its interface measurements, and the thermal phase on
    /// the frozen configuration.
    pub fn solve(&self, pressures: &[f64]) -> Result<Vec<WavyPoint>> {
        let mut model = self.model()?;
        let m = Self::material();
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        let mut out = Vec::with_capacity(pressures.len());
        let mut last = 0.0;
        for &p in pressures {
            model.set_path([last, 0.0], [p, 0.0]);
            let mut iterations = newton.solve(&mut model)?.total_iterations();
            last = p;
            let interface = measure(&model, 1.0)?;
            let active_fraction = {
                let c = model.contact.as_ref().expect("the sample has contact");
                let total: f64 = c.lumped_area.iter().sum();
                (0..c.n_slave())
                    .filter(|&i| c.is_active(i))
                    .map(|i| c.lumped_area[i])
                    .sum::<f64>()
                    / total
            };
            let compliance = platen_compliance(&mut model, p)?;
            let saved = model.save();
            model.set_coupling(Coupling::Thermal)?;
            model.set_path([p, 0.0], [p, 1.0]);
            iterations += newton.solve(&mut model)?.total_iterations();
            let top = model.face_mean_temperature(UPPER, 1, Side::High);
            model.restore(&saved);
            model.set_coupling(Coupling::Mechanical)?;
            // Jump (3.4): far-face difference less the bulk drops of the
            // compressed bars (constant k).
            let stretch = platen_stretch(&m, p, m.reference_temperature)?;
            let bulk = 2.0 * self.flux * stretch * self.height / m.thermal_conductivity;
            let jump = top - m.reference_temperature - bulk;
            let dp = 1e-6 * p;
            let bars = 2.0
                * self.height
                * (platen_stretch(&m, p + dp, m.reference_temperature)?
                    - platen_stretch(&m, p - dp, m.reference_temperature)?)
                / (2.0 * dp);
            out.push(WavyPoint {
                pressure: p,
                interface,
                active_fraction,
                conductance: self.flux / jump,
                stiffness: 1.0 / (compliance + bars),
                newton_iterations: iterations,
            });
        }
        Ok(out)
    }

    /// The sample as a case file (spec §5 with the case file's own meshes:
    /// uniform through the height, PR sides, plain two-phase, Table I with a
    /// constant conductivity) at the fractions `levels` of `p*`, with the
    /// elements `[nx, nz]` of the upper and lower bodies and extra lines for
    /// `[discretization]` and `[contact]`: the Westergaard case of the
    /// adaptivity tests and of `tcgen bench --only effectivity`.
    pub fn case(
        &self,
        levels: &[f64],
        upper: [usize; 2],
        lower: [usize; 2],
        discretization: &str,
        contact: &str,
    ) -> Result<crate::sample::Case> {
        let pressures: Vec<String> = levels
            .iter()
            .map(|f| format!("{:e}", f * self.p_star()))
            .collect();
        let text = format!(
            r#"
[sample]
width = {w:e}
height = {h:e}
lateral = "periodic"
[surface.upper]
kind = "sinusoid"
rms = {rms:e}
wavelength = {w:e}
[surface.lower]
kind = "flat"
[material]
conductivity_slope = 0.0
[discretization]
degree = {degree}
elements_upper = {upper:?}
elements_lower = {lower:?}
{discretization}
[contact]
{contact}
[homogenization]
method = "two-phase"
[load]
flux = {flux:e}
pressures = [{p}]
"#,
            w = self.wavelength,
            h = self.height,
            rms = self.amplitude / 2f64.sqrt(),
            degree = self.degree,
            flux = self.flux,
            p = pressures.join(", "),
        );
        crate::sample::Case::from_toml(&text, std::path::Path::new("."))
    }

    /// Closed-form conductance of the strips of half-width `a` between the
    /// two layers at pressure `p` (deformed heights, far faces as in the OHP).
    pub fn strip_conductance(&self, pressure: f64, half_width: f64) -> Result<f64> {
        let m = Self::material();
        let stretch = platen_stretch(&m, pressure, m.reference_temperature)?;
        let layer = |far_face| StripLayer {
            conductivity: m.thermal_conductivity,
            height: stretch * self.height,
            far_face,
        };
        strip_conductance_layers(
            &layer(FarFace::UniformFlux),
            &layer(FarFace::Isothermal),
            self.wavelength,
            half_width,
        )
    }
}

/// Platen compliance `dδ/dp̄` (m/Pa) of a converged mechanical state: one
/// linear solve with its consistent tangent (active set fixed) for a
/// pressure increment. The state is left unchanged.
pub fn platen_compliance(model: &mut Model, pressure: f64) -> Result<f64> {
    let saved = model.save();
    let dp = 1e-3 * pressure;
    model.set_path([pressure, 0.0], [pressure + dp, 0.0]);
    model.prepare()?;
    let n = model.n_eq();
    let nnz = model.pattern().row_idx().len();
    let mut r0 = vec![0.0; n];
    model.set_load(0.0);
    model.assemble(None, &mut r0)?;
    let mut values = vec![0.0; nnz];
    let mut r1 = vec![0.0; n];
    model.set_load(1.0);
    model.assemble(Some(&mut values), &mut r1)?;
    let kind = model.factorization();
    let ordering = model.ordering(&kind);
    let mut solver = LinearSolver::new(model.pattern(), kind, ordering)?;
    solver.factorize(&values)?;
    let mut dx: Vec<f64> = r1.iter().zip(&r0).map(|(a, b)| b - a).collect();
    solver.solve_in_place(&mut dx)?;
    let platen = &model.platens()[0];
    let (node, field) = (platen.nodes[0], platen.field);
    let before = model.displacement(node, field);
    model.update(&dx);
    let after = model.displacement(node, field);
    model.restore(&saved);
    model.set_path([pressure, 0.0], [pressure, 0.0]);
    model.set_load(1.0);
    Ok(-(after - before) / dp)
}

/// Fractions of `p*` of the Westergaard check (spec: 5 % to 90 %).
pub const WESTERGAARD_LEVELS: [f64; 7] = [0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.9];

/// One row of the wavy benchmark.
#[derive(Clone, Debug)]
pub struct WavyRow {
    /// `p̄/p*`.
    pub level: f64,
    /// Computed contact fraction.
    pub contact_fraction: f64,
    /// Westergaard's contact fraction `2a/λ`.
    pub westergaard: f64,
    /// Lumped area fraction of the active set.
    pub active_fraction: f64,
    /// Computed conductance `h̄/jump` (W/(m²K)).
    pub conductance: f64,
    /// Closed-form strip conductance at Westergaard's half-width.
    pub strips: f64,
    /// Closed-form strip conductance at the active set's half-width.
    pub strips_active: f64,
    /// The contact fraction `2a/λ` of the strips whose closed-form
    /// conductance is the computed one.
    pub conductance_fraction: f64,
    /// Computed interface stiffness `dp̄/dδ̄` (Pa/m).
    pub stiffness: f64,
    /// Westergaard's stiffness `π E*/(2λ ln(1/sin(πa/λ)))`.
    pub stiffness_westergaard: f64,
    /// Barber's conductance `(k_s/E*) dp̄/dδ̄` from the computed stiffness.
    pub barber: f64,
    /// Newton iterations of the point.
    pub newton_iterations: usize,
}

/// Runs the path through `levels` (fractions of `p*`) and evaluates every reference.
pub fn wavy_rows(s: &WavySample, levels: &[f64]) -> Result<Vec<WavyRow>> {
    let p_star = s.p_star();
    let e_star = s.e_star();
    let pressures: Vec<f64> = levels.iter().map(|f| f * p_star).collect();
    let points = s.solve(&pressures)?;
    let k = WavySample::material().thermal_conductivity;
    let mut rows = Vec::new();
    for (&level, r) in levels.iter().zip(&points) {
        let a = westergaard::contact_half_width(e_star, s.amplitude, s.wavelength, r.pressure);
        // The strip conductance increases with the half-width: bisection.
        let (mut lo, mut hi) = (1e-9 * s.wavelength, 0.5 * s.wavelength * (1.0 - 1e-12));
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if s.strip_conductance(r.pressure, mid)? < r.conductance {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        rows.push(WavyRow {
            level,
            contact_fraction: r.interface.contact_fraction,
            westergaard: 2.0 * a / s.wavelength,
            active_fraction: r.active_fraction,
            conductance: r.conductance,
            strips: s.strip_conductance(r.pressure, a)?,
            strips_active: s
                .strip_conductance(r.pressure, 0.5 * r.active_fraction * s.wavelength)?,
            conductance_fraction: (lo + hi) / s.wavelength,
            stiffness: r.stiffness,
            stiffness_westergaard: westergaard::contact_stiffness(e_star, s.wavelength, a),
            barber: barber_conductance_from_stiffness(k, k, e_star, r.stiffness),
            newton_iterations: r.newton_iterations,
        });
    }
    // The curves of the plots (docs/validation.md).
    let levels: Vec<f64> = rows.iter().map(|r| r.level).collect();
    let n = s.elements_x[0];
    for (name, y) in [
        (
            format!("contact fraction ({n} el.)"),
            rows.iter().map(|r| r.contact_fraction).collect::<Vec<_>>(),
        ),
        (
            "Westergaard 2a/λ".to_string(),
            rows.iter().map(|r| r.westergaard).collect(),
        ),
    ] {
        record_series(
            "contact_wavy",
            &name,
            ("p/p*", "contact fraction"),
            &levels,
            &y,
        );
    }
    for (name, y) in [
        (
            format!("h/jump ({n} el.)"),
            rows.iter().map(|r| r.conductance).collect::<Vec<_>>(),
        ),
        (
            format!("Barber (k/E*) dp/dδ ({n} el.)"),
            rows.iter().map(|r| r.barber).collect(),
        ),
    ] {
        record_series(
            "contact_wavy_conductance",
            &name,
            ("p/p*", "conductance (W/(m² K))"),
            &levels,
            &y,
        );
    }
    Ok(rows)
}

/// Westergaard at one mesh: `|cf − 2a/λ|` in slave elements along x (the
/// edges are located to a fraction of an element) at every level.
pub fn westergaard_checks(
    name: &str,
    s: &WavySample,
    rows: &[WavyRow],
    tolerance: f64,
) -> Vec<Check> {
    let n = s.elements_x[0] as f64;
    rows.iter()
        .map(|r| {
            let e = (r.contact_fraction - r.westergaard).abs() * n;
            Check::with_error(
                name,
                &format!("p/p*={}: contact fraction (err in el.)", r.level),
                r.contact_fraction,
                r.westergaard,
                e,
                tolerance,
            )
        })
        .collect()
}

/// Westergaard at one mesh, relative: `|cf/(2a/λ) − 1|` at every level
/// (the issue's 2 % from 5 % to 90 % of `p*` needs 256 slave elements per
/// wavelength with the first-order edge bias of about half an element).
pub fn westergaard_relative_checks(name: &str, rows: &[WavyRow], tolerance: f64) -> Vec<Check> {
    rows.iter()
        .map(|r| {
            Check::relative(
                name,
                &format!("p/p*={}: contact fraction", r.level),
                r.contact_fraction,
                r.westergaard,
                tolerance,
            )
        })
        .collect()
}

/// Westergaard by Richardson extrapolation of two meshes (`fine` has twice
/// the elements of `coarse`) for an error of the given `order`:
/// `cf_fine + (cf_fine − cf_coarse)/(2^order − 1)` against `2a/λ`
/// (relative), and the observed order against `order` (±0.3). The zone's
/// fitted edges converge at about 3/2, the order the `√s` pressure field at
/// an edge allows (observed 1.39 on 128 → 256 elements); the edges at the
/// indicator's crossings, before stop 21, at first order.
pub fn richardson_checks(
    name: &str,
    coarse: &[WavyRow],
    fine: &[WavyRow],
    order: f64,
    tolerance: f64,
) -> Vec<Check> {
    let mut v = Vec::new();
    for (c, f) in coarse.iter().zip(fine) {
        let extrapolated = f.contact_fraction
            + (f.contact_fraction - c.contact_fraction) / (2f64.powf(order) - 1.0);
        v.push(Check::relative(
            name,
            &format!("p/p*={}: extrapolated contact fraction", f.level),
            extrapolated,
            f.westergaard,
            tolerance,
        ));
    }
    let observed = |c: &WavyRow, f: &WavyRow| {
        ((c.contact_fraction - c.westergaard).abs() / (f.contact_fraction - f.westergaard).abs())
            .log2()
    };
    let orders: Vec<f64> = coarse
        .iter()
        .zip(fine)
        .map(|(c, f)| observed(c, f))
        .collect();
    let mean = orders.iter().sum::<f64>() / orders.len() as f64;
    let finest = fine
        .iter()
        .map(|f| (f.contact_fraction / f.westergaard - 1.0).abs())
        .fold(0.0, f64::max);
    v.push(Check::rate(
        name,
        "order of the contact-fraction error",
        finest,
        mean,
        order,
        0.3,
    ));
    v
}

/// Constriction checks at every level, as differences of equivalent contact
/// fractions in slave elements: the closed-form strips of the computed
/// conductance against the contact zone's width (the thermal contact is
/// integrated over the zone) and against Westergaard's width. Barber's
/// analogy with the computed stiffness is reported, not checked: the
/// stiffness follows the nodal active set (a stair-step in the load), the
/// conductance the zone, so they are not one discrete identity any more.
pub fn constriction_checks(
    name: &str,
    s: &WavySample,
    rows: &[WavyRow],
    (tol_zone, tol_westergaard): (f64, f64),
) -> Vec<Check> {
    let n = s.elements_x[0] as f64;
    let mut v = Vec::new();
    for r in rows {
        v.push(Check::with_error(
            name,
            &format!("p/p*={}: h/jump vs Barber (report)", r.level),
            r.conductance,
            r.barber,
            (r.conductance - r.barber).abs() / r.barber,
            f64::INFINITY,
        ));
        for (what, reference, tol_elements) in [
            ("zone", r.contact_fraction, tol_zone),
            ("Westergaard", r.westergaard, tol_westergaard),
        ] {
            v.push(Check::with_error(
                name,
                &format!("p/p*={}: strips width vs {what} (el.)", r.level),
                r.conductance_fraction,
                reference,
                (r.conductance_fraction - reference).abs() * n,
                tol_elements,
            ));
        }
    }
    v
}
