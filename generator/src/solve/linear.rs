//! Sparse direct solvers behind one small interface: analyse once, refactorize per Newton step, solve.
//!
//! [`LinearSolver::new`] performs the symbolic analysis (fill-reducing ordering, elimination
//! tree, factor structure) of a fixed pattern; [`LinearSolver::factorize`] refills the kept
//! numeric storage for new values; [`LinearSolver::solve_in_place`] solves with the current
//! factors followed by a few steps of iterative refinement against the kept matrix.
//!
//! - [`Factorization::Cholesky`]: SPD systems (the thermal phase).
//! - [`Factorization::Ldlt`]: symmetric quasi-definite saddle-point systems (the mechanical
//!   phase: displacements + contact Lagrange multipliers), faer's LDLᵀ with dynamic
//!   regularization towards the given pivot signs.
//! - [`Factorization::Lu`]: nonsymmetric systems; faer's supernodal LU with partial pivoting,
//!   columns always ordered by COLAMD.

use super::ordering::{
    approximate_minimum_degree, inverse_permutation, is_permutation, multipliers_after_neighbours,
};
use crate::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::ldlt::factor::{LdltError, LdltRegularization};
use faer::linalg::cholesky::llt::factor::LltError;
use faer::perm::PermRef;
use faer::sparse::linalg::LuError;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LdltRef, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::linalg::lu::{LuRef, NumericLu, SymbolicLu, factorize_symbolic_lu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// LDLᵀ pivots of the wrong sign or smaller than this times max|aᵢⱼ| are regularized.
pub const LDLT_REGULARIZATION_EPSILON: f64 = 1e-13;
/// Regularized LDLᵀ pivots are set to ±(this times max|aᵢⱼ|).
pub const LDLT_REGULARIZATION_DELTA: f64 = 1e-8;
/// Systems with fewer equations are factorized and solved on one thread:
/// below it the synchronisation of faer's parallel supernodal kernels costs
/// more than it gains (the micro-samples have a few thousand unknowns).
pub const PARALLEL_FACTORIZATION_MIN_EQ: usize = 20_000;
/// At most this many steps of iterative refinement follow each solve.
pub const MAX_REFINEMENT_STEPS: usize = 3;
/// Refinement stops once ‖b − Ax‖∞ ≤ this × (‖A‖∞‖x‖∞ + ‖b‖∞).
pub const REFINEMENT_TOLERANCE: f64 = 1e-14;

/// Which factorization of the global matrix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Factorization {
    /// A = PᵀLUQ, partial pivoting, any nonsingular matrix.
    Lu,
    /// A = LLᵀ, symmetric positive definite matrices; fails on a non-positive pivot.
    Cholesky,
    /// A = LDLᵀ without pivoting, symmetric quasi-definite matrices. `signs[i]` is the expected
    /// sign of equation i's pivot: +1 for displacement rows, −1 for Lagrange multiplier rows
    /// (0: no expectation). Pivots of the wrong sign or near zero are replaced by
    /// ±[`LDLT_REGULARIZATION_DELTA`]·max|aᵢⱼ| (faer's dynamic regularization). The ordering is
    /// adjusted so that each −1 equation is eliminated after all +1 equations it couples to;
    /// then, for an SPD displacement block and a full-rank constraint block, every pivot has
    /// its expected sign and no regularization occurs.
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
}

/// The factorization-specific symbolic and numeric parts.
enum Factors {
    Lu {
        symbolic: SymbolicLu<usize>,
        numeric: NumericLu<usize, f64>,
    },
    Cholesky {
        symbolic: SymbolicCholesky<usize>,
        l_values: Vec<f64>,
    },
}

/// Analyse once (symbolic), refactorize per Newton step, solve. Holds the symbolic factorization
/// and the numeric storage.
pub struct LinearSolver {
    kind: Factorization,
    pattern: SymbolicSparseColMat<usize>,
    factors: Factors,
    /// The last factorized matrix values, for iterative refinement.
    values: Vec<f64>,
    /// ‖A‖∞ of the last factorized matrix.
    norm_inf: f64,
    factorized: bool,
    /// Numeric factorization workspace, kept across refactorizations.
    workspace: Option<(StackReq, MemBuffer)>,
}

