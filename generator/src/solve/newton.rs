//! Newton's method with a consistent tangent, per-field convergence tests and
//! load stepping with adaptive cutback.

use serde::Serialize;

use crate::solve::golden::golden_section;
use crate::solve::linear::{
    FactorPrecision, Factorization, KRYLOV_MAX_ITERATIONS, KRYLOV_TOLERANCE, LinearSolver, Ordering,
};
use crate::{Error, Result};

/// A fill-reducing ordering computed apart from its problem
/// ([`NonlinearProblem::ordering_job`]).
pub type OrderingJob = Box<dyn FnOnce() -> Ordering + Send>;

/// A discrete nonlinear problem `R(x; λ) = 0` driven by a load factor `λ ∈ [0, 1]`
/// (`Send`: its tangent is assembled on a worker thread beside a symbolic analysis).
pub trait NonlinearProblem: Send {
    /// Number of unknowns.
    fn n_eq(&self) -> usize;
    /// Field class of every equation (indexes [`NonlinearProblem::field_names`]).
    fn eq_fields(&self) -> &[usize];
    /// Names of the field classes, for messages and histories.
    fn field_names(&self) -> &[&'static str];
    /// The sparsity pattern of the tangent. When it changes (e.g. a new
    /// contact coupling), [`NonlinearProblem::pattern_version`] must change too.
    fn pattern(&self) -> faer::sparse::SymbolicSparseColMatRef<'_, usize>;
    /// The pattern of [`NonlinearProblem::pattern`] to share rather than copy into the linear
    /// solver that factorizes it, where the problem holds it shared.
    fn shared_pattern(&self) -> Option<std::sync::Arc<faer::sparse::SymbolicSparseColMat<usize>>> {
        None
    }
    /// Identifies the current pattern; the solver re-analyses when it changes.
    fn pattern_version(&self) -> u64 {
        0
    }
    /// What the problem holds, for the trace of a symbolic analysis (`TCGEN_TRACE`).
    fn storage_report(&self) -> Option<String> {
        None
    }
    /// Identifies the current equations (which unknown each is, in order): while it stays, the
    /// factors of an earlier pattern may precondition the tangent of a new one. By default the
    /// pattern version (no reuse across patterns).
    fn numbering_version(&self) -> u64 {
        self.pattern_version()
    }
    /// Which factorization suits the tangent (queried when the pattern changes).
    fn factorization(&self) -> Factorization {
        Factorization::Lu
    }
    /// The fill-reducing ordering for `kind` (queried once per analysed pattern).
    fn ordering(&self, _kind: &Factorization) -> Ordering {
        Ordering::Default
    }
    /// [`NonlinearProblem::ordering`] as a job that owns what it reads, with
    /// [`NonlinearProblem::shared_pattern`]: a new pattern's symbolic analysis
    /// then runs beside the assembly of its first tangent ([`Newton`]). `None`
    /// (the default): the analysis comes first.
    fn ordering_job(&self, _kind: &Factorization) -> Option<OrderingJob> {
        None
    }
    /// Updates state-dependent data (e.g. contact projections) before the
    /// pattern is queried and the system assembled; may change the pattern.
    fn prepare(&mut self) -> Result<()> {
        Ok(())
    }
    /// Applies the prescribed values and loads of load factor `λ`.
    fn set_load(&mut self, load_factor: f64);
    /// Whether [`NonlinearProblem::set_load`] changes the problem. Where it does not (a
    /// re-solve at the same loads and prescribed values from a state carried over to a new
    /// mesh), a smaller load step poses the same problem again, and [`Newton::solve_path`]
    /// does not cut back.
    fn load_varies(&self) -> bool {
        true
    }
    /// Residual (and tangent values when `values` is given) at the current state.
    /// Newton calls it for the residual alone first, and again with `values`
    /// when an iteration follows: a repeat at the same state must give the same
    /// residual.
    fn assemble(&mut self, values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()>;
    /// External load per field class at the current load factor, as a reference
    /// magnitude for the relative residual test (Euclidean norms).
    fn load_norms(&self) -> Vec<f64>;
    /// `x ← x + dx` (with `dx` in equation space).
    fn update(&mut self, dx: &[f64]);
    /// Called once per Newton iteration after the update (e.g. active sets).
    fn after_update(&mut self) {}
    /// A copy of the state, to return to after a failed load step.
    fn save(&self) -> Vec<f64>;
    /// Restores a state from [`NonlinearProblem::save`].
    fn restore(&mut self, state: &[f64]);
    /// Called after a failed load step's state is restored ([`NonlinearProblem::restore`]):
    /// drops what the failed iterates added to the problem that the restored state does not
    /// need (the contact's coupling band).
    fn after_cutback(&mut self) {}
    /// Frees what the problem rebuilds by itself at its next assembly, while
    /// a factorization of at least [`FACTOR_BYTES_RELEASING_CACHES`] holds the
    /// memory (the 3D models' bulk quadrature).
    fn release_caches_for_factorization(&mut self) {}
    /// Leaves the contact's curvature out of the tangent (`false`) or puts it
    /// back (`true`): the gaps' second variations weighted by the pressures,
    /// which under pressures of the order of `E` can make the tangent
    /// indefinite ([`crate::contact::ContactInterface::set_curvature`]). The
    /// residual does not change. Returns whether the tangent holds such terms;
    /// `false` without contact.
    ///
    /// At a constant load, [`Newton`] takes a solve's first increment again
    /// from the initial state with the tangent without them where its end
    /// cannot be evaluated ([`NON_FINITE_RESIDUAL`]), before any halving
    /// (`UNEVALUABLE_HALVINGS`), then goes on with the curvature. On a steep
    /// height map (docs/3d.md,
    /// "Stop 103") the spots of an adaptive level carry pressures of the
    /// order of `E`, the curvature makes the displacement block indefinite
    /// there, and the first increment from the carried-over state, almost all
    /// along one saddle mode, moved the faces 2.4 cell widths (24 μm on 7 μm
    /// tall bodies): no halving to 1/32 evaluated, and the level was solved
    /// again from the configuration solved (125.5 s). Taken again without
    /// the curvature, it converged from the carried-over state (68.6 s), to
    /// the same jump within 3e-7. Until stop 107 only where no halving
    /// evaluated: on the same map's second level at 30 kPa (205 700
    /// unknowns) the first increment evaluated at 1/32, the second at 1/16,
    /// and the level was solved again from the configuration solved
    /// (1 724 s); taken again at once, it converges from the carried-over
    /// state in 7 iterations (402 s; docs/3d.md, "Stop 107").
    /// Later increments are not taken again: where they met such states the
    /// solves went on without progress, and a level that falls back to the
    /// configuration solved or to rest sooner took less time.
    fn set_contact_curvature(&mut self, _on: bool) -> bool {
        false
    }
    /// The discrete part of the prepared state (the contact's active set): the nodes in it
    /// and a hash of which they are; `None` without one. `TCGEN_TRACE` prints it per
    /// iterate. States within the residual tolerance may differ by a node or two at a
    /// spot's edge, which moved the 3D egg box's self-consistent jump by 0.1–0.15 % at
    /// 6.25 and 11.51 kPa (docs/3d.md, "Stop 96").
    fn active_set(&self) -> Option<(usize, u64)> {
        None
    }
}

/// Wall time (s) of the parts of Newton iterations, summed over them (`tcgen bench`
/// reports it per phase; `TCGEN_TRACE` prints it per iteration).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IterationTimes {
    /// The problem's preparation (the contact's projections, a new pattern's structure)
    /// and the solver's selection for its pattern.
    pub preparation: f64,
    /// Residual assemblies.
    pub residuals: f64,
    /// Tangent assemblies (a new pattern's ordering and symbolic analysis run beside them).
    pub tangents: f64,
    /// Linear solves: GMRES on kept factors, numeric factorizations, triangular solves (and
    /// the new analysis of a pattern whose kept factors went stale).
    pub linear_solves: f64,
    /// Of which numeric Cholesky and LDLᵀ factorizations (LU's are counted in
    /// `linear_solves` only, faer not exposing their factors' size).
    pub factorizations: f64,
    /// Floating-point operations of those factorizations
    /// ([`crate::solve::linear::cholesky_factor_flops`]): their rate compares machines and
    /// days where seconds alone do not.
    pub factorization_flops: f64,
}

impl IterationTimes {
    /// Adds `other`'s times to these.
    pub fn add(&mut self, other: &IterationTimes) {
        self.add_scaled(other, 1.0);
    }

    /// These times less `earlier`'s (the part of a run after `earlier` was read).
    pub fn since(&self, earlier: &IterationTimes) -> IterationTimes {
        let mut part = *self;
        part.add_scaled(earlier, -1.0);
        part
    }

    /// Adds `scale` times `other`, field by field.
    fn add_scaled(&mut self, other: &IterationTimes, scale: f64) {
        self.preparation += scale * other.preparation;
        self.residuals += scale * other.residuals;
        self.tangents += scale * other.tangents;
        self.linear_solves += scale * other.linear_solves;
        self.factorizations += scale * other.factorizations;
        self.factorization_flops += scale * other.factorization_flops;
    }
}

/// Settings of Newton's method (tolerances in the solver's scaled units).
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct NewtonSettings {
    /// Maximum iterations per load step.
    pub max_iterations: usize,
    /// Relative residual tolerance, per field class.
    pub relative_tolerance: f64,
    /// Absolute residual tolerance, per field class (scaled units).
    pub absolute_tolerance: f64,
    /// A residual growing by this factor over the first is a divergence.
    pub divergence_factor: f64,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            max_iterations: 30,
            relative_tolerance: 1e-10,
            absolute_tolerance: 1e-12,
            divergence_factor: 1e8,
        }
    }
}

/// Load stepping with adaptive cutback.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LoadStepping {
    /// First load increment (fraction of the total load).
    pub initial_step: f64,
    /// Smallest increment before giving up.
    pub min_step: f64,
    /// Largest increment.
    pub max_step: f64,
    /// Growth factor after an easy step (fewer than `easy_iterations`).
    pub growth: f64,
    /// Iterations below which a step counts as easy.
    pub easy_iterations: usize,
    /// Cut factor after a failed step.
    pub cutback: f64,
}

impl Default for LoadStepping {
    fn default() -> Self {
        LoadStepping {
            initial_step: 1.0,
            min_step: 1e-5,
            max_step: 1.0,
            growth: 2.0,
            easy_iterations: 6,
            cutback: 0.25,
        }
    }
}

/// One Newton iteration: residual norm of every field class before the update.
#[derive(Clone, Debug, Serialize)]
pub struct IterationRecord {
    /// Residual norms per field class.
    pub residuals: Vec<f64>,
    /// Why the increment was solved by LU instead of the symmetric factorization, if it was
    /// ([`LinearSolver::fallback`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_fallback: Option<String>,
}

/// One converged load step.
#[derive(Clone, Debug, Serialize)]
pub struct StepRecord {
    /// Load factor reached.
    pub load_factor: f64,
    /// Iterations (the last entry is the converged residual).
    pub iterations: Vec<IterationRecord>,
}

/// The history of a solve.
#[derive(Clone, Debug, Default, Serialize)]
pub struct SolveHistory {
    /// Converged steps.
    pub steps: Vec<StepRecord>,
    /// Failed attempts (cut back).
    pub cutbacks: usize,
}

impl SolveHistory {
    /// Iterations of the converged steps whose increment fell back to LU.
    pub fn linear_fallbacks(&self) -> usize {
        self.steps
            .iter()
            .flat_map(|s| &s.iterations)
            .filter(|i| i.linear_fallback.is_some())
            .count()
    }

    /// Total Newton iterations over all converged steps.
    pub fn total_iterations(&self) -> usize {
        self.steps
            .iter()
            .map(|s| s.iterations.len().saturating_sub(1))
            .sum()
    }
}

/// Newton's method with kept linear solvers: the symbolic analysis of a
/// pattern is reused while the pattern and the factorization kind do not
/// change, and when they come back (the phases of the two-phase framework
/// alternate between two patterns).
pub struct Newton {
    /// Iteration settings.
    pub settings: NewtonSettings,
    /// Load stepping settings.
    pub stepping: LoadStepping,
    /// The problem's pattern version the front solver was checked against.
    version: Option<u64>,
    /// Analysed solvers, most recently used first.
    solvers: Vec<KeptSolver>,
    /// The front solver was analysed for an earlier pattern of the current equations: its
    /// factors precondition GMRES until a factorization is needed, which analyses the current
    /// pattern first.
    stale_front: bool,
    /// Iterations whose symmetric factorization fell back to LU.
    linear_fallbacks: usize,
    /// Symbolic analyses performed.
    analyses: usize,
    /// Systems with at least this many unknowns try [`LinearSolver::solve_preconditioned`]
    /// before factorizing ([`KRYLOV_MIN_EQ`]).
    krylov_min_eq: usize,
    /// ... and factors with at least this many entries per equation ([`KRYLOV_MIN_FILL`]).
    krylov_min_fill: usize,
    /// Kept solvers of the phase of a new pattern at least this large are dropped before it
    /// is analysed ([`KEPT_SOLVER_BYTES`]).
    kept_solver_bytes: usize,
    /// Factorizations whose factor values take at least this many bytes free the problem's
    /// caches first ([`FACTOR_BYTES_RELEASING_CACHES`]).
    factor_bytes_releasing_caches: usize,
    /// Newton increments solved by a numeric factorization, and by preconditioned GMRES.
    factorizations: usize,
    krylov_solves: usize,
    /// GMRES iterations of those solves.
    krylov_iterations: usize,
    /// Wall time of the iterations' parts, and the factorizations' work.
    times: IterationTimes,
    /// Whether GMRES increments stop at the [`forcing_term`] (an inexact Newton method) or at
    /// [`KRYLOV_TOLERANCE`].
    inexact: bool,
    /// The factor precision of large systems ([`LARGE_FACTOR_PRECISION`]).
    large_factor_precision: FactorPrecision,
}

