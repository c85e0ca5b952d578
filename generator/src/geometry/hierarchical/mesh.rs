//! Hierarchical meshes: nested refinements `Ω^0 ⊇ Ω^1 ⊇ …` of the parameter
//! domain of a tensor-product patch (1 to 3 directions).
//!
//! Level 0 is the patch's own mesh; level `ℓ + 1` halves every element of level
//! `ℓ` in the directions that the mesh's *pattern* names for `ℓ` (its knot
//! vectors get the mid-point of every non-empty span there): every direction
//! at every level by default (dyadic), or e.g. the tangential directions and
//! then the normal one in turn, which grades a region refined to every other
//! level in the tangential directions only. Every level is a tensor-product
//! space containing the one before, which is all that THB needs. A *cell* is an
//! element of one level, named by its element ordinal in each direction (the
//! `i`-th non-empty span), so the children of ordinal `e` in a halved direction
//! are `2e` and `2e + 1`. `Ω^ℓ` (`ℓ ≥ 1`) is the union of the children of the
//! *refined* cells of level `ℓ − 1`; the active cells (the elements of the
//! hierarchical mesh) are the cells of `Ω^ℓ` that are not refined.
//!
//! Refinement keeps the mesh *admissible of class 2* (Buffa & Giannelli 2016,
//! Bracco et al. 2019, "refine_recursive"), counted in cycles of the pattern:
//! before a cell `Q` of level `ℓ` is refined, every cell of level `ℓ − P` (`P`
//! the pattern's length, 1 when dyadic) that meets the support extension of
//! `Q` is refined, so that the functions on any element come from one cycle of
//! levels and the one before it: their sizes differ by at most a factor of 2
//! in each direction, as in the dyadic mesh. Directions declared
//! *periodic* keep the first and last layer of cells mirror images of each
//! other, so that the traces of the basis on the two opposite faces coincide
//! (periodic ties of the PR conditions (2.3) pair them one to one).

use std::collections::HashSet;

use crate::geometry::KnotVector;

/// A cell: an element of one level, by its element ordinal per direction (unused directions 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Cell {
    /// The level (0: the patch's own elements).
    pub level: usize,
    /// Element ordinal (the `i`-th non-empty knot span of the level) per direction.
    pub index: [u32; 3],
}

/// One level of the hierarchy: its knot vectors and index maps.
#[derive(Clone, Debug)]
pub struct Level {
    /// Knot vectors, one per direction.
    pub knots: Vec<KnotVector>,
    /// `spans[d][e]`: knot span of element ordinal `e` in direction `d`.
    spans: Vec<Vec<usize>>,
    /// `support[d][i]`: first and last element ordinal on which basis function `i` of
    /// direction `d` is nonzero.
    support: Vec<Vec<(u32, u32)>>,
}

impl Level {
    fn new(knots: Vec<KnotVector>) -> Self {
        let spans: Vec<Vec<usize>> = knots.iter().map(KnotVector::element_spans).collect();
        let support = knots
            .iter()
            .zip(&spans)
            .map(|(kv, sp)| {
                let p = kv.degree();
                (0..kv.n_basis())
                    .map(|i| {
                        // Non-empty spans s with i ≤ s ≤ i + p, as ordinals.
                        let first = sp.partition_point(|&s| s < i) as u32;
                        let last = sp.partition_point(|&s| s <= i + p) as u32 - 1;
                        (first, last)
                    })
                    .collect()
            })
            .collect();
        Level {
            knots,
            spans,
            support,
        }
    }

    /// The next level: the mid-point of every non-empty span inserted in the
    /// directions `halved` marks (the others keep their knots).
    fn refined(&self, halved: [bool; 3]) -> Level {
        let knots = self
            .knots
            .iter()
            .zip(halved)
            .map(|(kv, halve)| {
                if !halve {
                    return kv.clone();
                }
                let mut k = kv.knots().to_vec();
                for w in kv.knots().windows(2) {
                    if w[0] < w[1] {
                        k.push(0.5 * (w[0] + w[1]));
                    }
                }
                k.sort_by(f64::total_cmp);
                KnotVector::new(kv.degree(), k).expect("mid-points keep the knot vector valid")
            })
            .collect();
        Level::new(knots)
    }

    /// Number of elements in direction `d`.
    pub fn n_elements(&self, d: usize) -> usize {
        self.spans[d].len()
    }

    /// Number of basis functions in direction `d`.
    pub fn n_functions(&self, d: usize) -> usize {
        self.knots[d].n_basis()
    }

