//! Gauss quadrature over the elements of a NURBS patch and over its boundary faces.
#![allow(clippy::needless_range_loop)]

use super::KnotVector;
use super::nurbs::{Element, NurbsPatch, Side};
use crate::basis::RationalBasis;
use crate::quadrature::GaussLegendre;

/// One bulk quadrature point: where it is, its weight, and the map from
/// parametric to physical derivatives. The basis values and gradients are
/// the element's ([`ElementQuadrature::values`],
/// [`ElementQuadrature::gradients`]).
#[derive(Clone, Debug, PartialEq)]
pub struct QuadPoint {
    /// Parametric coordinates (unused directions 0).
    pub xi: [f64; 3],
    /// Physical point.
    pub x: [f64; 3],
    /// Gauss weight × parametric element scaling × `|det J|`.
    pub weight: f64,
    /// `J⁻¹` with `J[i][k] = ∂x_i/∂ξ_k`: `inverse_jacobian[k][i] = ∂ξ_k/∂x_i`.
    pub(crate) inverse_jacobian: [[f64; 3]; 3],
    /// The NURBS weight function `W = Σ_b w_b N_b` at the point (1 for B-splines).
    pub(crate) weight_function: f64,
}

/// How an element's quadrature gives `∂R_a/∂x` at its points.
#[derive(Clone, Debug, PartialEq)]
enum BasisGradients {
    /// Stored per point (point-major, like the values): where the Gauss
    /// points cannot represent the element's polynomials.
    Stored(Vec<[f64; 3]>),
    /// Recovered from the values when asked ([`ElementQuadrature::gradients`]):
    /// on an element, `W R_a = w_a N_a` is a polynomial of degree `p_d` in
    /// each direction `d`, so with at least `p_d + 1` Gauss points its
    /// values there determine it and the Lagrange differentiation on the
    /// points gives `∂(W R_a)/∂ξ` exactly (to round-off); then
    /// `∂R_a/∂ξ = (∂(W R_a)/∂ξ − R_a ∂W/∂ξ) / W` and `∂R_a/∂x = J⁻ᵀ ∂R_a/∂ξ`.
    /// A third of the memory of stored gradients (the bulk quadrature of a
    /// large 3D level is gigabytes).
    Interpolated {
        /// Gauss points per direction (1 in unused directions).
        counts: [usize; 3],
        /// Half the element's parametric widths (the rule's scaling).
        half_widths: [f64; 3],
    },
}

/// Quadrature data of one element.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementQuadrature {
    /// Global control point indices of the element's basis functions.
    pub conn: Vec<usize>,
    /// The Gauss points, first direction fastest.
    pub points: Vec<QuadPoint>,
    /// `R_a` at the points, point-major (`values[q · conn.len() + a]`).
    values: Vec<f64>,
    /// `∂R_a/∂x` at the points.
    gradients: BasisGradients,
    /// Parametric dimension.
    dim: usize,
}

/// The most Gauss points per direction whose differentiation matrices are kept.
const MAX_DIFFERENTIATED_POINTS: usize = 16;

/// The Lagrange differentiation matrix of the `n`-point Gauss rule on
/// `[−1, 1]` (row-major: `D[i][m] = ℓ_m'(t_i)`, exact for polynomials of
/// degree < `n`), from the barycentric weights `λ_m = 1 / Π_{j≠m} (t_m − t_j)`:
/// `D[i][m] = (λ_m / λ_i) / (t_i − t_m)` off the diagonal and minus the row's
/// other entries on it. Kept for `n ≤` [`MAX_DIFFERENTIATED_POINTS`].
fn gauss_differentiation(n: usize) -> &'static [f64] {
    static CACHE: [std::sync::OnceLock<Vec<f64>>; MAX_DIFFERENTIATED_POINTS + 1] =
        [const { std::sync::OnceLock::new() }; MAX_DIFFERENTIATED_POINTS + 1];
    CACHE[n].get_or_init(|| {
        let t = GaussLegendre::new(n).points;
        let lambda: Vec<f64> = (0..n)
            .map(|m| {
                1.0 / (0..n)
                    .filter(|&j| j != m)
                    .map(|j| t[m] - t[j])
                    .product::<f64>()
            })
            .collect();
        let mut d = vec![0.0; n * n];
        for i in 0..n {
            let mut diagonal = 0.0;
            for m in (0..n).filter(|&m| m != i) {
                let v = lambda[m] / lambda[i] / (t[i] - t[m]);
                d[i * n + m] = v;
                diagonal -= v;
            }
            d[i * n + i] = diagonal;
        }
        d
    })
}