/// The reason of a Newton failure whose residual was not finite: an inverted element or
/// a contact search that found no closest point, i.e. a state the model cannot evaluate
/// (an adaptive level's carried-over state is then given up for a solve from rest,
/// `homogenize::path`). A failure after increments shortened for such states
/// (see `UNEVALUABLE_HALVINGS`) starts with it.
pub const NON_FINITE_RESIDUAL: &str = "non-finite residual";

/// Newton increments of systems with at least this many unknowns are first
/// solved by GMRES preconditioned by the last factorization of the same pattern
/// (a previous iteration's, or the same phase's in the previous self-consistent
/// iteration), or of an earlier pattern of the same equations (the mechanical
/// phase after its contact pattern changed with the active set,
/// [`NonlinearProblem::numbering_version`]), where their factor is also dense
/// enough ([`KRYLOV_MIN_FILL`], which keeps 2D on a factorization per
/// increment). Measured on the 3D egg box (p = 2, 31 085 mechanical unknowns):
/// a numeric factorization takes 16.5 s, a preconditioned GMRES iteration a
/// fraction of a second. Until stop 42 this was 20 000, and the adaptive
/// egg box's second levels (8 700–19 600 mechanical unknowns, 1 300–2 400
/// factor entries per equation) factorized every increment in double
/// precision: at 72 kPa six factorizations of 2.2–2.9 s; with GMRES first
/// (and [`crate::solve::linear::PARALLEL_FACTORIZATION_MIN_ENTRIES`]) three of
/// 0.9–1.1 s in single precision and three GMRES solves, the level's solves
/// 15.2 → 5.7 s and its jump the same to 1e-14 (docs/3d.md, "Stop 42").
pub const KRYLOV_MIN_EQ: usize = 5_000;

/// ... and whose symmetric factors hold at least this many entries per
/// equation ([`LinearSolver::factor_nnz`]; LU factors, whose size faer does
/// not expose, count as large): a deterministic proxy of how much a
/// factorization costs against a preconditioned iteration. The 3D egg box's
/// third level has 5 300 (165 M entries for 31 085 equations: factorization
/// 16.5 s, GMRES iteration 0.15–0.25 s); the uniform 128 × 64 mesh of the
/// 2D Sect. 5.7 sample has 260 (7.6 M for 29 327), where a factorization
/// (0.18 s) costs less than the 13–25 GMRES iterations an increment needs
/// (0.25–0.5 s): with GMRES tried there, its 100 kPa solve took 46 s against
/// 28 s.
pub const KRYLOV_MIN_FILL: usize = 1_000;

/// GMRES iterations tried at least before a Newton increment is refactorized
/// ([`krylov_budget`]).
pub const KRYLOV_ITERATIONS: usize = 25;

/// Factor entries per equation that buy one GMRES iteration before a Newton
/// increment is refactorized ([`krylov_budget`]): a factorization costs about
/// as many preconditioned iterations as the factor's entries per equation over
/// 60. Measured on the adaptive 3D egg boxes (single-precision factors, 2
/// cores): 16.5 s against 0.15–0.25 s at 5 300 entries per equation, 13 s
/// against 0.10 s at 8 100, 21 s against 0.17 s at 7 900, 50–58 s against
/// 0.30 s at 10 900. A failed attempt thus costs at most about one
/// factorization, and the increments that follow a change of the active set
/// need 59–69 iterations where the factorization is worth 135 (the small-strain
/// egg box at 0.3 p*, level 3: two of its four factorizations saved; level 4,
/// 130–150 iterations where it is worth 150–180: two of five).
pub const KRYLOV_FILL_PER_ITERATION: usize = 60;

/// The GMRES budget of an increment preconditioned by `solver`'s factors: its
/// factor entries per equation over [`KRYLOV_FILL_PER_ITERATION`], within
/// [`KRYLOV_ITERATIONS`] and [`KRYLOV_MAX_ITERATIONS`].
pub fn krylov_budget(solver: &LinearSolver) -> usize {
    let fill = solver
        .factor_nnz()
        .map_or(usize::MAX, |l| l / solver.n_eq().max(1));
    (fill / KRYLOV_FILL_PER_ITERATION).clamp(KRYLOV_ITERATIONS, KRYLOV_MAX_ITERATIONS)
}

/// The largest forcing term ([`forcing_term`]).
pub const FORCING_MAX: f64 = 1e-3;

/// The share of the reduction that quadratic convergence predicts which the
/// linear solve may leave ([`forcing_term`]).
pub const FORCING_SAFETY: f64 = 0.1;

/// The relative tolerance of a Newton increment's GMRES solve on earlier factors
/// (an inexact Newton method; Eisenstat & Walker 1996, their second choice):
/// `FORCING_SAFETY (‖r_k‖/‖r_{k−1}‖)²`, a tenth of the residual reduction that
/// quadratic convergence predicts from the last two residuals (the linearized
/// residual it leaves is then a tenth of the next nonlinear one), at most
/// [`FORCING_MAX`]; never below what leaves the linearized residual at a tenth
/// of the convergence test's smallest tolerance `tolerance` (of the field
/// classes with equations, [`smallest_tolerance`]: no linear solve is tighter
/// than the Newton iteration needs), nor below [`KRYLOV_TOLERANCE`].
/// A solve's first increment, without an earlier residual, is solved to that
/// floor: a problem that one increment solves (the thermal phase on a kept
/// mechanical state) then takes one, as with an exact solve. Until stop 44
/// every such solve went to [`KRYLOV_TOLERANCE`] (1e-11): the 3D egg box's
/// level-4 increments at 72 kPa took 15–21 GMRES iterations where the
/// residual they leave needed 6–11 (docs/3d.md, "Stop 44").
pub fn forcing_term(previous: Option<f64>, current: f64, tolerance: f64) -> f64 {
    if !(current.is_finite() && current > 0.0) {
        return KRYLOV_TOLERANCE;
    }
    let predicted = match previous {
        Some(p) if p > 0.0 && p.is_finite() => {
            (FORCING_SAFETY * (current / p).powi(2)).min(FORCING_MAX)
        }
        _ => 0.0,
    };
    let sufficient = 0.1 * tolerance / current;
    // `predicted` is finite, so the maximum is not NaN.
    predicted
        .max(sufficient)
        .clamp(KRYLOV_TOLERANCE, FORCING_MAX)
}

/// The smallest convergence tolerance (`targets`, one per field class) of
/// the field classes that have equations (`eq_fields`), for
/// [`forcing_term`]. A class without equations in this problem (the
/// temperatures and thermal multipliers of a mechanical phase, the
/// displacements of a thermal one) keeps a zero residual and the absolute
/// floor (`absolute_tolerance`, 1e-12) as its tolerance, which no linear
/// solve needs to reach: until stop 53 it set every first increment's
/// forcing term, and the 3D egg box's self-consistency re-solves on level 4
/// took 23 and 28 GMRES iterations (to 2e-10 and 7e-9), where 17 and 21 now
/// bring the mechanical residual below its own tolerance (docs/3d.md,
/// "Stop 53").
/// Infinite without equations.
pub fn smallest_tolerance(targets: &[f64], eq_fields: &[usize]) -> f64 {
    let present = field_classes(eq_fields);
    targets
        .iter()
        .enumerate()
        .filter(|&(f, _)| present & (1u64 << f.min(63)) != 0)
        .map(|(_, &t)| t)
        .fold(f64::INFINITY, f64::min)
}

/// The precision of the factors of large systems (those that try GMRES first,
/// [`KRYLOV_MIN_EQ`] and [`KRYLOV_MIN_FILL`]); the others are factorized in
/// double precision.
pub const LARGE_FACTOR_PRECISION: FactorPrecision = FactorPrecision::Single;

/// How many analysed patterns a [`Newton`] keeps.
const KEPT_SOLVERS: usize = 4;

/// A kept solver at least this large ([`LinearSolver::storage_bytes`]) is
/// dropped before a new pattern of the same field classes (the same phase) is
/// analysed: a new contact pattern seldom comes back in large systems, and two
/// factors of the 3D refined levels do not fit in memory together (the egg
/// box's fourth level, 580 M factor entries per mechanical pattern: the
/// self-consistent iterations kept three and ran out of 24 GB). The other
/// phase's solver is kept (its pattern returns in the next self-consistent
/// iteration), and so are small solvers (every 2D micro-sample's).
pub const KEPT_SOLVER_BYTES: usize = 256 << 20;

/// A numeric factorization whose factor values take at least this many bytes
/// first frees the problem's rebuildable caches
/// ([`NonlinearProblem::release_caches_for_factorization`]): the factor and
/// its workspace are the largest allocation of a solve, and the caches come
/// back at the next assembly. On the 3D egg box's fourth level (150 k
/// unknowns, a 2.5 GB single-precision factor) the bulk quadrature holds
/// 1.15 GB and takes about a second to rebuild against a factorization of
/// 30 s (docs/3d.md, "Stop 47"); the third levels' factors (below 1 GB)
/// keep their caches.
pub const FACTOR_BYTES_RELEASING_CACHES: usize = 1 << 30;

/// A tangent whose values take at least this many bytes first returns the
/// allocator's free pages to the system
/// ([`super::resources::return_free_memory`]): its values are a new block,
/// and what the iterations before freed in small blocks (contact point
/// states, the bulk quadrature, work arrays) stays resident beside it
/// otherwise. On the 3D egg box's fourth level at 132 kPa (a 580 MB
/// tangent) each call returned 0.2–0.7 GB in 10–60 ms, and the point's peak
/// fell 7.48 → 6.94 GB (docs/3d.md, "Stop 47"); 2D tangents stay below it.
pub const TANGENT_BYTES_RETURNING_FREE_MEMORY: usize = 128 << 20;

/// An analysed solver kept by [`Newton`].
struct KeptSolver {
    /// The field classes of its problem's equations (a bit per class: the phase it belongs to).
    classes: u64,
    /// The problem's [`NonlinearProblem::numbering_version`] when it was analysed.
    numbering: u64,
    solver: LinearSolver,
    /// GMRES iterations of the last increment its current factors preconditioned (0 after a
    /// factorization).
    last_krylov: usize,
}

/// The field classes present in `eq_fields`, a bit per class.
fn field_classes(eq_fields: &[usize]) -> u64 {
    eq_fields.iter().fold(0, |m, &f| m | 1u64 << f.min(63))
}

impl Newton {
    /// A solver with the given settings.
    pub fn new(settings: NewtonSettings, stepping: LoadStepping) -> Self {
        Newton {
            settings,
            stepping,
            version: None,
            solvers: Vec::new(),
            stale_front: false,
            linear_fallbacks: 0,
            analyses: 0,
            krylov_min_eq: KRYLOV_MIN_EQ,
            krylov_min_fill: KRYLOV_MIN_FILL,
            kept_solver_bytes: KEPT_SOLVER_BYTES,
            factor_bytes_releasing_caches: FACTOR_BYTES_RELEASING_CACHES,
            factorizations: 0,
            krylov_solves: 0,
            krylov_iterations: 0,
            times: IterationTimes::default(),
            inexact: true,
            large_factor_precision: LARGE_FACTOR_PRECISION,
        }
    }

    /// Sets the factor precision of large systems ([`LARGE_FACTOR_PRECISION`] by default).
    pub fn set_large_factor_precision(&mut self, precision: FactorPrecision) {
        self.large_factor_precision = precision;
    }

    /// Whether `solver`'s system of `n` equations is large: its increments first try
    /// preconditioned GMRES, and its factor has the large systems' precision.
    fn is_large(&self, n: usize, solver: &LinearSolver) -> bool {
        n >= self.krylov_min_eq
            && solver
                .factor_nnz()
                .is_none_or(|l| l >= self.krylov_min_fill.saturating_mul(n))
    }

    /// Sets the size from which increments are first solved by preconditioned GMRES
    /// ([`KRYLOV_MIN_EQ`] by default; `usize::MAX`: always factorize).
    pub fn set_krylov_min_eq(&mut self, n: usize) {
        self.krylov_min_eq = n;
    }

    /// Sets the bytes of factor values from which a factorization frees the problem's caches
    /// first ([`FACTOR_BYTES_RELEASING_CACHES`] by default; 0: before every factorization).
    pub fn set_factor_bytes_releasing_caches(&mut self, bytes: usize) {
        self.factor_bytes_releasing_caches = bytes;
    }

    /// Sets the factor entries per equation from which increments are first solved by
    /// preconditioned GMRES ([`KRYLOV_MIN_FILL`] by default).
    pub fn set_krylov_min_fill(&mut self, entries: usize) {
        self.krylov_min_fill = entries;
    }

    /// Sets the storage from which a kept solver is dropped before a new pattern of its
    /// phase is analysed ([`KEPT_SOLVER_BYTES`] by default).
    pub fn set_kept_solver_bytes(&mut self, bytes: usize) {
        self.kept_solver_bytes = bytes;
    }

    /// Whether GMRES increments stop at the [`forcing_term`] (the default) or are solved to
    /// [`KRYLOV_TOLERANCE`].
    pub fn set_inexact(&mut self, inexact: bool) {
        self.inexact = inexact;
    }

    /// GMRES iterations of the Newton increments solved so far by preconditioned GMRES.
    pub fn krylov_iterations(&self) -> usize {
        self.krylov_iterations
    }

