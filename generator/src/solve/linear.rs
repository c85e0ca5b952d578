//! Sparse direct solvers behind one small interface: analyse once, refactorize per Newton step, solve.
//!
//! [`LinearSolver::new`] performs the symbolic analysis (fill-reducing ordering, elimination
//! tree, factor structure) of a fixed pattern; [`LinearSolver::factorize`] refills the kept
//! numeric storage for new values; [`LinearSolver::solve_in_place`] solves with the current
//! factors followed by a few steps of iterative refinement against the kept matrix.
//!
//! - [`Factorization::Cholesky`]: SPD systems (the thermal phase).
//! - [`Factorization::Ldlt`]: symmetric saddle-point systems (the phases with contact Lagrange
//!   multipliers), faer's LDLᵀ without pivoting, each multiplier eliminated after its
//!   displacements; a factorization with a near-zero pivot (regularized) or failed, or a solve
//!   whose backward error stays above [`LDLT_BACKWARD_ERROR_LIMIT`], falls back to LU
//!   ([`LinearSolver::fallback`]).
//! - [`Factorization::Lu`]: nonsymmetric systems; faer's supernodal LU with partial pivoting,
//!   columns always ordered by COLAMD.
//!
//! A Cholesky or LDLᵀ solver takes the pattern of its symmetric matrix with both triangles or
//! with the lower one ([`stores_lower`]; an assembly's [`crate::bulk::global::Storage::Lower`]);
//! its products (refinement, GMRES) then use the upper triangle mirrored, and its fallback LU
//! a full copy ([`full_from_lower`]).
//!
//! A Cholesky or LDLᵀ factor can be stored in single precision ([`FactorPrecision::Single`]):
//! half the memory and 0.5–0.8× the time of a numeric factorization and solve (the 3D egg
//! box's fourth level), each solve then by GMRES in double precision preconditioned by it
//! (mixed-precision refinement), and the factorization redone in double precision where that
//! does not converge.

use super::ordering::{
    approximate_minimum_degree, fewest_entries_postordered, inverse_permutation, is_permutation,
    multipliers_after_neighbours,
};
use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::perm::PermRef;
use faer::sparse::linalg::LuError;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLdltRef;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::traits::{ComplexField, RealField};
use faer::{Conj, MatMut, Par, Side};
use rayon::prelude::*;
use std::sync::Arc;

/// LDLᵀ pivots of magnitude at most this times max|aᵢⱼ| are regularized (then LU is used).
pub const LDLT_REGULARIZATION_EPSILON: f64 = 1e-13;
/// Regularized LDLᵀ pivots are set to ±(this times max|aᵢⱼ|).
pub const LDLT_REGULARIZATION_DELTA: f64 = 1e-8;
/// Systems with fewer equations are factorized and solved on one thread:
/// below it the synchronisation of faer's parallel supernodal kernels costs
/// more than it gains (the micro-samples have a few thousand unknowns),
/// unless their factor is large ([`PARALLEL_FACTORIZATION_MIN_ENTRIES`]).
pub const PARALLEL_FACTORIZATION_MIN_EQ: usize = 20_000;
/// Symmetric factors with at least this many entries are computed and
/// applied in parallel whatever their equations: the 3D adaptive levels
/// below [`PARALLEL_FACTORIZATION_MIN_EQ`] fill 1 300–2 400 entries per
/// equation (the egg box's second level at 72 kPa: 38 M entries for 15 902
/// equations, 2.2–2.9 s per factorization on one thread), where a 2D
/// micro-sample's factor holds a few hundred.
pub const PARALLEL_FACTORIZATION_MIN_ENTRIES: usize = 4_000_000;
/// At most this many steps of iterative refinement follow each solve.
pub const MAX_REFINEMENT_STEPS: usize = 3;
/// Refinement stops once ‖b − Ax‖∞ ≤ this × (‖A‖∞‖x‖∞ + ‖b‖∞).
pub const REFINEMENT_TOLERANCE: f64 = 1e-14;
/// An LDLᵀ solve whose backward error ‖b − Ax‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞) stays above this after
/// refinement is repeated with LU.
pub const LDLT_BACKWARD_ERROR_LIMIT: f64 = 1e-10;

/// At most this many GMRES iterations of [`LinearSolver::solve_preconditioned`] (no restart).
/// The basis holds two vectors of f64 per iteration: with Newton's budget
/// (`solve::newton::krylov_budget`, the factor's entries per equation over 60, at least 25)
/// that is about 7 % of a single-precision factor's bytes, and 10 % at most (25 iterations on
/// the 1 000 entries per equation from which Newton tries GMRES first).
pub const KRYLOV_MAX_ITERATIONS: usize = 150;
/// GMRES iterations of a single-precision solve ([`FactorPrecision::Single`]) before its
/// factorization is redone in double precision: such a solve takes 2–4.
pub const SINGLE_PRECISION_ITERATIONS: usize = 40;
/// [`LinearSolver::solve_preconditioned`] converges at ‖b − A x‖₂ ≤ this × ‖b‖₂.
pub const KRYLOV_TOLERANCE: f64 = 1e-11;

/// Which factorization of the global matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Factorization {
    /// A = PᵀLUQ, partial pivoting, any nonsingular matrix.
    Lu,
    /// A = LLᵀ, symmetric positive definite matrices; fails on a non-positive pivot.
    Cholesky,
    /// A = LDLᵀ without pivoting, symmetric (quasi-definite) matrices. `signs[i]` is the
    /// expected sign of equation i's pivot: +1 for displacement rows, −1 for Lagrange multiplier
    /// rows (0: no expectation). The ordering is adjusted so that each −1 equation is
    /// eliminated after all +1 equations it couples to; then, for an SPD displacement block and
    /// a full-rank constraint block, every pivot has its expected sign. Pivots of the other sign
    /// (an indefinite displacement block) are kept, exact, and counted
    /// ([`LinearSolver::sign_mismatches`]); near-zero pivots are replaced by
    /// ±[`LDLT_REGULARIZATION_DELTA`]·max|aᵢⱼ| (faer's dynamic regularization), and such a
    /// factorization is not used: the matrix is factorized by LU instead.
    Ldlt {
        /// Expected pivot sign per equation (−1, 0 or +1).
        signs: Vec<i8>,
    },
}

/// Fill-reducing ordering for the symbolic analysis.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ordering {
    /// faer's choice: AMD for Cholesky and LDLᵀ, COLAMD for LU.
    Default,
    /// `perm[new] = old`: `perm[k]` is the equation eliminated k-th (e.g. from
    /// [`super::ordering::nested_dissection`]). Cholesky and LDLᵀ only.
    Custom(Vec<usize>),
    /// This permutation or AMD, whichever gives the factor fewer entries (counted from the
    /// elimination tree, [`super::ordering::factor_entries`]; for LDLᵀ after the multiplier
    /// adjustment of both). Cholesky and LDLᵀ only.
    FewerEntries(Vec<usize>),
    /// The permutation among these (at least one) that gives the factor the fewest entries
    /// (the first on a tie; counted as for [`Ordering::FewerEntries`]). Cholesky and LDLᵀ
    /// only.
    Fewest(Vec<Vec<usize>>),
}

impl Ordering {
    /// The variant's name, for messages.
    pub fn name(&self) -> &'static str {
        match self {
            Ordering::Default => "Default",
            Ordering::Custom(_) => "Custom",
            Ordering::FewerEntries(_) => "FewerEntries",
            Ordering::Fewest(_) => "Fewest",
        }
    }
}

