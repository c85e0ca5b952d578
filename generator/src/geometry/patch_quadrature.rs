//! Gauss quadrature over the elements of a NURBS patch and over its boundary faces.
#![allow(clippy::needless_range_loop)]

use super::nurbs::{Element, NurbsPatch, Side};
use crate::basis::RationalBasis;
use crate::quadrature::GaussLegendre;

/// One bulk quadrature point.
#[derive(Clone, Debug, PartialEq)]
pub struct QuadPoint {
    /// Parametric coordinates (unused directions 0).
    pub xi: [f64; 3],
    /// Physical point.
    pub x: [f64; 3],
    /// Gauss weight × parametric element scaling × `|det J|`.
    pub weight: f64,
    /// `R_a` at the point, indexed like [`ElementQuadrature::conn`].
    pub r: Vec<f64>,
    /// `∂R_a/∂x_i` (unused spatial directions 0).
    pub dr_dx: Vec<[f64; 3]>,
}

/// Quadrature data of one element.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementQuadrature {
    /// Global control point indices of the element's basis functions.
    pub conn: Vec<usize>,
    /// The Gauss points, first direction fastest.
    pub points: Vec<QuadPoint>,
}

impl ElementQuadrature {
    /// Bytes held (the points' vectors included).
    pub fn storage_bytes(&self) -> usize {
        size_of::<Self>()
            + self.conn.capacity() * size_of::<usize>()
            + self
                .points
                .iter()
                .map(|q| {
                    size_of::<QuadPoint>()
                        + q.r.capacity() * size_of::<f64>()
                        + q.dr_dx.capacity() * size_of::<[f64; 3]>()
                })
                .sum::<usize>()
    }
}

/// One face quadrature point.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceQuadPoint {
    /// Patch parameters (the face direction at its end value; unused directions 0).
    pub xi: [f64; 3],
    /// Physical point.
    pub x: [f64; 3],
    /// Gauss weight × parametric scaling × surface (3D) or line (2D) Jacobian.
    pub weight: f64,
    /// Face basis values, indexed like [`FaceElementQuadrature::conn`].
    pub r: Vec<f64>,
    /// Unit outward normal.
    pub normal: [f64; 3],
}

/// Quadrature data of one face element.
#[derive(Clone, Debug, PartialEq)]
pub struct FaceElementQuadrature {
    /// Global (patch) indices of the face basis functions nonzero on this face element.
    pub conn: Vec<usize>,
    /// The Gauss points, first face direction fastest.
    pub points: Vec<FaceQuadPoint>,
}

/// Tensor Gauss points of the parametric box `[lower, upper]` over the directions `dirs`:
/// `(xi, parametric weight)`, first direction fastest.
pub(crate) fn tensor_points(
    dirs: &[usize],
    lower: [f64; 3],
    upper: [f64; 3],
    rules: &[GaussLegendre],
) -> Vec<([f64; 3], f64)> {
    let counts: Vec<usize> = rules.iter().map(GaussLegendre::len).collect();
    let total: usize = counts.iter().product();
    let mut out = Vec::with_capacity(total);
    for q in 0..total {
        let mut rest = q;
        // Directions not integrated over stay at the element's lower value.
        let mut xi = lower;
        let mut w = 1.0;
        for (m, &d) in dirs.iter().enumerate() {
            let g = rest % counts[m];
            rest /= counts[m];
            let half = 0.5 * (upper[d] - lower[d]);
            xi[d] = lower[d] + half * (1.0 + rules[m].points[g]);
            w *= half * rules[m].weights[g];
        }
        out.push((xi, w));
    }
    out
}

/// The Gauss rules of an element with `n_gauss[d]` points in direction `d` (a single entry
/// applies to all directions).
#[track_caller]
pub(crate) fn gauss_rules(dim: usize, n_gauss: &[usize]) -> Vec<GaussLegendre> {
    assert!(
        n_gauss.len() == dim || n_gauss.len() == 1,
        "element_quadrature: n_gauss needs 1 or {dim} entries, got {}",
        n_gauss.len()
    );
    (0..dim)
        .map(|d| {
            GaussLegendre::new(if n_gauss.len() == 1 {
                n_gauss[0]
            } else {
                n_gauss[d]
            })
        })
        .collect()
}

