//! NURBS patches: one type for curves, surfaces and volumes.
//!
//! Refinement lives in [`super::refine`], element and face quadrature in
//! [`super::patch_quadrature`]; their types are re-exported here.
#![allow(clippy::needless_range_loop)]

use super::knots::KnotVector;
use crate::basis::{basis_ders, nurbs_basis_into};
use crate::{Error, Result};

pub use super::patch_quadrature::{
    ElementQuadrature, FaceElementQuadrature, FaceQuadPoint, QuadPoint,
};
pub use crate::basis::RationalBasis;

/// A NURBS patch with 1 to 3 parametric directions, control points in 3D Cartesian coordinates.
#[derive(Clone, Debug)]
pub struct NurbsPatch {
    knots: Vec<KnotVector>,
    points: Vec<[f64; 3]>,
    weights: Vec<f64>,
}

/// Which end of a parametric direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    /// `ξ_dir` at its first knot.
    Low,
    /// `ξ_dir` at its last knot.
    High,
}

/// One element: a non-empty knot span in every parametric direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Element {
    /// Span index per direction (unused directions 0).
    pub spans: [usize; 3],
    /// Lower parametric corner (unused directions 0).
    pub lower: [f64; 3],
    /// Upper parametric corner (unused directions 0).
    pub upper: [f64; 3],
}

impl NurbsPatch {
    /// A patch from its knot vectors (1 to 3), Cartesian control points `[x, y, z]`
    /// (z = 0 for planar) and positive weights, ordered first direction fastest:
    /// `index = i0 + n0 (i1 + n1 i2)`.
    pub fn new(knots: Vec<KnotVector>, points: Vec<[f64; 3]>, weights: Vec<f64>) -> Result<Self> {
        if !(1..=3).contains(&knots.len()) {
            return Err(Error::Geometry(format!(
                "NURBS patch: 1 to 3 parametric directions (knot vectors), got {}",
                knots.len()
            )));
        }
        let n: usize = knots.iter().map(KnotVector::n_basis).product();
        if points.len() != n || weights.len() != n {
            return Err(Error::Geometry(format!(
                "NURBS patch: the knot vectors define {n} control points, got {} points and {} weights",
                points.len(),
                weights.len()
            )));
        }
        if let Some(i) = weights.iter().position(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(Error::Geometry(format!(
                "NURBS patch: weight {i} = {} must be finite and > 0",
                weights[i]
            )));
        }
        if let Some(i) = points.iter().position(|x| x.iter().any(|c| !c.is_finite())) {
            return Err(Error::Geometry(format!(
                "NURBS patch: control point {i} = {:?} is not finite",
                points[i]
            )));
        }
        Ok(NurbsPatch {
            knots,
            points,
            weights,
        })
    }

    /// A B-spline patch (all weights 1).
    pub fn bspline(knots: Vec<KnotVector>, points: Vec<[f64; 3]>) -> Result<Self> {
        let weights = vec![1.0; points.len()];
        Self::new(knots, points, weights)
    }

    /// Number of parametric directions (1 curve, 2 surface, 3 volume).
    pub fn param_dim(&self) -> usize {
        self.knots.len()
    }

    /// The knot vectors, one per parametric direction.
    pub fn knots(&self) -> &[KnotVector] {
        &self.knots
    }

    /// The degrees, one per parametric direction.
    pub fn degrees(&self) -> Vec<usize> {
        self.knots.iter().map(KnotVector::degree).collect()
    }

    /// Control points per direction.
    pub fn n_per_dir(&self) -> Vec<usize> {
        self.knots.iter().map(KnotVector::n_basis).collect()
    }

    /// Total number of control points.
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

    /// Global index of the control point with per-direction indices `ijk`.
    #[track_caller]
    pub fn index(&self, ijk: &[usize]) -> usize {
        assert_eq!(
            ijk.len(),
            self.param_dim(),
            "NurbsPatch::index: need one index per direction"
        );
        let mut index = 0;
        for d in (0..self.param_dim()).rev() {
            let n = self.knots[d].n_basis();
            assert!(
                ijk[d] < n,
                "NurbsPatch::index: index {} out of range 0..{n} in direction {d}",
                ijk[d]
            );
            index = index * n + ijk[d];
        }
        index
    }

