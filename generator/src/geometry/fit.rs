//! Fitting a rough surface height function by a B-spline graph and building the fitted block
//! (spec §3: the surface is represented exactly in the NURBS geometry; the block is the linear
//! blend between the fitted surface and the flat outer face; the fitting error is reported).
#![allow(clippy::needless_range_loop)]

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
    if degree_vertical == 0 || n_elements_vertical == 0 {
        return Err(Error::Geometry(format!(
            "rough block: need degree_vertical >= 1 and n_elements_vertical >= 1, got {degree_vertical}, {n_elements_vertical}"
        )));
    }
    let rough: Vec<f64> = fit.heights.iter().map(|h| h + z_shift).collect();
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
    let nx = fit.x.len();
    let mut points = Vec::with_capacity(nx * v.len());
    for &vj in &v {
        for i in 0..nx {
            let (bottom, top) = match face {
                RoughFace::Top => (z_flat, rough[i]),
                RoughFace::Bottom => (rough[i], z_flat),
            };
            points.push([fit.x[i], bottom + vj * (top - bottom), 0.0]);
        }
    }
    let weights = vec![1.0; points.len()];
    NurbsPatch::new(vec![fit.knots.clone(), vertical], points, weights)
}

/// A square banded matrix (half bandwidth `k`) solved by Gaussian elimination without pivoting,
/// stable for the totally positive collocation and the SPD mass matrices used here.
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
