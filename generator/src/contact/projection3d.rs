//! Closest-point projection of a slave point onto the master surface in 3D
//! (spec §6): the master face is a THB (or NURBS) surface in the current
//! configuration ([`MasterSurface`]), possibly locally refined (elements of
//! different sizes), and repeated periodically in x and y (PR conditions).
//!
//! The search ([`MasterSearch`]) bounds every element by an axis-aligned box
//! that holds it: that of its polynomial piece's Bézier coefficients where
//! the pieces are built ([`FacePieces::bezier_box`]), else that of its
//! functions' control points (THB and NURBS functions are non-negative and
//! sum to one on an element, so the element's surface lies in their convex
//! hull, which at p = 2 reaches half an element over each neighbour): the
//! distance to that box is a lower bound of the distance to the element.
//! Elements (and periodic images) are minimized in the order of their bounds,
//! starting with the previous projection's element (without one: the element
//! with the nearest box among those over the point), until the bound exceeds
//! the best distance found; every element that could hold a closer point —
//! in particular every element sharing the closest point — has been
//! minimized. The bounds are computed only for the elements listed in the
//! cells of a uniform x-y grid that the best distance reaches (`BoxGrid`),
//! so a point costs the elements near it, not all of them. The surface is
//! evaluated on each element's polynomial piece ([`FacePieces`]). Each
//! element minimization is a Newton iteration on `½|x − x_m(η)|²` over the element's parameter box (projected Newton:
//! coordinates at a bound with the gradient pointing outward are held, the
//! others take the Newton step, with backtracking).
//!
//! Where the closest point lies on an element boundary without being
//! orthogonal there, it is a C0 feature of the master (degree 1 or repeated
//! knots): an *edge* (one parameter held, the point in the edge's normal
//! cone) or a *vertex* (both held). As in 2D, the gap is then the signed
//! distance to the feature ([`SurfaceProjection::fixed`]). At a boundary of
//! a non-periodic master the projection is *clamped* there.

use super::pieces::FacePieces;
pub use super::pieces::SurfacePoint;
use crate::basis::{RationalBasis, TensorBasis};
use crate::geometry::ThbPatch;
use crate::{Error, Result};

/// The master surface in the current configuration: the reference face patch
/// (its mesh, basis and weights) with current control points.
#[derive(Clone, Copy, Debug)]
pub struct MasterSurface<'a> {
    /// The master face (reference configuration), two parametric directions.
    pub face: &'a ThbPatch,
    /// Current control points, in the face's numbering.
    pub points: &'a [[f64; 3]],
    /// The polynomial pieces of `face` at `points`, if built
    /// ([`FacePieces::new`]): the evaluator then reads them instead of the
    /// THB basis.
    pub pieces: Option<&'a FacePieces>,
}

/// Evaluates a [`MasterSurface`] with reused buffers.
pub struct SurfaceEvaluator<'a> {
    surface: MasterSurface<'a>,
    scratch: TensorBasis,
    basis: RationalBasis,
}

impl<'a> SurfaceEvaluator<'a> {
    /// An evaluator of `surface`.
    #[track_caller]
    pub fn new(surface: MasterSurface<'a>) -> Self {
        assert_eq!(
            surface.face.param_dim(),
            2,
            "SurfaceEvaluator: the master face must be a surface"
        );
        SurfaceEvaluator {
            surface,
            scratch: TensorBasis::default(),
            basis: RationalBasis::default(),
        }
    }

    /// Position, tangents and second derivatives of element `e`'s polynomial
    /// (rational) piece at `eta` (one-sided at the element's boundary).
    pub fn at(&mut self, e: usize, eta: [f64; 2]) -> SurfacePoint {
        if let Some(s) = self
            .surface
            .pieces
            .and_then(|p| p.at(self.surface.face, e, &eta))
        {
            return s;
        }
        self.at_basis(e, eta)
    }

    /// [`Self::at`] by the THB basis.
    fn at_basis(&mut self, e: usize, eta: [f64; 2]) -> SurfacePoint {
        self.surface
            .face
            .element_basis_into(e, &eta, 2, &mut self.scratch, &mut self.basis);
        let b = &self.basis;
        let mut s = SurfacePoint::default();
        for (k, &g) in b.indices.iter().enumerate() {
            let p = self.surface.points[g];
            for c in 0..3 {
                s.x[c] += b.values[k] * p[c];
                for i in 0..2 {
                    s.a[i][c] += b.d1[k][i] * p[c];
                    for l in 0..2 {
                        s.aa[i][l][c] += b.d2[k][i][l] * p[c];
                    }
                }
            }
        }
        s
    }
}

impl MasterSurface<'_> {
    /// Number of elements.
    pub fn n_elements(&self) -> usize {
        self.face.n_elements()
    }

    /// Parameter box `(lower, upper)` of element `e`.
    pub fn bounds(&self, e: usize) -> ([f64; 2], [f64; 2]) {
        let el = &self.face.elements()[e];
        ([el.lower[0], el.lower[1]], [el.upper[0], el.upper[1]])
    }

    /// The current point at `eta`.
    pub fn point(&self, eta: [f64; 2]) -> [f64; 3] {
        SurfaceEvaluator::new(*self)
            .at(self.face.locate(&eta), eta)
            .x
    }
}

/// Result of a projection onto the master surface.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceProjection {
    /// Master surface parameters.
    pub eta: [f64; 2],
    /// Master element whose polynomial piece holds the projection.
    pub element: usize,
    /// Periodic image `(k_x, k_y)`: the master's points shifted by `(k_x W_x, k_y W_y, 0)`.
    pub image: [i64; 2],
    /// The physical shift of that image.
    pub shift: [f64; 3],
    /// Parameters held at the element's boundary: at a C0 edge (one) or
    /// vertex (both) of the master, the slave point in its normal cone, or at
    /// the end of a non-periodic master ([`Self::clamped`]).
    pub fixed: [bool; 2],
    /// The projection stopped at a boundary of a non-periodic master.
    pub clamped: bool,
    /// Distance to the projected point.
    pub distance: f64,
}

