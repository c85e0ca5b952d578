//! Fill-reducing orderings for the sparse Cholesky and LDLᵀ factorizations of
//! [`super::linear`]: nested dissection (METIS), faer's AMD, the saddle-point
//! adjustment that eliminates each Lagrange multiplier after its displacements, and the
//! size of the factor an order gives ([`factor_entries`], to choose between them).
//!
//! Permutations follow faer's convention: `perm[new] = old`, i.e. `perm[k]` is the
//! original equation eliminated k-th.

use std::collections::HashMap;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::SymbolicSparseColMatRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::simplicial::{
    prefactorize_symbolic_cholesky, prefactorize_symbolic_cholesky_scratch,
};
use rayon::prelude::*;

/// Nested dissection of the matrix graph by METIS (`METIS_NodeND`, multilevel vertex
/// separators refined by Fiduccia–Mattheyses; its own seeded generator, so the order is
/// reproducible), on the graph of the *nodes*: equations with the same coordinates (the fields
/// and multipliers of one node) are one vertex, weighted by their number, and are eliminated
/// consecutively. On the adaptive 3D egg box its factor is 36 % smaller than AMD's and 55 %
/// smaller than that of a geometric bisection at the median of the coordinates (level 4,
/// docs/3d.md, "Stop 40"): METIS places the separators where the refined band is thin.
///
/// The graph is that of `A + Aᵀ` (entries in either triangle connect two equations), so the
/// pattern need not be structurally symmetric. The result is a valid permutation for any input,
/// including non-finite coordinates (they only group equations differently); where METIS cannot
/// order the graph (more than `i32::MAX` edges, or an error) the order is AMD's.
/// Returns `perm` with `perm[new] = old`.
///
/// Panics if `pattern` is not square or `coords.len()` differs from its dimension.
#[track_caller]
pub fn nested_dissection(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
) -> Vec<usize> {
    node_order(pattern, coords, |graph| vec![graph.metis_order()]).remove(0)
}

/// Systems from this many equations take AMD's order of their nodes' graph
/// ([`node_minimum_degree`]) as the alternative to METIS's in [`node_orders`]; smaller ones
/// AMD's of their equations (its cost is small there, and the order the same as before).
pub const NODE_AMD_MIN_EQUATIONS: usize = 20_000;

/// The candidate orders of a system whose equations sit at nodes (`coords`): METIS's nested
/// dissection of the nodes ([`nested_dissection`]) and an AMD order (of the nodes from
/// [`NODE_AMD_MIN_EQUATIONS`] equations, else of the equations), for
/// [`super::linear::Ordering::Fewest`]; the nodes' graph is built once for both. One
/// candidate, AMD's of the equations, where that graph cannot be built.
///
/// Panics if `pattern` is not square or `coords.len()` differs from its dimension.
#[track_caller]
pub fn node_orders(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
) -> Vec<Vec<usize>> {
    let of_nodes = pattern.ncols() >= NODE_AMD_MIN_EQUATIONS;
    node_order(pattern, coords, |graph| candidate_orders(graph, of_nodes))
}

/// An order of the nodes (`perm[new] = old`), or `None` for AMD's order of the equations.
type NodeOrder = Option<Vec<usize>>;

/// The node orders of [`node_orders`]: METIS's, and AMD's if `of_nodes` (else `None`).
fn candidate_orders(graph: NodeGraph, of_nodes: bool) -> Vec<NodeOrder> {
    if of_nodes {
        // The two orders at once (METIS's is serial, and so is AMD's).
        let (metis, amd) = rayon::join(|| graph.clone().metis_order(), || graph.amd_order());
        vec![metis, Some(amd)]
    } else {
        vec![graph.metis_order(), None]
    }
}