/// The precision in which a Cholesky or LDLᵀ factor is stored (LU factors are always double).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FactorPrecision {
    /// f64 factors; each solve is refined against the kept matrix.
    Double,
    /// f32 factors: half the memory of the factor and of the factorization's workspace, and
    /// 0.5–0.8× the time of a numeric factorization and solve (docs/3d.md). A solve is GMRES
    /// in f64 preconditioned by them ([`LinearSolver::solve_preconditioned`] against the
    /// factorized matrix itself, to [`KRYLOV_TOLERANCE`]); the residuals and the matrix stay in
    /// f64, so the accuracy is that of a double-precision solve as long as the factor's
    /// rounding (about the condition number times 6e-8) leaves the preconditioned matrix near
    /// the identity. A single-precision factorization that fails, regularizes a pivot or does
    /// not fit f32's range, and a solve whose GMRES does not converge within
    /// [`SINGLE_PRECISION_ITERATIONS`], are redone in double precision, which the solver then keeps
    /// ([`LinearSolver::precision_escalations`]).
    Single,
}

impl FactorPrecision {
    /// Bytes of one factor value.
    pub fn value_bytes(self) -> usize {
        match self {
            FactorPrecision::Double => std::mem::size_of::<f64>(),
            FactorPrecision::Single => std::mem::size_of::<f32>(),
        }
    }
}

/// The numeric values of a Cholesky/LDLᵀ factor, in the solver's precision (empty until the
/// first factorization).
enum FactorValues {
    Double(Vec<f64>),
    Single(Vec<f32>),
}

impl FactorValues {
    fn bytes(&self) -> usize {
        match self {
            FactorValues::Double(v) => v.len() * std::mem::size_of::<f64>(),
            FactorValues::Single(v) => v.len() * std::mem::size_of::<f32>(),
        }
    }
}

/// The factorization-specific symbolic and numeric parts.
enum Factors {
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
    },
    Cholesky {
        symbolic: SymbolicCholesky<usize>,
        l_values: FactorValues,
    },
}

/// Analyse once (symbolic), refactorize per Newton step, solve. Holds the symbolic factorization
/// and the numeric storage.
pub struct LinearSolver {
    kind: Factorization,
    /// Sorted within columns, no `col_nnz`; shared with the assembly where it came from one.
    pattern: Arc<SymbolicSparseColMat<usize>>,
    /// Where `pattern` is the lower triangle of a symmetric matrix (Cholesky/LDLᵀ only;
    /// [`stores_lower`]), the first row of each of its columns: which entries stand for
    /// their mirrors too.
    lower: Option<Vec<usize>>,
    factors: Factors,
    /// The last factorized matrix values, for iterative refinement (empty once released,
    /// [`Self::release_matrix`]).
    values: Vec<f64>,
    /// ‖A‖∞ of the last factorized matrix.
    norm_inf: f64,
    factorized: bool,
    /// Numeric factorization workspace, kept across refactorizations.
    workspace: Option<(StackReq, MemBuffer)>,
    /// LDLᵀ only: the LU of the same pattern that replaces a regularized or failed
    /// factorization (analysed on first use, then kept).
    lu: Option<Box<LinearSolver>>,
    /// Why the current factors are the fallback LU's (`None`: they are LDLᵀ's own).
    fallback: Option<String>,
    /// Factorizations that fell back to LU so far.
    fallbacks: usize,
    /// LDLᵀ pivots of the last factorization whose sign is not the expected one.
    sign_mismatches: usize,
    /// The precision of the Cholesky/LDLᵀ factor.
    precision: FactorPrecision,
    /// Single-precision factorizations or solves redone in double precision.
    precision_escalations: usize,
}

impl std::fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinearSolver")
            .field("kind", &self.kind)
            .field("n_eq", &self.n_eq())
            .field("nnz", &self.nnz())
            .field("factor_nnz", &self.factor_nnz())
            .field("factorized", &self.factorized)
            .field("fallback", &self.fallback)
            .field("precision", &self.precision)
            .finish()
    }
}

impl LinearSolver {
    /// Symbolic analysis of `pattern`: FULL (both triangles; structurally symmetric for
    /// Cholesky/LDLᵀ, of which only the lower triangle is factorized). Fails on an LDLᵀ sign
    /// vector of the wrong length, a custom ordering that is not a permutation, a custom
    /// ordering for LU (faer's LU always orders its columns by COLAMD), or lack of memory.
    #[track_caller]
    pub fn new(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        kind: Factorization,
        ordering: Ordering,
    ) -> Result<Self> {
        Self::with_pattern(Arc::new(owned_pattern(pattern)), kind, ordering)
    }

    /// [`LinearSolver::new`] on a pattern it shares rather than copies (an assembly's,
    /// [`crate::bulk::global::Assembly::shared_pattern`]: half a gigabyte at 57 M entries).
    /// The rows must be sorted within each column.
    #[track_caller]
    pub fn with_pattern(
        pattern: Arc<SymbolicSparseColMat<usize>>,
        kind: Factorization,
        ordering: Ordering,
    ) -> Result<Self> {
        let n = pattern.ncols();
        assert_eq!(
            pattern.nrows(),
            n,
            "LinearSolver::new: the pattern must be square"
        );
        debug_assert!(
            (0..n).all(|j| {
                let rows = &pattern.row_idx()[pattern.col_ptr()[j]..pattern.col_ptr()[j + 1]];
                rows.windows(2).all(|w| w[0] < w[1])
            }),
            "LinearSolver::with_pattern: rows not sorted"
        );
        let candidates: &[Vec<usize>] = match &ordering {
            Ordering::Default => &[],
            Ordering::Custom(perm) | Ordering::FewerEntries(perm) => std::slice::from_ref(perm),
            Ordering::Fewest(perms) if perms.is_empty() => {
                return Err(Error::invalid(
                    "ordering",
                    "Fewest(no candidate)",
                    "at least one permutation",
                ));
            }
            Ordering::Fewest(perms) => perms,
        };
        if let Some(perm) = candidates.iter().find(|perm| !is_permutation(perm, n)) {
            return Err(Error::invalid(
                "ordering",
                format!("{}(len {})", ordering.name(), perm.len()),
                format!("a permutation of 0..{n} (perm[new] = old)"),
            ));
        }
        let factors = match &kind {
            Factorization::Lu => {
                if !matches!(ordering, Ordering::Default) {
                    return Err(Error::invalid(
                        "ordering",
                        ordering.name(),
                        "Ordering::Default for Factorization::Lu (faer's LU always orders its columns by COLAMD)",
                    ));
                }
                let symbolic = factorize_symbolic_lu((*pattern).as_ref(), Default::default())
                    .map_err(|e| {
                        Error::LinearSolver(format!("LU symbolic analysis failed: {e:?}"))
                    })?;
                Factors::Lu {
                    symbolic,
                    numeric: NumericLu::new(),
                }
            }
            Factorization::Cholesky | Factorization::Ldlt { .. } => {
                let perm = symmetric_permutation((*pattern).as_ref(), &kind, ordering)?;
                let symbolic = match perm {
                    None => factorize_symbolic_cholesky(
                        (*pattern).as_ref(),
                        Side::Lower,
                        SymmetricOrdering::Amd,
                        CholeskySymbolicParams::default(),
                    ),
                    Some(perm) => {
                        let inverse = inverse_permutation(&perm);
                        factorize_symbolic_cholesky(
                            (*pattern).as_ref(),
                            Side::Lower,
                            SymmetricOrdering::Custom(PermRef::new_checked(&perm, &inverse, n)),
                            CholeskySymbolicParams::default(),
                        )
                    }
                }
                .map_err(|e| {
                    Error::LinearSolver(format!("Cholesky symbolic analysis failed: {e:?}"))
                })?;
                Factors::Cholesky {
                    symbolic,
                    l_values: FactorValues::Double(Vec::new()),
                }
            }
        };
        let lower = match kind {
            Factorization::Lu => None,
            _ => lower_first_rows((*pattern).as_ref()),
        };
        Ok(Self {
            kind,
            pattern,
            lower,
            factors,
            values: Vec::new(),
            norm_inf: 0.0,
            factorized: false,
            workspace: None,
            lu: None,
            fallback: None,
            fallbacks: 0,
            sign_mismatches: 0,
            precision: FactorPrecision::Double,
            precision_escalations: 0,
        })
    }