/// Periodic images of the master per direction beyond which a contact
/// search is refused: a slave point that far from the sample is a diverged
/// iterate (a search there once asked for 4.5 TB and aborted the process,
/// the 3D egg box with segment-based integration).
pub const MAX_IMAGES: usize = 64;

/// Per-configuration search data: the bounding boxes of the master elements,
/// the periods and where the parameter domain has seams.
#[derive(Clone, Debug)]
pub struct MasterSearch {
    boxes: Vec<([f64; 3], [f64; 3])>,
    /// Bounding box of the whole master.
    extent: ([f64; 3], [f64; 3]),
    /// Periods in x and y (PR conditions).
    periods: [Option<f64>; 2],
    /// Parameter domain of the face.
    domain: ([f64; 2], [f64; 2]),
    /// Whether the ends of parametric direction `d` are periodic seams.
    seams: [bool; 2],
    /// A length of the master (for relative tolerances).
    scale: f64,
    /// The elements over each cell of a uniform grid on the master's x-y extent.
    grid: BoxGrid,
}

/// A uniform grid of cells over the x-y extent of the master, each listing the
/// elements whose bounding box overlaps it: the elements whose box lies within
/// a distance `r` of a point are among those of the cells the square of side
/// `2r` around it overlaps, so a search with a finite bound visits those only
/// (the number of elements near the point, not all of them).
#[derive(Clone, Debug)]
struct BoxGrid {
    origin: [f64; 2],
    cell: [f64; 2],
    n: [usize; 2],
    elements: Vec<Vec<u32>>,
}

impl BoxGrid {
    fn new(boxes: &[([f64; 3], [f64; 3])], extent: ([f64; 3], [f64; 3])) -> Self {
        let side = (boxes.len() as f64).sqrt().ceil().max(1.0) as usize;
        let origin = [extent.0[0], extent.0[1]];
        let mut n = [1; 2];
        let mut cell = [1.0; 2];
        for d in 0..2 {
            let length = extent.1[d] - extent.0[d];
            if length.is_finite() && length > 0.0 {
                n[d] = side;
                cell[d] = length / side as f64;
            }
        }
        let mut grid = BoxGrid {
            origin,
            cell,
            n,
            elements: vec![Vec::new(); n[0] * n[1]],
        };
        for (e, (lo, hi)) in boxes.iter().enumerate() {
            if let Some(([i0, j0], [i1, j1])) = grid.range([lo[0], lo[1]], [hi[0], hi[1]]) {
                for j in j0..=j1 {
                    for i in i0..=i1 {
                        grid.elements[i + grid.n[0] * j].push(e as u32);
                    }
                }
            }
        }
        grid
    }

    /// The cells overlapping the box `[lo, hi]` (x-y), if any.
    fn range(&self, lo: [f64; 2], hi: [f64; 2]) -> Option<([usize; 2], [usize; 2])> {
        let mut out = ([0; 2], [0; 2]);
        for d in 0..2 {
            let a = ((lo[d] - self.origin[d]) / self.cell[d]).floor();
            let b = ((hi[d] - self.origin[d]) / self.cell[d]).floor();
            let last = (self.n[d] - 1) as f64;
            // Outside the grid (or NaN): no cell. Boxes that overlap share a
            // point, and its cell (clamped to the grid) lies in both ranges.
            if !(b >= 0.0 && a <= last) {
                return None;
            }
            out.0[d] = a.max(0.0) as usize;
            out.1[d] = b.min(last) as usize;
        }
        Some(out)
    }

    /// Pushes onto `out` the elements of the cells that the square of
    /// half-side `r` around `x` overlaps (with repetitions).
    fn near(&self, x: [f64; 3], r: f64, out: &mut Vec<u32>) {
        if let Some(([i0, j0], [i1, j1])) = self.range([x[0] - r, x[1] - r], [x[0] + r, x[1] + r]) {
            for j in j0..=j1 {
                for i in i0..=i1 {
                    out.extend_from_slice(&self.elements[i + self.n[0] * j]);
                }
            }
        }
    }
}

impl MasterSearch {
    /// Bounding boxes of `surface`'s elements; `periods` in x and y. A
    /// parametric direction whose ends are a period apart along a periodic
    /// axis has seams there, not boundaries.
    pub fn new(surface: &MasterSurface, periods: [Option<f64>; 2]) -> Self {
        let face = surface.face;
        let mut boxes = Vec::with_capacity(face.n_elements());
        let mut extent = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for (e, el) in face.elements().iter().enumerate() {
            let mut b = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            if let Some(tight) = surface.pieces.and_then(|p| p.bezier_box(e)) {
                // Widened by the round-off of the conversion (relative to
                // the coordinates' size).
                for c in 0..3 {
                    let slack =
                        1e-13 * (tight.1[c] - tight.0[c] + tight.0[c].abs().max(tight.1[c].abs()));
                    b.0[c] = tight.0[c] - slack;
                    b.1[c] = tight.1[c] + slack;
                }
            } else {
                for &g in &el.functions {
                    let p = surface.points[g];
                    for c in 0..3 {
                        b.0[c] = b.0[c].min(p[c]);
                        b.1[c] = b.1[c].max(p[c]);
                    }
                }
            }
            for c in 0..3 {
                extent.0[c] = extent.0[c].min(b.0[c]);
                extent.1[c] = extent.1[c].max(b.1[c]);
            }
            boxes.push(b);
        }
        let kv = face.knots();
        let domain = ([kv[0].first(), kv[1].first()], [kv[0].last(), kv[1].last()]);
        // Seams: the two ends of direction d differ by a period along an axis.
        let mut seams = [false; 2];
        let mid = [
            0.5 * (domain.0[0] + domain.1[0]),
            0.5 * (domain.0[1] + domain.1[1]),
        ];
        for (d, seam) in seams.iter_mut().enumerate() {
            let (mut lo, mut hi) = (mid, mid);
            lo[d] = domain.0[d];
            hi[d] = domain.1[d];
            let (xl, xh) = (surface.point(lo), surface.point(hi));
            *seam = (0..2)
                .any(|c| periods[c].is_some_and(|w| ((xh[c] - xl[c]).abs() - w).abs() <= 1e-9 * w));
        }
        let scale = (0..3)
            .map(|c| extent.1[c] - extent.0[c])
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let grid = BoxGrid::new(&boxes, extent);
        MasterSearch {
            boxes,
            extent,
            periods,
            domain,
            seams,
            scale,
            grid,
        }
    }

