//! Closed-form bulk benchmarks: homogeneous compression under the rigid
//! platen with LN or PR lateral sides, 1D conduction through the compressed
//! block (the accompanying bar problem, spec §8), the same bar fully coupled,
//! and invariance under a change of the unit system (spec §2).

use crate::Result;
use crate::analytical::compression::{
    bar_top_temperature, coupled_bar_top_temperature, platen_stretch,
};
use crate::bulk::Coupling;
use crate::geometry::{NurbsPatch, Side, shapes};
use crate::material::Material;
use crate::solve::{LoadStepping, Model, ModelBuilder, Newton, NewtonSettings, Scales};
use crate::verify::{Case, Check};

/// A `w × h` block `[0, w] × [0, h]` of degree `p` with `nx × ny` elements.
pub fn block_mesh(w: f64, h: f64, p: usize, nx: usize, ny: usize) -> NurbsPatch {
    let mut g = shapes::rectangle(0.0, w, 0.0, h);
    if p > 1 {
        g = g.elevate_degree(0, p - 1).elevate_degree(1, p - 1);
    }
    if nx > 1 {
        g = g.refine_uniform(0, nx);
    }
    if ny > 1 {
        g = g.refine_uniform(1, ny);
    }
    g
}

/// Lateral boundary condition of a micro-sample (2.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lateral {
    /// LN: normal displacement zero, adiabatic.
    Linear,
    /// PR: periodic displacement and temperature.
    Periodic,
}

/// The bar of the benchmarks, in the units of the arguments: block
/// `width × height`, bottom fixed at `theta_bottom`, platen `pressure` and heat
/// flux `flux` into the top face.
pub struct BarSetup {
    /// Material.
    pub material: Material,
    /// Block width.
    pub width: f64,
    /// Block height.
    pub height: f64,
    /// Platen pressure.
    pub pressure: f64,
    /// Heat flux entering at the top.
    pub flux: f64,
    /// Bottom temperature (also the initial temperature).
    pub theta_bottom: f64,
    /// Lateral condition.
    pub lateral: Lateral,
    /// Degree and elements (x, y).
    pub mesh: (usize, usize, usize),
    /// Uniform dead traction on the top instead of the rigid platen.
    pub traction: bool,
}

impl Default for BarSetup {
    fn default() -> Self {
        BarSetup {
            material: Material::default(),
            width: 1.0e-5,
            height: 7.0e-6,
            pressure: 2.0e5,
            flux: 1.0e6,
            theta_bottom: 300.0,
            lateral: Lateral::Linear,
            mesh: (2, 2, 8),
            traction: false,
        }
    }
}

impl BarSetup {
    /// Builds the model (top platen, bottom fixed, lateral condition).
    pub fn model(&self, coupling: Coupling) -> Result<Model> {
        let (p, nx, ny) = self.mesh;
        let g = block_mesh(self.width, self.height, p, nx, ny);
        let mut b = ModelBuilder::new(2, Scales::new(self.width, &self.material));
        let body = b.add_body("bar", &g, &self.material)?;
        b.fix_face(body, 1, Side::Low, 0, 0.0);
        b.fix_face(body, 1, Side::Low, 1, 0.0);
        b.fix_face(body, 1, Side::Low, 2, self.theta_bottom);
        match self.lateral {
            Lateral::Linear => b.linear_lateral(body, 0, 0),
            Lateral::Periodic => b.periodic(body, 0),
        }
        if self.traction {
            b.traction(body, 1, Side::High, [0.0, -self.pressure, 0.0]);
        } else {
            b.platen(body, 1, Side::High, 1, self.pressure);
        }
        b.flux(body, 1, Side::High, self.flux);
        b.initial_temperature(self.theta_bottom);
        b.build(coupling)
    }
}

fn newton() -> Newton {
    Newton::new(NewtonSettings::default(), LoadStepping::default())
}

/// Top displacement of the platen (units of the setup).
pub fn platen_displacement(model: &Model) -> f64 {
    let pl = &model.platens()[0];
    model.displacement(pl.nodes[0], pl.field)
}

fn compression_case(lateral: Lateral, traction: bool) -> Result<Vec<Check>> {
    let name = match (lateral, traction) {
        (_, true) => "traction_compression_ln",
        (Lateral::Linear, _) => "platen_compression_ln",
        (Lateral::Periodic, _) => "platen_compression_pr",
    };
    let s = BarSetup {
        lateral,
        traction,
        theta_bottom: 320.0,
        pressure: 1.5e5,
        ..BarSetup::default()
    };
    let mut model = s.model(Coupling::Mechanical)?;
    newton().solve(&mut model)?;
    let lambda = platen_stretch(&s.material, s.pressure, s.theta_bottom)?;
    // Top displacement: the platen's, or the mean over the top control points.
    let top = model.bodies[0].face_nodes(1, Side::High);
    let computed = top.iter().map(|&n| model.displacement(n, 1)).sum::<f64>() / top.len() as f64;
    let reference = (lambda - 1.0) * s.height;
    // Homogeneity: u_y = (λ − 1) Y and u_x = 0 at every control point.
    let mut dev: f64 = 0.0;
    for (i, x) in model.bodies[0].patch.control_points().iter().enumerate() {
        let y = x[1] * model.scales.length;
        dev = dev.max((model.displacement(i, 1) - (lambda - 1.0) * y).abs());
        dev = dev.max(model.displacement(i, 0).abs());
    }
    Ok(vec![
        Check::relative(
            name,
            "platen displacement (rel)",
            computed,
            reference,
            1e-10,
        ),
        Check::absolute(
            name,
            "max deviation from homogeneous (rel)",
            dev / reference.abs(),
            0.0,
            1e-10,
        ),
    ])
}

