//! The truncated hierarchical B-spline (THB) basis of a [`HierarchicalMesh`]
//! (Giannelli, Jüttler & Speleers 2012), by element extraction.
//!
//! A B-spline `B^ℓ_i` of level `ℓ` is *active* if its support lies in `Ω^ℓ`
//! but not in `Ω^{ℓ+1}`. The THB function of an active `B^ℓ_i` is its
//! *truncation*: written in the B-splines of level `ℓ + 1` (two-scale
//! relation), the coefficients of the functions whose support lies in
//! `Ω^{ℓ+1}` are dropped, and so on up the levels. THB functions are
//! non-negative, form a partition of unity, are linearly independent, and the
//! spaces are nested under refinement.
//!
//! Every active element `Q` (a cell of level `L`) stores its *extraction*:
//! each THB function nonzero on `Q` as a combination of the `Π (p_d + 1)`
//! B-splines of level `L` on `Q` (truncations above level `L` do not reach
//! `Q`, which does not lie in `Ω^{L+1}`). Elements of level 0 need none: only
//! the untruncated level-0 B-splines are nonzero there. The extraction is
//! computed cell by cell along the chain of ancestors of `Q`: the coefficient
//! vectors of the active functions met so far are carried from level `k` to
//! `k + 1` by the local two-scale matrices (tensor products of 1D ones), then
//! truncated.

use std::collections::{BTreeSet, HashMap};

use nalgebra::DMatrix;

use super::mesh::{Cell, HierarchicalMesh};
use crate::basis::basis_ders;

/// One element of the hierarchical mesh with its THB functions.
#[derive(Clone, Debug, PartialEq)]
pub struct ThbElement {
    /// The cell.
    pub cell: Cell,
    /// Knot spans of the cell in its level's knot vectors (unused directions 0).
    pub spans: [usize; 3],
    /// Lower parametric corner (unused directions 0).
    pub lower: [f64; 3],
    /// Upper parametric corner (unused directions 0).
    pub upper: [f64; 3],
    /// Global indices of the THB functions nonzero on the element.
    pub functions: Vec<usize>,
    /// Row-major `functions.len() × Π(p_d + 1)`: function `a` is `Σ_j C[a][j] B_j` with
    /// `B_j` the level's B-splines on the cell in local order (first direction fastest).
    /// `None`: the identity (a level-0 element, functions in local order).
    pub extraction: Option<Vec<f64>>,
}

/// The THB basis of a hierarchical mesh: its active functions and extracted elements.
#[derive(Clone, Debug)]
pub struct ThbBasis {
    dim: usize,
    degrees: [usize; 3],
    /// `(level, multi-index)` of every active function, by global index.
    functions: Vec<(usize, [usize; 3])>,
    ids: HashMap<(usize, [usize; 3]), usize>,
    elements: Vec<ThbElement>,
    element_of: HashMap<Cell, usize>,
}

/// Local tensor index `j = j0 + P0 (j1 + P1 j2)` to per-direction indices.
fn unflatten(j: usize, p1: [usize; 3]) -> [usize; 3] {
    [j % p1[0], (j / p1[0]) % p1[1], j / (p1[0] * p1[1])]
}

impl ThbBasis {
    /// Builds the basis of `mesh`.
    pub fn new(mesh: &HierarchicalMesh) -> Self {
        let dim = mesh.dim();
        let mut degrees = [0usize; 3];
        for d in 0..dim {
            degrees[d] = mesh.level(0).knots[d].degree();
        }
        let mut b = Builder::new(mesh, degrees);
        // Active functions, level by level, first direction fastest.
        let mut functions = Vec::new();
        for l in 0..mesh.n_levels() {
            let lv = mesh.level(l);
            let mut n = [1usize; 3];
            for d in 0..dim {
                n[d] = lv.n_functions(d);
            }
            let candidates: Vec<[usize; 3]> = if l == 0 {
                let mut v = Vec::with_capacity(n[0] * n[1] * n[2]);
                for i2 in 0..n[2] {
                    for i1 in 0..n[1] {
                        for i0 in 0..n[0] {
                            v.push([i0, i1, i2]);
                        }
                    }
                }
                v
            } else {
                let mut set = BTreeSet::new();
                for parent in mesh
                    .refined_cells()
                    .into_iter()
                    .filter(|c| c.level == l - 1)
                {
                    for c in mesh.children(parent) {
                        let s = mesh.spans(c);
                        let p1 = degrees.map(|p| p + 1);
                        for j in 0..p1[0] * p1[1] * p1[2] {
                            let jj = unflatten(j, p1);
                            let f = [0, 1, 2].map(|d| s[d] + jj[d] - degrees[d]);
                            set.insert([f[2], f[1], f[0]]);
                        }
                    }
                }
                set.into_iter().map(|k| [k[2], k[1], k[0]]).collect()
            };
            for f in candidates {
                if b.support_in_domain(l, f) && !b.support_refined(l, f) {
                    functions.push((l, f));
                }
            }
        }
        let ids: HashMap<(usize, [usize; 3]), usize> =
            functions.iter().enumerate().map(|(i, &k)| (k, i)).collect();
        let mut elements = Vec::new();
        let mut element_of = HashMap::new();
        for cell in mesh.active_cells() {
            element_of.insert(cell, elements.len());
            elements.push(b.element(cell, &ids));
        }
        ThbBasis {
            dim,
            degrees,
            functions,
            ids,
            elements,
            element_of,
        }
    }

