//! Fitting a rough surface height function by a B-spline graph and building the fitted block
//! (spec §3: the surface is represented exactly in the NURBS geometry; the block is the linear
//! blend between the fitted surface and the flat outer face; the fitting error is reported).
#![allow(clippy::needless_range_loop)]

use super::hierarchical::ThbPatch;
use super::knots::KnotVector;
use super::nurbs::{NurbsPatch, Side};
use crate::basis::basis_ders;
use crate::quadrature::GaussLegendre;
use crate::{Error, Result};

/// How the heights are fitted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitMethod {
    /// Collocation at the Greville abscissae (end values exact).
    Interpolation,
    /// Continuous least squares (L2 projection by Gauss quadrature with `p + 4` points per
    /// element) with both end values exact.
    LeastSquares,
}

/// A fitted B-spline graph `x(u) = W u`, `z(u) = Σ_i N_i(u) h_i`, `u ∈ [0, 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceFit {
    /// Open uniform knot vector on `[0, 1]`.
    pub knots: KnotVector,
    /// Control abscissae `W ū_i` (Greville), so `x(u) = W u` exactly.
    pub x: Vec<f64>,
    /// Control heights `h_i`.
    pub heights: Vec<f64>,
    /// Largest height error `|z − f|` on the dense sample (50 points per element).
    pub max_error: f64,
    /// RMS height error on the same sample.
    pub rms_error: f64,
}

/// Points per element of the dense error sample.
const ERROR_SAMPLES_PER_ELEMENT: usize = 50;

impl SurfaceFit {
    /// The width `W` of the fitted interval `[0, W]`.
    pub fn width(&self) -> f64 {
        self.x[self.x.len() - 1]
    }

    /// The fitted height at abscissa `x ∈ [0, W]` (clamped).
    pub fn height_at(&self, x: f64) -> f64 {
        let u = (x / self.width()).clamp(0.0, 1.0);
        let span = self.knots.find_span(u);
        let p = self.knots.degree();
        let n = basis_ders(&self.knots, span, u, 0);
        (0..=p).map(|j| n[0][j] * self.heights[span - p + j]).sum()
    }
}