    /// Newton increments solved so far by a numeric factorization, and by GMRES
    /// preconditioned by an earlier one.
    pub fn linear_solves(&self) -> (usize, usize) {
        (self.factorizations, self.krylov_solves)
    }

    /// Wall time of the iterations' parts so far, and the factorizations' work
    /// (`tcgen bench`).
    pub fn iteration_times(&self) -> IterationTimes {
        self.times
    }

    /// Frees the kept solvers (their factors and workspaces): the next
    /// iteration analyses its pattern anew. For a problem set aside while a
    /// larger one is solved (the previous level of adaptive refinement).
    pub fn release_solvers(&mut self) {
        self.solvers = Vec::new();
        self.version = None;
        self.stale_front = false;
    }

    /// Symbolic analyses (ordering and factor structure) performed so far:
    /// one per new pattern and factorization kind.
    pub fn analyses(&self) -> usize {
        self.analyses
    }

    /// Iterations so far (failed load steps included) whose symmetric
    /// factorization fell back to LU.
    pub fn linear_fallbacks(&self) -> usize {
        self.linear_fallbacks
    }

    fn field_norms<P: NonlinearProblem + ?Sized>(p: &P, r: &[f64]) -> Vec<f64> {
        let mut s = vec![0.0; p.field_names().len()];
        for (v, &f) in r.iter().zip(p.eq_fields()) {
            s[f] += v * v;
        }
        s.iter().map(|x| x.sqrt()).collect()
    }

    /// Puts in front the solver for the problem's current pattern: a kept one analysed for it;
    /// else a factorized large one of the same phase and equations, whose factors then
    /// precondition the new pattern's GMRES ([`Self::stale_front`]). Returns `true` where
    /// neither is kept: the pattern is to be analysed ([`Self::analyse_beside`]).
    fn select_solver<P: NonlinearProblem + ?Sized>(&mut self, p: &P, trace: bool) -> Result<bool> {
        let kind = p.factorization();
        self.stale_front = false;
        if let Some(i) = self
            .solvers
            .iter()
            .position(|k| *k.solver.kind() == kind && k.solver.analyses(p.pattern()))
        {
            let kept = self.solvers.remove(i);
            self.solvers.insert(0, kept);
            return Ok(false);
        }
        let (classes, numbering, n) = (
            field_classes(p.eq_fields()),
            p.numbering_version(),
            p.n_eq(),
        );
        if let Some(i) = self.solvers.iter().position(|k| {
            k.classes == classes
                && k.numbering == numbering
                && *k.solver.kind() == kind
                && k.solver.n_eq() == n
                && k.solver.is_factorized()
                && self.is_large(n, &k.solver)
        }) {
            let kept = self.solvers.remove(i);
            self.solvers.insert(0, kept);
            self.stale_front = true;
            if trace {
                eprintln!(
                    "  new pattern of the same equations: the previous factors precondition GMRES"
                );
            }
            return Ok(false);
        }
        Ok(true)
    }

    /// Drops the large kept solvers of the problem's phase ([`KEPT_SOLVER_BYTES`]) before a
    /// new analysis of its pattern.
    fn release_kept_solvers<P: NonlinearProblem + ?Sized>(&mut self, p: &P) {
        let classes = field_classes(p.eq_fields());
        self.stale_front = false;
        self.solvers
            .retain(|k| k.classes != classes || k.solver.storage_bytes() < self.kept_solver_bytes);
    }