    /// The elements and periodic images whose bounding box lies within
    /// `reach` of the box `[lo, hi]`: every element that can hold the
    /// closest point of a point in that box at a distance up to `reach`
    /// (the elements listed by the grid's cells near the box, then the
    /// exact distance between the boxes). An error where that takes more
    /// than [`MAX_IMAGES`] periodic images per direction (a diverged
    /// iterate).
    pub fn near_box(
        &self,
        lo: [f64; 3],
        hi: [f64; 3],
        reach: f64,
    ) -> Result<Vec<(usize, [i64; 2])>> {
        let centre = [0, 1, 2].map(|c| 0.5 * (lo[c] + hi[c]));
        let radius = reach + (0..2).map(|c| 0.5 * (hi[c] - lo[c])).fold(0.0, f64::max);
        let (wide_lo, wide_hi) = (lo.map(|v| v - reach), hi.map(|v| v + reach));
        let mut out = Vec::new();
        let mut near = Vec::new();
        for k in self.images_between(wide_lo, wide_hi)? {
            let shift = self.shift(k);
            near.clear();
            self.grid.near(sub(centre, shift), radius, &mut near);
            near.sort_unstable();
            near.dedup();
            for &e in &near {
                let (bl, bh) = self.boxes[e as usize];
                let d2: f64 = (0..3)
                    .map(|c| {
                        let (a, b) = (bl[c] + shift[c], bh[c] + shift[c]);
                        (a - hi[c]).max(lo[c] - b).max(0.0).powi(2)
                    })
                    .sum();
                if d2.sqrt() <= reach {
                    out.push((e as usize, k));
                }
            }
        }
        Ok(out)
    }

    /// The periodic images of the master that may hold the closest point to `x`.
    fn images(&self, x: [f64; 3]) -> Result<Vec<[i64; 2]>> {
        self.images_between(x, x)
    }

    /// The periodic images of the master that may hold the closest point to
    /// a point of the box `[lo, hi]`; an error for more than [`MAX_IMAGES`]
    /// per direction or a box that is not finite.
    fn images_between(&self, lo: [f64; 3], hi: [f64; 3]) -> Result<Vec<[i64; 2]>> {
        let range = |c: usize| -> Result<std::ops::RangeInclusive<i64>> {
            let Some(w) = self.periods[c] else {
                return Ok(0..=0);
            };
            let (k0, k1) = (
                ((lo[c] - self.extent.1[c]) / w).floor(),
                ((hi[c] - self.extent.0[c]) / w).ceil(),
            );
            if !(k0.is_finite() && k1.is_finite()) || k1 - k0 >= MAX_IMAGES as f64 {
                return Err(Error::Geometry(format!(
                    "contact search over [{:e}, {:e}] along {}: more than {MAX_IMAGES} periodic \
                     images of the master (the configuration has diverged)",
                    lo[c],
                    hi[c],
                    ["x", "y"][c]
                )));
            }
            Ok(k0 as i64..=k1 as i64)
        };
        let (kx, ky) = (range(0)?, range(1)?);
        Ok(kx.flat_map(|i| ky.clone().map(move |j| [i, j])).collect())
    }

    /// The physical shift of image `k`.
    pub fn shift(&self, k: [i64; 2]) -> [f64; 3] {
        [
            self.periods[0].map_or(0.0, |w| k[0] as f64 * w),
            self.periods[1].map_or(0.0, |w| k[1] as f64 * w),
            0.0,
        ]
    }

    /// The unit normal `a_1 × a_2 / |a_1 × a_2|` at a point `eta` of element
    /// `e`'s boundary, averaged over the elements that meet there (two at
    /// an edge, up to four at a vertex, across periodic seams; `e` alone
    /// where `eta` is interior or at the end of a non-periodic master). At a
    /// C0 crease of the master (degree 1, repeated knots) this is the
    /// direction of the bisector of the two faces: the slave points along
    /// `x_m(eta) + g n` are as far from the one face as from the other, so
    /// the closest point passes from one element to the next there. Where
    /// the master is C1 it is the element's own normal.
    pub fn crease_normal(&self, ev: &mut SurfaceEvaluator, e: usize, eta: [f64; 2]) -> [f64; 3] {
        let face = ev.surface.face;
        let (lo, hi) = ev.surface.bounds(e);
        // Per direction, the offsets probed: into `e` and, at its boundary,
        // out of it.
        let probes = |d: usize| -> Vec<f64> {
            let eps = 1e-9 * (self.domain.1[d] - self.domain.0[d]);
            if eta[d] <= lo[d] {
                vec![eps, -eps]
            } else if eta[d] >= hi[d] {
                vec![-eps, eps]
            } else {
                vec![0.0]
            }
        };
        let mut sum = [0.0; 3];
        for s0 in probes(0) {
            'probe: for s1 in probes(1) {
                let (mut probe, mut at) = (eta, eta);
                for (d, s) in [s0, s1].into_iter().enumerate() {
                    probe[d] += s;
                    let width = self.domain.1[d] - self.domain.0[d];
                    let wrap = if probe[d] < self.domain.0[d] {
                        width
                    } else if probe[d] > self.domain.1[d] {
                        -width
                    } else {
                        continue;
                    };
                    if !self.seams[d] {
                        continue 'probe;
                    }
                    probe[d] += wrap;
                    at[d] += wrap;
                }
                let n = face.locate(&probe);
                let (l, h) = ev.surface.bounds(n);
                let at = [0, 1].map(|d| at[d].clamp(l[d], h[d]));
                let sp = ev.at(n, at);
                let c = nalgebra::Vector3::from(sp.a[0]).cross(&nalgebra::Vector3::from(sp.a[1]));
                let len = c.norm();
                for k in 0..3 {
                    sum[k] += c[k] / len;
                }
            }
        }
        let len = dot(sum, sum).sqrt();
        sum.map(|v| v / len)
    }

    /// Distance from `x` to the bounding box of element `e`.
    fn lower_bound(&self, e: usize, x: [f64; 3]) -> f64 {
        let (lo, hi) = self.boxes[e];
        (0..3)
            .map(|c| (lo[c] - x[c]).max(x[c] - hi[c]).max(0.0).powi(2))
            .sum::<f64>()
            .sqrt()
    }
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Closest point of element `e` to `x` by projected Newton on
/// `f(η) = ½|x − x_m(η)|²` over the element's parameter box. From `start`
/// (the previous projection) alone when Newton converges inside the element
/// there (the minimum is tracked as the configuration moves); otherwise
/// from the closest of `start` and a 3 × 3 grid of the element's corners,
/// edge mid-points and centre (the distance may have several local minima
/// on one element). Returns `(η, |x − x_m(η)|²)`.
fn element_minimum(
    ev: &mut SurfaceEvaluator,
    e: usize,
    x: [f64; 3],
    start: Option<[f64; 2]>,
) -> ([f64; 2], f64) {
    if let Some(s) = start {
        let (eta, f, interior) = element_descent(ev, e, x, &[s]);
        if interior {
            return (eta, f);
        }
    }
    let (lo, hi) = ev.surface.bounds(e);
    // `start` (if any), then the grid: on the stack (a hot path).
    let mut starts = [[0.0; 2]; 10];
    let first = usize::from(start.is_some());
    starts[0] = start.unwrap_or_default();
    for k in 0..9 {
        let t = [(k % 3) as f64 / 2.0, (k / 3) as f64 / 2.0];
        starts[first + k] = [
            lo[0] + t[0] * (hi[0] - lo[0]),
            lo[1] + t[1] * (hi[1] - lo[1]),
        ];
    }
    let (eta, f, _) = element_descent(ev, e, x, &starts[..first + 9]);
    (eta, f)
}

