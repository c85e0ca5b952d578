//! Sparse assembly: pattern and scatter map built once, values filled per iteration.
//!
//! [`Assembly::new`] takes, for every element, the global equation of each local
//! degree of freedom (or `None` for a prescribed one) and builds once
//! - the CSC pattern of the global matrix (the union of all element blocks plus the
//!   diagonal, rows sorted within each column; for a symmetric matrix
//!   ([`Storage::Lower`]) its lower triangle only),
//! - the scatter map: for every entry of every element block its position in the
//!   CSC values,
//! - groups of consecutive elements ([`ELEMENT_GROUP_ENTRIES`]) and a greedy
//!   coloring of the groups: no two groups of one color share an equation.
//!
//! [`Assembly::assemble`] then evaluates the element kernels color by color, the
//! groups of one color in parallel and the elements of a group one after the
//! other, each scattering straight into the global arrays. Within a color every
//! global entry receives the contributions of one group only, so every entry is
//! summed in the same order (color by color, element by element within a group,
//! and within an element in local order) whatever the number of threads: the
//! result is bit-identical for any rayon pool. Consecutive elements share most of
//! their entries, so a group's scatter finds them in cache.

use crate::{Error, Result};
use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// Marks a dropped (prescribed) local dof and a dropped scatter entry.
const DROPPED: usize = usize::MAX;
/// Marks a dropped entry in the 32-bit scatter map.
const DROPPED_ENTRY: u32 = u32::MAX;
/// The run map's rows, offsets and lengths are below this (16 bits).
const RUN_LIMIT: u16 = u16::MAX;

/// Where each element-block entry goes in the CSC values. Where every column
/// holds fewer than [`RUN_LIMIT`] entries (3D p = 2 tangents: a few
/// thousand at most), in runs of offsets within the columns ([`RunMap`]): the
/// scatter maps are the largest bookkeeping of the refined 3D levels (4.8 GB
/// of the 12.1 GB heap peak of the adaptive egg box's fourth level with one
/// 32-bit position per entry, 1.1 GB of the third level's 4.3 GB with one
/// 16-bit offset per entry).
#[derive(Debug, Clone)]
enum ScatterMap {
    /// Runs of offsets within the columns, shared by the columns of a node.
    Runs(RunMap),
    /// The position of every entry, [`DROPPED_ENTRY`] if dropped.
    Positions(Vec<u32>),
}

/// Local rows `row..row + len` of an element column go to the consecutive
/// entries `offset..offset + len` of its global column (offsets from the
/// column's start). The fields of a node have consecutive equations, and so
/// have the nodes numbered one after the other: a column of a 3D p = 2
/// mechanical element (81 rows) is a few runs, not 81 offsets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Run {
    row: u16,
    len: u16,
    offset: u16,
}

/// The scatter map in runs. Consecutive columns of an element with the same
/// offsets (the fields of one node, whose global columns have the same rows)
/// share one run list.
#[derive(Debug, Clone, Default)]
struct RunMap {
    /// The run list of every local column of every element (indexed like
    /// `Assembly::dof_eq`), [`NO_RUNS`] for a dropped column.
    column_list: Vec<u32>,
    /// Run list `l` is `runs[list_ptr[l]..list_ptr[l + 1]]`.
    list_ptr: Vec<usize>,
    runs: Vec<Run>,
}

/// Marks a dropped column in [`RunMap::column_list`].
const NO_RUNS: u32 = u32::MAX;

/// Which entries of the global matrix an [`Assembly`] stores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    /// Both triangles (any matrix).
    Full,
    /// The lower triangle of a symmetric matrix, by groups of equations (the
    /// fields of a node): a column holds the rows from its group's first on,
    /// so the diagonal blocks of the groups whole, and every other entry once,
    /// below the diagonal ([`crate::solve::linear::full_from_lower`] mirrors
    /// the entries `(i, j)` with `j` above column `i`'s first row); the
    /// element blocks' other entries are not scattered. Half the
    /// pattern, the values and the products' memory traffic of [`Storage::Full`];
    /// the linear solvers factorize the lower triangle of a symmetric matrix
    /// anyway, and their products use both triangles of it
    /// ([`crate::solve::linear::LinearSolver`]). On the 3D egg box's
    /// six-level peak (244 kPa, level 5, 163 159 mechanical equations) the
    /// full pattern held 110 M entries, 0.88 GB of row indices and 0.88 GB
    /// per tangent (docs/3d.md, "Stop 89").
    Lower,
}

/// Element-to-equation map and CSC pattern built once; values filled per iteration.
#[derive(Debug, Clone)]
pub struct Assembly {
    n_eq: usize,
    /// Which entries the pattern holds.
    storage: Storage,
    /// Shared with the linear solvers that factorize it ([`Assembly::shared_pattern`]).
    pattern: Arc<SymbolicSparseColMat<usize>>,
    /// Element e's local dofs are `dof_eq[dof_ptr[e]..dof_ptr[e + 1]]`.
    dof_ptr: Vec<usize>,
    /// Global equation of each local dof, [`DROPPED`] if prescribed.
    dof_eq: Vec<usize>,
    /// Element e's block entries (column-major) are `entry_pos[entry_ptr[e]..entry_ptr[e + 1]]`.
    entry_ptr: Vec<usize>,
    /// Where each element-block entry goes in the CSC values.
    entry_pos: ScatterMap,
    /// Group g is the elements `group_ptr[g]..group_ptr[g + 1]`.
    group_ptr: Vec<usize>,
    /// Groups of color c are `color_groups[color_ptr[c]..color_ptr[c + 1]]`, in group order.
    color_ptr: Vec<usize>,
    color_groups: Vec<usize>,
}