/// Fits `z = f(x)` on `[0, width]` by a B-spline graph with `n_elements` uniform elements of
/// `degree` (see [`SurfaceFit`]); end heights are `f(0)` and `f(width)` exactly, and set equal
/// (to their mean) when they agree to 1e-12 relative, so periodic `f` gives bitwise periodic ends.
///
/// Panics unless `width > 0`, `degree ≥ 1`, `n_elements ≥ 1`.
#[track_caller]
pub fn fit_height_function(
    f: &dyn Fn(f64) -> f64,
    width: f64,
    degree: usize,
    n_elements: usize,
    method: FitMethod,
) -> SurfaceFit {
    assert!(
        width > 0.0 && width.is_finite(),
        "fit_height_function: width must be > 0, got {width}"
    );
    let knots = KnotVector::open_uniform(degree, n_elements, 0.0, 1.0);
    let p = degree;
    let greville = knots.greville();
    let n = greville.len();
    let x: Vec<f64> = greville.iter().map(|&g| width * g).collect();
    let (f0, f1) = (f(0.0), f(width));
    let mut heights = vec![0.0; n];
    match method {
        FitMethod::Interpolation => {
            // Collocation matrix A[i][j] = N_j(ū_i), banded with half bandwidth p.
            let mut band = Banded::new(n, p);
            let mut rhs = vec![0.0; n];
            for (i, &g) in greville.iter().enumerate() {
                let span = knots.find_span(g);
                let ders = basis_ders(&knots, span, g, 0);
                for j in 0..=p {
                    band.add(i, span - p + j, ders[0][j]);
                }
                rhs[i] = f(width * g);
            }
            rhs[0] = f0;
            rhs[n - 1] = f1;
            heights = band
                .solve(rhs)
                .expect("the Greville collocation matrix is totally positive");
        }
        FitMethod::LeastSquares => {
            heights[0] = f0;
            heights[n - 1] = f1;
            if n > 2 {
                // Normal equations for the interior heights h_1..h_{n-2}: M h = b − M_ends h_ends.
                let m = n - 2;
                let mut band = Banded::new(m, p);
                let mut rhs = vec![0.0; m];
                let rule = GaussLegendre::new(p + 4);
                for span in knots.element_spans() {
                    let (a, b) = (knots.knots()[span], knots.knots()[span + 1]);
                    for (u, w) in rule.on_interval(a, b) {
                        let ders = basis_ders(&knots, span, u, 0);
                        let fu = f(width * u);
                        for j in 0..=p {
                            let gj = span - p + j;
                            if gj == 0 || gj == n - 1 {
                                continue;
                            }
                            let mut r = fu;
                            for k in 0..=p {
                                let gk = span - p + k;
                                if gk == 0 || gk == n - 1 {
                                    r -= ders[0][k] * heights[gk];
                                } else {
                                    band.add(gj - 1, gk - 1, w * ders[0][j] * ders[0][k]);
                                }
                            }
                            rhs[gj - 1] += w * ders[0][j] * r;
                        }
                    }
                }
                let interior = band
                    .solve(rhs)
                    .expect("the B-spline mass matrix is positive definite");
                heights[1..n - 1].copy_from_slice(&interior);
            }
        }
    }
    if (f0 - f1).abs() <= 1e-12 * f0.abs().max(f1.abs()).max(f64::MIN_POSITIVE) {
        let mean = 0.5 * (f0 + f1);
        heights[0] = mean;
        heights[n - 1] = mean;
    }
    let mut fit = SurfaceFit {
        knots,
        x,
        heights,
        max_error: 0.0,
        rms_error: 0.0,
    };
    let (mut max_error, mut sum_sq, mut count) = (0.0f64, 0.0, 0usize);
    for e in 0..n_elements {
        for s in 0..ERROR_SAMPLES_PER_ELEMENT {
            let xs = width * (e as f64 + s as f64 / (ERROR_SAMPLES_PER_ELEMENT - 1) as f64)
                / n_elements as f64;
            let err = fit.height_at(xs) - f(xs);
            max_error = max_error.max(err.abs());
            sum_sq += err * err;
            count += 1;
        }
    }
    fit.max_error = max_error;
    fit.rms_error = (sum_sq / count as f64).sqrt();
    fit
}

/// Which face of the block is rough.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RoughFace {
    /// The rough face is on top: `z ∈ [z_flat, f + z_shift]` (body 2, the lower body).
    Top,
    /// The rough face is at the bottom: `z ∈ [f + z_shift, z_flat]` (body 1, the upper body).
    Bottom,
}

impl RoughFace {
    /// The side of parametric direction 1 that carries the rough face in [`rough_block`].
    pub fn side(self) -> Side {
        match self {
            RoughFace::Top => Side::High,
            RoughFace::Bottom => Side::Low,
        }
    }
}

/// The 2D block between the fitted rough curve (shifted by `z_shift`) and the flat face
/// `z = z_flat`, in the x-y plane with y the vertical coordinate (control points `[x, z, 0]`).
/// dir 0 = x (the fit's knots), dir 1 = vertical, increasing upwards (open uniform, degree
/// `degree_vertical`, `n_elements_vertical` elements); the rough face is at
/// `(dir 1, face.side())`. Control points in between are the linear blend at the vertical
/// Greville abscissae, so the map is exactly `z(u, v) = z_bottom(u) + v (z_top(u) − z_bottom(u))`.
/// Both parametric directions increase with x and z, so `det J > 0`.
///
/// Panics if a rough control height is not strictly on the block's side of `z_flat`
/// (see [`try_rough_block`] for the checked version).
#[track_caller]
pub fn rough_block(
    fit: &SurfaceFit,
    z_shift: f64,
    z_flat: f64,
    face: RoughFace,
    degree_vertical: usize,
    n_elements_vertical: usize,
) -> NurbsPatch {
    match try_rough_block(
        fit,
        z_shift,
        z_flat,
        face,
        degree_vertical,
        n_elements_vertical,
    ) {
        Ok(patch) => patch,
        Err(e) => panic!("rough_block: {e}"),
    }
}