/// Projected Newton of [`element_minimum`] from the closest of `starts`;
/// returns `(η, |x − x_m(η)|², interior)`, `interior` when no parameter
/// ends at the element's boundary.
fn element_descent(
    ev: &mut SurfaceEvaluator,
    e: usize,
    x: [f64; 3],
    starts: &[[f64; 2]],
) -> ([f64; 2], f64, bool) {
    let (lo, hi) = ev.surface.bounds(e);
    let clamp = |eta: [f64; 2]| [eta[0].clamp(lo[0], hi[0]), eta[1].clamp(lo[1], hi[1])];
    let mut eta = [0.0; 2];
    let mut p = SurfacePoint::default();
    let mut f = f64::INFINITY;
    for s in starts.iter().map(|&s| clamp(s)) {
        let ps = ev.at(e, s);
        let fs = dot(sub(x, ps.x), sub(x, ps.x));
        if fs < f {
            (eta, p, f) = (s, ps, fs);
        }
    }
    for _ in 0..60 {
        let r = sub(x, p.x);
        // Gradient and Hessian of f.
        let g = [-dot(r, p.a[0]), -dot(r, p.a[1])];
        let mut h = [[0.0; 2]; 2];
        for i in 0..2 {
            for l in 0..2 {
                h[i][l] = dot(p.a[i], p.a[l]) - dot(r, p.aa[i][l]);
            }
        }
        let free: [bool; 2] = std::array::from_fn(|d| {
            !((eta[d] <= lo[d] && g[d] > 0.0) || (eta[d] >= hi[d] && g[d] < 0.0))
        });
        let gradient_step = |d: usize| -g[d] / dot(p.a[d], p.a[d]);
        let step = match free {
            [true, true] => {
                let det = h[0][0] * h[1][1] - h[0][1] * h[1][0];
                if h[0][0] > 0.0 && det > 0.0 {
                    [
                        -(h[1][1] * g[0] - h[0][1] * g[1]) / det,
                        -(h[0][0] * g[1] - h[1][0] * g[0]) / det,
                    ]
                } else {
                    [gradient_step(0), gradient_step(1)]
                }
            }
            [false, false] => break,
            _ => {
                let d = usize::from(free[1]);
                let mut s = [0.0; 2];
                s[d] = if h[d][d] > 0.0 {
                    -g[d] / h[d][d]
                } else {
                    gradient_step(d)
                };
                s
            }
        };
        // Backtracking: accept the first step length that does not increase f.
        let mut t = 1.0;
        let (next, pn, fnext) = loop {
            let cand = clamp([eta[0] + t * step[0], eta[1] + t * step[1]]);
            let pc = ev.at(e, cand);
            let fc = dot(sub(x, pc.x), sub(x, pc.x));
            if fc <= f * (1.0 + 1e-14) || t < 1e-4 {
                break (cand, pc, fc);
            }
            t *= 0.5;
        };
        if fnext > f * (1.0 + 1e-14) {
            break;
        }
        let done = (0..2).all(|d| (next[d] - eta[d]).abs() <= 1e-15 * (hi[d] - lo[d]));
        (eta, p, f) = (next, pn, fnext);
        if done {
            break;
        }
    }
    let interior = (0..2).all(|d| eta[d] > lo[d] && eta[d] < hi[d]);
    (eta, f, interior)
}

/// A starting guess for [`project`]: the previous projection of the point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guess {
    /// Master element.
    pub element: usize,
    /// Periodic image.
    pub image: [i64; 2],
    /// Parameters.
    pub eta: [f64; 2],
}

impl From<&SurfaceProjection> for Guess {
    fn from(p: &SurfaceProjection) -> Self {
        Guess {
            element: p.element,
            image: p.image,
            eta: p.eta,
        }
    }
}