    /// Stores the Cholesky/LDLᵀ factor in `precision` from the next factorization on (LU
    /// factors stay double). The current factors are dropped.
    pub fn set_precision(&mut self, precision: FactorPrecision) {
        if matches!(self.factors, Factors::Lu { .. }) || precision == self.precision {
            return;
        }
        self.precision = precision;
        self.factorized = false;
        self.workspace = None;
        if let Factors::Cholesky { l_values, .. } = &mut self.factors {
            *l_values = FactorValues::Double(Vec::new());
        }
    }

    /// The precision of the factor ([`FactorPrecision::Double`] after an escalation).
    pub fn precision(&self) -> FactorPrecision {
        self.precision
    }

    /// Single-precision factorizations or solves redone in double precision so far.
    pub fn precision_escalations(&self) -> usize {
        self.precision_escalations
    }

    /// Numeric factorization of the matrix with the analysed pattern and `values` (CSC, one per
    /// pattern entry), reusing the symbolic analysis and the factor's storage. An LDLᵀ that
    /// regularizes a pivot or fails is replaced by LU ([`Self::fallback`] says why). Fails with
    /// [`Error::LinearSolver`] naming the failure (non-positive Cholesky pivot, structurally
    /// singular LU, non-finite values).
    #[track_caller]
    pub fn factorize(&mut self, values: &[f64]) -> Result<()> {
        self.factorize_owned(values.to_vec())
    }