/// [`rough_block`] returning [`Error::Geometry`] if the block would be folded (a rough control
/// height on the wrong side of `z_flat`) or the vertical discretization is empty.
pub fn try_rough_block(
    fit: &SurfaceFit,
    z_shift: f64,
    z_flat: f64,
    face: RoughFace,
    degree_vertical: usize,
    n_elements_vertical: usize,
) -> Result<NurbsPatch> {
    let base: Vec<[f64; 2]> = fit.x.iter().map(|&x| [x, 0.0]).collect();
    blend_block(
        vec![fit.knots.clone()],
        &base,
        &fit.heights,
        [z_shift, z_flat],
        face,
        degree_vertical,
        n_elements_vertical,
    )
}

/// The block between rough control heights (plus `shift_flat[0]`) over the
/// horizontal control positions `base` and the flat face `z = shift_flat[1]`:
/// the linear blend at the vertical Greville abscissae (the vertical is the
/// last parametric direction and the last coordinate of the point; in 2D the
/// points are `[x, z, 0]`, in 3D `[x, y, z]`).
fn blend_block(
    horizontal: Vec<KnotVector>,
    base: &[[f64; 2]],
    heights: &[f64],
    [z_shift, z_flat]: [f64; 2],
    face: RoughFace,
    degree_vertical: usize,
    n_elements_vertical: usize,
) -> Result<NurbsPatch> {
    if degree_vertical == 0 || n_elements_vertical == 0 {
        return Err(Error::Geometry(format!(
            "rough block: need degree_vertical >= 1 and n_elements_vertical >= 1, got {degree_vertical}, {n_elements_vertical}"
        )));
    }
    let rough: Vec<f64> = heights.iter().map(|h| h + z_shift).collect();
    let folded = match face {
        RoughFace::Top => rough.iter().position(|&z| z <= z_flat),
        RoughFace::Bottom => rough.iter().position(|&z| z >= z_flat),
    };
    if let Some(i) = folded {
        return Err(Error::Geometry(format!(
            "rough block ({face:?}): rough control height {} (index {i}) is not strictly {} the flat face z = {z_flat}",
            rough[i],
            if face == RoughFace::Top {
                "above"
            } else {
                "below"
            }
        )));
    }
    let vertical = KnotVector::open_uniform(degree_vertical, n_elements_vertical, 0.0, 1.0);
    let v = vertical.greville();
    let three_d = horizontal.len() == 2;
    let mut points = Vec::with_capacity(base.len() * v.len());
    for &vj in &v {
        for (b, &z_rough) in base.iter().zip(&rough) {
            let (bottom, top) = match face {
                RoughFace::Top => (z_flat, z_rough),
                RoughFace::Bottom => (z_rough, z_flat),
            };
            let z = bottom + vj * (top - bottom);
            points.push(if three_d {
                [b[0], b[1], z]
            } else {
                [b[0], z, 0.0]
            });
        }
    }
    let weights = vec![1.0; points.len()];
    let mut knots = horizontal;
    knots.push(vertical);
    NurbsPatch::new(knots, points, weights)
}