/// The accompanying bar problem on the frozen compressed configuration:
/// mechanical phase, then the thermal phase with `k(θ)`.
pub fn frozen_bar_top_temperature(s: &BarSetup) -> Result<f64> {
    let mut model = s.model(Coupling::Mechanical)?;
    newton().solve(&mut model)?;
    model.set_coupling(Coupling::Thermal)?;
    newton().solve(&mut model)?;
    Ok(model.face_mean_temperature(0, 1, Side::High))
}

fn frozen_bar_case() -> Result<Vec<Check>> {
    let mut checks = Vec::new();
    let base = BarSetup::default();
    let lambda = platen_stretch(&base.material, base.pressure, base.theta_bottom)?;
    let reference = bar_top_temperature(
        &base.material,
        lambda,
        base.theta_bottom,
        base.flux,
        base.height,
    )?;
    let mut es = Vec::new();
    for ny in [2, 4, 8, 16] {
        let s = BarSetup {
            mesh: (2, 1, ny),
            ..BarSetup::default()
        };
        let t = frozen_bar_top_temperature(&s)?;
        es.push((t - reference).abs());
        if ny == 16 {
            let rise = reference - base.theta_bottom;
            checks.push(Check::with_error(
                "abp_conduction_frozen",
                "top temperature rise (K), 16 el.",
                t - base.theta_bottom,
                rise,
                (t - reference).abs() / rise,
                1e-8,
            ));
        }
    }
    // Galerkin solutions of 1D conduction are nodally exact (up to the
    // nonlinearity, which is mild here): the error stays at round-off from
    // the coarsest mesh on, so no rate can be fitted; check every level.
    let worst = es.iter().cloned().fold(0.0, f64::max);
    let rise = reference - base.theta_bottom;
    checks.push(Check::absolute(
        "abp_conduction_frozen",
        "worst top temperature error over 2..16 el. (rel)",
        worst / rise,
        0.0,
        1e-8,
    ));
    Ok(checks)
}

/// The coupled bar: platen pressure and flux together, temperature-dependent
/// stretch through thermal expansion.
pub fn coupled_bar_top_temperature_fe(s: &BarSetup) -> Result<f64> {
    let mut model = s.model(Coupling::Coupled)?;
    newton().solve(&mut model)?;
    Ok(model.face_mean_temperature(0, 1, Side::High))
}

fn coupled_bar_case() -> Result<Vec<Check>> {
    // A visible thermal expansion, so the stretch varies with θ.
    let m = Material {
        thermal_expansion: 1e-3,
        ..Material::default()
    };
    let s = BarSetup {
        material: m,
        mesh: (2, 1, 16),
        ..BarSetup::default()
    };
    let t = coupled_bar_top_temperature_fe(&s)?;
    let reference =
        coupled_bar_top_temperature(&s.material, s.pressure, s.theta_bottom, s.flux, s.height)?;
    let rise = reference - s.theta_bottom;
    Ok(vec![Check::with_error(
        "abp_conduction_coupled",
        "top temperature rise (K), 16 el.",
        t - s.theta_bottom,
        rise,
        (t - reference).abs() / rise,
        1e-7,
    )])
}

fn units_case() -> Result<Vec<Check>> {
    let si = BarSetup {
        mesh: (2, 2, 4),
        ..BarSetup::default()
    };
    // The same problem in mm, MPa, mW (temperatures in K).
    let mut m = si.material.clone();
    m.youngs_modulus *= 1e-6; // Pa → MPa
    m.thermal_conductivity *= 1.0; // W/(m K) = mW/(mm K)
    let mm = BarSetup {
        material: m,
        width: si.width * 1e3,
        height: si.height * 1e3,
        pressure: si.pressure * 1e-6,
        flux: si.flux * 1e-3, // W/m² → mW/mm²
        ..BarSetup {
            mesh: si.mesh,
            ..BarSetup::default()
        }
    };
    let run = |s: &BarSetup| -> Result<(f64, f64)> {
        let mut model = s.model(Coupling::Coupled)?;
        newton().solve(&mut model)?;
        Ok((
            model.face_mean_temperature(0, 1, Side::High),
            platen_displacement(&model),
        ))
    };
    let (t_si, d_si) = run(&si)?;
    let (t_mm, d_mm) = run(&mm)?;
    Ok(vec![
        Check::relative(
            "unit_invariance",
            "top temperature, mm-MPa-mW vs SI",
            t_mm,
            t_si,
            1e-9,
        ),
        Check::relative(
            "unit_invariance",
            "platen displacement, mm vs m",
            d_mm * 1e-3,
            d_si,
            1e-9,
        ),
    ])
}

/// The bulk benchmark cases.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "platen_compression_ln",
            description: "homogeneous compression, LN sides",
            run: || compression_case(Lateral::Linear, false),
        },
        Case {
            name: "traction_compression_ln",
            description: "homogeneous compression, uniform traction, LN sides",
            run: || compression_case(Lateral::Linear, true),
        },
        Case {
            name: "platen_compression_pr",
            description: "homogeneous compression, PR sides",
            run: || compression_case(Lateral::Periodic, false),
        },
        Case {
            name: "abp_conduction_frozen",
            description: "ABP: k(θ) conduction, compressed block",
            run: frozen_bar_case,
        },
        Case {
            name: "abp_conduction_coupled",
            description: "coupled bar vs 1D integral",
            run: coupled_bar_case,
        },
        Case {
            name: "unit_invariance",
            description: "SI vs mm-MPa-mW",
            run: units_case,
        },
    ]
}