    /// Number of parametric directions.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Degree per direction (unused directions 0).
    pub fn degrees(&self) -> [usize; 3] {
        self.degrees
    }

    /// Number of active (THB) functions.
    pub fn n_functions(&self) -> usize {
        self.functions.len()
    }

    /// `(level, multi-index)` of THB function `a`.
    pub fn function(&self, a: usize) -> (usize, [usize; 3]) {
        self.functions[a]
    }

    /// Global index of the active function of `level` with multi-index `f`, if active.
    pub fn id(&self, level: usize, f: [usize; 3]) -> Option<usize> {
        self.ids.get(&(level, f)).copied()
    }

    /// The elements, in the order of [`HierarchicalMesh::active_cells`].
    pub fn elements(&self) -> &[ThbElement] {
        &self.elements
    }

    /// Index of the element of an active cell.
    pub fn element_of(&self, c: Cell) -> Option<usize> {
        self.element_of.get(&c).copied()
    }

    /// Number of local B-splines per element, `Π (p_d + 1)`.
    pub fn n_local(&self) -> usize {
        (0..self.dim).map(|d| self.degrees[d] + 1).product()
    }
}

/// Memoized queries while a basis is built.
struct Builder<'a> {
    mesh: &'a HierarchicalMesh,
    degrees: [usize; 3],
    in_domain: HashMap<(usize, [usize; 3]), bool>,
    two_scale: HashMap<(usize, usize, u32), Vec<f64>>,
}

impl<'a> Builder<'a> {
    fn new(mesh: &'a HierarchicalMesh, degrees: [usize; 3]) -> Self {
        Builder {
            mesh,
            degrees,
            in_domain: HashMap::new(),
            two_scale: HashMap::new(),
        }
    }

    fn p1(&self) -> [usize; 3] {
        self.degrees.map(|p| p + 1)
    }

    /// Whether the support of level-`l` function `f` lies in `Ω^l`.
    fn support_in_domain(&mut self, l: usize, f: [usize; 3]) -> bool {
        if l == 0 {
            return true;
        }
        if let Some(&v) = self.in_domain.get(&(l, f)) {
            return v;
        }
        let m = self.mesh;
        let v = m.all_cells(l, m.support(l, f), |c| m.in_domain(c));
        self.in_domain.insert((l, f), v);
        v
    }

    /// Whether the support of level-`l` function `f` lies in `Ω^{l+1}`.
    fn support_refined(&self, l: usize, f: [usize; 3]) -> bool {
        let m = self.mesh;
        m.all_cells(l, m.support(l, f), |c| m.is_refined(c))
    }