/// Projects `x` onto `surface` (current configuration) and its periodic
/// images; `guess`: the previous projection of the point, if any.
pub fn project(
    surface: &MasterSurface,
    search: &MasterSearch,
    x: [f64; 3],
    guess: Option<Guess>,
) -> Result<SurfaceProjection> {
    let mut ev = SurfaceEvaluator::new(*surface);
    // (distance², element, image, η)
    let mut best: Option<(f64, usize, [i64; 2], [f64; 2])> = None;
    let consider = |ev: &mut SurfaceEvaluator,
                    best: &mut Option<(f64, usize, [i64; 2], [f64; 2])>,
                    e: usize,
                    k: [i64; 2],
                    start: Option<[f64; 2]>| {
        let xs = sub(x, search.shift(k));
        let (eta, d2) = element_minimum(ev, e, xs, start);
        if best.is_none_or(|b| d2 < b.0 * (1.0 - 1e-13)) {
            *best = Some((d2, e, k, eta));
        }
    };
    let n = surface.n_elements();
    let images = search.images(x)?;
    // The first bound: the previous projection's element, or else the
    // element whose box is nearest among those over the point.
    let seed = match guess.filter(|g| g.element < n) {
        Some(g) => Some((g.element, g.image, Some(g.eta))),
        None => {
            let mut over = Vec::new();
            let mut nearest: Option<(f64, usize, [i64; 2])> = None;
            for &k in &images {
                let xs = sub(x, search.shift(k));
                over.clear();
                search.grid.near(xs, 0.0, &mut over);
                for &e in &over {
                    let lb = search.lower_bound(e as usize, xs);
                    if nearest.is_none_or(|b| lb < b.0) {
                        nearest = Some((lb, e as usize, k));
                    }
                }
            }
            nearest.map(|(_, e, k)| (e, k, None))
        }
    };
    if let Some((e, k, start)) = seed {
        consider(&mut ev, &mut best, e, k, start);
    }
    let mut candidates: Vec<(f64, usize, [i64; 2])> = Vec::new();
    let mut near = Vec::new();
    for &k in &images {
        let xs = sub(x, search.shift(k));
        let bound = best.map_or(f64::INFINITY, |b| b.0.sqrt());
        let reach = bound * (1.0 + 1e-12) + 1e-14 * search.scale;
        let mut push = |e: usize| {
            let lb = search.lower_bound(e, xs);
            if lb <= reach {
                candidates.push((lb, e, k));
            }
        };
        if reach.is_finite() {
            near.clear();
            search.grid.near(xs, reach, &mut near);
            near.iter().for_each(|&e| push(e as usize));
        } else {
            (0..n).for_each(push);
        }
    }
    // By bound, then element and image: the repetitions of the grid's cells
    // are adjacent.
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    candidates.dedup_by(|a, b| a.1 == b.1 && a.2 == b.2);
    for (lb, e, k) in candidates {
        if let Some(b) = best
            && lb > b.0.sqrt() * (1.0 + 1e-12) + 1e-14 * search.scale
        {
            break;
        }
        if seed.is_some_and(|(se, sk, _)| se == e && sk == k) {
            continue;
        }
        consider(&mut ev, &mut best, e, k, None);
    }
    let (d2, element, image, eta) = best.ok_or_else(|| {
        Error::Geometry(format!(
            "no projection of the point ({}, {}, {}) onto the master surface",
            x[0], x[1], x[2]
        ))
    })?;
    Ok(projection_at(&mut ev, search, x, (element, image, eta), d2))
}

/// The closest point to `x` on element `e` of image `k` alone: one side of
/// a boundary between master pieces ([`crate::contact::segments::Crossing`]),
/// where the gap of either piece is wanted.
pub fn project_on_element(
    surface: &MasterSurface,
    search: &MasterSearch,
    x: [f64; 3],
    (e, k): crate::contact::segments::MasterPiece,
) -> SurfaceProjection {
    let mut ev = SurfaceEvaluator::new(*surface);
    let (eta, d2) = element_minimum(&mut ev, e, sub(x, search.shift(k)), None);
    projection_at(&mut ev, search, x, (e, k, eta), d2)
}

