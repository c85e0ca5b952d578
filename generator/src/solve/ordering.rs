//! Fill-reducing orderings for the sparse Cholesky and LDLᵀ factorizations of
//! [`super::linear`]: geometric nested dissection, faer's AMD, the saddle-point
//! adjustment that eliminates each Lagrange multiplier after its displacements, and the
//! size of the factor an order gives ([`factor_entries`], to choose between them).
//!
//! Permutations follow faer's convention: `perm[new] = old`, i.e. `perm[k]` is the
//! original equation eliminated k-th.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::simplicial::{
    prefactorize_symbolic_cholesky, prefactorize_symbolic_cholesky_scratch,
};

/// Vertex sets at most this large are not bisected further but ordered by AMD.
pub const LEAF_SIZE: usize = 64;

/// Geometric nested dissection from the coordinates of each equation's node (tensor-product
/// patches give regular grids; several patches allowed): recursive bisection along the longest
/// extent at the median, separator = the vertices of one half adjacent (in the matrix graph) to
/// the other half (the smaller of the two candidate separators), separators numbered last,
/// leaves of at most [`LEAF_SIZE`] vertices ordered by faer's AMD. Equations sharing a node
/// (several fields, multipliers) share coordinates; the cut is moved to the nearest change of
/// coordinate so that they stay on one side. Returns `perm` with `perm[new] = old`.
///
/// The graph is that of `A + Aᵀ` (entries in either triangle connect two equations), so the
/// pattern need not be structurally symmetric. The result is a valid permutation for any input,
/// including non-finite coordinates (they only degrade the quality of the ordering).
///
/// Panics if `pattern` is not square or `coords.len()` differs from its dimension.
#[track_caller]
pub fn nested_dissection(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
) -> Vec<usize> {
    let n = pattern.ncols();
    assert_eq!(
        pattern.nrows(),
        n,
        "nested_dissection: the pattern must be square"
    );
    assert_eq!(
        coords.len(),
        n,
        "nested_dissection: one coordinate triple per equation"
    );
    let mut dissection = Dissection {
        pattern,
        coords,
        side: vec![Side::Outside; n],
        local: vec![usize::MAX; n],
        order: Vec::with_capacity(n),
    };
    dissection.dissect((0..n).collect());
    debug_assert!(is_permutation(&dissection.order, n));
    dissection.order
}

/// True if `perm` holds every index `0..n` exactly once.
pub fn is_permutation(perm: &[usize], n: usize) -> bool {
    if perm.len() != n {
        return false;
    }
    let mut seen = vec![false; n];
    perm.iter()
        .all(|&i| i < n && !std::mem::replace(&mut seen[i], true))
}

/// The inverse permutation: `inverse[old] = new`.
#[track_caller]
pub fn inverse_permutation(perm: &[usize]) -> Vec<usize> {
    let mut inverse = vec![usize::MAX; perm.len()];
    for (new, &old) in perm.iter().enumerate() {
        assert!(
            old < perm.len() && inverse[old] == usize::MAX,
            "not a permutation"
        );
        inverse[old] = new;
    }
    inverse
}

/// Approximate minimum degree ordering of `A + Aᵀ` by faer, `perm[new] = old`.
#[track_caller]
pub fn approximate_minimum_degree(pattern: SymbolicSparseColMatRef<'_, usize>) -> Vec<usize> {
    let n = pattern.ncols();
    assert_eq!(
        pattern.nrows(),
        n,
        "approximate_minimum_degree: the pattern must be square"
    );
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let nnz = pattern.compute_nnz();
    let mut buffer = MemBuffer::new(amd::order_maybe_unsorted_scratch::<usize>(n, nnz));
    let ordered = amd::order_maybe_unsorted(
        &mut perm,
        &mut perm_inv,
        pattern,
        amd::Control::default(),
        MemStack::new(&mut buffer),
    );
    match ordered {
        Ok(_) => perm,
        // Index overflow cannot happen with usize indices; fall back to the natural order.
        Err(_) => (0..n).collect(),
    }
}