/// The rough block `patch` (built by [`try_rough_block`] or [`try_rough_volume`] on
/// `[0, W]`, possibly refined) with its rough face moved towards the surface
/// `z = height(x, y) + z_shift` (`y` unused in 2D): the control points get the
/// hierarchical quasi-interpolant ([`ThbPatch::quasi_interpolate`]) of the vertical
/// correction `(height(x, y) + z_shift − z) r(ζ)`, `(x, y, z)` the patch's own rough
/// face at the lateral parameters and `r` the block's linear blend (1 on the rough
/// face, 0 on the flat one). The lateral map is kept. The block of the fit is a
/// polynomial B-spline patch, so the new map is exactly the quasi-interpolant of the
/// block between the surface and the flat face: where the patch is refined the face
/// follows the surface at the order of the finer level (the fit's error does not
/// survive refinement), and where it is not, at the order of the case's mesh.
pub fn resolve_rough_face(
    patch: &ThbPatch,
    face: RoughFace,
    z_shift: f64,
    height: impl Fn(f64, f64) -> f64,
) -> Result<ThbPatch> {
    if patch.weights().iter().any(|&w| (w - 1.0).abs() > 1e-12) {
        return Err(Error::Geometry(
            "resolve_rough_face: a rough block is a polynomial B-spline patch (weights 1)".into(),
        ));
    }
    let dim = patch.param_dim();
    let vertical = dim - 1;
    let (first, last) = (
        patch.knots()[vertical].first(),
        patch.knots()[vertical].last(),
    );
    let face_param = match face {
        RoughFace::Top => last,
        RoughFace::Bottom => first,
    };
    // The correction on the rough face, per lateral parameter point (the
    // quasi-interpolant asks each at several heights).
    let memo = std::cell::RefCell::new(std::collections::HashMap::<[u64; 2], f64>::new());
    let on_face = |u: f64, v: f64| -> f64 {
        *memo
            .borrow_mut()
            .entry([u.to_bits(), v.to_bits()])
            .or_insert_with(|| {
                let mut xi = [u, v, 0.0];
                xi[vertical] = face_param;
                let x = patch.point(&xi[..dim]);
                let y = if dim == 3 { x[1] } else { 0.0 };
                height(x[0], y) + z_shift - x[vertical]
            })
    };
    let correction = patch.quasi_interpolate(|xi| {
        let t = (xi[vertical] - first) / (last - first);
        let r = match face {
            RoughFace::Top => t,
            RoughFace::Bottom => 1.0 - t,
        };
        if r == 0.0 {
            return 0.0;
        }
        let v = if dim == 3 { xi[1] } else { 0.0 };
        on_face(xi[0], v) * r
    });
    let points = patch
        .control_points()
        .iter()
        .zip(&correction)
        .map(|(x, dz)| {
            let mut y = *x;
            y[vertical] += dz;
            y
        })
        .collect();
    Ok(patch.with_control_points(points))
}

/// A fitted bivariate B-spline graph over the cell `[0, W]²` (3D samples):
/// `x = W u`, `y = W v`, `z(u, v) = Σ_ij N_i(u) N_j(v) h_ij`.
#[derive(Clone, Debug, PartialEq)]
pub struct ArealFit {
    /// Open uniform knot vectors on `[0, 1]` along x and y.
    pub knots: [KnotVector; 2],
    /// Control abscissae `W ū_i` (Greville).
    pub x: Vec<f64>,
    /// Control ordinates `W v̄_j` (Greville).
    pub y: Vec<f64>,
    /// Control heights `h_ij`, `i` (x) fastest.
    pub heights: Vec<f64>,
    /// Largest height error `|z − f|` on the dense sample (8 × 8 points per element).
    pub max_error: f64,
    /// RMS height error on the same sample.
    pub rms_error: f64,
}

/// Points per element and direction of the 3D error sample.
const AREAL_ERROR_SAMPLES: usize = 8;

impl ArealFit {
    /// The cell width `W`.
    pub fn width(&self) -> f64 {
        self.x[self.x.len() - 1]
    }