/// AMD's order of the graph of the nodes (as [`nested_dissection`] groups the equations),
/// each node's equations eliminated consecutively: AMD on the equations' graph took 2.2 s of
/// the symbolic analysis of the 72 kPa egg box's level 4 (96 334 equations, 57 M entries; its
/// nodes' graph has about a tenth of the entries). The order is AMD's of the equations
/// where the nodes' graph does not fit 32-bit indices. Returns `perm` with `perm[new] = old`.
///
/// Panics if `pattern` is not square or `coords.len()` differs from its dimension.
#[track_caller]
pub fn node_minimum_degree(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
) -> Vec<usize> {
    node_order(pattern, coords, |graph| vec![Some(graph.amd_order())]).remove(0)
}

/// The node orders of one mesh's system ([`node_orders`]), kept for the mesh's other systems:
/// the other phase's (the thermal phase's nodes are the mechanical phase's, one equation each
/// instead of three, and their graph the same but for the contact's couplings). Ordering the
/// same nodes again took 2.0 s of the 72 kPa egg box's level 4 (METIS and AMD on its 30 951
/// nodes; docs/3d.md, "Stop 55"). Each node is known by its coordinates (bit for bit), as
/// [`node_orders`] groups the equations.
#[derive(Clone, Debug, Default)]
pub struct KeptNodeOrders {
    /// Per candidate order of [`node_orders`]: each node's position in it, or `None` for the
    /// candidate that was AMD's order of the equations (small systems).
    ranks: Vec<Option<HashMap<[u64; 3], usize>>>,
}

/// The largest share of a system's nodes that [`KeptNodeOrders::orders`] places itself (nodes
/// the kept orders do not hold: the mechanical phase's prescribed nodes, which carry the
/// thermal phase's equations: 80 of the benchmark egg box's thermal nodes, 9.7 % on its case
/// mesh and 0.26 % on level 4).
pub const KEPT_ORDERS_MAX_NEW_NODES: f64 = 0.1;

impl KeptNodeOrders {
    /// The orders `kept` gives the equations at `coords`, each node's equations consecutive (the
    /// candidates of [`node_orders`], AMD's of the equations where the kept one was). A node
    /// the kept orders do not hold is eliminated just after the last held node it is coupled
    /// to: it creates no fill itself, and joins a nested dissection's separator where it
    /// touches one (eliminated before its first neighbour it would couple the parts the
    /// separator divides: 19 % more entries than the grid's own order with a new row, against
    /// 1.1 %). `None` if more than [`KEPT_ORDERS_MAX_NEW_NODES`] of the nodes are new.
    ///
    /// Panics if `pattern` is not square or `coords.len()` differs from its dimension.
    #[track_caller]
    pub fn orders(
        &self,
        pattern: SymbolicSparseColMatRef<'_, usize>,
        coords: &[[f64; 3]],
    ) -> Option<Vec<Vec<usize>>> {
        assert_eq!(
            coords.len(),
            pattern.ncols(),
            "kept node orders: one coordinate triple per equation"
        );
        let nodes = EquationNodes::new(coords);
        let m = nodes.count();
        let mut amd = None;
        self.ranks
            .iter()
            .map(|ranks| match ranks {
                Some(ranks) => {
                    let held: Vec<Option<usize>> = (0..m)
                        .map(|a| ranks.get(&nodes.key(coords, a)).copied())
                        .collect();
                    let new = held.iter().filter(|r| r.is_none()).count();
                    if new as f64 > KEPT_ORDERS_MAX_NEW_NODES * m as f64 {
                        return None;
                    }
                    // (rank, new after held, node): a new node at its last held neighbour's
                    // rank (entries in either triangle couple two nodes), at the end without one.
                    let mut last: Vec<Option<usize>> = vec![None; m];
                    if new > 0 {
                        for j in 0..pattern.ncols() {
                            let b = nodes.node[j];
                            for &i in &pattern.row_idx()[pattern.col_range(j)] {
                                let a = nodes.node[i];
                                for (x, y) in [(a, b), (b, a)] {
                                    if let (None, Some(r)) = (held[x], held[y]) {
                                        last[x] = last[x].max(Some(r));
                                    }
                                }
                            }
                        }
                    }
                    let mut key: Vec<(usize, bool, usize)> = (0..m)
                        .map(|a| match held[a] {
                            Some(r) => (r, false, a),
                            None => (last[a].unwrap_or(usize::MAX), true, a),
                        })
                        .collect();
                    key.sort_unstable();
                    Some(
                        key.into_iter()
                            .flat_map(|(_, _, a)| nodes.equations(a).iter().copied())
                            .collect(),
                    )
                }
                None => Some(
                    amd.get_or_insert_with(|| approximate_minimum_degree(pattern))
                        .clone(),
                ),
            })
            .collect()
    }
}

