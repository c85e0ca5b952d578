//! One micro-sample along a pressure path: for every `p̄N` of the case, the
//! macroscopic jump by the requested identification, with everything spec §9
//! asks a micro-solve to report.

use std::collections::BTreeSet;
use std::sync::{Arc, Mutex};

use serde::Serialize;

use crate::bulk::Coupling;
use crate::geometry::Side;
use crate::homogenize::abp::{AbpProperties, AbpTemperatures, accompanying_bar};
use crate::homogenize::adapt::{
    BULK_TARGET_SHARE, bulk_approach_error, bulk_indicator_applies, bulk_marks, contact_face_side,
    keep_transferred_configuration, level_census, mark_contact_edges, refine_bodies,
    surface_misfit_marks, transfer_state, write_two_level_system,
};
use crate::homogenize::recovery::{RecoveredErrors, recovered_errors};
use crate::material::Material;
use crate::sample::case::{Acceleration, Case, MasterBody, Method};
use crate::sample::micro::{
    Bodies, InterfaceMeasures, LOWER, SampleGeometry, ThermalBc, UPPER, build_model_on,
    case_bodies, case_geometry, case_heights, contact_fraction, exact_first_touch, measure,
    measure_but_contact, place_at_first_touch, slave_body,
};
use crate::sample::vtk::{Fields, PointInfo, VtkSeries};
use crate::solve::resources::{format_bytes, process_memory};
use crate::solve::{
    IterationTimes, Model, NON_FINITE_RESIDUAL, Newton, NewtonSettings, NonlinearProblem,
};
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
    /// Newton iterations spent on this point (all phases, every adaptive level).
    pub newton_iterations: usize,
    /// Estimated discretization error of `jump` (K): the two-level estimate
    /// of the adaptive refinement ([`two_level_estimate`]); `None` on a
    /// fixed mesh or where no finer level could be solved.
    pub jump_error: Option<f64>,
    /// With a target error: whether the estimate met it (`false`: the point
    /// stopped at `max_dofs`, `max_levels` or a failed level, and reports
    /// its best jump with its estimate). `None` on a fixed mesh.
    pub error_target_met: Option<bool>,
    /// With a target error: why the refinement stopped, `"target met"`,
    /// `"max_levels"`, `"max_dofs: level L would have N unknowns"` or
    /// `"level L failed: reason"` (then the jump and estimate are those of
    /// the last solved level; a failed first level leaves no estimate).
    /// Where the last level's estimate met the target but an indicator kept
    /// the refinement going (the bulk's approach error, a face that may hide
    /// a touch) or the level came before [`min_adaptive_levels`], the reason
    /// follows in parentheses:
    /// `"max_levels (level 4's jump estimate met the target; the bulk's
    /// estimated approach error 1.291 % exceeds 1 %)"`, or `"max_dofs: level L
    /// would have N unknowns (level L−1: the plain jump's estimate met the
    /// target; the self-consistent jump's is X %)"`. Where the plain
    /// jump's estimate met the target on the last level allowed, or with a
    /// tolerance not below the target, but the self-consistent jump's (with
    /// its fixed point's bound) does not: `"the plain jump's estimate met
    /// the target; the self-consistent jump's is 1.012 %"`.
    /// `None` on a fixed mesh.
    pub refinement_stop: Option<String>,
    /// Unknowns of the mesh of `jump`: `(d + 1)` per control point.
    pub dofs: usize,
    /// The finest refinement level of each body, `[lower, upper]`.
    pub levels: [usize; 2],
    /// Whether the point converged.
    pub converged: bool,
    /// Status and reason.
    pub status: Status,
}

impl PointResult {
    /// A failed point (values NaN, `converged = false`).
    pub fn failed(case: &Case, pressure: f64, reason: String) -> Self {
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
            jump_error: None,
            error_target_met: None,
            refinement_stop: None,
            dofs: 0,
            levels: [0, 0],
            converged: false,
            status: Status::Failed(reason),
        }
    }
}

/// The cost of one phase along a path (benchmarks).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseCost {
    /// Wall time, s.
    pub seconds: f64,
    /// Newton iterations.
    pub newton_iterations: usize,
    /// Where the iterations' time went, and the factorizations' work.
    pub parts: IterationTimes,
}

impl PhaseCost {
    /// Adds `other` to this cost.
    fn add(&mut self, other: &PhaseCost) {
        self.seconds += other.seconds;
        self.newton_iterations += other.newton_iterations;
        self.parts.add(&other.parts);
    }
}

/// The cost of each phase: mechanical, thermal, coupled.
pub type PhaseCosts = [PhaseCost; 3];

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
    /// The bodies of the model (SI units; the model holds them scaled).
    pub bodies: Bodies,
    /// Whether to sample the fields of every solved point ([`Fields`]).
    capture: bool,
    /// The fields of the last solved point, when capturing.
    fields: Option<Fields>,
    history: Vec<f64>,
    /// Per flux of the last self-consistent solve on an adaptive level, the
    /// bound (K) on its output's distance to the fixed point where its
    /// iterations ended: the distance reached ([`fixed_point_output_error`],
    /// or the last change where `F`'s slope is not known yet), or at a step
    /// of `F` across it, the step's ([`Secant::step_bound`]).
    fixed_point_bounds: Vec<Option<f64>>,
    /// The secant slope `F'` of the last self-consistency iterations (a first
    /// guess of the next pressure's: [`Secant`]).
    self_consistency_slope: Option<f64>,
    /// Whether each self-consistency evaluation's mechanical phase starts
    /// from the extrapolation of the last two end states ([`MechanicalStarts`];
    /// always, but where a test measures what it saves).
    extrapolated_starts: bool,
    /// The pressure and first (unit-flux) thermal phase of the last plain
    /// two-phase solve, on the mechanical state the model was left in: the
    /// start of the self-consistent iterations that follow on the same mesh
    /// (the final adaptive level), which then need not solve them again.
    plain_phase: Option<(f64, ThermalPhase)>,
    /// Wall time, Newton iterations and their parts per phase so far.
    phase_cost: PhaseCosts,
    /// Sees every adaptive level as it ends ([`PathSolver::observe_levels`]).
    level_observer: Option<LevelObserver>,
}

/// One refined level of an adaptive point, reported as it ends
/// ([`PathSolver::observe_levels`]): a 3D point takes minutes per level, and
/// its result comes only after the last.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelReport {
    /// p̄N (Pa).
    pub pressure: f64,
    /// The refined level (1 is the first refinement of the case mesh).
    pub level: usize,
    /// `[discretization] max_levels`.
    pub max_levels: usize,
    /// Unknowns of the level (the refused level's where `max_dofs` stopped it).
    pub dofs: usize,
    /// The level's plain two-phase jump (K) and its estimate relative to it
    /// ([`two_level_estimate`]), of the first flux; `None` where the level
    /// was not solved.
    pub jump: Option<(f64, f64)>,
    /// `[discretization] target_error`.
    pub target: f64,
    /// Wall time of the level: marking, refining, building and solving (s).
    pub seconds: f64,
    /// The process's peak resident memory so far (bytes; Linux's `VmHWM`,
    /// which the kernel updates lazily, so that a later reading can be a
    /// little lower), if known: for sizing a cluster job's memory.
    pub peak_memory: Option<u64>,
    /// Why the refinement stops at this level, if it does: `"target met"`, a
    /// failure (the previous level is kept), `max_dofs`, or `max_levels`.
    pub stop: Option<String>,
    /// Why the refinement goes on although the level's jump estimate met
    /// the target, if it does: a 3D estimate's levels
    /// ([`min_adaptive_levels`]), the bulk's approach error, a face that may
    /// hide a touch, or the self-consistent jump's estimate (the reason that
    /// `refinement_stop` gives in parentheses should the refinement then
    /// stop without meeting the target).
    pub goes_on: Option<String>,
    /// How the level was solved where Newton from the state carried over
    /// from the previous level did not converge: again from the
    /// configuration the previous level solved, or from rest along the
    /// pressure path (either costs a solve or a path more).
    pub started: Option<String>,
}

/// A function that sees every [`LevelReport`]; shared by the points that run
/// in parallel.
pub type LevelObserver = Arc<dyn Fn(&LevelReport) + Send + Sync>;

impl std::fmt::Display for LevelReport {
    /// `"3.000e4 Pa: level 2/4, 13164 unknowns, two-phase jump 2.91200 K ± 14.00 %
    /// (target 1.00 %), 21.3 s, peak memory 1.4 GB"` (after the seconds, how
    /// the level was solved where its carried-over state failed, e.g.
    /// `"(solved again from rest (…))"`): the jump is the plain
    /// two-phase one the estimate is made on, which the self-consistent
    /// iteration then corrects; the memory is the process's peak so far.
    /// Then `"; stop: …"` where the refinement stops, or `"; goes on: …"`
    /// where it goes on although the estimate met the target.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:.3e} Pa: level {}/{}, {} unknowns",
            self.pressure, self.level, self.max_levels, self.dofs
        )?;
        if let Some((jump, estimate)) = self.jump {
            write!(
                f,
                ", two-phase jump {jump:.5} K ± {:.2} % (target {:.2} %)",
                100.0 * estimate,
                100.0 * self.target
            )?;
        }
        write!(f, ", {:.1} s", self.seconds)?;
        if let Some(how) = &self.started {
            write!(f, " ({how})")?;
        }
        if let Some(bytes) = self.peak_memory {
            write!(f, ", peak memory {}", format_bytes(bytes as f64))?;
        }
        match (&self.stop, &self.goes_on) {
            (Some(stop), _) => write!(f, "; stop: {stop}"),
            (None, Some(why)) => write!(f, "; goes on: {why}"),
            (None, None) => Ok(()),
        }
    }
}

/// What one thermal phase gives.
struct ThermalPhase {
    abp: AbpTemperatures,
    /// `θ(I)` (K).
    theta_s: f64,
    iterations: usize,
    interface: InterfaceMeasures,
    /// The fields of the mechanical phase it ran on and its own, when capturing.
    fields: Option<Fields>,
}

impl<'a> PathSolver<'a> {
    /// Prepares the model of a case.
    pub fn new(case: &'a Case) -> Result<Self> {
        let geometry = case_geometry(case)?;
        Self::build(case, geometry, None)
    }

    /// The solver of a case on given (refined) bodies, in their reference
    /// positions: its state is to be set (`adapt::transfer_state`).
    pub fn with_bodies(case: &'a Case, geometry: SampleGeometry, bodies: Bodies) -> Result<Self> {
        Self::build(case, geometry, Some(bodies))
    }