    /// The fitted height at `(x, y)` in the cell (clamped).
    pub fn height_at(&self, x: f64, y: f64) -> f64 {
        let w = self.width();
        let [kx, ky] = &self.knots;
        let (u, v) = ((x / w).clamp(0.0, 1.0), (y / w).clamp(0.0, 1.0));
        let (su, sv) = (kx.find_span(u), ky.find_span(v));
        let (px, py) = (kx.degree(), ky.degree());
        let (nu, nv) = (basis_ders(kx, su, u, 0), basis_ders(ky, sv, v, 0));
        let nx = self.x.len();
        let mut z = 0.0;
        for b in 0..=py {
            for a in 0..=px {
                z += nu[0][a] * nv[0][b] * self.heights[(sv - py + b) * nx + su - px + a];
            }
        }
        z
    }
}

/// The collocation abscissae of the open uniform `knots` on `[0, 1]`: the
/// Greville points; `periodic`: those of the periodic (wrapped) B-splines on
/// the same breaks, `u_k = ((k + (p + 1)/2)/n) mod 1`, `k < n` (the knots for
/// odd `p`, the element mid-points for even `p`: Schoenberg's cardinal
/// interpolation, uniquely solvable).
fn collocation_points(knots: &KnotVector, periodic: bool) -> Vec<f64> {
    if !periodic {
        return knots.greville();
    }
    let (p, n) = (knots.degree(), knots.n_elements());
    (0..n)
        .map(|k| ((2 * k + p + 1) % (2 * n)) as f64 / (2 * n) as f64)
        .collect()
}

/// Solves the collocation system of `knots` at [`collocation_points`] for
/// each right-hand side, in place; the solutions are the `n + p` coefficients
/// of the open (clamped) basis. Not periodic: interpolation at the Greville
/// points (end values exact). Periodic: the `n` interpolation conditions and
/// `p` seam conditions `s^(k)(1) = s^(k)(0)`, `k < p`, i.e. the periodic
/// spline (C^(p−1) across the seam, as at every interior knot) written in the
/// open basis; solved densely (LU with partial pivoting).
fn collocate(knots: &KnotVector, periodic: bool, rhs: &mut [Vec<f64>]) -> Result<()> {
    let p = knots.degree();
    let points = collocation_points(knots, periodic);
    if !periodic {
        let mut band = Banded::new(points.len(), p);
        for (i, &g) in points.iter().enumerate() {
            let span = knots.find_span(g);
            let ders = basis_ders(knots, span, g, 0);
            for j in 0..=p {
                band.add(i, span - p + j, ders[0][j]);
            }
        }
        for r in rhs.iter_mut() {
            *r = band.clone().solve(std::mem::take(r))?;
        }
        return Ok(());
    }
    let m = knots.n_basis();
    let mut a = nalgebra::DMatrix::<f64>::zeros(m, m);
    for (i, &u) in points.iter().enumerate() {
        let span = knots.find_span(u);
        let ders = basis_ders(knots, span, u, 0);
        for j in 0..=p {
            a[(i, span - p + j)] = ders[0][j];
        }
    }
    let (first, last) = (knots.find_span(0.0), knots.find_span(1.0));
    let (d0, d1) = (
        basis_ders(knots, first, 0.0, p - 1),
        basis_ders(knots, last, 1.0, p - 1),
    );
    for k in 0..p {
        let row = points.len() + k;
        for j in 0..=p {
            a[(row, last - p + j)] += d1[k][j];
            a[(row, first - p + j)] -= d0[k][j];
        }
    }
    let lu = a.lu();
    for r in rhs.iter_mut() {
        let mut b = nalgebra::DVector::<f64>::zeros(m);
        b.rows_mut(0, r.len()).copy_from_slice(r);
        let c = lu.solve(&b).ok_or_else(|| {
            Error::Geometry("periodic surface fit: singular collocation matrix".into())
        })?;
        *r = c.iter().copied().collect();
    }
    Ok(())
}

