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
//!   `[0.25, 2]` elements outside the crossing (where the gap is clearly
//!   open), against `G(t)`, `t = −(φ + δ)` where positive, `G` the gap's
//!   shape ([`gap_profile`]: `t^(3/2)` at a straight edge, Hertz's gap
//!   outside a spot whose radius is fitted to the curve's segments, the
//!   penny-shaped gap inside a closing gap). Only open gaps are fitted: in
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
//! - the fit applies only where the indicator keeps its sign
//!   [`EDGE_MIN_RANGE`] elements along the normal on both sides (spots and
//!   gaps at least that wide, as in 2D); other elements keep the crossing.
//!
//! A point is in contact where `φ + δ > 0`, `δ` that of the element of its
//! nearest segment (and where `v > 0` far from any segment).

use std::collections::BTreeSet;

use super::{ContactInterface, EDGE_MIN_RANGE};
use crate::basis::{RationalBasis, TensorBasis};

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

/// The slave elements of each slave node (its support) and the contact
/// integration points of each slave element.
struct Supports<'a> {
    of_function: &'a [Vec<usize>],
    of_element: &'a [Vec<usize>],
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
    /// on `n × n` sub-cells of every slave element.
    pub(crate) fn area(&self, iface: &ContactInterface, state: &[f64], n: usize) -> f64 {
        let mut area = 0.0;
        self.visit_cells(iface, state, n, |_, _, cell, inside| {
            if inside {
                area += cell;
            }
        });
        area
    }

    /// Visits the `n × n` sub-cells of every slave element with the
    /// element, the cell's centre (parameters), its area projected on the
    /// mean plane (midpoint rule) and whether its centre is in contact.
    pub(crate) fn visit_cells(
        &self,
        iface: &ContactInterface,
        state: &[f64],
        n: usize,
        mut visit: impl FnMut(usize, [f64; 2], f64, bool),
    ) {
        let mut probe = Probe::new(iface, &self.ind, state);
        for (e, el) in iface.slave_face.elements().iter().enumerate() {
            let h = [0, 1].map(|d| (el.upper[d] - el.lower[d]) / n as f64);
            for k in 0..n * n {
                let xi = [
                    el.lower[0] + h[0] * ((k % n) as f64 + 0.5),
                    el.lower[1] + h[1] * ((k / n) as f64 + 0.5),
                ];
                let p = probe.at(e, xi);
                visit(e, xi, p.det().abs() * h[0] * h[1], self.level(e, &p) > 0.0);
            }
        }
    }
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
    /// element's size `√(area)` in the mean plane (from the centre's Jacobian).
    fn at_centre(&mut self, e: usize) -> ([f64; 2], IndicatorPoint, f64) {
        let el = &self.iface.slave_face.elements()[e];
        let centre = [0, 1].map(|d| 0.5 * (el.lower[d] + el.upper[d]));
        let area = (el.upper[0] - el.lower[0]) * (el.upper[1] - el.lower[1]);
        let p = self.at(e, centre);
        (centre, p, (p.det().abs() * area).sqrt())
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
        let mut probe = Probe::new(self, &ind, state);
        let mut segments = Vec::new();
        let mut by_element = vec![Vec::new(); n_el];
        for (e, el) in elements.iter().enumerate() {
            if crosses(&el.functions, &ind) {
                let start = segments.len();
                probe.trace(e, CURVE_CELLS, &mut segments);
                by_element[e] = (start..segments.len()).collect();
            }
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
            let supports = Supports {
                of_function: &of_function,
                of_element: &of_element,
            };
            for e in 0..n_el {
                if level.by_element[e].is_empty() || !self.wide_both_sides(&mut probe, &level, e) {
                    continue;
                }
                level.shift[e] = self.fit_shift(&mut probe, &level, e, &supports, state);
            }
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

    /// Whether the indicator keeps its sign up to [`EDGE_MIN_RANGE`]
    /// element sizes on both sides of the crossing curve in element `e`,
    /// along the normal of its segment nearest the element's centre (the
    /// asymptotics hold a few elements from the other edge only).
    fn wide_both_sides(&self, probe: &mut Probe, level: &ContactLevel3d, e: usize) -> bool {
        let (centre, p, size) = probe.at_centre(e);
        let Some((mid, tangent)) = level.by_element[e]
            .iter()
            .map(|&s| {
                let seg = &level.segments[s];
                let t = level.offset(seg.b, seg.a);
                ([seg.a[0] + 0.5 * t[0], seg.a[1] + 0.5 * t[1]], t)
            })
            .min_by(|a, b| {
                let d = |m: [f64; 2]| {
                    let o = level.offset(m, p.x);
                    o[0].hypot(o[1])
                };
                d(a.0).total_cmp(&d(b.0))
            })
        else {
            return false;
        };
        let length = tangent[0].hypot(tangent[1]);
        if length <= 0.0 {
            return false;
        }
        let mut normal = [-tangent[1] / length, tangent[0] / length];
        // The parameters of the point at `t` along the normal from `mid`.
        let param = |normal: [f64; 2], t: f64| {
            let to = level.offset([0, 1].map(|d| mid[d] + t * normal[d]), p.x);
            let dxi = p.param_offset(to);
            [centre[0] + dxi[0], centre[1] + dxi[1]]
        };
        // Into contact.
        if probe.at_param(param(normal, 0.25 * size)).value <= 0.0 {
            normal = normal.map(|v| -v);
        }
        let steps = EDGE_MIN_RANGE.ceil() as usize;
        for side in [1.0, -1.0] {
            for k in 1..=steps {
                let t = side * k as f64 * size;
                if (probe.at_param(param(normal, t)).value > 0.0) != (side > 0.0) {
                    return false;
                }
            }
        }
        true
    }

    /// The shift `δ` of the edge in slave element `e` fitted to the point
    /// gaps just outside it, in the configuration `state` (module docs).
    fn fit_shift(
        &self,
        probe: &mut Probe,
        level: &ContactLevel3d,
        e: usize,
        supports: &Supports,
        state: &[f64],
    ) -> Option<f64> {
        let ind = probe.ind;
        let (_, at_centre, h) = probe.at_centre(e);
        let radius = level.radius(e, h, at_centre.grad);
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
}