    /// [`Self::analyse`] beside `assemble` (the first tangent of the new pattern): the ordering
    /// and symbolic factorization run on one worker while the assembly takes the other
    /// ([`NonlinearProblem::ordering_job`]; in place before it where the problem gives no
    /// job). Both are serial in part (METIS, faer's symbolic Cholesky): on the 3D egg box's
    /// fourth level at 72 kPa they took 5.1 s before its 4.8 s residual and tangent.
    fn analyse_beside<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &mut P,
        trace: bool,
        assemble: impl FnOnce(&mut P) -> Result<()> + Send,
    ) -> Result<()> {
        let kind = p.factorization();
        let (Some(job), Some(pattern)) = (p.ordering_job(&kind), p.shared_pattern()) else {
            self.analyse(p, trace)?;
            return assemble(p);
        };
        self.release_kept_solvers(p);
        let clock = std::time::Instant::now();
        let (analysed, assembled) = rayon::join(
            move || {
                let ordering = job();
                let ordered = clock.elapsed().as_secs_f64();
                LinearSolver::with_pattern(pattern, kind, ordering)
                    .map(|s| (s, (ordered, clock.elapsed().as_secs_f64() - ordered)))
            },
            || assemble(p),
        );
        assembled?;
        let (solver, seconds) = analysed?;
        if trace {
            eprintln!("  analysis beside the tangent's assembly:");
        }
        self.insert_analysed(p, solver, trace, seconds);
        Ok(())
    }

    /// Analyses the problem's current pattern into a new front solver, after dropping the
    /// large kept solvers of its phase ([`KEPT_SOLVER_BYTES`]).
    fn analyse<P: NonlinearProblem + ?Sized>(&mut self, p: &P, trace: bool) -> Result<()> {
        let clock = std::time::Instant::now();
        let kind = p.factorization();
        self.release_kept_solvers(p);
        let ordering = p.ordering(&kind);
        let ordered = clock.elapsed().as_secs_f64();
        let solver = match p.shared_pattern() {
            Some(pattern) => LinearSolver::with_pattern(pattern, kind, ordering)?,
            None => LinearSolver::new(p.pattern(), kind, ordering)?,
        };
        let symbolic = clock.elapsed().as_secs_f64() - ordered;
        self.insert_analysed(p, solver, trace, (ordered, symbolic));
        Ok(())
    }

    /// Puts a new analysis of the problem's pattern in front (its precision set; traced with
    /// the seconds its ordering and symbolic factorization took).
    fn insert_analysed<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &P,
        mut solver: LinearSolver,
        trace: bool,
        (ordered, symbolic): (f64, f64),
    ) {
        let n = p.n_eq();
        let classes = field_classes(p.eq_fields());
        if self.is_large(n, &solver) {
            solver.set_precision(self.large_factor_precision);
        }
        if trace {
            eprintln!("  analysis: ordering {ordered:.2} s, symbolic {symbolic:.2} s");
            eprintln!(
                "  analysis: {}, {} equations, {} entries, factor {:?} entries ({} flop) in {:?} precision ({} MB resident)",
                match solver.kind() {
                    Factorization::Lu => "LU",
                    Factorization::Cholesky => "Cholesky",
                    Factorization::Ldlt { .. } => "LDLT",
                },
                solver.n_eq(),
                p.pattern().row_idx().len(),
                solver.factor_nnz(),
                solver
                    .factor_flops()
                    .map_or("n/a".into(), |f| format!("{f:.3e}")),
                solver.precision(),
                super::resources::process_memory("VmRSS:").unwrap_or(0) >> 20
            );
            let kept: usize = self.solvers.iter().map(|k| k.solver.storage_bytes()).sum();
            eprintln!(
                "  analysis: this solver {} MB, the kept ones {} MB; {}",
                solver.storage_bytes() >> 20,
                kept >> 20,
                p.storage_report().unwrap_or_default()
            );
        }
        self.analyses += 1;
        self.solvers.insert(
            0,
            KeptSolver {
                classes,
                numbering: p.numbering_version(),
                solver,
                last_krylov: 0,
            },
        );
        self.solvers.truncate(KEPT_SOLVERS);
    }

    /// Newton iterations at the current load factor. Returns the iteration records.
    pub fn iterate<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &mut P,
        step: usize,
        load_factor: f64,
    ) -> Result<Vec<IterationRecord>> {
        self.iterate_up_to(p, step, load_factor, None)
            .map(|(history, _)| history)
    }

    /// At most `increments` Newton increments at the problem's full load
    /// (load factor 1 of its path), fewer where the residual converges
    /// first; an increment left short is not an error. A predictor whose
    /// state only steers an outer iteration (the first self-consistency
    /// iteration's mechanical phase, `homogenize::path`). Returns the
    /// increments made.
    pub fn increments<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &mut P,
        increments: usize,
    ) -> Result<usize> {
        p.set_load(1.0);
        let (history, converged) = self.iterate_up_to(p, 0, 1.0, Some(increments))?;
        Ok(history.len() - usize::from(converged))
    }

    /// [`Newton::iterate`], stopped after `increments` increments if given;
    /// also returns whether the residual converged. The problem leaves with
    /// its contact's curvature in the tangent, however the iterations end.
    fn iterate_up_to<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &mut P,
        step: usize,
        load_factor: f64,
        increments: Option<usize>,
    ) -> Result<(Vec<IterationRecord>, bool)> {
        let result = self.iterations(p, step, load_factor, increments);
        p.set_contact_curvature(true);
        result
    }

    /// The iterations of [`Newton::iterate_up_to`].
    fn iterations<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &mut P,
        step: usize,
        load_factor: f64,
        increments: Option<usize>,
    ) -> Result<(Vec<IterationRecord>, bool)> {
        let n = p.n_eq();
        let mut r = vec![0.0; n];
        let mut history = Vec::new();
        let mut first: Option<Vec<f64>> = None;
        let mut targets: Option<Vec<f64>> = None;
        let mut previous_total: Option<f64> = None;
        let mut cycle_searches = 0;
        // Whether an increment that raised the residual has been searched
        // along ([`RISE_SEARCH_FACTOR`]; once per solve), and whether the
        // damped iterations follow from it (not from a cycle of two).
        let (mut rise_searched, mut rise_damped) = (false, false);
        let names: Vec<&str> = p.field_names().to_vec();
        // Increments shortened so far ([`UNEVALUABLE_HALVINGS`]): a solve that
        // then fails says so first, as one that starts from a state it cannot
        // evaluate (`homogenize::path` solves such a level again from the
        // configuration solved, then from rest).
        let shortened = std::cell::Cell::new(0usize);
        // Increments taken again without the contact's curvature
        // ([`NonlinearProblem::set_contact_curvature`]).
        let retaken = std::cell::Cell::new(0usize);
        let fail = |iterations: usize, reason: String| Error::NewtonDiverged {
            step,
            load_factor,
            iterations,
            reason: match (retaken.get(), shortened.get()) {
                _ if reason == NON_FINITE_RESIDUAL => reason,
                (0, 0) => reason,
                (0, k) => {
                    format!("{NON_FINITE_RESIDUAL} met and increments halved {k}×, then {reason}")
                }
                (j, 0) => format!(
                    "{NON_FINITE_RESIDUAL} met, increments taken again without the contact's curvature {j}×, then {reason}"
                ),
                (j, k) => format!(
                    "{NON_FINITE_RESIDUAL} met, increments taken again without the contact's curvature {j}× and halved {k}×, then {reason}"
                ),
            },
        };
        // A failed linear solve fails the iteration, but memory that is not
        // there stays an error of its own (no cut-back helps).
        let linear_failure = |iterations: usize, e: Error| match e {
            Error::OutOfMemory { .. } => e,
            e => fail(iterations, e.to_string()),
        };
        let trace = std::env::var_os("TCGEN_TRACE").is_some();
        // The last increment taken, from the state it was taken at: where the
        // state it leads to cannot be evaluated at a constant load, it is
        // shortened (where the load varies, load stepping cuts back instead).
        let shortens = !p.load_varies();
        let mut taken: Option<TakenIncrement> = None;
        // The smallest residual merit so far and its iteration.
        let mut smallest = (f64::INFINITY, 0);
        // Whether the next increment is taken without the contact's curvature.
        let mut flat_next = false;
        // The merit of the iterate the last increment was taken from.
        let mut previous_merit = f64::INFINITY;
        for it in 0..=self.settings.max_iterations {
            if increments.is_some_and(|m| it >= m) {
                return Ok((history, false));
            }
            let clock = std::time::Instant::now();
            let (analysis, version, prepared, assembled, norms) = loop {
                p.prepare()?;
                let version = p.pattern_version();
                // A new pattern without a kept solver is analysed beside its
                // first tangent's assembly (none where the residual converges);
                // until then the front solver is not this pattern's.
                let analysis = self.version != Some(version) && self.select_solver(p, trace)?;
                if !analysis {
                    self.version = Some(version);
                }
                let prepared = clock.elapsed().as_secs_f64();
                // The residual first: the tangent is assembled only if the
                // iteration goes on (the last iteration of every solve only checks
                // convergence, and in 3D the tangent costs several residuals).
                p.assemble(None, &mut r)?;
                let assembled = clock.elapsed().as_secs_f64();
                let norms = Self::field_norms(p, &r);
                if norms.iter().all(|v| v.is_finite()) {
                    break (analysis, version, prepared, assembled, norms);
                }
                // A solve's first increment whose end cannot be evaluated is
                // taken again from the initial state with a tangent without
                // the contact's curvature, before any halving (where the
                // problem has such terms); the later increments, the retaken
                // one among them, are halved ([`UNEVALUABLE_HALVINGS`]).
                if taken.as_ref().is_some_and(|t| t.first) && p.set_contact_curvature(false) {
                    let t = taken.take().expect("a first increment");
                    p.restore(&t.from);
                    p.after_update();
                    retaken.set(retaken.get() + 1);
                    flat_next = true;
                    if trace {
                        eprintln!(
                            "  step {step} λ={load_factor:.4} it {it}: {NON_FINITE_RESIDUAL}; the increment taken again without the contact's curvature"
                        );
                    }
                    continue;
                }
                match taken.as_mut().filter(|t| t.halvings < UNEVALUABLE_HALVINGS) {
                    Some(t) => {
                        t.halve(p);
                        shortened.set(shortened.get() + 1);
                        if trace {
                            eprintln!(
                                "  step {step} λ={load_factor:.4} it {it}: {NON_FINITE_RESIDUAL}; the increment shortened to {}",
                                0.5f64.powi(t.halvings as i32)
                            );
                        }
                    }
                    None => return Err(fail(it, NON_FINITE_RESIDUAL.into())),
                }
            };
            history.push(IterationRecord {
                residuals: norms.clone(),
                linear_fallback: None,
            });
            if trace {
                let rss = super::resources::process_memory("VmRSS:").unwrap_or(0);
                eprintln!(
                    "  step {step} λ={load_factor:.4} it {it}: {norms:?} ({} MB resident){}",
                    rss >> 20,
                    p.active_set().map_or(String::new(), |(n, h)| format!(
                        " active {n} #{:08x}",
                        h & 0xffff_ffff
                    ))
                );
            }
            let reference = first.get_or_insert_with(|| {
                let loads = p.load_norms();
                norms.iter().zip(&loads).map(|(a, b)| a.max(*b)).collect()
            });
            // Each field class's convergence tolerance.
            let targets = targets.get_or_insert_with(|| {
                let s = &self.settings;
                reference
                    .iter()
                    .map(|r0| s.absolute_tolerance.max(s.relative_tolerance * r0))
                    .collect()
            });
            let converged = norms.iter().zip(targets.iter()).all(|(v, t)| v <= t);
            self.times.preparation += prepared;
            self.times.residuals += assembled - prepared;
            if converged {
                return Ok((history, true));
            }
            // A cycle of two iterates near convergence: the root sits at a
            // kink of the semi-smooth residual, and this iteration's increment
            // is searched along for a smaller residual, and so is every
            // iteration's after it (damped); after CYCLE_LINE_SEARCHES cycles,
            // or a search that finds no smaller residual, or a cycle far from
            // convergence (left to load stepping's cut-back), the iterations
            // end.
            let merit = residual_merit(&norms, targets);
            // An increment at a constant load whose end raises the merit
            // [`RISE_SEARCH_FACTOR`]-fold above the iterate it was taken from
            // (after the solve's first, from more than a decade above the
            // tolerance) is searched along from that iterate instead, and
            // the later iterations are damped, as after a cycle of two:
            // semi-smooth iterates that overshoot into another active set
            // wander among such sets (a steep height map's refined level,
            // docs/3d.md, "Stop 105").
            if let Some(t) = taken.as_ref().filter(|t| !t.first)
                && !rise_searched
                && cycle_searches == 0
                && previous_merit > CYCLE_SEARCH_MERIT
                && merit > RISE_SEARCH_FACTOR * previous_merit
            {
                let dx = t.taken_step();
                let from = t.from.clone();
                p.restore(&from);
                p.after_update();
                let (s, found) = cycle_line_search(p, &dx, targets, None)?;
                if trace {
                    eprintln!(
                        "  step {step} λ={load_factor:.4} it {it}: the residual rose {:.1}-fold to {merit:.3e} of its tolerance; line search from {previous_merit:.3e}: step {s:.4}, residual {found:.3e}",
                        merit / previous_merit
                    );
                }
                if found >= previous_merit {
                    return Err(fail(
                        it,
                        format!(
                            "the residual rose {:.1}-fold over an increment, and no smaller one along it; residuals {}",
                            merit / previous_merit,
                            residual_detail(&names, &norms, targets)
                        ),
                    ));
                }
                let mut scaled = vec![0.0; dx.len()];
                step_from(p, &from, &dx, s, &mut scaled);
                taken = Some(TakenIncrement {
                    from,
                    increment: scaled,
                    halvings: 0,
                    first: false,
                });
                cycle_searches = 1;
                (rise_searched, rise_damped) = (true, true);
                previous_merit = found;
                continue;
            }
            previous_merit = merit;
            // A solve that shortened increments ends where its residual has not
            // come below its smallest for SHORTENED_STAGNATION iterations.
            if merit < smallest.0 {
                smallest = (merit, it);
            }
            // So does one that took its first increment again.
            if shortened.get() + retaken.get() > 0 && it - smallest.1 >= SHORTENED_STAGNATION {
                return Err(fail(
                    it,
                    format!(
                        "no progress: the smallest residual, {:.3e} of its tolerance, at iteration {}",
                        smallest.0, smallest.1
                    ),
                ));
            }
            let cycle_failure = |why: String, other: &[f64]| {
                format!(
                    "no convergence, the iterates in a cycle of two{why}; residuals {} (the other: {})",
                    residual_detail(&names, &norms, targets),
                    residual_detail(&names, other, &[]),
                )
            };
            // The merit to search from, where this iteration's increment is
            // searched: at a cycle, and after one on every iteration (damped
            // Newton: a step is taken only where it lowers the merit, the full
            // one first), for the full steps from the searched state return to
            // the cycle (the degree-1 egg box's self-consistent third level:
            // 1.5 of the tolerance after the search, then 2.3, 4.7, 5.4 and
            // the same cycle again; docs/3d.md, "Stop 76").
            let search = match residual_cycle(&history) {
                Some(_) if merit <= CYCLE_SEARCH_MERIT && cycle_searches < CYCLE_LINE_SEARCHES => {
                    cycle_searches += 1;
                    Some(merit)
                }
                Some(other) => {
                    let why = match cycle_searches {
                        0 => String::new(),
                        k => format!(" after {k} line searches along its increments"),
                    };
                    return Err(fail(it, cycle_failure(why, other)));
                }
                None if cycle_searches > 0 => Some(merit),
                None => None,
            };
            if it == self.settings.max_iterations {
                break;
            }
            let total: f64 = norms.iter().map(|v| v * v).sum::<f64>().sqrt();
            let total_ref: f64 = reference.iter().map(|v| v * v).sum::<f64>().sqrt();
            if total
                > self.settings.divergence_factor * total_ref.max(self.settings.absolute_tolerance)
            {
                return Err(fail(
                    it,
                    format!("residual grew to {total:.3e} from {total_ref:.3e}"),
                ));
            }
            let nnz = p.pattern().row_idx().len();
            if nnz * size_of::<f64>() >= TANGENT_BYTES_RETURNING_FREE_MEMORY {
                super::resources::return_free_memory();
            }
            let mut values = vec![0.0; nnz];
            if analysis {
                self.analyse_beside(p, trace, |p: &mut P| p.assemble(Some(&mut values), &mut r))?;
                self.version = Some(version);
            } else {
                p.assemble(Some(&mut values), &mut r)?;
            }
            let tangent = clock.elapsed().as_secs_f64();
            self.times.tangents += tangent - assembled;
            let (front, last_krylov) = (&self.solvers[0].solver, self.solvers[0].last_krylov);
            let large = self.is_large(n, front);
            r.iter_mut().for_each(|v| *v = -*v);
            // Large systems first try GMRES preconditioned by the factors of an earlier
            // tangent of this pattern, or of an earlier pattern of these equations; a numeric
            // factorization (of this pattern, analysed first if it is new) follows where it
            // does not converge within the budget.
            // Factors that needed more than half the budget for the last increment have gone
            // stale (the tangent moves away from theirs as the active set changes): the
            // next increment would likely need more, so it is factorized at once.
            let budget = krylov_budget(front);
            let tried = large && front.is_factorized() && 2 * last_krylov <= budget;
            let forcing = match self.inexact {
                true => forcing_term(
                    previous_total,
                    total,
                    smallest_tolerance(targets, p.eq_fields()),
                ),
                false => KRYLOV_TOLERANCE,
            };
            previous_total = Some(total);
            let krylov = match tried {
                true => front
                    .solve_preconditioned_on(p.pattern(), &values, &mut r, budget, forcing)
                    .map_err(|e| linear_failure(it, e))?,
                false => None,
            };
            if krylov.is_none() && self.stale_front {
                self.analyse(p, trace)?;
            }
            let solver = &mut self.solvers[0].solver;
            if krylov.is_none() {
                if solver.factor_value_bytes() >= self.factor_bytes_releasing_caches {
                    p.release_caches_for_factorization();
                }
                let started = std::time::Instant::now();
                solver
                    .factorize_owned(std::mem::take(&mut values))
                    .map_err(|e| linear_failure(it, e))?;
                if let Some(flops) = solver.factor_flops() {
                    self.times.factorizations += started.elapsed().as_secs_f64();
                    self.times.factorization_flops += flops;
                }
                solver
                    .solve_in_place(&mut r)
                    .map_err(|e| linear_failure(it, e))?;
                // A large system's later increments are GMRES on these factors with
                // their own tangent, or a new factorization: its matrix is not needed.
                if large {
                    solver.release_matrix();
                }
                self.factorizations += 1;
            } else {
                self.krylov_solves += 1;
                self.krylov_iterations += krylov.unwrap_or(0);
            }
            self.times.linear_solves += clock.elapsed().as_secs_f64() - tangent;
            if trace {
                eprintln!(
                    "  step {step} it {it}: prepare {prepared:.2} s, residual {:.2} s, tangent {:.2} s, {} {:.2} s",
                    assembled - prepared,
                    tangent - assembled,
                    match krylov {
                        Some(k) => format!("GMRES ({k} iterations to {forcing:.0e})"),
                        None if tried => format!("GMRES not within {budget}, factorize and solve"),
                        None if large && last_krylov > 0 => {
                            format!(
                                "factors stale after {last_krylov} GMRES iterations, factorize and solve"
                            )
                        }
                        None => "factorize and solve".into(),
                    },
                    clock.elapsed().as_secs_f64() - tangent
                );
            }
            if let Some(reason) = solver.fallback().filter(|_| krylov.is_none()) {
                self.linear_fallbacks += 1;
                if trace {
                    eprintln!("  step {step} λ={load_factor:.4} it {it}: solved by LU: {reason}");
                }
                let record = history.last_mut().expect("pushed above");
                record.linear_fallback = Some(reason.to_string());
            }
            self.solvers[0].last_krylov = krylov.unwrap_or(0);
            if r.iter().any(|v| !v.is_finite()) {
                return Err(fail(it, "non-finite increment".into()));
            }
            if let Some(merit) = search {
                let cycle = residual_cycle(&history);
                let damped = cycle.is_none().then_some(merit);
                let (t, found) = cycle_line_search(p, &r, targets, damped)?;
                if trace {
                    eprintln!(
                        "  step {step} λ={load_factor:.4} it {it}: {}; line search: step {t:.4}, residual {found:.3e} of its tolerance (from {merit:.3e})",
                        if cycle.is_some() {
                            "a cycle of two"
                        } else {
                            "damped"
                        }
                    );
                }
                if found < merit {
                    r.iter_mut().for_each(|v| *v *= t);
                } else if cycle.is_none() && rise_damped {
                    // Damped after a rise, no smaller residual along this
                    // increment (a kink of the semi-smooth residual): the
                    // full increment is taken, and the iterations go on
                    // undamped.
                    (rise_damped, cycle_searches) = (false, 0);
                } else {
                    let why = " and no smaller residual along the increment".to_string();
                    return Err(fail(
                        it,
                        match cycle {
                            Some(other) => cycle_failure(why, other),
                            None => format!(
                                "no convergence after a cycle of two{why}; residuals {}",
                                residual_detail(&names, &norms, targets)
                            ),
                        },
                    ));
                }
            }
            if std::mem::take(&mut flat_next) {
                p.set_contact_curvature(true);
            }
            taken = shortens.then(|| TakenIncrement {
                from: p.save(),
                increment: r.clone(),
                halvings: 0,
                first: it == 0,
            });
            p.update(&r);
            p.after_update();
        }
        let last = history
            .last()
            .map(|h| h.residuals.clone())
            .unwrap_or_default();
        let targets = targets.unwrap_or_default();
        Err(fail(
            self.settings.max_iterations,
            format!(
                "no convergence; residuals {}",
                residual_detail(&names, &last, &targets)
            ),
        ))
    }

    /// Drives the load factor from 0 to 1 with adaptive steps; on a failed
    /// step restores the last converged state and cuts the step back.
    pub fn solve<P: NonlinearProblem + ?Sized>(&mut self, p: &mut P) -> Result<SolveHistory> {
        self.solve_path(p, 0.0, 1.0)
    }

    /// Like [`Newton::solve`], from load factor `from` to `to`. A problem whose
    /// load does not vary ([`NonlinearProblem::load_varies`]) fails with its first
    /// failure: a cut-back step would pose the same problem from the same state,
    /// and fail the same way (the re-solve of the adaptive egg box's third level
    /// at degree 1 repeated its 30 iterations nine times, to the same residuals
    /// within 1e-12, before the step fell below `min_step`).
    pub fn solve_path<P: NonlinearProblem + ?Sized>(
        &mut self,
        p: &mut P,
        from: f64,
        to: f64,
    ) -> Result<SolveHistory> {
        let mut hist = SolveHistory::default();
        let mut lf = from;
        let span = to - from;
        let mut dl = (self.stepping.initial_step * span).min(span);
        let mut saved = p.save();
        let mut step = 0;
        while lf < to - 1e-14 * span.abs().max(1.0) {
            let target = if lf + dl > to - 1e-12 * span {
                to
            } else {
                lf + dl
            };
            p.set_load(target);
            match self.iterate(p, step, target) {
                Ok(iters) => {
                    let easy = iters.len() <= self.stepping.easy_iterations;
                    hist.steps.push(StepRecord {
                        load_factor: target,
                        iterations: iters,
                    });
                    lf = target;
                    saved = p.save();
                    step += 1;
                    if easy {
                        dl = (dl * self.stepping.growth).min(self.stepping.max_step * span);
                    }
                }
                Err(e @ Error::OutOfMemory { .. }) => return Err(e),
                Err(e) if !p.load_varies() => {
                    if std::env::var_os("TCGEN_TRACE").is_some() {
                        eprintln!("  at a constant load, no cut back: {e}");
                    }
                    return Err(e);
                }
                Err(e) => {
                    if std::env::var_os("TCGEN_TRACE").is_some() {
                        eprintln!("  cut back from λ={target:.4}: {e}");
                    }
                    hist.cutbacks += 1;
                    p.restore(&saved);
                    p.after_cutback();
                    p.set_load(lf);
                    dl *= self.stepping.cutback;
                    if dl < self.stepping.min_step * span {
                        return Err(Error::LoadStepStalled {
                            load_factor: lf,
                            step_size: dl / span,
                            last: Box::new(e),
                        });
                    }
                }
            }
        }
        Ok(hist)
    }
}

