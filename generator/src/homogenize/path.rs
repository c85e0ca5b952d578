//! One micro-sample along a pressure path: for every `p̄N` of the case, the
//! macroscopic jump by the requested identification, with everything spec §9
//! asks a micro-solve to report.

use serde::Serialize;

use crate::bulk::Coupling;
use crate::geometry::Side;
use crate::homogenize::abp::{AbpProperties, AbpTemperatures, accompanying_bar};
use crate::material::Material;
use crate::sample::case::{Case, MasterBody, Method};
use crate::sample::micro::{
    InterfaceMeasures, LOWER, SampleGeometry, ThermalBc, UPPER, build_model, measure,
    sample_geometry, slave_body,
};
use crate::solve::{Model, Newton, NonlinearProblem};
use crate::{Error, Result};

/// Outcome of one load point.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Converged.
    Converged,
    /// Failed; the reason.
    Failed(String),
}

/// Everything reported for one pressure of a micro-sample (spec §9).
#[derive(Clone, Debug, Serialize)]
pub struct PointResult {
    /// Macroscopic pressure `p̄N` (Pa).
    pub pressure: f64,
    /// Macroscopic flux magnitude `|h̄|` (W/m²).
    pub flux: f64,
    /// Contact temperature `θ̄c` (K).
    pub contact_temperature: f64,
    /// Macroscopic jump magnitude `|ϑ̄c|` (K) by the case's identification.
    pub jump: f64,
    /// Macroscopic conductance `|h̄| / jump` (W/(m² K)); infinite for a vanishing jump.
    pub conductance: f64,
    /// Mean temperature of the slave's external face, `θ(I)` (K).
    pub theta_top: f64,
    /// `θ_ABP(1)` (K).
    pub theta_abp_upper: f64,
    /// `θ_ABP(2)` (K).
    pub theta_abp_lower: f64,
    /// Interface measurements (contact fraction, mean gap, `[pN^α]`, ...).
    #[serde(flatten)]
    pub interface: InterfaceMeasures,
    /// Self-consistency iterations (0 when not self-consistent).
    pub self_consistency_iterations: usize,
    /// Newton iterations spent on this point (all phases).
    pub newton_iterations: usize,
    /// Whether the point converged.
    pub converged: bool,
    /// Status and reason.
    pub status: Status,
}

impl PointResult {
    fn failed(case: &Case, pressure: f64, reason: String) -> Self {
        PointResult {
            pressure,
            flux: case.load.flux,
            contact_temperature: case.load.contact_temperature,
            jump: f64::NAN,
            conductance: f64::NAN,
            theta_top: f64::NAN,
            theta_abp_upper: f64::NAN,
            theta_abp_lower: f64::NAN,
            interface: InterfaceMeasures::default(),
            self_consistency_iterations: 0,
            newton_iterations: 0,
            converged: false,
            status: Status::Failed(reason),
        }
    }
}

/// The solver state of one sample along its path.
pub struct PathSolver<'a> {
    case: &'a Case,
    materials: (Material, Material),
    /// The model (mechanical or coupled).
    pub model: Model,
    newton: Newton,
    last_pressure: f64,
    alpha: f64,
    /// Sample geometry (fits, `g0`).
    pub geometry: SampleGeometry,
    last_interface: Option<InterfaceMeasures>,
}

impl<'a> PathSolver<'a> {
    /// Prepares the model of a case.
    pub fn new(case: &'a Case) -> Result<Self> {
        let materials = case.materials()?;
        let su = case
            .surface
            .upper
            .build("surface.upper", case.sample.width, &case.base_dir)?;
        let sl = case
            .surface
            .lower
            .build("surface.lower", case.sample.width, &case.base_dir)?;
        let geometry = sample_geometry(case, su.as_ref(), sl.as_ref());
        let theta_c = case.load.contact_temperature;
        let coupling = match case.homogenization.method {
            Method::Coupled | Method::Linearized => Coupling::Coupled,
            Method::TwoPhase | Method::TwoPhaseSelfConsistent => Coupling::Mechanical,
        };
        let bc = ThermalBc {
            master_face_temperature: theta_c,
            flux: case.load.flux,
        };
        let model = build_model(case, &geometry, (&materials.0, &materials.1), bc, coupling)?;
        let alpha = match case.contact.thermal {
            crate::contact::ThermalContact::Constitutive {
                pressure_exponent, ..
            } => pressure_exponent,
            _ => 1.0,
        };
        Ok(PathSolver {
            case,
            materials,
            model,
            newton: Newton::new(case.solver.newton.clone(), case.solver.stepping.clone()),
            last_pressure: 0.0,
            alpha,
            geometry,
            last_interface: None,
        })
    }