    /// [`Self::factorize`] of `values`, which the solver keeps without a copy (a
    /// Newton tangent that is not needed after its factorization: the 3D
    /// systems' matrices hold hundreds of MB).
    #[track_caller]
    pub fn factorize_owned(&mut self, values: Vec<f64>) -> Result<()> {
        assert_eq!(
            values.len(),
            self.nnz(),
            "factorize: one value per pattern entry"
        );
        self.factorized = false;
        self.fallback = None;
        self.sign_mismatches = 0;
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::LinearSolver(format!(
                "matrix entry {i} is not finite ({})",
                values[i]
            )));
        }
        self.norm_inf = row_sum_norm(self.pattern_ref(), &values, self.lower.as_deref());
        self.values = values;
        self.factorize_kept()
    }

    /// Frees what the solver keeps only to solve its last factorized matrix
    /// again ([`Self::solve_in_place`]) and to factorize the next one faster:
    /// the matrix values and the factorization workspace (its fallback LU's
    /// too). The factors stay and precondition [`Self::solve_preconditioned_on`];
    /// [`Self::solve_in_place`] fails until the next factorization. On the 3D
    /// egg box's fourth level at 132 kPa the mechanical matrix alone holds
    /// 580 MB, which were kept through the thermal phase and the
    /// self-consistent iterations (docs/3d.md, "Stop 44").
    pub fn release_matrix(&mut self) {
        self.values = Vec::new();
        self.workspace = None;
        if let Some(lu) = self.lu.as_mut() {
            lu.release_matrix();
        }
    }

    /// Entries of the analysed pattern.
    fn nnz(&self) -> usize {
        self.pattern.row_idx().len()
    }

    /// [`Self::factorize`] of the kept values.
    fn factorize_kept(&mut self) -> Result<()> {
        self.factorized = false;
        self.fallback = None;
        self.sign_mismatches = 0;
        if self.precision == FactorPrecision::Single {
            match self.factorize_numeric() {
                Ok(None) => {
                    self.factorized = true;
                    return Ok(());
                }
                Err(e @ Error::OutOfMemory { .. }) => return Err(e),
                // Failed or regularized in single precision: double precision decides.
                Ok(Some(_)) | Err(_) => self.escalate(),
            }
        }
        let reason = match self.factorize_numeric() {
            Ok(None) => {
                self.factorized = true;
                return Ok(());
            }
            Ok(Some(reason)) => reason,
            Err(e @ Error::OutOfMemory { .. }) => return Err(e),
            Err(e) if matches!(self.kind, Factorization::Ldlt { .. }) => message(e),
            Err(e) => return Err(e),
        };
        self.fall_back(reason)
    }

    /// Switches a single-precision solver to double precision for good (see
    /// [`FactorPrecision::Single`]); the factors are to be recomputed.
    fn escalate(&mut self) {
        self.set_precision(FactorPrecision::Double);
        self.precision_escalations += 1;
        self.sign_mismatches = 0;
    }

    /// The numeric factorization of the kept values by the solver's own kind; for LDLᵀ, why it
    /// is not to be used (regularized pivots), if so.
    fn factorize_numeric(&mut self) -> Result<Option<String>> {
        let par = self.par();
        let req = match &self.factors {
            Factors::Lu { symbolic, .. } => {
                symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default())
            }
            Factors::Cholesky { symbolic, .. } => match (&self.kind, self.precision) {
                (Factorization::Ldlt { .. }, FactorPrecision::Double) => {
                    symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
                }
                (Factorization::Ldlt { .. }, FactorPrecision::Single) => {
                    symbolic.factorize_numeric_ldlt_scratch::<f32>(par, Default::default())
                }
                (_, FactorPrecision::Double) => {
                    symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default())
                }
                (_, FactorPrecision::Single) => {
                    symbolic.factorize_numeric_llt_scratch::<f32>(par, Default::default())
                }
            },
        };
        if let Factors::Cholesky { symbolic, l_values } = &mut self.factors {
            let len = symbolic.len_val();
            let fits = match (&*l_values, self.precision) {
                (FactorValues::Double(v), FactorPrecision::Double) => v.len() == len,
                (FactorValues::Single(v), FactorPrecision::Single) => v.len() == len,
                _ => false,
            };
            if !fits {
                // The old values are freed before the new ones are allocated.
                *l_values = FactorValues::Double(Vec::new());
                super::resources::ensure_memory(
                    "the factorization's values",
                    len * self.precision.value_bytes(),
                )?;
                *l_values = match self.precision {
                    FactorPrecision::Double => FactorValues::Double(zeroed(len)?),
                    FactorPrecision::Single => FactorValues::Single(zeroed(len)?),
                };
            }
        }
        if self.workspace.as_ref().is_none_or(|(r, _)| *r != req) {
            self.workspace = None;
            super::resources::ensure_memory(
                "the factorization's workspace",
                req.unaligned_bytes_required(),
            )?;
            let buffer = MemBuffer::try_new(req)
                .map_err(|_| out_of_memory(req.unaligned_bytes_required()))?;
            self.workspace = Some((req, buffer));
        }
        let stack = MemStack::new(&mut self.workspace.as_mut().expect("allocated above").1);
        let a = SparseColMatRef::new((*self.pattern).as_ref(), &self.values);
        match &mut self.factors {
            Factors::Lu { symbolic, numeric } => {
                symbolic.factorize_numeric_lu(numeric, a, par, stack, Default::default()).map_err(|e| match e {
                    LuError::SymbolicSingular { index } => Error::LinearSolver(format!(
                        "LU: matrix structurally singular, no pivot found at elimination step {index}"
                    )),
                    LuError::Generic(e) => Error::LinearSolver(format!("LU factorization failed: {e:?}")),
                })?;
            }
            Factors::Cholesky { symbolic, l_values } => {
                let amax = self.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let signs = match &self.kind {
                    Factorization::Ldlt { signs } => Some(signs.as_slice()),
                    _ => None,
                };
                let pivots = match l_values {
                    FactorValues::Double(l) => {
                        cholesky_numeric(symbolic, l, a, signs, amax, par, stack)?
                    }
                    FactorValues::Single(l) => {
                        let values = single_values(&self.values)?;
                        let a = SparseColMatRef::new((*self.pattern).as_ref(), &values);
                        cholesky_numeric(symbolic, l, a, signs, amax, par, stack)?
                    }
                };
                if let Some(pivots) = pivots {
                    self.sign_mismatches = pivots.sign_mismatches;
                    if pivots.regularized > 0 {
                        return Ok(Some(format!(
                            "LDLT: {} near-zero pivot(s) regularized (the first at equation {})",
                            pivots.regularized, pivots.first_regularized
                        )));
                    }
                }
            }
        }
        Ok(None)
    }

    /// Factorizes the kept values by the fallback LU (analysed on first use), recording `reason`.
    fn fall_back(&mut self, reason: String) -> Result<()> {
        self.factorized = false;
        let failed = |e| Error::LinearSolver(format!("{reason}; the fallback LU: {}", message(e)));
        if self.lu.is_none()
            && let Some(entries) = self.factor_nnz()
        {
            // LU holds at least both triangles of the symmetric factor (faer
            // allocates it itself, so its size is checked here).
            super::resources::ensure_memory(
                "the fallback LU factorization (at least)",
                2 * entries * std::mem::size_of::<f64>(),
            )?;
        }
        // Both triangles of a lower one, once: the LU's pattern (on first use) and values.
        let (pattern, full) = match self.lower.is_some() {
            true => {
                let (pattern, values) = full_from_lower(self.pattern_ref(), &self.values);
                (Some(pattern), Some(values))
            }
            false => (None, None),
        };
        if self.lu.is_none() {
            let pattern = pattern.map_or_else(|| Arc::clone(&self.pattern), Arc::new);
            let lu = LinearSolver::with_pattern(pattern, Factorization::Lu, Ordering::Default)
                .map_err(failed)?;
            self.lu = Some(Box::new(lu));
        }
        let lu = self.lu.as_mut().expect("analysed above");
        match full {
            Some(values) => lu.factorize_owned(values),
            None => lu.factorize(&self.values),
        }
        .map_err(failed)?;
        self.fallbacks += 1;
        self.fallback = Some(reason);
        self.factorized = true;
        Ok(())
    }

    /// Solves A x = rhs with the current factors, x overwriting `rhs`, followed by up to
    /// [`MAX_REFINEMENT_STEPS`] steps of iterative refinement. An LDLᵀ solve whose backward
    /// error stays above [`LDLT_BACKWARD_ERROR_LIMIT`] (or is not finite) is repeated with LU.
    /// With single-precision factors, GMRES preconditioned by them to [`KRYLOV_TOLERANCE`]
    /// instead, and the factorization redone in double precision where it does not converge
    /// ([`FactorPrecision::Single`]).
    /// Fails if [`Self::factorize`] has not succeeded or the solution is not finite
    /// (numerically singular matrix).
    #[track_caller]
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<()> {
        let n = self.n_eq();
        assert_eq!(rhs.len(), n, "solve_in_place: rhs.len() must equal n_eq");
        if !self.factorized {
            return Err(Error::LinearSolver(
                "solve called without a successful factorization".into(),
            ));
        }
        if self.values.len() != self.nnz() {
            return Err(Error::LinearSolver(
                "solve called after the factorized matrix was released".into(),
            ));
        }
        if self.fallback.is_some() {
            let lu = self.lu.as_mut().expect("a fallback has its LU");
            return lu.solve_in_place(rhs);
        }
        if self.precision == FactorPrecision::Single {
            if self
                .solve_preconditioned(&self.values, rhs, SINGLE_PRECISION_ITERATIONS)?
                .is_some()
            {
                return Ok(());
            }
            self.escalate();
            self.factorize_kept()?;
            return self.solve_in_place(rhs);
        }
        if !matches!(self.kind, Factorization::Ldlt { .. }) {
            return self.refined_solve(rhs).map(|_| ());
        }
        let b = rhs.to_vec();
        let reason = match self.refined_solve(rhs) {
            Ok(e) if e <= LDLT_BACKWARD_ERROR_LIMIT => return Ok(()),
            Ok(e) => format!("LDLT solve: backward error {e:.1e} after refinement"),
            Err(e) => message(e),
        };
        self.fall_back(reason)?;
        rhs.copy_from_slice(&b);
        self.lu
            .as_mut()
            .expect("a fallback has its LU")
            .solve_in_place(rhs)
    }

    /// Solve and iterative refinement with the solver's own factors; returns the backward
    /// error ‖b − Ax‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞) of the result.
    fn refined_solve(&self, rhs: &mut [f64]) -> Result<f64> {
        let n = self.n_eq();
        let b = rhs.to_vec();
        let norm_b = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut stack_buffer = MemBuffer::try_new(self.solve_scratch())
            .map_err(|_| out_of_memory(self.solve_scratch().unaligned_bytes_required()))?;
        let stack = MemStack::new(&mut stack_buffer);
        self.apply_inverse(rhs, stack);
        if let Some(i) = rhs.iter().position(|v| !v.is_finite()) {
            return Err(Error::LinearSolver(format!(
                "solution component {i} is not finite: the matrix is numerically singular"
            )));
        }
        let mut residual = vec![0.0; n];
        let mut previous = f64::INFINITY;
        let mut steps = 0;
        loop {
            residual.copy_from_slice(&b);
            self.subtract_product(rhs, &mut residual);
            let norm_r = residual.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let norm_x = rhs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let scale = self.norm_inf * norm_x + norm_b;
            if norm_r <= REFINEMENT_TOLERANCE * scale
                || norm_r > 0.5 * previous
                || steps == MAX_REFINEMENT_STEPS
            {
                return Ok(if scale > 0.0 { norm_r / scale } else { norm_r });
            }
            previous = norm_r;
            steps += 1;
            self.apply_inverse(&mut residual, stack);
            if residual.iter().any(|v| !v.is_finite()) {
                return Ok(if scale > 0.0 { norm_r / scale } else { norm_r });
            }
            rhs.iter_mut().zip(&residual).for_each(|(x, d)| *x += d);
        }
    }

    /// Whether the current factors (of the last matrix given to [`Self::factorize`], the
    /// solver's own or the fallback LU's) can precondition [`Self::solve_preconditioned`].
    pub fn is_factorized(&self) -> bool {
        self.factorized
    }

    /// Solves A x = rhs, `values` the matrix A on the analysed pattern (one per entry), by
    /// GMRES right-preconditioned by the current factors, which are those of an earlier matrix
    /// of the same pattern (a Newton tangent of a previous iteration or phase): the Krylov
    /// iterations cost a triangular solve and a product each, against a numeric factorization
    /// that costs tens of solves for the 3D systems. `Some(iterations)` once the true residual
    /// meets ‖b − A x‖₂ ≤ [`KRYLOV_TOLERANCE`] ‖b‖₂ within `max_iterations` (at most
    /// [`KRYLOV_MAX_ITERATIONS`]), x overwriting `rhs`; `None` (and `rhs` unchanged) when it
    /// does not, or when there are no factors: the caller then factorizes A. The factors and the
    /// kept matrix are not changed.
    pub fn solve_preconditioned(
        &self,
        values: &[f64],
        rhs: &mut [f64],
        max_iterations: usize,
    ) -> Result<Option<usize>> {
        self.solve_preconditioned_on(
            self.pattern_ref(),
            values,
            rhs,
            max_iterations,
            KRYLOV_TOLERANCE,
        )
    }

    /// [`Self::solve_preconditioned`] of a matrix on another `pattern` of the same equations
    /// (the same unknowns in the same order): the tangent of a new contact pattern
    /// preconditioned by the factors of the previous one (a self-consistent iteration's
    /// mechanical phase after the active set changed), to ‖b − A x‖₂ ≤ `tolerance` ‖b‖₂
    /// (at least [`KRYLOV_TOLERANCE`]; a Newton increment needs less,
    /// `solve::newton::forcing_term`). `None` also where `pattern` stores other triangles than
    /// the solver's ([`stores_lower`]: a phase whose tangent's symmetry changed), whose
    /// product it would misread. Panics unless `pattern` has [`Self::n_eq`] rows and columns
    /// and `values` one entry per pattern entry.
    pub fn solve_preconditioned_on(
        &self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
        rhs: &mut [f64],
        max_iterations: usize,
        tolerance: f64,
    ) -> Result<Option<usize>> {
        let tolerance = tolerance.max(KRYLOV_TOLERANCE);
        let n = self.n_eq();
        assert!(
            pattern.nrows() == n && pattern.ncols() == n,
            "solve_preconditioned_on: the pattern must have the solver's {n} equations"
        );
        assert_eq!(
            values.len(),
            pattern.row_idx().len(),
            "one value per pattern entry"
        );
        assert_eq!(
            rhs.len(),
            n,
            "solve_preconditioned: rhs.len() must equal n_eq"
        );
        if !self.factorized {
            return Ok(None);
        }
        let own = std::ptr::eq(pattern.row_idx(), self.pattern.row_idx())
            && std::ptr::eq(pattern.col_ptr(), self.pattern.col_ptr());
        let other = (!own).then(|| lower_first_rows(pattern));
        let first = match &other {
            None => self.lower.as_deref(),
            Some(other) if other.is_some() == self.lower.is_some() => other.as_deref(),
            Some(_) => return Ok(None),
        };
        let m = max_iterations.clamp(1, KRYLOV_MAX_ITERATIONS);
        let norm_b = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm_b == 0.0 {
            return Ok(Some(0));
        }
        let factors: &Self = match &self.fallback {
            Some(_) => self.lu.as_deref().expect("a fallback has its LU"),
            None => self,
        };
        let mut buffer = MemBuffer::try_new(factors.solve_scratch())
            .map_err(|_| out_of_memory(factors.solve_scratch().unaligned_bytes_required()))?;
        let product = |x: &[f64], y: &mut [f64]| {
            y.fill(0.0);
            multiply_add(pattern, values, first, 1.0, x, y);
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        // Arnoldi on A M⁻¹ from x0 = 0 (modified Gram–Schmidt), Givens rotations on the
        // Hessenberg matrix; `z[k] = M⁻¹ v[k]` kept for the update x = Σ y_k z_k.
        let mut basis: Vec<Vec<f64>> = vec![rhs.iter().map(|v| v / norm_b).collect()];
        let mut preconditioned: Vec<Vec<f64>> = Vec::with_capacity(m);
        let mut h: Vec<Vec<f64>> = Vec::with_capacity(m);
        let (mut cs, mut sn): (Vec<f64>, Vec<f64>) = (Vec::with_capacity(m), Vec::with_capacity(m));
        let mut g = vec![norm_b];
        let mut w = vec![0.0; n];
        let mut steps = 0;
        while steps < m {
            let mut z = basis[steps].clone();
            factors.apply_inverse(&mut z, MemStack::new(&mut buffer));
            product(&z, &mut w);
            preconditioned.push(z);
            let mut column = vec![0.0; steps + 2];
            for (i, v) in basis.iter().enumerate() {
                let hij = dot(&w, v);
                column[i] = hij;
                w.iter_mut().zip(v).for_each(|(a, b)| *a -= hij * b);
            }
            let norm_w = dot(&w, &w).sqrt();
            column[steps + 1] = norm_w;
            for i in 0..steps {
                let (a, b) = (column[i], column[i + 1]);
                column[i] = cs[i] * a + sn[i] * b;
                column[i + 1] = -sn[i] * a + cs[i] * b;
            }
            let (a, b) = (column[steps], column[steps + 1]);
            let r = a.hypot(b);
            if !(r.is_finite() && r > 0.0) {
                return Ok(None);
            }
            cs.push(a / r);
            sn.push(b / r);
            column[steps] = r;
            column[steps + 1] = 0.0;
            g.push(-sn[steps] * g[steps]);
            g[steps] *= cs[steps];
            h.push(column);
            steps += 1;
            if g[steps].abs() <= 0.1 * tolerance * norm_b || norm_w == 0.0 {
                break;
            }
            basis.push(w.iter().map(|v| v / norm_w).collect());
        }
        // Back substitution for y, then x = Σ y_k z_k and the true residual.
        let mut y = vec![0.0; steps];
        for i in (0..steps).rev() {
            let s: f64 = (i + 1..steps).map(|k| h[k][i] * y[k]).sum();
            y[i] = (g[i] - s) / h[i][i];
        }
        let mut x = vec![0.0; n];
        for (yk, z) in y.iter().zip(&preconditioned) {
            x.iter_mut().zip(z).for_each(|(a, b)| *a += yk * b);
        }
        product(&x, &mut w);
        let residual = w
            .iter()
            .zip(rhs.iter())
            .map(|(a, b)| (b - a) * (b - a))
            .sum::<f64>()
            .sqrt();
        let accurate = residual <= tolerance * norm_b;
        if !accurate || x.iter().any(|v| !v.is_finite()) {
            return Ok(None);
        }
        rhs.copy_from_slice(&x);
        Ok(Some(steps))
    }

    /// Why the current factors are LU's rather than this LDLᵀ solver's own (a regularized or
    /// failed factorization, or an inaccurate solve); `None` when they are its own.
    pub fn fallback(&self) -> Option<&str> {
        self.fallback.as_deref()
    }

    /// How many factorizations fell back to LU so far.
    pub fn fallbacks(&self) -> usize {
        self.fallbacks
    }

    /// LDLᵀ pivots of the last factorization whose sign is not the expected one (the
    /// displacement block is indefinite there); 0 for the other kinds.
    pub fn sign_mismatches(&self) -> usize {
        self.sign_mismatches
    }

    /// The factorization kind.
    pub fn kind(&self) -> &Factorization {
        &self.kind
    }

    /// Number of equations.
    pub fn n_eq(&self) -> usize {
        self.pattern.ncols()
    }

    /// Number of stored entries of the Cholesky/LDLᵀ factor L (supernodal blocks counted in
    /// full); `None` for LU, whose factor sizes faer does not expose.
    pub fn factor_nnz(&self) -> Option<usize> {
        match &self.factors {
            Factors::Lu { .. } => None,
            Factors::Cholesky { symbolic, .. } => Some(symbolic.len_val()),
        }
    }

    /// Floating-point operations of one numeric factorization
    /// ([`cholesky_factor_flops`]); `None` for LU, whose factor faer does not expose.
    pub fn factor_flops(&self) -> Option<f64> {
        match &self.factors {
            Factors::Lu { .. } => None,
            Factors::Cholesky { symbolic, .. } => Some(cholesky_factor_flops(symbolic)),
        }
    }

    /// Bytes of the factor's values in the solver's precision (0 for LU,
    /// whose factor size is known only once factorized).
    pub fn factor_value_bytes(&self) -> usize {
        self.factor_nnz().unwrap_or(0) * self.precision.value_bytes()
    }

    /// The fill-reducing permutation in use, `perm[new] = old` (the column permutation for LU).
    pub fn permutation(&self) -> Vec<usize> {
        match &self.factors {
            Factors::Lu { symbolic, .. } => symbolic.col_perm().arrays().0.to_vec(),
            Factors::Cholesky { symbolic, .. } => symbolic
                .perm()
                .map_or_else(|| (0..self.n_eq()).collect(), |p| p.arrays().0.to_vec()),
        }
    }

    /// Bytes held: the factor values and the supernodal structure's indices, the kept pattern
    /// and matrix, the factorization workspace, and the fallback LU's pattern and matrix (faer
    /// does not expose the size of LU factors, which are not counted).
    pub fn storage_bytes(&self) -> usize {
        let f = std::mem::size_of::<f64>();
        let u = std::mem::size_of::<usize>();
        let factor = match &self.factors {
            Factors::Lu { .. } => 0,
            Factors::Cholesky { l_values, .. } => l_values.bytes(),
        };
        // The supernodal structure's index arrays (faer does not expose its row-major
        // copy of the supernodes' graph, which is not counted).
        let symbolic = match &self.factors {
            Factors::Cholesky { symbolic, .. } => match symbolic.raw() {
                SymbolicCholeskyRaw::Supernodal(s) => {
                    (s.row_idx().len()
                        + s.supernode_begin().len()
                        + s.col_ptr_for_row_idx().len()
                        + s.col_ptr_for_val().len()
                        + 2 * self.n_eq())
                        * u
                }
                SymbolicCholeskyRaw::Simplicial(_) => 2 * self.n_eq() * u,
            },
            Factors::Lu { .. } => 0,
        };
        let workspace = self
            .workspace
            .as_ref()
            .map_or(0, |(r, _)| r.unaligned_bytes_required());
        factor
            + symbolic
            + self.values.len() * f
            + self.nnz() * u
            + (self.n_eq() + 1) * u
            + workspace
            + self.lu.as_ref().map_or(0, |lu| lu.storage_bytes())
    }

    /// The kept pattern as a faer view.
    fn pattern_ref(&self) -> SymbolicSparseColMatRef<'_, usize> {
        (*self.pattern).as_ref()
    }

    /// Whether this solver was analysed for exactly `pattern`.
    pub fn analyses(&self, pattern: SymbolicSparseColMatRef<'_, usize>) -> bool {
        let own = self.pattern_ref();
        own.nrows() == pattern.nrows()
            && own.col_ptr() == pattern.col_ptr()
            && own.row_idx() == pattern.row_idx()
    }

    /// Parallel for large systems only ([`PARALLEL_FACTORIZATION_MIN_EQ`],
    /// [`PARALLEL_FACTORIZATION_MIN_ENTRIES`]).
    fn par(&self) -> Par {
        if self.n_eq() >= PARALLEL_FACTORIZATION_MIN_EQ
            || self
                .factor_nnz()
                .is_some_and(|l| l >= PARALLEL_FACTORIZATION_MIN_ENTRIES)
        {
            Par::rayon(0)
        } else {
            Par::Seq
        }
    }

    fn solve_scratch(&self) -> StackReq {
        let par = self.par();
        match &self.factors {
            Factors::Lu { symbolic, .. } => symbolic.solve_in_place_scratch::<f64>(1, par),
            Factors::Cholesky { symbolic, .. } => match self.precision {
                FactorPrecision::Double => symbolic.solve_in_place_scratch::<f64>(1, par),
                FactorPrecision::Single => symbolic.solve_in_place_scratch::<f32>(1, par),
            },
        }
    }

    /// x ← A⁻¹x with the current factors (in their precision).
    fn apply_inverse(&self, x: &mut [f64], stack: &mut MemStack) {
        let n = x.len();
        let par = self.par();
        let ldlt = matches!(self.kind, Factorization::Ldlt { .. });
        match &self.factors {
            Factors::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(x, n, 1),
                    par,
                    stack,
                ),
            Factors::Cholesky {
                symbolic,
                l_values: FactorValues::Double(l),
            } => cholesky_solve(symbolic, l, ldlt, x, par, stack),
            Factors::Cholesky {
                symbolic,
                l_values: FactorValues::Single(l),
            } => {
                let mut single: Vec<f32> = x.iter().map(|&v| v as f32).collect();
                cholesky_solve(symbolic, l, ldlt, &mut single, par, stack);
                x.iter_mut()
                    .zip(&single)
                    .for_each(|(v, s)| *v = f64::from(*s));
            }
        }
    }

    /// r ← r − A x with the kept matrix.
    fn subtract_product(&self, x: &[f64], r: &mut [f64]) {
        multiply_add(
            self.pattern_ref(),
            &self.values,
            self.lower.as_deref(),
            -1.0,
            x,
            r,
        );
    }
}