impl std::fmt::Debug for LinearSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinearSolver")
            .field("kind", &self.kind)
            .field("n_eq", &self.n_eq())
            .field("nnz", &self.values.len())
            .field("factor_nnz", &self.factor_nnz())
            .field("factorized", &self.factorized)
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
        let n = pattern.ncols();
        assert_eq!(
            pattern.nrows(),
            n,
            "LinearSolver::new: the pattern must be square"
        );
        let pattern = owned_pattern(pattern);
        if let Ordering::Custom(perm) = &ordering
            && !is_permutation(perm, n)
        {
            return Err(Error::invalid(
                "ordering",
                format!("Custom(len {})", perm.len()),
                format!("a permutation of 0..{n} (perm[new] = old)"),
            ));
        }
        let factors = match &kind {
            Factorization::Lu => {
                if matches!(ordering, Ordering::Custom(_)) {
                    return Err(Error::invalid(
                        "ordering",
                        "Custom",
                        "Ordering::Default for Factorization::Lu (faer's LU always orders its columns by COLAMD)",
                    ));
                }
                let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
                    .map_err(|e| {
                        Error::LinearSolver(format!("LU symbolic analysis failed: {e:?}"))
                    })?;
                Factors::Lu {
                    symbolic,
                    numeric: NumericLu::new(),
                }
            }
            Factorization::Cholesky | Factorization::Ldlt { .. } => {
                let perm = symmetric_permutation(pattern.as_ref(), &kind, ordering)?;
                let symbolic = match perm {
                    None => factorize_symbolic_cholesky(
                        pattern.as_ref(),
                        Side::Lower,
                        SymmetricOrdering::Amd,
                        CholeskySymbolicParams::default(),
                    ),
                    Some(perm) => {
                        let inverse = inverse_permutation(&perm);
                        factorize_symbolic_cholesky(
                            pattern.as_ref(),
                            Side::Lower,
                            SymmetricOrdering::Custom(PermRef::new_checked(&perm, &inverse, n)),
                            CholeskySymbolicParams::default(),
                        )
                    }
                }
                .map_err(|e| {
                    Error::LinearSolver(format!("Cholesky symbolic analysis failed: {e:?}"))
                })?;
                let len = symbolic.len_val();
                let mut l_values = Vec::new();
                l_values
                    .try_reserve_exact(len)
                    .map_err(|_| out_of_memory(len))?;
                l_values.resize(len, 0.0);
                Factors::Cholesky { symbolic, l_values }
            }
        };
        let nnz = pattern.row_idx().len();
        Ok(Self {
            kind,
            pattern,
            factors,
            values: vec![0.0; nnz],
            norm_inf: 0.0,
            factorized: false,
            workspace: None,
        })
    }

    /// Numeric factorization of the matrix with the analysed pattern and `values` (CSC, one per
    /// pattern entry), reusing the symbolic analysis and the numeric storage. Fails with
    /// [`Error::LinearSolver`] naming the failure (non-positive Cholesky pivot, zero LDLᵀ pivot,
    /// structurally singular LU, non-finite values).
    #[track_caller]
    pub fn factorize(&mut self, values: &[f64]) -> Result<()> {
        assert_eq!(
            values.len(),
            self.values.len(),
            "factorize: one value per pattern entry"
        );
        self.factorized = false;
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(Error::LinearSolver(format!(
                "matrix entry {i} is not finite ({})",
                values[i]
            )));
        }
        self.values.copy_from_slice(values);
        self.norm_inf = row_sum_norm(self.pattern.as_ref(), values);
        let par = self.par();
        let req = match &self.factors {
            Factors::Lu { symbolic, .. } => {
                symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default())
            }
            Factors::Cholesky { symbolic, .. } => match self.kind {
                Factorization::Ldlt { .. } => {
                    symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default())
                }
                _ => symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
            },
        };
        if self.workspace.as_ref().is_none_or(|(r, _)| *r != req) {
            self.workspace = None;
            let buffer = MemBuffer::try_new(req)
                .map_err(|_| out_of_memory(req.unaligned_bytes_required()))?;
            self.workspace = Some((req, buffer));
        }
        let stack = MemStack::new(&mut self.workspace.as_mut().expect("allocated above").1);
        let a = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        match &mut self.factors {
            Factors::Lu { symbolic, numeric } => {
                symbolic.factorize_numeric_lu(numeric, a, par, stack, Default::default()).map_err(|e| match e {
                    LuError::SymbolicSingular { index } => Error::LinearSolver(format!(
                        "LU: matrix structurally singular, no pivot found at elimination step {index}"
                    )),
                    LuError::Generic(e) => Error::LinearSolver(format!("LU factorization failed: {e:?}")),
                })?;
            }
            Factors::Cholesky { symbolic, l_values } => match &self.kind {
                Factorization::Ldlt { signs } => {
                    let amax = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                    let regularization = LdltRegularization {
                        dynamic_regularization_signs: Some(signs),
                        dynamic_regularization_delta: LDLT_REGULARIZATION_DELTA * amax,
                        dynamic_regularization_epsilon: LDLT_REGULARIZATION_EPSILON * amax,
                    };
                    let perm = symbolic.perm().map(|p| p.arrays().0.to_vec());
                    symbolic
                        .factorize_numeric_ldlt(l_values, a, Side::Lower, regularization, par, stack, Default::default())
                        .map_err(|e| {
                            let LdltError::ZeroPivot { index } = e;
                            let eq = perm.as_ref().map_or(index, |p| p[index]);
                            Error::LinearSolver(format!(
                                "LDLT: zero pivot at elimination step {index} (equation {eq}); the matrix is singular"
                            ))
                        })?;
                }
                _ => {
                    let perm = symbolic.perm().map(|p| p.arrays().0.to_vec());
                    symbolic
                        .factorize_numeric_llt(l_values, a, Side::Lower, Default::default(), par, stack, Default::default())
                        .map_err(|e| {
                            let LltError::NonPositivePivot { index } = e;
                            let eq = perm.as_ref().map_or(index, |p| p[index]);
                            Error::LinearSolver(format!(
                                "Cholesky: non-positive pivot at elimination step {index} (equation {eq}); \
                                 the matrix is not positive definite"
                            ))
                        })?;
                }
            },
        }
        self.factorized = true;
        Ok(())
    }

    /// Solves A x = rhs with the current factors, x overwriting `rhs`, followed by up to
    /// [`MAX_REFINEMENT_STEPS`] steps of iterative refinement. Fails if [`Self::factorize`] has
    /// not succeeded or the solution is not finite (numerically singular matrix).
    #[track_caller]
    pub fn solve_in_place(&self, rhs: &mut [f64]) -> Result<()> {
        let n = self.n_eq();
        assert_eq!(rhs.len(), n, "solve_in_place: rhs.len() must equal n_eq");
        if !self.factorized {
            return Err(Error::LinearSolver(
                "solve called without a successful factorization".into(),
            ));
        }
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
        for _ in 0..MAX_REFINEMENT_STEPS {
            residual.copy_from_slice(&b);
            self.subtract_product(rhs, &mut residual);
            let norm_r = residual.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let norm_x = rhs.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if norm_r <= REFINEMENT_TOLERANCE * (self.norm_inf * norm_x + norm_b)
                || norm_r > 0.5 * previous
            {
                break;
            }
            previous = norm_r;
            self.apply_inverse(&mut residual, stack);
            if residual.iter().any(|v| !v.is_finite()) {
                break;
            }
            rhs.iter_mut().zip(&residual).for_each(|(x, d)| *x += d);
        }
        Ok(())
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

    /// The fill-reducing permutation in use, `perm[new] = old` (the column permutation for LU).
    pub fn permutation(&self) -> Vec<usize> {
        match &self.factors {
            Factors::Lu { symbolic, .. } => symbolic.col_perm().arrays().0.to_vec(),
            Factors::Cholesky { symbolic, .. } => symbolic
                .perm()
                .map_or_else(|| (0..self.n_eq()).collect(), |p| p.arrays().0.to_vec()),
        }
    }

    /// Whether this solver was analysed for exactly `pattern`.
    pub fn analyses(&self, pattern: SymbolicSparseColMatRef<'_, usize>) -> bool {
        let own = self.pattern.as_ref();
        own.nrows() == pattern.nrows()
            && own.col_ptr() == pattern.col_ptr()
            && own.row_idx() == pattern.row_idx()
    }

    /// Parallel for large systems only ([`PARALLEL_FACTORIZATION_MIN_EQ`]).
    fn par(&self) -> Par {
        if self.n_eq() >= PARALLEL_FACTORIZATION_MIN_EQ {
            Par::rayon(0)
        } else {
            Par::Seq
        }
    }

    fn solve_scratch(&self) -> StackReq {
        let par = self.par();
        match &self.factors {
            Factors::Lu { symbolic, .. } => symbolic.solve_in_place_scratch::<f64>(1, par),
            Factors::Cholesky { symbolic, .. } => symbolic.solve_in_place_scratch::<f64>(1, par),
        }
    }

    /// x ← A⁻¹x with the current factors.
    fn apply_inverse(&self, x: &mut [f64], stack: &mut MemStack) {
        let n = x.len();
        let par = self.par();
        let x = MatMut::from_column_major_slice_mut(x, n, 1);
        match &self.factors {
            Factors::Lu { symbolic, numeric } => LuRef::new_unchecked(symbolic, numeric)
                .solve_in_place_with_conj(Conj::No, x, par, stack),
            Factors::Cholesky { symbolic, l_values } => match self.kind {
                Factorization::Ldlt { .. } => LdltRef::new(symbolic, l_values)
                    .solve_in_place_with_conj(Conj::No, x, par, stack),
                _ => LltRef::new(symbolic, l_values).solve_in_place_with_conj(
                    Conj::No,
                    x,
                    par,
                    stack,
                ),
            },
        }
    }

    /// r ← r − A x with the kept matrix.
    fn subtract_product(&self, x: &[f64], r: &mut [f64]) {
        let col_ptr = self.pattern.col_ptr();
        let row_idx = self.pattern.row_idx();
        for (j, &xj) in x.iter().enumerate() {
            if xj != 0.0 {
                for k in col_ptr[j]..col_ptr[j + 1] {
                    r[row_idx[k]] -= self.values[k] * xj;
                }
            }
        }
    }
}

