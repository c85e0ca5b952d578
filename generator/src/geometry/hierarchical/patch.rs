//! [`ThbPatch`]: a rational THB-spline patch — the locally refinable
//! counterpart of [`NurbsPatch`] that the analysis works on.
//!
//! The geometry is the one of the NURBS patch it was built from, exactly:
//! the THB spaces contain the level-0 space, so the homogeneous coordinates
//! `(w x, w)` of the NURBS map are prolonged exactly ([`prolongate`]) and the
//! rational THB functions `R_a = w_a T_a / W` with `W = Σ w_a T_a` reproduce
//! the NURBS map. An unrefined `ThbPatch` has the NURBS patch's functions,
//! numbering and elements.

use super::basis::{ThbBasis, ThbElement, prolongate, prolongation_entries};
use super::mesh::{Cell, HierarchicalMesh};
use crate::basis::{RationalBasis, TensorBasis, bspline_tensor_into, rationalize};
use crate::geometry::patch_quadrature::{
    bulk_point, face_point, gauss_rules, physical_gradients, tensor_points,
};
use crate::geometry::{ElementQuadrature, FaceElementQuadrature, KnotVector, NurbsPatch, Side};
use crate::quadrature::GaussLegendre;
use std::sync::Arc;

/// A rational THB-spline patch of 1 to 3 parametric directions, control points in 3D.
/// The mesh and the basis are shared by the copies that move the control points only
/// ([`ThbPatch::map_points`], [`ThbPatch::with_control_points`]): the 3D egg box's
/// fourth-level basis holds 200 MB of extraction operators, which the fitted geometry and
/// the model's scaled copy held twice (docs/3d.md, "Stop 44").
#[derive(Clone, Debug)]
pub struct ThbPatch {
    mesh: Arc<HierarchicalMesh>,
    basis: Arc<ThbBasis>,
    points: Vec<[f64; 3]>,
    weights: Vec<f64>,
}

/// Homogeneous coordinates `(w x, w y, w z, w)` per control point.
fn homogeneous(points: &[[f64; 3]], weights: &[f64]) -> Vec<f64> {
    points
        .iter()
        .zip(weights)
        .flat_map(|(x, &w)| [w * x[0], w * x[1], w * x[2], w])
        .collect()
}

/// Control points and weights from homogeneous coordinates.
fn cartesian(h: &[f64]) -> (Vec<[f64; 3]>, Vec<f64>) {
    h.chunks(4)
        .map(|c| ([c[0] / c[3], c[1] / c[3], c[2] / c[3]], c[3]))
        .unzip()
}

impl From<&NurbsPatch> for ThbPatch {
    fn from(patch: &NurbsPatch) -> Self {
        ThbPatch::from_nurbs(patch)
    }
}

impl ThbPatch {
    /// The unrefined THB patch of a NURBS patch (same functions, numbering and elements),
    /// refined dyadically from now on.
    pub fn from_nurbs(patch: &NurbsPatch) -> Self {
        let dyadic = HierarchicalMesh::dyadic_pattern(patch.param_dim());
        Self::from_nurbs_with_pattern(patch, dyadic)
    }

    /// [`Self::from_nurbs`] whose levels halve the directions of `pattern` in turn (see
    /// [`HierarchicalMesh::with_pattern`]).
    pub fn from_nurbs_with_pattern(patch: &NurbsPatch, pattern: Vec<[bool; 3]>) -> Self {
        let mesh = HierarchicalMesh::with_pattern(patch.knots().to_vec(), pattern);
        let basis = ThbBasis::new(&mesh);
        debug_assert_eq!(basis.n_functions(), patch.n_control_points());
        ThbPatch {
            mesh: Arc::new(mesh),
            basis: Arc::new(basis),
            points: patch.control_points().to_vec(),
            weights: patch.weights().to_vec(),
        }
    }

    /// The NURBS patch of an unrefined THB patch (`None` once refined).
    pub fn to_nurbs(&self) -> Option<NurbsPatch> {
        (self.mesh.n_levels() == 1).then(|| {
            NurbsPatch::new(
                self.knots().to_vec(),
                self.points.clone(),
                self.weights.clone(),
            )
            .expect("a THB patch has valid control points and weights")
        })
    }

