//! Robustness of the pressure path (paper Sect. 5.7, spec §5) and
//! determinism of the micro-solve.
//!
//! The sinusoid-on-flat micro-sample of Sect. 5.7 (width 10 μm, RMS 1 μm,
//! wavelength 10 μm, heights 7 μm, Table I material, the meshes of
//! `tables/sinusoid_on_flat.toml`), driven from first touch along a
//! log-spaced pressure path until the contact fraction reaches 95 %: at every
//! pressure the mechanical phase (Newton with its adaptive cutbacks, default
//! settings, nothing tuned per case) and the thermal phase on the frozen
//! configuration (two-phase framework, conductivities frozen at `θ̄c`).

use crate::Error;
use crate::Result;
use crate::bulk::Coupling;
use crate::contact::ContactSettings;
use crate::homogenize::{PointResult, solve_case};
use crate::sample::Case;
use crate::sample::case::{
    DiscretizationSection, HomogenizationSection, LateralCondition, LoadSection, Method,
    SampleSection, SolverSection, SurfaceSection,
};
use crate::sample::micro::{ThermalBc, build_model, case_geometry, measure};
use crate::solve::{Newton, NonlinearProblem};
use crate::surface::SurfaceSpec;

/// The case of Sect. 5.7 with degree `p`, lateral condition and meshes
/// (`elements_upper`, `elements_lower`); two-phase identification along `pressures`.
pub fn sinusoid_case(
    degree: usize,
    lateral: LateralCondition,
    elements_upper: [usize; 2],
    elements_lower: [usize; 2],
    pressures: Vec<f64>,
    method: Method,
) -> Case {
    Case {
        sample: SampleSection {
            width: 1.0e-5,
            height: 7.0e-6,
            lateral,
            ..SampleSection::default()
        },
        surface: SurfaceSection {
            upper: SurfaceSpec::Sinusoid {
                rms: 1.0e-6,
                wavelength: 1.0e-5,
                phase: 0.0,
            }
            .into(),
            lower: SurfaceSpec::Flat.into(),
        },
        material: toml::Table::new(),
        discretization: DiscretizationSection {
            degree,
            elements_upper: elements_upper.into(),
            elements_lower: elements_lower.into(),
            ..DiscretizationSection::default()
        },
        contact: ContactSettings::default(),
        load: LoadSection {
            pressures,
            ..LoadSection::default()
        },
        homogenization: HomogenizationSection {
            method,
            ..HomogenizationSection::default()
        },
        solver: SolverSection::default(),
        base_dir: std::path::PathBuf::new(),
    }
}

/// `n` pressures log-spaced from `first` to `last` (Pa).
pub fn log_path(first: f64, last: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| first * (last / first).powf(i as f64 / (n - 1) as f64))
        .collect()
}

/// One converged pressure of the robustness path.
#[derive(Clone, Debug)]
pub struct PathPoint {
    /// Pressure (Pa).
    pub pressure: f64,
    /// Contact fraction after the mechanical phase.
    pub contact_fraction: f64,
    /// Newton iterations (mechanical, thermal).
    pub iterations: [usize; 2],
    /// Load steps of the mechanical phase.
    pub steps: usize,
    /// Failed attempts cut back inside the mechanical phase.
    pub cutbacks: usize,
}

/// Drives the case's sample along its pressures until the contact fraction
/// reaches `target`; every point must converge.
pub fn run_path(case: &Case, target: f64) -> Result<Vec<PathPoint>> {
    let (mu, ml) = case.materials()?;
    let geo = case_geometry(case)?;
    let theta_c = case.load.contact_temperature;
    let bc = ThermalBc {
        master_face_temperature: theta_c,
        flux: case.load.flux,
    };
    let mut model = build_model(case, &geo, (&mu, &ml), bc, Coupling::Mechanical)?;
    let mut newton = Newton::new(case.solver.newton.clone(), case.solver.stepping.clone());
    let mut out = Vec::new();
    let mut last = 0.0;
    for &p in &case.load.pressures {
        model.set_path([last, 0.0], [p, 0.0]);
        let mech = newton.solve(&mut model)?;
        last = p;
        let contact_fraction = measure(&model, 1.0)?.contact_fraction;
        let saved = model.save();
        model.set_coupling(Coupling::Thermal)?;
        model.freeze_conductivity(theta_c);
        model.set_path([p, 0.0], [p, 1.0]);
        let therm = newton.solve(&mut model)?;
        model.restore_materials();
        model.restore(&saved);
        model.set_coupling(Coupling::Mechanical)?;
        out.push(PathPoint {
            pressure: p,
            contact_fraction,
            iterations: [mech.total_iterations(), therm.total_iterations()],
            steps: mech.steps.len(),
            cutbacks: mech.cutbacks,
        });
        if contact_fraction >= target {
            break;
        }
    }
    Ok(out)
}

/// Solves `case` with the full `tcgen solve` pipeline in a rayon pool of
/// `threads` threads.
pub fn solve_with_threads(case: &Case, threads: usize) -> Result<Vec<PointResult>> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::Config(format!("rayon pool of {threads} threads: {e}")))?;
    pool.install(|| solve_case(case, None, |_| {}))
}