    /// Knot span of element ordinal `e` in direction `d`.
    pub fn span(&self, d: usize, e: u32) -> usize {
        self.spans[d][e as usize]
    }

    /// First and last element ordinal of basis function `i` of direction `d`.
    pub fn support(&self, d: usize, i: usize) -> (u32, u32) {
        self.support[d][i]
    }

    /// Parametric bounds of element ordinal `e` in direction `d`.
    pub fn bounds(&self, d: usize, e: u32) -> (f64, f64) {
        let s = self.span(d, e);
        let k = self.knots[d].knots();
        (k[s], k[s + 1])
    }
}

/// A hierarchical mesh over the parameter domain of a tensor-product patch.
#[derive(Clone, Debug)]
pub struct HierarchicalMesh {
    dim: usize,
    levels: Vec<Level>,
    /// `refined[ℓ]`: the cells of level `ℓ` whose children belong to `Ω^{ℓ+1}`.
    refined: Vec<HashSet<[u32; 3]>>,
    periodic: [bool; 3],
    /// The directions halved from level `ℓ` to `ℓ + 1` are `pattern[ℓ % pattern.len()]`
    /// (dyadic: every direction at every level).
    pattern: Vec<[bool; 3]>,
}

impl HierarchicalMesh {
    /// The mesh of one level: the knot vectors' own elements, refined dyadically
    /// (every direction halved at every level).
    #[track_caller]
    pub fn new(knots: Vec<KnotVector>) -> Self {
        let dim = knots.len();
        Self::with_pattern(knots, Self::dyadic_pattern(dim))
    }

    /// The pattern that halves every one of `dim` directions at every level.
    pub fn dyadic_pattern(dim: usize) -> Vec<[bool; 3]> {
        vec![[0, 1, 2].map(|d| d < dim)]
    }

    /// The mesh of one level whose level `ℓ + 1` halves the directions
    /// `pattern[ℓ % pattern.len()]` of level `ℓ` (e.g. `[[true, true, false],
    /// [false, false, true]]`: the tangential directions, then the normal one,
    /// so that a region refined to every other level only is graded tangentially).
    /// The levels stay nested tensor-product spaces, which is all that THB needs.
    /// A mask that halves no direction repeats a level (the face traces of
    /// normal-only levels).
    #[track_caller]
    pub fn with_pattern(knots: Vec<KnotVector>, pattern: Vec<[bool; 3]>) -> Self {
        let dim = knots.len();
        assert!(
            (1..=3).contains(&dim),
            "HierarchicalMesh: 1 to 3 directions"
        );
        assert!(
            !pattern.is_empty() && pattern.iter().all(|m| m[dim..].iter().all(|&h| !h)),
            "HierarchicalMesh: a pattern of masks over the mesh's directions"
        );
        HierarchicalMesh {
            dim,
            levels: vec![Level::new(knots)],
            refined: vec![HashSet::new()],
            periodic: [false; 3],
            pattern,
        }
    }

    /// The pattern that halves the directions other than `normal` and then `normal` in
    /// turn, over `dim` directions: a marked cell is halved in every direction over two
    /// levels, and the cells that admissibility refines around it take the tangential
    /// level first (`[discretization] refinement = "alternating"`).
    pub fn alternating_pattern(dim: usize, normal: usize) -> Vec<[bool; 3]> {
        let tangential = [0, 1, 2].map(|d| d < dim && d != normal);
        let across = [0, 1, 2].map(|d| d == normal);
        vec![tangential, across]
    }

    /// The directions that level `l + 1` halves of level `l`.
    pub fn halved(&self, l: usize) -> [bool; 3] {
        self.pattern[l % self.pattern.len()]
    }

    /// The pattern's length: the levels over which every direction is halved once (1 dyadic).
    pub fn cycle(&self) -> usize {
        self.pattern.len()
    }

    /// The refinement depth of the mesh in whole cycles of the pattern: the finest level
    /// divided by [`Self::cycle`], rounded up (dyadic: the finest level).
    pub fn depth(&self) -> usize {
        (self.n_levels() - 1).div_ceil(self.cycle())
    }

    /// How many times direction `d` is halved from level 0 to level `l`.
    fn halvings(&self, l: usize, d: usize) -> u32 {
        let (n, m) = (
            self.pattern.len(),
            self.pattern.iter().filter(|h| h[d]).count(),
        );
        let rest = self.pattern[..l % n].iter().filter(|h| h[d]).count();
        ((l / n) * m + rest) as u32
    }