    /// The same geometry on a refinement of the mesh (`mesh` must contain every refined cell
    /// of this patch's mesh): control points by exact prolongation.
    #[track_caller]
    pub fn with_mesh(&self, mesh: HierarchicalMesh) -> ThbPatch {
        assert!(
            self.mesh
                .refined_cells()
                .into_iter()
                .all(|c| mesh.is_refined(c)),
            "ThbPatch::with_mesh: the new mesh must refine the old one"
        );
        let basis = ThbBasis::new(&mesh);
        let h = prolongate(
            &self.basis,
            &mesh,
            &basis,
            &homogeneous(&self.points, &self.weights),
            4,
        );
        let (points, weights) = cartesian(&h);
        ThbPatch {
            mesh: Arc::new(mesh),
            basis: Arc::new(basis),
            points,
            weights,
        }
    }

    /// A copy with the given cells halved in every direction (see
    /// [`HierarchicalMesh::refine_cycle`]).
    pub fn refined(&self, cells: &[Cell]) -> ThbPatch {
        let mut mesh = HierarchicalMesh::clone(&self.mesh);
        mesh.refine_cycle(cells);
        self.with_mesh(mesh)
    }

    /// A copy whose parametric direction `d` is periodic: the first and last cell layers
    /// are refined alike (see [`HierarchicalMesh::set_periodic`]), so the traces on the two
    /// opposite faces match one to one (periodic ties).
    pub fn periodic(&self, d: usize) -> ThbPatch {
        let mut mesh = HierarchicalMesh::clone(&self.mesh);
        mesh.set_periodic(d);
        self.with_mesh(mesh)
    }

    /// A copy refined `levels` times at the face where direction `dir` is at its `side`
    /// end: each round halves the elements touching the face; admissibility grades the
    /// mesh away from it.
    pub fn refined_at_face(&self, dir: usize, side: Side, levels: usize) -> ThbPatch {
        let mut mesh = HierarchicalMesh::clone(&self.mesh);
        let kv = &self.knots()[dir];
        for _ in 0..levels {
            mesh.refine_where(|_, lo, hi| match side {
                Side::Low => lo[dir] <= kv.first(),
                Side::High => hi[dir] >= kv.last(),
            });
        }
        self.with_mesh(mesh)
    }

    /// The coefficients in the space of the refinement `to` of a field with `n_comp`
    /// components per function (function-major) in this patch's space: exact (nested
    /// spaces; the rational basis is handled through the weights).
    pub fn prolongate(&self, to: &ThbPatch, values: &[f64], n_comp: usize) -> Vec<f64> {
        let weighted: Vec<f64> = values
            .iter()
            .enumerate()
            .map(|(i, v)| v * self.weights[i / n_comp])
            .collect();
        let mut out = prolongate(&self.basis, &to.mesh, &to.basis, &weighted, n_comp);
        for (i, v) in out.iter_mut().enumerate() {
            *v /= to.weights[i / n_comp];
        }
        out
    }

    /// The matrix of [`ThbPatch::prolongate`] for one component: `(fine, coarse, value)`
    /// for every nonzero coefficient (the weights of the rational basis included).
    pub fn prolongation_entries(&self, to: &ThbPatch) -> Vec<(usize, usize, f64)> {
        let mut out = prolongation_entries(&self.basis, &to.mesh, &to.basis);
        for (a, g, v) in out.iter_mut() {
            *v *= self.weights[*g] / to.weights[*a];
        }
        out
    }

    /// The hierarchical mesh.
    pub fn mesh(&self) -> &HierarchicalMesh {
        &self.mesh
    }

    /// The THB basis (functions, elements, extraction).
    pub fn thb_basis(&self) -> &ThbBasis {
        &self.basis
    }

    /// Number of parametric directions.
    pub fn param_dim(&self) -> usize {
        self.mesh.dim()
    }

    /// The level-0 knot vectors, one per direction.
    pub fn knots(&self) -> &[KnotVector] {
        &self.mesh.level(0).knots
    }

    /// The degrees, one per parametric direction.
    pub fn degrees(&self) -> Vec<usize> {
        self.knots().iter().map(KnotVector::degree).collect()
    }

    /// Number of control points (THB functions).
    pub fn n_control_points(&self) -> usize {
        self.points.len()
    }

    /// Cartesian control points.
    pub fn control_points(&self) -> &[[f64; 3]] {
        &self.points
    }