/// [`node_orders`], with the node orders kept for the mesh's other systems
/// ([`KeptNodeOrders::orders`]).
#[track_caller]
pub fn node_orders_kept(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
) -> (Vec<Vec<usize>>, KeptNodeOrders) {
    let of_nodes = pattern.ncols() >= NODE_AMD_MIN_EQUATIONS;
    let (perms, node_orders, nodes) =
        node_order_with(pattern, coords, |graph| candidate_orders(graph, of_nodes));
    let ranks = node_orders
        .iter()
        .map(|order| {
            order.as_ref().map(|order| {
                order
                    .iter()
                    .enumerate()
                    .map(|(rank, &a)| (nodes.key(coords, a), rank))
                    .collect()
            })
        })
        .collect();
    (perms, KeptNodeOrders { ranks })
}

/// The equations in each of the orders `orders` gives the nodes of their graph, each node's
/// equations consecutive; AMD's order of the equations for an order that is `None`, and
/// alone where the graph cannot be built.
#[track_caller]
fn node_order(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
    orders: impl FnOnce(NodeGraph) -> Vec<NodeOrder>,
) -> Vec<Vec<usize>> {
    node_order_with(pattern, coords, orders).0
}

/// [`node_order`], also returning the orders of the nodes (`None` for each equation order)
/// and the nodes.
#[track_caller]
fn node_order_with(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
    orders: impl FnOnce(NodeGraph) -> Vec<NodeOrder>,
) -> (Vec<Vec<usize>>, Vec<NodeOrder>, EquationNodes) {
    let n = pattern.ncols();
    assert_eq!(
        pattern.nrows(),
        n,
        "node orders: the pattern must be square"
    );
    assert_eq!(
        coords.len(),
        n,
        "node orders: one coordinate triple per equation"
    );
    let nodes = EquationNodes::new(coords);
    let mut amd = None;
    let mut equation_amd = || {
        amd.get_or_insert_with(|| approximate_minimum_degree(pattern))
            .clone()
    };
    let node_orders = match NodeGraph::new(pattern, &nodes) {
        None => vec![None],
        Some(graph) => orders(graph),
    };
    let perms: Vec<Vec<usize>> = node_orders
        .iter()
        .map(|order| match order {
            Some(node_order) => node_order
                .iter()
                .flat_map(|&a| nodes.equations(a).iter().copied())
                .collect(),
            None => equation_amd(),
        })
        .collect();
    debug_assert!(perms.iter().all(|perm| is_permutation(perm, n)));
    (perms, node_orders, nodes)
}

/// Separators METIS computes at each bisection, keeping the smallest (`METIS_OPTION_NSEPS`; the
/// default is 1), where the nodes carry several equations each. Three cut the level-4 egg box's
/// mechanical factor by a further 5 % for about twice the ordering time (2 s, against 7–12 s
/// for the numeric factorization). A scalar field's factor on about the same graph is far
/// cheaper (one equation per node instead of three), and there the ordering took twice the
/// factorization (the 72 kPa egg box's level 3: the thermal ordering 0.9 s, its factorization
/// 0.44 s, the mechanical one 5.0 s): one separator ([`metis_separators`]).
const METIS_SEPARATORS: i32 = 3;