    /// The cell of level `level ≤ c.level` that contains `c`.
    #[track_caller]
    pub fn ancestor(&self, c: Cell, level: usize) -> Cell {
        assert!(
            level <= c.level,
            "HierarchicalMesh::ancestor: level {level} is finer"
        );
        let mut index = c.index;
        for (d, i) in index.iter_mut().enumerate().take(self.dim) {
            *i >>= self.halvings(c.level, d) - self.halvings(level, d);
        }
        Cell { level, index }
    }

    /// The children of a cell (`2^k` of them, `k` the directions its level halves), first
    /// direction fastest.
    pub fn children(&self, c: Cell) -> impl Iterator<Item = Cell> + use<> {
        let (dim, halved) = (self.dim, self.halved(c.level));
        // Bit d of k: the upper half in direction d; none in a direction not halved.
        (0..1u32 << dim)
            .filter(move |k| (0..dim).all(|d| halved[d] || (k >> d) & 1 == 0))
            .map(move |k| {
                let mut index = c.index;
                for d in (0..dim).filter(|&d| halved[d]) {
                    index[d] = 2 * index[d] + ((k >> d) & 1);
                }
                Cell {
                    level: c.level + 1,
                    index,
                }
            })
    }

    /// Creates the levels up to `l` (on demand, as refinement reaches them).
    fn ensure_level(&mut self, l: usize) {
        while self.levels.len() <= l {
            let next = self
                .levels
                .last()
                .expect("level 0")
                .refined(self.halved(self.levels.len() - 1));
            self.levels.push(next);
        }
    }

    /// Declares direction `d` periodic: its first and last layers of cells are
    /// refined alike from now on (and at once, for cells already refined).
    pub fn set_periodic(&mut self, d: usize) {
        self.periodic[d] = true;
        let cells: Vec<Cell> = self.refined_cells();
        for c in cells {
            self.refine_cell(c);
        }
    }

    /// Whether direction `d` is periodic.
    pub fn is_periodic(&self, d: usize) -> bool {
        self.periodic[d]
    }

    /// Number of parametric directions.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Number of levels with cells (at least 1).
    pub fn n_levels(&self) -> usize {
        self.refined
            .iter()
            .rposition(|r| !r.is_empty())
            .map_or(1, |l| l + 2)
    }

    /// Level `l` (created on demand by [`Self::refine`]).
    pub fn level(&self, l: usize) -> &Level {
        &self.levels[l]
    }

    /// Number of elements of level `l` in direction `d` (1 for unused directions).
    pub fn n_cells(&self, l: usize, d: usize) -> u32 {
        if d < self.dim {
            (self.levels[0].n_elements(d) as u32) << self.halvings(l, d)
        } else {
            1
        }
    }

    /// Whether the cell lies in `Ω^ℓ` (its parent is refined; every level-0 cell).
    pub fn in_domain(&self, c: Cell) -> bool {
        c.level == 0 || self.is_refined(self.ancestor(c, c.level - 1))
    }

    /// Whether the cell is refined (its children lie in `Ω^{ℓ+1}`).
    pub fn is_refined(&self, c: Cell) -> bool {
        self.refined
            .get(c.level)
            .is_some_and(|r| r.contains(&c.index))
    }

    /// Whether the cell is an element of the mesh (in `Ω^ℓ`, not refined).
    pub fn is_active(&self, c: Cell) -> bool {
        self.in_domain(c) && !self.is_refined(c)
    }

    /// The refined cells, by level then index (deterministic).
    pub fn refined_cells(&self) -> Vec<Cell> {
        let mut out = Vec::new();
        for (level, r) in self.refined.iter().enumerate() {
            let mut v: Vec<[u32; 3]> = r.iter().copied().collect();
            v.sort_by_key(|i| [i[2], i[1], i[0]]);
            out.extend(v.into_iter().map(|index| Cell { level, index }));
        }
        out
    }

    /// The active cells: level-0 cells first direction fastest, each refined cell
    /// replaced by its active descendants in the same order (depth first). For an
    /// unrefined mesh, the tensor-product element order.
    pub fn active_cells(&self) -> Vec<Cell> {
        let n: Vec<u32> = (0..3).map(|d| self.n_cells(0, d)).collect();
        let mut out = Vec::new();
        for i2 in 0..n[2] {
            for i1 in 0..n[1] {
                for i0 in 0..n[0] {
                    self.push_active(
                        Cell {
                            level: 0,
                            index: [i0, i1, i2],
                        },
                        &mut out,
                    );
                }
            }
        }
        out
    }