/// x ← A⁻¹x with a Cholesky (`ldlt` false) or LDLᵀ factor in the precision of `x`.
fn cholesky_solve<T>(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &[T],
    ldlt: bool,
    x: &mut [T],
    par: Par,
    stack: &mut MemStack,
) where
    T: RealField + ComplexField<Real = T> + Copy,
{
    let n = x.len();
    let x = MatMut::from_column_major_slice_mut(x, n, 1);
    match ldlt {
        true => LdltRef::new(symbolic, l_values).solve_in_place_with_conj(Conj::No, x, par, stack),
        false => LltRef::new(symbolic, l_values).solve_in_place_with_conj(Conj::No, x, par, stack),
    }
}

/// Matrices with at least this many entries are multiplied in
/// [`PRODUCT_CHUNKS`] column ranges in parallel (GMRES, `multiply_add`): the 3D
/// adaptive levels from the second on (9–74 M entries on the egg box), whose
/// GMRES products were serial. On the 72 kPa egg box's fourth level (57 M
/// entries) its five mechanical GMRES solves took 12.0 s with serial
/// products, 10.2–10.8 s with these in two runs (the same iterations; per
/// iteration the factor's triangular solves 0.16 s, the product 0.03 s; the
/// same jump to 1e-14; stop 48, 2 cores).
pub const PARALLEL_PRODUCT_MIN_ENTRIES: usize = 4_000_000;