impl Assembly {
    /// `n_eq` unknowns; `element_eqs[e]` lists, for each local dof of element e, its global
    /// equation or None (a prescribed dof: its row and column are dropped). Several local dofs
    /// may map to the same equation (periodic or platen ties): their contributions add. The
    /// pattern is the union of all element blocks, plus the full diagonal (so that equations
    /// such as Lagrange multipliers with a zero diagonal keep a structural diagonal entry).
    ///
    /// Panics if an equation is `>= n_eq` or the pattern has `u32::MAX` entries or more
    /// ([`Assembly::try_new`] returns an error instead, and checks the memory first).
    #[track_caller]
    pub fn new(n_eq: usize, element_eqs: Vec<Vec<Option<usize>>>) -> Self {
        Self::new_stored(n_eq, element_eqs, Storage::Full)
    }

    /// [`Assembly::new`] storing `storage`'s entries.
    #[track_caller]
    pub fn new_stored(n_eq: usize, element_eqs: Vec<Vec<Option<usize>>>, storage: Storage) -> Self {
        let (dof_ptr, dof_eq) = flatten(n_eq, element_eqs);
        Self::build(n_eq, dof_ptr, dof_eq, storage).unwrap_or_else(|e| panic!("{e}"))
    }

    /// [`Assembly::new`], refused with [`Error::OutOfMemory`] where the memory left
    /// ([`crate::solve::resources::ensure_memory`]) cannot hold its pattern, scatter map and
    /// the values of one matrix ([`Assembly::bytes_for`]), and with an error (not a panic) for
    /// a pattern of `u32::MAX` entries or more. The pattern's entries are bounded first by the
    /// element blocks' (one pass over their lengths), and counted where that bound does not fit.
    /// A diverged iterate whose contact couplings span far-apart nodes can make dense blocks of
    /// hundreds of unknowns, and an assembly of them that the factorization's own guard comes
    /// too late for.
    ///
    /// Panics if an equation is `>= n_eq`.
    #[track_caller]
    pub fn try_new(n_eq: usize, element_eqs: Vec<Vec<Option<usize>>>) -> Result<Self> {
        Self::try_new_stored(n_eq, element_eqs, Storage::Full)
    }

    /// [`Assembly::try_new`] storing `storage`'s entries.
    #[track_caller]
    pub fn try_new_stored(
        n_eq: usize,
        element_eqs: Vec<Vec<Option<usize>>>,
        storage: Storage,
    ) -> Result<Self> {
        const WHAT: &str = "the assembly's pattern, scatter map and values";
        let blocks: usize = element_eqs.iter().map(|e| e.len() * e.len()).sum();
        let (dof_ptr, dof_eq) = flatten(n_eq, element_eqs);
        // Every entry is a block's or the diagonal's.
        let bound = blocks.saturating_add(n_eq).min(n_eq.saturating_mul(n_eq));
        if crate::solve::resources::ensure_memory(
            WHAT,
            Self::bytes_for(blocks, bound, dof_eq.len()),
        )
        .is_err()
        {
            let entries = count_pattern(n_eq, &dof_ptr, &dof_eq, storage);
            crate::solve::resources::ensure_memory(
                WHAT,
                Self::bytes_for(blocks, entries, dof_eq.len()),
            )?;
        }
        Self::build(n_eq, dof_ptr, dof_eq, storage)
    }

    /// Bytes an assembly of `blocks` element-block entries (`Σ n_e²`), `entries` pattern
    /// entries and `dofs` local dofs (`Σ n_e`) takes to build and use, at most: the pattern's
    /// row indices (built per chunk, then copied), the scatter map (a 32-bit position per
    /// block entry where it cannot use runs), the element-to-equation maps and one matrix's
    /// values.
    pub fn bytes_for(blocks: usize, entries: usize, dofs: usize) -> usize {
        let word = std::mem::size_of::<usize>();
        entries
            .saturating_mul(3 * word)
            .saturating_add(blocks.saturating_mul(std::mem::size_of::<u32>()))
            .saturating_add(dofs.saturating_mul(2 * word))
    }

    /// The assembly of the flattened element equations ([`flatten`]).
    fn build(
        n_eq: usize,
        dof_ptr: Vec<usize>,
        dof_eq: Vec<usize>,
        storage: Storage,
    ) -> Result<Self> {
        let (eq_elem_ptr, eq_elems) = equation_to_elements(n_eq, &dof_ptr, &dof_eq);
        let pattern = build_pattern(n_eq, &dof_ptr, &dof_eq, &eq_elem_ptr, &eq_elems, storage);
        if pattern.row_idx().len() >= DROPPED_ENTRY as usize {
            return Err(Error::LinearSolver(format!(
                "assembly pattern too large for the 32-bit scatter map ({} entries)",
                pattern.row_idx().len()
            )));
        }
        let (entry_ptr, entry_pos) = build_scatter_map(&pattern, &dof_ptr, &dof_eq);
        let group_ptr = element_groups(&dof_ptr);
        let (color_ptr, color_groups) =
            color_groups(&group_ptr, &dof_ptr, &dof_eq, &eq_elem_ptr, &eq_elems);
        Ok(Self {
            n_eq,
            storage,
            pattern: Arc::new(pattern),
            dof_ptr,
            dof_eq,
            entry_ptr,
            entry_pos,
            group_ptr,
            color_ptr,
            color_groups,
        })
    }