    /// The 1D two-scale matrix `R[j][j']` (row-major `(p+1)²`) of direction `d` from level
    /// `l` to the child cell ordinal `child` of level `l + 1`: on the child,
    /// `B^l_{s−p+j} = Σ_j' R[j][j'] B^{l+1}_{s'−p+j'}`. By collocation at `p + 1` interior
    /// points of the child: both local bases span the polynomials of degree `p` there.
    fn two_scale(&mut self, l: usize, d: usize, child: u32) -> &[f64] {
        let mesh = self.mesh;
        let p = self.degrees[d];
        self.two_scale.entry((l, d, child)).or_insert_with(|| {
            let (coarse, fine) = (mesh.level(l), mesh.level(l + 1));
            let parent = if mesh.halved(l)[d] { child / 2 } else { child };
            let (s0, s1) = (coarse.span(d, parent), fine.span(d, child));
            let (a, b) = fine.bounds(d, child);
            let n = p + 1;
            let mut bc = DMatrix::zeros(n, n);
            let mut bf = DMatrix::zeros(n, n);
            for q in 0..n {
                let x = a + (b - a) * (q as f64 + 0.5) / n as f64;
                let vc = basis_ders(&coarse.knots[d], s0, x, 0);
                let vf = basis_ders(&fine.knots[d], s1, x, 0);
                for j in 0..n {
                    bc[(q, j)] = vc[0][j];
                    bf[(q, j)] = vf[0][j];
                }
            }
            // bc = bf · Rᵀ.
            let rt = bf
                .lu()
                .solve(&bc)
                .expect("B-splines on a cell are linearly independent");
            let mut r = vec![0.0; n * n];
            for j in 0..n {
                for jp in 0..n {
                    r[j * n + jp] = rt[(jp, j)];
                }
            }
            r
        })
    }

    /// Carries local coefficients on the parent of `child` (level `child.level − 1`) to the
    /// local coefficients on `child`: the tensor product of the 1D two-scale matrices,
    /// applied direction by direction.
    fn subdivide(&mut self, child: Cell, v: &mut Vec<f64>) {
        let p1 = self.p1();
        let dim = self.mesh.dim();
        for d in 0..dim {
            let r = self.two_scale(child.level - 1, d, child.index[d]).to_vec();
            let n = p1[d];
            let mut w = vec![0.0; v.len()];
            for (j, &vj) in v.iter().enumerate() {
                if vj == 0.0 {
                    continue;
                }
                let jj = unflatten(j, p1);
                for jp in 0..n {
                    let mut kk = jj;
                    kk[d] = jp;
                    let k = kk[0] + p1[0] * (kk[1] + p1[1] * kk[2]);
                    w[k] += vj * r[jj[d] * n + jp];
                }
            }
            *v = w;
        }
    }

    /// The element of an active cell: its THB functions and their extraction.
    fn element(&mut self, cell: Cell, ids: &HashMap<(usize, [usize; 3]), usize>) -> ThbElement {
        let mesh = self.mesh;
        let (lower, upper) = mesh.bounds(cell);
        let spans = mesh.spans(cell);
        let p1 = self.p1();
        let n_local = p1[0] * p1[1] * p1[2];
        let local_function = |s: [usize; 3], j: usize, deg: [usize; 3]| {
            let jj = unflatten(j, p1);
            [0, 1, 2].map(|d| s[d] + jj[d] - deg[d])
        };
        if cell.level == 0 {
            let functions = (0..n_local)
                .map(|j| {
                    *ids.get(&(0, local_function(spans, j, self.degrees)))
                        .expect("level-0 functions on a level-0 element are active")
                })
                .collect();
            return ThbElement {
                cell,
                spans,
                lower,
                upper,
                functions,
                extraction: None,
            };
        }
        let mut rows: Vec<(usize, Vec<f64>)> = Vec::new();
        for k in 0..=cell.level {
            let ck = mesh.ancestor(cell, k);
            let sk = mesh.spans(ck);
            if k > 0 {
                for (_, v) in rows.iter_mut() {
                    self.subdivide(ck, v);
                }
                // Truncation: drop the level-k functions whose support lies in Ω^k.
                for j in 0..n_local {
                    let f = local_function(sk, j, self.degrees);
                    if self.support_in_domain(k, f) {
                        for (_, v) in rows.iter_mut() {
                            v[j] = 0.0;
                        }
                    }
                }
            }
            for j in 0..n_local {
                if let Some(&id) = ids.get(&(k, local_function(sk, j, self.degrees))) {
                    let mut v = vec![0.0; n_local];
                    v[j] = 1.0;
                    rows.push((id, v));
                }
            }
        }
        // A truncated function may vanish on the element (all its coefficients dropped).
        rows.retain(|(_, v)| v.iter().any(|&c| c != 0.0));
        rows.sort_by_key(|(id, _)| *id);
        let functions = rows.iter().map(|(id, _)| *id).collect();
        let extraction = rows.into_iter().flat_map(|(_, v)| v).collect();
        ThbElement {
            cell,
            spans,
            lower,
            upper,
            functions,
            extraction: Some(extraction),
        }
    }
}