    fn build(case: &'a Case, geometry: SampleGeometry, bodies: Option<Bodies>) -> Result<Self> {
        let materials = case.materials()?;
        let theta_c = case.load.contact_temperature;
        let coupling = match case.homogenization.method {
            Method::Coupled | Method::Linearized => Coupling::Coupled,
            Method::TwoPhase | Method::TwoPhaseSelfConsistent => Coupling::Mechanical,
        };
        // Nominal flux 1 W/m²: the thermal load multiplier is the flux itself.
        let bc = ThermalBc {
            master_face_temperature: theta_c,
            flux: 1.0,
        };
        let mats = (&materials.0, &materials.1);
        let (model, bodies) = match bodies {
            None => {
                let bodies = case_bodies(case, &geometry)?;
                let mut model = build_model_on(case, bodies.clone(), mats, bc, coupling)?;
                place_at_first_touch(case, &geometry, &mut model)?;
                (model, bodies)
            }
            Some(b) => (build_model_on(case, b.clone(), mats, bc, coupling)?, b),
        };
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
            newton: Newton::new(newton_settings(case), case.solver.stepping.clone()),
            last_pressure: 0.0,
            alpha,
            geometry,
            bodies,
            capture: false,
            fields: None,
            history: Vec::new(),
            self_consistency_slope: None,
            extrapolated_starts: true,
            fixed_point_bounds: Vec::new(),
            plain_phase: None,
            phase_cost: Default::default(),
            level_observer: None,
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

    /// Newton from the current state to the loads `to` = [pressure (Pa), flux (W/m²)].
    fn drive(&mut self, from: [f64; 2], to: [f64; 2]) -> Result<usize> {
        if std::env::var_os("TCGEN_TRACE").is_some() {
            eprintln!(
                "drive {from:?} -> {to:?} ({:?} phase)",
                self.model.coupling()
            );
        }
        self.model.set_path(from, to);
        self.timed(|newton, model| Ok(newton.solve(model)?.total_iterations()))
    }

    /// At most `increments` Newton increments towards the loads `to` (no
    /// load stepping; [`Newton::increments`]), the model left where they
    /// end. Returns the increments made.
    fn drive_increments(&mut self, to: [f64; 2], increments: usize) -> Result<usize> {
        if std::env::var_os("TCGEN_TRACE").is_some() {
            eprintln!(
                "drive {to:?}, at most {increments} increment(s) ({:?} phase)",
                self.model.coupling()
            );
        }
        self.model.set_path(to, to);
        self.timed(|newton, model| newton.increments(model, increments))
    }

    /// Runs `solve` (returning Newton iterations), adding its wall time and
    /// iterations to the current phase's cost.
    fn timed(
        &mut self,
        solve: impl FnOnce(&mut Newton, &mut Model) -> Result<usize>,
    ) -> Result<usize> {
        let start = std::time::Instant::now();
        let phase = match self.model.coupling() {
            Coupling::Mechanical => 0,
            Coupling::Thermal => 1,
            Coupling::Coupled => 2,
        };
        let before = self.newton.iteration_times();
        let iterations = solve(&mut self.newton, &mut self.model);
        let cost = &mut self.phase_cost[phase];
        cost.seconds += start.elapsed().as_secs_f64();
        cost.parts
            .add(&self.newton.iteration_times().since(&before));
        let iterations = iterations?;
        cost.newton_iterations += iterations;
        Ok(iterations)
    }

    /// Wall time (s), Newton iterations and factorizations spent so far in
    /// the mechanical, thermal and coupled phases (benchmarks), the adaptive
    /// levels' solves included.
    pub fn phase_cost(&self) -> PhaseCosts {
        self.phase_cost
    }

    /// Lets `observer` see every adaptive level of this solver's points as it
    /// ends ([`LevelReport`]).
    pub fn observe_levels(&mut self, observer: Option<LevelObserver>) {
        self.level_observer = observer;
    }

    /// Reports a level to the observer, if any.
    fn report_level(&self, report: impl FnOnce() -> LevelReport) {
        if let Some(observe) = &self.level_observer {
            observe(&report());
        }
    }

    /// Moves the phase cost of `level` (an adaptive level's solver) into
    /// this one's.
    fn absorb_cost(&mut self, level: &mut PathSolver) {
        for (total, part) in self.phase_cost.iter_mut().zip(&mut level.phase_cost) {
            total.add(part);
            *part = PhaseCost::default();
        }
    }

    /// Newton iterations so far whose LDLᵀ fell back to LU ([`Newton::linear_fallbacks`]).
    pub fn linear_fallbacks(&self) -> usize {
        self.newton.linear_fallbacks()
    }

    /// Symbolic analyses of the linear solver so far ([`Newton::analyses`]).
    pub fn analyses(&self) -> usize {
        self.newton.analyses()
    }

    /// The jumps (K, signed) of the last two-phase solve, one per
    /// self-consistency iteration; the first is the plain two-phase jump
    /// (Fig. 14a). For a multi-flux solve, those of the last flux.
    pub fn self_consistency_history(&self) -> &[f64] {
        &self.history
    }

    /// Samples the fields of every solved point for output
    /// ([`PathSolver::take_fields`]): each phase's fields from its own
    /// state ([`crate::sample::vtk`]).
    pub fn capture_fields(&mut self, on: bool) {
        self.capture = on;
    }

    /// The fields of the last solved point (with several fluxes, of the
    /// last flux), if captured and converged.
    pub fn take_fields(&mut self) -> Option<Fields> {
        self.fields.take()
    }

    fn slave_abp(&self, abp: &AbpTemperatures) -> f64 {
        if slave_body(self.case) == UPPER {
            abp.upper
        } else {
            abp.lower
        }
    }

    /// The jump magnitude by the case's identification from `θ(I)` and the ABP.
    fn identify(&self, theta_s: f64, abp: &AbpTemperatures) -> f64 {
        let theta_c = self.case.load.contact_temperature;
        let t_abp = self.slave_abp(abp);
        match self.case.homogenization.method {
            Method::Coupled => (theta_s / t_abp - 1.0) * theta_c,
            _ => theta_s - t_abp,
        }
        .abs()
    }

    #[allow(clippy::too_many_arguments)]
    fn result(
        &self,
        pressure: f64,
        flux: f64,
        jump: f64,
        theta_s: f64,
        abp: AbpTemperatures,
        interface: InterfaceMeasures,
        sc: usize,
        newton: usize,
    ) -> PointResult {
        PointResult {
            pressure,
            flux,
            contact_temperature: self.case.load.contact_temperature,
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
            self_consistency_iterations: sc,
            newton_iterations: newton,
            jump_error: None,
            error_target_met: None,
            refinement_stop: None,
            dofs: (self.model.dim + 1)
                * self
                    .model
                    .bodies
                    .iter()
                    .map(|b| b.patch.n_control_points())
                    .sum::<usize>(),
            levels: [LOWER, UPPER].map(|b| self.model.bodies[b].patch.mesh().depth()),
            converged: true,
            status: Status::Converged,
        }
    }

    /// The plain two-phase jump (K) of a thermal phase alone on the solved
    /// mechanical state at `pressure` (the last [`PathSolver::solve_pressure`]),
    /// properties frozen at θ̄c, at the case's flux: e.g. another thermal
    /// contact model on the same mechanical solution, without solving it
    /// again.
    pub fn thermal_phase_jump(&mut self, pressure: f64) -> Result<f64> {
        let theta_c = self.case.load.contact_temperature;
        let phase = self.thermal_phase(pressure, [theta_c, theta_c], self.case.load.flux, false)?;
        Ok(self.identify(phase.theta_s, &phase.abp))
    }

    /// Solves the next pressure of the path at the case's flux.
    pub fn solve_pressure(&mut self, pressure: f64) -> Result<PointResult> {
        let flux = self.case.load.flux;
        match self.case.homogenization.method {
            Method::Coupled | Method::Linearized => self.solve_coupled(pressure),
            _ => {
                let mut r = self.solve_pressure_fluxes(pressure, &[flux])?;
                let r = r.pop().expect("one flux");
                match &r.status {
                    Status::Converged => Ok(r),
                    Status::Failed(m) => Err(Error::NewtonDiverged {
                        step: 0,
                        load_factor: 1.0,
                        iterations: r.newton_iterations,
                        reason: m.clone(),
                    }),
                }
            }
        }
    }

    fn solve_coupled(&mut self, pressure: f64) -> Result<PointResult> {
        let case = self.case;
        let (flux, theta_c, h0) = (
            case.load.flux,
            case.load.contact_temperature,
            case.sample.height,
        );
        let (mface, sface) = (self.master_face(), self.slave_face());
        let abp = accompanying_bar(
            &self.materials.0,
            &self.materials.1,
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
        self.model
            .prescribe_face(mface.0, self.model.dim - 1, mface.1, self.model.dim, tm);
        // Staggered predictor, then the monolithic corrector: the pressure
        // step mechanically at the current temperatures, the flux thermally
        // on that frozen configuration, then the coupled problem at the
        // target loads. Stepping the coupled problem in pressure directly
        // starts each step from the temperatures of the previous contact
        // zone: non-finite residuals and cut-backs to the minimum step on
        // fine meshes (32 elements along x stalled between 1 and 10 kPa).
        let from = if self.last_pressure == 0.0 {
            [0.0, 0.0]
        } else {
            [self.last_pressure, flux]
        };
        self.model.set_coupling(Coupling::Mechanical)?;
        let mut it = self.drive(from, [pressure, flux])?;
        self.model.set_coupling(Coupling::Thermal)?;
        it += self.drive([pressure, from[1]], [pressure, flux])?;
        self.model.set_coupling(Coupling::Coupled)?;
        it += self.drive([pressure, flux], [pressure, flux])?;
        self.last_pressure = pressure;
        let ts = self
            .model
            .face_mean_temperature(sface.0, self.model.dim - 1, sface.1);
        if self.capture {
            // One monolithic state: every field from it.
            self.fields = Some(Fields::sample(&self.model)?);
        }
        let interface = measure(&self.model, self.alpha)?;
        Ok(self.result(
            pressure,
            flux,
            self.identify(ts, &abp),
            ts,
            abp,
            interface,
            0,
            it,
        ))
    }

    /// The self-consistency iterations on an adaptive level after its plain
    /// solve (`plain`, whose jumps' estimate is `estimate`), and the
    /// self-consistent jumps' estimate: the plain one scaled by the ratio of
    /// the jumps, plus the bound on the output's distance to the fixed point
    /// where the iterations stopped (the distance they reached, at least the
    /// case's tolerance; at a step of `F`, the step's). They stop once that
    /// distance or their change is below the share
    /// [`SELF_CONSISTENCY_ESTIMATE_SHARE`] of the estimate.
    fn self_consistent_level(
        &mut self,
        pressure: f64,
        fluxes: &[f64],
        plain: &[PointResult],
        estimate: Option<&[f64]>,
    ) -> Result<(Vec<PointResult>, Option<Vec<f64>>)> {
        let solved = self.solve_fluxes_on_mesh(pressure, fluxes, false, estimate)?;
        let tolerance = self.case.homogenization.tolerance;
        let estimate = estimate.map(|e| {
            let mut e = e.to_vec();
            for (i, (r, p)) in solved.iter().zip(plain).enumerate() {
                if p.jump != 0.0 && r.converged {
                    // Where no bound was recorded, the share at which the
                    // iterations stop.
                    let reached = self
                        .fixed_point_bounds
                        .get(i)
                        .copied()
                        .flatten()
                        .unwrap_or(SELF_CONSISTENCY_ESTIMATE_SHARE * e[i]);
                    let residual = (tolerance * r.jump.abs()).max(reached);
                    e[i] = e[i] * (r.jump / p.jump).abs() + residual;
                }
            }
            e
        });
        Ok((solved, estimate))
    }

    /// Two-phase (self-consistent) jumps at one pressure for several fluxes
    /// (W/m², > 0), on the case's mesh, or adaptively refined from it until
    /// the estimated error of every flux's jump meets
    /// `[discretization] target_error` (`PathSolver::adapt`).
    pub fn solve_pressure_fluxes(
        &mut self,
        pressure: f64,
        fluxes: &[f64],
    ) -> Result<Vec<PointResult>> {
        let Some(target) = self.case.discretization.target_error else {
            return self.solve_fluxes_on_mesh(pressure, fluxes, false, None);
        };
        // The levels compare plain two-phase jumps; the self-consistent
        // iterations run once, on the final mesh.
        let coarse = self.solve_fluxes_on_mesh(pressure, fluxes, true, None)?;
        if coarse.iter().all(|r| r.converged) {
            self.adapt(pressure, fluxes, coarse, target)
        } else {
            Ok(coarse)
        }
    }

    /// The adaptive loop at one pressure: from the solved case mesh (which
    /// stays on the path, for continuation), mark the contact edges, refine,
    /// resolve the rough faces on the exact surfaces ([`Bodies::resolved`]:
    /// the refined levels converge to the surface's jump, not to its fit's),
    /// carry the state over, solve again at the same loads; stop when every
    /// flux's [`two_level_estimate`] is below `target` times its jump (after
    /// at least [`min_adaptive_levels`] levels, and where the zone's edges
    /// are fitted, counting from the first fitted level, after
    /// [`FITTED_LEVELS`] differences), or at `max_levels`,
    /// `max_dofs` or a level that fails (then flagged, with the last
    /// estimate). The levels run the plain two-phase identification (one
    /// mechanical and one thermal phase); with the self-consistent method
    /// its iterations then run on the final mesh, and the estimate is
    /// scaled by the ratio of the final to the plain jump, plus the fixed
    /// point's bound ([`PathSolver::self_consistent_level`]). They run on
    /// the level whose plain jumps met the target; where that estimate
    /// misses it, the refinement goes on (unless the case's tolerance,
    /// which no level lowers, is not below the target).
    fn adapt(
        &mut self,
        pressure: f64,
        fluxes: &[f64],
        coarse: Vec<PointResult>,
        target: f64,
    ) -> Result<Vec<PointResult>> {
        let case = self.case;
        let d = &case.discretization;
        let slave = slave_body(case);
        let trace = std::env::var_os("TCGEN_ADAPT_TRACE").is_some();
        let mut iterations = max_newton_iterations(&coarse);
        let mut best = coarse;
        let mut diffs: Vec<Vec<f64>> = Vec::new();
        let mut estimate: Option<Vec<f64>> = None;
        let mut met = false;
        let mut stop = "max_levels".to_string();
        // Why the last level whose jump estimate met the target went on.
        let mut withheld: Option<String> = None;
        // The estimate's history starts where every contact edge is fitted
        // (`regime`: the first difference between two fitted levels; the
        // change onto the first fitted level is one of regime, not of
        // resolution), and [`FITTED_LEVELS`] differences are needed there.
        // It also prepares the contact at the solved state for the next
        // level's marks (`marks`: unless this is the last level, and then
        // only where the edges can be fitted).
        let fitted = |m: &mut Model, marks: bool| -> Result<bool> {
            if !marks && !m.contact.as_ref().is_some_and(|c| c.zone_edges_can_fit()) {
                return Ok(false);
            }
            m.prepare_contact()?;
            Ok(m.contact
                .as_ref()
                .is_some_and(|c| c.zone_edges_fitted(&m.state)))
        };
        let mut regime = fitted(&mut self.model, true)?.then_some(0);
        // Refined levels resolve the rough faces on the exact surfaces (the
        // case mesh keeps its fit), and their approach counts from the exact
        // surfaces' first touch.
        let heights = case_heights(case)?;
        let touch_shift = exact_first_touch(case, &heights) - self.geometry.g0;
        let ratio = level_error_ratio(case.sample.dimension);
        // Faces whose height error exceeds their gap may hide a touch of the
        // exact surfaces ([`surface_misfit_marks`]); the case fits' errors,
        // with a margin for the sampling, bound every level's.
        let misfit_bound = MISFIT_BOUND_MARGIN
            * (self.geometry.fit_upper.max_error() + self.geometry.fit_lower.max_error());
        let g0 = self.geometry.g0;
        let mut hidden: Option<BTreeSet<usize>> = None;
        // The bulk-resolution indicator (degree 1): the recovered errors of
        // the last solved mesh and the bulk's estimated relative error of
        // the approach (`adapt::bulk_approach_error`).
        let bulk_applies = bulk_indicator_applies(&self.model);
        let bulk_threshold = BULK_TARGET_SHARE * target;
        let bulk_of = |m: &Model, r: &[PointResult]| -> Option<(RecoveredErrors, f64)> {
            if !bulk_applies {
                return None;
            }
            let rec = recovered_errors(m);
            let approach = r.first().map_or(0.0, |r| r.interface.approach);
            let error = bulk_approach_error(m, &rec, pressure, case.sample.width, approach)?;
            if trace {
                eprintln!(
                    "adapt {pressure:e} Pa: the bulk's estimated approach error {:.3} % of the approach {approach:.6e} m (recovered gradients)",
                    100.0 * error,
                );
            }
            Some((rec, error))
        };
        let mut bulk = bulk_of(&self.model, &best);
        let mut fine: Option<PathSolver<'a>> = None;
        // With the self-consistent method, its results on the last level
        // kept and their estimate, where its iterations ran there in the
        // loop (the plain jumps met the target; `best` keeps the plain ones,
        // which the levels compare).
        let self_consistent = case.homogenization.method == Method::TwoPhaseSelfConsistent;
        let mut consistent: Option<(Vec<PointResult>, Option<Vec<f64>>)> = None;
        // Why the last level reports the target missed although its plain
        // jumps met it (no further level may run).
        let mut consistent_missed: Option<String> = None;
        for level in 1..=d.max_levels {
            let (src, src_bodies, src_newton) = match fine.as_mut() {
                Some(f) => (&mut f.model, &f.bodies, Some(&mut f.newton)),
                None => (&mut self.model, &self.bodies, None),
            };
            let clock = std::time::Instant::now();
            let level_report = |dofs, jump, stop| LevelReport {
                pressure,
                level,
                max_levels: d.max_levels,
                dofs,
                jump,
                target,
                seconds: clock.elapsed().as_secs_f64(),
                peak_memory: process_memory("VmHWM:"),
                stop,
                goes_on: None,
                started: None,
            };
            // `src` is prepared at its solved state: by `fitted` above (the
            // case mesh) or below (the previous level).
            let misfit = match hidden.take() {
                Some(m) => m,
                None => surface_misfit_marks(src, slave, &heights, g0, misfit_bound)?,
            };
            if trace && !misfit.is_empty() {
                eprintln!(
                    "adapt {pressure:e} Pa: level {level}: {} slave face elements marked where the faces may hide a touch",
                    misfit.len()
                );
            }
            let neighbours = d.edge_neighbours_in(case.dimension()).at(level);
            let mut marks = mark_contact_edges(src, slave, &misfit, neighbours)?;
            if let Some((rec, error)) = bulk.take()
                && error > bulk_threshold
            {
                marks.extend(bulk_marks(src, &rec));
            }
            let marked = clock.elapsed().as_secs_f64();
            let bodies = refine_bodies(src_bodies, &marks);
            // Resolving the faces keeps the control points.
            let dofs = (src.dim + 1) * bodies.n_control_points();
            if trace {
                let normal = src.dim - 1;
                for (name, body) in [("upper", UPPER), ("lower", LOWER)] {
                    let census = level_census(bodies.get(body), normal, contact_face_side(body));
                    let all: Vec<usize> = census.iter().map(|c| c[0]).collect();
                    let deep: Vec<usize> = census.iter().map(|c| c[1]).collect();
                    eprintln!(
                        "adapt {pressure:e} Pa: level {level}: {name} body's elements by cell level {all:?}, of which below their level's first two layers {deep:?}"
                    );
                }
            }
            if dofs > d.max_dofs {
                if trace {
                    eprintln!(
                        "adapt {pressure:e} Pa: level {level} would have {dofs} unknowns > max_dofs"
                    );
                }
                // The previous level stays the last, with its factors and
                // caches (the self-consistency iterations run on it).
                stop = format!("max_dofs: level {level} would have {dofs} unknowns");
                self.report_level(|| {
                    let kept = format!("max_dofs ({}), level {} kept", d.max_dofs, level - 1);
                    level_report(dofs, None, Some(kept))
                });
                break;
            }
            // The previous level's factors and caches are not needed while
            // this one builds and solves (rebuilt should it be kept after a
            // failure); freed first, so that this level reuses their memory.
            let releasing = clock.elapsed().as_secs_f64();
            if let Some(newton) = src_newton {
                newton.release_solvers();
                src.release_caches();
            }
            let released = clock.elapsed().as_secs_f64() - releasing;
            let unresolved = [LOWER, UPPER].map(|k| bodies.get(k).control_points().to_vec());
            let bodies = bodies.resolved(&heights, self.geometry.g0)?;
            let refined = clock.elapsed().as_secs_f64();
            let mut next = PathSolver::with_bodies(case, self.geometry.clone(), bodies)?;
            let modelled = clock.elapsed().as_secs_f64();
            next.capture = self.capture;
            // The self-consistency iterations of the final level start with
            // the slope of the path's previous pressure.
            next.self_consistency_slope = self.self_consistency_slope;
            let symmetric = src.symmetric_solvers();
            next.model.set_symmetric_solvers(symmetric);
            transfer_state(src, &mut next.model);
            // Kept for a second start should this one fail (below).
            let transferred = next.model.save();
            next.last_pressure = pressure;
            let built = clock.elapsed().as_secs_f64();
            let solved = next.solve_fluxes_on_mesh(pressure, fluxes, true, None);
            self.absorb_cost(&mut next);
            // How the level was solved where its carried-over state failed.
            let mut started = None;
            let solved = match solved {
                Ok(r) if r.iter().all(|r| r.converged) => Ok(r),
                // The carried-over state is a near-solution where the refined
                // faces stay close to the coarse ones. Where the exact surface
                // has features finer than the coarse fit (a narrow asperity of
                // a measured surface), the refined faces overlap the other
                // body by up to the fit's error, and the first increments may
                // invert an element. The level is then solved again from the
                // configuration the coarser level solved (the gaps unchanged,
                // the faces' change of shape a strain instead;
                // `keep_transferred_configuration`), and should that fail too,
                // from rest along the pressure path. A solve that stalls
                // instead (it evaluates but does not converge) is not repeated.
                Err(e) if starts_unevaluable(&e) => {
                    let reason = NON_FINITE_RESIDUAL;
                    let bodies = next.bodies.clone();
                    drop(next);
                    let mut again =
                        PathSolver::with_bodies(case, self.geometry.clone(), bodies.clone())?;
                    again.model.restore(&transferred);
                    keep_transferred_configuration(&mut again.model, &unresolved);
                    again.last_pressure = pressure;
                    let mut attempts = Vec::new();
                    let solved = loop {
                        if trace {
                            eprintln!(
                                "adapt {pressure:e} Pa: level {level}: {reason} from the carried-over state; solving it {}",
                                ["from the configuration solved", "from rest"][attempts.len()]
                            );
                        }
                        again.capture = self.capture;
                        again.self_consistency_slope = self.self_consistency_slope;
                        again.model.set_symmetric_solvers(symmetric);
                        let result = again.solve_fluxes_on_mesh(pressure, fluxes, true, None);
                        self.absorb_cost(&mut again);
                        match result {
                            Ok(r) if r.iter().all(|r| r.converged) => {
                                started = Some(match attempts.len() {
                                    0 => format!(
                                        "solved again from the configuration solved ({reason} from the carried-over state)"
                                    ),
                                    _ => format!(
                                        "solved again from rest ({reason} from the carried-over state; the configuration solved did not converge)"
                                    ),
                                });
                                break Ok(r);
                            }
                            other => attempts.push(failure_reason(other)),
                        }
                        if attempts.len() == 2 {
                            break Err(format!(
                                "{reason} from the carried-over state; from the configuration solved: {}; from rest: {}",
                                attempts[0], attempts[1]
                            ));
                        }
                        // The failed attempt's factors are freed first.
                        drop(again);
                        again =
                            PathSolver::with_bodies(case, self.geometry.clone(), bodies.clone())?;
                        place_at_first_touch(case, &again.geometry, &mut again.model)?;
                    };
                    next = again;
                    solved
                }
                other => Err(failure_reason(other)),
            };
            let solved = match solved {
                Ok(r) => r,
                Err(why) => {
                    if trace {
                        eprintln!(
                            "adapt {pressure:e} Pa: level {level} failed ({why}); keeping level {}",
                            level - 1
                        );
                    }
                    stop = format!("level {level} failed: {why}");
                    self.report_level(|| {
                        let kept = format!("failed ({why}), level {} kept", level - 1);
                        level_report(dofs, None, Some(kept))
                    });
                    break;
                }
            };
            if let Some(dir) = std::env::var_os("TCGEN_DUMP_TWOLEVEL") {
                let src = match fine.as_mut() {
                    Some(f) => &mut f.model,
                    None => &mut self.model,
                };
                write_two_level_system(src, &mut next.model, std::path::Path::new(&dir), level)?;
            }
            iterations += max_newton_iterations(&solved);
            let diff: Vec<f64> = solved
                .iter()
                .zip(&best)
                .map(|(f, c)| (f.jump - c.jump).abs())
                .collect();
            regime = match (fitted(&mut next.model, level < d.max_levels)?, regime) {
                (false, _) => None,
                (true, Some(start)) => Some(start),
                (true, None) => Some(diffs.len() + 1),
            };
            let start = regime.filter(|&s| s <= diffs.len()).unwrap_or(0);
            let est: Vec<f64> = (0..diff.len())
                .map(|i| {
                    let previous: Vec<f64> = diffs[start..].iter().map(|d| d[i]).collect();
                    two_level_estimate(diff[i], &previous, ratio)
                })
                .collect();
            // Differences within the fitted regime, this one included.
            let in_regime = regime.map_or(usize::MAX, |s| (diffs.len() + 1).saturating_sub(s));
            diffs.push(diff);
            best = solved;
            consistent = None;
            if trace {
                eprintln!(
                    "adapt {pressure:e} Pa: level {level}, {} unknowns, levels {:?}, jump {:?}, estimate {:?}, contact {:.5}, fitted regime {regime:?}; built in {built:.1} s (marks {marked:.1} s, refinement {:.1} s, previous level released {released:.1} s, model {:.1} s, transfer {:.1} s), solved in {:.1} s; the process's peak resident memory so far {}",
                    best[0].dofs,
                    best[0].levels,
                    best.iter().map(|r| r.jump).collect::<Vec<_>>(),
                    est,
                    best[0].interface.contact_fraction,
                    refined - marked - released,
                    modelled - refined,
                    built - modelled,
                    clock.elapsed().as_secs_f64() - built,
                    process_memory("VmHWM:").map_or("unknown".into(), |b| format_bytes(b as f64))
                );
            }
            let estimate_met = est
                .iter()
                .zip(&best)
                .all(|(e, r)| *e <= target * r.jump.abs());
            let least = min_adaptive_levels(case.sample.dimension);
            met = level >= least && in_regime >= FITTED_LEVELS && estimate_met;
            // The estimate sees the bulk only where the levels refined it:
            // while the bulk's estimated approach error exceeds its share of
            // the target, the refinement goes on, marking the bulk too.
            bulk = bulk_of(&next.model, &best);
            withheld = (estimate_met && level < least).then(|| {
                format!(
                    "level {level}'s jump estimate met the target; a {}D estimate may end the refinement from level {least} on",
                    case.sample.dimension
                )
            });
            if met && let Some((_, error)) = bulk.as_ref().filter(|b| b.1 > bulk_threshold) {
                withheld = Some(format!(
                    "level {level}'s jump estimate met the target; the bulk's estimated approach error {:.3} % exceeds {} %",
                    100.0 * error,
                    100.0 * bulk_threshold
                ));
                met = false;
            }
            if met && level < d.max_levels {
                // The estimate sees only what the levels refined: where the
                // solved faces may still hide a touch of the exact surfaces,
                // the refinement goes on (the contact was prepared at the
                // solved state by `fitted` above).
                let m = surface_misfit_marks(&next.model, slave, &heights, g0, misfit_bound)?;
                if !m.is_empty() {
                    withheld = Some(format!(
                        "level {level}'s jump estimate met the target; {} slave face elements may hide a touch of the exact surfaces",
                        m.len()
                    ));
                    met = false;
                    hidden = Some(m);
                }
            }
            if met && self_consistent {
                // The self-consistent jumps' estimate adds the fixed point's
                // bound to the plain one: where it misses the target, and the
                // bound that refinement cannot lower (the case's tolerance)
                // is below it, the refinement goes on (the iterations
                // restore the plain state, from which the next level starts).
                // The previous level is not needed any more: freed first, so
                // that the iterations reuse its memory.
                drop(fine.take());
                let solved = next.self_consistent_level(pressure, fluxes, &best, Some(&est));
                self.absorb_cost(&mut next);
                let (solved, e) = solved?;
                iterations += max_newton_iterations(&solved);
                let tolerance = case.homogenization.tolerance;
                let missed = solved
                    .iter()
                    .zip(e.iter().flatten())
                    .filter(|(r, e)| r.converged && **e > target * r.jump.abs())
                    .map(|(r, e)| e / r.jump.abs())
                    .reduce(f64::max);
                if let Some(missed) = missed {
                    let why = self_consistent_estimate_missed(missed);
                    if level < d.max_levels && tolerance < target {
                        withheld = Some(format!("level {level}: {why}"));
                        met = false;
                        next.model.prepare_contact()?;
                    } else {
                        consistent_missed = Some(why);
                    }
                }
                consistent = Some((solved, e));
            }
            if trace && let Some(w) = &withheld {
                eprintln!("adapt {pressure:e} Pa: {w}");
            }
            self.report_level(|| {
                let jump = (best[0].jump, est[0] / best[0].jump.abs());
                let stop = if met {
                    Some(consistent_missed.clone().unwrap_or("target met".into()))
                } else if level == d.max_levels {
                    Some(match &withheld {
                        Some(w) => format!("max_levels ({w})"),
                        None => "max_levels".into(),
                    })
                } else {
                    None
                };
                let goes_on = withheld.clone().filter(|_| stop.is_none());
                LevelReport {
                    goes_on,
                    started: started.clone(),
                    ..level_report(best[0].dofs, Some(jump), stop)
                }
            });
            estimate = Some(est);
            fine = Some(next);
            if met {
                stop = "target met".into();
                break;
            }
        }
        // The self-consistency iterations on the final level, unless they ran
        // on it in the loop.
        if self_consistent && consistent.is_none() {
            let last = fine.as_mut().unwrap_or(self);
            let solved = last.self_consistent_level(pressure, fluxes, &best, estimate.as_deref());
            if let Some(f) = fine.as_mut() {
                self.absorb_cost(f);
            }
            let solved = solved?;
            iterations += max_newton_iterations(&solved.0);
            consistent = Some(solved);
        }
        if let Some((solved, e)) = consistent {
            best = solved;
            estimate = e;
            if let Some(f) = &fine {
                // The slope measured on the final level, for the next pressure.
                self.self_consistency_slope = f.self_consistency_slope;
            }
        }
        // The fields of the mesh of `best`.
        if let Some(f) = fine.as_mut() {
            self.fields = f.fields.take();
            for r in best.iter_mut() {
                r.interface.approach += touch_shift;
            }
        }
        if let Some(w) = withheld.filter(|_| !met) {
            stop = format!("{stop} ({w})");
        }
        for (i, r) in best.iter_mut().enumerate() {
            r.jump_error = estimate.as_ref().map(|e| e[i]);
            r.error_target_met = Some(met);
            r.refinement_stop = Some(stop.clone());
            r.newton_iterations = iterations;
            // The plain jump met the target; the self-consistent one's
            // estimate, with its fixed point's bound, may not.
            if let Some(e) = r.jump_error.filter(|e| met && *e > target * r.jump.abs()) {
                r.error_target_met = Some(false);
                r.refinement_stop = Some(self_consistent_estimate_missed(e / r.jump.abs()));
            }
        }
        Ok(best)
    }

    /// Two-phase (self-consistent) jumps at one pressure for several fluxes
    /// (W/m², > 0) on the current mesh. The mechanical phase at θ̄c and the first thermal phase
    /// are shared by all fluxes: with every property frozen the thermal phase
    /// is linear in `h̄`, so its solution for a unit flux scales exactly. Each
    /// flux then runs its own self-consistency iterations from that state.
    /// A flux whose iterations fail is reported as failed; the others go on.
    ///
    /// `estimates` (adaptive levels: each flux's estimated discretization
    /// error of the plain jump, K) lets the self-consistency iterations stop
    /// once their change is below [`SELF_CONSISTENCY_ESTIMATE_SHARE`] of it.
    fn solve_fluxes_on_mesh(
        &mut self,
        pressure: f64,
        fluxes: &[f64],
        plain: bool,
        estimates: Option<&[f64]>,
    ) -> Result<Vec<PointResult>> {
        let case = self.case;
        let self_consistent_method = case.homogenization.method == Method::TwoPhaseSelfConsistent;
        let self_consistent = !plain && self_consistent_method;
        // The plain solve of the self-consistent method, whose own iterations
        // replace its results (it reports no contact fraction).
        let replaced = plain && self_consistent_method;
        if matches!(
            case.homogenization.method,
            Method::Coupled | Method::Linearized
        ) {
            return Err(Error::invalid(
                "homogenization.method",
                "coupled/linearized",
                "a two-phase method for multi-flux solves",
            ));
        }
        if let Some(h) = fluxes.iter().find(|h| !(h.is_finite() && **h > 0.0)) {
            return Err(Error::invalid("flux", h, "a finite flux > 0 (W/m²)"));
        }
        let theta_c = case.load.contact_temperature;
        let slave = slave_body(case);
        let trace = std::env::var_os("TCGEN_TRACE").is_some();
        let kept = self
            .plain_phase
            .take()
            .filter(|(p, _)| !plain && *p == pressure && self.last_pressure == pressure);
        let (base_it, first) = match kept {
            // The plain solve's phases at this pressure, on this mesh: their
            // iterations are counted there.
            Some((_, first)) => (
                0,
                ThermalPhase {
                    iterations: 0,
                    ..first
                },
            ),
            None => {
                // Mechanical phase at θ̄c along the pressure path.
                self.model.set_frozen_temperature(UPPER, theta_c);
                self.model.set_frozen_temperature(LOWER, theta_c);
                let p0 = self.last_pressure;
                let base_it = self.drive([p0, 0.0], [pressure, 0.0])?;
                self.last_pressure = pressure;
                // First thermal phase at unit flux. Its contact fraction is
                // reported, except for the plain solves of the
                // self-consistent method (its own iterations replace them;
                // measured for the adaptive levels' trace).
                let contact = !replaced || std::env::var_os("TCGEN_ADAPT_TRACE").is_some();
                (
                    base_it,
                    self.thermal_phase(pressure, [theta_c, theta_c], 1.0, contact)?,
                )
            }
        };
        let base = self.model.save();
        let mut out = Vec::with_capacity(fluxes.len());
        self.fields = None;
        self.fixed_point_bounds = vec![None; fluxes.len()];
        for (i, &flux) in fluxes.iter().enumerate() {
            let scale = |t: f64| theta_c + flux * (t - theta_c);
            let estimate_floor = estimates.map_or(0.0, |e| SELF_CONSISTENCY_ESTIMATE_SHARE * e[i]);
            let mut abp = AbpTemperatures {
                upper: scale(first.abp.upper),
                lower: scale(first.abp.lower),
            };
            let mut ts = scale(first.theta_s);
            let mut jump = ts - self.slave_abp(&abp);
            self.history = vec![jump];
            let mut iface = first.interface;
            iface.max_active_jump *= flux;
            // The unit-flux thermal fields scale the same way.
            let mut fields = first.fields.as_ref().map(|f| f.at_flux(theta_c, flux));
            let mut iterations = base_it + first.iterations;
            let mut k = 1;
            let mut failure = None;
            if self_consistent {
                let mut converged = false;
                // The fixed point ϑ̄c = F(ϑ̄c): the first phase gave F(0); the
                // next input is the last output, or the secant extrapolation.
                let mut secant = Secant::new(
                    case.homogenization.acceleration,
                    jump,
                    self.self_consistency_slope,
                );
                let mut input = secant.first_input();
                // With the secant update the first iteration's mechanical
                // phase is a predictor of one Newton increment
                // ([`PREDICTOR_INCREMENTS`]): its output only steers the
                // secant, and where it would end the iterations, the phase is
                // solved to convergence and evaluated again (the same `k`),
                // unless its state has converged already: then its output is
                // `F` of its input.
                let mut predictor = (case.homogenization.acceleration == Acceleration::Secant)
                    .then_some(PREDICTOR_INCREMENTS);
                // Whether the secant's previous pair is an evaluation of `F`
                // (the first, `(0, F(0))`, is; a predictor's is not).
                let mut previous_exact = true;
                // Each evaluation's mechanical phase starts from the secant
                // extrapolation of the last two end states to its input.
                let mut starts = MechanicalStarts::new(base.clone());
                // The last two evaluations where `F` stepped across the
                // fixed point (for the failure's reason on a fixed mesh).
                let mut stepped: Option<[f64; 4]> = None;
                while k < case.homogenization.max_iterations {
                    k += 1;
                    // Slave properties at θ̄ = θ̄c + ϑ̄c (first-order corrector), master at θ̄c.
                    let t_slave = theta_c + input;
                    let temps = if slave == UPPER {
                        [t_slave, theta_c]
                    } else {
                        [theta_c, t_slave]
                    };
                    if let Some((t, start)) = self
                        .extrapolated_starts
                        .then(|| starts.start(input))
                        .flatten()
                    {
                        if trace {
                            eprintln!(
                                "self-consistency {k}: the mechanical phase starts from the last two end states extrapolated by {t:.3}"
                            );
                        }
                        self.model.restore(&start);
                    }
                    let step = (|| -> Result<ThermalPhase> {
                        self.model.set_frozen_temperature(UPPER, temps[0]);
                        self.model.set_frozen_temperature(LOWER, temps[1]);
                        let it = match predictor {
                            Some(m) => {
                                let saved = self.model.save();
                                match self.drive_increments([pressure, 0.0], m) {
                                    Ok(it) => it,
                                    Err(e @ Error::OutOfMemory { .. }) => return Err(e),
                                    // Solved as the other iterations are.
                                    Err(_) => {
                                        self.model.restore(&saved);
                                        predictor = None;
                                        self.drive([pressure, 0.0], [pressure, 0.0])?
                                    }
                                }
                            }
                            None => self.drive([pressure, 0.0], [pressure, 0.0])?,
                        };
                        let mut phase = self.thermal_phase(pressure, temps, flux, false)?;
                        phase.iterations += it;
                        Ok(phase)
                    })();
                    match step {
                        Ok(phase) => {
                            starts.push(input, self.model.save(), predictor.is_none());
                            iterations += phase.iterations;
                            let new_jump = phase.theta_s - self.slave_abp(&phase.abp);
                            if predictor.is_none() {
                                self.history.push(new_jump);
                            }
                            // The fixed point's residual |F(ϑ) − ϑ|.
                            let change = (new_jump - input).abs();
                            // The output's distance to the fixed point, from
                            // the chord of `F` at this pressure.
                            let output_error = secant
                                .chord_slope(input, new_jump)
                                .map(|slope| fixed_point_output_error(slope, change));
                            if trace {
                                let distance =
                                    output_error.map_or("unknown".into(), |e| format!("{e:.2e} K"));
                                let how = if predictor.is_some() {
                                    " (predictor)"
                                } else {
                                    ""
                                };
                                eprintln!(
                                    "self-consistency {k}{how}: slave at θc + {input:.9e} K, jump {new_jump:.9e} K (to the fixed point: {distance})"
                                );
                            }
                            (abp, ts, jump, iface) =
                                (phase.abp, phase.theta_s, new_jump, phase.interface);
                            fields = phase.fields;
                            // Relative to the jump, and absolute at 1e-12 θc
                            // (1e4 round-offs of the temperatures): a jump of
                            // round-off size (conforming flat surfaces) stops;
                            // on an adaptive level, also a change, or the
                            // output's distance to the fixed point, far below
                            // the discretization's estimated error.
                            if change
                                <= (case.homogenization.tolerance * jump.abs())
                                    .max(1e-12 * theta_c)
                                    .max(estimate_floor)
                                || output_error.is_some_and(|e| e <= estimate_floor)
                            {
                                if predictor.take().is_some() {
                                    // Newton from the predictor's state (the
                                    // thermal phase restored it): no increment
                                    // where its residual meets the tolerance.
                                    match self.drive([pressure, 0.0], [pressure, 0.0]) {
                                        Ok(0) => self.history.push(new_jump),
                                        Ok(it) => {
                                            // The same iteration, its mechanical
                                            // phase solved to convergence.
                                            iterations += it;
                                            k -= 1;
                                            continue;
                                        }
                                        Err(e) => {
                                            failure = Some(e.to_string());
                                            break;
                                        }
                                    }
                                }
                                // The output's distance to the fixed point
                                // reached, added to an adaptive level's
                                // estimate.
                                self.fixed_point_bounds[i] = Some(output_error.unwrap_or(change));
                                converged = true;
                                break;
                            }
                            // `F` steps across the fixed point between the
                            // last two inputs (the nodal active set's
                            // conducting supports, docs/adaptivity.md): no
                            // further iteration comes closer than the step.
                            // An adaptive level stops here, the bound added to
                            // its estimate; a fixed mesh goes on (an up-step
                            // has fixed points on its sides).
                            let exact = predictor.is_none() && previous_exact;
                            if let Some(bound) =
                                secant.step_bound(input, new_jump).filter(|_| exact)
                            {
                                let (x0, f0) = secant.previous;
                                stepped = Some([x0, f0, input, new_jump]);
                                if trace {
                                    eprintln!(
                                        "self-consistency {k}: F steps across the fixed point between ϑ = {x0:.9e} (F = {f0:.9e}) and {input:.9e} K; bound {bound:.3e} K"
                                    );
                                }
                                if estimates.is_some() {
                                    self.fixed_point_bounds[i] = Some(bound);
                                    converged = true;
                                    break;
                                }
                            }
                            previous_exact = predictor.is_none();
                            predictor = None;
                            input = secant.next(input, new_jump);
                        }
                        Err(e) => {
                            failure = Some(e.to_string());
                            break;
                        }
                    }
                }
                // The contact fraction of the last mechanical phase, the one
                // reported (the phases' own were not measured).
                if failure.is_none() {
                    match contact_fraction(&self.model) {
                        Ok(f) => iface.contact_fraction = f,
                        Err(e) => failure = Some(e.to_string()),
                    }
                }
                if converged {
                    self.self_consistency_slope = secant.slope.or(self.self_consistency_slope);
                }
                if !converged && failure.is_none() {
                    let step = stepped.map_or(String::new(), |[x0, f0, x1, f1]| {
                        format!(
                            " (F(ϑ) stepped across the fixed point: F({x0:.6}) = {f0:.6} K, F({x1:.6}) = {f1:.6} K; an adaptive run, `target_error`, reports the jump with the step in its estimate)"
                        )
                    });
                    failure = Some(format!(
                        "self-consistency did not converge in {} iterations{step}",
                        case.homogenization.max_iterations
                    ));
                }
                // The next flux (or pressure) starts again from the shared state at θ̄c.
                self.model.restore(&base);
                self.model.set_frozen_temperature(UPPER, theta_c);
                self.model.set_frozen_temperature(LOWER, theta_c);
            }
            if failure.is_some() {
                fields = None;
            }
            // The fields of the last flux.
            self.fields = fields;
            let r = match failure {
                None => self.result(
                    pressure,
                    flux,
                    self.identify(ts, &abp),
                    ts,
                    abp,
                    iface,
                    if self_consistent { k } else { 0 },
                    iterations,
                ),
                Some(m) => {
                    let mut r = PointResult::failed(case, pressure, m);
                    r.flux = flux;
                    r.newton_iterations = iterations;
                    r
                }
            };
            out.push(r);
        }
        if plain {
            self.plain_phase = Some((pressure, first));
        }
        debug_assert!(
            out.iter()
                .all(|r| !r.converged || r.interface.contact_fraction.is_finite() || replaced),
            "a reported result without its contact fraction"
        );
        Ok(out)
    }

    /// The thermal phase on the frozen configuration (Sect. 3.1 (ii)) with
    /// conductivities frozen at `temps` (upper, lower) and flux `flux`;
    /// restores the mechanical phase afterwards. Returns the ABP, `θ(I)`, the
    /// iterations, the interface measurements and, when capturing, the
    /// fields: each phase's from its own state ([`Fields::two_phase`]).
    ///
    /// The contact fraction is measured only with `contact` set (else `NaN`,
    /// [`measure_but_contact`]): in 3D it costs more than the rest of the
    /// measurements, and of the phases at a pressure only the last one's is
    /// reported.
    fn thermal_phase(
        &mut self,
        pressure: f64,
        temps: [f64; 2],
        flux: f64,
        contact: bool,
    ) -> Result<ThermalPhase> {
        let case = self.case;
        let (mface, sface) = (self.master_face(), self.slave_face());
        let abp = accompanying_bar(
            &self.materials.0,
            &self.materials.1,
            pressure,
            flux,
            case.load.contact_temperature,
            case.sample.height,
            AbpProperties::Frozen(temps),
        )?;
        let saved = self.model.save();
        // The mechanical phase's equilibrium: its displacements at the
        // temperatures it was solved with.
        let mechanical = self
            .capture
            .then(|| Fields::sample(&self.model))
            .transpose()?;
        self.model.set_coupling(Coupling::Thermal)?;
        self.model.freeze_body_conductivity(UPPER, temps[0]);
        self.model.freeze_body_conductivity(LOWER, temps[1]);
        let tm = if mface.0 == UPPER {
            abp.upper
        } else {
            abp.lower
        };
        self.model
            .prescribe_face(mface.0, self.model.dim - 1, mface.1, self.model.dim, tm);
        let result = self.drive([pressure, 0.0], [pressure, flux]);
        let ts = self
            .model
            .face_mean_temperature(sface.0, self.model.dim - 1, sface.1);
        let interface = match contact {
            true => measure(&self.model, self.alpha)?,
            false => measure_but_contact(&self.model, self.alpha)?,
        };
        // The thermal phase's own state (with its frozen conductivities).
        let fields = match (mechanical, &result) {
            (Some(m), Ok(_)) => Some(Fields::sample(&self.model).map(|t| Fields::two_phase(m, t))),
            _ => None,
        };
        // Back to the mechanical phase.
        self.model.restore_materials();
        self.model.restore(&saved);
        self.model.set_coupling(Coupling::Mechanical)?;
        Ok(ThermalPhase {
            abp,
            theta_s: ts,
            iterations: result?,
            interface,
            fields: fields.transpose()?,
        })
    }
}

/// With adaptive refinement in 2D, Newton's relative residual tolerance is
/// at least this share of `[discretization] target_error` (1e-5 at a 1 %
/// target; [`newton_settings`]): the algebraic error is balanced against the
/// discretization error, as [`SELF_CONSISTENCY_ESTIMATE_SHARE`] balances the
/// self-consistency iterations, instead of driven to the default 1e-10.
/// Newton converges quadratically there, so the tolerance saves the last
/// increment of a solve whose residual has fallen below it. Stop 50 set
/// 1e-4 (1e-6 at 1 %): on the 3D egg box's 72 kPa point
/// (`tables/egg_box_on_flat.toml` adaptive to 1 %, four levels,
/// self-consistent) 29 Newton increments instead of 35, the jump within
/// 6e-8 and its estimate within 1.5e-4 (relative) of the default's. Stop 57
/// set 1e-3: the egg box's path took 279 increments instead of 299, its
/// jumps within 1.4e-5 (relative); the demo table's jumps moved by at most
/// 4.8e-6 and their estimates by 1.1e-4; where a jump is small against its
/// sample's (the Sect. 5.7 sample at 350 kPa, 0.0435 K) the algebraic error
/// is about 1e-4 of it, which its estimate then sees (0.003 % → 0.012 %),
/// a hundredth of the 1 % target (docs/adaptivity.md; docs/3d.md,
/// "Stop 57"). In 2D an increment costs milliseconds, and the demo table at
/// 1e-2 moved a jump by 6.5e-4 (a third of its estimate): 2D keeps 1e-3 (3D:
/// [`NEWTON_TARGET_SHARE_3D`]).
pub const NEWTON_TARGET_SHARE: f64 = 1e-3;

/// [`NEWTON_TARGET_SHARE`] in 3D (1e-4 at a 1 % target), where a fourth
/// level's increment costs 5–7 s (a tangent and a GMRES solve). Stop 59, the
/// 3D benchmark's path: 259 Newton increments instead of 279, 638.6 against
/// 671.9 s (one run each, back to back), the ten jumps within 5.5e-5
/// (relative; at most 0.41 % of their estimates) and the estimates within
/// 1.2e-2 of 1e-3's; the 72 kPa point's level 4 marked 125 776 unknowns
/// instead of 127 888 (docs/3d.md, "Stop 59"). Against 1e-4 of the target
/// (stop 96, the same path) the jumps move by up to 1.2e-3, a node or two
/// of the contact's active set exchanged at a spot's edge (11.51 kPa), for
/// 28 % of the path's time more; the contact's discrete decisions scatter
/// the jumps by about as much at any tolerance (docs/adaptivity.md).
pub const NEWTON_TARGET_SHARE_3D: f64 = 1e-2;

/// The share of `[discretization] target_error` that bounds Newton's
/// relative tolerance on adaptive runs in dimension `dim`
/// ([`NEWTON_TARGET_SHARE`], [`NEWTON_TARGET_SHARE_3D`]).
pub fn newton_target_share(dim: usize) -> f64 {
    if dim >= 3 {
        NEWTON_TARGET_SHARE_3D
    } else {
        NEWTON_TARGET_SHARE
    }
}

/// The Newton settings of a case's solves: `[solver.newton]`, with the
/// relative tolerance raised to [`newton_target_share`] of the target error
/// on adaptive runs (where the case's own is tighter).
pub fn newton_settings(case: &Case) -> NewtonSettings {
    let mut settings = case.solver.newton.clone();
    if let Some(target) = case.discretization.target_error {
        settings.relative_tolerance = settings
            .relative_tolerance
            .max(newton_target_share(case.dimension()) * target);
    }
    settings
}

/// On an adaptive level, the self-consistency iterations (2.14) also stop
/// once the change of the slave's temperature is below this share of the
/// jump's estimated discretization error, which then includes that bound.
/// The fixed-point map has a floor of noise there: the discrete contact
/// decisions (active set, zone edges) follow the last digits of the state,
/// and on the refined 3D egg box (level 3, 100 kPa) they moved its output by
/// up to 4e-5 relative from one iteration to the next, above the default
/// tolerance (1e-6), so that whether the iterations met it was a matter of
/// chance (6, 10 or more than 20 iterations with round-off as the only
/// difference), while the level's estimate was 7 % of the jump.
pub const SELF_CONSISTENCY_ESTIMATE_SHARE: f64 = 0.01;

/// Newton increments of the first self-consistency iteration's mechanical
/// phase with the secant update (a predictor; the phase is not solved to
/// convergence). On the 3D egg box at 72 kPa (level 4, 96 334 mechanical
/// equations) the first iteration moved the slave's temperature by 4.7 K
/// and its mechanical phase took three increments of about 10 s (residual
/// 6e-4, 2e-6, 2e-9, 6e-15); after one, the secant's next input is the same
/// to about 1e-4 K, far below what ends the iterations (docs/3d.md,
/// "Stop 43").
pub const PREDICTOR_INCREMENTS: usize = 1;

/// The distance of a self-consistency iteration's output `F(ϑ)` to the
/// fixed point `ϑ* = F(ϑ*)` (K), from its change `|F(ϑ) − ϑ|` and the slope
/// `F'` of `F` (a chord at this pressure): to first order
/// `F(ϑ) − ϑ* = F'(ϑ − ϑ*)` and `ϑ − ϑ* = (ϑ − F(ϑ))/(1 − F')`, so
/// `|F(ϑ) − ϑ*| = |F'|/(1 − F') |F(ϑ) − ϑ|`, here doubled for the chord's
/// own error. On the 3D egg box's path (level 4, 1–244 kPa, `F'` −0.005 to
/// −0.2) the first-order distance matched the distance to the converged
/// iterate within 1 % at the iterations where it stops them, and within a
/// factor 2.3 (either way) at the others, on longer chords
/// (docs/adaptivity.md).
pub fn fixed_point_output_error(slope: f64, change: f64) -> f64 {
    2.0 * slope.abs() / (1.0 - slope) * change
}

/// Levels of adaptive refinement before the estimate may stop the loop in
/// dimension `dim`: 2 in 2D (the first difference can be small by chance on
/// a pre-asymptotic coarse mesh), 3 in 3D. Against independent boundary
/// elements the 3D level-2 estimates fell below the error at 5 of 21
/// measured levels (effectivity 0.45–0.78; the self-affine surface from
/// `[16, 16, 4]` at 29 % contact: 0.55 % for an error of 0.88 %, a 1 %
/// target met falsely; a Gaussian surface at 600 Pa: 1.5 % for 3.09 %),
/// and the level-3 ones at 1 of 21 (0.97, on an estimate of 3.4 %;
/// docs/3d.md, "Many small spots against the boundary elements"). The
/// jumps of a 3D surface alternate around the limit from level to level,
/// so that two changes may both be small by chance; three give the
/// estimate's guards their whole history.
pub fn min_adaptive_levels(dim: usize) -> usize {
    if dim >= 3 { 3 } else { 2 }
}

/// Differences between levels on which every contact edge is fitted to the
/// near-edge asymptotics (`ContactInterface::zone_edges_fitted`) before the
/// estimate may stop the loop, where the edges are fitted at all (2D
/// constraint models): in that regime the jumps converge faster and less
/// regularly (the fits' scatter), so that two small differences in a row
/// occur by chance (a random profile at 100 Pa: estimate 0.41 of the true
/// error with two, 1.8 with three).
pub const FITTED_LEVELS: usize = 3;

/// Margin on the case fits' largest height errors (sampled at 8 points per element and
/// direction) for the bound below which [`surface_misfit_marks`] samples a face element's
/// error: the refined levels' quasi-interpolants and the samples between the fits' own.
pub const MISFIT_BOUND_MARGIN: f64 = 2.0;

/// Why a point missed its target where its plain jump's estimate met it and
/// the self-consistent jump's, `relative` to the jump, does not.
fn self_consistent_estimate_missed(relative: f64) -> String {
    format!(
        "the plain jump's estimate met the target; the self-consistent jump's is {:.3} %",
        100.0 * relative
    )
}

/// The Newton iterations of a solve at one pressure for several fluxes: the
/// most any flux spent (they share the mechanical phase).
fn max_newton_iterations(results: &[PointResult]) -> usize {
    results
        .iter()
        .map(|r| r.newton_iterations)
        .max()
        .unwrap_or(0)
}

/// Whether a failed solve ended on a state the model cannot evaluate (a residual
/// that is not finite), or failed after shortening increments that led to such
/// states: Newton's failure at a constant load (a level's re-solve from its
/// carried-over state, whose prescribed values [`transfer_state`] holds), or
/// the load stepping's last one where the load varies and it cut back.
fn starts_unevaluable(e: &Error) -> bool {
    match e {
        Error::NewtonDiverged { reason, .. } => reason.starts_with(NON_FINITE_RESIDUAL),
        Error::LoadStepStalled { last, .. } => starts_unevaluable(last),
        _ => false,
    }
}

/// Why a level's solve failed: the first failed point's status, or the error.
fn failure_reason(solved: Result<Vec<PointResult>>) -> String {
    match solved {
        Ok(r) => r
            .iter()
            .find_map(|r| match &r.status {
                Status::Failed(m) => Some(m.clone()),
                Status::Converged => None,
            })
            .unwrap_or_default(),
        Err(e) => e.to_string(),
    }
}

/// The ratio of successive errors of the jump per adaptive level that
/// [`two_level_estimate`] assumes in dimension `dim`: the edge elements halve
/// per level, and the jump converges at first order in their size in 2D
/// (ratio 1/2) and at order 3/2 in 3D (ratio `2^(−3/2)`). In 3D a spot's edge
/// is a curve that crosses many elements, and its position converges as the
/// near-edge gap `~ t^(3/2)` allows: the egg box's contact fraction against
/// the boundary elements on uniformly refined meshes at order about 1.5
/// (docs/validation.md), and its adaptive jumps' errors against them at
/// 0.02–0.5 `p*` fall by a median factor of 3.1 per level (docs/3d.md,
/// "Adaptive levels against the boundary elements"). In 2D the single
/// contact edge crosses element boundaries as a whole, and the sequences
/// are too irregular for more than first order (an order-3/2 estimate gave
/// 0.16 of the true error on the random profile at 100 Pa).
pub fn level_error_ratio(dim: usize) -> f64 {
    if dim >= 3 {
        std::f64::consts::FRAC_1_SQRT_2 * 0.5
    } else {
        0.5
    }
}

/// The two-level error estimate of a jump (K) after a refinement level:
/// `max(d_k, ρ d_{k−1}, ρ² d_{k−2}) · ρ/(1 − ρ)` with `d_k = |J_k − J_{k−1}|`
/// the change of the jump over the last level, `d_{k−1}`, `d_{k−2}`
/// (`previous`, most recent last) the ones before, and `ρ` the ratio of
/// successive errors per level ([`level_error_ratio`]). For errors that fall
/// by `ρ` per level the error of `J_k` equals `d_k ρ/(1 − ρ)`, and
/// `d_k = ρ d_{k−1} = ρ² d_{k−2}` asymptotically; the older terms keep a
/// non-monotone sequence (the contact edge crossing element boundaries
/// makes single differences small by chance) from stopping early. With
/// `ρ = 1/2` (2D) this is `max(d_k, d_{k−1}/2, d_{k−2}/4)`.
pub fn two_level_estimate(d_k: f64, previous: &[f64], ratio: f64) -> f64 {
    previous
        .iter()
        .rev()
        .take(2)
        .zip([ratio, ratio * ratio])
        .fold(d_k, |m, (d, w)| m.max(w * d))
        * (ratio / (1.0 - ratio))
}

/// Solves every pressure of a case in order (one path); a failed point is
/// reported with its reason and ends the path (the later points are reported
/// as not reached). `progress` sees every result as it comes. With `vtk`,
/// the fields of every converged point go to that directory
/// ([`crate::sample::vtk`]: `pKKK_*.vtu` and the collection `series.pvd`).
pub fn solve_case(
    case: &Case,
    vtk: Option<std::path::PathBuf>,
    progress: impl FnMut(&PointResult),
) -> Result<Vec<PointResult>> {
    solve_case_observed(case, vtk, progress, None)
}

/// [`solve_case`], with `levels` seeing every adaptive level as it ends
/// ([`LevelReport`]). Adaptive 3D points are refined one after the other, and
/// `progress` sees each as it ends; adaptive 2D points run in parallel, and
/// `progress` sees them when all have.
pub fn solve_case_observed(
    case: &Case,
    vtk: Option<std::path::PathBuf>,
    mut progress: impl FnMut(&PointResult),
    levels: Option<LevelObserver>,
) -> Result<Vec<PointResult>> {
    let mut solver = PathSolver::new(case)?;
    solver.observe_levels(levels);
    let series = vtk
        .map(|dir| VtkSeries::create(&dir, &case.load.pressures))
        .transpose()?
        .map(Mutex::new);
    let series = series.as_ref();
    solver.capture_fields(series.is_some());
    if let Some(target) = case.discretization.target_error
        && matches!(
            case.homogenization.method,
            Method::TwoPhase | Method::TwoPhaseSelfConsistent
        )
    {
        return solve_path_adaptive(&mut solver, target, series, &mut progress);
    }
    let mut out = Vec::new();
    let mut failed = None;
    for (k, &p) in case.load.pressures.iter().enumerate() {
        let r = match &failed {
            Some(reason) => PointResult::failed(case, p, format!("not reached: {reason}")),
            None => match solver
                .solve_pressure(p)
                .and_then(|r| write_point(series, case, k, r, solver.take_fields()))
            {
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

/// Writes the fields of point `k` of the path (if converged and captured)
/// into `series` (if any).
fn write_point(
    series: Option<&Mutex<VtkSeries>>,
    case: &Case,
    k: usize,
    r: PointResult,
    fields: Option<Fields>,
) -> Result<PointResult> {
    if let (Some(s), Some(f), true) = (series, fields, r.converged) {
        let info = PointInfo {
            index: k,
            pressure: r.pressure,
            flux: r.flux,
            contact_temperature: r.contact_temperature,
            method: case.homogenization.method,
        };
        s.lock()
            .unwrap_or_else(|e| e.into_inner())
            .write_point(&info, &f)?;
    }
    Ok(r)
}

/// The adaptive path of [`solve_case`]: the case mesh along the whole path
/// first (continuation, plain two-phase), then every pressure refined from
/// its saved coarse state independently: in parallel (rayon) in 2D, one
/// at a time in 3D. The results
/// equal those of [`PathSolver::solve_pressure`] at each pressure; the
/// fields written to `series` are those of the final mesh of each.
fn solve_path_adaptive(
    solver: &mut PathSolver<'_>,
    target: f64,
    series: Option<&Mutex<VtkSeries>>,
    progress: &mut dyn FnMut(&PointResult),
) -> Result<Vec<PointResult>> {
    use rayon::prelude::*;
    let case = solver.case;
    let fluxes = [case.load.flux];
    // (index, pressure, Ok((coarse results, saved state, coarse fields)) or
    // the failure reason)
    let mut coarse = Vec::new();
    let mut failed: Option<String> = None;
    for (k, &p) in case.load.pressures.iter().enumerate() {
        let item = match &failed {
            Some(reason) => Err(format!("not reached: {reason}")),
            None => match solver.solve_fluxes_on_mesh(p, &fluxes, true, None) {
                Ok(r) if r.iter().all(|r| r.converged) => {
                    Ok((r, solver.model.save(), solver.take_fields()))
                }
                Ok(mut r) => {
                    failed = Some(format!("failed at {p:e} Pa"));
                    Err(match r.pop().map(|r| r.status) {
                        Some(Status::Failed(m)) => m,
                        _ => "failed".into(),
                    })
                }
                Err(e) => {
                    failed = Some(format!("failed at {p:e} Pa"));
                    Err(e.to_string())
                }
            },
        };
        coarse.push((k, p, item));
    }
    let (geometry, bodies, capture) = (&solver.geometry, &solver.bodies, solver.capture);
    let observer = &solver.level_observer;
    type Coarse = (Vec<PointResult>, Vec<f64>, Option<Fields>);
    // One point, its self-consistency iterations started with the slope
    // `hint` (`Secant`); returns the result and the slope it measured.
    let refine_point = |(k, p, item): (usize, f64, std::result::Result<Coarse, String>),
                        hint: Option<f64>| {
        let refine = |(r, saved, fields): Coarse| -> Result<(PointResult, Option<f64>)> {
            let mut base = PathSolver::with_bodies(case, geometry.clone(), bodies.clone())?;
            base.model.restore(&saved);
            base.last_pressure = p;
            base.capture = capture;
            base.self_consistency_slope = hint;
            base.observe_levels(observer.clone());
            // The coarse fields stand unless a finer mesh is solved.
            base.fields = fields;
            let r = base.adapt(p, &fluxes, r, target)?.pop().expect("one flux");
            let slope = base.self_consistency_slope;
            Ok((write_point(series, case, k, r, base.take_fields())?, slope))
        };
        match item.and_then(|c| refine(c).map_err(|e| e.to_string())) {
            Ok(r) => r,
            Err(m) => (PointResult::failed(case, p, m), hint),
        }
    };
    // In 3D one pressure at a time: a refined level's factorization takes
    // the machine's cores by itself, and its memory (7-22 GB on the fourth
    // level of the egg box) would not fit twice. Its self-consistency
    // iterations then start with the previous pressure's slope, as on a fixed
    // mesh; in 2D, where the points run in parallel, without one (their
    // results do not depend on the order they run in).
    Ok(if case.sample.dimension >= 3 {
        let mut hint = None;
        coarse
            .into_iter()
            .map(|c| {
                let (r, slope) = refine_point(c, hint);
                hint = slope;
                progress(&r);
                r
            })
            .collect()
    } else {
        let out: Vec<PointResult> = coarse
            .into_par_iter()
            .map(|c| refine_point(c, None).0)
            .collect();
        out.iter().for_each(progress);
        out
    })
}

/// The mechanical phase's end states along the self-consistency iterations at
/// one pressure and flux, each with the slave's temperature offset `ϑ̄c` it
/// was solved at (the plain solve's at 0 first). The slave's properties
/// change with `ϑ̄c`, and so does the mechanical phase's solution: the next
/// evaluation starts from the secant extrapolation of two end states to its
/// input, a continuation predictor in `ϑ̄c`, instead of from the last state
/// (solved at another temperature). The two are the latest state and the
/// latest converged one before it: the one-increment predictor's state
/// ([`PREDICTOR_INCREMENTS`]) is the tangent's first-order change from the
/// plain state, so the evaluation after it starts from the tangent
/// predictor at its own input; later ones extrapolate converged states only
/// (the predictor's own nonlinear remainder, extrapolated, cost the egg box
/// at 9.5 kPa two more Newton increments; docs/3d.md, "Stop 94").
struct MechanicalStarts {
    /// `(ϑ̄c, state, converged)`: the latest converged state before the
    /// latest, and the latest.
    states: Vec<(f64, Vec<f64>, bool)>,
}

impl MechanicalStarts {
    /// The largest extrapolation factor used; beyond it the evaluation
    /// starts from the last state (a secant step far past the last two
    /// inputs, where the linear change is not to be trusted).
    const MAX_FACTOR: f64 = 2.0;

    /// The smallest step between the two states' inputs, relative to the
    /// inputs, that is extrapolated. Closer states differ by their algebraic
    /// error more than by the step, and their extrapolation would move a
    /// converged state by that noise: at a self-consistency tolerance of
    /// 1e-10 (2D, 100 kPa) the map's output then scattered by 1e-9 relative
    /// and the iterations took 12 evaluations instead of 6 (test
    /// `self_consistency_ends_on_a_converged_mechanical_phase`).
    const MIN_RELATIVE_STEP: f64 = 1e-6;

    fn new(plain: Vec<f64>) -> Self {
        MechanicalStarts {
            states: vec![(0.0, plain, true)],
        }
    }

    /// Records the end state at `input`, `converged` or a predictor's
    /// (replacing one at the same input: the predictor's state solved to
    /// convergence).
    fn push(&mut self, input: f64, state: Vec<f64>, converged: bool) {
        match self.states.last_mut() {
            Some(last) if last.0 == input => *last = (input, state, converged),
            _ => self.states.push((input, state, converged)),
        }
        if let Some(latest) = self.states.pop() {
            let anchor = self.states.drain(..).rev().find(|s| s.2);
            self.states.extend(anchor);
            self.states.push(latest);
        }
    }

    /// The start at `input` and its extrapolation factor `t`:
    /// `s_b + t (s_b − s_a)`, `t = (ϑ − ϑ_b)/(ϑ_b − ϑ_a)`, with `b` the latest
    /// state and `a` the latest converged one before it; none at the latest
    /// state's own input, before two states, for states closer than
    /// [`Self::MIN_RELATIVE_STEP`], or beyond [`Self::MAX_FACTOR`].
    fn start(&self, input: f64) -> Option<(f64, Vec<f64>)> {
        let [(xa, sa, true), (xb, sb, _)] = self.states.as_slice() else {
            return None;
        };
        let t = (input - xb) / (xb - xa);
        let close = (xb - xa).abs() <= Self::MIN_RELATIVE_STEP * xa.abs().max(xb.abs());
        if input == *xb || close || !t.is_finite() || t.abs() > Self::MAX_FACTOR {
            return None;
        }
        let start = sb.iter().zip(sa).map(|(b, a)| b + t * (b - a)).collect();
        Some((t, start))
    }
}

/// The next input of the self-consistency iterations `ϑ ← F(ϑ)` (Sect. 3.3)
/// by [`Acceleration`]: the secant through the last two pairs `(ϑ, F(ϑ))`
/// gives the fixed point of the line `F(ϑk) + F'(ϑ − ϑk)`,
/// `ϑ = F(ϑk) + F'/(1 − F') (F(ϑk) − ϑk)`. The first pair is `(0, F(0))`
/// (the plain two-phase jump); the first input extrapolates from it with the
/// slope of the previous pressure's iterations where there is one (`F'`
/// changes slowly along a path: −0.09, −0.06, −0.02 at 1, 10, 100 kPa on the
/// Sect. 5.7 sample), and is `F(0)` otherwise.
#[derive(Clone, Copy, Debug)]
struct Secant {
    acceleration: Acceleration,
    /// The previous pair `(ϑ, F(ϑ))`.
    previous: (f64, f64),
    /// The last secant slope `F'` (or the hint it started from).
    slope: Option<f64>,
}

impl Secant {
    /// The largest secant slope `|F'|` that is extrapolated: the mechanical
    /// and thermal phases make `F` a strong contraction (above); a slope near
    /// 1 is noise or a change of the active set, and the plain update is safer
    /// there.
    const MAX_SLOPE: f64 = 0.9;

    fn new(acceleration: Acceleration, plain_jump: f64, slope_hint: Option<f64>) -> Self {
        Secant {
            acceleration,
            previous: (0.0, plain_jump),
            slope: slope_hint.filter(|s| s.is_finite() && s.abs() <= Self::MAX_SLOPE),
        }
    }

    /// The fixed point of the line through `(ϑk, F(ϑk))` of slope `slope`.
    fn extrapolate(input: f64, output: f64, slope: f64) -> f64 {
        output + slope / (1.0 - slope) * (output - input)
    }

    /// The first input after the plain two-phase jump `F(0)`.
    fn first_input(&self) -> f64 {
        let (x0, f0) = self.previous;
        match (self.acceleration, self.slope) {
            (Acceleration::Secant, Some(s)) => Self::extrapolate(x0, f0, s),
            _ => f0,
        }
    }

    /// The slope `F'` of the chord from the previous pair to `(input,
    /// output = F(input))`, where it is one that is extrapolated (finite,
    /// `|F'| ≤` [`Self::MAX_SLOPE`]).
    fn chord_slope(&self, input: f64, output: f64) -> Option<f64> {
        let (x0, f0) = self.previous;
        if input == x0 {
            return None;
        }
        let slope = (output - f0) / (input - x0);
        (slope.is_finite() && slope.abs() <= Self::MAX_SLOPE).then_some(slope)
    }

    /// Where `F` steps across its fixed point between the previous input and
    /// `input`: the fixed point's residual `F(ϑ) − ϑ` changes sign between
    /// them, and the chord is steeper than a contraction's
    /// (`|F'| >` [`Self::MAX_SLOPE`], or `F` changed at the same input). Then
    /// the fixed point (or, where `F` jumps over the diagonal, the step that
    /// takes its place) lies between the two inputs, and
    /// `max(|F(ϑ) − ϑ_prev|, |F(ϑ) − ϑ|)` bounds the output's distance to it:
    /// the bound returned. The constraint model's nodal supports make such
    /// steps (a node entering the active set adds its support to the
    /// conducting area): 0.3–0.4 % of the jump on 3D levels
    /// (docs/adaptivity.md). A smooth contraction never gives one.
    fn step_bound(&self, input: f64, output: f64) -> Option<f64> {
        let (x0, f0) = self.previous;
        let straddles = (f0 - x0) * (output - input) < 0.0;
        // A chord at the same input is not finite: steep as well.
        let steep = !((output - f0) / (input - x0)).abs().le(&Self::MAX_SLOPE);
        (straddles && steep).then(|| (output - x0).abs().max((output - input).abs()))
    }

    /// The input after `output = F(input)`.
    fn next(&mut self, input: f64, output: f64) -> f64 {
        let chord = self.chord_slope(input, output);
        self.previous = (input, output);
        let Some(slope) = chord.filter(|_| self.acceleration != Acceleration::None) else {
            return output;
        };
        self.slope = Some(slope);
        Self::extrapolate(input, output, slope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level is solved again (from the configuration solved, then from
    /// rest) where its solve ended on a residual
    /// that is not finite, whether Newton failed at a constant load or the
    /// load stepping cut back to its minimum, or where it stalled after
    /// shortening increments that led to such states; not where it stalled
    /// otherwise.
    #[test]
    fn only_an_unevaluable_state_is_solved_again_from_rest() {
        let newton = |reason: &str| Error::NewtonDiverged {
            step: 0,
            load_factor: 1.0,
            iterations: 1,
            reason: reason.into(),
        };
        let stalled = |last: Error| Error::LoadStepStalled {
            load_factor: 0.0,
            step_size: 3.8e-6,
            last: Box::new(last),
        };
        let stall = "no convergence; residuals mechanical 2.232e-7 > 1.950e-7";
        assert!(starts_unevaluable(&newton(NON_FINITE_RESIDUAL)));
        assert!(starts_unevaluable(&stalled(newton(NON_FINITE_RESIDUAL))));
        assert!(!starts_unevaluable(&newton(stall)));
        assert!(!starts_unevaluable(&stalled(newton(stall))));
        let shortened = format!("{NON_FINITE_RESIDUAL} met and increments halved 2×, then {stall}");
        assert!(starts_unevaluable(&newton(&shortened)));
        assert!(!starts_unevaluable(&Error::Geometry("x".into())));
    }

    /// Iterates `F` from `F(0)` with `secant` until `|F(ϑ) − ϑ| ≤ tol |F(ϑ)|`;
    /// returns the iterations (phases run after the first) and the last output.
    fn iterate(f: impl Fn(f64) -> f64, secant: Secant, tol: f64) -> (usize, f64) {
        let (k, output, _) = iterate_to_step(f, secant, tol, false).expect("no convergence");
        (k, output)
    }

    /// [`iterate`], also ending at a step of `F` across the fixed point where
    /// `steps` is set (as an adaptive level's iterations do; then with the
    /// step's bound). `None` where 50 iterations do not end.
    fn iterate_to_step(
        f: impl Fn(f64) -> f64,
        mut secant: Secant,
        tol: f64,
        steps: bool,
    ) -> Option<(usize, f64, Option<f64>)> {
        let mut input = secant.first_input();
        for k in 1..=50 {
            let output = f(input);
            if (output - input).abs() <= tol * output.abs() {
                return Some((k, output, None));
            }
            if let Some(bound) = secant.step_bound(input, output).filter(|_| steps) {
                return Some((k, output, Some(bound)));
            }
            input = secant.next(input, output);
        }
        None
    }

    /// A map that steps down across its fixed point (no fixed point: the
    /// nodal supports' stair-stepping can make one, docs/adaptivity.md) sends
    /// the secant iterations into a cycle of two; ending at the step, they
    /// stop within a few iterations with a bound on the output's distance to
    /// the step. Smooth contractions never see a step, and an up-step's
    /// bound covers a fixed point.
    #[test]
    fn a_step_of_f_across_the_fixed_point_ends_the_iterations_with_its_bound() {
        for at in [20.12, 20.14, 20.16, 20.18] {
            // Below the step the fixed point would be 22 / 1.09 = 20.183,
            // above it 21.92 / 1.09 = 20.110: both on the step's other side.
            let stepped = |x: f64| 22.0 - 0.09 * x - if x > at { 0.08 } else { 0.0 };
            for hint in [Some(-0.09), None] {
                let start = Secant::new(Acceleration::Secant, stepped(0.0), hint);
                assert!(iterate_to_step(stepped, start, 1e-6, false).is_none());
                let (k, output, bound) =
                    iterate_to_step(stepped, start, 1e-6, true).expect("ends at the step");
                let bound = bound.expect("a step");
                assert!(k <= 4, "step at {at}, hint {hint:?}: {k} iterations");
                assert!(
                    (output - at).abs() <= bound && bound <= 0.2,
                    "step at {at}: output {output}, bound {bound}"
                );
            }
        }
        // An up-step has a fixed point on one of its sides (here both).
        let up = |x: f64| 22.0 - 0.09 * x + if x > 20.2 { 0.08 } else { 0.0 };
        let fixed = [22.0 / 1.09, 22.08 / 1.09];
        let start = Secant::new(Acceleration::Secant, up(0.0), Some(-0.09));
        let (_, output, bound) = iterate_to_step(up, start, 1e-9, true).expect("ends");
        let distance = fixed
            .iter()
            .map(|x| (output - x).abs())
            .fold(f64::MAX, f64::min);
        assert!(
            distance <= bound.unwrap_or(1e-9 * output),
            "{output} {bound:?}"
        );
        // Smooth contractions end by their tolerance, never at a step.
        for smooth in [
            |x: f64| 22.0 - 0.09 * x,
            |x: f64| 3.5 / (1.0 + 0.01 * x) + 0.002 * x * x,
            |x: f64| 30.0 / (1.0 + 0.005 * x) - 0.1 * x,
        ] {
            for hint in [Some(-0.2), Some(0.0), None] {
                let start = Secant::new(Acceleration::Secant, smooth(0.0), hint);
                let (_, _, bound) = iterate_to_step(smooth, start, 1e-12, true).expect("ends");
                assert_eq!(bound, None);
            }
        }
    }

    /// Adaptive runs balance Newton's tolerance against the target error;
    /// fixed meshes, and a case's own looser tolerance, keep theirs.
    #[test]
    fn adaptive_runs_balance_the_newton_tolerance_against_the_target() {
        let text = "[surface.upper]\nkind = \"flat\"\n[surface.lower]\nkind = \"flat\"\n";
        let mut case = Case::from_toml(text, std::path::Path::new(".")).expect("a minimal case");
        assert_eq!(newton_settings(&case), case.solver.newton);
        case.discretization.target_error = Some(0.01);
        let s = newton_settings(&case);
        assert!((s.relative_tolerance - 1e-5).abs() < 1e-19, "{s:?}");
        assert_eq!(
            NewtonSettings {
                relative_tolerance: case.solver.newton.relative_tolerance,
                ..s
            },
            case.solver.newton
        );
        case.discretization.target_error = Some(1e-4);
        assert!((newton_settings(&case).relative_tolerance - 1e-7).abs() < 1e-21);
        case.solver.newton.relative_tolerance = 1e-4;
        assert_eq!(newton_settings(&case).relative_tolerance, 1e-4);
        // 3D: a share ten times larger (an increment costs seconds there).
        case.solver.newton.relative_tolerance = 1e-10;
        case.sample.dimension = 3;
        case.discretization.target_error = Some(0.01);
        assert!((newton_settings(&case).relative_tolerance - 1e-4).abs() < 1e-18);
    }

    /// The start of a self-consistency evaluation: exact for states linear in
    /// `ϑ̄c`, the predictor's state replaced once solved at the same input,
    /// none before two states, at the last input or far past the last two.
    #[test]
    fn mechanical_starts_extrapolate_the_last_two_end_states() {
        let state = |x: f64| vec![1.0 + 0.5 * x, -2.0 * x, 3.0];
        let mut starts = MechanicalStarts::new(state(0.0));
        assert!(starts.start(4.0).is_none());
        // The predictor's state at 10: the tangent's change from the plain one.
        starts.push(10.0, state(10.0), false);
        let (t, s) = starts.start(8.0).expect("two states");
        assert!((t + 0.2).abs() < 1e-15, "{t}");
        for (a, b) in s.iter().zip(state(8.0)) {
            assert!((a - b).abs() < 1e-12, "{s:?}");
        }
        // Solved to convergence at the same input: replaced, no new start.
        starts.push(10.0, state(10.0), true);
        assert_eq!(starts.states.len(), 2);
        assert!(starts.start(10.0).is_none());
        // A predictor's state is not extrapolated once converged ones follow:
        // the start at 9 comes from the states at 10 and 8.
        let mut starts = MechanicalStarts::new(state(0.0));
        starts.push(10.0, vec![7.0; 3], false);
        starts.push(8.0, state(8.0), true);
        assert_eq!(starts.states.len(), 2);
        assert_eq!(starts.states[0].0, 0.0);
        starts.push(6.0, state(6.0), true);
        assert_eq!(starts.states[0].0, 8.0);
        let (_, s) = starts.start(5.0).expect("two converged states");
        for (a, b) in s.iter().zip(state(5.0)) {
            assert!((a - b).abs() < 1e-12, "{s:?}");
        }
        // Within twice the last step, not beyond.
        assert!(starts.start(2.0).is_some());
        assert!(starts.start(1.5).is_none());
        // States closer than their algebraic error are not extrapolated.
        starts.push(6.0 + 1e-8, state(6.0), true);
        assert!(starts.start(6.0 - 1e-8).is_none());
    }

    /// The Sect. 5.7 sample (`tables/sinusoid_on_flat.toml`: fixed mesh,
    /// self-consistent).
    fn sect57_case() -> Case {
        Case::from_toml(
            include_str!("../../../tables/sinusoid_on_flat.toml"),
            std::path::Path::new("."),
        )
        .expect("the Sect. 5.7 case")
    }

    /// The active set that `TCGEN_TRACE` prints per Newton iterate
    /// (`NonlinearProblem::active_set`): the slave nodes in contact, counted
    /// and hashed; more of them, and another hash, at a higher pressure.
    #[test]
    fn the_traced_active_set_is_the_slave_nodes_in_contact() {
        let case = sect57_case();
        let mut solver = PathSolver::new(&case).expect("a solver");
        let mut sets = Vec::new();
        for p in [1.0e3, 1.0e5] {
            let r = solver.solve_pressure_fluxes(p, &[case.load.flux]);
            assert!(r.expect("solved")[0].converged);
            let c = solver.model.contact.as_ref().expect("a contact interface");
            let nodes = (0..c.n_slave()).filter(|&i| c.is_active(i)).count();
            let set = solver.model.active_set().expect("an active set");
            assert_eq!(set.0, nodes);
            assert!(
                nodes > 0 && nodes < c.n_slave(),
                "{nodes} of {}",
                c.n_slave()
            );
            // The same state, the same set.
            assert_eq!(solver.model.active_set(), Some(set));
            sets.push(set);
        }
        assert!(sets[1].0 > sets[0].0 && sets[1].1 != sets[0].1, "{sets:?}");
    }

    /// On the Sect. 5.7 sample (fixed mesh, self-consistent), the
    /// extrapolated starts take fewer Newton increments to the same jumps.
    #[test]
    fn extrapolated_starts_save_newton_increments() {
        let case = sect57_case();
        let run = |extrapolated: bool| -> (usize, Vec<f64>) {
            let mut solver = PathSolver::new(&case).expect("a solver");
            solver.extrapolated_starts = extrapolated;
            let mut newton = 0;
            let mut jumps = Vec::new();
            for &p in &case.load.pressures {
                let r = solver
                    .solve_pressure_fluxes(p, &[case.load.flux])
                    .expect("solved");
                assert!(r[0].converged && r[0].self_consistency_iterations >= 3);
                newton += r[0].newton_iterations;
                jumps.push(r[0].jump);
            }
            (newton, jumps)
        };
        let (with, jumps) = run(true);
        let (without, reference) = run(false);
        assert!(with < without, "{with} against {without} increments");
        for (a, b) in jumps.iter().zip(&reference) {
            assert!((a - b).abs() < 1e-6 * b, "{jumps:?} against {reference:?}");
        }
    }

    #[test]
    fn secant_update_reaches_the_fixed_point_in_fewer_iterations() {
        // A linear contraction: the secant is exact after one pair.
        let linear = |x: f64| 22.0 - 0.09 * x;
        let fixed = 22.0 / 1.09;
        let (k, x) = iterate(linear, Secant::new(Acceleration::Secant, 22.0, None), 1e-12);
        assert!(k <= 3 && (x - fixed).abs() < 1e-10 * fixed, "{k} {x}");
        let (k_plain, x_plain) =
            iterate(linear, Secant::new(Acceleration::None, 22.0, None), 1e-12);
        assert!(k_plain > 8 && (x_plain - fixed).abs() < 1e-10 * fixed);
        // With the right slope hint the first input is the fixed point.
        let s = Secant::new(Acceleration::Secant, 22.0, Some(-0.09));
        assert!((s.first_input() - fixed).abs() < 1e-12 * fixed);
        // A nonlinear one (the conductivity varies with the temperature).
        let curved = |x: f64| 3.5 / (1.0 + 0.01 * x) + 0.002 * x * x;
        let (k, x) = iterate(
            curved,
            Secant::new(Acceleration::Secant, curved(0.0), None),
            1e-10,
        );
        let (k_plain, x_plain) = iterate(
            curved,
            Secant::new(Acceleration::None, curved(0.0), None),
            1e-10,
        );
        assert!(
            k < k_plain && (x - x_plain).abs() < 1e-8 * x,
            "{k} {k_plain}"
        );
        // No extrapolation where F is not a contraction, nor with a wild hint.
        let mut steep = Secant::new(Acceleration::Secant, 1.0, Some(5.0));
        assert_eq!(steep.first_input(), 1.0);
        assert_eq!(steep.next(1.0, 3.0), 3.0);
    }

    /// The output's distance to the fixed point from the chord slope: exact
    /// (before its doubling) for a linear `F`, and a bound, doubled, on a
    /// curved one along the iterations from `F(0)`, of either sign of `F'`.
    #[test]
    fn the_output_distance_to_the_fixed_point_follows_the_chord() {
        let linear = |x: f64| 22.0 - 0.09 * x;
        let fixed = 22.0 / 1.09;
        let s = Secant::new(Acceleration::None, linear(0.0), None);
        let (x, fx) = (linear(0.0), linear(linear(0.0)));
        let slope = s.chord_slope(x, fx).expect("a contraction's chord");
        assert!((slope + 0.09).abs() < 1e-12, "{slope}");
        let estimate = 0.5 * fixed_point_output_error(slope, (fx - x).abs());
        assert!(((fx - fixed).abs() - estimate).abs() < 1e-12, "{estimate}");
        for curved in [
            |x: f64| 3.5 / (1.0 + 0.01 * x) + 0.002 * x * x,
            |x: f64| 30.0 / (1.0 + 0.005 * x) - 0.1 * x,
            |x: f64| 2.0 + 0.3 * x - 0.004 * x * x,
        ] {
            // The fixed point, by many plain iterations.
            let fixed = (0..2000).fold(curved(0.0), |x, _| curved(x));
            let mut secant = Secant::new(Acceleration::Secant, curved(0.0), None);
            let mut input = secant.first_input();
            for _ in 0..4 {
                let output = curved(input);
                let change = (output - input).abs();
                let slope = secant.chord_slope(input, output).expect("a contraction");
                let estimate = fixed_point_output_error(slope, change);
                let distance = (output - fixed).abs();
                assert!(
                    distance <= estimate + 1e-13 * fixed.abs(),
                    "F' {slope}: distance {distance} above the estimate {estimate}"
                );
                assert!(
                    estimate <= 6.0 * distance + 1e-12 * fixed.abs(),
                    "F' {slope}: estimate {estimate} far above the distance {distance}"
                );
                input = secant.next(input, output);
            }
        }
        // No chord through the same input, nor for a map that is no contraction.
        let s = Secant::new(Acceleration::Secant, 1.0, None);
        assert_eq!(s.chord_slope(0.0, 2.0), None);
        assert_eq!(s.chord_slope(1.0, 3.0), None);
    }
}