    /// Whether this assembly is the one [`Assembly::new_stored`] builds from
    /// `n_eq`, `element_eqs` and `storage` (same unknowns, elements,
    /// local-to-global map and stored entries: the same pattern and scatter map).
    pub fn describes(
        &self,
        n_eq: usize,
        element_eqs: &[Vec<Option<usize>>],
        storage: Storage,
    ) -> bool {
        self.n_eq == n_eq
            && self.storage == storage
            && self.dof_ptr.len() == element_eqs.len() + 1
            && element_eqs.iter().enumerate().all(|(e, eqs)| {
                let mine = &self.dof_eq[self.dof_ptr[e]..self.dof_ptr[e + 1]];
                mine.len() == eqs.len()
                    && mine
                        .iter()
                        .zip(eqs)
                        .all(|(&m, q)| q.map_or(m == DROPPED, |i| m == i))
            })
    }

    /// Which entries the pattern holds.
    pub fn storage(&self) -> Storage {
        self.storage
    }

    /// Number of unknowns (rows and columns of the global matrix).
    pub fn n_eq(&self) -> usize {
        self.n_eq
    }

    /// Number of structural nonzeros of the global matrix (length of `values`).
    pub fn nnz(&self) -> usize {
        self.pattern.row_idx().len()
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.dof_ptr.len() - 1
    }

    /// Number of local dofs of element `e` (the element block is `n_dofs × n_dofs`).
    pub fn n_dofs(&self, e: usize) -> usize {
        self.dof_ptr[e + 1] - self.dof_ptr[e]
    }

    /// Global equations of element `e`'s local dofs (`None` for prescribed ones).
    pub fn element_eqs(&self, e: usize) -> impl Iterator<Item = Option<usize>> + '_ {
        self.dof_eq[self.dof_ptr[e]..self.dof_ptr[e + 1]]
            .iter()
            .map(|&i| (i != DROPPED).then_some(i))
    }

    /// Bytes held by the scatter map (where each element-block entry goes in the values).
    pub fn scatter_map_bytes(&self) -> usize {
        match &self.entry_pos {
            ScatterMap::Runs(map) => {
                map.column_list.len() * size_of::<u32>()
                    + map.list_ptr.len() * size_of::<usize>()
                    + map.runs.len() * size_of::<Run>()
            }
            ScatterMap::Positions(positions) => positions.len() * size_of::<u32>(),
        }
    }

    /// Bytes held: the pattern (shared with the solvers that factorize it), the element-to-equation
    /// maps, the scatter map and the colors.
    pub fn storage_bytes(&self) -> usize {
        let u = size_of::<usize>();
        (self.pattern.row_idx().len() + self.pattern.col_ptr().len()) * u
            + (self.dof_ptr.len() + self.dof_eq.len() + self.entry_ptr.len()) * u
            + self.scatter_map_bytes()
            + (self.group_ptr.len() + self.color_ptr.len() + self.color_groups.len()) * u
    }

    /// Number of colors of the element groups (parallel stages of one assembly).
    pub fn n_colors(&self) -> usize {
        self.color_ptr.len() - 1
    }

    /// The CSC pattern: both triangles, or the lower one ([`Self::storage`]), rows sorted within
    /// each column, diagonal included.
    pub fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        (*self.pattern).as_ref()
    }

    /// The CSC pattern of [`Self::symbolic`], shared rather than copied (a linear solver that
    /// keeps it: [`crate::solve::linear::LinearSolver::with_pattern`]).
    pub fn shared_pattern(&self) -> Arc<SymbolicSparseColMat<usize>> {
        Arc::clone(&self.pattern)
    }

    /// The global matrix as a faer view over `values` (CSC, length [`Self::nnz`]): the stored
    /// entries ([`Self::storage`]; [`Self::full_matrix`] has both triangles).
    #[track_caller]
    pub fn matrix<'a>(
        &'a self,
        values: &'a [f64],
    ) -> faer::sparse::SparseColMatRef<'a, usize, f64> {
        faer::sparse::SparseColMatRef::new(self.symbolic(), values)
    }

    /// The global matrix with both triangles (a copy; the upper one mirrored from the lower
    /// where [`Storage::Lower`]).
    #[track_caller]
    pub fn full_matrix(&self, values: &[f64]) -> faer::sparse::SparseColMat<usize, f64> {
        let (pattern, full) = match self.storage {
            Storage::Full => (
                self.symbolic().to_owned().expect("a copy of the pattern"),
                values.to_vec(),
            ),
            Storage::Lower => crate::solve::linear::full_from_lower(self.symbolic(), values),
        };
        faer::sparse::SparseColMat::new(pattern, full)
    }

    /// Calls `local(e, k_e, r_e)` for every element in parallel (rayon), `k_e` a zeroed dense
    /// n_e×n_e column-major buffer, `r_e` a zeroed n_e vector; scatters into `values` (CSC,
    /// length nnz) and `rhs` (n_eq), both zeroed first. The result is bit-identical for any
    /// number of rayon threads (elements are processed color by color). If local closures fail,
    /// the first error in element order is returned (and `values`, `rhs` are incomplete).
    #[track_caller]
    pub fn assemble<F>(&self, values: &mut [f64], rhs: &mut [f64], local: F) -> Result<()>
    where
        F: Fn(usize, &mut [f64], &mut [f64]) -> Result<()> + Sync,
    {
        assert_eq!(
            values.len(),
            self.nnz(),
            "assemble: values.len() must equal nnz"
        );
        assert_eq!(rhs.len(), self.n_eq, "assemble: rhs.len() must equal n_eq");
        values.par_iter_mut().for_each(|v| *v = 0.0);
        rhs.fill(0.0);
        let values = SharedSlice::new(values);
        let rhs = SharedSlice::new(rhs);
        self.for_each_element_by_color(|e, k_e, r_e| {
            let n = self.n_dofs(e);
            k_e.clear();
            k_e.resize(n * n, 0.0);
            r_e.clear();
            r_e.resize(n, 0.0);
            local(e, k_e, r_e)?;
            let eqs = &self.dof_eq[self.dof_ptr[e]..self.dof_ptr[e + 1]];
            // SAFETY: elements of one color share no equation, hence no matrix entry and no rhs
            // entry; colors are processed one after the other.
            unsafe {
                match &self.entry_pos {
                    ScatterMap::Runs(map) => {
                        let col_ptr = self.pattern.col_ptr();
                        let lists = &map.column_list[self.dof_ptr[e]..self.dof_ptr[e + 1]];
                        for ((&j, &l), k) in eqs.iter().zip(lists).zip(k_e.chunks_exact(n.max(1))) {
                            if l == NO_RUNS {
                                continue;
                            }
                            let start = col_ptr[j];
                            let l = l as usize;
                            for run in &map.runs[map.list_ptr[l]..map.list_ptr[l + 1]] {
                                let (row, at) = (run.row as usize, start + run.offset as usize);
                                for (t, &k) in k[row..row + run.len as usize].iter().enumerate() {
                                    values.add(at + t, k);
                                }
                            }
                        }
                    }
                    ScatterMap::Positions(positions) => {
                        let entries = self.entry_ptr[e]..self.entry_ptr[e + 1];
                        for (&p, &k) in positions[entries].iter().zip(k_e.iter()) {
                            if p != DROPPED_ENTRY {
                                values.add(p as usize, k);
                            }
                        }
                    }
                }
                for (&i, &r) in eqs.iter().zip(r_e.iter()) {
                    if i != DROPPED {
                        rhs.add(i, r);
                    }
                }
            }
            Ok(())
        })
    }

    /// Residual only (no matrix), same guarantees as [`Self::assemble`]: `local(e, r_e)` with
    /// `r_e` a zeroed n_e vector, scattered into `rhs` (zeroed first).
    #[track_caller]
    pub fn assemble_vector<F>(&self, rhs: &mut [f64], local: F) -> Result<()>
    where
        F: Fn(usize, &mut [f64]) -> Result<()> + Sync,
    {
        assert_eq!(
            rhs.len(),
            self.n_eq,
            "assemble_vector: rhs.len() must equal n_eq"
        );
        rhs.fill(0.0);
        let rhs = SharedSlice::new(rhs);
        self.for_each_element_by_color(|e, _, r_e| {
            r_e.clear();
            r_e.resize(self.n_dofs(e), 0.0);
            local(e, r_e)?;
            let eqs = &self.dof_eq[self.dof_ptr[e]..self.dof_ptr[e + 1]];
            // SAFETY: as in `assemble`.
            unsafe {
                for (&i, &r) in eqs.iter().zip(r_e.iter()) {
                    if i != DROPPED {
                        rhs.add(i, r);
                    }
                }
            }
            Ok(())
        })
    }

    /// Runs `work(e, k_buffer, r_buffer)` on every element, color after color, the groups of
    /// one color in parallel, the elements of a group in order. Elements after the first failed
    /// one are skipped; the error of the lowest failing element is returned.
    fn for_each_element_by_color<W>(&self, work: W) -> Result<()>
    where
        W: Fn(usize, &mut Vec<f64>, &mut Vec<f64>) -> Result<()> + Sync,
    {
        let first_failure = AtomicUsize::new(usize::MAX);
        let failures: Mutex<Vec<(usize, Error)>> = Mutex::new(Vec::new());
        for c in 0..self.n_colors() {
            let groups = &self.color_groups[self.color_ptr[c]..self.color_ptr[c + 1]];
            groups.par_iter().for_each_init(
                || (Vec::new(), Vec::new()),
                |(k_e, r_e), &g| {
                    for e in self.group_ptr[g]..self.group_ptr[g + 1] {
                        if e > first_failure.load(Ordering::Relaxed) {
                            return;
                        }
                        if let Err(err) = work(e, k_e, r_e) {
                            first_failure.fetch_min(e, Ordering::Relaxed);
                            failures
                                .lock()
                                .unwrap_or_else(|p| p.into_inner())
                                .push((e, err));
                            return;
                        }
                    }
                },
            );
        }
        let failures = failures.into_inner().unwrap_or_else(|p| p.into_inner());
        match failures.into_iter().min_by_key(|(e, _)| *e) {
            Some((_, err)) => Err(err),
            None => Ok(()),
        }
    }
}