    fn push_active(&self, c: Cell, out: &mut Vec<Cell>) {
        if self.is_refined(c) {
            for child in self.children(c) {
                self.push_active(child, out);
            }
        } else {
            out.push(c);
        }
    }

    /// The active cell containing the parameter point `xi` (clamped into the domain; on an
    /// element boundary, the element whose span search picks it, as for knot spans).
    pub fn locate(&self, xi: &[f64]) -> Cell {
        let l0 = &self.levels[0];
        let mut index = [0u32; 3];
        for d in 0..self.dim {
            let s = l0.knots[d].find_span(xi[d]);
            index[d] = l0.spans[d].partition_point(|&x| x < s) as u32;
        }
        let mut c = Cell { level: 0, index };
        while self.is_refined(c) {
            let lv = &self.levels[c.level + 1];
            let halved = self.halved(c.level);
            let mut index = c.index;
            for d in (0..self.dim).filter(|&d| halved[d]) {
                let left = 2 * c.index[d];
                let (_, mid) = lv.bounds(d, left);
                index[d] = if xi[d] >= mid { left + 1 } else { left };
            }
            c = Cell {
                level: c.level + 1,
                index,
            };
        }
        c
    }

    /// Parametric bounds (lower, upper) of a cell (unused directions 0).
    pub fn bounds(&self, c: Cell) -> ([f64; 3], [f64; 3]) {
        let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
        for d in 0..self.dim {
            (lo[d], hi[d]) = self.levels[c.level].bounds(d, c.index[d]);
        }
        (lo, hi)
    }

    /// Knot spans of a cell in its level's knot vectors (unused directions 0).
    pub fn spans(&self, c: Cell) -> [usize; 3] {
        let mut s = [0; 3];
        for d in 0..self.dim {
            s[d] = self.levels[c.level].span(d, c.index[d]);
        }
        s
    }

    /// Cells of level `l` in the support of function `f` (multi-index at level `l`), as
    /// inclusive ordinal ranges per direction.
    pub fn support(&self, l: usize, f: [usize; 3]) -> [(u32, u32); 3] {
        let mut r = [(0, 0); 3];
        for d in 0..self.dim {
            r[d] = self.levels[l].support(d, f[d]);
        }
        r
    }

    /// Whether every cell of `range` (level `l`) satisfies `pred`.
    pub fn all_cells(
        &self,
        l: usize,
        range: [(u32, u32); 3],
        mut pred: impl FnMut(Cell) -> bool,
    ) -> bool {
        for i2 in range[2].0..=range[2].1 {
            for i1 in range[1].0..=range[1].1 {
                for i0 in range[0].0..=range[0].1 {
                    if !pred(Cell {
                        level: l,
                        index: [i0, i1, i2],
                    }) {
                        return false;
                    }
                }
            }
        }
        true
    }

    /// Refines the given cells (each made refined, with the cells that admissibility and
    /// periodicity require). Cells already refined are left as they are.
    pub fn refine(&mut self, cells: &[Cell]) {
        for &c in cells {
            self.refine_cell(c);
        }
    }

    /// Halves the given cells once in every direction: each cell refined, and its
    /// descendants through the rest of one cycle of the pattern ([`Self::refine`] when
    /// dyadic).
    pub fn refine_cycle(&mut self, cells: &[Cell]) {
        let mut now = cells.to_vec();
        for step in 0..self.cycle() {
            self.refine(&now);
            if step + 1 < self.cycle() {
                now = now.iter().flat_map(|&c| self.children(c)).collect();
            }
        }
    }

    /// Refines every active cell whose parametric box meets `pred` (e.g. a layer near a face)
    /// once in every direction ([`Self::refine_cycle`]). Returns the number of cells marked.
    pub fn refine_where(
        &mut self,
        mut pred: impl FnMut(Cell, [f64; 3], [f64; 3]) -> bool,
    ) -> usize {
        let marked: Vec<Cell> = self
            .active_cells()
            .into_iter()
            .filter(|&c| {
                let (lo, hi) = self.bounds(c);
                pred(c, lo, hi)
            })
            .collect();
        self.refine_cycle(&marked);
        marked.len()
    }