/// Entries of the Cholesky factor `L` (diagonal included) of the symmetric matrix whose lower
/// triangle has the pattern of `pattern`'s lower triangle, eliminated in the order `perm`
/// (`perm[new] = old`): the sum of the column counts of its elimination tree (faer's
/// `prefactorize_symbolic_cholesky`, linear in the entries), without the symbolic
/// factorization itself. The supernodal factor stores somewhat more (its dense blocks).
///
/// Panics if `pattern` is not square or `perm` is not a permutation of its equations.
#[track_caller]
pub fn factor_entries(pattern: SymbolicSparseColMatRef<'_, usize>, perm: &[usize]) -> usize {
    let n = pattern.ncols();
    assert_eq!(
        pattern.nrows(),
        n,
        "factor_entries: the pattern must be square"
    );
    let position = inverse_permutation(perm);
    assert_eq!(
        position.len(),
        n,
        "factor_entries: one position per equation"
    );
    // The permuted matrix's upper triangle: entry (i ≥ j) goes to column max, row min.
    let mut count = vec![0usize; n + 1];
    let lower = |j: usize| {
        pattern.row_idx()[pattern.col_range(j)]
            .iter()
            .copied()
            .filter(move |&i| i >= j)
    };
    for j in 0..n {
        for i in lower(j) {
            count[position[i].max(position[j]) + 1] += 1;
        }
    }
    for k in 0..n {
        count[k + 1] += count[k];
    }
    let mut next = count.clone();
    let mut row_idx = vec![0usize; count[n]];
    for j in 0..n {
        for i in lower(j) {
            let (a, b) = (position[i], position[j]);
            let col = a.max(b);
            row_idx[next[col]] = a.min(b);
            next[col] += 1;
        }
    }
    let upper = SymbolicSparseColMatRef::new_unsorted_checked(n, n, &count, None, &row_idx);
    let mut etree = vec![0isize; n];
    let mut col_counts = vec![0usize; n];
    let mut buffer = MemBuffer::new(prefactorize_symbolic_cholesky_scratch::<usize>(
        n,
        row_idx.len(),
    ));
    prefactorize_symbolic_cholesky(
        &mut etree,
        &mut col_counts,
        upper,
        MemStack::new(&mut buffer),
    );
    col_counts.iter().sum()
}

/// Reorders `perm` (`perm[new] = old`) so that every equation with sign −1 comes after all
/// equations with sign +1 it is coupled to (and after its own original position); all other
/// equations keep their relative order. Eliminating each Lagrange multiplier after the
/// displacements it constrains makes every leading block of a saddle-point matrix
/// [K Bᵀ; B 0] (K SPD, B of full row rank) nonsingular with the expected inertia.
pub fn multipliers_after_neighbours(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    perm: Vec<usize>,
    signs: &[i8],
) -> Vec<usize> {
    let position = inverse_permutation(&perm);
    let mut key: Vec<(usize, u8, usize)> = Vec::with_capacity(perm.len());
    for (new, &old) in perm.iter().enumerate() {
        if signs[old] == -1 {
            let mut last = new;
            for &r in &pattern.row_idx()[pattern.col_range(old)] {
                if signs[r] == 1 {
                    last = last.max(position[r]);
                }
            }
            key.push((last, 1, new));
        } else {
            key.push((new, 0, new));
        }
    }
    key.sort_unstable();
    key.into_iter().map(|(_, _, new)| perm[new]).collect()
}

/// Membership of a vertex in the bisection being processed.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Outside,
    Left,
    Right,
    LeftSeparator,
    RightSeparator,
}

struct Dissection<'a> {
    pattern: SymbolicSparseColMatRef<'a, usize>,
    coords: &'a [[f64; 3]],
    side: Vec<Side>,
    local: Vec<usize>,
    order: Vec<usize>,
}