/// The column ranges of a parallel product ([`PARALLEL_PRODUCT_MIN_ENTRIES`]),
/// a number fixed apart from the threads: each range sums its columns into a
/// vector of its own, and the vectors are added in range order, so the
/// product is the same for any number of threads.
pub const PRODUCT_CHUNKS: usize = 8;

/// y ← y + α A x, `A` the CSC matrix of `pattern` and `values` (with `first`, the first
/// rows of its columns, the symmetric matrix of that lower triangle, [`stores_lower`]: an
/// entry `(i, j)` whose mirror `(j, i)` column `i` does not hold counts twice); in parallel from
/// [`PARALLEL_PRODUCT_MIN_ENTRIES`] entries, with the same result for any
/// number of threads.
fn multiply_add(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    first: Option<&[usize]>,
    alpha: f64,
    x: &[f64],
    y: &mut [f64],
) {
    multiply_add_from(
        pattern,
        values,
        first,
        alpha,
        x,
        y,
        PARALLEL_PRODUCT_MIN_ENTRIES,
    );
}

/// The first row of every column of `pattern` (its own index where empty).
fn first_rows(pattern: SymbolicSparseColMatRef<'_, usize>) -> Vec<usize> {
    (0..pattern.ncols())
        .map(|j| {
            pattern.row_idx()[pattern.col_range(j)]
                .first()
                .copied()
                .unwrap_or(j)
        })
        .collect()
}

/// [`multiply_add`], in parallel from `parallel_entries` entries.
fn multiply_add_from(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    first: Option<&[usize]>,
    alpha: f64,
    x: &[f64],
    y: &mut [f64],
    parallel_entries: usize,
) {
    let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
    let columns_into = |columns: std::ops::Range<usize>, y: &mut [f64]| {
        for j in columns {
            let xj = x[j];
            let entries = col_ptr[j]..col_ptr[j + 1];
            if let Some(first) = first {
                // Column j and, mirrored, row j: y_i += a_ij x_j, and y_j += a_ij x_i where
                // column i does not hold row j.
                let mut yj = 0.0;
                for k in entries {
                    let (i, a) = (row_idx[k], alpha * values[k]);
                    y[i] += a * xj;
                    if j < first[i] {
                        yj += a * x[i];
                    }
                }
                y[j] += yj;
            } else if xj != 0.0 {
                for k in entries {
                    y[row_idx[k]] += alpha * values[k] * xj;
                }
            }
        }
    };
    let nnz = row_idx.len();
    if nnz < parallel_entries {
        columns_into(0..x.len(), y);
        return;
    }
    // Ranges of about equal entries: range c starts at the first column
    // whose entries start at c/PRODUCT_CHUNKS of them (nondecreasing in c).
    let bounds: Vec<usize> = (0..=PRODUCT_CHUNKS)
        .map(|c| match c {
            PRODUCT_CHUNKS => x.len(),
            c => col_ptr.partition_point(|&p| p < nnz * c / PRODUCT_CHUNKS),
        })
        .collect();
    let parts: Vec<Vec<f64>> = bounds
        .par_windows(2)
        .map(|w| {
            let mut part = vec![0.0; y.len()];
            columns_into(w[0]..w[1], &mut part);
            part
        })
        .collect();
    y.par_iter_mut().enumerate().for_each(|(i, yi)| {
        for part in &parts {
            *yi += part[i];
        }
    });
}