/// For each equation, the elements that contain it (each element once, in element order).
fn equation_to_elements(
    n_eq: usize,
    dof_ptr: &[usize],
    dof_eq: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let n_elements = dof_ptr.len() - 1;
    let mut last = vec![usize::MAX; n_eq];
    let mut count = vec![0usize; n_eq + 1];
    for e in 0..n_elements {
        for &i in &dof_eq[dof_ptr[e]..dof_ptr[e + 1]] {
            if i != DROPPED && last[i] != e {
                last[i] = e;
                count[i + 1] += 1;
            }
        }
    }
    for i in 0..n_eq {
        count[i + 1] += count[i];
    }
    let ptr = count;
    let mut next = ptr.clone();
    let mut elems = vec![0usize; ptr[n_eq]];
    last.fill(usize::MAX);
    for e in 0..n_elements {
        for &i in &dof_eq[dof_ptr[e]..dof_ptr[e + 1]] {
            if i != DROPPED && last[i] != e {
                last[i] = e;
                elems[next[i]] = e;
                next[i] += 1;
            }
        }
    }
    (ptr, elems)
}

/// Column j holds j and every equation of every element containing j, sorted (for
/// [`Storage::Lower`], those from its group's first on: [`PatternColumns`]). Columns are
/// built in parallel chunks and concatenated in order.
fn build_pattern(
    n_eq: usize,
    dof_ptr: &[usize],
    dof_eq: &[usize],
    eq_elem_ptr: &[usize],
    eq_elems: &[usize],
    storage: Storage,
) -> SymbolicSparseColMat<usize> {
    let chunks: Vec<(Vec<usize>, Vec<usize>)> = (0..n_eq.div_ceil(PATTERN_CHUNK))
        .into_par_iter()
        .map_init(
            || PatternColumns::new(n_eq, (dof_ptr, dof_eq), (eq_elem_ptr, eq_elems), storage),
            |walker, c| {
                let columns = c * PATTERN_CHUNK..((c + 1) * PATTERN_CHUNK).min(n_eq);
                let mut col_len = Vec::with_capacity(columns.len());
                let mut rows = Vec::new();
                for j in columns {
                    let stored = walker.rows(j);
                    col_len.push(stored.len());
                    rows.extend_from_slice(stored);
                }
                (col_len, rows)
            },
        )
        .collect();
    let mut col_ptr = Vec::with_capacity(n_eq + 1);
    col_ptr.push(0);
    let mut row_idx = Vec::with_capacity(chunks.iter().map(|(_, rows)| rows.len()).sum());
    for (col_len, rows) in chunks {
        for len in col_len {
            col_ptr.push(col_ptr.last().copied().unwrap_or(0) + len);
        }
        row_idx.extend_from_slice(&rows);
    }
    SymbolicSparseColMat::new_checked(n_eq, n_eq, col_ptr, None, row_idx)
}