    fn refine_cell(&mut self, c: Cell) {
        if self.is_refined(c) {
            return;
        }
        if !self.in_domain(c) {
            self.refine_cell(self.ancestor(c, c.level - 1));
        }
        // Admissibility (class 2 in cycles of the pattern): the cells of level ℓ − P (P the
        // pattern's length; ℓ − 1 when dyadic) meeting the support extension of c (the
        // supports of the level-ℓ functions nonzero on c) first.
        let cycle = self.pattern.len();
        if c.level >= cycle {
            let ext = self.support_extension(c);
            let cl = c.level - cycle;
            let mut coarse = ext;
            for d in 0..self.dim {
                let s = self.halvings(c.level, d) - self.halvings(cl, d);
                coarse[d] = (ext[d].0 >> s, ext[d].1 >> s);
            }
            let mut todo = Vec::new();
            self.all_cells(cl, coarse, |q| {
                if !self.is_refined(q) {
                    todo.push(q);
                }
                true
            });
            for q in todo {
                self.refine_cell(q);
            }
        }
        self.ensure_level(c.level + 1);
        while self.refined.len() <= c.level + 1 {
            self.refined.push(HashSet::new());
        }
        self.refined[c.level].insert(c.index);
        // Periodic directions: the first and last layers alike.
        for d in 0..self.dim {
            if !self.periodic[d] {
                continue;
            }
            let n = self.n_cells(c.level, d);
            let mirror = if c.index[d] == 0 {
                n - 1
            } else if c.index[d] == n - 1 {
                0
            } else {
                continue;
            };
            let mut m = c;
            m.index[d] = mirror;
            self.refine_cell(m);
        }
    }

    /// The support extension of a cell within its level: the cells on which some function
    /// nonzero on the cell is nonzero (inclusive ordinal ranges).
    pub fn support_extension(&self, c: Cell) -> [(u32, u32); 3] {
        let lv = &self.levels[c.level];
        let mut r = [(0, 0); 3];
        for d in 0..self.dim {
            let s = lv.span(d, c.index[d]);
            let p = lv.knots[d].degree();
            r[d] = (lv.support(d, s - p).0, lv.support(d, s).1);
        }
        r
    }