    /// Control weights.
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The elements (active cells).
    pub fn elements(&self) -> &[ThbElement] {
        self.basis.elements()
    }

    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.basis.elements().len()
    }

    /// A copy with every control point mapped by `f` (weights and mesh unchanged).
    pub fn map_points(&self, f: impl Fn([f64; 3]) -> [f64; 3]) -> ThbPatch {
        ThbPatch {
            mesh: Arc::clone(&self.mesh),
            basis: Arc::clone(&self.basis),
            points: self.points.iter().map(|&x| f(x)).collect(),
            weights: self.weights.clone(),
        }
    }

    /// A copy with the given control points (one per THB function; weights and mesh unchanged).
    #[track_caller]
    pub fn with_control_points(&self, points: Vec<[f64; 3]>) -> ThbPatch {
        assert_eq!(
            points.len(),
            self.points.len(),
            "ThbPatch::with_control_points: one point per function"
        );
        ThbPatch {
            mesh: Arc::clone(&self.mesh),
            basis: Arc::clone(&self.basis),
            points,
            weights: self.weights.clone(),
        }
    }

    /// Coefficients (one per THB function, this patch's numbering) of the hierarchical
    /// quasi-interpolant `Σ_a λ_a(g) T_a` of a scalar function `g` of the parameters, in
    /// the polynomial THB functions `T_a`. The functional of a function of level `ℓ` and
    /// multi-index `f` is the coefficient of the level-`ℓ` B-spline `f` in the interpolant
    /// of `g` by the level-`ℓ` tensor B-splines of one *active* level-`ℓ` cell of its
    /// support, at `p + 1` equally spaced points per direction (the cell's ends included).
    /// On an active level-`ℓ` cell the level-`ℓ` B-spline coefficients of any function of
    /// the truncated basis's span are its THB coefficients (Speleers & Manni 2016,
    /// *Effortless quasi-interpolation in hierarchical spaces*), so the quasi-interpolant
    /// reproduces the THB space exactly, is local, and approximates a smooth `g` at the
    /// order of the finest level around each point. At a clamped end the end function's
    /// coefficient is `g` there: opposite faces carrying the same values get the same
    /// coefficients (periodic ties).
    pub fn quasi_interpolate(&self, g: impl Fn([f64; 3]) -> f64) -> Vec<f64> {
        let dim = self.param_dim();
        let degrees = self.degrees();
        let mut local: std::collections::HashMap<Cell, Vec<f64>> = Default::default();
        (0..self.basis.n_functions())
            .map(|a| {
                let (l, f) = self.basis.function(a);
                let range = self.mesh.support(l, f);
                let cell = active_cell_in(&self.mesh, l, range).expect(
                    "an active THB function has an active cell of its level in its support",
                );
                let spans = self.mesh.spans(cell);
                let coefficients = local
                    .entry(cell)
                    .or_insert_with(|| local_interpolant(&self.mesh, cell, &degrees, &g));
                // Local tensor index (first direction fastest) of `f` on the cell.
                let mut at = 0;
                let mut stride = 1;
                for d in 0..dim {
                    at += (f[d] + degrees[d] - spans[d]) * stride;
                    stride *= degrees[d] + 1;
                }
                coefficients[at]
            })
            .collect()
    }

    /// The rational THB functions nonzero on element `e` at `xi` (the element's polynomial
    /// pieces: its ends give one-sided limits) with parametric derivatives up to `n_ders ≤ 2`,
    /// into `out`; `scratch` holds the element's B-splines.
    pub fn element_basis_into(
        &self,
        e: usize,
        xi: &[f64],
        n_ders: usize,
        scratch: &mut TensorBasis,
        out: &mut RationalBasis,
    ) {
        self.thb_functions_into(e, xi, n_ders, scratch, out);
        rationalize(out, &self.weights, self.param_dim(), n_ders);
    }

    /// The polynomial THB functions `T_a` (before the rational weighting) nonzero on
    /// element `e` at `xi`, with parametric derivatives up to `n_ders ≤ 2`: the element's
    /// B-splines times its extraction.
    pub fn thb_functions_into(
        &self,
        e: usize,
        xi: &[f64],
        n_ders: usize,
        scratch: &mut TensorBasis,
        out: &mut RationalBasis,
    ) {
        let el = &self.basis.elements()[e];
        let dim = self.param_dim();
        let level = self.mesh.level(el.cell.level);
        bspline_tensor_into(&level.knots, &el.spans[..dim], xi, n_ders, scratch);
        out.indices.clone_from(&el.functions);
        let Some(c) = &el.extraction else {
            out.values.clone_from(&scratch.values);
            out.d1.clone_from(&scratch.d1);
            out.d2.clone_from(&scratch.d2);
            return;
        };
        let n_local = scratch.values.len();
        out.values.clear();
        out.d1.clear();
        out.d2.clear();
        for row in c.chunks(n_local) {
            let mut v = 0.0;
            let mut g = [0.0; 3];
            let mut h = [[0.0; 3]; 3];
            for (j, &cj) in row.iter().enumerate() {
                if cj == 0.0 {
                    continue;
                }
                v += cj * scratch.values[j];
                if n_ders >= 1 {
                    for k in 0..3 {
                        g[k] += cj * scratch.d1[j][k];
                    }
                    if n_ders >= 2 {
                        for k in 0..3 {
                            for l in 0..3 {
                                h[k][l] += cj * scratch.d2[j][k][l];
                            }
                        }
                    }
                }
            }
            out.values.push(v);
            if n_ders >= 1 {
                out.d1.push(g);
            }
            if n_ders >= 2 {
                out.d2.push(h);
            }
        }
    }

    /// For curves: `ders[k][a]`, the `k`-th parametric derivative (`k = 0..=n`) at `u` of
    /// the polynomial THB function `a` of element `e` (in the order of its `functions`),
    /// from the element's polynomial piece (derivatives above the degree are 0).
    #[track_caller]
    pub fn curve_element_ders(&self, e: usize, u: f64, n: usize) -> Vec<Vec<f64>> {
        assert_eq!(self.param_dim(), 1, "curve_element_ders: only for curves");
        let el = &self.basis.elements()[e];
        let kv = &self.mesh.level(el.cell.level).knots[0];
        let ders = crate::basis::basis_ders(kv, el.spans[0], u, n);
        match &el.extraction {
            None => ders,
            Some(c) => {
                let n_local = kv.degree() + 1;
                ders.iter()
                    .map(|row| {
                        c.chunks(n_local)
                            .map(|ca| ca.iter().zip(row).map(|(x, y)| x * y).sum())
                            .collect()
                    })
                    .collect()
            }
        }
    }

    /// For surfaces: `ders[k1 (n + 1) + k2][a]`, the derivative `∂^(k1+k2) / ∂u^k1 ∂v^k2`
    /// (`k1, k2 = 0..=n`) at `u` of the polynomial THB function `a` of element `e` (in the
    /// order of its `functions`), from the element's polynomial piece. With `n` at least the
    /// degrees, the table is the function's exact bivariate Taylor expansion about `u`.
    #[track_caller]
    pub fn surface_element_ders(&self, e: usize, u: [f64; 2], n: usize) -> Vec<Vec<f64>> {
        assert_eq!(
            self.param_dim(),
            2,
            "surface_element_ders: only for surfaces"
        );
        let el = &self.basis.elements()[e];
        let knots = &self.mesh.level(el.cell.level).knots;
        let d0 = crate::basis::basis_ders(&knots[0], el.spans[0], u[0], n);
        let d1 = crate::basis::basis_ders(&knots[1], el.spans[1], u[1], n);
        let (p0, p1) = (knots[0].degree() + 1, knots[1].degree() + 1);
        let mut out = Vec::with_capacity((n + 1) * (n + 1));
        for k1 in 0..=n {
            for k2 in 0..=n {
                // Local tensor functions, first direction fastest.
                let local: Vec<f64> = (0..p0 * p1)
                    .map(|j| d0[k1][j % p0] * d1[k2][j / p0])
                    .collect();
                out.push(match &el.extraction {
                    None => local,
                    Some(c) => c
                        .chunks(p0 * p1)
                        .map(|ca| ca.iter().zip(&local).map(|(x, y)| x * y).sum())
                        .collect(),
                });
            }
        }
        out
    }

    /// [`Self::element_basis_into`] with fresh buffers.
    pub fn element_basis(&self, e: usize, xi: &[f64], n_ders: usize) -> RationalBasis {
        let mut out = RationalBasis::default();
        self.element_basis_into(e, xi, n_ders, &mut TensorBasis::default(), &mut out);
        out
    }

    /// The rational basis functions nonzero at `xi` (in the element [`Self::locate`] finds)
    /// with parametric derivatives up to `n_ders ≤ 2`.
    pub fn basis(&self, xi: &[f64], n_ders: usize) -> RationalBasis {
        self.element_basis(self.locate(xi), xi, n_ders)
    }

    /// The element containing the parameter point `xi` (clamped into the domain).
    pub fn locate(&self, xi: &[f64]) -> usize {
        self.basis
            .element_of(self.mesh.locate(xi))
            .expect("locate returns an active cell")
    }

    /// The physical point `x(ξ)`.
    pub fn point(&self, xi: &[f64]) -> [f64; 3] {
        let b = self.element_basis(self.locate(xi), xi, 0);
        let mut x = [0.0; 3];
        for (&a, &r) in b.indices.iter().zip(&b.values) {
            for i in 0..3 {
                x[i] += r * self.points[a][i];
            }
        }
        x
    }

    /// The physical length of cell `c` across its parametric direction `d`:
    /// the chord between the midpoints of its two faces normal to `d` (exact
    /// geometry; the cell need not be active).
    pub fn cell_extent(&self, c: Cell, d: usize) -> f64 {
        let (lo, hi) = self.mesh.bounds(c);
        let dim = self.param_dim();
        let mid: Vec<f64> = (0..dim).map(|k| 0.5 * (lo[k] + hi[k])).collect();
        let (mut a, mut b) = (mid.clone(), mid);
        (a[d], b[d]) = (lo[d], hi[d]);
        let (xa, xb) = (self.point(&a), self.point(&b));
        (0..3).map(|i| (xb[i] - xa[i]).powi(2)).sum::<f64>().sqrt()
    }

    /// Bulk quadrature of element `e` with `n_gauss[d]` Gauss points in direction `d` (a
    /// single entry applies to all directions), for `param_dim ==` spatial dimension.
    #[track_caller]
    pub fn element_quadrature(&self, e: usize, n_gauss: &[usize]) -> ElementQuadrature {
        let dim = self.param_dim();
        let el = &self.basis.elements()[e];
        let degrees: Vec<usize> = self.knots().iter().map(KnotVector::degree).collect();
        let mut scratch = TensorBasis::default();
        ElementQuadrature::build(
            dim,
            (el.lower, el.upper),
            &gauss_rules(dim, n_gauss),
            &degrees,
            &self.points,
            &self.weights,
            |xi, basis| self.element_basis_into(e, xi, 1, &mut scratch, basis),
        )
    }

    /// The boundary face where direction `dir` is at its `side` end, as a patch of one
    /// dimension less (remaining directions in order), and the indices in this patch of its
    /// functions (the THB functions with a nonzero trace), in the face patch's numbering.
    #[track_caller]
    pub fn face(&self, dir: usize, side: Side) -> (ThbPatch, Vec<usize>) {
        let dim = self.param_dim();
        assert!(
            dim >= 2 && dir < dim,
            "ThbPatch::face: direction {dir} of a {dim}-direction patch"
        );
        let mesh = self.mesh.face(dir, side == Side::Low);
        let basis = ThbBasis::new(&mesh);
        let others: Vec<usize> = (0..dim).filter(|&d| d != dir).collect();
        let indices: Vec<usize> = (0..basis.n_functions())
            .map(|a| {
                let (l, g) = basis.function(a);
                let mut f = [0usize; 3];
                for (k, &d) in others.iter().enumerate() {
                    f[d] = g[k];
                }
                f[dir] = match side {
                    Side::Low => 0,
                    Side::High => self.mesh.level(l).n_functions(dir) - 1,
                };
                self.basis
                    .id(l, f)
                    .expect("the face functions are traces of active functions")
            })
            .collect();
        let points = indices.iter().map(|&a| self.points[a]).collect();
        let weights = indices.iter().map(|&a| self.weights[a]).collect();
        (
            ThbPatch {
                mesh: Arc::new(mesh),
                basis: Arc::new(basis),
                points,
                weights,
            },
            indices,
        )
    }

    /// The cell of the volume element adjacent to face cell `c` of face (`dir`, `side`).
    pub fn face_volume_cell(&self, c: Cell, dir: usize, side: Side) -> Cell {
        let dim = self.param_dim();
        let mut index = [0u32; 3];
        let mut k = 0;
        for (d, i) in index.iter_mut().enumerate().take(dim) {
            if d == dir {
                *i = match side {
                    Side::Low => 0,
                    Side::High => self.mesh.n_cells(c.level, dir) - 1,
                };
            } else {
                *i = c.index[k];
                k += 1;
            }
        }
        Cell {
            level: c.level,
            index,
        }
    }

    /// The volume element at the parameter point `xi` and the derivatives
    /// `∂R_a/∂x_dir` (reference configuration) of the functions nonzero there.
    pub fn normal_derivatives(&self, xi: [f64; 3], dir: usize) -> SeamSide {
        let dim = self.param_dim();
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        let e = self.locate(&xi[..dim]);
        self.element_basis_into(e, &xi[..dim], 1, &mut scratch, &mut basis);
        let point = bulk_point(dim, xi, 1.0, &basis, &self.points);
        let el = &self.basis.elements()[e];
        let mut column = [0.0; 3];
        for (a, &g) in basis.indices.iter().enumerate() {
            for (i, c) in column.iter_mut().enumerate() {
                *c += basis.d1[a][dir] * self.points[g][i];
            }
        }
        let length = column.iter().map(|c| c * c).sum::<f64>().sqrt();
        let normal_derivative = physical_gradients(dim, &point, &basis)
            .map(|d| d[dir])
            .collect();
        SeamSide {
            element: e,
            conn: basis.indices,
            normal_derivative,
            width: length * (el.upper[dir] - el.lower[dir]),
        }
    }

    /// The periodic seam across direction `dir` (the faces at its two ends,
    /// identified by PR conditions): at each Gauss point of the low face
    /// (`n_gauss` per face direction), [`Self::normal_derivatives`] on either
    /// side, the low one at the point and the high one at the same face
    /// parameters; the weight is the low face's (Gauss weight × surface or
    /// line Jacobian).
    pub fn seam_points(&self, dir: usize, n_gauss: usize) -> Vec<SeamPoint> {
        let high_end = self.knots()[dir].last();
        let mut out = Vec::new();
        for fe in self.face_quadrature(dir, Side::Low, n_gauss) {
            for qp in fe.points {
                let mut high = qp.xi;
                high[dir] = high_end;
                out.push(SeamPoint {
                    weight: qp.weight,
                    sides: [
                        self.normal_derivatives(qp.xi, dir),
                        self.normal_derivatives(high, dir),
                    ],
                });
            }
        }
        out
    }

    /// Quadrature over the face where direction `dir` is at its `side` end, per face
    /// element, with `n_gauss` points per face direction (weights with the surface or line
    /// Jacobian, outward unit normals). `conn` holds this patch's indices of the face
    /// functions, `r` their values.
    #[track_caller]
    pub fn face_quadrature(
        &self,
        dir: usize,
        side: Side,
        n_gauss: usize,
    ) -> Vec<FaceElementQuadrature> {
        let dim = self.param_dim();
        let (face, indices) = self.face(dir, side);
        let end = match side {
            Side::Low => self.knots()[dir].first(),
            Side::High => self.knots()[dir].last(),
        };
        let face_dirs: Vec<usize> = (0..dim).filter(|&d| d != dir).collect();
        let rules = vec![GaussLegendre::new(n_gauss); dim - 1];
        let (mut scratch, mut volume, mut trace) = (
            TensorBasis::default(),
            RationalBasis::default(),
            RationalBasis::default(),
        );
        let mut out = Vec::with_capacity(face.n_elements());
        for (fe, fel) in face.elements().iter().enumerate() {
            let cell = self.face_volume_cell(fel.cell, dir, side);
            let e = self
                .basis
                .element_of(cell)
                .expect("a face element lies on an active volume element");
            let el = &self.basis.elements()[e];
            let (mut lo, mut hi) = (el.lower, el.upper);
            lo[dir] = end;
            hi[dir] = end;
            let points = tensor_points(&face_dirs, lo, hi, &rules)
                .into_iter()
                .map(|(xi, wq)| {
                    self.element_basis_into(e, &xi[..dim], 1, &mut scratch, &mut volume);
                    let fxi: Vec<f64> = face_dirs.iter().map(|&d| xi[d]).collect();
                    face.element_basis_into(fe, &fxi, 0, &mut scratch, &mut trace);
                    face_point(
                        dim,
                        (dir, side),
                        xi,
                        wq,
                        &volume,
                        &self.points,
                        trace.values.clone(),
                    )
                })
                .collect();
            out.push(FaceElementQuadrature {
                conn: fel.functions.iter().map(|&a| indices[a]).collect(),
                points,
            });
        }
        out
    }
}

