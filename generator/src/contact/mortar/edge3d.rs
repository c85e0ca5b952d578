//! The edge of the 3D contact area fitted to the near-edge asymptotics of
//! elastic contact: the counterpart on slave surfaces of
//! `ContactInterface::locate_edge` (2D).
//!
//! The indicator `v = λN − εN g` interpolated from the slave control points
//! crosses zero where its augmentation puts it: a fraction of an element
//! inside the contact edge at the default `mechanical_penalty` (in 2D a
//! quarter to half an element; the 3D Hertz radius from the crossings is
//! 6.6 % short on its default mesh). Outside the edge of a frictionless
//! elastic contact (Hertz, Westergaard, any smooth spot) the gap is
//! `(4A/3E*) t^(3/2)` at a distance `t`. The edge is taken as the crossing
//! curve `v = 0` moved along its normal by a shift `δ` per slave element
//! that the curve passes through:
//!
//! - the crossing curve is traced by marching squares on [`CURVE_CELLS`]²
//!   sub-cells of each such element, as segments in the mean plane (x, y)
//!   of the configuration;
//! - `φ(x)`, the signed distance (positive in contact, the sign of `v`) to
//!   the nearest segment of the elements that share a node with the point's
//!   element (across the periodic seams), measures the distance to the
//!   crossing curve whatever its shape;
//! - `δ` and an amplitude are fitted by least squares to the gaps `g` of
//!   the contact integration points near the edge: the points in the
//!   supports of the element's nodes out of contact whose nearest segment
//!   is the element's own (one profile along the normal) and which lie
//!   `[0.25, 2]` element sizes outside the crossing (where the gap is
//!   clearly open; sizes along the edge normal, `ElementSides::along`),
//!   against `G(t)`, `t = −(φ + δ)` where positive, `G` the gap's shape
//!   ([`gap_profile`]: `t^(3/2)` at a straight edge, Hertz's gap outside a
//!   spot whose radius is fitted to the curve's segments, the penny-shaped
//!   gap inside a closing gap). Only open gaps are fitted: in
//!   3D the lumped pressures carry a checkerboard mode (`docs/validation.md`,
//!   3D Hertz), and inside the edge the point gaps oscillate about zero with
//!   it (the lumped constraint (4.8) holds on average over a support).
//!   Point gaps, not the weighted nodal gaps `g^J` (4.8): a support spans
//!   three elements along the edge, over which the gap at a given distance
//!   varies (a spot of the egg box is not round), and the nodes at the edge
//!   average the inside oscillation in; fitted to `g^J`, the egg box's edges
//!   stayed near the crossings (shifts −0.2 to +0.14 elements on one level)
//!   and with two levels its area was 19.5 % short of the boundary
//!   elements' where the gaps outside matched them (stop 23, `docs/3d.md`);
//! - straight crossing curves (radius above [`STRAIGHT_RADIUS`] element
//!   sizes) are fitted instead as in 2D (`ContactInterface::locate_edge`),
//!   to the nodal pressures inside and weighted gaps outside
//!   ([`ContactInterface::fit_straight_edge`]): on ridges the point gaps
//!   just outside put the edge 0.07–0.12 elements inside the crossing,
//!   while the converged (2D) edge lies outside it (stop 29,
//!   `docs/validation.md`, plane strain);
//! - element sizes are measured along the edge normal
//!   (`ElementSides::along`);
//! - the fit applies only where the indicator keeps its sign
//!   [`EDGE_MIN_RANGE`] elements along the normal on both sides (spots and
//!   gaps at least that wide, as in 2D); other elements keep the crossing.
//!
//! A point is in contact where `φ + δ > 0`, `δ` that of the element of its
//! nearest segment (and where `v > 0` far from any segment).

use std::collections::BTreeSet;

use rayon::prelude::*;

use super::{ContactInterface, EDGE_MIN_RANGE};
use crate::basis::{RationalBasis, TensorBasis};
use crate::quadrature::GaussLegendre;

/// A crossing curve of larger radius (in element sizes) is straight.
const STRAIGHT_RADIUS: f64 = 20.0;

/// Sub-cells per element and direction on which the crossing curve is traced.
const CURVE_CELLS: usize = 8;

/// The band of distances outside the crossing curve (element sizes) whose
/// point gaps the edge is fitted to.
const FIT_BAND: (f64, f64) = (0.25, 2.0);

/// The interpolated indicator at a point of the slave surface (3D).
#[derive(Clone, Copy, Debug)]
struct IndicatorPoint {
    /// `v`, interpolated from the nodal values.
    value: f64,
    /// `∇v` in the mean plane (x, y) of the configuration.
    grad: [f64; 2],
    /// The point's position in the mean plane.
    x: [f64; 2],
    /// `∂x/∂ξ` (mean plane).
    jac: [[f64; 2]; 2],
}

impl IndicatorPoint {
    /// `det ∂x/∂ξ`.
    fn det(&self) -> f64 {
        self.jac[0][0] * self.jac[1][1] - self.jac[0][1] * self.jac[1][0]
    }

    /// The parametric offset of a mean-plane offset `dx` (linearized).
    fn param_offset(&self, dx: [f64; 2]) -> [f64; 2] {
        let (j, d) = (&self.jac, self.det());
        [
            (j[1][1] * dx[0] - j[0][1] * dx[1]) / d,
            (-j[1][0] * dx[0] + j[0][0] * dx[1]) / d,
        ]
    }
}

/// A piece of the crossing curve in the mean plane, traced in `element`.
#[derive(Clone, Copy, Debug)]
struct Segment {
    a: [f64; 2],
    b: [f64; 2],
    element: usize,
}