/// The projection of `x` at `eta` on element `element` of image `image`
/// (`d2` the squared distance): which parameters are held at a C0 edge or
/// vertex, or clamped at the end of a non-periodic master.
fn projection_at(
    ev: &mut SurfaceEvaluator,
    search: &MasterSearch,
    x: [f64; 3],
    (element, image, eta): (usize, [i64; 2], [f64; 2]),
    d2: f64,
) -> SurfaceProjection {
    let shift = search.shift(image);
    let xs = sub(x, shift);
    let p = ev.at(element, eta);
    let r = sub(xs, p.x);
    let rn = dot(r, r).sqrt();
    let (lo, hi) = ev.surface.bounds(element);
    let mut fixed = [false; 2];
    let mut clamped = false;
    for d in 0..2 {
        if eta[d] != lo[d] && eta[d] != hi[d] {
            continue;
        }
        let cosine = dot(r, p.a[d]) / (rn * dot(p.a[d], p.a[d]).sqrt());
        if rn <= 1e-13 * search.scale || cosine.abs() <= 1e-9 {
            // Orthogonal at the element boundary (a smooth or flat master).
            continue;
        }
        fixed[d] = true;
        let at_end = eta[d] == search.domain.0[d] || eta[d] == search.domain.1[d];
        if at_end && !search.seams[d] {
            clamped = true;
        }
    }
    SurfaceProjection {
        eta,
        element,
        image,
        shift,
        fixed,
        clamped,
        distance: d2.sqrt(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::testing::rng;
    use crate::geometry::{KnotVector, NurbsPatch, circular_arc};

    fn surface(p: &ThbPatch) -> MasterSurface<'_> {
        MasterSurface {
            face: p,
            points: p.control_points(),
            pieces: None,
        }
    }

    /// A wavy B-spline height map over `[0, 1]²` of degree `p` with `n × n`
    /// elements (control heights random), locally refined in one corner.
    fn wavy(p: usize, n: usize, amplitude: f64, refine: bool) -> ThbPatch {
        let kv = KnotVector::open_uniform(p, n, 0.0, 1.0);
        let m = kv.n_basis();
        let g = kv.greville();
        let mut r = rng(5);
        let mut points = Vec::new();
        for j in 0..m {
            for i in 0..m {
                points.push([g[i], g[j], amplitude * (2.0 * r() - 1.0)]);
            }
        }
        let patch = ThbPatch::from(
            &NurbsPatch::new(vec![kv.clone(), kv], points, vec![1.0; m * m]).unwrap(),
        );
        if refine {
            let mut mesh = patch.mesh().clone();
            mesh.refine_where(|_, lo, _| lo[0] < 0.3 && lo[1] < 0.5);
            patch.with_mesh(mesh)
        } else {
            patch
        }
    }

    /// Brute-force minimum distance from `x` to the master and its images
    /// `shifts`: `per × per` samples per element, then a finer sampling
    /// around the best few samples.
    fn brute_force(s: &MasterSurface, x: [f64; 3], shifts: &[[f64; 2]], per: usize) -> f64 {
        let mut ev = SurfaceEvaluator::new(*s);
        let mut dist = |e: usize, eta: [f64; 2], sh: [f64; 2]| {
            let q = ev.at(e, eta).x;
            let r = sub(x, [q[0] + sh[0], q[1] + sh[1], q[2]]);
            dot(r, r).sqrt()
        };
        // (distance, element, shift, η)
        let mut coarse: Vec<(f64, usize, [f64; 2], [f64; 2])> = Vec::new();
        for e in 0..s.n_elements() {
            let (lo, hi) = s.bounds(e);
            for &sh in shifts {
                for i in 0..=per {
                    for j in 0..=per {
                        let eta = [
                            lo[0] + (hi[0] - lo[0]) * i as f64 / per as f64,
                            lo[1] + (hi[1] - lo[1]) * j as f64 / per as f64,
                        ];
                        coarse.push((dist(e, eta, sh), e, sh, eta));
                    }
                }
            }
        }
        coarse.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best = coarse[0].0;
        for &(_, e, sh, eta) in coarse.iter().take(6) {
            let (lo, hi) = s.bounds(e);
            let h = [(hi[0] - lo[0]) / per as f64, (hi[1] - lo[1]) / per as f64];
            for i in 0..=60 {
                for j in 0..=60 {
                    let t = [i as f64 / 30.0 - 1.0, j as f64 / 30.0 - 1.0];
                    let q = [
                        (eta[0] + t[0] * h[0]).clamp(lo[0], hi[0]),
                        (eta[1] + t[1] * h[1]).clamp(lo[1], hi[1]),
                    ];
                    best = best.min(dist(e, q, sh));
                }
            }
        }
        best
    }

    /// The search's bounds from the functions' control points and from the
    /// pieces' Bézier boxes (tighter) both find the closest point.
    fn check_against_brute_force(patch: &ThbPatch, per: usize, tol: f64, cases: usize) {
        let pieces = FacePieces::new(patch, patch.control_points());
        let plain = surface(patch);
        let fast = MasterSurface {
            pieces: Some(&pieces),
            ..plain
        };
        for s in [plain, fast] {
            check_surface_against_brute_force(s, per, tol, cases);
        }
    }

    fn check_surface_against_brute_force(s: MasterSurface, per: usize, tol: f64, cases: usize) {
        let mut r = rng(11);
        for periods in [[None, None], [Some(1.0), Some(1.0)]] {
            let search = MasterSearch::new(&s, periods);
            let mut previous: Option<SurfaceProjection> = None;
            for _ in 0..cases {
                let x = [-0.4 + 1.8 * r(), -0.4 + 1.8 * r(), -0.5 + 1.0 * r()];
                // Half of the points with the previous projection as a (poor) guess.
                let guess = previous.filter(|_| r() < 0.5).as_ref().map(Guess::from);
                let pr = project(&s, &search, x, guess).unwrap();
                let shifts: Vec<[f64; 2]> = if periods[0].is_some() {
                    (-1..=1)
                        .flat_map(|i| (-1..=1).map(move |j| [i as f64, j as f64]))
                        .collect()
                } else {
                    vec![[0.0, 0.0]]
                };
                // The projection is a point of the surface: never closer than
                // the true minimum, so only the upper side is a check; the
                // lower side checks the brute force.
                let brute = brute_force(&s, x, &shifts, per);
                assert!(
                    pr.distance <= brute + 1e-12 && pr.distance >= brute - tol,
                    "{x:?} {periods:?}: {} vs {brute} ({pr:?})",
                    pr.distance
                );
                let y = SurfaceEvaluator::new(s).at(pr.element, pr.eta).x;
                let d = dot(sub(sub(x, pr.shift), y), sub(sub(x, pr.shift), y)).sqrt();
                assert!((d - pr.distance).abs() < 1e-12);
                previous = Some(pr);
            }
        }
    }

    /// The polynomial pieces are the surface: position, tangents and second
    /// derivatives as the THB basis gives them, on refined (truncated)
    /// elements of degrees 1–3, and the projections onto them are the same;
    /// rational elements are left to the basis.
    #[test]
    fn polynomial_pieces_evaluate_the_surface() {
        let mut r = rng(17);
        for (p, n) in [(1, 5), (2, 4), (3, 3)] {
            let patch = wavy(p, n, 0.08, true);
            let moved: Vec<[f64; 3]> = patch
                .control_points()
                .iter()
                .map(|x| [x[0] + 0.01 * r(), x[1], x[2] + 0.02 * r()])
                .collect();
            let pieces = FacePieces::new(&patch, &moved);
            assert!(pieces.coefficients.iter().all(|v| v.is_some()));
            let plain = MasterSurface {
                face: &patch,
                points: &moved,
                pieces: None,
            };
            let fast = MasterSurface {
                pieces: Some(&pieces),
                ..plain
            };
            let (mut a, mut b) = (SurfaceEvaluator::new(plain), SurfaceEvaluator::new(fast));
            for e in 0..patch.n_elements() {
                let (lo, hi) = plain.bounds(e);
                for _ in 0..5 {
                    let eta = [0, 1].map(|d| lo[d] + r() * (hi[d] - lo[d]));
                    let (x, y) = (a.at(e, eta), b.at(e, eta));
                    let scale = [x.a, x.aa[0], x.aa[1]]
                        .iter()
                        .flatten()
                        .flatten()
                        .fold(1.0f64, |m, v| m.max(v.abs()));
                    let all = |s: &SurfacePoint| -> Vec<f64> {
                        let mut v = s.x.to_vec();
                        v.extend(s.a.iter().flatten());
                        v.extend(s.aa.iter().flatten().flatten());
                        v
                    };
                    for (u, v) in all(&x).iter().zip(all(&y)) {
                        assert!(
                            (u - v).abs() < 1e-12 * scale,
                            "p = {p}, element {e}: {u} vs {v}"
                        );
                    }
                }
            }
            let (sa, sb) = (
                MasterSearch::new(&plain, [None, None]),
                MasterSearch::new(&fast, [None, None]),
            );
            for _ in 0..20 {
                let x = [r(), r(), 0.3 * r() - 0.15];
                let (u, v) = (
                    project(&plain, &sa, x, None).unwrap(),
                    project(&fast, &sb, x, None).unwrap(),
                );
                assert!((u.distance - v.distance).abs() < 1e-12, "{u:?} {v:?}");
            }
        }
        let sphere = sphere_patch([0.0; 3], 1.0, [0.1, 0.7], [0.0, 1.2]);
        let pieces = FacePieces::new(&sphere, sphere.control_points());
        assert!(pieces.coefficients.iter().all(|v| v.is_none()));
    }

    /// The Bézier box of a polynomial element holds its piece and lies in
    /// the box of its functions' control points; on degree 1 it is the box
    /// of the element's corners.
    #[test]
    fn bezier_boxes_hold_their_elements_within_the_control_points_boxes() {
        let mut r = rng(23);
        for (p, n) in [(1, 5), (2, 4), (3, 3)] {
            let patch = wavy(p, n, 0.08, true);
            let pieces = FacePieces::new(&patch, patch.control_points());
            let s = MasterSurface {
                pieces: Some(&pieces),
                ..surface(&patch)
            };
            let plain = MasterSearch::new(&surface(&patch), [None, None]);
            let mut ev = SurfaceEvaluator::new(s);
            let mut tighter = 0.0;
            for e in 0..patch.n_elements() {
                let (lo, hi) = pieces.bezier_box(e).unwrap();
                let (clo, chi) = plain.boxes[e];
                let (plo, phi) = s.bounds(e);
                let mut corners = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                for k in 0..4 {
                    let eta = [
                        if k % 2 == 0 { plo[0] } else { phi[0] },
                        if k / 2 == 0 { plo[1] } else { phi[1] },
                    ];
                    let x = ev.at(e, eta).x;
                    for c in 0..3 {
                        corners.0[c] = corners.0[c].min(x[c]);
                        corners.1[c] = corners.1[c].max(x[c]);
                    }
                }
                for c in 0..3 {
                    assert!(
                        lo[c] >= clo[c] - 1e-14 && hi[c] <= chi[c] + 1e-14,
                        "p = {p}, {e}"
                    );
                    if p == 1 {
                        assert!((lo[c] - corners.0[c]).abs() < 1e-14, "p = 1, {e}");
                        assert!((hi[c] - corners.1[c]).abs() < 1e-14, "p = 1, {e}");
                    }
                }
                tighter +=
                    (hi[0] - lo[0]) * (hi[1] - lo[1]) / ((chi[0] - clo[0]) * (chi[1] - clo[1]));
                for _ in 0..50 {
                    let eta = [0, 1].map(|d| plo[d] + r() * (phi[d] - plo[d]));
                    let x = ev.at(e, eta).x;
                    for c in 0..3 {
                        assert!(
                            x[c] >= lo[c] - 1e-14 && x[c] <= hi[c] + 1e-14,
                            "p = {p}, {e}: {x:?}"
                        );
                    }
                }
            }
            // At p ≥ 2 the control points reach over the neighbours.
            if p >= 2 {
                assert!(
                    tighter / (patch.n_elements() as f64) < 0.5,
                    "p = {p}: {tighter}"
                );
            }
        }
    }

    #[test]
    fn projection_distance_is_the_minimum_over_a_smooth_refined_surface() {
        check_against_brute_force(&wavy(2, 4, 0.06, true), 8, 3e-4, 40);
        check_against_brute_force(&wavy(3, 3, 0.1, false), 8, 3e-4, 40);
    }

    #[test]
    fn a_search_far_past_the_periodic_sample_is_an_error_not_an_abort() {
        // A unit-periodic master: a box within a few periods finds its
        // images; one a million periods wide (a diverged iterate, which
        // once asked for 4.5 TB) or not finite is refused with a reason.
        let patch = wavy(2, 4, 0.1, false);
        let s = surface(&patch);
        let search = MasterSearch::new(&s, [Some(1.0), Some(1.0)]);
        let near = search
            .near_box([0.2, 0.2, 0.3], [0.4, 0.4, 0.3], 1.5)
            .unwrap();
        let images: std::collections::BTreeSet<[i64; 2]> = near.iter().map(|n| n.1).collect();
        assert!(
            images.contains(&[0, 0]) && images.contains(&[-1, 1]),
            "{images:?}"
        );
        for (lo, hi, reach) in [
            ([0.2, 0.2, 0.3], [0.4, 0.4, 0.3], 1e6),
            ([-1e9, 0.2, 0.3], [0.4, 0.4, 0.3], 0.1),
            ([0.2, 0.2, 0.3], [f64::INFINITY, 0.4, 0.3], 0.1),
            ([0.2, f64::NAN, 0.3], [0.4, 0.4, 0.3], 0.1),
        ] {
            let e = search.near_box(lo, hi, reach).unwrap_err().to_string();
            assert!(
                e.contains("periodic images") && e.contains("diverged"),
                "{e}"
            );
        }
        let e = project(&s, &search, [0.3, f64::INFINITY, 0.2], None).unwrap_err();
        assert!(e.to_string().contains("diverged"), "{e}");
    }

    #[test]
    fn projection_distance_is_the_minimum_over_a_faceted_surface() {
        // Degree 1: C0 edges and vertices everywhere (the minimum is often on them).
        check_against_brute_force(&wavy(1, 4, 0.2, false), 8, 3e-4, 60);
    }

    /// The surface of revolution of the meridian arc `[φ0, φ1]` (latitude) of
    /// the sphere of radius `radius` about `c`, longitudes `[λ0, λ1]`: an exact
    /// rational biquadratic sphere patch (Piegl & Tiller A8.1).
    fn sphere_patch(c: [f64; 3], radius: f64, lat: [f64; 2], lon: [f64; 2]) -> ThbPatch {
        let meridian = circular_arc([0.0; 3], radius, lat[0], lat[1]);
        let circle = circular_arc([0.0; 3], 1.0, lon[0], lon[1]);
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for (m, wm) in meridian.control_points().iter().zip(meridian.weights()) {
            for (q, wq) in circle.control_points().iter().zip(circle.weights()) {
                // Meridian point (ρ, z) = (m_x, m_y).
                points.push([c[0] + m[0] * q[0], c[1] + m[0] * q[1], c[2] + m[1]]);
                weights.push(wm * wq);
            }
        }
        ThbPatch::from(
            &NurbsPatch::new(
                vec![circle.knots()[0].clone(), meridian.knots()[0].clone()],
                points,
                weights,
            )
            .unwrap(),
        )
    }

    #[test]
    fn projects_onto_a_sphere_and_a_cylinder_exactly() {
        let c = [0.1, -0.2, 0.3];
        let sphere = sphere_patch(c, 2.0, [0.2, 1.2], [-0.4, 1.1]);
        let s = surface(&sphere);
        let search = MasterSearch::new(&s, [None, None]);
        let mut r = rng(3);
        for _ in 0..50 {
            // Directions inside the patch, inside and outside the sphere.
            let (lat, lon) = (0.25 + 0.9 * r(), -0.35 + 1.4 * r());
            let rad = 2.0 * (0.3 + 1.4 * r());
            let dir = [lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()];
            let x = [
                c[0] + rad * dir[0],
                c[1] + rad * dir[1],
                c[2] + rad * dir[2],
            ];
            let pr = project(&s, &search, x, None).unwrap();
            assert!((pr.distance - (rad - 2.0).abs()).abs() < 1e-12, "{pr:?}");
            let y = s.point(pr.eta);
            for k in 0..3 {
                assert!((y[k] - (c[k] + 2.0 * dir[k])).abs() < 1e-12);
            }
            assert!(!pr.clamped && pr.fixed == [false, false]);
        }
        // A cylinder of radius 1 about the y axis: the arc (x, z) extruded in y.
        let arc = circular_arc([0.0; 3], 1.0, 0.3, 2.5);
        let line = KnotVector::open_uniform(1, 2, 0.0, 1.0);
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for y in [-1.0, 0.0, 1.0] {
            for (q, w) in arc.control_points().iter().zip(arc.weights()) {
                points.push([q[0], y, q[1]]);
                weights.push(*w);
            }
        }
        let cyl = ThbPatch::from(
            &NurbsPatch::new(vec![arc.knots()[0].clone(), line], points, weights).unwrap(),
        );
        let s = surface(&cyl);
        let search = MasterSearch::new(&s, [None, None]);
        for _ in 0..50 {
            let (t, y, rad) = (0.4 + 2.0 * r(), -0.9 + 1.8 * r(), 0.2 + 2.0 * r());
            let x = [rad * t.cos(), y, rad * t.sin()];
            let pr = project(&s, &search, x, None).unwrap();
            assert!((pr.distance - (rad - 1.0).abs()).abs() < 1e-12, "{pr:?}");
            let q = s.point(pr.eta);
            assert!((q[0] - t.cos()).abs() < 1e-12 && (q[1] - y).abs() < 1e-12);
        }
    }

    /// A degree-1 tent over `[0, 2]²`: four bilinear pieces rising from a flat
    /// rim (z = 0) to the apex `(1, 1, 1)`, with kinks along x = 1 and y = 1.
    fn tent() -> ThbPatch {
        let kv = KnotVector::new(1, vec![0.0, 0.0, 0.5, 1.0, 1.0]).unwrap();
        let mut points = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let z = if i == 1 && j == 1 { 1.0 } else { 0.0 };
                points.push([i as f64, j as f64, z]);
            }
        }
        ThbPatch::from(&NurbsPatch::new(vec![kv.clone(), kv], points, vec![1.0; 9]).unwrap())
    }

    #[test]
    fn points_in_normal_cones_project_onto_edges_and_vertices() {
        let p = tent();
        let s = surface(&p);
        let search = MasterSearch::new(&s, [None, None]);
        // Above the apex: the vertex.
        let v = project(&s, &search, [1.0, 1.0, 2.0], None).unwrap();
        assert_eq!(v.fixed, [true, true]);
        assert!(!v.clamped && (v.distance - 1.0).abs() < 1e-14);
        assert_eq!(v.eta, [0.5, 0.5]);
        // Above the element edge x = 1 (between elements 0 and 1), y = 0.25:
        // the bilinear pieces meet at a kink there.
        let q = project(&s, &search, [1.0, 0.25, 1.0], None).unwrap();
        assert!(!q.clamped);
        assert_eq!(q.fixed.iter().filter(|&&f| f).count(), 1, "{q:?}");
        let y = s.point(q.eta);
        assert!((y[0] - 1.0).abs() < 1e-14, "{y:?}");
        // Edge: the vector to the point is orthogonal to the edge's tangent.
        let edge_tangent = [0.0, 1.0, 1.0];
        let r = sub([1.0, 0.25, 1.0], y);
        assert!(dot(r, edge_tangent).abs() < 1e-12, "{r:?}");
        // Beyond the rim of a non-periodic master: clamped; periodic: not.
        let c = project(&s, &search, [2.4, 1.3, 0.2], None).unwrap();
        assert!(c.clamped && c.fixed[0] && !c.fixed[1], "{c:?}");
        let periodic = MasterSearch::new(&s, [Some(2.0), Some(2.0)]);
        let w = project(&s, &periodic, [2.4, 1.3, 0.2], None).unwrap();
        assert!(!w.clamped && w.image == [1, 0], "{w:?}");
        assert!(w.distance < c.distance);
    }
}