/// Whether `f(x, y)` is periodic over the cell along x (`axis` 0) or y (1):
/// `f(0, t) = f(W, t)` (with y for t along x, and x for t along y) at 64
/// ordinates, to 1e-12 of the largest `|f|` there.
fn periodic_along(f: &dyn Fn(f64, f64) -> f64, width: f64, axis: usize) -> bool {
    let ends: Vec<(f64, f64)> = (0..64)
        .map(|k| {
            let t = width * (k as f64 + 0.3) / 64.0;
            if axis == 0 {
                (f(0.0, t), f(width, t))
            } else {
                (f(t, 0.0), f(t, width))
            }
        })
        .collect();
    let scale = ends
        .iter()
        .fold(f64::MIN_POSITIVE, |m, (a, b)| m.max(a.abs()).max(b.abs()));
    ends.iter().all(|(a, b)| (a - b).abs() <= 1e-12 * scale)
}

/// Fits `z = f(x, y)` on the cell `[0, W]²` by a tensor-product B-spline graph
/// of `degree` with `n_elements = [n_x, n_y]` uniform elements, by
/// collocation (separable: along x, then along y). Along a direction in which
/// `f` is periodic (every areal surface of a case) the fit is the periodic
/// spline interpolant: C^(p−1) across the cell's seam as at every interior
/// knot, so a periodic master has no kink there (a kink makes the closest
/// point of a slave point above it jump between its two sides, and Newton
/// cycle); opposite edges are then set bitwise equal. Otherwise it
/// interpolates at the Greville points (the edges interpolate `f` on the
/// boundary). The error is measured on a dense sample.
pub fn fit_height_map(
    f: &dyn Fn(f64, f64) -> f64,
    width: f64,
    degree: usize,
    n_elements: [usize; 2],
) -> Result<ArealFit> {
    if !(width.is_finite() && width > 0.0) || degree == 0 || n_elements.contains(&0) {
        return Err(Error::Geometry(format!(
            "areal fit: need width > 0, degree >= 1 and elements >= 1, got {width}, {degree}, {n_elements:?}"
        )));
    }
    let knots = n_elements.map(|n| KnotVector::open_uniform(degree, n, 0.0, 1.0));
    let periodic = [0, 1].map(|axis| periodic_along(f, width, axis));
    let [ux, uy] = [0, 1].map(|d| collocation_points(&knots[d], periodic[d]));
    let (nx, ny) = (knots[0].n_basis(), knots[1].n_basis());
    // Along x for every collocation row y_j, then along y for every column.
    let mut rows: Vec<Vec<f64>> = uy
        .iter()
        .map(|&v| ux.iter().map(|&u| f(width * u, width * v)).collect())
        .collect();
    collocate(&knots[0], periodic[0], &mut rows)?;
    let mut columns: Vec<Vec<f64>> = (0..nx)
        .map(|i| rows.iter().map(|r| r[i]).collect())
        .collect();
    collocate(&knots[1], periodic[1], &mut columns)?;
    let mut heights = vec![0.0; nx * ny];
    for (i, c) in columns.iter().enumerate() {
        for (j, h) in c.iter().enumerate() {
            heights[j * nx + i] = *h;
        }
    }
    // Periodic: the seam's control points agree to rounding; make them equal.
    if periodic[0] {
        for j in 0..ny {
            let m = 0.5 * (heights[j * nx] + heights[j * nx + nx - 1]);
            heights[j * nx] = m;
            heights[j * nx + nx - 1] = m;
        }
    }
    if periodic[1] {
        for i in 0..nx {
            let m = 0.5 * (heights[i] + heights[(ny - 1) * nx + i]);
            heights[i] = m;
            heights[(ny - 1) * nx + i] = m;
        }
    }
    let [gx, gy] = [knots[0].greville(), knots[1].greville()];
    let mut fit = ArealFit {
        knots,
        x: gx.iter().map(|g| width * g).collect(),
        y: gy.iter().map(|g| width * g).collect(),
        heights,
        max_error: 0.0,
        rms_error: 0.0,
    };
    let (mut max_error, mut sum_sq) = (0.0f64, 0.0);
    let (sx, sy) = (
        n_elements[0] * AREAL_ERROR_SAMPLES,
        n_elements[1] * AREAL_ERROR_SAMPLES,
    );
    for j in 0..=sy {
        for i in 0..=sx {
            let (x, y) = (width * i as f64 / sx as f64, width * j as f64 / sy as f64);
            let e = fit.height_at(x, y) - f(x, y);
            max_error = max_error.max(e.abs());
            sum_sq += e * e;
        }
    }
    fit.max_error = max_error;
    fit.rms_error = (sum_sq / ((sx + 1) * (sy + 1)) as f64).sqrt();
    Ok(fit)
}