impl Dissection<'_> {
    /// Appends the nested-dissection order of `set` to `self.order`.
    fn dissect(&mut self, mut set: Vec<usize>) {
        if set.len() <= LEAF_SIZE {
            self.leaf(&set);
            return;
        }
        let Some(axis) = self.longest_axis(&set) else {
            self.leaf(&set);
            return;
        };
        let coords = self.coords;
        set.sort_unstable_by(|&u, &v| coords[u][axis].total_cmp(&coords[v][axis]).then(u.cmp(&v)));
        let cut = cut_position(&set, |v| coords[v][axis]);
        let (left, right) = set.split_at(cut);
        for &v in left {
            self.side[v] = Side::Left;
        }
        for &v in right {
            self.side[v] = Side::Right;
        }
        // Mark the vertices of each half adjacent to the other half (edges in either triangle).
        for &v in &set {
            let v_left = matches!(self.side[v], Side::Left | Side::LeftSeparator);
            for &r in &self.pattern.row_idx()[self.pattern.col_range(v)] {
                let r_left = match self.side[r] {
                    Side::Outside => continue,
                    s => matches!(s, Side::Left | Side::LeftSeparator),
                };
                if v_left != r_left {
                    let (l, rr) = if v_left { (v, r) } else { (r, v) };
                    self.side[l] = Side::LeftSeparator;
                    self.side[rr] = Side::RightSeparator;
                }
            }
        }
        let n_left_sep = left
            .iter()
            .filter(|&&v| self.side[v] == Side::LeftSeparator)
            .count();
        let n_right_sep = right
            .iter()
            .filter(|&&v| self.side[v] == Side::RightSeparator)
            .count();
        let separator_side = if n_left_sep <= n_right_sep {
            Side::LeftSeparator
        } else {
            Side::RightSeparator
        };
        let (mut first, mut second, mut separator) = (Vec::new(), Vec::new(), Vec::new());
        for (half, out) in [(left, &mut first), (right, &mut second)] {
            for &v in half {
                if self.side[v] == separator_side {
                    separator.push(v);
                } else {
                    out.push(v);
                }
            }
        }
        for &v in &set {
            self.side[v] = Side::Outside;
        }
        drop(set);
        self.dissect(first);
        self.dissect(second);
        self.order.extend_from_slice(&separator);
    }

    /// The axis of largest finite extent of `set`, or None if all coordinates coincide.
    fn longest_axis(&self, set: &[usize]) -> Option<usize> {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &v in set {
            for d in 0..3 {
                let x = self.coords[v][d];
                if x.is_finite() {
                    lo[d] = lo[d].min(x);
                    hi[d] = hi[d].max(x);
                }
            }
        }
        let extent = |d: usize| if hi[d] > lo[d] { hi[d] - lo[d] } else { 0.0 };
        let axis = (0..3).max_by(|&a, &b| extent(a).total_cmp(&extent(b)))?;
        (extent(axis) > 0.0).then_some(axis)
    }

    /// Orders a small vertex set by AMD on its induced subgraph.
    fn leaf(&mut self, set: &[usize]) {
        if set.len() <= 2 {
            self.order.extend_from_slice(set);
            return;
        }
        for (k, &v) in set.iter().enumerate() {
            self.local[v] = k;
        }
        let mut col_ptr = Vec::with_capacity(set.len() + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::new();
        for &v in set {
            for &r in &self.pattern.row_idx()[self.pattern.col_range(v)] {
                let k = self.local[r];
                if k != usize::MAX {
                    row_idx.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        for &v in set {
            self.local[v] = usize::MAX;
        }
        let sub = SymbolicSparseColMatRef::new_unsorted_checked(
            set.len(),
            set.len(),
            &col_ptr,
            None,
            &row_idx,
        );
        let perm = approximate_minimum_degree(sub);
        self.order.extend(perm.iter().map(|&k| set[k]));
    }
}

/// Index splitting the sorted `set` into two halves: the change of coordinate nearest to the
/// middle within the central half of the set, else the middle itself (so both halves are
/// non-empty and the recursion depth stays logarithmic).
fn cut_position(set: &[usize], coordinate: impl Fn(usize) -> f64) -> usize {
    let m = set.len();
    let mid = m / 2;
    let changes = |k: usize| {
        coordinate(set[k - 1])
            .total_cmp(&coordinate(set[k]))
            .is_lt()
    };
    for offset in 0..=m / 4 {
        if mid - offset >= 1 && changes(mid - offset) {
            return mid - offset;
        }
        if mid + offset < m && changes(mid + offset) {
            return mid + offset;
        }
    }
    mid
}