/// [`METIS_SEPARATORS`] where the nodes carry two equations or more on average, else 1.
fn metis_separators(graph: &NodeGraph) -> i32 {
    let equations: i64 = graph.weights.iter().map(|&w| i64::from(w)).sum();
    if equations >= 2 * graph.weights.len() as i64 {
        METIS_SEPARATORS
    } else {
        1
    }
}

/// The equations grouped by identical coordinates (bit for bit), in increasing order within a
/// group; groups numbered in the order of their coordinates.
struct EquationNodes {
    /// Equations sorted by node.
    equations: Vec<usize>,
    /// `equations[start[a]..start[a + 1]]` are node `a`'s.
    start: Vec<usize>,
    /// The node of each equation.
    node: Vec<usize>,
}

/// The key that groups equations into nodes: their coordinates, bit for bit.
fn coordinate_key(coords: &[[f64; 3]], e: usize) -> [u64; 3] {
    coords[e].map(f64::to_bits)
}

impl EquationNodes {
    fn new(coords: &[[f64; 3]]) -> Self {
        let key = |e: usize| coordinate_key(coords, e);
        let mut equations: Vec<usize> = (0..coords.len()).collect();
        equations.sort_unstable_by_key(|&e| (key(e), e));
        let mut start = Vec::new();
        let mut node = vec![0; coords.len()];
        for (k, &e) in equations.iter().enumerate() {
            if k == 0 || key(e) != key(equations[k - 1]) {
                start.push(k);
            }
            node[e] = start.len() - 1;
        }
        start.push(equations.len());
        EquationNodes {
            equations,
            start,
            node,
        }
    }

    fn count(&self) -> usize {
        self.start.len() - 1
    }

    fn equations(&self, a: usize) -> &[usize] {
        &self.equations[self.start[a]..self.start[a + 1]]
    }

    /// Node `a`'s [`coordinate_key`].
    fn key(&self, coords: &[[f64; 3]], a: usize) -> [u64; 3] {
        coordinate_key(coords, self.equations(a)[0])
    }
}

/// The symmetric graph of the nodes (no self loops), in METIS's compressed form.
#[derive(Clone)]
struct NodeGraph {
    xadj: Vec<i32>,
    adjncy: Vec<i32>,
    weights: Vec<i32>,
}

impl NodeGraph {
    /// `None` if the graph does not fit METIS's 32-bit indices.
    fn new(pattern: SymbolicSparseColMatRef<'_, usize>, nodes: &EquationNodes) -> Option<Self> {
        let m = nodes.count();
        // The nodes each node's columns reach (duplicates removed with a stamp per node).
        let mut stamp = vec![usize::MAX; m];
        let mut reach_start = Vec::with_capacity(m + 1);
        let mut reach = Vec::new();
        reach_start.push(0);
        for a in 0..m {
            for &j in nodes.equations(a) {
                for &i in &pattern.row_idx()[pattern.col_range(j)] {
                    let b = nodes.node[i];
                    if b != a && stamp[b] != a {
                        stamp[b] = a;
                        reach.push(b);
                    }
                }
            }
            reach_start.push(reach.len());
        }
        // Symmetrize: a–b if either reaches the other.
        let mut degree = vec![0usize; m];
        for a in 0..m {
            for &b in &reach[reach_start[a]..reach_start[a + 1]] {
                degree[a] += 1;
                degree[b] += 1;
            }
        }
        let mut offset = Vec::with_capacity(m + 1);
        offset.push(0usize);
        for a in 0..m {
            offset.push(offset[a] + degree[a]);
        }
        let mut next = offset.clone();
        let mut both = vec![0usize; offset[m]];
        for a in 0..m {
            for &b in &reach[reach_start[a]..reach_start[a + 1]] {
                both[next[a]] = b;
                next[a] += 1;
                both[next[b]] = a;
                next[b] += 1;
            }
        }
        drop(reach);
        stamp.fill(usize::MAX);
        let mut xadj = Vec::with_capacity(m + 1);
        let mut adjncy = Vec::new();
        xadj.push(0i32);
        for a in 0..m {
            let start = adjncy.len();
            for &b in &both[offset[a]..offset[a + 1]] {
                if stamp[b] != a {
                    stamp[b] = a;
                    adjncy.push(i32::try_from(b).ok()?);
                }
            }
            // In increasing order: the graph's lists, and METIS's order, depend on the
            // couplings only, not on the triangles the pattern stores.
            adjncy[start..].sort_unstable();
            xadj.push(i32::try_from(adjncy.len()).ok()?);
        }
        let weights = (0..m)
            .map(|a| i32::try_from(nodes.equations(a).len()).ok())
            .collect::<Option<Vec<_>>>()?;
        Some(NodeGraph {
            xadj,
            adjncy,
            weights,
        })
    }