/// The 3D block between the fitted rough surface (shifted by `z_shift`) and
/// the flat face `z = z_flat`: parametric directions x, y (the fit's knots)
/// and the vertical (open uniform, `degree_vertical`, `n_elements_vertical`),
/// the map `z(u, v, w) = z_bottom(u, v) + w (z_top(u, v) − z_bottom(u, v))`
/// exactly (the 3D counterpart of [`try_rough_block`]); the rough face is at
/// `(dir 2, face.side())`. Errors as [`try_rough_block`].
pub fn try_rough_volume(
    fit: &ArealFit,
    z_shift: f64,
    z_flat: f64,
    face: RoughFace,
    degree_vertical: usize,
    n_elements_vertical: usize,
) -> Result<NurbsPatch> {
    let base: Vec<[f64; 2]> = fit
        .y
        .iter()
        .flat_map(|&y| fit.x.iter().map(move |&x| [x, y]))
        .collect();
    blend_block(
        fit.knots.to_vec(),
        &base,
        &fit.heights,
        [z_shift, z_flat],
        face,
        degree_vertical,
        n_elements_vertical,
    )
}

/// A square banded matrix (half bandwidth `k`) solved by Gaussian elimination without pivoting,
/// stable for the totally positive collocation and the SPD mass matrices used here.
#[derive(Clone)]
struct Banded {
    n: usize,
    k: usize,
    /// Row i, column j stored at `i * (2k + 1) + (j + k − i)`.
    data: Vec<f64>,
}

impl Banded {
    fn new(n: usize, k: usize) -> Self {
        Banded {
            n,
            k,
            data: vec![0.0; n * (2 * k + 1)],
        }
    }

    fn at(&self, i: usize, j: usize) -> usize {
        i * (2 * self.k + 1) + (j + self.k - i)
    }

    fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(i.abs_diff(j) <= self.k);
        let at = self.at(i, j);
        self.data[at] += v;
    }

    fn solve(mut self, mut b: Vec<f64>) -> Result<Vec<f64>> {
        let (n, k) = (self.n, self.k);
        for c in 0..n {
            let pivot = self.data[self.at(c, c)];
            if pivot == 0.0 || !pivot.is_finite() {
                return Err(Error::Geometry(format!(
                    "surface fit: zero pivot in row {c}"
                )));
            }
            for i in c + 1..(c + k + 1).min(n) {
                let factor = self.data[self.at(i, c)] / pivot;
                if factor == 0.0 {
                    continue;
                }
                for j in c..(c + k + 1).min(n) {
                    let v = self.data[self.at(c, j)];
                    let at = self.at(i, j);
                    self.data[at] -= factor * v;
                }
                b[i] -= factor * b[c];
            }
        }
        for c in (0..n).rev() {
            let mut s = b[c];
            for j in c + 1..(c + k + 1).min(n) {
                s -= self.data[self.at(c, j)] * b[j];
            }
            b[c] = s / self.data[self.at(c, c)];
        }
        Ok(b)
    }
}