/// Relative agreement of the residuals (each field class) at which
/// Newton takes two iterates for the same state (its cycle test).
pub const CYCLE_TOLERANCE: f64 = 1.0e-6;

/// Whether the last four iterations' residuals repeat with a period of two (or
/// one), each field class within [`CYCLE_TOLERANCE`]: the iterates return to
/// the same states, and Newton's map would alternate between them until its
/// iterations run out (a semi-smooth residual whose root sits at a kink of the
/// contact's active set; the sharp dent of docs/adaptivity.md alternated
/// between 2.004e-7 and 5.390e-7 for 22 iterations against a tolerance of
/// 1.902e-7). Newton then searches along its increment
/// ([`cycle_line_search`]). Returns the residuals of the other iterate of the
/// cycle.
fn residual_cycle(history: &[IterationRecord]) -> Option<&[f64]> {
    let [a, b, c, d] = history.last_chunk::<4>()?;
    let same = |x: &IterationRecord, y: &IterationRecord| {
        x.residuals
            .iter()
            .zip(&y.residuals)
            .all(|(u, v)| (u - v).abs() <= CYCLE_TOLERANCE * u.abs().max(v.abs()))
    };
    (same(a, c) && same(b, d)).then_some(c.residuals.as_slice())
}

/// The factor by which an increment at a constant load may raise the
/// residual merit ([`residual_merit`]) above the iterate it was taken from
/// before it is searched along instead ([`cycle_line_search`]; once per
/// solve), and the later iterations are damped; not the solve's first
/// increment (where a new level's or input's active set settles), nor one
/// taken within [`CYCLE_SEARCH_MERIT`] of the tolerance (kinks of the
/// semi-smooth residual, left to the cycle's search). Where a damped
/// iteration then finds no smaller residual along its increment, the full
/// increment is taken and the iterations go on undamped. Measured
/// (docs/3d.md, "Stop 105"): a steep height map's first level at 30 kPa,
/// whose Newton from the carried-over state wandered among active sets of
/// 251–259 nodes at 45–630 times its tolerance (a 12.3-fold rise at its
/// eighth increment) until it gave up and the level was solved again from
/// rest (613 s), converges five iterations after the search, to the same
/// jump (104 s). On the egg box's benchmark path the rises of 2.1–4.4-fold
/// are at first increments; searching them and damping the rest took the
/// same time to the same jumps, while searching later rises wherever they
/// started, and failing where a damped iteration found nothing smaller,
/// failed a level that Newton converges (6.25 kPa's third, at 1.09 times
/// its tolerance).
const RISE_SEARCH_FACTOR: f64 = 2.0;

/// Line searches along a Newton increment that one solve may take where its
/// iterates cycle between two states ([`residual_cycle`]).
const CYCLE_LINE_SEARCHES: usize = 4;

/// Halvings of a Newton increment at a constant load whose end state cannot
/// be evaluated (its residual not finite: an element inverted, `det F ≤ 0`,
/// where the first increments from an adaptive level's carried-over state push
/// an overlap of the bodies out at once) before the iterations fail with
/// [`NON_FINITE_RESIDUAL`]: the increment is shortened to `1/2, 1/4, …, 1/32`
/// of itself, and the iterations go on from the first state that evaluates.
/// A solve's first increment is first taken again without the contact's
/// curvature ([`NonlinearProblem::set_contact_curvature`]), and that one is
/// halved should its end not evaluate either.
/// Only the path of the iterates changes, not what converges. Where the load
/// varies, load stepping's cut-back is the remedy (shortened increments at the
/// full load took about five times as long as the cut-back on the case mesh
/// of the measured surface of docs/adaptivity.md, "Stop 92". There, at
/// 20 kPa, adaptive levels whose carried-over states had failed in their
/// first increments and been solved again from rest converge with the
/// shortening, the point 3.4 times faster over three levels; at 5 kPa, where
/// fewer levels had fallen back, 1.03 times).
const UNEVALUABLE_HALVINGS: usize = 5;

/// Iterations without a new smallest residual ([`residual_merit`]) after
/// which a solve that has shortened increments ([`UNEVALUABLE_HALVINGS`])
/// ends, for the solve from the configuration solved or from rest that
/// follows (`homogenize::path`). On the measured surface of
/// docs/adaptivity.md, "Stop 92", the shortened solves traced at 20 kPa that
/// converged went at most 3 iterations without one; on its dented profile ("A narrow
/// asperity") those that did not wandered at up to 70 times their smallest
/// residual until their iterations ran out (30).
const SHORTENED_STAGNATION: usize = 5;

/// A Newton increment as taken ([`UNEVALUABLE_HALVINGS`]): the state it was
/// taken from ([`NonlinearProblem::save`]), the full increment, and how many
/// times the step along it has been halved.
struct TakenIncrement {
    from: Vec<f64>,
    increment: Vec<f64>,
    halvings: usize,
    /// Whether it is the solve's first increment, from its initial state.
    first: bool,
}

impl TakenIncrement {
    /// The step taken: the increment, shortened by its halvings.
    fn taken_step(&self) -> Vec<f64> {
        let t = 0.5f64.powi(self.halvings as i32);
        self.increment.iter().map(|d| t * d).collect()
    }

    /// Takes half of the last step along the increment instead, from the
    /// same state.
    fn halve<P: NonlinearProblem + ?Sized>(&mut self, p: &mut P) {
        self.halvings += 1;
        let mut step = vec![0.0; self.increment.len()];
        let t = 0.5f64.powi(self.halvings as i32);
        step_from(p, &self.from, &self.increment, t, &mut step);
    }
}

/// Moves `p` to the saved state `from` plus `t · dx` (`step` receives the
/// scaled increment): a shortened Newton step ([`TakenIncrement::halve`],
/// [`cycle_line_search`]).
fn step_from<P: NonlinearProblem + ?Sized>(
    p: &mut P,
    from: &[f64],
    dx: &[f64],
    t: f64,
    step: &mut [f64],
) {
    p.restore(from);
    step.iter_mut().zip(dx).for_each(|(s, d)| *s = t * d);
    p.update(step);
    p.after_update();
}

/// The largest [`residual_merit`] at which a cycle of two is searched along
/// ([`cycle_line_search`]): a cycle within a decade of its tolerance. Farther
/// from convergence the active set is still changing and a cut-back of the
/// load step is the cheaper remedy: the sharp dent of docs/adaptivity.md on
/// its 64 × 32 mesh at 20 kPa cycled at 4e2 to 3e4 of its tolerance, and
/// searching there took 547 Newton iterations to the same result as 303
/// without.
const CYCLE_SEARCH_MERIT: f64 = 10.0;

/// Golden sections of [`cycle_line_search`]'s bracket (each one residual).
const GOLDEN_SECTIONS: usize = 8;

/// The largest ratio of a field class's residual to its tolerance (converged
/// at most 1; infinite where a residual is not finite).
fn residual_merit(residuals: &[f64], targets: &[f64]) -> f64 {
    residuals
        .iter()
        .zip(targets)
        .map(|(r, t)| if r.is_finite() { r / t } else { f64::INFINITY })
        .fold(0.0, f64::max)
}

/// Searches the increment `dx` from `p`'s state for the step `t ∈ (0, 1)`
/// of the smallest [`residual_merit`], and returns `(t, merit)` with `p`
/// back in its state. Where Newton's iterates cycle between two states the
/// residual is semi-smooth with its root at a kink of the contact's active
/// set (a node that becomes active or inactive, with the pressure and the gap
/// both near zero there): along the increment it falls until the kink and
/// rises beyond (the sharp dent of docs/adaptivity.md: from 1.11 of its
/// tolerance to 0.90 at `t ≈ 0.2`, then to 3.9 at `t = 1`), and both full
/// steps overshoot it. Tries `t = 2^−1 … 2^−6`, ending at a converged merit
/// (at most 1), then narrows the bracket around the best by golden sections.
/// `damped`: the merit of the damped iterations after a cycle, where the full
/// step `t = 1` is tried first and taken if it lowers it.
fn cycle_line_search<P: NonlinearProblem + ?Sized>(
    p: &mut P,
    dx: &[f64],
    targets: &[f64],
    damped: Option<f64>,
) -> Result<(f64, f64)> {
    let saved = p.save();
    let mut step = vec![0.0; dx.len()];
    let mut residual = vec![0.0; dx.len()];
    let mut merit_at = |p: &mut P, t: f64| -> Result<f64> {
        step_from(p, &saved, dx, t, &mut step);
        // A state that cannot be evaluated (the contact search refusing it)
        // is not a step to take; memory that is not there stays an error.
        match p.prepare().and_then(|_| p.assemble(None, &mut residual)) {
            Ok(()) => Ok(residual_merit(&Newton::field_norms(p, &residual), targets)),
            Err(e @ Error::OutOfMemory { .. }) => Err(e),
            Err(_) => Ok(f64::INFINITY),
        }
    };
    let mut best = (0.0, f64::INFINITY);
    if let Some(current) = damped {
        let m = merit_at(p, 1.0)?;
        if m < current {
            p.restore(&saved);
            return Ok((1.0, m));
        }
        best = (1.0, m);
    }
    for k in 1..=6 {
        let t = 0.5f64.powi(k);
        let m = merit_at(p, t)?;
        if m < best.1 {
            best = (t, m);
        }
        if m <= 1.0 {
            break;
        }
    }
    if best.1 > 1.0 && best.1.is_finite() {
        // Golden sections on [t/2, 2t] around the best dyadic step.
        let bracket = (0.5 * best.0, (2.0 * best.0).min(1.0));
        let found = golden_section(|t| merit_at(p, t), bracket, GOLDEN_SECTIONS, |m| m <= 1.0)?;
        if found.best.1 < best.1 {
            best = found.best;
        }
    }
    p.restore(&saved);
    Ok(best)
}