/// A slave element's two sides `a = ∂x/∂ξ₁ Δξ₁`, `b = ∂x/∂ξ₂ Δξ₂` in the
/// mean plane (at its centre).
#[derive(Clone, Copy, Debug)]
struct ElementSides([[f64; 2]; 2]);

impl ElementSides {
    /// The element's size along the unit direction `n`: `1/|A⁻¹ n|`,
    /// `A = [a b]` (the mesh metric `A⁻ᵀ A⁻¹`), the side length for a
    /// rectangle's axes and the same in every direction for a square. The
    /// edge's asymptotics and fit band are measured along the edge normal,
    /// which on anisotropic elements (ridges on 2 elements along y) differs
    /// from `√(area)` by the aspect ratio.
    fn along(&self, n: [f64; 2]) -> f64 {
        let [a, b] = self.0;
        let det = a[0] * b[1] - b[0] * a[1];
        let inv_n = [
            (b[1] * n[0] - b[0] * n[1]) / det,
            (-a[1] * n[0] + a[0] * n[1]) / det,
        ];
        1.0 / inv_n[0].hypot(inv_n[1])
    }
}

/// A point of the crossing curve with its normal, about a slave element.
struct EdgeFrame {
    /// The element's centre (parameters).
    centre: [f64; 2],
    /// The indicator at the centre.
    at: IndicatorPoint,
    /// The element's sides (mean plane).
    sides: ElementSides,
    /// The midpoint of the element's segment nearest its centre.
    mid: [f64; 2],
    /// The unit normal of that segment, into contact.
    normal: [f64; 2],
}

impl EdgeFrame {
    /// The element's size along the normal.
    fn size(&self) -> f64 {
        self.sides.along(self.normal)
    }

    /// The parameters of the point at `t` along the normal from `mid`
    /// (the mapping linearized at the element's centre).
    fn param(&self, level: &ContactLevel3d, t: f64) -> [f64; 2] {
        let to = level.offset([0, 1].map(|d| self.mid[d] + t * self.normal[d]), self.at.x);
        let dxi = self.at.param_offset(to);
        [self.centre[0] + dxi[0], self.centre[1] + dxi[1]]
    }

    /// The signed distance of `x` from the straight crossing line through
    /// `mid` (positive in contact).
    fn distance(&self, level: &ContactLevel3d, x: [f64; 2]) -> f64 {
        let o = level.offset(x, self.mid);
        o[0] * self.normal[0] + o[1] * self.normal[1]
    }
}

/// Gauss points per direction and element of the nodal edge fit's supports.
const FIT_POINTS: usize = 12;

/// Samples per element size when measuring the ranges in and out of contact.
const RANGE_STEPS: usize = 4;

/// The farthest a range is followed (element sizes).
const RANGE_SIZES: f64 = 256.0;

/// The contact area's level set on the slave surface (3D; module docs).
#[derive(Clone, Debug)]
pub(crate) struct ContactLevel3d {
    /// Nodal indicator values.
    ind: Vec<f64>,
    /// The crossing curve's segments.
    segments: Vec<Segment>,
    /// Per slave element: its segments.
    by_element: Vec<Vec<usize>>,
    /// Per slave element: the elements with segments that share a node with it.
    near: Vec<Vec<usize>>,
    /// Per slave element: the edge's fitted shift `δ` (scaled length),
    /// `None` where the crossing is kept.
    shift: Vec<Option<f64>>,
    /// The cell's period in x and y (scaled), if periodic.
    period: Option<f64>,
}

/// What the point-gap fit reads: the slave elements of each slave node (its
/// support), the contact integration points of each slave element, the
/// nodal indicator and the configuration.
struct Supports<'a> {
    of_function: &'a [Vec<usize>],
    of_element: &'a [Vec<usize>],
    /// The slave elements in the support of each node (its copies' too).
    of_node: &'a [Vec<usize>],
    ind: &'a [f64],
    state: &'a [f64],
}

/// The shape of the gap at a distance `t` outside the edge (any scale: the
/// amplitude is fitted): `t^(3/2)` at a straight edge; outside a spot whose
/// crossing curve has the radius `ρ > 0`, moved out by `δ` to `a = ρ + δ`,
/// Hertz's gap `a^(3/2) H(1 + t/a)`, `H(s) = s²/2 − 1 + ((2 − s²) asin(1/s)
/// + √(s² − 1))/π` (Johnson 3.42, for both bodies; `(4√2/3π) (t/a)^(3/2)`
/// near the edge); inside a gap of radius `b = −ρ − δ`, the penny-shaped gap
/// `(t (1 − t/2b))^(3/2)` (exact for a gap closing under uniform pressure).
fn gap_profile(t: f64, radius: Option<f64>, delta: f64) -> f64 {
    match radius {
        Some(r) if r > 0.0 && r + delta > 0.0 => {
            let a = r + delta;
            let s = 1.0 + t / a;
            let h = 0.5 * s * s - 1.0
                + ((2.0 - s * s) * (1.0 / s).asin() + (s * s - 1.0).sqrt()) / std::f64::consts::PI;
            a.powf(1.5) * h.max(0.0) * 3.0 * std::f64::consts::PI / (4.0 * std::f64::consts::SQRT_2)
        }
        Some(r) if r < 0.0 => {
            let b = (-r - delta).max(f64::MIN_POSITIVE);
            (t * (1.0 - t / (2.0 * b)).max(0.0)).powf(1.5)
        }
        _ => t.powf(1.5),
    }
}

