//! Tensor-product B-spline basis functions of one element, and the rational
//! (NURBS) basis `R_a = w_a B_a / W` built from any such functions with their
//! parametric derivatives — for a tensor-product NURBS patch, or for the
//! extracted functions of a hierarchical element.

use super::bspline::basis_ders_into;
use crate::geometry::KnotVector;

/// The rational basis functions nonzero at one parametric point and their parametric derivatives.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RationalBasis {
    /// Global control point indices `a` (`i0 + n0 (i1 + n1 i2)`), first direction fastest.
    pub indices: Vec<usize>,
    /// `R_a`.
    pub values: Vec<f64>,
    /// `d1[a][k] = ∂R_a/∂ξ_k` (unused directions 0); empty if no derivatives were requested.
    pub d1: Vec<[f64; 3]>,
    /// `d2[a][k][l] = ∂²R_a/∂ξ_k∂ξ_l`; empty unless second derivatives were requested.
    pub d2: Vec<[[f64; 3]; 3]>,
}

impl RationalBasis {
    /// Number of nonzero basis functions.
    pub fn len(&self) -> usize {
        self.indices.len()
    }

    /// True if there are none (never for a valid evaluation).
    pub fn is_empty(&self) -> bool {
        self.indices.is_empty()
    }
}

/// The tensor-product B-spline functions of one element (polynomial, unit weights) and their
/// parametric derivatives, in local order: first direction fastest, `Π_d (p_d + 1)` functions.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TensorBasis {
    /// `B_j`.
    pub values: Vec<f64>,
    /// `∂B_j/∂ξ_k` (unused directions 0); empty without derivatives.
    pub d1: Vec<[f64; 3]>,
    /// `∂²B_j/∂ξ_k∂ξ_l`; empty unless second derivatives were requested.
    pub d2: Vec<[[f64; 3]; 3]>,
}

/// Stack buffer for the three directions' derivative tables (degrees up to 9 in 3D).
const STACK_LEN: usize = 3 * 3 * 10;

/// Evaluates the tensor-product B-spline functions of the knot vectors `knots` (1 to 3
/// directions) nonzero on the non-empty `spans`, at `xi` (the spans' polynomial pieces, so
/// element ends give one-sided limits), with parametric derivatives up to `n_ders ≤ 2`, into
/// `out` (its vectors are reused), in local order (first direction fastest). Allocation-free
/// for degrees ≤ 9 once `out` has grown.
#[track_caller]
#[allow(clippy::needless_range_loop)]
pub fn bspline_tensor_into(
    knots: &[KnotVector],
    spans: &[usize],
    xi: &[f64],
    n_ders: usize,
    out: &mut TensorBasis,
) {
    let dim = knots.len();
    assert!(
        (1..=3).contains(&dim),
        "bspline_tensor: 1 to 3 parametric directions, got {dim}"
    );
    assert!(
        spans.len() >= dim && xi.len() >= dim,
        "bspline_tensor: spans and xi need {dim} entries"
    );
    assert!(
        n_ders <= 2,
        "bspline_tensor: derivatives up to order 2, asked for {n_ders}"
    );
    let nd = n_ders + 1;
    // Per-direction B-spline derivative tables, direction d at offset[d]:
    // table[offset[d] + k * (p_d + 1) + j]; unused directions: one function equal to 1.
    let mut p1 = [1usize; 3];
    let mut offset = [0usize; 4];
    for d in 0..3 {
        if d < dim {
            p1[d] = knots[d].degree() + 1;
        }
        offset[d + 1] = offset[d] + 3 * p1[d];
    }
    let mut stack = [0.0; STACK_LEN];
    let mut heap = Vec::new();
    let table: &mut [f64] = if offset[3] <= STACK_LEN {
        &mut stack[..offset[3]]
    } else {
        heap.resize(offset[3], 0.0);
        &mut heap
    };
    for d in 0..3 {
        let t = &mut table[offset[d]..offset[d + 1]];
        if d < dim {
            basis_ders_into(&knots[d], spans[d], xi[d], n_ders, &mut t[..nd * p1[d]]);
        } else {
            t.copy_from_slice(&[1.0, 0.0, 0.0]);
        }
    }
    let table = &*table;
    out.values.clear();
    out.d1.clear();
    out.d2.clear();
    // Value and derivative of the 1D factor d, local index j, derivative order k.
    let n1 = |d: usize, k: usize, j: usize| table[offset[d] + k * p1[d] + j];
    for j2 in 0..p1[2] {
        for j1 in 0..p1[1] {
            for j0 in 0..p1[0] {
                let j = [j0, j1, j2];
                let v = [n1(0, 0, j0), n1(1, 0, j1), n1(2, 0, j2)];
                out.values.push(v[0] * v[1] * v[2]);
                if n_ders >= 1 {
                    let g = [n1(0, 1, j0), n1(1, 1, j1), n1(2, 1, j2)];
                    let mut db = [0.0; 3];
                    for k in 0..dim {
                        let mut prod = g[k];
                        for d in 0..3 {
                            if d != k {
                                prod *= v[d];
                            }
                        }
                        db[k] = prod;
                    }
                    out.d1.push(db);
                    if n_ders >= 2 {
                        let mut ddb = [[0.0; 3]; 3];
                        for k in 0..dim {
                            for l in k..dim {
                                let mut prod = 1.0;
                                for d in 0..3 {
                                    let order = usize::from(d == k) + usize::from(d == l);
                                    prod *= n1(d, order, j[d]);
                                }
                                ddb[k][l] = prod;
                                ddb[l][k] = prod;
                            }
                        }
                        out.d2.push(ddb);
                    }
                }
            }
        }
    }
}