    /// Per-direction indices of the control point with global index `a` (inverse of [`Self::index`]).
    #[track_caller]
    pub fn ijk(&self, a: usize) -> [usize; 3] {
        assert!(
            a < self.points.len(),
            "NurbsPatch::ijk: index {a} out of range"
        );
        let mut rest = a;
        let mut ijk = [0; 3];
        for (d, kv) in self.knots.iter().enumerate() {
            ijk[d] = rest % kv.n_basis();
            rest /= kv.n_basis();
        }
        ijk
    }

    /// The knot spans containing `xi` (clamped into the parameter range), unused directions 0.
    #[track_caller]
    pub fn find_spans(&self, xi: &[f64]) -> [usize; 3] {
        assert_eq!(
            xi.len(),
            self.param_dim(),
            "NurbsPatch: xi needs one entry per parametric direction"
        );
        let mut spans = [0; 3];
        for (d, kv) in self.knots.iter().enumerate() {
            spans[d] = kv.find_span(xi[d]);
        }
        spans
    }

    /// The physical point `x(ξ)`.
    #[track_caller]
    pub fn point(&self, xi: &[f64]) -> [f64; 3] {
        let b = self.basis(xi, 0);
        let mut x = [0.0; 3];
        for (&a, &r) in b.indices.iter().zip(&b.values) {
            for i in 0..3 {
                x[i] += r * self.points[a][i];
            }
        }
        x
    }

    /// Rational basis functions nonzero at `xi` and their parametric derivatives up to order
    /// `n_ders` (0, 1 or 2). `d1` is empty for `n_ders = 0`, `d2` unless `n_ders = 2`.
    #[track_caller]
    pub fn basis(&self, xi: &[f64], n_ders: usize) -> RationalBasis {
        let mut out = RationalBasis::default();
        self.basis_into(xi, n_ders, &mut out);
        out
    }

    /// [`Self::basis`] into a reused buffer.
    #[track_caller]
    pub fn basis_into(&self, xi: &[f64], n_ders: usize, out: &mut RationalBasis) {
        let spans = self.find_spans(xi);
        nurbs_basis_into(&self.knots, &self.weights, &spans, xi, n_ders, out);
    }

    /// [`Self::basis`] with the polynomial pieces of the given spans (e.g. those of an
    /// [`Element`]): one-sided limits at element boundaries, and no span search.
    #[track_caller]
    pub fn basis_in_spans(
        &self,
        spans: &[usize],
        xi: &[f64],
        n_ders: usize,
        out: &mut RationalBasis,
    ) {
        assert_eq!(
            xi.len(),
            self.param_dim(),
            "NurbsPatch: xi needs one entry per parametric direction"
        );
        nurbs_basis_into(&self.knots, &self.weights, spans, xi, n_ders, out);
    }

    /// Position and parametric Jacobian `J[i][k] = ∂x_i/∂ξ_k` at `xi` (unused directions 0).
    #[track_caller]
    pub fn jacobian(&self, xi: &[f64]) -> ([f64; 3], [[f64; 3]; 3]) {
        let b = self.basis(xi, 1);
        let mut x = [0.0; 3];
        let mut jac = [[0.0; 3]; 3];
        for (a, &g) in b.indices.iter().enumerate() {
            let p = self.points[g];
            for i in 0..3 {
                x[i] += b.values[a] * p[i];
                for k in 0..3 {
                    jac[i][k] += b.d1[a][k] * p[i];
                }
            }
        }
        (x, jac)
    }

    /// The elements (non-empty knot spans), tensor product, first direction fastest.
    pub fn elements(&self) -> Vec<Element> {
        let dim = self.param_dim();
        let spans: Vec<Vec<usize>> = self.knots.iter().map(KnotVector::element_spans).collect();
        let counts: Vec<usize> = spans.iter().map(Vec::len).collect();
        let total: usize = counts.iter().product();
        let mut out = Vec::with_capacity(total);
        for e in 0..total {
            let mut rest = e;
            let mut el = Element {
                spans: [0; 3],
                lower: [0.0; 3],
                upper: [0.0; 3],
            };
            for d in 0..dim {
                let s = spans[d][rest % counts[d]];
                rest /= counts[d];
                el.spans[d] = s;
                el.lower[d] = self.knots[d].knots()[s];
                el.upper[d] = self.knots[d].knots()[s + 1];
            }
            out.push(el);
        }
        out
    }

    /// Total number of elements.
    pub fn n_elements(&self) -> usize {
        self.knots.iter().map(KnotVector::n_elements).product()
    }