/// Each field class's residual, with its tolerance where one of `targets` is
/// exceeded: `"mechanical 2.004e-7 > 1.902e-7, thermal 0.000e0"`.
fn residual_detail(names: &[&str], residuals: &[f64], targets: &[f64]) -> String {
    names
        .iter()
        .zip(residuals)
        .enumerate()
        .map(|(i, (n, v))| match targets.get(i) {
            Some(t) if v > t => format!("{n} {v:.3e} > {t:.3e}"),
            _ => format!("{n} {v:.3e}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

    /// `R(x) = A x − b` with a symmetric `A` whose LDLᵀ meets a zero pivot in
    /// any ordering (regularized).
    struct Indefinite {
        pattern: SymbolicSparseColMat<usize>,
        x: Vec<f64>,
    }

    const A: [[f64; 3]; 3] = [[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 3.0]];

    impl NonlinearProblem for Indefinite {
        fn n_eq(&self) -> usize {
            3
        }
        fn eq_fields(&self) -> &[usize] {
            &[0, 0, 0]
        }
        fn field_names(&self) -> &[&'static str] {
            &["x"]
        }
        fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
            self.pattern.as_ref()
        }
        fn factorization(&self) -> Factorization {
            Factorization::Ldlt {
                signs: vec![1, 1, 1],
            }
        }
        fn set_load(&mut self, _: f64) {}
        fn assemble(&mut self, values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()> {
            for (i, r) in residual.iter_mut().enumerate() {
                *r = (0..3).map(|j| A[i][j] * self.x[j]).sum::<f64>() - 1.0;
            }
            if let Some(v) = values {
                for j in 0..3 {
                    for i in 0..3 {
                        v[3 * j + i] = A[i][j];
                    }
                }
            }
            Ok(())
        }
        fn load_norms(&self) -> Vec<f64> {
            vec![3f64.sqrt()]
        }
        fn update(&mut self, dx: &[f64]) {
            self.x.iter_mut().zip(dx).for_each(|(x, d)| *x += d);
        }
        fn save(&self) -> Vec<f64> {
            self.x.clone()
        }
        fn restore(&mut self, state: &[f64]) {
            self.x.copy_from_slice(state);
        }
    }

    /// A regularized LDLᵀ is replaced by LU: Newton converges in one step to
    /// the exact solution, and the iteration records why.
    #[test]
    fn regularized_ldlt_increment_is_solved_by_lu() {
        let full = SymbolicSparseColMat::new_checked(
            3,
            3,
            vec![0, 3, 6, 9],
            None,
            vec![0, 1, 2, 0, 1, 2, 0, 1, 2],
        );
        let mut p = Indefinite {
            pattern: full,
            x: vec![0.0; 3],
        };
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        let history = newton.solve(&mut p).unwrap();
        assert_eq!(p.x, [1.0, 1.0, 1.0 / 3.0]);
        assert_eq!(history.total_iterations(), 1);
        assert_eq!(
            (history.linear_fallbacks(), newton.linear_fallbacks()),
            (1, 1)
        );
        let reason = history.steps[0].iterations[0].linear_fallback.as_ref();
        assert!(
            reason.is_some_and(|r| r.contains("regularized")),
            "{reason:?}"
        );
    }

    /// A problem of one unknown `x`: `residual(x, λ)` gives `(R, dR/dx)` at
    /// the load factor `λ`, which stays 1 where `constant`.
    struct Scalar {
        pattern: SymbolicSparseColMat<usize>,
        x: f64,
        load: f64,
        constant: bool,
        residual: fn(f64, f64) -> (f64, f64),
        /// The "contact curvature's" part of the slope, left out of the
        /// tangent while `curved` is off
        /// ([`NonlinearProblem::set_contact_curvature`]), and how often it was.
        curvature: Option<fn(f64) -> f64>,
        curved: bool,
        flat_tangents: usize,
    }

    impl Scalar {
        fn new(x: f64, constant: bool, residual: fn(f64, f64) -> (f64, f64)) -> Self {
            Scalar {
                pattern: SymbolicSparseColMat::new_checked(1, 1, vec![0, 1], None, vec![0]),
                x,
                load: 1.0,
                constant,
                residual,
                curvature: None,
                curved: true,
                flat_tangents: 0,
            }
        }

        fn with_curvature(self, curvature: fn(f64) -> f64) -> Self {
            Scalar {
                curvature: Some(curvature),
                ..self
            }
        }
    }

    impl NonlinearProblem for Scalar {
        fn n_eq(&self) -> usize {
            1
        }
        fn eq_fields(&self) -> &[usize] {
            &[0]
        }
        fn field_names(&self) -> &[&'static str] {
            &["x"]
        }
        fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
            self.pattern.as_ref()
        }
        fn factorization(&self) -> Factorization {
            Factorization::Lu
        }
        fn set_load(&mut self, load_factor: f64) {
            self.load = if self.constant { 1.0 } else { load_factor };
        }
        fn load_varies(&self) -> bool {
            !self.constant
        }
        fn assemble(&mut self, values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()> {
            let (r, slope) = (self.residual)(self.x, self.load);
            residual[0] = r;
            if let Some(v) = values {
                v[0] = match (self.curved, self.curvature) {
                    (false, Some(c)) => {
                        self.flat_tangents += 1;
                        slope - c(self.x)
                    }
                    _ => slope,
                };
            }
            Ok(())
        }
        fn load_norms(&self) -> Vec<f64> {
            vec![1.0]
        }
        fn update(&mut self, dx: &[f64]) {
            self.x += dx[0];
        }
        fn save(&self) -> Vec<f64> {
            vec![self.x]
        }
        fn restore(&mut self, state: &[f64]) {
            self.x = state[0];
        }
        fn set_contact_curvature(&mut self, on: bool) -> bool {
            self.curved = on;
            self.curvature.is_some()
        }
    }

    /// `R(x) = sign(x) √|x|`: Newton's map is `x ↦ −x`, a cycle of two
    /// iterates whose residuals are equal, with the root halfway.
    fn cusp(x: f64, _: f64) -> (f64, f64) {
        (x.signum() * x.abs().sqrt(), 0.5 / x.abs().sqrt())
    }

    /// `R(x) = sign(x) (1 + |x|)` (`sign(0) = 1`): Newton's map is
    /// `x ↦ −sign(x)`, and no state has a residual below 1.
    fn cusp_step(x: f64, _: f64) -> (f64, f64) {
        (x.signum() * (1.0 + x.abs()), 1.0)
    }

    /// `R(x) = ln x − λ ln 2` (root `2^λ`), not finite for `x ≤ 0`: from
    /// `x = 6` at `λ = 1` Newton's first increment, `−6 ln 3`, leaves the
    /// domain.
    fn logarithm(x: f64, load: f64) -> (f64, f64) {
        (x.ln() - load * 2f64.ln(), 1.0 / x)
    }

    /// `R(x) = 1 + sin(x)/2` for `x > 0` (no root; not finite for `x ≤ 0`):
    /// Newton's iterates wander, and from `x = 11` several of its increments
    /// leave the domain.
    fn wave(x: f64, _: f64) -> (f64, f64) {
        match x > 0.0 {
            true => (1.0 + 0.5 * x.sin(), 0.5 * x.cos()),
            false => (f64::NAN, f64::NAN),
        }
    }

    /// `R(x) = 10 x` for `|x| ≤ 1`, `10 + (x − 1)/10` beyond it on the
    /// positive side and `−10 + (x + 1)` on the negative (root 0): a stiff
    /// branch at the root between a soft one and a steeper one, semi-smooth
    /// as a contact node's residual across a change of its active set. From
    /// `x = −3` Newton's first increment lands on the soft branch at `x = 9`
    /// (residual 10.8 against 12), the second overshoots to `x = −99`
    /// (−108: a tenfold rise), and the third returns to 9: a cycle of two far
    /// from the root.
    fn overshoot(x: f64, _: f64) -> (f64, f64) {
        if x.abs() <= 1.0 {
            (10.0 * x, 10.0)
        } else if x > 0.0 {
            (10.0 + 0.1 * (x - 1.0), 0.1)
        } else {
            (-10.0 + (x + 1.0), 1.0)
        }
    }

    /// An increment at a constant load (after the solve's first, from an
    /// iterate more than [`CYCLE_SEARCH_MERIT`] above its tolerance) whose
    /// end raises the residual more than [`RISE_SEARCH_FACTOR`]-fold is
    /// searched along instead, and the damped iterations after it converge
    /// where Newton's cycle; where the load varies (load stepping cuts
    /// back), or the rise starts near the tolerance, the iterations fail as
    /// before.
    #[test]
    fn a_rise_of_the_residual_at_a_constant_load_is_searched_along() {
        let settings = NewtonSettings {
            relative_tolerance: 1e-10,
            ..NewtonSettings::default()
        };
        let mut p = Scalar::new(-3.0, true, overshoot);
        let mut newton = Newton::new(settings.clone(), LoadStepping::default());
        p.set_load(1.0);
        let history = newton.iterate(&mut p, 0, 1.0).unwrap();
        assert!(p.x.abs() < 1e-9, "{}", p.x);
        // −3, 9, −99 (searched along from 9), then near the root and on it.
        assert!(history.len() <= 6, "{} iterations", history.len());
        // Where the load varies, and where the rise starts within a decade
        // of the tolerance (0.1 of the first residual, 12: 10.8 at `x = 9`
        // is 9 times it), Newton cycles as before.
        let near = NewtonSettings {
            relative_tolerance: 0.1,
            ..settings.clone()
        };
        for (constant, settings) in [(false, settings), (true, near)] {
            let mut p = Scalar::new(-3.0, constant, overshoot);
            let mut newton = Newton::new(settings, LoadStepping::default());
            p.set_load(1.0);
            match newton.iterate(&mut p, 0, 1.0) {
                Err(Error::NewtonDiverged { reason, .. }) => {
                    assert!(reason.contains("a cycle of two"), "{reason}")
                }
                other => panic!("expected a cycle, got {other:?}"),
            }
        }
    }

    /// An increment at a constant load whose end state cannot be evaluated
    /// is shortened until it can ([`UNEVALUABLE_HALVINGS`]), and Newton
    /// converges from there; without a shortening that evaluates, or with the
    /// shortening off where the load varies, the iterations fail as before
    /// with [`NON_FINITE_RESIDUAL`] (for load stepping to cut back).
    #[test]
    fn an_unevaluable_increment_at_a_constant_load_is_shortened() {
        let settings = NewtonSettings {
            relative_tolerance: 1e-12,
            ..NewtonSettings::default()
        };
        // The reason and iterations of a solve at the full load that fails.
        let failure = |mut p: Scalar, settings: &NewtonSettings| -> (String, usize) {
            let mut newton = Newton::new(settings.clone(), LoadStepping::default());
            p.set_load(1.0);
            match newton.iterate(&mut p, 0, 1.0) {
                Err(Error::NewtonDiverged {
                    reason, iterations, ..
                }) => (reason, iterations),
                other => panic!("{other:?}"),
            }
        };
        // At a constant load: 6 − 6 ln 3 < 0, its half 6 − 3 ln 3 > 0.
        let mut p = Scalar::new(6.0, true, logarithm);
        let mut newton = Newton::new(settings.clone(), LoadStepping::default());
        p.set_load(1.0);
        let history = newton.iterate(&mut p, 0, 1.0).unwrap();
        assert!((p.x - 2.0).abs() < 1e-9, "{}", p.x);
        assert!(history.len() <= 8, "{} iterations", history.len());
        // The same first increment where the load varies: not shortened.
        let (reason, iterations) = failure(Scalar::new(6.0, false, logarithm), &settings);
        assert_eq!((reason.as_str(), iterations), (NON_FINITE_RESIDUAL, 1));
        // A failure after a shortening says so first (with one iteration
        // allowed: the shortened state evaluates, but has not converged).
        let one = NewtonSettings {
            max_iterations: 1,
            ..settings.clone()
        };
        let (reason, _) = failure(Scalar::new(6.0, true, logarithm), &one);
        let prefix =
            format!("{NON_FINITE_RESIDUAL} met and increments halved 1×, then no convergence");
        assert!(reason.starts_with(&prefix), "{reason}");
        // A shortened solve without progress ends SHORTENED_STAGNATION
        // iterations after its smallest residual (here the first), not when
        // its iterations run out.
        let (reason, iterations) = failure(Scalar::new(11.0, true, wave), &settings);
        assert_eq!(iterations, SHORTENED_STAGNATION, "{reason}");
        assert!(
            reason.starts_with(NON_FINITE_RESIDUAL)
                && reason.contains("no progress: the smallest residual"),
            "{reason}"
        );
        // From x = 1e15 no shortening to 1/32 stays in the domain (the
        // increment is −x ln(x/2) ≈ −33.8 x), and the iterations fail as before.
        let (reason, _) = failure(Scalar::new(1e15, true, logarithm), &settings);
        assert_eq!(reason, NON_FINITE_RESIDUAL);
    }

    /// `R(x) = ln x − a (x − 1)³` (root 1, not finite for `x ≤ 0`), whose
    /// "curvature" `−3a (x − 1)²` ([`soft_curvature`]) nearly cancels the
    /// slope at `x = 3`: Newton's increment there, about −8 800, leaves the
    /// domain at every halving to 1/32; without the curvature it is −2.63.
    fn soft(x: f64, _: f64) -> (f64, f64) {
        match x > 0.0 {
            true => (
                x.ln() - SOFT_A * (x - 1.0).powi(3),
                1.0 / x + soft_curvature(x),
            ),
            false => (f64::NAN, f64::NAN),
        }
    }

    /// [`soft`]'s `a`: the slope at `x = 3` is `1/3 − 12a = 1e-4`.
    const SOFT_A: f64 = (1.0 / 3.0 - 1e-4) / 12.0;

    /// The "curvature's" part of [`soft`]'s slope.
    fn soft_curvature(x: f64) -> f64 {
        -3.0 * SOFT_A * (x - 1.0).powi(2)
    }

    /// `R(x) = ln x − b (x − 1)³` with a milder "curvature" `−3b (x − 1)²`
    /// ([`shallow_curvature`]): Newton's increment at `x = 3` is −3.5, whose
    /// end leaves the domain and whose half does not; without the curvature
    /// it is −3.25, whose end leaves the domain too and whose half does not.
    fn shallow(x: f64, _: f64) -> (f64, f64) {
        match x > 0.0 {
            true => (
                x.ln() - shallow_b() * (x - 1.0).powi(3),
                1.0 / x + shallow_curvature(x),
            ),
            false => (f64::NAN, f64::NAN),
        }
    }

    /// [`shallow`]'s `b`: `R(3) / R'(3) = (ln 3 − 8b) / (1/3 − 12b) = 3.5`.
    fn shallow_b() -> f64 {
        (3.5 / 3.0 - 3f64.ln()) / (42.0 - 8.0)
    }

    /// The "curvature's" part of [`shallow`]'s slope.
    fn shallow_curvature(x: f64) -> f64 {
        -3.0 * shallow_b() * (x - 1.0).powi(2)
    }

    /// A solve's first increment at a constant load whose end cannot be
    /// evaluated is taken again without the contact's curvature
    /// ([`NonlinearProblem::set_contact_curvature`]) before any halving, also
    /// where a halving would evaluate, and Newton converges from there with
    /// the curvature back in its tangent; a problem without such terms is
    /// halved, or fails, as before, and however the solve ends, the
    /// curvature is back in.
    #[test]
    fn an_unevaluable_increment_is_taken_again_without_the_contact_curvature() {
        let settings = NewtonSettings {
            relative_tolerance: 1e-12,
            ..NewtonSettings::default()
        };
        let solve = |p: &mut Scalar, settings: &NewtonSettings| {
            let mut newton = Newton::new(settings.clone(), LoadStepping::default());
            p.set_load(1.0);
            newton.iterate(p, 0, 1.0)
        };
        let mut p = Scalar::new(3.0, true, soft).with_curvature(soft_curvature);
        let history = solve(&mut p, &settings).unwrap();
        assert!((p.x - 1.0).abs() < 1e-9, "{}", p.x);
        assert_eq!(p.flat_tangents, 1);
        assert!(p.curved);
        // Quadratic from there: a handful of iterations.
        assert!(history.len() <= 9, "{} iterations", history.len());
        // Without the curvature's switch, the halvings alone do not evaluate.
        let mut plain = Scalar::new(3.0, true, soft);
        match solve(&mut plain, &settings) {
            Err(Error::NewtonDiverged { reason, .. }) => assert_eq!(reason, NON_FINITE_RESIDUAL),
            other => panic!("{other:?}"),
        }
        // A solve that ends after the curvature-free increment (one
        // iteration allowed) says so first, and leaves the curvature in.
        let one = NewtonSettings {
            max_iterations: 1,
            ..settings.clone()
        };
        let mut p = Scalar::new(3.0, true, soft).with_curvature(soft_curvature);
        match solve(&mut p, &one) {
            Err(Error::NewtonDiverged { reason, .. }) => assert!(
                reason.starts_with(&format!(
                    "{NON_FINITE_RESIDUAL} met, increments taken again without the contact's curvature 1×, then"
                )),
                "{reason}"
            ),
            other => panic!("{other:?}"),
        }
        assert!(p.curved);
        // Where the load varies, load stepping cuts back instead.
        let mut p = Scalar::new(3.0, false, soft).with_curvature(soft_curvature);
        assert!(solve(&mut p, &settings).is_err());
        assert_eq!(p.flat_tangents, 0);
        // A first increment that a halving would bring into the domain is
        // taken again without the curvature first (stop 107: on a steep map's
        // refined level the halvings went on at every increment), and the
        // retaken one halved; without such terms it is halved at once.
        let mut p = Scalar::new(3.0, true, shallow).with_curvature(shallow_curvature);
        solve(&mut p, &settings).unwrap();
        assert!((p.x - 1.0).abs() < 1e-9, "{}", p.x);
        assert_eq!(p.flat_tangents, 1);
        // (Two iterations allowed: the retaken increment's end is the second.)
        let two = NewtonSettings {
            max_iterations: 2,
            ..settings.clone()
        };
        for (mut p, path) in [
            (
                Scalar::new(3.0, true, shallow).with_curvature(shallow_curvature),
                ", increments taken again without the contact's curvature 1× and halved 1×",
            ),
            (Scalar::new(3.0, true, shallow), " and increments halved 1×"),
        ] {
            match solve(&mut p, &two) {
                Err(Error::NewtonDiverged { reason, .. }) => assert!(
                    reason.starts_with(&format!("{NON_FINITE_RESIDUAL} met{path}, then")),
                    "{reason}"
                ),
                other => panic!("{other:?}"),
            }
        }
    }

    /// Iterates that return to the same states are detected after four
    /// residuals. Far from convergence (here at 1e10 of the tolerance) the
    /// iterations end at once, for load stepping to cut back; within
    /// [`CYCLE_SEARCH_MERIT`] of the tolerance a line search along the
    /// increment finds the root between them (here halfway: `R(0) = 0`), and
    /// where no state along the increments converges the damped iterations
    /// after the search end as soon as their increment lowers the residual
    /// nowhere, with a reason that says so, instead of running through every
    /// allowed iteration; a converging sequence is not taken for a cycle.
    #[test]
    fn a_cycle_of_two_iterates_is_searched_along_near_convergence_then_ends() {
        let cusp = |step| Scalar::new(1.0, false, if step { cusp_step } else { cusp });
        let mut p = cusp(false);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        match newton.iterate(&mut p, 0, 1.0) {
            Err(Error::NewtonDiverged {
                iterations, reason, ..
            }) => {
                assert_eq!(iterations, 3, "{reason}");
                assert!(reason.contains("a cycle of two; residuals"), "{reason}");
                assert!(reason.contains("x 1.000e0 > "), "{reason}");
            }
            other => panic!("expected a cycle, got {other:?}"),
        }
        // Tolerances a quarter of the first residual: the cycles are at four
        // times theirs.
        let near = NewtonSettings {
            relative_tolerance: 0.25,
            ..NewtonSettings::default()
        };
        let mut newton = Newton::new(near, LoadStepping::default());
        let mut p = cusp(false);
        let history = newton.iterate(&mut p, 0, 1.0).unwrap();
        assert_eq!(history.len(), 5);
        assert_eq!(p.x, 0.0);
        let mut p = cusp(true);
        match newton.iterate(&mut p, 0, 1.0) {
            Err(Error::NewtonDiverged {
                iterations, reason, ..
            }) => {
                // Four residuals to the first cycle; the search lands on
                // `x = 0` (residual 1, against 2 at `x = ±1`), and the damped
                // iteration after it finds no smaller residual along its
                // increment (back to `x = −1`).
                assert_eq!(iterations, 4, "{reason}");
                assert!(
                    reason.contains("after a cycle of two and no smaller residual"),
                    "{reason}"
                );
                assert!(reason.contains("x 1.000e0 > 5.000e-1"), "{reason}");
            }
            other => panic!("expected a cycle, got {other:?}"),
        }
        assert_eq!(p.x, 0.0);
        let mut chain = Chain::new(20);
        chain.constant_load = Some(1.0);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        assert!(newton.solve(&mut chain).is_ok());
    }

    /// `R(x) = A x + c x³ − λ b` on a chain of `n` unknowns (`A` the tridiagonal
    /// `[−1, 2.5, −1]`): a symmetric tangent `A + 3c diag(x²)` that changes with
    /// every iteration. With `refuse_beyond`, its preparation refuses states
    /// beyond that bound (as the contact search refuses a diverged iterate).
    struct Chain {
        pattern: SymbolicSparseColMat<usize>,
        x: Vec<f64>,
        load: f64,
        refuse_beyond: Option<f64>,
        /// A load that [`NonlinearProblem::set_load`] does not change.
        constant_load: Option<f64>,
        /// Calls of [`NonlinearProblem::prepare`].
        prepared: usize,
    }

    impl Chain {
        const CUBIC: f64 = 0.5;

        fn new(n: usize) -> Self {
            let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
            for j in 0..n {
                row_idx.extend(j.saturating_sub(1)..(j + 2).min(n));
                col_ptr.push(row_idx.len());
            }
            Chain {
                pattern: SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx),
                x: vec![0.0; n],
                load: 0.0,
                refuse_beyond: None,
                constant_load: None,
                prepared: 0,
            }
        }
    }

    impl NonlinearProblem for Chain {
        fn n_eq(&self) -> usize {
            self.x.len()
        }
        fn eq_fields(&self) -> &[usize] {
            static ZEROS: [usize; 64] = [0; 64];
            &ZEROS[..self.x.len()]
        }
        fn field_names(&self) -> &[&'static str] {
            &["x"]
        }
        fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
            self.pattern.as_ref()
        }
        fn factorization(&self) -> Factorization {
            Factorization::Cholesky
        }
        fn prepare(&mut self) -> Result<()> {
            self.prepared += 1;
            match self
                .refuse_beyond
                .is_some_and(|b| self.x.iter().any(|x| x.abs() > b))
            {
                true => Err(Error::Geometry("past the search".into())),
                false => Ok(()),
            }
        }
        fn set_load(&mut self, load_factor: f64) {
            self.load = self.constant_load.unwrap_or(load_factor);
        }
        fn load_varies(&self) -> bool {
            self.constant_load.is_none()
        }
        fn assemble(&mut self, values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()> {
            let n = self.x.len();
            let x = &self.x;
            for (i, r) in residual.iter_mut().enumerate() {
                let left = if i > 0 { x[i - 1] } else { 0.0 };
                let right = if i + 1 < n { x[i + 1] } else { 0.0 };
                let neighbours = left + right;
                *r = 2.5 * x[i] - neighbours + Self::CUBIC * x[i].powi(3)
                    - self.load * (1.0 + (i % 3) as f64);
            }
            if let Some(v) = values {
                let (col_ptr, row_idx) = (self.pattern.col_ptr(), self.pattern.row_idx());
                for j in 0..n {
                    for k in col_ptr[j]..col_ptr[j + 1] {
                        v[k] = match row_idx[k] == j {
                            true => 2.5 + 3.0 * Self::CUBIC * x[j] * x[j],
                            false => -1.0,
                        };
                    }
                }
            }
            Ok(())
        }
        fn load_norms(&self) -> Vec<f64> {
            vec![self.load * (self.x.len() as f64).sqrt()]
        }
        fn update(&mut self, dx: &[f64]) {
            self.x.iter_mut().zip(dx).for_each(|(x, d)| *x += d);
        }
        fn save(&self) -> Vec<f64> {
            self.x.clone()
        }
        fn restore(&mut self, state: &[f64]) {
            self.x.copy_from_slice(state);
        }
    }

    /// [`Chain`] whose pattern alternates between two versions (the full
    /// tridiagonal and one without the coupling of the first pair, whose zero
    /// entries it then lacks) at every update, as a contact pattern does when
    /// the active set flips.
    struct Flipping {
        chain: Chain,
        patterns: [std::sync::Arc<SymbolicSparseColMat<usize>>; 2],
        version: usize,
        /// Whether it says that its equations stay ([`NonlinearProblem::numbering_version`]).
        same_equations: bool,
        /// Whether it shares its patterns and gives an ordering job (its analyses then run
        /// beside its tangents' assembly, [`NonlinearProblem::ordering_job`]).
        beside: bool,
    }

    impl Flipping {
        fn new(n: usize, same_equations: bool) -> Self {
            let chain = Chain::new(n);
            let reduced = {
                let (mut col_ptr, mut row_idx) = (vec![0], Vec::new());
                for j in 0..n {
                    for &i in &chain.pattern.row_idx()[chain.pattern.col_range(j)] {
                        if !matches!((i, j), (0, 1) | (1, 0)) {
                            row_idx.push(i);
                        }
                    }
                    col_ptr.push(row_idx.len());
                }
                SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx)
            };
            Flipping {
                patterns: [
                    std::sync::Arc::new(chain.pattern.clone()),
                    std::sync::Arc::new(reduced),
                ],
                chain,
                version: 0,
                same_equations,
                beside: false,
            }
        }
    }

    impl NonlinearProblem for Flipping {
        fn n_eq(&self) -> usize {
            self.chain.n_eq()
        }
        fn eq_fields(&self) -> &[usize] {
            self.chain.eq_fields()
        }
        fn field_names(&self) -> &[&'static str] {
            self.chain.field_names()
        }
        fn pattern(&self) -> SymbolicSparseColMatRef<'_, usize> {
            (*self.patterns[self.version % 2]).as_ref()
        }
        fn pattern_version(&self) -> u64 {
            (self.version % 2) as u64
        }
        fn shared_pattern(&self) -> Option<std::sync::Arc<SymbolicSparseColMat<usize>>> {
            self.beside
                .then(|| std::sync::Arc::clone(&self.patterns[self.version % 2]))
        }
        fn ordering_job(&self, _kind: &Factorization) -> Option<OrderingJob> {
            self.beside
                .then(|| Box::new(|| Ordering::Default) as OrderingJob)
        }
        fn numbering_version(&self) -> u64 {
            match self.same_equations {
                true => 7,
                false => self.pattern_version(),
            }
        }
        fn factorization(&self) -> Factorization {
            Factorization::Cholesky
        }
        fn set_load(&mut self, load_factor: f64) {
            self.chain.set_load(load_factor);
        }
        fn assemble(&mut self, values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()> {
            let mut full = vec![0.0; self.patterns[0].row_idx().len()];
            let with_values = values.is_some();
            self.chain
                .assemble(with_values.then_some(&mut full[..]), residual)?;
            if let Some(v) = values {
                // Copy the chain's entries into the current pattern (the first pair's
                // coupling, absent from pattern 1, is dropped: a modified Newton step).
                let (full_pattern, own) = (&self.patterns[0], &self.patterns[self.version % 2]);
                for j in 0..own.ncols() {
                    for k in own.col_range(j) {
                        let i = own.row_idx()[k];
                        let at = full_pattern
                            .col_range(j)
                            .find(|&q| full_pattern.row_idx()[q] == i)
                            .expect("pattern 1 lies in pattern 0");
                        v[k] = full[at];
                    }
                }
            }
            Ok(())
        }
        fn load_norms(&self) -> Vec<f64> {
            self.chain.load_norms()
        }
        fn update(&mut self, dx: &[f64]) {
            self.chain.update(dx);
            self.version += 1;
        }
        fn save(&self) -> Vec<f64> {
            self.chain.save()
        }
        fn restore(&mut self, state: &[f64]) {
            self.chain.restore(state);
        }
    }

    /// Solvers of a pattern that returns are reused while they are small; from
    /// the storage limit on, a new pattern of the same phase replaces the kept
    /// one (analysed anew when it returns), and the solution is the same.
    #[test]
    fn large_solvers_of_the_same_phase_are_dropped_before_a_new_analysis() {
        let solve = |kept_bytes: usize| {
            let mut p = Flipping::new(30, false);
            let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
            newton.set_kept_solver_bytes(kept_bytes);
            let history = newton.solve(&mut p).unwrap();
            (p.chain.x, history.total_iterations(), newton.analyses())
        };
        let (kept, iterations, analyses) = solve(KEPT_SOLVER_BYTES);
        assert!(iterations >= 4, "{iterations} iterations");
        assert_eq!(analyses, 2, "both patterns kept");
        let (dropped, iterations_dropped, analyses_dropped) = solve(0);
        assert_eq!(iterations_dropped, iterations);
        // The last pattern, whose residual converged, is not analysed (stop 59).
        assert_eq!(
            analyses_dropped, iterations,
            "one analysis per pattern change that an increment factorizes"
        );
        assert_eq!(dropped, kept);
    }

    /// A problem that gives an ordering job has each new pattern analysed beside its first
    /// tangent's assembly: the same analyses, increments and solution (to the bit) as the
    /// analyses made before the assembly.
    #[test]
    fn an_analysis_beside_the_tangent_gives_the_same_solve() {
        let solve = |beside: bool| {
            let mut p = Flipping::new(30, false);
            p.beside = beside;
            let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
            newton.set_kept_solver_bytes(0);
            let history = newton.solve(&mut p).unwrap();
            (p.chain.x, history.total_iterations(), newton.analyses())
        };
        let (before, iterations, analyses) = solve(false);
        assert!(iterations >= 4, "{iterations} iterations");
        assert_eq!(analyses, iterations);
        assert_eq!(solve(true), (before, iterations, analyses));
    }

    /// While the equations stay, the factors of one pattern precondition the
    /// GMRES increments of the next, and its analysis waits until a
    /// factorization is needed; the solution is that of factorizing every
    /// pattern anew (to the tolerance). Where the problem says nothing of its
    /// equations, every new pattern is analysed and factorized.
    #[test]
    fn the_factors_of_a_previous_pattern_precondition_a_new_one() {
        let solve = |same_equations: bool| {
            let mut p = Flipping::new(40, same_equations);
            let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
            newton.set_krylov_min_eq(0);
            newton.set_krylov_min_fill(0);
            newton.set_kept_solver_bytes(0);
            let history = newton.solve(&mut p).unwrap();
            let iterations = history.total_iterations();
            (
                p.chain.x,
                iterations,
                newton.analyses(),
                newton.linear_solves(),
            )
        };
        let (fresh, iterations_fresh, analyses_fresh, (factorized_fresh, _)) = solve(false);
        assert!(iterations_fresh >= 4, "{iterations_fresh} iterations");
        assert_eq!(
            analyses_fresh, iterations_fresh,
            "a new pattern each increment (not the converged residual's)"
        );
        assert_eq!(factorized_fresh, iterations_fresh);
        let (reused, iterations, analyses, (factorized, krylov)) = solve(true);
        assert_eq!(iterations, iterations_fresh);
        // The first pattern's factors, and those that follow an increment whose GMRES
        // did not converge within the budget or took more than half of it (the first
        // increments, large steps from x = 0).
        assert_eq!(factorized + krylov, iterations);
        assert!(
            2 * factorized < iterations,
            "{factorized} of {iterations} increments factorized"
        );
        assert_eq!(analyses, factorized, "analysed when factorized only");
        for (a, b) in reused.iter().zip(&fresh) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
    }

    /// An iterate that cannot be prepared (the contact search's refusal of a
    /// diverged one, [`crate::contact::projection3d::MAX_IMAGES`]) fails its
    /// load step, which is cut back, as every error but missing memory: the
    /// full step's first (linear) iterate overshoots the chain's solution
    /// past the bound, the smaller steps reach the same solution.
    #[test]
    fn an_iterate_that_cannot_be_prepared_cuts_the_step_back() {
        let mut plain = Chain::new(20);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        let steps = newton.solve(&mut plain).unwrap().steps.len();
        let top = plain.x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut p = Chain::new(20);
        p.refuse_beyond = Some(1.2 * top);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        let history = newton.solve(&mut p).unwrap();
        assert!(
            history.steps.len() > steps,
            "{} steps against {steps}",
            history.steps.len()
        );
        for (a, b) in p.x.iter().zip(&plain.x) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
    }

    /// A problem whose load does not vary fails with its first failure: the
    /// cut-back steps would repeat it. [`Chain`] at a constant full load, its
    /// first iterate refused as above: one attempt (two preparations, the
    /// start and the refused iterate), the refusal as the error; with the
    /// same load ramped, the steps are cut back and solve it.
    #[test]
    fn a_constant_load_is_not_cut_back() {
        let mut plain = Chain::new(20);
        Newton::new(NewtonSettings::default(), LoadStepping::default())
            .solve(&mut plain)
            .unwrap();
        let top = plain.x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut p = Chain::new(20);
        p.refuse_beyond = Some(1.2 * top);
        p.constant_load = Some(1.0);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        match newton.solve(&mut p) {
            Err(Error::Geometry(m)) => assert_eq!(m, "past the search"),
            other => panic!("expected the first failure, got {other:?}"),
        }
        assert_eq!(p.prepared, 2);
        p.constant_load = None;
        p.x.iter_mut().for_each(|x| *x = 0.0);
        let history = newton.solve(&mut p).unwrap();
        assert!(history.cutbacks > 0);
        for (a, b) in p.x.iter().zip(&plain.x) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
    }

    /// A solve that runs out of iterations names each residual above its
    /// tolerance with the tolerance (the classes at or below it without one).
    #[test]
    fn an_unconverged_solve_names_the_tolerance_it_missed() {
        let mut p = Chain::new(20);
        p.constant_load = Some(1.0);
        let settings = NewtonSettings {
            max_iterations: 2,
            ..NewtonSettings::default()
        };
        let mut newton = Newton::new(settings, LoadStepping::default());
        // The chain's load norm at load 1.
        let load_norm = 20f64.sqrt();
        match newton.solve(&mut p) {
            Err(Error::NewtonDiverged { reason, .. }) => {
                let (residual, tolerance) = reason
                    .strip_prefix("no convergence; residuals x ")
                    .and_then(|r| r.split_once(" > "))
                    .unwrap_or_else(|| panic!("{reason}"));
                let (residual, tolerance): (f64, f64) =
                    (residual.parse().unwrap(), tolerance.parse().unwrap());
                assert!(residual > tolerance, "{reason}");
                // Relative to the first residual or the load, whichever is
                // larger (printed to 4 digits).
                assert!(tolerance >= 1e-10 * load_norm * (1.0 - 1e-3), "{reason}");
            }
            other => panic!("expected no convergence, got {other:?}"),
        }
    }

    /// `increments` makes the increments it is given, leaves the state where
    /// they end without an error, and goes on from there to the solution
    /// that a full solve reaches, stopping where the residual has converged.
    #[test]
    fn a_limited_number_of_increments_leaves_the_state_between() {
        let full = {
            let mut p = Chain::new(20);
            p.set_load(1.0);
            let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
            let iterations = newton.iterate(&mut p, 0, 1.0).unwrap().len() - 1;
            assert!(iterations >= 4, "nonlinear: {iterations} iterations");
            (p.x, iterations)
        };
        let mut p = Chain::new(20);
        let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
        assert_eq!(newton.increments(&mut p, 1).unwrap(), 1);
        let mut r = vec![0.0; 20];
        p.assemble(None, &mut r).unwrap();
        let norm = r.iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!(norm > 1e-3, "one increment does not converge: {norm:e}");
        // The second call's convergence is relative to its own first
        // residual (here the larger one of the first increment's overshoot).
        let rest = newton.increments(&mut p, 100).unwrap();
        assert!(rest >= 1 && rest < full.1, "{rest} more of {}", full.1);
        for (a, b) in p.x.iter().zip(&full.0) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
    }

    /// The forcing term: a tenth of the squared reduction after an earlier
    /// residual, at most [`FORCING_MAX`], and never tighter than the
    /// convergence test needs (the only bound without an earlier residual)
    /// nor below [`KRYLOV_TOLERANCE`].
    #[test]
    fn the_forcing_term_follows_the_predicted_reduction_within_its_bounds() {
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b;
        // A reduction by 1e-2 predicts 1e-4 for the next one.
        assert!(close(forcing_term(Some(1.0), 1e-2, 1e-14), 1e-5));
        assert_eq!(forcing_term(Some(1.0), 0.5, 1e-14), FORCING_MAX);
        // Near convergence the linearized residual need only be a tenth of
        // the tolerance: 1e-13 of 1e-9; without an earlier residual, too.
        assert!(close(forcing_term(Some(1e-6), 1e-9, 1e-12), 1e-4));
        assert!(close(forcing_term(None, 1e-9, 1e-12), 1e-4));
        assert!(close(forcing_term(None, 1e-5, 1e-12), 1e-8));
        assert_eq!(forcing_term(None, 1e-13, 1e-12), FORCING_MAX);
        assert_eq!(forcing_term(None, 1.0, 1e-14), KRYLOV_TOLERANCE);
        assert_eq!(forcing_term(Some(1.0), 1e-8, 0.0), KRYLOV_TOLERANCE);
        assert_eq!(forcing_term(Some(f64::NAN), 1e-5, 1e-12), 1e-8);
        assert_eq!(forcing_term(Some(1.0), f64::NAN, 1e-12), KRYLOV_TOLERANCE);
    }

    /// The forcing term's tolerance is that of the field classes with
    /// equations: a mechanical phase's temperatures (no equations, the
    /// absolute floor as tolerance) do not set it.
    #[test]
    fn the_smallest_tolerance_is_that_of_the_classes_with_equations() {
        // Displacements, temperatures, mechanical and thermal multipliers.
        let targets = [1e-9, 1e-12, 1e-10, 1e-12];
        assert_eq!(smallest_tolerance(&targets, &[0, 0, 2, 0, 2]), 1e-10);
        assert_eq!(smallest_tolerance(&targets, &[0, 0, 0]), 1e-9);
        assert_eq!(smallest_tolerance(&targets, &[1, 3, 1]), 1e-12);
        assert_eq!(smallest_tolerance(&targets, &[]), f64::INFINITY);
        // The mechanical phase's first increment, 1e-5 from its solution:
        // solved to 1e-6 (a tenth of 1e-10 over 1e-5), not to 1e-8.
        let first = forcing_term(None, 1e-5, smallest_tolerance(&targets, &[0, 2]));
        assert!((first - 1e-6).abs() <= 1e-18, "{first}");
    }

    /// GMRES increments stopped at the forcing term reach the solution of
    /// increments solved to [`KRYLOV_TOLERANCE`] within the Newton tolerance,
    /// in as many Newton iterations and fewer GMRES iterations (the chain: 12
    /// Newton iterations, 74 GMRES iterations against 104, and two
    /// factorizations against three: an increment that needed more than half
    /// the budget at 1e-11 refactorized the next one).
    #[test]
    fn inexact_gmres_increments_keep_the_newton_iterations() {
        let solve = |inexact: bool| {
            let mut p = Chain::new(40);
            let stepping = LoadStepping {
                initial_step: 0.5,
                ..LoadStepping::default()
            };
            let mut newton = Newton::new(NewtonSettings::default(), stepping);
            newton.set_krylov_min_eq(0);
            newton.set_krylov_min_fill(0);
            newton.set_inexact(inexact);
            let history = newton.solve(&mut p).unwrap();
            (
                p.x,
                history.total_iterations(),
                newton.linear_solves(),
                newton.krylov_iterations(),
            )
        };
        let (exact, iterations_exact, solves_exact, gmres_exact) = solve(false);
        let (inexact, iterations, solves, gmres) = solve(true);
        assert!(solves_exact.1 > 0, "GMRES increments: {solves_exact:?}");
        assert_eq!(iterations, iterations_exact);
        assert!(gmres < gmres_exact, "{gmres} against {gmres_exact}");
        assert!(
            solves.0 <= solves_exact.0,
            "factorized: {solves:?} against {solves_exact:?}"
        );
        for (a, b) in inexact.iter().zip(&exact) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
    }

    /// Increments solved by GMRES preconditioned by the first iteration's
    /// factorization reach the solution of the factorized Newton iterations
    /// (to the tolerance), with one factorization per load step at most.
    #[test]
    fn preconditioned_gmres_increments_reach_the_factorized_solution() {
        let stepping = LoadStepping {
            initial_step: 0.5,
            ..LoadStepping::default()
        };
        let solve_in = |krylov_min_eq: usize, krylov_min_fill: usize, large: FactorPrecision| {
            let mut p = Chain::new(40);
            let mut newton = Newton::new(NewtonSettings::default(), stepping.clone());
            newton.set_krylov_min_eq(krylov_min_eq);
            newton.set_krylov_min_fill(krylov_min_fill);
            newton.set_large_factor_precision(large);
            let history = newton.solve(&mut p).unwrap();
            let precision = newton.solvers[0].solver.precision();
            (
                p.x,
                history.total_iterations(),
                newton.linear_solves(),
                precision,
            )
        };
        let solve_with = |krylov_min_eq: usize, krylov_min_fill: usize| {
            let (x, iterations, solves, _) =
                solve_in(krylov_min_eq, krylov_min_fill, LARGE_FACTOR_PRECISION);
            (x, iterations, solves)
        };
        let solve = |krylov_min_eq: usize| solve_with(krylov_min_eq, 0);
        // Large systems' factors are single (the default), small ones' double; the
        // solution is the same either way.
        let (single, _, _, precision) = solve_in(0, 0, FactorPrecision::Single);
        assert_eq!(precision, FactorPrecision::Single);
        let (double, _, _, precision) = solve_in(0, 0, FactorPrecision::Double);
        assert_eq!(precision, FactorPrecision::Double);
        let (_, _, _, precision) = solve_in(usize::MAX, 0, FactorPrecision::Single);
        assert_eq!(precision, FactorPrecision::Double, "small: double");
        for (a, b) in single.iter().zip(&double) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
        let (direct, direct_iterations, (factorized, krylov)) = solve(usize::MAX);
        assert_eq!((factorized, krylov), (direct_iterations, 0));
        let (x, iterations, (factorized, krylov)) = solve(0);
        assert!(krylov > 0 && factorized < krylov, "{factorized} / {krylov}");
        assert_eq!(factorized + krylov, iterations);
        // The chain's factors hold a few entries per equation: with the
        // default fill threshold every increment is factorized.
        let (_, iterations, (factorized, krylov)) = solve_with(0, KRYLOV_MIN_FILL);
        assert_eq!((factorized, krylov), (iterations, 0));
        assert!(x[0] > 0.5, "a nonlinear solution: {}", x[0]);
        for (a, b) in x.iter().zip(&direct) {
            assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} against {b}");
        }
    }
}