impl ElementQuadrature {
    /// The quadrature of the element `[lower, upper]` with the Gauss `rules`
    /// (one per parametric direction), the basis (values and first
    /// derivatives) at a parameter point from `basis_at`, the patch's
    /// control points `cp` and NURBS `weights` (indexed by the basis's
    /// indices), and the polynomial `degrees` per direction: gradients
    /// recovered from the values where every direction has more points than
    /// its degree ([`BasisGradients::Interpolated`]), stored otherwise.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn build(
        dim: usize,
        (lower, upper): ([f64; 3], [f64; 3]),
        rules: &[GaussLegendre],
        degrees: &[usize],
        cp: &[[f64; 3]],
        weights: &[f64],
        mut basis_at: impl FnMut(&[f64], &mut RationalBasis),
    ) -> Self {
        let dirs: Vec<usize> = (0..dim).collect();
        let mut counts = [1; 3];
        let mut half_widths = [1.0; 3];
        for d in 0..dim {
            counts[d] = rules[d].len();
            half_widths[d] = 0.5 * (upper[d] - lower[d]);
        }
        let interpolated =
            (0..dim).all(|d| counts[d] > degrees[d] && counts[d] <= MAX_DIFFERENTIATED_POINTS);
        let mut basis = RationalBasis::default();
        let (mut conn, mut points, mut values, mut stored) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (xi, wq) in tensor_points(&dirs, lower, upper, rules) {
            basis_at(&xi[..dim], &mut basis);
            if conn.is_empty() {
                conn.clone_from(&basis.indices);
            }
            let mut point = bulk_point(dim, xi, wq, &basis, cp);
            // `Σ_a R_a / w_a = Σ_a N_a / W = 1 / W` (the N_a a partition of unity).
            point.weight_function = 1.0
                / basis
                    .indices
                    .iter()
                    .zip(&basis.values)
                    .map(|(&g, r)| r / weights[g])
                    .sum::<f64>();
            values.extend_from_slice(&basis.values);
            if !interpolated {
                stored.extend(physical_gradients(dim, &point, &basis));
            }
            points.push(point);
        }
        let gradients = if interpolated {
            BasisGradients::Interpolated {
                counts,
                half_widths,
            }
        } else {
            BasisGradients::Stored(stored)
        };
        Self {
            conn,
            points,
            values,
            gradients,
            dim,
        }
    }

    /// A quadrature with given values and gradients per point (point-major,
    /// `conn.len()` per point), in `dim` parametric directions.
    pub fn with_gradients(
        dim: usize,
        conn: Vec<usize>,
        points: Vec<QuadPoint>,
        values: Vec<f64>,
        gradients: Vec<[f64; 3]>,
    ) -> Self {
        assert!(
            values.len() == conn.len() * points.len() && gradients.len() == values.len(),
            "ElementQuadrature::with_gradients: {} values and {} gradients for {} points of {} functions",
            values.len(),
            gradients.len(),
            points.len(),
            conn.len()
        );
        Self {
            conn,
            points,
            values,
            gradients: BasisGradients::Stored(gradients),
            dim,
        }
    }

    /// `R_a` at point `q`, indexed like [`Self::conn`].
    pub fn values(&self, q: usize) -> &[f64] {
        let n = self.conn.len();
        &self.values[q * n..(q + 1) * n]
    }

    /// `∂R_a/∂x_i` (unused spatial directions 0) at every point, point-major
    /// (`out[q · conn.len() + a]`): the stored ones, or recovered from the
    /// values into `scratch`: on an element `W R_a` is a polynomial of degree `p_d` in each
    /// direction, which the Gauss points' Lagrange differentiation recovers exactly where a
    /// direction has more points than its degree.
    pub fn gradients<'a>(&'a self, scratch: &'a mut Vec<[f64; 3]>) -> &'a [[f64; 3]] {
        let (counts, half_widths) = match &self.gradients {
            BasisGradients::Stored(g) => return g,
            BasisGradients::Interpolated {
                counts,
                half_widths,
            } => (counts, half_widths),
        };
        let (n, dim) = (self.conn.len(), self.dim);
        let strides = [1, counts[0], counts[0] * counts[1]];
        let rows: [&[f64]; 3] = std::array::from_fn(|d| {
            if d < dim {
                gauss_differentiation(counts[d])
            } else {
                &[]
            }
        });
        scratch.clear();
        scratch.resize(self.points.len() * n, [0.0; 3]);
        let w = |q: usize| self.points[q].weight_function;
        for (q, point) in self.points.iter().enumerate() {
            // ∂(W R_a)/∂ξ_d (reference coordinates) along the point's line in
            // each direction, all functions at once (contiguous in a), and ∂W/∂ξ_d.
            let out = &mut scratch[q * n..(q + 1) * n];
            let mut dw = [0.0; 3];
            for d in 0..dim {
                let i = (q / strides[d]) % counts[d];
                let first = q - i * strides[d];
                let row = &rows[d][i * counts[d]..(i + 1) * counts[d]];
                for (m, &c) in row.iter().enumerate() {
                    let qm = first + m * strides[d];
                    let cw = c * w(qm);
                    dw[d] += cw;
                    for (o, &v) in out.iter_mut().zip(&self.values[qm * n..(qm + 1) * n]) {
                        o[d] += cw * v;
                    }
                }
            }
            // ∂R_a/∂ξ_k = (∂(W R_a)/∂ξ_k − R_a ∂W/∂ξ_k) / W, then J⁻ᵀ.
            let wq = w(q);
            let mut map = [[0.0; 3]; 3];
            for k in 0..dim {
                let scale = 1.0 / (wq * half_widths[k]);
                for i in 0..dim {
                    map[k][i] = point.inverse_jacobian[k][i] * scale;
                }
            }
            for (o, &r) in out.iter_mut().zip(&self.values[q * n..(q + 1) * n]) {
                let dxi: [f64; 3] = std::array::from_fn(|k| o[k] - r * dw[k]);
                let mut g = [0.0; 3];
                for i in 0..dim {
                    for k in 0..dim {
                        g[i] += map[k][i] * dxi[k];
                    }
                }
                *o = g;
            }
        }
        scratch
    }

    /// Every point with its basis values and gradients ([`Self::values`],
    /// [`Self::gradients`], which may use `scratch`).
    pub fn points_with_basis<'a>(
        &'a self,
        scratch: &'a mut Vec<[f64; 3]>,
    ) -> impl Iterator<Item = (&'a QuadPoint, &'a [f64], &'a [[f64; 3]])> {
        let n = self.conn.len();
        let gradients = self.gradients(scratch);
        self.points
            .iter()
            .enumerate()
            .map(move |(q, p)| (p, self.values(q), &gradients[q * n..(q + 1) * n]))
    }

    /// Whether the gradients are stored rather than recovered from the values.
    pub fn stores_gradients(&self) -> bool {
        matches!(self.gradients, BasisGradients::Stored(_))
    }

    /// Bytes held (the points' vectors included).
    pub fn storage_bytes(&self) -> usize {
        size_of::<Self>()
            + self.conn.capacity() * size_of::<usize>()
            + self.points.capacity() * size_of::<QuadPoint>()
            + self.values.capacity() * size_of::<f64>()
            + match &self.gradients {
                BasisGradients::Stored(g) => g.capacity() * size_of::<[f64; 3]>(),
                BasisGradients::Interpolated { .. } => 0,
            }
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
/// points `cp` (indexed by `basis.indices`): physical point, `J⁻¹` with
/// `J[i][k] = ∂x_i/∂ξ_k` and the weight `wq · |det J|` (the weight function left at 1).
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
    QuadPoint {
        xi,
        x,
        weight: wq * det.abs(),
        inverse_jacobian: inv,
        weight_function: 1.0,
    }
}