/// One side of a [`SeamPoint`].
#[derive(Clone, Debug, PartialEq)]
pub struct SeamSide {
    /// The volume element.
    pub element: usize,
    /// Patch indices of the functions nonzero there.
    pub conn: Vec<usize>,
    /// `∂R_a/∂x_dir`, indexed like `conn`.
    pub normal_derivative: Vec<f64>,
    /// The element's width along `dir` (its parametric length times `|∂x/∂ξ_dir|`).
    pub width: f64,
}

/// A quadrature point of a periodic seam ([`ThbPatch::seam_points`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SeamPoint {
    /// Gauss weight × the low face's surface (3D) or line (2D) Jacobian.
    pub weight: f64,
    /// The low side (`ξ_dir` at its first knot) and the high side (last knot).
    pub sides: [SeamSide; 2],
}

/// An active cell of level `l` in the ordinal ranges `range` (inclusive, per direction),
/// the one nearest the middle of the ranges.
fn active_cell_in(mesh: &HierarchicalMesh, l: usize, range: [(u32, u32); 3]) -> Option<Cell> {
    let mut best: Option<(u64, Cell)> = None;
    for k in range[2].0..=range[2].1 {
        for j in range[1].0..=range[1].1 {
            for i in range[0].0..=range[0].1 {
                let cell = Cell {
                    level: l,
                    index: [i, j, k],
                };
                if !mesh.is_active(cell) {
                    continue;
                }
                let distance: u64 = (0..3)
                    .map(|d| {
                        let twice_mid = u64::from(range[d].0) + u64::from(range[d].1);
                        (2 * u64::from(cell.index[d])).abs_diff(twice_mid)
                    })
                    .sum();
                if best.is_none_or(|(b, _)| distance < b) {
                    best = Some((distance, cell));
                }
            }
        }
    }
    best.map(|(_, c)| c)
}