    /// faer's AMD order of the nodes (`perm[new] = old`).
    fn amd_order(&self) -> Vec<usize> {
        let m = self.weights.len();
        let col_ptr: Vec<usize> = self.xadj.iter().map(|&k| k as usize).collect();
        let row_idx: Vec<usize> = self.adjncy.iter().map(|&b| b as usize).collect();
        let graph = SymbolicSparseColMatRef::new_unsorted_checked(m, m, &col_ptr, None, &row_idx);
        approximate_minimum_degree(graph)
    }

    /// METIS's nested-dissection order of the nodes (`perm[new] = old`), `None` on its error.
    fn metis_order(mut self) -> Option<Vec<usize>> {
        let m = self.weights.len();
        let separators = metis_separators(&self);
        if m <= 1 || self.adjncy.is_empty() {
            return Some((0..m).collect());
        }
        let mut nvtxs = i32::try_from(m).ok()?;
        let mut options = [0 as metis_sys::idx_t; metis_sys::METIS_NOPTIONS as usize];
        let mut perm = vec![0 as metis_sys::idx_t; m];
        let mut iperm = vec![0 as metis_sys::idx_t; m];
        // METIS catches SIGABRT and SIGTERM while it runs (GKlib's `gk_sigtrap`: it installs
        // its own handlers, process-wide, and puts back the ones it found when it returns).
        // Two calls at once (the 2D points refine in parallel) could put back each other's
        // handlers and leave METIS's installed for good, so one call runs at a time. A SIGTERM
        // that arrives during a call (about 2 s on the largest 3D level) ends that call with
        // an error, and the order is AMD's.
        static METIS: std::sync::Mutex<()> = std::sync::Mutex::new(());
        let _one_at_a_time = METIS.lock().unwrap_or_else(|e| e.into_inner());
        // SAFETY: the arrays have the lengths METIS reads (nvtxs + 1, xadj[nvtxs], nvtxs,
        // METIS_NOPTIONS, nvtxs, nvtxs); xadj is non-decreasing from 0 and every adjncy entry
        // is a vertex other than its own, as NodeND requires; METIS keeps no pointer after the
        // call.
        let status = unsafe {
            metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
            options[metis_sys::moptions_et_METIS_OPTION_NSEPS as usize] = separators;
            metis_sys::METIS_NodeND(
                &mut nvtxs,
                self.xadj.as_mut_ptr(),
                self.adjncy.as_mut_ptr(),
                self.weights.as_mut_ptr(),
                options.as_mut_ptr(),
                perm.as_mut_ptr(),
                iperm.as_mut_ptr(),
            )
        };
        if status != metis_sys::rstatus_et_METIS_OK {
            return None;
        }
        let order: Vec<usize> = perm.into_iter().map(|p| p as usize).collect();
        is_permutation(&order, m).then_some(order)
    }
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
    EliminationTree::new(pattern, perm, "factor_entries")
        .col_counts
        .iter()
        .sum()
}