/// Where THB function `a` of the refinement `to` is read off the coarse space `from`: an
/// active cell `c` of its level `ℓ` in its support, the element of `from` containing `c`
/// with its cell `q`, and the index of `B^ℓ_τ` among the level-`ℓ` B-splines on `c`.
struct FineFunction {
    c: Cell,
    q: Cell,
    element: usize,
    local: usize,
}

fn fine_function(
    from: &ThbBasis,
    to_mesh: &HierarchicalMesh,
    to: &ThbBasis,
    p1: [usize; 3],
    a: usize,
) -> FineFunction {
    let (l, f) = to.functions[a];
    let range = to_mesh.support(l, f);
    let mut found = None;
    to_mesh.all_cells(l, range, |c| {
        if to_mesh.is_active(c) {
            found = Some(c);
            false
        } else {
            true
        }
    });
    let c = found.expect("an active function has an active cell of its level in its support");
    let (q, element) = (0..=l)
        .find_map(|k| {
            let q = to_mesh.ancestor(c, k);
            from.element_of(q).map(|e| (q, e))
        })
        .expect("the coarse mesh covers the domain");
    let spans = to_mesh.spans(c);
    let mut local = 0;
    for d in (0..3).rev() {
        local = local * p1[d] + (f[d] + to.degrees[d] - spans[d]);
    }
    FineFunction {
        c,
        q,
        element,
        local,
    }
}

/// Prolongation of a field from the THB space of `from` to that of a refinement `to`
/// (whose refined cells include those of `from`): the coefficients, `n_comp` per function
/// (function-major), of the same function in the finer space, exact since the spaces are
/// nested. For THB function `τ` of level `ℓ` the coefficient is that of `B^ℓ_τ` in the
/// level-`ℓ` B-spline form of the field on any active cell `Q` of level `ℓ` in the support
/// of `τ`: there the truncated coarser functions have no `B^ℓ_τ` component (its support
/// lies in `Ω^ℓ`), the functions of level `ℓ` are untruncated, and finer ones vanish.
pub fn prolongate(
    from: &ThbBasis,
    to_mesh: &HierarchicalMesh,
    to: &ThbBasis,
    coefficients: &[f64],
    n_comp: usize,
) -> Vec<f64> {
    assert_eq!(
        coefficients.len(),
        from.n_functions() * n_comp,
        "prolongate: coefficients must hold n_comp values per function"
    );
    let mut b = Builder::new(to_mesh, to.degrees);
    let p1 = b.p1();
    let n_local = p1[0] * p1[1] * p1[2];
    let mut out = vec![0.0; to.n_functions() * n_comp];
    for a in 0..to.n_functions() {
        let ff = fine_function(from, to_mesh, to, p1, a);
        let el = &from.elements[ff.element];
        for comp in 0..n_comp {
            let mut v = vec![0.0; n_local];
            for (r, &g) in el.functions.iter().enumerate() {
                let u = coefficients[g * n_comp + comp];
                match &el.extraction {
                    None => v[r] += u,
                    Some(x) => {
                        for j in 0..n_local {
                            v[j] += u * x[r * n_local + j];
                        }
                    }
                }
            }
            for k in ff.q.level + 1..=ff.c.level {
                b.subdivide(to_mesh.ancestor(ff.c, k), &mut v);
            }
            out[a * n_comp + comp] = v[ff.local];
        }
    }
    out
}

/// The matrix of [`prolongate`] for one component: `(fine, coarse, value)` for every
/// nonzero coefficient of a coarse function in a fine one.
pub fn prolongation_entries(
    from: &ThbBasis,
    to_mesh: &HierarchicalMesh,
    to: &ThbBasis,
) -> Vec<(usize, usize, f64)> {
    let mut b = Builder::new(to_mesh, to.degrees);
    let p1 = b.p1();
    let n_local = p1[0] * p1[1] * p1[2];
    let mut out = Vec::new();
    for a in 0..to.n_functions() {
        let ff = fine_function(from, to_mesh, to, p1, a);
        let el = &from.elements[ff.element];
        for (r, &g) in el.functions.iter().enumerate() {
            let mut v = vec![0.0; n_local];
            match &el.extraction {
                None => v[r] = 1.0,
                Some(x) => v.copy_from_slice(&x[r * n_local..(r + 1) * n_local]),
            }
            for k in ff.q.level + 1..=ff.c.level {
                b.subdivide(to_mesh.ancestor(ff.c, k), &mut v);
            }
            if v[ff.local] != 0.0 {
                out.push((a, g, v[ff.local]));
            }
        }
    }
    out
}