/// Whether the nodes `functions` have indicators of both signs.
fn crosses(functions: &[usize], ind: &[f64]) -> bool {
    functions.iter().any(|&c| ind[c] > 0.0) && functions.iter().any(|&c| ind[c] <= 0.0)
}

impl ContactLevel3d {
    /// Whether every element the crossing curve passes through has a fitted edge.
    pub(crate) fn edges_fitted(&self) -> bool {
        self.by_element
            .iter()
            .zip(&self.shift)
            .all(|(s, d)| s.is_empty() || d.is_some())
    }

    /// `x − y` across the periodic seams (the nearest image).
    fn offset(&self, x: [f64; 2], y: [f64; 2]) -> [f64; 2] {
        let mut d = [x[0] - y[0], x[1] - y[1]];
        if let Some(w) = self.period {
            d = d.map(|t| t - w * (t / w).round());
        }
        d
    }

    /// The distance from `x` (in slave element `e`) to the nearest segment
    /// near `e`, and that segment's element.
    fn nearest(&self, e: usize, x: [f64; 2]) -> Option<(f64, usize)> {
        self.near[e]
            .iter()
            .flat_map(|&k| &self.by_element[k])
            .map(|&s| {
                let seg = &self.segments[s];
                let ab = self.offset(seg.b, seg.a);
                let ax = self.offset(x, seg.a);
                let ll = ab[0] * ab[0] + ab[1] * ab[1];
                let t = if ll > 0.0 {
                    ((ax[0] * ab[0] + ax[1] * ab[1]) / ll).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = (ax[0] - t * ab[0]).hypot(ax[1] - t * ab[1]);
                (d, seg.element)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// The signed radius of the crossing curve about element `e`: a circle
    /// fitted (algebraically, Kåsa) to the ends of the segments of the
    /// elements near it; positive where its centre lies in contact (a
    /// spot), negative for a gap; `None` for a straight curve (radius above
    /// [`STRAIGHT_RADIUS`] element sizes `h`) or too few points.
    fn radius(&self, e: usize, h: f64, inward: [f64; 2]) -> Option<f64> {
        let first = self.by_element[e].first().map(|&s| self.segments[s].a)?;
        let pts: Vec<[f64; 2]> = self.near[e]
            .iter()
            .flat_map(|&k| &self.by_element[k])
            .flat_map(|&s| [self.segments[s].a, self.segments[s].b])
            .map(|x| self.offset(x, first))
            .collect();
        if pts.len() < 6 {
            return None;
        }
        // Normal equations of x² + y² + D x + E y + F = 0.
        let mut m = nalgebra::Matrix3::<f64>::zeros();
        let mut r = nalgebra::Vector3::<f64>::zeros();
        for x in &pts {
            let row = nalgebra::Vector3::new(x[0], x[1], 1.0);
            m += row * row.transpose();
            r -= row * (x[0] * x[0] + x[1] * x[1]);
        }
        let sol = m.lu().solve(&r)?;
        let centre = [-0.5 * sol[0], -0.5 * sol[1]];
        let rr = centre[0] * centre[0] + centre[1] * centre[1] - sol[2];
        if rr.is_nan() || rr <= 0.0 || rr.sqrt() > STRAIGHT_RADIUS * h {
            return None;
        }
        // In contact: the centre lies towards increasing indicator.
        let towards = (centre[0] * inward[0] + centre[1] * inward[1]).signum();
        Some(towards * rr.sqrt())
    }

    /// `φ`: the signed distance from a point `p` of element `e` to the
    /// crossing curve (positive in contact), `None` far from it.
    fn distance(&self, e: usize, p: &IndicatorPoint) -> Option<(f64, usize)> {
        self.nearest(e, p.x)
            .map(|(d, k)| (if p.value > 0.0 { d } else { -d }, k))
    }

    /// The level at a point `p` of element `e`: positive in contact (its
    /// sign only is meaningful).
    fn level(&self, e: usize, p: &IndicatorPoint) -> f64 {
        match self.distance(e, p) {
            Some((phi, k)) => match self.shift[k] {
                Some(delta) => phi + delta,
                None => p.value,
            },
            None => p.value,
        }
    }

    /// The area in contact projected on the mean plane: the midpoint rule
    /// on `n × n` sub-cells of every slave element, the cells the edge cuts
    /// by their part in contact ([`ContactLevel3d::visit_cells`]).
    pub(crate) fn area(&self, iface: &ContactInterface, state: &[f64], n: usize) -> f64 {
        // The elements' cells in parallel, summed in the serial order.
        let terms: Vec<Vec<f64>> = (0..iface.slave_face.elements().len())
            .into_par_iter()
            .map_init(
                || {
                    (
                        Probe::new(iface, &self.ind, state),
                        vec![0.0; (n + 1) * (n + 1)],
                    )
                },
                |(probe, corners), e| {
                    let mut terms = Vec::new();
                    self.visit_element_cells(probe, corners, e, n, &mut |_, _, fraction, cell| {
                        terms.push(fraction * cell)
                    });
                    terms
                },
            )
            .collect();
        let mut area = 0.0;
        for t in terms.iter().flatten() {
            area += t;
        }
        area
    }

    /// Visits the `n × n` sub-cells of every slave element that are in
    /// contact, wholly or in part, with the element, the centroid
    /// (parameters) of the cell's part in contact, that part's fraction of
    /// the cell, and the cell's area projected on the mean plane (midpoint
    /// rule). Near the crossing curve the level is also taken at the cells'
    /// corners; in a cell whose corners differ in sign the part in contact
    /// is that of the level interpolated bilinearly from its corners
    /// (sampled on [`CUT_SAMPLES`]² points): the level is a signed distance
    /// there, nearly linear across a cell, so the edge's position is
    /// resolved to a fraction of a cell rather than to a whole one.
    pub(crate) fn visit_cells(
        &self,
        iface: &ContactInterface,
        state: &[f64],
        n: usize,
        mut visit: impl FnMut(usize, [f64; 2], f64, f64),
    ) {
        let mut probe = Probe::new(iface, &self.ind, state);
        let mut corners = vec![0.0; (n + 1) * (n + 1)];
        for e in 0..iface.slave_face.elements().len() {
            self.visit_element_cells(&mut probe, &mut corners, e, n, &mut visit);
        }
    }

    /// [`ContactLevel3d::visit_cells`] in slave element `e` (`corners`:
    /// scratch of `(n + 1)²` values).
    fn visit_element_cells(
        &self,
        probe: &mut Probe,
        corners: &mut [f64],
        e: usize,
        n: usize,
        visit: &mut impl FnMut(usize, [f64; 2], f64, f64),
    ) {
        let el = &probe.iface.slave_face.elements()[e];
        let h = [0, 1].map(|d| (el.upper[d] - el.lower[d]) / n as f64);
        let near_edge = !self.near[e].is_empty();
        if near_edge {
            for (k, c) in corners.iter_mut().enumerate() {
                let xi = [
                    el.lower[0] + h[0] * (k % (n + 1)) as f64,
                    el.lower[1] + h[1] * (k / (n + 1)) as f64,
                ];
                *c = self.level(e, &probe.at(e, xi));
            }
        }
        for k in 0..n * n {
            let (i, j) = (k % n, k / n);
            let xi = [
                el.lower[0] + h[0] * (i as f64 + 0.5),
                el.lower[1] + h[1] * (j as f64 + 0.5),
            ];
            let p = probe.at(e, xi);
            let cell = p.det().abs() * h[0] * h[1];
            let centre_in = self.level(e, &p) > 0.0;
            let c = near_edge.then(|| {
                let at = |a: usize, b: usize| corners[(j + b) * (n + 1) + i + a];
                [at(0, 0), at(1, 0), at(0, 1), at(1, 1)]
            });
            match c {
                Some(c) if c.iter().any(|&v| v > 0.0) && c.iter().any(|&v| v <= 0.0) => {
                    if let Some((fraction, at)) = bilinear_part_in_contact(c, CUT_SAMPLES) {
                        let centroid =
                            [0, 1].map(|d| el.lower[d] + h[d] * ([i, j][d] as f64 + at[d]));
                        visit(e, centroid, fraction, cell);
                    }
                }
                _ if centre_in => visit(e, xi, 1.0, cell),
                _ => {}
            }
        }
    }
}

/// Samples per direction of the bilinear level in a cell the edge cuts.
const CUT_SAMPLES: usize = 16;

/// The part in contact (level `> 0`) of the unit square for the level
/// interpolated bilinearly from its corners `c` (`(0,0)`, `(1,0)`, `(0,1)`,
/// `(1,1)`): its area fraction and centroid by the midpoint rule on `m × m`
/// samples (exact to `1/(2m)` of the side for a straight edge); `None` if
/// no sample is in contact.
fn bilinear_part_in_contact(c: [f64; 4], m: usize) -> Option<(f64, [f64; 2])> {
    let (mut count, mut sum) = (0usize, [0.0; 2]);
    for q in 0..m * m {
        let s = ((q % m) as f64 + 0.5) / m as f64;
        let t = ((q / m) as f64 + 0.5) / m as f64;
        let v = (1.0 - t) * ((1.0 - s) * c[0] + s * c[1]) + t * ((1.0 - s) * c[2] + s * c[3]);
        if v > 0.0 {
            count += 1;
            sum[0] += s;
            sum[1] += t;
        }
    }
    (count > 0).then(|| {
        let n = count as f64;
        (n / (m * m) as f64, [sum[0] / n, sum[1] / n])
    })
}

/// The points of a nodal edge fit's supports, flat: each point's signed
/// distance `φ` to the edge and the nodes with a basis value there (their
/// places in the fit's node list, and weight × value, in that order), split
/// by their indicator's sign: the model's value inside the edge is the one
/// of the nodes in contact (`entries[start..split]`), outside that of the
/// others (`entries[split..end]`). The misfit reads them all at each of
/// its 138 evaluations per fit.
#[derive(Default)]
struct FitPoints {
    phi: Vec<f64>,
    /// `(start, split, end)` into `entries`, per point.
    ranges: Vec<(u32, u32, u32)>,
    entries: Vec<(u32, f64)>,
}

/// Evaluates the indicator on the slave face (scratch space held).
struct Probe<'a> {
    iface: &'a ContactInterface,
    ind: &'a [f64],
    state: &'a [f64],
    scratch: TensorBasis,
    basis: RationalBasis,
}

impl<'a> Probe<'a> {
    fn new(iface: &'a ContactInterface, ind: &'a [f64], state: &'a [f64]) -> Self {
        Probe {
            iface,
            ind,
            state,
            scratch: TensorBasis::default(),
            basis: RationalBasis::default(),
        }
    }

    /// The indicator at `xi` of slave element `e`; the basis stays in
    /// `self.basis`.
    fn at(&mut self, e: usize, xi: [f64; 2]) -> IndicatorPoint {
        self.iface
            .slave_face
            .element_basis_into(e, &xi, 1, &mut self.scratch, &mut self.basis);
        let (mut value, mut dv, mut x, mut jac) = (0.0, [0.0; 2], [0.0; 2], [[0.0; 2]; 2]);
        for (a, &c) in self.basis.indices.iter().enumerate() {
            value += self.basis.values[a] * self.ind[c];
            for d in 0..2 {
                dv[d] += self.basis.d1[a][d] * self.ind[c];
            }
            for j in 0..2 {
                let xj = self.iface.slave_coordinate(c, j, self.state);
                x[j] += self.basis.values[a] * xj;
                for d in 0..2 {
                    jac[j][d] += self.basis.d1[a][d] * xj;
                }
            }
        }
        let mut p = IndicatorPoint {
            value,
            grad: [0.0; 2],
            x,
            jac,
        };
        // ∇_x v = J^(−T) ∇_ξ v.
        let det = p.det();
        p.grad = [
            (jac[1][1] * dv[0] - jac[1][0] * dv[1]) / det,
            (-jac[0][1] * dv[0] + jac[0][0] * dv[1]) / det,
        ];
        p
    }

    /// The centre (parameters) of element `e`, the indicator there, and the
    /// element's mapped sides in the mean plane (from the centre's Jacobian).
    fn at_centre(&mut self, e: usize) -> ([f64; 2], IndicatorPoint, ElementSides) {
        let el = &self.iface.slave_face.elements()[e];
        let centre = [0, 1].map(|d| 0.5 * (el.lower[d] + el.upper[d]));
        let span = [0, 1].map(|d| el.upper[d] - el.lower[d]);
        let p = self.at(e, centre);
        let sides = ElementSides([0, 1].map(|d| [p.jac[0][d] * span[d], p.jac[1][d] * span[d]]));
        (centre, p, sides)
    }

    /// The indicator at the parameters `xi` of the face, continued beyond
    /// it as the lateral faces continue the model: wrapped across periodic
    /// seams (PR); mirrored at LN faces, which are planes of symmetry (zero
    /// normal displacement and shear traction, adiabatic: the cell is one
    /// half-period of its mirror images).
    fn at_param(&mut self, xi: [f64; 2]) -> IndicatorPoint {
        let xi = if self.iface.period.is_some() {
            xi.map(|t| t.rem_euclid(1.0))
        } else {
            xi.map(|t| {
                let t = t.rem_euclid(2.0);
                if t > 1.0 { 2.0 - t } else { t }
            })
        };
        let e = self.iface.slave_face.locate(&xi);
        self.at(e, xi)
    }

    /// The crossing curve in element `e`: marching squares on `n × n`
    /// sub-cells, the crossings interpolated linearly along cell sides.
    fn trace(&mut self, e: usize, n: usize, out: &mut Vec<Segment>) {
        let el = &self.iface.slave_face.elements()[e];
        let (lo, hi) = ([el.lower[0], el.lower[1]], [el.upper[0], el.upper[1]]);
        let corner: Vec<IndicatorPoint> = (0..(n + 1) * (n + 1))
            .map(|k| {
                let (i, j) = (k % (n + 1), k / (n + 1));
                let t = [i as f64 / n as f64, j as f64 / n as f64];
                self.at(e, [0, 1].map(|d| lo[d] + (hi[d] - lo[d]) * t[d]))
            })
            .collect();
        let at = |i: usize, j: usize| &corner[j * (n + 1) + i];
        let cut = |p: &IndicatorPoint, q: &IndicatorPoint| -> [f64; 2] {
            let s = p.value / (p.value - q.value);
            [0, 1].map(|d| p.x[d] + s * (q.x[d] - p.x[d]))
        };
        for j in 0..n {
            for i in 0..n {
                // Corners counter-clockwise and the sides between them.
                let c = [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)];
                let cuts: Vec<[f64; 2]> = (0..4)
                    .filter(|&s| (c[s].value > 0.0) != (c[(s + 1) % 4].value > 0.0))
                    .map(|s| cut(c[s], c[(s + 1) % 4]))
                    .collect();
                for pair in cuts.chunks_exact(2) {
                    out.push(Segment {
                        a: pair[0],
                        b: pair[1],
                        element: e,
                    });
                }
            }
        }
    }
}

impl ContactInterface {
    /// The contact area's level set for the nodal indicator `ind` in the
    /// configuration `state` (3D; module docs).
    pub(crate) fn contact_level_3d(&self, ind: Vec<f64>, state: &[f64]) -> ContactLevel3d {
        let elements = self.slave_face.elements();
        let n_el = elements.len();
        // The crossing curve element by element (in parallel, one probe per
        // worker), concatenated in element order.
        let traced: Vec<Vec<Segment>> = (0..n_el)
            .into_par_iter()
            .map_init(
                || Probe::new(self, &ind, state),
                |probe, e| {
                    let mut out = Vec::new();
                    if crosses(&elements[e].functions, &ind) {
                        probe.trace(e, CURVE_CELLS, &mut out);
                    }
                    out
                },
            )
            .collect();
        let mut segments = Vec::with_capacity(traced.iter().map(Vec::len).sum());
        let mut by_element = vec![Vec::new(); n_el];
        for (e, t) in traced.into_iter().enumerate() {
            let start = segments.len();
            segments.extend(t);
            by_element[e] = (start..segments.len()).collect();
        }
        // Elements per function, then the elements with segments near each.
        let mut of_function: Vec<Vec<usize>> = vec![Vec::new(); ind.len()];
        for (e, el) in elements.iter().enumerate() {
            for &f in &el.functions {
                of_function[f].push(e);
            }
        }
        let near: Vec<Vec<usize>> = elements
            .iter()
            .map(|el| {
                el.functions
                    .iter()
                    .flat_map(|&f| &of_function[f])
                    .copied()
                    .filter(|&k| !by_element[k].is_empty())
                    .collect::<BTreeSet<usize>>()
                    .into_iter()
                    .collect()
            })
            .collect();
        let mut level = ContactLevel3d {
            ind: Vec::new(),
            segments,
            by_element,
            near,
            shift: vec![None; n_el],
            period: self.period,
        };
        if self.e_star.is_some() {
            let mut of_element: Vec<Vec<usize>> = vec![Vec::new(); n_el];
            for (q, point) in self.points.iter().enumerate() {
                of_element[point.element].push(q);
            }
            // The elements in the support of each node (a node stands for
            // its periodic copies, `copy_of`).
            let mut of_node: Vec<Vec<usize>> = vec![Vec::new(); ind.len()];
            for (f, elements) in of_function.iter().enumerate() {
                of_node[self.copy_of[f]].extend(elements);
            }
            let supports = Supports {
                of_function: &of_function,
                of_element: &of_element,
                of_node: &of_node,
                ind: &ind,
                state,
            };
            // Each element's shift reads the crossing curve, never another
            // element's shift: the fits are independent (in parallel).
            let shifts: Vec<Option<f64>> = (0..n_el)
                .into_par_iter()
                .map_init(
                    || Probe::new(self, &ind, state),
                    |probe, e| {
                        if level.by_element[e].is_empty() {
                            return None;
                        }
                        let frame = self.edge_frame(probe, &level, e)?;
                        if !self.wide_both_sides(probe, &level, &frame) {
                            return None;
                        }
                        let h = frame.size();
                        match level.radius(e, h, frame.normal) {
                            None => {
                                let widths = self.range_widths(probe, &level, &frame);
                                self.fit_straight_edge(probe, &level, e, &frame, widths, &supports)
                            }
                            radius => self.fit_shift(&level, e, radius, h, &supports),
                        }
                    },
                )
                .collect();
            level.shift = shifts;
        }
        level.ind = ind;
        level
    }

    /// The level of the contact area at `xi` of slave element `e`: its
    /// sign (positive in contact) only is meaningful.
    pub(crate) fn contact_level_at(
        &self,
        level: &ContactLevel3d,
        state: &[f64],
        e: usize,
        xi: [f64; 2],
    ) -> f64 {
        level.level(e, &Probe::new(self, &level.ind, state).at(e, xi))
    }

    /// The crossing curve at slave element `e`: its segment nearest the
    /// element's centre, with the normal into contact (`None` without a
    /// segment of positive length).
    fn edge_frame(&self, probe: &mut Probe, level: &ContactLevel3d, e: usize) -> Option<EdgeFrame> {
        let (centre, at, sides) = probe.at_centre(e);
        let (mid, tangent) = level.by_element[e]
            .iter()
            .map(|&s| {
                let seg = &level.segments[s];
                let t = level.offset(seg.b, seg.a);
                ([seg.a[0] + 0.5 * t[0], seg.a[1] + 0.5 * t[1]], t)
            })
            .min_by(|a, b| {
                let d = |m: [f64; 2]| {
                    let o = level.offset(m, at.x);
                    o[0].hypot(o[1])
                };
                d(a.0).total_cmp(&d(b.0))
            })?;
        let length = tangent[0].hypot(tangent[1]);
        if length.is_nan() || length <= 0.0 {
            return None;
        }
        let mut frame = EdgeFrame {
            centre,
            at,
            sides,
            mid,
            normal: [-tangent[1] / length, tangent[0] / length],
        };
        // Into contact.
        if probe
            .at_param(frame.param(level, 0.25 * frame.size()))
            .value
            <= 0.0
        {
            frame.normal = frame.normal.map(|v| -v);
        }
        Some(frame)
    }

    /// Whether the indicator keeps its sign up to [`EDGE_MIN_RANGE`]
    /// element sizes (along the normal) on both sides of the crossing curve
    /// at `frame`, sampled at whole sizes (the asymptotics hold a few
    /// elements from the other edge only).
    fn wide_both_sides(
        &self,
        probe: &mut Probe,
        level: &ContactLevel3d,
        frame: &EdgeFrame,
    ) -> bool {
        let size = frame.size();
        let steps = EDGE_MIN_RANGE.ceil() as usize;
        for side in [1.0, -1.0] {
            for k in 1..=steps {
                let t = side * k as f64 * size;
                if (probe.at_param(frame.param(level, t)).value > 0.0) != (side > 0.0) {
                    return false;
                }
            }
        }
        true
    }

    /// The widths of the ranges in and out of contact across the crossing
    /// at `frame`: the distances along its normal to the next sign change of
    /// the indicator on either side (sampled at [`RANGE_STEPS`] per element
    /// size, up to one period or [`RANGE_SIZES`] sizes).
    fn range_widths(
        &self,
        probe: &mut Probe,
        level: &ContactLevel3d,
        frame: &EdgeFrame,
    ) -> [f64; 2] {
        let size = frame.size();
        let step = size / RANGE_STEPS as f64;
        let max = level
            .period
            .unwrap_or(f64::INFINITY)
            .min(RANGE_SIZES * size);
        let start = frame.param(level, 0.0);
        [1.0, -1.0].map(|side| {
            // Along the normal in the mean plane, the mapping linearized at
            // each sample (finite strain stretches the surface laterally).
            let dx = frame.normal.map(|v| side * step * v);
            let mut xi = start;
            let mut t = 0.0;
            while t < max {
                let p = probe.at_param(xi);
                if t > 0.0 && (p.value > 0.0) != (side > 0.0) {
                    return t - 0.5 * step;
                }
                let d = p.param_offset(dx);
                xi = [xi[0] + d[0], xi[1] + d[1]];
                t += step;
            }
            max
        })
    }

    /// The shift `δ` of the edge in slave element `e` fitted to the point
    /// gaps just outside it (module docs), for
    /// the crossing curve's radius (`None`: straight) and the element size
    /// `h` along its normal: spots and gaps, whose curvature the gap
    /// profile takes in ([`gap_profile`]); straight edges are fitted to the
    /// nodal values ([`ContactInterface::fit_straight_edge`]).
    fn fit_shift(
        &self,
        level: &ContactLevel3d,
        e: usize,
        radius: Option<f64>,
        h: f64,
        supports: &Supports,
    ) -> Option<f64> {
        let (ind, state) = (supports.ind, supports.state);
        let elements: BTreeSet<usize> = self.slave_face.elements()[e]
            .functions
            .iter()
            .filter(|&&c| ind[c] <= 0.0)
            .flat_map(|&c| &supports.of_function[c])
            .copied()
            .collect();
        // (φ, weight, gap) of the points in the band outside the element's
        // own segments.
        let mut data: Vec<(f64, f64, f64)> = Vec::new();
        for k in elements {
            for &q in &supports.of_element[k] {
                let point = &self.points[q];
                let mut at = IndicatorPoint {
                    value: 0.0,
                    grad: [0.0; 2],
                    x: [0.0; 2],
                    jac: [[0.0; 2]; 2],
                };
                for (a, &c) in point.conn.iter().enumerate() {
                    at.value += point.basis[a] * ind[c];
                    for j in 0..2 {
                        at.x[j] += point.basis[a] * self.slave_coordinate(c, j, state);
                    }
                }
                if let Some((phi, s)) = level.distance(k, &at)
                    && s == e
                    && (-FIT_BAND.1 * h..=-FIT_BAND.0 * h).contains(&phi)
                {
                    data.push((phi, point.weight, self.state[q].gap.value));
                }
            }
        }
        // The weighted squared misfit of the best amplitude for the shift `delta`.
        let misfit = |delta: f64| -> Option<f64> {
            let model: Vec<f64> = data
                .iter()
                .map(|&(phi, _, _)| {
                    let t = -(phi + delta);
                    if t > 0.0 {
                        gap_profile(t, radius, delta)
                    } else {
                        0.0
                    }
                })
                .collect();
            let mm: f64 = model.iter().zip(&data).map(|(m, d)| d.1 * m * m).sum();
            if mm <= 0.0 {
                return None;
            }
            let amp = model
                .iter()
                .zip(&data)
                .map(|(m, d)| d.1 * m * d.2)
                .sum::<f64>()
                / mm;
            (amp > 0.0).then(|| {
                model
                    .iter()
                    .zip(&data)
                    .map(|(m, d)| d.1 * (d.2 - amp * m).powi(2))
                    .sum()
            })
        };
        super::minimize_on(misfit, -1.5 * h, 1.5 * h, 64)
    }

    /// The shift `δ` of a straight edge in slave element `e` fitted as in
    /// 2D (`ContactInterface::locate_edge`) to the nodal values of the
    /// lumped mortar (4.8) about it: the pressures `λN^I` of the nodes in
    /// contact against `A ⟨N^I √s⟩/⟨N^I⟩` and the weighted gaps `g^J` of
    /// the others against `(4A/3E*) ⟨N^J t^(3/2)⟩/⟨N^J⟩`, `s`, `t` the
    /// distances inside and outside the edge (the line of `frame` moved by
    /// `δ` along its normal), replaced by `s (1 − s/L)` with `L` the range's
    /// width (`widths`: in, out), the supports' integrals by [`FIT_POINTS`]²
    /// Gauss points per element. The nodes: those of the elements within one element of the
    /// crossing at `frame`.
    fn fit_straight_edge(
        &self,
        probe: &mut Probe,
        level: &ContactLevel3d,
        e: usize,
        frame: &EdgeFrame,
        widths: [f64; 2],
        supports: &Supports,
    ) -> Option<f64> {
        let ind = supports.ind;
        let e_star = self.e_star?;
        let h = frame.size();
        let elements = self.slave_face.elements();
        // The elements within one element (parameters) of the crossing.
        let xi_c = frame.param(level, 0.0);
        let span = [0, 1].map(|d| elements[e].upper[d] - elements[e].lower[d]);
        let near = |k: usize| {
            (0..2).all(|d| {
                let (lo, hi) = (
                    xi_c[d] - (1.0 + 1e-6) * span[d],
                    xi_c[d] + (1.0 + 1e-6) * span[d],
                );
                let (a, b) = (elements[k].lower[d], elements[k].upper[d]);
                // Across the periodic seams (parameters wrap at 1).
                [-1.0, 0.0, 1.0].iter().any(|w| b + w > lo && a + w < hi)
            })
        };
        let nodes: BTreeSet<usize> = (0..elements.len())
            .filter(|&k| near(k))
            .flat_map(|k| elements[k].functions.iter().map(|&c| self.copy_of[c]))
            .collect();
        if !nodes.iter().any(|&c| ind[c] > 0.0) || nodes.iter().all(|&c| ind[c] > 0.0) {
            return None;
        }
        let index: Vec<usize> = nodes.iter().copied().collect();
        // The supports' points ([`FitPoint`]).
        let support: BTreeSet<usize> = nodes
            .iter()
            .flat_map(|&c| &supports.of_node[c])
            .copied()
            .collect();
        let rule = GaussLegendre::new(FIT_POINTS);
        let mut points = FitPoints::default();
        let mut area = vec![0.0; index.len()];
        let mut n = vec![0.0; index.len()];
        for &k in &support {
            let el = &elements[k];
            let (lo, hi) = (el.lower, el.upper);
            for (&u, &wu) in rule.points.iter().zip(&rule.weights) {
                for (&v, &wv) in rule.points.iter().zip(&rule.weights) {
                    let xi = [
                        0.5 * (lo[0] + hi[0]) + 0.5 * (hi[0] - lo[0]) * u,
                        0.5 * (lo[1] + hi[1]) + 0.5 * (hi[1] - lo[1]) * v,
                    ];
                    let p = probe.at(k, xi);
                    let w = 0.25 * (hi[0] - lo[0]) * (hi[1] - lo[1]) * wu * wv * p.det().abs();
                    n.iter_mut().for_each(|v| *v = 0.0);
                    for (&c, &nc) in probe.basis.indices.iter().zip(&probe.basis.values) {
                        if let Ok(m) = index.binary_search(&self.copy_of[c]) {
                            n[m] += nc;
                        }
                    }
                    // The nodes with a value here, in the order of `index`:
                    // those in contact, then the others.
                    let mut side = |in_contact: bool| {
                        for (m, &nm) in n.iter().enumerate() {
                            if nm != 0.0 && (ind[index[m]] > 0.0) == in_contact {
                                points.entries.push((m as u32, w * nm));
                                area[m] += w * nm;
                            }
                        }
                        points.entries.len() as u32
                    };
                    let (split, end) = (side(true), side(false));
                    let start = points.ranges.last().map_or(0, |r| r.2);
                    points.ranges.push((start, split, end));
                    points.phi.push(frame.distance(level, p.x));
                }
            }
        }
        let data = self.edge_fit_data(&index, ind, e_star, h);
        // Evaluated 138 times per fit (`minimize_on`): each point adds
        // to the nodes of its side of the edge only.
        let misfit = |delta: f64| -> Option<f64> {
            let mut model = vec![0.0; index.len()];
            for (&phi, &(start, split, end)) in points.phi.iter().zip(&points.ranges) {
                let d = phi + delta;
                let inside = d > 0.0;
                let nodes = if inside {
                    &points.entries[start as usize..split as usize]
                } else {
                    &points.entries[split as usize..end as usize]
                };
                if nodes.is_empty() {
                    continue;
                }
                let d =
                    d.abs() * (1.0 - d.abs() / if inside { widths[0] } else { widths[1] }).max(0.0);
                // d^(3/2) as d √d, far cheaper than `powf`.
                let f = if inside { d.sqrt() } else { d * d.sqrt() / h };
                for &(m, wn) in nodes {
                    model[m as usize] += wn * f;
                }
            }
            model.iter_mut().zip(&area).for_each(|(v, a)| *v /= a);
            super::amplitude_misfit(&model, &data)
        };
        super::minimize_on(misfit, -1.5 * h, 1.5 * h, 96)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn element_size_along_a_direction_follows_the_mesh_metric() {
        // A 0.5 × 4 rectangle: its sides along the axes, between them by
        // the metric; a square (rotated) the same in every direction.
        let rect = ElementSides([[0.5, 0.0], [0.0, 4.0]]);
        assert!((rect.along([1.0, 0.0]) - 0.5).abs() < 1e-15);
        assert!((rect.along([0.0, -1.0]) - 4.0).abs() < 1e-15);
        let d = std::f64::consts::FRAC_1_SQRT_2;
        let expect = 1.0 / (0.5 / 0.25 + 0.5 / 16.0f64).sqrt();
        assert!((rect.along([d, d]) - expect).abs() < 1e-14);
        let (c, s) = (0.3f64.cos(), 0.3f64.sin());
        let square = ElementSides([[2.0 * c, 2.0 * s], [-2.0 * s, 2.0 * c]]);
        for a in [0.0, 0.7, 2.1] {
            assert!((square.along([f64::cos(a), f64::sin(a)]) - 2.0).abs() < 1e-14);
        }
    }

    #[test]
    fn a_cut_cell_keeps_the_part_in_contact_of_a_straight_edge() {
        // v = s − 0.3: in contact on s > 0.3, fraction 0.7, centroid (0.65, 0.5).
        for m in [8, 16, 64] {
            let (f, at) = bilinear_part_in_contact([-0.3, 0.7, -0.3, 0.7], m).unwrap();
            let tol = 1.0 / m as f64;
            assert!((f - 0.7).abs() <= tol, "m = {m}: fraction {f}");
            assert!((at[0] - 0.65).abs() <= tol && (at[1] - 0.5).abs() < 1e-12);
        }
        // An oblique edge s + t > 1 (v = s + t − 1): half the cell, centroid (2/3, 2/3).
        let (f, at) = bilinear_part_in_contact([-1.0, 0.0, 0.0, 1.0], 64).unwrap();
        assert!((f - 0.5).abs() < 1.0 / 64.0, "fraction {f}");
        assert!((at[0] - 2.0 / 3.0).abs() < 1.0 / 64.0 && (at[0] - at[1]).abs() < 1e-12);
        assert!(bilinear_part_in_contact([-1.0; 4], 16).is_none());
    }
}
