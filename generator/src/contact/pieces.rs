//! The master face's polynomial pieces in the current configuration, for the
//! closest-point projections of both dimensions ([`crate::contact::projection`]
//! on curves, [`crate::contact::projection3d`] on surfaces).
//!
//! On an element whose functions all have weight 1 (to 1e-13) the face is a
//! polynomial of degree `p_α` in each of its `d − 1` parameters: its values
//! at the `Π (p_α + 1)` equispaced nodes of the element, converted once to
//! the coefficients of the tensor monomials of the element's centred local
//! coordinates (the inverse Vandermonde matrix of the nodes), and evaluated
//! by them (exact up to round-off: the same face). The
//! projections evaluate the face many times per point (the search, the
//! element minimizations); this replaces each THB evaluation (the level's
//! B-splines, the truncation's extraction, the rational weighting) by a few
//! dozen multiplications. Rational elements keep the THB evaluation.

use rayon::prelude::*;

use crate::basis::{RationalBasis, TensorBasis};
use crate::geometry::ThbPatch;

/// Position and parametric derivatives of the master face at one point (on
/// a curve, the first parameter's only; the rest zero).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfacePoint {
    /// Position `x_m(η)`.
    pub x: [f64; 3],
    /// Tangents `a_α = ∂x_m/∂η_α`.
    pub a: [[f64; 3]; 2],
    /// Second derivatives `a_αβ = ∂²x_m/∂η_α∂η_β`.
    pub aa: [[[f64; 3]; 2]; 2],
}

/// The polynomial pieces of a master face (a curve or a surface) with its
/// current control points (module docs).
#[derive(Clone, Debug)]
pub struct FacePieces {
    /// Degrees per parameter; 0 in the second for a curve.
    degrees: [usize; 2],
    /// Per element: the coefficients of the monomials `s₁^i s₂^j` of the
    /// centred local coordinates `s_α ∈ [−1, 1]` (`i` fastest), or `None`
    /// (rational: evaluate the basis).
    pub(crate) coefficients: Vec<Option<Vec<[f64; 3]>>>,
}

impl FacePieces {
    /// The pieces of `face` (one or two parameters) with current control
    /// points `points`.
    #[track_caller]
    pub fn new(face: &ThbPatch, points: &[[f64; 3]]) -> Self {
        let dims = face.param_dim();
        assert!(dims == 1 || dims == 2, "FacePieces: a curve or a surface");
        let degrees = [
            face.degrees()[0],
            if dims == 2 { face.degrees()[1] } else { 0 },
        ];
        let weights = face.weights();
        let node = |i: usize, p: usize| if p == 0 { 0.0 } else { i as f64 / p as f64 };
        // The monomials of the centred coordinate `s = 2t − 1 ∈ [−1, 1]`.
        let inverse = degrees.map(|p| inverse_vandermonde(p, |i| 2.0 * node(i, p) - 1.0));
        let n0 = degrees[0] + 1;
        let coefficients: Vec<Option<Vec<[f64; 3]>>> = (0..face.n_elements())
            .into_par_iter()
            .map_init(
                || (TensorBasis::default(), RationalBasis::default()),
                |(scratch, basis), e| {
                    let el = &face.elements()[e];
                    if el
                        .functions
                        .iter()
                        .any(|&g| (weights[g] - 1.0).abs() > 1e-13)
                    {
                        return None;
                    }
                    let mut values = Vec::with_capacity((degrees[0] + 1) * (degrees[1] + 1));
                    for j in 0..=degrees[1] {
                        for i in 0..=degrees[0] {
                            let t = [node(i, degrees[0]), node(j, degrees[1])];
                            let eta: [f64; 2] = std::array::from_fn(|d| {
                                if d < dims {
                                    el.lower[d] + t[d] * (el.upper[d] - el.lower[d])
                                } else {
                                    0.0
                                }
                            });
                            face.element_basis_into(e, &eta[..dims], 0, scratch, basis);
                            let mut x = [0.0; 3];
                            for (k, &g) in basis.indices.iter().enumerate() {
                                for c in 0..3 {
                                    x[c] += basis.values[k] * points[g][c];
                                }
                            }
                            values.push(x);
                        }
                    }
                    // Nodal values to monomial coefficients: the tensor
                    // product of the directions' inverse Vandermonde matrices.
                    let mut coefficients = vec![[0.0; 3]; values.len()];
                    for (k, c) in coefficients.iter_mut().enumerate() {
                        let (i, j) = (k % n0, k / n0);
                        for (m, x) in values.iter().enumerate() {
                            let f = inverse[0][i][m % n0] * inverse[1][j][m / n0];
                            for (cc, xx) in c.iter_mut().zip(x) {
                                *cc += f * xx;
                            }
                        }
                    }
                    Some(coefficients)
                },
            )
            .collect();
        FacePieces {
            degrees,
            coefficients,
        }
    }