/// A bulk quadrature point from the basis at `xi` (with first derivatives) and the control
/// points `cp` (indexed by `basis.indices`): physical point, `∂R/∂x = J^{-T} ∂R/∂ξ` with
/// `J[i][k] = ∂x_i/∂ξ_k`, and the weight `wq · |det J|`.
pub(crate) fn bulk_point(
    dim: usize,
    xi: [f64; 3],
    wq: f64,
    basis: &RationalBasis,
    cp: &[[f64; 3]],
) -> QuadPoint {
    let mut x = [0.0; 3];
    let mut jac = [[0.0; 3]; 3];
    for (a, &g) in basis.indices.iter().enumerate() {
        for i in 0..3 {
            x[i] += basis.values[a] * cp[g][i];
        }
        for i in 0..dim {
            for k in 0..dim {
                jac[i][k] += basis.d1[a][k] * cp[g][i];
            }
        }
    }
    let (det, inv) = invert(&jac, dim);
    let dr_dx = basis
        .d1
        .iter()
        .map(|g| {
            let mut out = [0.0; 3];
            for i in 0..dim {
                for k in 0..dim {
                    out[i] += inv[k][i] * g[k];
                }
            }
            out
        })
        .collect();
    QuadPoint {
        xi,
        x,
        weight: wq * det.abs(),
        r: basis.values.clone(),
        dr_dx,
    }
}

/// A face quadrature point on the face where direction `dir` is at its `side` end, from the
/// *volume* basis at `xi` (with first derivatives, for the position, the face tangents and
/// the transversal tangent) and the face basis values `r`: the weight includes the surface
/// (volume patches) or line (surface patches) Jacobian; the unit normal points out of the
/// patch (oriented by the transversal tangent `∂x/∂ξ_dir`; planar patches: in the x-y plane).
pub(crate) fn face_point(
    dim: usize,
    (dir, side): (usize, Side),
    xi: [f64; 3],
    wq: f64,
    volume: &RationalBasis,
    cp: &[[f64; 3]],
    r: Vec<f64>,
) -> FaceQuadPoint {
    let face_dirs: Vec<usize> = (0..dim).filter(|&d| d != dir).collect();
    let mut x = [0.0; 3];
    let mut jac = [[0.0; 3]; 3];
    for (a, &g) in volume.indices.iter().enumerate() {
        for i in 0..3 {
            x[i] += volume.values[a] * cp[g][i];
            for k in 0..dim {
                jac[i][k] += volume.d1[a][k] * cp[g][i];
            }
        }
    }
    let column = |k: usize| [jac[0][k], jac[1][k], jac[2][k]];
    let transversal = column(dir);
    let (mut normal, measure) = if dim == 2 {
        let t = column(face_dirs[0]);
        let len = (t[0] * t[0] + t[1] * t[1]).sqrt();
        ([t[1] / len, -t[0] / len, 0.0], len)
    } else {
        let n = cross(column(face_dirs[0]), column(face_dirs[1]));
        let len = norm(n);
        ([n[0] / len, n[1] / len, n[2] / len], len)
    };
    let sign = if side == Side::High { 1.0 } else { -1.0 };
    if sign * dot(normal, transversal) < 0.0 {
        normal = normal.map(|c| -c);
    }
    FaceQuadPoint {
        xi,
        x,
        weight: wq * measure,
        r,
        normal,
    }
}