    fn master_face(&self) -> (usize, Side) {
        match self.case.homogenization.master {
            MasterBody::Lower => (LOWER, Side::Low),
            MasterBody::Upper => (UPPER, Side::High),
        }
    }

    fn slave_face(&self) -> (usize, Side) {
        match self.case.homogenization.master {
            MasterBody::Lower => (UPPER, Side::High),
            MasterBody::Upper => (LOWER, Side::Low),
        }
    }

    /// Newton from the current state to the loads `to` = [pressure (Pa), flux multiplier].
    fn drive(&mut self, from: [f64; 2], to: [f64; 2]) -> Result<usize> {
        self.model.set_path(from, to);
        let h = self.newton.solve(&mut self.model)?;
        Ok(h.total_iterations())
    }

    /// Solves the next pressure of the path.
    pub fn solve_pressure(&mut self, pressure: f64) -> Result<PointResult> {
        let case = self.case;
        let method = case.homogenization.method;
        let flux = case.load.flux;
        let theta_c = case.load.contact_temperature;
        let h0 = case.sample.height;
        let (mu, ml) = (self.materials.0.clone(), self.materials.1.clone());
        let (mface, sface) = (self.master_face(), self.slave_face());
        let slave = slave_body(case);
        let mut iterations = 0;
        let p0 = self.last_pressure;
        let (abp, theta_s, sc_iters) = match method {
            Method::Coupled | Method::Linearized => {
                let abp = accompanying_bar(
                    &mu,
                    &ml,
                    pressure,
                    flux,
                    theta_c,
                    h0,
                    AbpProperties::Coupled,
                )?;
                let tm = if mface.0 == UPPER {
                    abp.upper
                } else {
                    abp.lower
                };
                self.model.prescribe_face(mface.0, 1, mface.1, 2, tm);
                let start = if p0 == 0.0 { [0.0, 0.0] } else { [p0, 1.0] };
                iterations += self.drive(start, [pressure, 1.0])?;
                (
                    abp,
                    self.model.face_mean_temperature(sface.0, 1, sface.1),
                    0,
                )
            }
            Method::TwoPhase | Method::TwoPhaseSelfConsistent => {
                let self_consistent = method == Method::TwoPhaseSelfConsistent;
                let max_it = if self_consistent {
                    case.homogenization.max_iterations
                } else {
                    1
                };
                let mut jump = 0.0;
                let mut last = None;
                let mut converged = !self_consistent;
                let mut k = 0;
                while k < max_it {
                    k += 1;
                    // Slave properties at θ̄ = θ̄c + ϑ̄c (first-order corrector), master at θ̄c.
                    let t_slave = theta_c + jump;
                    let temps = if slave == UPPER {
                        [t_slave, theta_c]
                    } else {
                        [theta_c, t_slave]
                    };
                    self.model.set_frozen_temperature(UPPER, temps[0]);
                    self.model.set_frozen_temperature(LOWER, temps[1]);
                    // The first iteration moves along the pressure path; the
                    // next ones only change the slave's temperature at `p`.
                    let from = if k == 1 { p0 } else { pressure };
                    iterations += self.drive([from, 0.0], [pressure, 0.0])?;
                    let (abp, ts, it) = self.thermal_phase(pressure, temps)?;
                    iterations += it;
                    let new_jump = ts - if slave == UPPER { abp.upper } else { abp.lower };
                    last = Some((abp, ts));
                    let change = (new_jump - jump).abs();
                    jump = new_jump;
                    if self_consistent
                        && change <= case.homogenization.tolerance * jump.abs().max(1e-12 * theta_c)
                    {
                        converged = true;
                        break;
                    }
                }
                self.last_pressure = pressure;
                let (abp, ts) = last.expect("at least one two-phase iteration");
                if !converged {
                    return Err(Error::NewtonDiverged {
                        step: k,
                        load_factor: 1.0,
                        iterations: k,
                        reason: format!("self-consistency did not converge in {max_it} iterations"),
                    });
                }
                (abp, ts, if self_consistent { k } else { 0 })
            }
        };
        self.last_pressure = pressure;
        let theta_abp_slave = if slave == UPPER { abp.upper } else { abp.lower };
        let jump = match method {
            Method::Coupled => (theta_s / theta_abp_slave - 1.0) * theta_c,
            _ => theta_s - theta_abp_slave,
        }
        .abs();
        let interface = self
            .last_interface
            .take()
            .map_or_else(|| measure(&self.model, self.alpha), Ok)?;
        Ok(PointResult {
            pressure,
            flux,
            contact_temperature: theta_c,
            jump,
            conductance: if jump > 0.0 {
                flux / jump
            } else {
                f64::INFINITY
            },
            theta_top: theta_s,
            theta_abp_upper: abp.upper,
            theta_abp_lower: abp.lower,
            interface,
            self_consistency_iterations: sc_iters,
            newton_iterations: iterations,
            converged: true,
            status: Status::Converged,
        })
    }