/// Turns polynomial functions `B_a` with derivatives (in `out.values`, `out.d1`, `out.d2`, as
/// far as `n_ders`) into the rational functions `R_a = w_a B_a / W`, `W = Σ w_a B_a`, in
/// place, with the control weights `w_a = weights[out.indices[a]]`:
/// `∂_k R = (w ∂_k B − R ∂_k W)/W`,
/// `∂_kl R = (w ∂_kl B − ∂_k R ∂_l W − ∂_l R ∂_k W − R ∂_kl W)/W`.
#[allow(clippy::needless_range_loop)]
pub fn rationalize(out: &mut RationalBasis, weights: &[f64], dim: usize, n_ders: usize) {
    let n = out.values.len();
    debug_assert_eq!(out.indices.len(), n);
    let mut w_sum = 0.0;
    let mut dw = [0.0; 3];
    let mut d2w = [[0.0; 3]; 3];
    for a in 0..n {
        let w = weights[out.indices[a]];
        out.values[a] *= w;
        w_sum += out.values[a];
        if n_ders >= 1 {
            for k in 0..dim {
                out.d1[a][k] *= w;
                dw[k] += out.d1[a][k];
            }
            if n_ders >= 2 {
                for k in 0..dim {
                    for l in 0..dim {
                        out.d2[a][k][l] *= w;
                        d2w[k][l] += out.d2[a][k][l];
                    }
                }
            }
        }
    }
    let inv_w = 1.0 / w_sum;
    for a in 0..n {
        let r = out.values[a] * inv_w;
        out.values[a] = r;
        if n_ders >= 1 {
            let mut dr = [0.0; 3];
            for k in 0..dim {
                dr[k] = (out.d1[a][k] - r * dw[k]) * inv_w;
            }
            out.d1[a] = dr;
            if n_ders >= 2 {
                let mut ddr = [[0.0; 3]; 3];
                for k in 0..dim {
                    for l in k..dim {
                        let v = (out.d2[a][k][l] - dr[k] * dw[l] - dr[l] * dw[k] - r * d2w[k][l])
                            * inv_w;
                        ddr[k][l] = v;
                        ddr[l][k] = v;
                    }
                }
                out.d2[a] = ddr;
            }
        }
    }
}

/// Evaluates the tensor-product NURBS basis of the knot vectors `knots` (1 to 3 directions)
/// with control weights `weights` (ordered first direction fastest) at `xi`, using the
/// polynomial pieces of the given non-empty `spans`, with parametric derivatives up to
/// `n_ders ≤ 2`, into `out` (its vectors are reused): [`bspline_tensor_into`], global
/// indices, then [`rationalize`].
#[track_caller]
pub fn nurbs_basis_into(
    knots: &[KnotVector],
    weights: &[f64],
    spans: &[usize],
    xi: &[f64],
    n_ders: usize,
    out: &mut RationalBasis,
) {
    let dim = knots.len();
    let mut t = TensorBasis {
        values: std::mem::take(&mut out.values),
        d1: std::mem::take(&mut out.d1),
        d2: std::mem::take(&mut out.d2),
    };
    bspline_tensor_into(knots, spans, xi, n_ders, &mut t);
    out.values = t.values;
    out.d1 = t.d1;
    out.d2 = t.d2;
    let mut p1 = [1usize; 3];
    let mut n_per_dir = [1usize; 3];
    let mut first = [0usize; 3];
    for d in 0..dim {
        p1[d] = knots[d].degree() + 1;
        n_per_dir[d] = knots[d].n_basis();
        first[d] = spans[d] + 1 - p1[d];
    }
    out.indices.clear();
    for j2 in 0..p1[2] {
        for j1 in 0..p1[1] {
            for j0 in 0..p1[0] {
                out.indices.push(
                    (first[0] + j0)
                        + n_per_dir[0] * ((first[1] + j1) + n_per_dir[1] * (first[2] + j2)),
                );
            }
        }
    }
    rationalize(out, weights, dim, n_ders);
}