/// `∂R/∂x = J^{-T} ∂R/∂ξ` of the basis at `point` (its `J⁻¹`), in `dim` directions.
pub(crate) fn physical_gradients(
    dim: usize,
    point: &QuadPoint,
    basis: &RationalBasis,
) -> impl Iterator<Item = [f64; 3]> {
    let inv = point.inverse_jacobian;
    basis.d1.iter().map(move |g| {
        let mut out = [0.0; 3];
        for i in 0..dim {
            for k in 0..dim {
                out[i] += inv[k][i] * g[k];
            }
        }
        out
    })
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
        let degrees: Vec<usize> = self.knots().iter().map(KnotVector::degree).collect();
        ElementQuadrature::build(
            dim,
            (el.lower, el.upper),
            &gauss_rules(dim, n_gauss),
            &degrees,
            self.control_points(),
            self.weights(),
            |xi, basis| self.basis_in_spans(&el.spans, xi, 1, basis),
        )
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shapes;

    /// The Gauss points' differentiation matrices differentiate every
    /// polynomial of degree below the number of points exactly.
    #[test]
    fn gauss_differentiation_is_exact_below_the_point_count() {
        for n in 1..=MAX_DIFFERENTIATED_POINTS {
            let t = GaussLegendre::new(n).points;
            let d = gauss_differentiation(n);
            for k in 0..n {
                for i in 0..n {
                    let dp: f64 = (0..n).map(|m| d[i * n + m] * t[m].powi(k as i32)).sum();
                    let exact = if k == 0 {
                        0.0
                    } else {
                        k as f64 * t[i].powi(k as i32 - 1)
                    };
                    assert!(
                        (dp - exact).abs() < 1e-9 * (1.0 + exact.abs()),
                        "n {n}, t^{k} at {i}: {dp} vs {exact}"
                    );
                }
            }
        }
    }

    /// The gradients recovered from the values equal those evaluated at the
    /// points (stored when the degrees are declared too high for the points),
    /// on a rational patch (quarter annulus) and on a distorted 3D patch of
    /// degrees 2 and 3; with as many points as the degree they are stored.
    #[test]
    fn recovered_gradients_equal_the_evaluated_ones() {
        let annulus = shapes::quarter_annulus(0.5, 1.5)
            .elevate_degree(1, 1)
            .refine_uniform(0, 2)
            .refine_uniform(1, 1);
        let mut cube = shapes::cuboid([0.0; 3], [1.0, 1.2, 0.8]);
        for d in 0..3 {
            cube = cube.elevate_degree(d, 1).refine_uniform(d, 1);
        }
        let distorted = |p: &NurbsPatch| {
            let points = p
                .control_points()
                .iter()
                .map(|x| {
                    [
                        x[0] + 0.05 * (3.0 * x[1] + x[2]).sin(),
                        x[1] + 0.04 * (2.0 * x[0]).cos() * x[2],
                        x[2] + 0.06 * x[0] * x[1],
                    ]
                })
                .collect();
            NurbsPatch::new(p.knots().to_vec(), points, p.weights().to_vec()).unwrap()
        };
        let cubic = distorted(
            &cube
                .elevate_degree(0, 1)
                .elevate_degree(1, 1)
                .elevate_degree(2, 1),
        );
        let cube = distorted(&cube);
        for (patch, n_gauss) in [
            (&annulus, 3),
            (&annulus, 5),
            (&cube, 3),
            (&cube, 4),
            (&cubic, 4),
        ] {
            let dim = patch.param_dim();
            let degrees: Vec<usize> = patch.knots().iter().map(KnotVector::degree).collect();
            for el in patch.elements() {
                let rules = gauss_rules(dim, &[n_gauss]);
                let build = |degrees: &[usize]| {
                    ElementQuadrature::build(
                        dim,
                        (el.lower, el.upper),
                        &rules,
                        degrees,
                        patch.control_points(),
                        patch.weights(),
                        |xi, basis| patch.basis_in_spans(&el.spans, xi, 1, basis),
                    )
                };
                let (recovered, evaluated) = (build(&degrees), build(&[usize::MAX / 2; 3]));
                assert!(!recovered.stores_gradients() && evaluated.stores_gradients());
                assert!(3 * recovered.storage_bytes() < 2 * evaluated.storage_bytes());
                let (mut s1, mut s2) = (Vec::new(), Vec::new());
                let (g1, g2) = (recovered.gradients(&mut s1), evaluated.gradients(&mut s2));
                let scale = g2.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                for (a, b) in g1.iter().zip(g2) {
                    for i in 0..3 {
                        assert!(
                            (a[i] - b[i]).abs() < 1e-12 * scale,
                            "{dim}D, {n_gauss} points: {a:?} vs {b:?}"
                        );
                    }
                }
                assert_eq!(recovered.values, evaluated.values);
            }
        }
        let el = &cube.elements()[0];
        assert!(cube.element_quadrature(el, &[2]).stores_gradients());
        assert!(!cube.element_quadrature(el, &[3]).stores_gradients());
    }
}