/// `perm` (`perm[new] = old`) renumbered in a postorder of its elimination tree: every subtree
/// numbered contiguously, children in their order in `perm`, each before its parent. The fill
/// is the same (the eliminations are equivalent), but the columns of a supernode become
/// consecutive, which faer's supernodal factorization needs to find them: a nested dissection
/// whose leaves and separators interleave otherwise factors in small supernodes. On the
/// level-4 egg box, METIS's order factors in 6.8 s postordered against 14.2 s as it is (f32,
/// 2 threads; docs/3d.md, "Stop 40"). An equation eliminated after another it is coupled to
/// (a multiplier after its displacements) is its ancestor, and stays after it.
///
/// Panics if `pattern` is not square or `perm` is not a permutation of its equations.
#[track_caller]
pub fn postordered(pattern: SymbolicSparseColMatRef<'_, usize>, perm: Vec<usize>) -> Vec<usize> {
    let parent = EliminationTree::new(pattern, &perm, "postordered").parent;
    postorder(perm, &parent)
}

/// Of candidate elimination orders (at least one), the one whose Cholesky factor of `pattern`
/// has the fewest entries ([`factor_entries`]; the first on a tie), postordered
/// ([`postordered`], from the elimination tree the count computed).
///
/// Panics if there is no candidate, or as [`factor_entries`] does.
#[track_caller]
pub fn fewest_entries_postordered(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    candidates: Vec<Vec<usize>>,
) -> Vec<usize> {
    // The candidates' trees at once; the first of the fewest entries wins, as in sequence.
    let (perm, tree) = candidates
        .into_par_iter()
        .map(|perm| {
            let tree = EliminationTree::new(pattern, &perm, "fewest_entries_postordered");
            (perm, tree)
        })
        .collect::<Vec<_>>()
        .into_iter()
        .reduce(|best, next| {
            let entries = |t: &EliminationTree| t.col_counts.iter().sum::<usize>();
            if entries(&next.1) < entries(&best.1) {
                next
            } else {
                best
            }
        })
        .expect("fewest_entries_postordered: at least one candidate");
    postorder(perm, &tree.parent)
}

/// `perm` renumbered in a postorder of the elimination tree `parent` (in `perm`'s numbering).
fn postorder(perm: Vec<usize>, parent: &[isize]) -> Vec<usize> {
    let n = perm.len();
    // Children lists in increasing order (a forest: roots have no parent).
    let mut first_child = vec![usize::MAX; n];
    let mut next_sibling = vec![usize::MAX; n];
    let mut roots = Vec::new();
    for k in (0..n).rev() {
        match usize::try_from(parent[k]) {
            Ok(p) => {
                next_sibling[k] = first_child[p];
                first_child[p] = k;
            }
            Err(_) => roots.push(k),
        }
    }
    let mut order = Vec::with_capacity(n);
    let mut stack = Vec::new();
    for &root in roots.iter().rev() {
        // Depth first: a vertex is numbered when its last child is done.
        stack.push((root, first_child[root]));
        while let Some(&mut (v, ref mut child)) = stack.last_mut() {
            if *child == usize::MAX {
                order.push(perm[v]);
                stack.pop();
            } else {
                let c = *child;
                *child = next_sibling[c];
                stack.push((c, first_child[c]));
            }
        }
    }
    debug_assert!(is_permutation(&order, n));
    order
}

/// The elimination tree and column counts of the symmetric matrix with `pattern`'s lower
/// triangle, eliminated in the order `perm`, in that order's numbering.
struct EliminationTree {
    /// The parent of each column (negative: a root).
    parent: Vec<isize>,
    col_counts: Vec<usize>,
}

impl EliminationTree {
    #[track_caller]
    fn new(pattern: SymbolicSparseColMatRef<'_, usize>, perm: &[usize], caller: &str) -> Self {
        let n = pattern.ncols();
        assert_eq!(pattern.nrows(), n, "{caller}: the pattern must be square");
        let position = inverse_permutation(perm);
        assert_eq!(position.len(), n, "{caller}: one position per equation");
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
        let mut parent = vec![0isize; n];
        let mut col_counts = vec![0usize; n];
        let mut buffer = MemBuffer::new(prefactorize_symbolic_cholesky_scratch::<usize>(
            n,
            row_idx.len(),
        ));
        prefactorize_symbolic_cholesky(
            &mut parent,
            &mut col_counts,
            upper,
            MemStack::new(&mut buffer),
        );
        EliminationTree { parent, col_counts }
    }
}