    /// The thermal phase on the frozen configuration (Sect. 3.1 (ii)) with
    /// conductivities frozen at `temps` (upper, lower); restores the
    /// mechanical phase afterwards. Returns the ABP, `θ(I)` and iterations.
    fn thermal_phase(
        &mut self,
        pressure: f64,
        temps: [f64; 2],
    ) -> Result<(AbpTemperatures, f64, usize)> {
        let case = self.case;
        let (mface, sface) = (self.master_face(), self.slave_face());
        let abp = accompanying_bar(
            &self.materials.0,
            &self.materials.1,
            pressure,
            case.load.flux,
            case.load.contact_temperature,
            case.sample.height,
            AbpProperties::Frozen(temps),
        )?;
        let saved = self.model.save();
        self.model.set_coupling(Coupling::Thermal)?;
        self.model.freeze_body_conductivity(UPPER, temps[0]);
        self.model.freeze_body_conductivity(LOWER, temps[1]);
        let tm = if mface.0 == UPPER {
            abp.upper
        } else {
            abp.lower
        };
        self.model.prescribe_face(mface.0, 1, mface.1, 2, tm);
        let result = self.drive([pressure, 0.0], [pressure, 1.0]);
        let ts = self.model.face_mean_temperature(sface.0, 1, sface.1);
        self.last_interface = Some(measure(&self.model, self.alpha)?);
        // Back to the mechanical phase.
        self.model.restore_materials();
        self.model.restore(&saved);
        self.model.set_coupling(Coupling::Mechanical)?;
        Ok((abp, ts, result?))
    }
}

/// Solves every pressure of a case in order (one path); a failed point is
/// reported with its reason and ends the path (the later points are reported
/// as not reached). `progress` sees every result as it comes.
pub fn solve_case(case: &Case, mut progress: impl FnMut(&PointResult)) -> Result<Vec<PointResult>> {
    let mut solver = PathSolver::new(case)?;
    let mut out = Vec::new();
    let mut failed = None;
    for &p in &case.load.pressures {
        let r = match &failed {
            Some(reason) => PointResult::failed(case, p, format!("not reached: {reason}")),
            None => match solver.solve_pressure(p) {
                Ok(r) => r,
                Err(e) => {
                    failed = Some(format!("failed at {p:e} Pa"));
                    PointResult::failed(case, p, e.to_string())
                }
            },
        };
        progress(&r);
        out.push(r);
    }
    Ok(out)
}