/// The permutation handed to faer's symbolic Cholesky (`None`: faer's AMD). For LDLᵀ with
/// multiplier rows, AMD is computed here and every −1 equation moved after its +1 neighbours.
fn symmetric_permutation(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    kind: &Factorization,
    ordering: Ordering,
) -> Result<Option<Vec<usize>>> {
    let n = pattern.ncols();
    let signs = match kind {
        Factorization::Ldlt { signs } => signs,
        _ => {
            return Ok(match ordering {
                Ordering::Default => None,
                Ordering::Custom(perm) => Some(perm),
            });
        }
    };
    if signs.len() != n || signs.iter().any(|s| !(-1..=1).contains(s)) {
        return Err(Error::invalid(
            "signs",
            format!("{} entries", signs.len()),
            format!("{n} entries, each −1, 0 or +1"),
        ));
    }
    Ok(match ordering {
        Ordering::Default if !signs.contains(&-1) => None,
        Ordering::Default => Some(multipliers_after_neighbours(
            pattern,
            approximate_minimum_degree(pattern),
            signs,
        )),
        Ordering::Custom(perm) if !signs.contains(&-1) => Some(perm),
        Ordering::Custom(perm) => Some(multipliers_after_neighbours(pattern, perm, signs)),
    })
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

/// ‖A‖∞ = max row sum of |aᵢⱼ|.
fn row_sum_norm(pattern: SymbolicSparseColMatRef<'_, usize>, values: &[f64]) -> f64 {
    let mut row_sum = vec![0.0f64; pattern.nrows()];
    for (&i, v) in pattern.row_idx().iter().zip(values) {
        row_sum[i] += v.abs();
    }
    row_sum.into_iter().fold(0.0, f64::max)
}

fn out_of_memory(bytes: usize) -> Error {
    Error::LinearSolver(format!(
        "out of memory allocating {bytes} bytes for the factorization"
    ))
}