/// Columns per parallel task of [`build_pattern`] and [`count_pattern`].
const PATTERN_CHUNK: usize = 2048;

/// The stored rows of the pattern's columns, one column after the other. A column holds its
/// equation and every equation of every element containing it. With [`Storage::Lower`] it
/// holds those from the first equation of its *group* on: the consecutive equations whose
/// columns have the same rows (the fields of a node, numbered one after the other), so that
/// the columns of a group keep the same rows, and one run list of the scatter map
/// ([`RunMap`]); the diagonal block of a group is stored whole (both of its triangles), every
/// other entry once, on or below the diagonal (lower rows than the group's first are the
/// mirror images of entries stored in their own columns).
struct PatternColumns<'a> {
    elements: (&'a [usize], &'a [usize]),
    equation_elements: (&'a [usize], &'a [usize]),
    storage: Storage,
    /// `marker[i] == stamp` marks the rows pushed for the current column.
    marker: Vec<usize>,
    stamp: usize,
    /// The last column visited and its group's first equation.
    last: Option<(usize, usize)>,
    /// The last column's rows (all of them, sorted), and a spare buffer.
    rows: Vec<usize>,
    spare: Vec<usize>,
}

impl<'a> PatternColumns<'a> {
    fn new(
        n_eq: usize,
        elements: (&'a [usize], &'a [usize]),
        equation_elements: (&'a [usize], &'a [usize]),
        storage: Storage,
    ) -> Self {
        Self {
            elements,
            equation_elements,
            storage,
            marker: vec![usize::MAX; n_eq],
            stamp: 0,
            last: None,
            rows: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// Every row of column `j`, sorted, into `rows`.
    fn all_rows(&mut self, j: usize, rows: &mut Vec<usize>) {
        let ((dof_ptr, dof_eq), (eq_elem_ptr, eq_elems)) = (self.elements, self.equation_elements);
        // A new stamp per column: a column may be visited again (a group's first ones, from
        // the first column of a chunk).
        self.stamp = self.stamp.wrapping_add(1);
        let stamp = self.stamp;
        rows.clear();
        self.marker[j] = stamp;
        rows.push(j);
        for &e in &eq_elems[eq_elem_ptr[j]..eq_elem_ptr[j + 1]] {
            for &i in &dof_eq[dof_ptr[e]..dof_ptr[e + 1]] {
                if i != DROPPED && self.marker[i] != stamp {
                    self.marker[i] = stamp;
                    rows.push(i);
                }
            }
        }
        rows.sort_unstable();
    }

    /// The stored rows of column `j`, sorted.
    fn rows(&mut self, j: usize) -> &[usize] {
        let mut rows = std::mem::take(&mut self.spare);
        self.all_rows(j, &mut rows);
        let first = match (self.storage, self.last) {
            (Storage::Full, _) => 0,
            // After the previous column: its group's, or a new group.
            (Storage::Lower, Some((k, group))) if k + 1 == j => {
                if self.rows == rows {
                    group
                } else {
                    j
                }
            }
            // The first column of a chunk: back while the columns are the same.
            (Storage::Lower, _) => {
                let mut first = j;
                let mut other = Vec::new();
                while first > 0 && rows.binary_search(&(first - 1)).is_ok() {
                    self.all_rows(first - 1, &mut other);
                    if other != rows {
                        break;
                    }
                    first -= 1;
                }
                first
            }
        };
        self.last = Some((j, first));
        self.spare = std::mem::replace(&mut self.rows, rows);
        let start = self.rows.partition_point(|&i| i < first);
        &self.rows[start..]
    }
}

/// The number of entries of [`build_pattern`]'s pattern, counted column by column without
/// keeping them.
fn count_pattern(n_eq: usize, dof_ptr: &[usize], dof_eq: &[usize], storage: Storage) -> usize {
    let (eq_elem_ptr, eq_elems) = equation_to_elements(n_eq, dof_ptr, dof_eq);
    (0..n_eq.div_ceil(PATTERN_CHUNK))
        .into_par_iter()
        .map_init(
            || PatternColumns::new(n_eq, (dof_ptr, dof_eq), (&eq_elem_ptr, &eq_elems), storage),
            |walker, c| {
                let columns = c * PATTERN_CHUNK..((c + 1) * PATTERN_CHUNK).min(n_eq);
                columns.map(|j| walker.rows(j).len()).sum::<usize>()
            },
        )
        .sum()
}

/// The element equations in one array (`dof_eq`, [`DROPPED`] for `None`) with each
/// element's start (`dof_ptr`).
///
/// Panics if an equation is `>= n_eq`.
#[track_caller]
fn flatten(n_eq: usize, element_eqs: Vec<Vec<Option<usize>>>) -> (Vec<usize>, Vec<usize>) {
    let n_elements = element_eqs.len();
    let mut dof_ptr = Vec::with_capacity(n_elements + 1);
    dof_ptr.push(0);
    let mut dof_eq = Vec::with_capacity(element_eqs.iter().map(Vec::len).sum());
    for (e, eqs) in element_eqs.iter().enumerate() {
        for &eq in eqs {
            match eq {
                Some(i) => {
                    assert!(
                        i < n_eq,
                        "element {e}: equation {i} out of range (n_eq = {n_eq})"
                    );
                    dof_eq.push(i);
                }
                None => dof_eq.push(DROPPED),
            }
        }
        dof_ptr.push(dof_eq.len());
    }
    (dof_ptr, dof_eq)
}

/// Where every entry (column-major) of every element block goes in the CSC values: runs of
/// offsets within the columns where every column and every element is short enough for 16
/// bits, positions otherwise ([`ScatterMap`]).
fn build_scatter_map(
    pattern: &SymbolicSparseColMat<usize>,
    dof_ptr: &[usize],
    dof_eq: &[usize],
) -> (Vec<usize>, ScatterMap) {
    let n_elements = dof_ptr.len() - 1;
    let mut entry_ptr = Vec::with_capacity(n_elements + 1);
    entry_ptr.push(0);
    for e in 0..n_elements {
        let n = dof_ptr[e + 1] - dof_ptr[e];
        entry_ptr.push(entry_ptr[e] + n * n);
    }
    let col_ptr = pattern.col_ptr();
    let longest = (0..pattern.ncols())
        .map(|j| col_ptr[j + 1] - col_ptr[j])
        .chain((0..n_elements).map(|e| dof_ptr[e + 1] - dof_ptr[e]))
        .max()
        .unwrap_or(0);
    let map = if longest < RUN_LIMIT as usize {
        ScatterMap::Runs(fill_run_map(pattern, dof_ptr, dof_eq))
    } else {
        ScatterMap::Positions(fill_positions(pattern, dof_ptr, dof_eq, &entry_ptr))
    };
    (entry_ptr, map)
}

/// Calls `column(b, j, within)` for every kept local column `b` (equation `j`) of the element
/// with local equations `eqs`, `within[a]` the index within global column `j` of the entry of
/// local row `a` ([`DROPPED`] for a dropped row, and for a row above the column's first:
/// [`Storage::Lower`]'s entries above the diagonal blocks). `rows` and `within` are scratch.
fn for_each_element_column(
    pattern: &SymbolicSparseColMat<usize>,
    eqs: &[usize],
    (rows, within): &mut (Vec<usize>, Vec<usize>),
    mut column: impl FnMut(usize, usize, &[usize]),
) {
    let (col_ptr, row_idx) = (pattern.col_ptr(), pattern.row_idx());
    let n = eqs.len();
    // The element's rows in increasing equation: each column is then
    // searched forwards from the previous row's entry.
    rows.clear();
    rows.extend((0..n).filter(|&a| eqs[a] != DROPPED));
    rows.sort_unstable_by_key(|&a| eqs[a]);
    within.clear();
    within.resize(n, DROPPED);
    let mut previous: Option<&[usize]> = None;
    for (b, &j) in eqs.iter().enumerate() {
        if j == DROPPED {
            continue;
        }
        let global = &row_idx[col_ptr[j]..col_ptr[j + 1]];
        // A column with the rows of the last one (the fields of a node): the same offsets.
        if previous == Some(global) {
            column(b, j, within);
            continue;
        }
        previous = Some(global);
        let mut from = 0;
        for &a in rows.iter() {
            if eqs[a] < global[0] {
                within[a] = DROPPED;
                continue;
            }
            let k = from + gallop(&global[from..], eqs[a]);
            assert!(
                global.get(k) == Some(&eqs[a]),
                "element entry missing from the pattern"
            );
            within[a] = k;
            from = k;
        }
        column(b, j, within);
    }
}

/// The scatter map in runs ([`RunMap`]): built per element in parallel, concatenated in order.
fn fill_run_map(
    pattern: &SymbolicSparseColMat<usize>,
    dof_ptr: &[usize],
    dof_eq: &[usize],
) -> RunMap {
    let n_elements = dof_ptr.len() - 1;
    // Per element: each column's list (local index) and the lists' runs.
    let per_element: Vec<(Vec<u32>, Vec<usize>, Vec<Run>)> = (0..n_elements)
        .into_par_iter()
        .map_init(
            || ((Vec::new(), Vec::new()), Vec::new()),
            |(scratch, previous), e| {
                let eqs = &dof_eq[dof_ptr[e]..dof_ptr[e + 1]];
                let mut lists = vec![NO_RUNS; eqs.len()];
                let mut ends: Vec<usize> = Vec::new();
                let mut runs: Vec<Run> = Vec::new();
                for_each_element_column(pattern, eqs, scratch, |b, _, within| {
                    // The same offsets as the element's previous kept column: its list.
                    if !ends.is_empty() && previous.as_slice() == within {
                        lists[b] = (ends.len() - 1) as u32;
                        return;
                    }
                    let mut a = 0;
                    while a < within.len() {
                        if within[a] == DROPPED {
                            a += 1;
                            continue;
                        }
                        let mut len = 1;
                        while a + len < within.len() && within[a + len] == within[a] + len {
                            len += 1;
                        }
                        runs.push(Run {
                            row: a as u16,
                            len: len as u16,
                            offset: within[a] as u16,
                        });
                        a += len;
                    }
                    ends.push(runs.len());
                    lists[b] = (ends.len() - 1) as u32;
                    previous.clear();
                    previous.extend_from_slice(within);
                });
                (lists, ends, runs)
            },
        )
        .collect();
    let mut map = RunMap {
        column_list: Vec::with_capacity(dof_eq.len()),
        list_ptr: vec![0],
        runs: Vec::with_capacity(per_element.iter().map(|(_, _, r)| r.len()).sum()),
    };
    for (lists, ends, runs) in per_element {
        let (first_list, first_run) = (map.list_ptr.len() - 1, map.runs.len());
        assert!(
            first_list + ends.len() < NO_RUNS as usize,
            "assembly scatter map too large for 32-bit run lists"
        );
        map.column_list.extend(lists.iter().map(|&l| {
            if l == NO_RUNS {
                l
            } else {
                l + first_list as u32
            }
        }));
        map.list_ptr.extend(ends.iter().map(|&end| first_run + end));
        map.runs.extend_from_slice(&runs);
    }
    map
}

/// The position in the CSC values of every entry (column-major) of every element block,
/// [`DROPPED_ENTRY`] where the row or the column is prescribed.
fn fill_positions(
    pattern: &SymbolicSparseColMat<usize>,
    dof_ptr: &[usize],
    dof_eq: &[usize],
    entry_ptr: &[usize],
) -> Vec<u32> {
    let n_elements = dof_ptr.len() - 1;
    let mut entry_pos = vec![DROPPED_ENTRY; entry_ptr[n_elements]];
    // Split the map into per-element slices, then fill them in parallel.
    let mut blocks = Vec::with_capacity(n_elements);
    let mut rest = entry_pos.as_mut_slice();
    for e in 0..n_elements {
        let (head, tail) = rest.split_at_mut(entry_ptr[e + 1] - entry_ptr[e]);
        blocks.push(head);
        rest = tail;
    }
    let col_ptr = pattern.col_ptr();
    blocks.into_par_iter().enumerate().for_each_init(
        || (Vec::new(), Vec::new()),
        |scratch, (e, block)| {
            let eqs = &dof_eq[dof_ptr[e]..dof_ptr[e + 1]];
            let n = eqs.len();
            for_each_element_column(pattern, eqs, scratch, |b, j, within| {
                for (a, &k) in within.iter().enumerate() {
                    if k != DROPPED {
                        block[b * n + a] = (col_ptr[j] + k) as u32;
                    }
                }
            });
        },
    );
    entry_pos
}

/// The index of the first entry `≥ x` of the sorted `s`, by galloping from
/// its start (cost logarithmic in the index found, not in `s.len()`).
fn gallop(s: &[usize], x: usize) -> usize {
    let mut hi = 1;
    while hi < s.len() && s[hi - 1] < x {
        hi *= 2;
    }
    let lo = hi / 2;
    let hi = hi.min(s.len());
    lo + s[lo..hi].partition_point(|&r| r < x)
}

/// Block entries a group of consecutive elements holds at most, unless one element holds more
/// (about 30 elements of a 3D p = 2 mechanical block, 6 561 entries; a contact element may hold
/// 10⁵): a group is scattered by one thread, element after element, and consecutive elements
/// share most of their entries. Processed color by color instead, element by element, the
/// mechanical scatter of the 72 kPa egg box's level 3 took 0.92 s of thread time per tangent;
/// in element order on one thread, 0.33 s.
pub const ELEMENT_GROUP_ENTRIES: usize = 200_000;

/// Groups are smaller where that leaves fewer than this many groups, so that small assemblies
/// still spread over the threads.
const MIN_ELEMENT_GROUPS: usize = 64;

/// The groups of consecutive elements ([`ELEMENT_GROUP_ENTRIES`]): group g is the elements
/// `group_ptr[g]..group_ptr[g + 1]`. Depends on the elements only, not on the threads.
fn element_groups(dof_ptr: &[usize]) -> Vec<usize> {
    let n_elements = dof_ptr.len() - 1;
    let entries = |e: usize| (dof_ptr[e + 1] - dof_ptr[e]).pow(2);
    let total: usize = (0..n_elements).map(entries).sum();
    let limit = ELEMENT_GROUP_ENTRIES.min(total.div_ceil(MIN_ELEMENT_GROUPS));
    let mut group_ptr = vec![0];
    let mut held = 0;
    for e in 0..n_elements {
        if held > 0 && held + entries(e) > limit {
            group_ptr.push(e);
            held = 0;
        }
        held += entries(e);
    }
    if n_elements > 0 {
        group_ptr.push(n_elements);
    }
    group_ptr
}

/// Greedy coloring of the element groups, the groups with the most entries first (group order
/// among equals): a group takes the smallest color not used by an already-colored group sharing
/// one of its equations. Large groups (contact elements couple a face's nodes with those of the
/// faces it projects onto) are the most constrained; colored last, they ended in the last colors
/// with few other elements, too little work per color to keep the threads busy.
fn color_groups(
    group_ptr: &[usize],
    dof_ptr: &[usize],
    dof_eq: &[usize],
    eq_elem_ptr: &[usize],
    eq_elems: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let n_groups = group_ptr.len().saturating_sub(1);
    let mut group_of = vec![0; dof_ptr.len() - 1];
    for g in 0..n_groups {
        group_of[group_ptr[g]..group_ptr[g + 1]].fill(g);
    }
    let entries = |g: usize| -> usize {
        (group_ptr[g]..group_ptr[g + 1])
            .map(|e| (dof_ptr[e + 1] - dof_ptr[e]).pow(2))
            .sum()
    };
    let mut order: Vec<usize> = (0..n_groups).collect();
    order.sort_by_cached_key(|&g| std::cmp::Reverse(entries(g)));
    let mut color = vec![usize::MAX; n_groups];
    // forbidden[c] == step: color c is taken near the group colored at that step.
    let mut forbidden: Vec<usize> = Vec::new();
    let mut n_colors = 0;
    for (step, &g) in order.iter().enumerate() {
        for &i in &dof_eq[dof_ptr[group_ptr[g]]..dof_ptr[group_ptr[g + 1]]] {
            if i == DROPPED {
                continue;
            }
            for &f in &eq_elems[eq_elem_ptr[i]..eq_elem_ptr[i + 1]] {
                let h = group_of[f];
                if color[h] != usize::MAX {
                    forbidden[color[h]] = step;
                }
            }
        }
        let c = (0..n_colors)
            .find(|&c| forbidden[c] != step)
            .unwrap_or(n_colors);
        if c == n_colors {
            n_colors += 1;
            forbidden.push(usize::MAX);
        }
        color[g] = c;
    }
    let mut color_ptr = vec![0usize; n_colors + 1];
    for &c in &color {
        color_ptr[c + 1] += 1;
    }
    for c in 0..n_colors {
        color_ptr[c + 1] += color_ptr[c];
    }
    let mut next = color_ptr.clone();
    let mut color_groups = vec![0usize; n_groups];
    for (g, &c) in color.iter().enumerate() {
        color_groups[next[c]] = g;
        next[c] += 1;
    }
    (color_ptr, color_groups)
}

/// A mutable slice shared between rayon workers that write disjoint entries.
struct SharedSlice {
    ptr: *mut f64,
    len: usize,
}

// SAFETY: access goes through `add`, whose callers guarantee disjoint entries per thread.
unsafe impl Sync for SharedSlice {}
unsafe impl Send for SharedSlice {}

impl SharedSlice {
    fn new(slice: &mut [f64]) -> Self {
        Self {
            ptr: slice.as_mut_ptr(),
            len: slice.len(),
        }
    }

    /// Adds `v` to entry `i`.
    ///
    /// # Safety
    /// No other thread may access entry `i` concurrently, and the borrowed slice must outlive `self`.
    #[inline]
    unsafe fn add(&self, i: usize, v: f64) {
        debug_assert!(i < self.len);
        // SAFETY: in bounds (positions come from the pattern); exclusive per the caller's contract.
        unsafe { *self.ptr.add(i) += v };
    }
}

#[cfg(test)]
mod tests {
    use super::{Assembly, gallop};

    /// Groups are consecutive elements within the entry bound (a larger element alone), each
    /// as full as the bound allows; groups of one color
    /// share no equation; large groups are colored first, so that every color that holds one
    /// also holds small groups (colored in order, with the large ones last, colors held large
    /// groups only).
    #[test]
    fn groups_are_bounded_disjoint_within_a_color_and_mixed() {
        let nodes = 10_000;
        // A chain of two-node elements, then five elements over 101 nodes every 100 nodes.
        let mut element_eqs: Vec<Vec<Option<usize>>> =
            (0..nodes - 1).map(|i| vec![Some(i), Some(i + 1)]).collect();
        let small = element_eqs.len();
        element_eqs.extend((0..5).map(|k| (100 * k..=100 * k + 100).map(Some).collect()));
        let assembly = Assembly::new(nodes, element_eqs.clone());
        let groups = &assembly.group_ptr;
        assert_eq!((groups[0], *groups.last().unwrap()), (0, element_eqs.len()));
        let entries = |e: usize| element_eqs[e].len().pow(2);
        let total: usize = (0..element_eqs.len()).map(entries).sum();
        let limit = total.div_ceil(super::MIN_ELEMENT_GROUPS);
        for g in groups.windows(3) {
            let held: usize = (g[0]..g[1]).map(entries).sum();
            assert!(
                g[1] - g[0] == 1 || held <= limit,
                "group {g:?}: {held} entries"
            );
            // Full: the next element would not have fitted.
            assert!(
                held + entries(g[1]) > limit,
                "group {g:?} could hold one more"
            );
        }
        let mut seen = vec![false; groups.len() - 1];
        for c in 0..assembly.n_colors() {
            let members = &assembly.color_groups[assembly.color_ptr[c]..assembly.color_ptr[c + 1]];
            let mut used = vec![false; nodes];
            for &g in members {
                assert!(!seen[g], "group {g} in two colors");
                seen[g] = true;
                for e in groups[g]..groups[g + 1] {
                    // An equation twice within one group is fine; across groups, not.
                    let eqs: std::collections::BTreeSet<usize> =
                        element_eqs[e].iter().flatten().copied().collect();
                    for eq in eqs {
                        assert!(
                            !used[eq] || (groups[g]..e).any(|f| element_eqs[f].contains(&Some(eq))),
                            "color {c}: equation {eq} in two groups"
                        );
                        used[eq] = true;
                    }
                }
            }
            let large = |g: &usize| groups[*g] >= small;
            if members.iter().any(large) {
                assert!(
                    !members.iter().all(large),
                    "color {c} holds large groups only"
                );
            }
        }
        assert!(seen.iter().all(|&s| s), "every group has a color");
    }

    /// Galloping finds what a binary search over the whole slice finds, at
    /// every position, for present and absent values and repeated entries.
    #[test]
    fn gallop_agrees_with_a_binary_search() {
        let s: Vec<usize> = vec![0, 2, 2, 3, 7, 8, 8, 8, 15, 40, 41, 100];
        for x in 0..=101 {
            assert_eq!(gallop(&s, x), s.partition_point(|&r| r < x), "x = {x}");
        }
        assert_eq!(gallop(&[], 5), 0);
        assert_eq!(gallop(&[5], 5), 0);
        assert_eq!(gallop(&[5], 6), 1);
    }
}