    /// The trace of the mesh on the face where direction `dir` is at its `side` end: a mesh
    /// of one direction less (the others in order), whose refined cells are those of the
    /// cells touching the face. The traces of the hierarchical basis on the face are the
    /// hierarchical basis of this mesh (open knot vectors: only the first function of a
    /// level is nonzero on the face, and its support is the first cell layer).
    #[track_caller]
    pub fn face(&self, dir: usize, low: bool) -> HierarchicalMesh {
        assert!(self.dim >= 2 && dir < self.dim, "HierarchicalMesh::face");
        let others: Vec<usize> = (0..self.dim).filter(|&d| d != dir).collect();
        let pattern = self
            .pattern
            .iter()
            .map(|h| {
                let mut m = [false; 3];
                for (k, &d) in others.iter().enumerate() {
                    m[k] = h[d];
                }
                m
            })
            .collect();
        let mut face = HierarchicalMesh::with_pattern(
            others
                .iter()
                .map(|&d| self.levels[0].knots[d].clone())
                .collect(),
            pattern,
        );
        for (k, &d) in others.iter().enumerate() {
            face.periodic[k] = self.periodic[d];
        }
        for (l, r) in self.refined.iter().enumerate() {
            if r.is_empty() {
                continue;
            }
            let edge = if low { 0 } else { self.n_cells(l, dir) - 1 };
            face.ensure_level(l + 1);
            while face.refined.len() <= l + 1 {
                face.refined.push(HashSet::new());
            }
            for idx in r.iter().filter(|i| i[dir] == edge) {
                let mut fi = [0u32; 3];
                for (k, &d) in others.iter().enumerate() {
                    fi[k] = idx[d];
                }
                face.refined[l].insert(fi);
            }
        }
        face
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh2(n: usize, p: usize) -> HierarchicalMesh {
        HierarchicalMesh::new(vec![
            KnotVector::open_uniform(p, n, 0.0, 1.0),
            KnotVector::open_uniform(p, n, 0.0, 1.0),
        ])
    }

    fn area(m: &HierarchicalMesh) -> f64 {
        m.active_cells()
            .iter()
            .map(|&c| {
                let (lo, hi) = m.bounds(c);
                (0..m.dim()).map(|d| hi[d] - lo[d]).product::<f64>()
            })
            .sum()
    }

    /// Points over the unit square each lie in the active cell that
    /// `locate` finds, which is one of `cells` (the mesh's active cells).
    fn assert_located_in(m: &HierarchicalMesh, cells: &[Cell]) {
        for k in 0..400 {
            let xi = [
                (k % 20) as f64 / 19.7 + 0.003,
                (k / 20) as f64 / 19.3 + 0.001,
            ];
            let c = m.locate(&xi);
            assert!(m.is_active(c));
            let (lo, hi) = m.bounds(c);
            assert!((0..2).all(|d| lo[d] <= xi[d].min(1.0) && xi[d].min(1.0) <= hi[d]));
            assert!(cells.contains(&c));
        }
    }

    #[test]
    fn active_cells_tile_the_domain() {
        let mut m = mesh2(4, 2);
        assert_eq!(m.active_cells().len(), 16);
        m.refine(&[Cell {
            level: 0,
            index: [1, 2, 0],
        }]);
        m.refine(&[Cell {
            level: 1,
            index: [3, 4, 0],
        }]);
        let cells = m.active_cells();
        assert!((area(&m) - 1.0).abs() < 1e-14);
        // Every point lies in exactly one active cell, the one `locate` finds.
        assert_located_in(&m, &cells);
    }

    #[test]
    fn refinement_is_admissible_of_class_2() {
        // Refining one corner cell four cycles deep grades the mesh: an active cell of
        // level ℓ meeting the support extension of an active cell of level ℓ + P + 1 or
        // more (P the pattern's length: one level dyadic, two graded) would violate class 2
        // counted in cycles.
        for (pattern, levels) in [
            (vec![[true, true, false]], 5),
            (vec![[true, false, false], [false, true, false]], 9),
        ] {
            let cycle = pattern.len();
            let mut m = mesh2(8, 2);
            m.pattern = pattern;
            for l in 0..4 * cycle {
                m.refine(&[Cell {
                    level: l,
                    index: [0, 0, 0],
                }]);
            }
            let cells = m.active_cells();
            for &q in &cells {
                let ext = m.support_extension(q);
                for &c in &cells {
                    if c.level + cycle < q.level {
                        let r = [0, 1].map(|d| m.n_cells(q.level, d) / m.n_cells(c.level, d));
                        let meets = (0..2).all(|d| {
                            c.index[d] * r[d] <= ext[d].1 && (c.index[d] + 1) * r[d] > ext[d].0
                        });
                        assert!(!meets, "{c:?} meets the support extension of {q:?}");
                    }
                }
            }
            assert_eq!(m.n_levels(), levels);
            assert!((area(&m) - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn a_graded_pattern_halves_its_directions_in_turn() {
        // Level 1 halves x, level 2 halves y, level 3 x again.
        let mut m = mesh2(4, 2);
        m.pattern = vec![[true, false, false], [false, true, false]];
        let c = Cell {
            level: 0,
            index: [1, 2, 0],
        };
        m.refine(&[c]);
        let kids: Vec<Cell> = m.children(c).collect();
        assert_eq!(kids.len(), 2);
        assert_eq!(kids[1].index, [3, 2, 0]);
        m.refine(&kids);
        let grandkids: Vec<Cell> = kids.iter().flat_map(|&k| m.children(k)).collect();
        assert_eq!(grandkids.len(), 4);
        m.refine(&grandkids[..1]);
        assert_eq!([0, 1].map(|d| m.n_cells(3, d)), [16, 8]);
        assert_eq!([0, 1].map(|d| m.level(2).n_elements(d)), [8, 8]);
        for &g in &grandkids {
            assert_eq!(m.ancestor(g, 0), c);
            assert_eq!(m.ancestor(g, 1).index, [g.index[0], g.index[1] / 2, 0]);
        }
        assert!((area(&m) - 1.0).abs() < 1e-14);
        assert_located_in(&m, &m.active_cells());
        // The face y = 1 sees the x-levels only: its level 2 repeats level 1.
        let face = m.face(1, false);
        assert_eq!(face.n_cells(1, 0), 8);
        assert_eq!(face.n_cells(2, 0), 8);
        assert_eq!(face.halved(1), [false; 3]);
    }

    #[test]
    fn periodic_directions_refine_both_layers() {
        let mut m = mesh2(4, 2);
        m.set_periodic(0);
        m.refine(&[Cell {
            level: 0,
            index: [0, 3, 0],
        }]);
        assert!(m.is_refined(Cell {
            level: 0,
            index: [3, 3, 0]
        }));
        let low = m.face(0, true);
        let high = m.face(0, false);
        assert_eq!(low.refined_cells(), high.refined_cells());
    }
}