impl NurbsPatch {
    /// Bulk quadrature of `el` with `n_gauss[d]` Gauss points in direction `d` (a single entry
    /// applies to all directions), for `param_dim ==` spatial dimension (1: x; 2: x, y; 3: x, y, z).
    /// Physical gradients `∂R/∂x = J^{-T} ∂R/∂ξ` with `J[i][k] = ∂x_i/∂ξ_k`.
    #[track_caller]
    pub fn element_quadrature(&self, el: &Element, n_gauss: &[usize]) -> ElementQuadrature {
        let dim = self.param_dim();
        let rules = gauss_rules(dim, n_gauss);
        let dirs: Vec<usize> = (0..dim).collect();
        let mut basis = RationalBasis::default();
        let mut conn = Vec::new();
        let mut points = Vec::new();
        for (xi, wq) in tensor_points(&dirs, el.lower, el.upper, &rules) {
            self.basis_in_spans(&el.spans, &xi[..dim], 1, &mut basis);
            if conn.is_empty() {
                conn.clone_from(&basis.indices);
            }
            points.push(bulk_point(dim, xi, wq, &basis, self.control_points()));
        }
        ElementQuadrature { conn, points }
    }

    /// Quadrature over the face where direction `dir` is at its `side` end, per face element,
    /// with `n_gauss` points per face direction (see `face_point` for weights and normals).
    /// `r` holds the face basis functions, indexed like `conn`.
    #[track_caller]
    pub fn face_quadrature(
        &self,
        dir: usize,
        side: Side,
        n_gauss: usize,
    ) -> Vec<FaceElementQuadrature> {
        let dim = self.param_dim();
        assert!(
            dim >= 2,
            "face_quadrature: a curve has no faces (param_dim 1)"
        );
        assert!(
            dir < dim,
            "face_quadrature: direction {dir} out of range 0..{dim}"
        );
        let kv = &self.knots()[dir];
        let (fixed_value, fixed_span, fixed_index) = match side {
            Side::Low => (kv.first(), kv.degree(), 0),
            Side::High => (kv.last(), kv.n_basis() - 1, kv.n_basis() - 1),
        };
        let face_dirs: Vec<usize> = (0..dim).filter(|&d| d != dir).collect();
        let rules = vec![GaussLegendre::new(n_gauss); face_dirs.len()];
        let mut basis = RationalBasis::default();
        let mut out = Vec::new();
        for mut el in self.elements() {
            if el.spans[dir] != fixed_span {
                continue;
            }
            el.lower[dir] = fixed_value;
            el.upper[dir] = fixed_value;
            let mut conn = Vec::new();
            let mut points = Vec::new();
            for (xi, wq) in tensor_points(&face_dirs, el.lower, el.upper, &rules) {
                self.basis_in_spans(&el.spans, &xi[..dim], 1, &mut basis);
                let collect_conn = conn.is_empty();
                let mut r = Vec::with_capacity(basis.len());
                let mut r_sum = 0.0;
                for (a, &g) in basis.indices.iter().enumerate() {
                    if self.ijk(g)[dir] == fixed_index {
                        r.push(basis.values[a]);
                        r_sum += basis.values[a];
                        if collect_conn {
                            conn.push(g);
                        }
                    }
                }
                // Basis functions not on the face vanish there; renormalise against round-off.
                r.iter_mut().for_each(|v| *v /= r_sum);
                points.push(face_point(
                    dim,
                    (dir, side),
                    xi,
                    wq,
                    &basis,
                    self.control_points(),
                    r,
                ));
            }
            out.push(FaceElementQuadrature { conn, points });
        }
        out
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Determinant and inverse of the leading `dim × dim` block of `m`.
pub(crate) fn invert(m: &[[f64; 3]; 3], dim: usize) -> (f64, [[f64; 3]; 3]) {
    let mut inv = [[0.0; 3]; 3];
    match dim {
        1 => {
            let det = m[0][0];
            inv[0][0] = 1.0 / det;
            (det, inv)
        }
        2 => {
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            inv[0][0] = m[1][1] / det;
            inv[0][1] = -m[0][1] / det;
            inv[1][0] = -m[1][0] / det;
            inv[1][1] = m[0][0] / det;
            (det, inv)
        }
        _ => {
            let c = |i: usize, j: usize| {
                let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
                let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
                m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]
            };
            let det = m[0][0] * c(0, 0) + m[0][1] * c(0, 1) + m[0][2] * c(0, 2);
            for i in 0..3 {
                for j in 0..3 {
                    inv[i][j] = c(j, i) / det;
                }
            }
            (det, inv)
        }
    }
}