    /// The boundary face where direction `dir` is at its `side` end, as a patch of one dimension
    /// less (remaining directions in order), and the global indices (in this patch) of its
    /// control points, in the face patch's ordering. Exact because the knot vectors are open.
    ///
    /// Panics for curves (`param_dim == 1`) or `dir >= param_dim`.
    #[track_caller]
    pub fn face(&self, dir: usize, side: Side) -> (NurbsPatch, Vec<usize>) {
        let dim = self.param_dim();
        assert!(
            dim >= 2,
            "NurbsPatch::face: a curve has no faces (param_dim 1)"
        );
        assert!(
            dir < dim,
            "NurbsPatch::face: direction {dir} out of range 0..{dim}"
        );
        let fixed = match side {
            Side::Low => 0,
            Side::High => self.knots[dir].n_basis() - 1,
        };
        let indices = self.slice_indices(dir, fixed);
        let knots: Vec<KnotVector> = (0..dim)
            .filter(|&d| d != dir)
            .map(|d| self.knots[d].clone())
            .collect();
        let points = indices.iter().map(|&a| self.points[a]).collect();
        let weights = indices.iter().map(|&a| self.weights[a]).collect();
        (
            NurbsPatch {
                knots,
                points,
                weights,
            },
            indices,
        )
    }

    /// Global indices of the control points with index `fixed` in direction `dir`, the other
    /// directions in order, first fastest.
    pub(crate) fn slice_indices(&self, dir: usize, fixed: usize) -> Vec<usize> {
        let n = self.n_per_dir();
        let others: Vec<usize> = (0..n.len()).filter(|&d| d != dir).collect();
        let count: usize = others.iter().map(|&d| n[d]).product();
        let mut out = Vec::with_capacity(count);
        let mut ijk = vec![0; n.len()];
        ijk[dir] = fixed;
        for c in 0..count {
            let mut rest = c;
            for &d in &others {
                ijk[d] = rest % n[d];
                rest /= n[d];
            }
            out.push(self.index(&ijk));
        }
        out
    }

    /// For curves: `C(u), C'(u), ..., C^(n)(u)` (A4.2, from the derivatives of the weighted
    /// curve `A(u) = Σ N_i w_i P_i` and of `w(u) = Σ N_i w_i`:
    /// `C^(k) = (A^(k) − Σ_{i=1..k} binom(k, i) w^(i) C^(k−i)) / w`).
    #[track_caller]
    pub fn curve_derivatives(&self, u: f64, n: usize) -> Vec<[f64; 3]> {
        assert_eq!(
            self.param_dim(),
            1,
            "NurbsPatch::curve_derivatives: only for curves (param_dim 1)"
        );
        let kv = &self.knots[0];
        let p = kv.degree();
        let span = kv.find_span(u);
        let ders = basis_ders(kv, span, u, n);
        let mut a_ders = vec![[0.0; 3]; n + 1];
        let mut w_ders = vec![0.0; n + 1];
        for k in 0..=n {
            for j in 0..=p {
                let g = span - p + j;
                let nw = ders[k][j] * self.weights[g];
                w_ders[k] += nw;
                for i in 0..3 {
                    a_ders[k][i] += nw * self.points[g][i];
                }
            }
        }
        let mut ck = vec![[0.0; 3]; n + 1];
        for k in 0..=n {
            let mut v = a_ders[k];
            let mut binom = 1.0;
            for i in 1..=k {
                binom = binom * (k + 1 - i) as f64 / i as f64;
                for c in 0..3 {
                    v[c] -= binom * w_ders[i] * ck[k - i][c];
                }
            }
            for c in 0..3 {
                ck[k][c] = v[c] / w_ders[0];
            }
        }
        ck
    }

    /// A copy with every control point mapped by `f` (weights and knots unchanged).
    pub fn map_points(&self, f: impl Fn([f64; 3]) -> [f64; 3]) -> NurbsPatch {
        NurbsPatch {
            knots: self.knots.clone(),
            points: self.points.iter().map(|&x| f(x)).collect(),
            weights: self.weights.clone(),
        }
    }

    /// Builds a patch without validation (for internal algorithms whose output is valid by construction).
    pub(crate) fn from_parts(
        knots: Vec<KnotVector>,
        points: Vec<[f64; 3]>,
        weights: Vec<f64>,
    ) -> Self {
        debug_assert_eq!(
            points.len(),
            knots.iter().map(KnotVector::n_basis).product::<usize>()
        );
        debug_assert_eq!(points.len(), weights.len());
        NurbsPatch {
            knots,
            points,
            weights,
        }
    }
}