/// The permutation handed to faer's symbolic Cholesky (`None`: faer's AMD), postordered
/// ([`super::ordering::postordered`]: the same fill, supernodes of consecutive columns). For LDLᵀ with
/// multiplier rows, every −1 equation is moved after its +1 neighbours (AMD computed here).
/// Of several candidates ([`Ordering::FewerEntries`], [`Ordering::Fewest`]) the one whose
/// factor has the fewest entries, after that adjustment.
fn symmetric_permutation(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    kind: &Factorization,
    ordering: Ordering,
) -> Result<Option<Vec<usize>>> {
    let n = pattern.ncols();
    let signs = match kind {
        Factorization::Ldlt { signs } => {
            if signs.len() != n || signs.iter().any(|s| !(-1..=1).contains(s)) {
                return Err(Error::invalid(
                    "signs",
                    format!("{} entries", signs.len()),
                    format!("{n} entries, each −1, 0 or +1"),
                ));
            }
            Some(signs).filter(|s| s.contains(&-1))
        }
        _ => None,
    };
    let adjusted = |perm: Vec<usize>| match signs {
        Some(signs) => multipliers_after_neighbours(pattern, perm, signs),
        None => perm,
    };
    let candidates = match ordering {
        Ordering::Default if signs.is_none() => return Ok(None),
        Ordering::Default => vec![approximate_minimum_degree(pattern)],
        Ordering::Custom(perm) => vec![perm],
        Ordering::FewerEntries(perm) => vec![perm, approximate_minimum_degree(pattern)],
        Ordering::Fewest(perms) => perms,
    };
    let candidates = candidates.into_iter().map(adjusted).collect();
    Ok(Some(fewest_entries_postordered(pattern, candidates)))
}

/// A standard-form (sorted, no `col_nnz`) owned copy of `pattern`.
fn owned_pattern(pattern: SymbolicSparseColMatRef<'_, usize>) -> SymbolicSparseColMat<usize> {
    let n = pattern.ncols();
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::with_capacity(pattern.compute_nnz());
    for j in 0..n {
        let start = row_idx.len();
        row_idx.extend_from_slice(&pattern.row_idx()[pattern.col_range(j)]);
        row_idx[start..].sort_unstable();
        col_ptr.push(row_idx.len());
    }
    SymbolicSparseColMat::new_checked(pattern.nrows(), n, col_ptr, None, row_idx)
}

/// ‖A‖∞ = max row sum of |aᵢⱼ| (with `first`, the first rows of its columns, of the
/// symmetric matrix of that lower triangle, [`stores_lower`]).
fn row_sum_norm(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    first: Option<&[usize]>,
) -> f64 {
    let mut row_sum = vec![0.0f64; pattern.nrows()];
    for j in 0..pattern.ncols() {
        for k in pattern.col_range(j) {
            let (i, v) = (pattern.row_idx()[k], values[k].abs());
            row_sum[i] += v;
            if first.is_some_and(|f| j < f[i]) {
                row_sum[j] += v;
            }
        }
    }
    row_sum.into_iter().fold(0.0, f64::max)
}

/// Whether `pattern` holds the lower triangle of a symmetric matrix
/// ([`crate::bulk::global::Storage::Lower`]): some entry `(i, j)` has no mirror `(j, i)`
/// because column `i` starts below row `j`. Each column then holds its rows from its first
/// on, and an entry `(i, j)` with `j` above column `i`'s first row stands for its mirror too;
/// the others (a diagonal block stored whole) once. A structurally symmetric pattern (both
/// triangles) has no such entry.
pub fn stores_lower(pattern: SymbolicSparseColMatRef<'_, usize>) -> bool {
    lower_first_rows(pattern).is_some()
}

/// The first row of every column of `pattern` where it holds a lower triangle
/// ([`stores_lower`]), else `None`.
fn lower_first_rows(pattern: SymbolicSparseColMatRef<'_, usize>) -> Option<Vec<usize>> {
    let first = first_rows(pattern);
    (0..pattern.ncols())
        .any(|j| {
            pattern.row_idx()[pattern.col_range(j)]
                .iter()
                .any(|&i| j < first[i])
        })
        .then_some(first)
}

/// The symmetric matrix of which `pattern` with `values` is the lower triangle
/// ([`stores_lower`]), with both triangles: its pattern (rows sorted within each column) and
/// values.
pub fn full_from_lower(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
) -> (SymbolicSparseColMat<usize>, Vec<f64>) {
    let n = pattern.ncols();
    let row_idx = pattern.row_idx();
    let first = first_rows(pattern);
    // Column j of the full matrix: the mirrors in row j (of columns k < first(j), in order),
    // then its stored column j.
    let mut count = vec![0usize; n + 1];
    for j in 0..n {
        for &i in &row_idx[pattern.col_range(j)] {
            count[j + 1] += 1;
            if j < first[i] {
                count[i + 1] += 1;
            }
        }
    }
    for j in 0..n {
        count[j + 1] += count[j];
    }
    let mut next = count.clone();
    let mut rows = vec![0usize; count[n]];
    let mut full = vec![0.0; count[n]];
    // Mirrored entries first: visiting the columns in order puts them in increasing row.
    for j in 0..n {
        for k in pattern.col_range(j) {
            let i = row_idx[k];
            if j < first[i] {
                rows[next[i]] = j;
                full[next[i]] = values[k];
                next[i] += 1;
            }
        }
    }
    for j in 0..n {
        for k in pattern.col_range(j) {
            rows[next[j]] = row_idx[k];
            full[next[j]] = values[k];
            next[j] += 1;
        }
    }
    (
        SymbolicSparseColMat::new_checked(n, n, count, None, rows),
        full,
    )
}

fn out_of_memory(bytes: usize) -> Error {
    Error::LinearSolver(format!(
        "out of memory allocating {bytes} bytes for the factorization"
    ))
}

/// The message of an [`Error::LinearSolver`] (else the error's text).
fn message(e: Error) -> String {
    match e {
        Error::LinearSolver(m) => m,
        e => e.to_string(),
    }
}

/// The original equation eliminated at step `index` (faer's index, clamped to the matrix).
fn original_equation(symbolic: &SymbolicCholesky<usize>, index: usize) -> usize {
    let k = index.min(symbolic.nrows().saturating_sub(1));
    symbolic.perm().map_or(k, |p| p.arrays().0[k])
}

/// A zero-filled vector of `len` values, or an out-of-memory error.
fn zeroed<T: Copy + Default>(len: usize) -> Result<Vec<T>> {
    let mut v = Vec::new();
    v.try_reserve_exact(len)
        .map_err(|_| out_of_memory(len * std::mem::size_of::<T>()))?;
    v.resize(len, T::default());
    Ok(v)
}

/// The matrix values rounded to f32; an error if one exceeds its range.
fn single_values(values: &[f64]) -> Result<Vec<f32>> {
    let single: Vec<f32> = values.iter().map(|&v| v as f32).collect();
    match single.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(Error::LinearSolver(format!(
            "matrix entry {i} ({:e}) exceeds single precision",
            values[i]
        ))),
        None => Ok(single),
    }
}