    /// Position and derivatives on element `e` of `face` at `eta` (one
    /// entry per parameter), if the element is polynomial.
    pub fn at(&self, face: &ThbPatch, e: usize, eta: &[f64]) -> Option<SurfacePoint> {
        let coefficients = self.coefficients[e].as_ref()?;
        let el = &face.elements()[e];
        // The monomials and their derivatives in each parameter.
        let mut l = [[[0.0; 3]; 4]; 2];
        for (d, &x) in eta.iter().enumerate() {
            let h = 0.5 * (el.upper[d] - el.lower[d]);
            let s = (x - el.lower[d]) / h - 1.0;
            l[d] = monomials(self.degrees[d], s);
            for b in l[d].iter_mut() {
                b[1] /= h;
                b[2] /= h * h;
            }
        }
        if eta.len() == 1 {
            l[1] = monomials(0, 0.0);
        }
        let mut s = SurfacePoint::default();
        let n0 = self.degrees[0] + 1;
        for (k, x) in coefficients.iter().enumerate() {
            let (u, v) = (l[0][k % n0], l[1][k / n0]);
            for c in 0..3 {
                s.x[c] += u[0] * v[0] * x[c];
                s.a[0][c] += u[1] * v[0] * x[c];
                s.a[1][c] += u[0] * v[1] * x[c];
                s.aa[0][0][c] += u[2] * v[0] * x[c];
                s.aa[0][1][c] += u[1] * v[1] * x[c];
                s.aa[1][1][c] += u[0] * v[2] * x[c];
            }
        }
        s.aa[1][0] = s.aa[0][1];
        Some(s)
    }

    /// The axis-aligned box of element `e`'s Bézier coefficients (its piece
    /// in the Bernstein basis of the element), if the element is polynomial.
    /// Bernstein polynomials are non-negative and sum to one, so the piece
    /// lies in their convex hull: a box about as large as the element itself,
    /// where that of the functions' control points reaches over the
    /// neighbours' (and, refined, over coarser functions' supports).
    pub fn bezier_box(&self, e: usize) -> Option<([f64; 3], [f64; 3])> {
        let coefficients = self.coefficients[e].as_ref()?;
        let [b0, b1] = self.degrees.map(monomials_to_bernstein);
        let [n0, n1] = self.degrees.map(|p| p + 1);
        let mut out = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for n in 0..n1 {
            for m in 0..n0 {
                let mut b = [0.0; 3];
                for (k, x) in coefficients.iter().enumerate() {
                    let f = b0[k % n0][m] * b1[k / n0][n];
                    for c in 0..3 {
                        b[c] += f * x[c];
                    }
                }
                for c in 0..3 {
                    out.0[c] = out.0[c].min(b[c]);
                    out.1[c] = out.1[c].max(b[c]);
                }
            }
        }
        Some(out)
    }
}

/// The Bernstein coefficients `β[k][m]` (degree `p ≤ 3`, `t ∈ [0, 1]`) of
/// the monomials `s^k` of the centred coordinate `s = 2t − 1`:
/// `(2t − 1)^k = Σ_j C(k, j) 2^j (−1)^(k−j) t^j` and
/// `t^j = Σ_(m ≥ j) C(m, j) / C(p, j) B_m^p(t)`.
fn monomials_to_bernstein(p: usize) -> [[f64; 4]; 4] {
    let binomial = |n: usize, k: usize| -> f64 {
        (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
    };
    let mut beta = [[0.0; 4]; 4];
    for (k, row) in beta.iter_mut().enumerate().take(p + 1) {
        for (m, b) in row.iter_mut().enumerate().take(p + 1) {
            *b = (0..=k.min(m))
                .map(|j| {
                    let sign = if (k - j) % 2 == 0 { 1.0 } else { -1.0 };
                    binomial(k, j) * 2f64.powi(j as i32) * sign * binomial(m, j) / binomial(p, j)
                })
                .sum();
        }
    }
    beta
}

/// The monomials `t^k` of degree `p ≤ 3` at `t`: `[t^k, (t^k)', (t^k)'']`
/// for `k = 0..=p` (the rest zero); `p = 0`: the constant 1.
fn monomials(p: usize, t: f64) -> [[f64; 3]; 4] {
    let mut out = [[0.0; 3]; 4];
    let mut power = [1.0; 4];
    for k in 1..4 {
        power[k] = power[k - 1] * t;
    }
    for (k, o) in out.iter_mut().enumerate().take(p + 1) {
        let kf = k as f64;
        o[0] = power[k];
        if k >= 1 {
            o[1] = kf * power[k - 1];
        }
        if k >= 2 {
            o[2] = kf * (kf - 1.0) * power[k - 2];
        }
    }
    out
}

/// The inverse of the Vandermonde matrix `V_ik = t_i^k` of the nodes
/// `t_i = node(i)`, `i, k = 0..=p ≤ 3` (Gauss–Jordan; the rest zero):
/// monomial coefficients `c = V⁻¹ x` of the values `x` at the nodes.
fn inverse_vandermonde(p: usize, node: impl Fn(usize) -> f64) -> [[f64; 4]; 4] {
    assert!(p <= 3, "FacePieces: degree 0 to 3");
    let n = p + 1;
    let mut a = [[0.0; 8]; 4];
    for (i, row) in a.iter_mut().enumerate().take(n) {
        for k in 0..n {
            row[k] = node(i).powi(k as i32);
        }
        row[n + i] = 1.0;
    }
    for c in 0..n {
        let pivot = (c..n)
            .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
            .unwrap_or(c);
        a.swap(c, pivot);
        let d = a[c][c];
        for v in a[c].iter_mut() {
            *v /= d;
        }
        for r in (0..n).filter(|&r| r != c) {
            let f = a[r][c];
            let pivot_row = a[c];
            for (v, w) in a[r].iter_mut().zip(pivot_row) {
                *v -= f * w;
            }
        }
    }
    let mut inverse = [[0.0; 4]; 4];
    for (row, source) in inverse.iter_mut().zip(&a).take(n) {
        row[..n].copy_from_slice(&source[n..2 * n]);
    }
    inverse
}