/// Reorders `perm` (`perm[new] = old`) so that every equation with sign −1 comes after all
/// equations with sign +1 it is coupled to (and after its own original position); all other
/// equations keep their relative order. Eliminating each Lagrange multiplier after the
/// displacements it constrains makes every leading block of a saddle-point matrix
/// [K Bᵀ; B 0] (K SPD, B of full row rank) nonsingular with the expected inertia. The
/// couplings are read from both triangles of `pattern`, or from the lower one where it holds
/// only that ([`crate::bulk::global::Storage::Lower`]).
pub fn multipliers_after_neighbours(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    perm: Vec<usize>,
    signs: &[i8],
) -> Vec<usize> {
    let position = inverse_permutation(&perm);
    // The last position of a +1 equation coupled to each −1 equation (its own at least).
    let mut last = position.clone();
    for j in 0..pattern.ncols() {
        for &i in &pattern.row_idx()[pattern.col_range(j)] {
            if signs[j] == -1 && signs[i] == 1 {
                last[j] = last[j].max(position[i]);
            } else if signs[i] == -1 && signs[j] == 1 {
                last[i] = last[i].max(position[j]);
            }
        }
    }
    let mut key: Vec<(usize, u8, usize)> = perm
        .iter()
        .enumerate()
        .map(|(new, &old)| match signs[old] {
            -1 => (last[old], 1, new),
            _ => (new, 0, new),
        })
        .collect();
    key.sort_unstable();
    key.into_iter().map(|(_, _, new)| perm[new]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// The nodes' graph is the symmetric adjacency of the nodes (no self loops, no
    /// duplicates) with the nodes' equation counts as weights: a 60 × 50 grid, two
    /// equations per node, 9-point stencil.
    #[test]
    fn the_node_graph_is_the_symmetric_adjacency_of_the_nodes() {
        let (nx, ny): (usize, usize) = (60, 50);
        let mut columns = Vec::new();
        let mut coords = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                for _field in 0..2 {
                    let mut rows = Vec::new();
                    for jj in j.saturating_sub(1)..(j + 2).min(ny) {
                        for ii in i.saturating_sub(1)..(i + 2).min(nx) {
                            rows.extend([2 * (jj * nx + ii), 2 * (jj * nx + ii) + 1]);
                        }
                    }
                    columns.push(rows);
                    coords.push([i as f64, j as f64, 0.0]);
                }
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        for rows in &columns {
            row_idx.extend_from_slice(rows);
            col_ptr.push(row_idx.len());
        }
        let n = coords.len();
        let pattern = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let nodes = EquationNodes::new(&coords);
        let graph = NodeGraph::new(pattern, &nodes).expect("fits 32 bits");
        let m = nodes.count();
        assert_eq!(m, nx * ny);
        let mut expected = vec![BTreeSet::new(); m];
        for (j, rows) in columns.iter().enumerate() {
            for &i in rows {
                let (a, b) = (nodes.node[j], nodes.node[i]);
                if a != b {
                    expected[a].insert(b as i32);
                    expected[b].insert(a as i32);
                }
            }
        }
        for (a, expected) in expected.iter().enumerate() {
            let list = &graph.adjncy[graph.xadj[a] as usize..graph.xadj[a + 1] as usize];
            let set: BTreeSet<i32> = list.iter().copied().collect();
            assert_eq!(set.len(), list.len(), "node {a}: a neighbour twice");
            assert_eq!(&set, expected, "node {a}");
            assert_eq!(graph.weights[a], 2);
        }
    }
}