/// The numeric Cholesky (`signs` `None`) or LDLᵀ factorization into `l_values`, in their
/// precision; for LDLᵀ the pivots against the signs. Near-zero LDLᵀ pivots (below
/// [`LDLT_REGULARIZATION_EPSILON`]·`amax`) are regularized, which the pivots report.
fn cholesky_numeric<T>(
    symbolic: &SymbolicCholesky<usize>,
    l_values: &mut [T],
    a: SparseColMatRef<'_, usize, T>,
    signs: Option<&[i8]>,
    amax: f64,
    par: Par,
    stack: &mut MemStack,
) -> Result<Option<Pivots>>
where
    T: RealField + ComplexField<Real = T> + Copy + Into<f64>,
{
    let Some(signs) = signs else {
        symbolic
            .factorize_numeric_llt(
                l_values,
                a,
                Side::Lower,
                Default::default(),
                par,
                stack,
                Default::default(),
            )
            .map_err(|e| {
                let LltError::NonPositivePivot { index } = e;
                Error::LinearSolver(format!(
                    "Cholesky: non-positive pivot at elimination step {index} (equation {}); \
                     the matrix is not positive definite",
                    original_equation(symbolic, index)
                ))
            })?;
        return Ok(None);
    };
    let delta = T::from_f64_impl(LDLT_REGULARIZATION_DELTA * amax);
    // No signs: pivots of either sign are kept, near-zero ones regularized.
    let regularization = LdltRegularization {
        dynamic_regularization_signs: None,
        dynamic_regularization_delta: delta,
        dynamic_regularization_epsilon: T::from_f64_impl(LDLT_REGULARIZATION_EPSILON * amax),
    };
    symbolic
        .factorize_numeric_ldlt(l_values, a, Side::Lower, regularization, par, stack, Default::default())
        .map_err(|e| {
            let LdltError::ZeroPivot { index } = e;
            Error::LinearSolver(format!(
                "LDLT: zero pivot at elimination step {index} (equation {}); the matrix is singular",
                original_equation(symbolic, index)
            ))
        })?;
    Ok(Some(Pivots::of(symbolic, l_values, delta.into(), signs)))
}

/// The pivots D of an LDLᵀ factor against the expected signs.
struct Pivots {
    /// Pivots that faer's dynamic regularization replaced (set to exactly ±delta).
    regularized: usize,
    /// The original equation of the first of them in elimination order.
    first_regularized: usize,
    /// Pivots whose sign is not the expected (nonzero) one.
    sign_mismatches: usize,
}

impl Pivots {
    fn of<T>(symbolic: &SymbolicCholesky<usize>, l_values: &[T], delta: f64, signs: &[i8]) -> Self
    where
        T: RealField + ComplexField<Real = T> + Copy + Into<f64>,
    {
        let perm = symbolic.perm().map(|p| p.arrays().0);
        let mut out = Pivots {
            regularized: 0,
            first_regularized: 0,
            sign_mismatches: 0,
        };
        let mut check = |k: usize, d: f64| {
            let eq = perm.map_or(k, |p| p[k]);
            if delta > 0.0 && d.abs() == delta {
                out.regularized += 1;
                if out.regularized == 1 {
                    out.first_regularized = eq;
                }
            }
            if d * f64::from(signs[eq]) < 0.0 {
                out.sign_mismatches += 1;
            }
        };
        match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                for (k, &start) in s.col_ptr()[..s.ncols()].iter().enumerate() {
                    check(k, l_values[start].into());
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let factor = SupernodalLdltRef::new(s, l_values);
                for i in 0..s.n_supernodes() {
                    let node = factor.supernode(i);
                    let d = node.val();
                    for j in 0..d.ncols() {
                        check(node.start() + j, d[(j, j)].into());
                    }
                }
            }
        }
        out
    }
}

/// Floating-point operations of a numeric Cholesky or LDLᵀ factorization with
/// this structure: `Σ_j (m_j² + 2 m_j)`, `m_j` the entries below the diagonal
/// of column `j` as the factor stores them (a supernode's explicit zeros
/// included, since its dense kernels compute them): the rank-one updates'
/// multiply-adds of the lower triangle and the column's scaling. A dense
/// `n × n` factor counts `n³/3 + O(n²)`. With the factorization's wall time
/// it gives the rate a machine reaches (`tcgen bench`), which compares runs
/// of different days and machines where seconds alone do not.
pub fn cholesky_factor_flops(symbolic: &SymbolicCholesky<usize>) -> f64 {
    let column = |m: usize| {
        let m = m as f64;
        m * m + 2.0 * m
    };
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            let rows = s.col_ptr_for_row_idx();
            (0..s.n_supernodes())
                .map(|k| {
                    let width = s.supernode_end()[k] - s.supernode_begin()[k];
                    let below = rows[k + 1] - rows[k];
                    (0..width)
                        .map(|j| column(width - 1 - j + below))
                        .sum::<f64>()
                })
                .sum()
        }
        // Each column's entries, its diagonal first.
        SymbolicCholeskyRaw::Simplicial(s) => s
            .col_ptr()
            .windows(2)
            .map(|c| column(c[1] - c[0] - 1))
            .sum(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factorization's flop count: `Σ (m² + 2m)` over the columns of a
    /// dense factor, supernodal or simplicial alike, and `3 (n − 1)` for a
    /// tridiagonal matrix kept in its order (one entry below each diagonal
    /// but the last).
    #[test]
    fn factor_flops_count_the_columns_below_their_diagonals() {
        use faer::sparse::linalg::SupernodalThreshold;
        // Both triangles of a banded matrix.
        let banded = |n: usize, band: usize| {
            let mut col_ptr = vec![0];
            let mut row_idx = Vec::new();
            for j in 0..n {
                row_idx.extend(j.saturating_sub(band)..n.min(j + band + 1));
                col_ptr.push(row_idx.len());
            }
            SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx)
        };
        let flops = |pattern: &SymbolicSparseColMat<usize>, threshold| {
            let params = CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: threshold,
                ..Default::default()
            };
            let symbolic = factorize_symbolic_cholesky(
                pattern.as_ref(),
                Side::Lower,
                SymmetricOrdering::Identity,
                params,
            )
            .expect("a symbolic factorization");
            let supernodal = matches!(symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_));
            (cholesky_factor_flops(&symbolic), supernodal)
        };
        let n = 40;
        let dense: f64 = (0..n).map(|m| (m * m + 2 * m) as f64).sum();
        assert!((dense - (n * n * n) as f64 / 3.0).abs() < (n * n) as f64);
        let full = banded(n, n);
        assert_eq!(
            flops(&full, SupernodalThreshold::FORCE_SUPERNODAL),
            (dense, true)
        );
        assert_eq!(
            flops(&full, SupernodalThreshold::FORCE_SIMPLICIAL),
            (dense, false)
        );
        let tridiagonal = banded(n, 1);
        let expected = 3.0 * (n - 1) as f64;
        assert_eq!(
            flops(&tridiagonal, SupernodalThreshold::FORCE_SIMPLICIAL),
            (expected, false)
        );
    }

    /// The chunked product is the serial one to round-off, and the same bits in pools of
    /// one and three threads.
    #[test]
    fn the_parallel_product_is_the_serial_one_for_any_threads() {
        let n = 3_000;
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for j in 0..n {
            // Uneven columns: the chunk bounds fall inside long and short runs alike.
            let mut rows: Vec<usize> = (0..1 + (j % 37))
                .map(|_| (next() * n as f64) as usize % n)
                .collect();
            rows.push(j);
            rows.sort_unstable();
            rows.dedup();
            values.extend(rows.iter().map(|_| next() - 0.5));
            row_idx.extend(rows);
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let x: Vec<f64> = (0..n)
            .map(|i| if i % 5 == 0 { 0.0 } else { next() })
            .collect();
        let y0: Vec<f64> = (0..n).map(|_| next()).collect();
        let product = |parallel_entries: usize, threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a thread pool");
            let mut y = y0.clone();
            pool.install(|| {
                multiply_add_from(
                    pattern.as_ref(),
                    &values,
                    None,
                    -0.7,
                    &x,
                    &mut y,
                    parallel_entries,
                )
            });
            y
        };
        let serial = product(usize::MAX, 1);
        let parallel = product(0, 3);
        assert_eq!(parallel, product(0, 1), "the same bits for 1 and 3 threads");
        let scale = serial.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in serial.iter().zip(&parallel) {
            assert!((a - b).abs() <= 1e-14 * scale, "{a} vs {b}");
        }
        assert_ne!(serial, y0, "the product changed y");
    }
}