/// The coefficients of the interpolant of `g` by the level's tensor B-splines nonzero on
/// `cell` (first direction fastest), at `p + 1` equally spaced points per direction.
fn local_interpolant(
    mesh: &HierarchicalMesh,
    cell: Cell,
    degrees: &[usize],
    g: &impl Fn([f64; 3]) -> f64,
) -> Vec<f64> {
    let dim = mesh.dim();
    let level = mesh.level(cell.level);
    let (lo, hi) = mesh.bounds(cell);
    let spans = mesh.spans(cell);
    let mut points: [Vec<f64>; 3] = Default::default();
    let mut inverses: Vec<nalgebra::DMatrix<f64>> = Vec::with_capacity(dim);
    for d in 0..dim {
        let p = degrees[d];
        let t: Vec<f64> = (0..=p)
            .map(|i| lo[d] + (hi[d] - lo[d]) * i as f64 / p as f64)
            .collect();
        let m = nalgebra::DMatrix::from_fn(p + 1, p + 1, |i, j| {
            crate::basis::basis_ders(&level.knots[d], spans[d], t[i], 0)[0][j]
        });
        inverses.push(
            m.try_inverse()
                .expect("B-splines of one span are unisolvent at distinct points of the span"),
        );
        points[d] = t;
    }
    for p in points.iter_mut().skip(dim) {
        *p = vec![0.0];
    }
    // Values on the tensor grid, first direction fastest.
    let mut c: Vec<f64> = Vec::new();
    for &z in &points[2] {
        for &y in &points[1] {
            for &x in &points[0] {
                c.push(g([x, y, z]));
            }
        }
    }
    // Mode products with the inverse collocation matrices, direction by direction.
    let sizes: Vec<usize> = (0..3).map(|d| points[d].len()).collect();
    for (d, inv) in inverses.iter().enumerate() {
        let stride: usize = sizes[..d].iter().product();
        let n = sizes[d];
        let mut next = vec![0.0; c.len()];
        for base in (0..c.len()).filter(|i| (i / stride).is_multiple_of(n)) {
            for r in 0..n {
                next[base + r * stride] = (0..n).map(|k| inv[(r, k)] * c[base + k * stride]).sum();
            }
        }
        c = next;
    }
    c
}
