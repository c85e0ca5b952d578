//! Segment-based integration of the mortar integrals (spec §6, the exact
//! alternative to element-based integration): every slave element is split
//! where the projection of its points passes from one master piece to the
//! next (an element of the master, a corner of it, a periodic image), and
//! each segment gets its own Gauss rule.
//!
//! Within a segment the gap and the jump are smooth, so the integrals (4.8)
//! are exact to the Gauss rule's order. The weighted gaps are then C1 in the
//! unknowns even over a master with C0 corners (degree 1), where pointwise
//! gaps at fixed slave points have kinks and Newton would cycle; and a flat
//! non-matching interface passes the patch test to round-off on any mesh.
//!
//! In 3D ([`Segmenter::cells`]) the pieces are areas: each slave element is
//! clipped by the *preimages* of the master elements it sees (the slave
//! points whose closest point lies on that element). A preimage's boundary
//! is found by projecting sampled points of the master element's edges back
//! along the master normal, averaged over the elements that meet there
//! (the bisector of a C0 crease, [`MasterSearch::crease_normal`]), onto the
//! slave surface (in its parameters); its polygon is clipped by the slave
//! element's box, fanned from its centroid, and each triangle gets the
//! collapsed Gauss rule; the points measure their gaps on that master
//! element ([`SlavePoint::piece`]). Where the preimages are straight in the
//! slave parameters (flat interfaces, cylinders about a parametric axis)
//! this is exact; where they are curved, the polygon's chords approximate
//! them. A mismatch left in a periodic sample's cover gets a scaled
//! element rule (`WEDGE_LIMIT`); otherwise an element that the polygons do
//! not cover (past the end of a non-periodic master) keeps its
//! element-based points.
//!
//! The breakpoints follow the configuration. First derivatives of the
//! weighted gaps are exact without their motion (the integrand is
//! continuous across a breakpoint); the second derivatives take the jump of
//! the integrand's gradient times the breakpoint motion as a term of its
//! own, which vanishes for a smooth master (2D: at every breakpoint; 3D:
//! at the [`Crossing`]s, and only where the cells were made again, kept
//! cells not moving).

use std::sync::Arc;

use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;

use crate::Result;
use crate::basis::{RationalBasis, TensorBasis};
use crate::contact::mortar::SlavePoint;
use crate::contact::projection3d::{self, MasterSearch, MasterSurface, SurfaceEvaluator};
use crate::geometry::ThbPatch;
use crate::quadrature::GaussLegendre;

mod clip;

/// Which master piece a slave point projects onto: `(element, periodic image, corner)`.
pub type Piece = (usize, i64, bool);

/// A point where the projection passes from one master piece to another
/// inside a slave element.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Breakpoint {
    /// Slave face element.
    pub element: usize,
    /// Slave face parameter.
    pub xi: f64,
    /// The pieces before and after it.
    pub pieces: (Piece, Piece),
}

/// Relative width (in the slave parameter) below which a breakpoint is located.
const BREAK_TOLERANCE: f64 = 1e-13;

/// The reference slave face and the rule applied to every segment.
#[derive(Clone, Debug)]
pub struct Segmenter {
    face: Arc<ThbPatch>,
    rule: GaussLegendre,
    /// Samples per element at which the pieces are first looked up.
    samples: usize,
}

impl Segmenter {
    /// Segments of `face` (the slave face curve, reference configuration,
    /// control points in the order of the interface's slave nodes) with
    /// `n_gauss` points each.
    pub fn new(face: Arc<ThbPatch>, n_gauss: usize) -> Self {
        Segmenter {
            face,
            rule: GaussLegendre::new(n_gauss),
            samples: (2 * n_gauss).max(8),
        }
    }

    /// The face curve.
    pub fn face(&self) -> &ThbPatch {
        &self.face
    }

    /// Integration points of the current configuration, and the breakpoints
    /// inside the slave elements. `current`: the face's current control
    /// points; `piece(x)` says which master piece the current point `x`
    /// projects onto.
    pub fn points(
        &self,
        current: &[[f64; 3]],
        mut piece: impl FnMut([f64; 2]) -> Result<Piece>,
    ) -> Result<(Vec<SlavePoint>, Vec<Breakpoint>)> {
        let mut out = Vec::new();
        let mut found = Vec::new();
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        for (e, el) in self.face.elements().iter().enumerate() {
            let (a, b) = (el.lower[0], el.upper[0]);
            let mut at = |xi: f64| -> Result<Piece> {
                self.face
                    .element_basis_into(e, &[xi], 0, &mut scratch, &mut basis);
                let cp = current;
                let mut x = [0.0; 2];
                for (&g, &n) in basis.indices.iter().zip(&basis.values) {
                    x[0] += n * cp[g][0];
                    x[1] += n * cp[g][1];
                }
                piece(x)
            };
            // Breakpoints: where the piece changes between samples, by bisection.
            let mut inner = Vec::new();
            let mut left = (a, at(a)?);
            for k in 1..=self.samples {
                let xi = a + (b - a) * k as f64 / self.samples as f64;
                let right = (xi, at(xi)?);
                bisect(&mut at, left, right, (b - a) * BREAK_TOLERANCE, &mut inner)?;
                left = right;
            }
            let mut breaks = vec![a];
            breaks.extend(inner.iter().map(|&(xi, _)| xi));
            breaks.push(b);
            found.extend(inner.into_iter().map(|(xi, pieces)| Breakpoint {
                element: e,
                xi,
                pieces,
            }));
            for w in breaks.windows(2) {
                if w[1] - w[0] <= (b - a) * BREAK_TOLERANCE {
                    continue;
                }
                interval_points(&self.face, e, (w[0], w[1]), &self.rule, &mut out);
            }
        }
        Ok((out, found))
    }
}

/// Samples per master element edge from which the preimage polygons are
/// built (3D; collinear ones are then dropped).
const EDGE_SAMPLES: usize = 4;

/// Relative mismatch between a slave element's area and the area of its
/// clipped polygons up to which the polygons cover it.
const COVER_TOLERANCE: f64 = 1e-9;

/// Relative mismatch above which a slave element of a periodic sample keeps
/// its element-based points (a master element was missed). Below it and
/// above [`COVER_TOLERANCE`] the mismatch is the wedges over C0 kinks of
/// the master (the seams, where the open bases meet with C0 continuity;
/// degree-1 masters), whose slave points project onto the kink: they get
/// the element's rule scaled to their area (negative where preimages
/// overlap). That is not exact, nor differentiated, but it follows the
/// configuration continuously (Newton converges) and vanishes in contact,
/// where a wedge's width, the gap times the kink's angle, goes to zero.
/// Without periodicity any mismatch above [`COVER_TOLERANCE`] keeps the
/// element-based points (the end of the master, or a kink).
const WEDGE_LIMIT: f64 = 1e-2;

/// Share of a slave element's area below which a clipped polygon is a
/// sliver of round-off (at the periodic seams: widths of 1e-13 of the
/// element, which the centroid fan cannot triangulate) and is dropped: far
/// below [`COVER_TOLERANCE`], so the cover is not changed by it.
const SLIVER_SHARE: f64 = 1e-11;

/// A master element and the periodic image it is seen in: the piece a 3D
/// cell measures its gaps on.
pub type MasterPiece = (usize, [i64; 2]);

/// A clipped cell: its polygon in the slave element's parameters and its
/// master piece.
type PieceCell = (Vec<clip::Point>, MasterPiece);

/// A point of a boundary between two master pieces inside a slave element
/// (3D): where the closest point passes from one master element (or
/// periodic image) to the next. The weighted gaps' second derivatives
/// take a term there for the boundary's motion (the 2D breakpoints' term,
/// integrated along the boundary): `−∫ N^I (∇g_A − ∇g_B) ⊗ (∇g_A − ∇g_B) /
/// ∂_ν(g_A − g_B)`, `ν` the boundary's normal from piece A into B in the
/// slave parameters. Without it, with the cells made at every iteration,
/// Newton diverged on the degree-1 egg box (docs/3d.md, "Stop 64").
#[derive(Clone, Debug)]
pub struct Crossing {
    /// The slave point; its weight is the Gauss weight times the chord's
    /// parametric length times the reference area Jacobian, halved (each
    /// boundary is met from the polygons on both its sides).
    pub point: SlavePoint,
    /// Derivatives of the slave basis along `ν`.
    pub normal_basis: Vec<f64>,
    /// The master pieces `(element, image)` on its two sides, A first.
    pub pieces: [MasterPiece; 2],
}

/// What [`Segmenter::cells`] made of the slave elements.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Clipping {
    /// Elements over one master element (their tensor Gauss rule).
    pub whole: usize,
    /// Elements split into the preimages of several master elements.
    pub clipped: usize,
    /// Elements whose preimages do not cover them (past the end of a
    /// non-periodic master, over its kinks; in a periodic sample more than
    /// 1 % missed): element-based points.
    pub element_based: usize,
}

/// One slave element in 3D: its points, and which case it was.
enum ElementCells {
    Whole(Option<MasterPiece>),
    Clipped(Vec<SlavePoint>, Vec<Crossing>),
    ElementBased,
}

/// The current slave surface, evaluated by its elements beyond its
/// parameter domain too: periodically continued where the sample is
/// periodic (the preimages of the master elements across a seam), else
/// extended linearly (the end of a non-periodic slave, where the polygons
/// are clipped anyway).
struct SlaveSurface<'a> {
    face: &'a ThbPatch,
    points: &'a [[f64; 3]],
    domain: ([f64; 2], [f64; 2]),
    periodic: bool,
    scratch: TensorBasis,
    basis: RationalBasis,
}

impl SlaveSurface<'_> {
    /// Position and tangents at `xi` inside the domain.
    fn inside(&mut self, xi: [f64; 2]) -> (Vector3<f64>, [Vector3<f64>; 2]) {
        let e = self.face.locate(&xi);
        self.face
            .element_basis_into(e, &xi, 1, &mut self.scratch, &mut self.basis);
        let (mut x, mut a) = (Vector3::zeros(), [Vector3::zeros(); 2]);
        for (k, &g) in self.basis.indices.iter().enumerate() {
            let p = Vector3::from(self.points[g]);
            x += self.basis.values[k] * p;
            for (d, a) in a.iter_mut().enumerate() {
                *a += self.basis.d1[k][d] * p;
            }
        }
        (x, a)
    }

    /// Position and tangents at `xi`.
    fn at(&mut self, xi: [f64; 2]) -> (Vector3<f64>, [Vector3<f64>; 2]) {
        let (lo, hi) = self.domain;
        if self.periodic {
            // ξ = ξ' + k (hi − lo): x(ξ) = x(ξ') + k (x(hi) − x(lo)) per direction.
            let k = [0, 1].map(|d| ((xi[d] - lo[d]) / (hi[d] - lo[d])).floor());
            let w = [0, 1].map(|d| (xi[d] - k[d] * (hi[d] - lo[d])).clamp(lo[d], hi[d]));
            let (mut x, a) = self.inside(w);
            for d in (0..2).filter(|&d| k[d] != 0.0) {
                let (mut h, mut l) = (w, w);
                (h[d], l[d]) = (hi[d], lo[d]);
                x += k[d] * (self.inside(h).0 - self.inside(l).0);
            }
            return (x, a);
        }
        let c = [0, 1].map(|d| xi[d].clamp(lo[d], hi[d]));
        let (x, a) = self.inside(c);
        (x + a[0] * (xi[0] - c[0]) + a[1] * (xi[1] - c[1]), a)
    }

    /// The slave parameters `ξ` where the line `y + g n` meets the surface
    /// (Newton on `(ξ, g)` from `start`), if it converges.
    fn meet(
        &mut self,
        y: Vector3<f64>,
        n: Vector3<f64>,
        start: [f64; 2],
        size: f64,
    ) -> Option<[f64; 2]> {
        let (mut xi, mut g) = (start, 0.0);
        for _ in 0..50 {
            let (x, a) = self.at(xi);
            let r = x - y - g * n;
            let j = Matrix3::from_columns(&[a[0], a[1], -n]);
            let step = j.lu().solve(&r)?;
            xi = [xi[0] - step[0], xi[1] - step[1]];
            g -= step[2];
            if !(xi[0].is_finite() && xi[1].is_finite()) {
                return None;
            }
            if step[0].abs().max(step[1].abs()) <= 1e-14 * size {
                return Some(xi);
            }
        }
        None
    }
}

impl Segmenter {
    /// 3D: the integration points of the current configuration (module
    /// docs). `current`: the slave face's current control points;
    /// `surface`, `search`: the master in the current configuration;
    /// `periodic`: whether the sample is periodic in x and y.
    pub fn cells(
        &self,
        current: &[[f64; 3]],
        surface: &MasterSurface,
        search: &MasterSearch,
        periodic: bool,
    ) -> Result<(Vec<SlavePoint>, Vec<Crossing>, Clipping)> {
        let els = self.face.elements();
        let mut domain = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for el in els {
            for d in 0..2 {
                domain.0[d] = domain.0[d].min(el.lower[d]);
                domain.1[d] = domain.1[d].max(el.upper[d]);
            }
        }
        let cells = (0..els.len())
            .into_par_iter()
            .map(|e| self.element_cells(e, current, (domain, periodic), surface, search))
            .collect::<Result<Vec<_>>>()?;
        let (mut out, mut crossings, mut count) = (Vec::new(), Vec::new(), Clipping::default());
        for (e, c) in cells.into_iter().enumerate() {
            match c {
                ElementCells::Clipped(points, on_boundaries) => {
                    count.clipped += 1;
                    out.extend(points);
                    crossings.extend(on_boundaries);
                    continue;
                }
                ElementCells::Whole(piece) => {
                    count.whole += 1;
                    // The fan of the box: the rule of a polygon that covers
                    // it, into which it passes continuously when another
                    // piece's preimage enters at a corner or an edge (the
                    // tensor rule would jump by its quadrature error there).
                    let (lo, hi) = (&els[e].lower, &els[e].upper);
                    let square = [
                        [lo[0], lo[1]],
                        [hi[0], lo[1]],
                        [hi[0], hi[1]],
                        [lo[0], hi[1]],
                    ];
                    let first = out.len();
                    let rule = clip::triangles(&square)
                        .into_iter()
                        .flat_map(|t| clip::triangle_points(t, &self.rule));
                    cell_points(&self.face, e, rule, &mut out);
                    for p in &mut out[first..] {
                        p.piece = piece;
                    }
                    continue;
                }
                ElementCells::ElementBased => count.element_based += 1,
            }
            let rule = self.box_rule(&els[e].lower, &els[e].upper, 1.0);
            cell_points(&self.face, e, rule, &mut out);
        }
        Ok((out, crossings, count))
    }

    /// The tensor Gauss rule on the parameter box `[lo, hi]` (first two
    /// directions), its weights times `scale`.
    fn box_rule(&self, lo: &[f64], hi: &[f64], scale: f64) -> Vec<([f64; 2], f64)> {
        let mut out = Vec::with_capacity(self.rule.len() * self.rule.len());
        for (y, wy) in self.rule.on_interval(lo[1], hi[1]) {
            for (x, wx) in self.rule.on_interval(lo[0], hi[0]) {
                out.push(([x, y], scale * wx * wy));
            }
        }
        out
    }

    /// [`Self::cells`] of slave element `e`.
    fn element_cells(
        &self,
        e: usize,
        current: &[[f64; 3]],
        (domain, periodic): (([f64; 2], [f64; 2]), bool),
        surface: &MasterSurface,
        search: &MasterSearch,
    ) -> Result<ElementCells> {
        let el = &self.face.elements()[e];
        let (lo, hi) = ([el.lower[0], el.lower[1]], [el.upper[0], el.upper[1]]);
        let mut slave = SlaveSurface {
            face: &self.face,
            points: current,
            domain,
            periodic,
            scratch: TensorBasis::default(),
            basis: RationalBasis::default(),
        };
        // Which master elements (and images) the element sees: those within
        // the largest sampled distance of the box of the samples (a closest
        // point lies within that distance of its slave point), the box
        // widened by a sample spacing for the surface between samples.
        let s = self.samples;
        let mut samples: Vec<([f64; 2], Vector3<f64>)> = Vec::with_capacity((s + 1) * (s + 1));
        let (mut bl, mut bh, mut reach) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0.0f64);
        let mut guess = None;
        for j in 0..=s {
            for i in 0..=s {
                let xi = [0, 1].map(|d| lo[d] + (hi[d] - lo[d]) * [i, j][d] as f64 / s as f64);
                let x = slave.at(xi).0;
                let pr = projection3d::project(surface, search, x.into(), guess)?;
                guess = Some((&pr).into());
                samples.push((xi, x));
                reach = reach.max(pr.distance);
                for c in 0..3 {
                    bl[c] = bl[c].min(x[c]);
                    bh[c] = bh[c].max(x[c]);
                }
            }
        }
        let pad = (0..3).map(|c| bh[c] - bl[c]).fold(0.0, f64::max) / s as f64;
        let candidates = search.near_box(bl, bh, reach + pad)?;
        if candidates.len() <= 1 {
            return Ok(ElementCells::Whole(candidates.first().copied()));
        }
        let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let tol = 1e-12 * size;
        let mut ev = SurfaceEvaluator::new(*surface);
        let mut polygons = Vec::new();
        for &(m, k) in &candidates {
            let (ml, mh) = surface.bounds(m);
            let corners = [ml, [mh[0], ml[1]], mh, [ml[0], mh[1]]];
            let shift = Vector3::from(search.shift(k));
            let mut poly = Vec::with_capacity(4 * EDGE_SAMPLES);
            for c in 0..4 {
                let (p, q) = (corners[c], corners[(c + 1) % 4]);
                for t in 0..EDGE_SAMPLES {
                    let t = t as f64 / EDGE_SAMPLES as f64;
                    let eta = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
                    let sp = ev.at(m, eta);
                    let y = Vector3::from(sp.x) + shift;
                    let n = Vector3::from(search.crease_normal(&mut ev, m, eta));
                    // Start from the sample nearest to this point.
                    let start = samples
                        .iter()
                        .min_by(|a, b| {
                            (a.1 - y)
                                .norm_squared()
                                .total_cmp(&(b.1 - y).norm_squared())
                        })
                        .map_or([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])], |x| x.0);
                    let Some(xi) = slave.meet(y, n, start, size) else {
                        return Ok(ElementCells::ElementBased);
                    };
                    poly.push(xi);
                }
            }
            if clip::signed_area(&poly) < 0.0 {
                poly.reverse();
            }
            let clipped = clip::simplify(clip::clip_to_box(&poly, lo, hi), tol);
            let a = clip::signed_area(&clipped);
            // Slivers of round-off width (a master element's preimage
            // meeting the slave's seam from the next image) are dropped.
            if a > SLIVER_SHARE * area {
                polygons.push((clipped, (m, k)));
            }
        }
        let covered: f64 = polygons.iter().map(|p| clip::signed_area(&p.0)).sum();
        let rest = area - covered;
        let limit = if periodic {
            WEDGE_LIMIT
        } else {
            COVER_TOLERANCE
        };
        if rest.abs() > limit * area {
            return Ok(ElementCells::ElementBased);
        }
        if polygons.len() == 1 && rest.abs() <= COVER_TOLERANCE * area {
            return Ok(ElementCells::Whole(Some(polygons[0].1)));
        }
        // The wedges over C0 kinks: the element's rule scaled to their area.
        let mut out = Vec::new();
        if rest.abs() > COVER_TOLERANCE * area {
            cell_points(
                &self.face,
                e,
                self.box_rule(&lo, &hi, rest / area),
                &mut out,
            );
        }
        // A polygon's points measure their gaps on its master piece.
        for (poly, piece) in &polygons {
            let first = out.len();
            let rule = clip::triangles(poly)
                .into_iter()
                .flat_map(|t| clip::triangle_points(t, &self.rule));
            cell_points(&self.face, e, rule, &mut out);
            for p in &mut out[first..] {
                p.piece = Some(*piece);
            }
        }
        let crossings = self.crossings(e, &polygons);
        Ok(ElementCells::Clipped(out, crossings))
    }
}

impl Segmenter {
    /// The [`Crossing`]s on the boundaries of slave element `e`'s clipped
    /// `polygons` (each with its master piece) inside the element: the
    /// piece across a chord is the polygon's on its other side. (Not the
    /// closest point's just outside it: over a convex crease the closest
    /// point of a fan of slave points is the crease itself, whichever
    /// element the search names, and from one side the chord then seemed
    /// to have its own piece across; such boundaries got half their term
    /// or none, docs/3d.md, "Stop 66".) A chord with no polygon across it
    /// (an uncovered wedge) has no term.
    fn crossings(&self, e: usize, polygons: &[PieceCell]) -> Vec<Crossing> {
        let el = &self.face.elements()[e];
        let (lo, hi) = ([el.lower[0], el.lower[1]], [el.upper[0], el.upper[1]]);
        let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        let on_box = |p: clip::Point, q: clip::Point| {
            (0..2).any(|d| {
                [lo[d], hi[d]]
                    .iter()
                    .any(|&b| (p[d] - b).abs() <= 1e-12 * size && (q[d] - b).abs() <= 1e-12 * size)
            })
        };
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        let mut out = Vec::new();
        for (k, (poly, piece)) in polygons.iter().enumerate() {
            for i in 0..poly.len() {
                let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
                let d = [q[0] - p[0], q[1] - p[1]];
                let length = d[0].hypot(d[1]);
                if length <= 1e-12 * size || on_box(p, q) {
                    continue;
                }
                // Outward for a counter-clockwise polygon.
                let nu = [d[1] / length, -d[0] / length];
                for (t, wq) in self.rule.on_interval(0.0, 1.0) {
                    let xi = [p[0] + t * d[0], p[1] + t * d[1]];
                    let outside = [0, 1].map(|c| xi[c] + 1e-7 * size * nu[c]);
                    let across = polygons
                        .iter()
                        .enumerate()
                        .find(|(j, (other, _))| *j != k && clip::contains(other, outside))
                        .map(|(_, (_, across))| *across);
                    let Some(across) = across.filter(|a| a != piece) else {
                        continue;
                    };
                    let point = slave_point(
                        &self.face,
                        e,
                        (xi, 0.5 * wq * length),
                        (&mut scratch, &mut basis),
                    );
                    out.push(Crossing {
                        point,
                        normal_basis: basis
                            .d1
                            .iter()
                            .map(|g| nu[0] * g[0] + nu[1] * g[1])
                            .collect(),
                        pieces: [*piece, across],
                    });
                }
            }
        }
        out
    }
}

/// Appends to `out` the Gauss points of `rule` on the parameter interval
/// `(a, b)` of element `e` of the slave face curve `face` (weights with the
/// reference line Jacobian).
pub fn interval_points(
    face: &ThbPatch,
    e: usize,
    (a, b): (f64, f64),
    rule: &GaussLegendre,
    out: &mut Vec<SlavePoint>,
) {
    let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
    let cp = face.control_points();
    for (xi, wq) in rule.on_interval(a, b) {
        face.element_basis_into(e, &[xi], 1, &mut scratch, &mut basis);
        let mut t = [0.0; 2];
        for (&g, d) in basis.indices.iter().zip(&basis.d1) {
            t[0] += d[0] * cp[g][0];
            t[1] += d[0] * cp[g][1];
        }
        out.push(SlavePoint {
            element: e,
            conn: basis.indices.clone(),
            basis: basis.values.clone(),
            weight: wq * t[0].hypot(t[1]),
            piece: None,
        });
    }
}

/// Appends to `out` the points `(ξ, w)` (parameters and parametric weights)
/// of element `e` of the slave face surface `face` (3D), their weights
/// times the reference area Jacobian `|∂x/∂ξ1 × ∂x/∂ξ2|`.
pub fn cell_points(
    face: &ThbPatch,
    e: usize,
    rule: impl IntoIterator<Item = ([f64; 2], f64)>,
    out: &mut Vec<SlavePoint>,
) {
    let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
    for point in rule {
        out.push(slave_point(face, e, point, (&mut scratch, &mut basis)));
    }
}

/// The point `ξ` (parametric weight `w`) of element `e` of the slave face
/// surface `face`, its weight times the reference area Jacobian
/// `|∂x/∂ξ1 × ∂x/∂ξ2|`; `basis` keeps its basis and first derivatives.
fn slave_point(
    face: &ThbPatch,
    e: usize,
    (xi, w): ([f64; 2], f64),
    (scratch, basis): (&mut TensorBasis, &mut RationalBasis),
) -> SlavePoint {
    face.element_basis_into(e, &xi, 1, scratch, basis);
    let cp = face.control_points();
    let mut t = [Vector3::zeros(); 2];
    for (&g, d) in basis.indices.iter().zip(&basis.d1) {
        for (k, t) in t.iter_mut().enumerate() {
            *t += d[k] * Vector3::from(cp[g]);
        }
    }
    SlavePoint {
        element: e,
        conn: basis.indices.clone(),
        basis: basis.values.clone(),
        weight: w * t[0].cross(&t[1]).norm(),
        piece: None,
    }
}

/// Appends to `breaks` every change of piece between `left` and `right`, each
/// located to `tolerance`, or to the spacing of doubles where that is coarser
/// (a small element far from 0 in the slave parameter: its mid-point then
/// rounds onto an end, and the interval no longer shrinks).
fn bisect(
    at: &mut impl FnMut(f64) -> Result<Piece>,
    left: (f64, Piece),
    right: (f64, Piece),
    tolerance: f64,
    breaks: &mut Vec<(f64, (Piece, Piece))>,
) -> Result<()> {
    if left.1 == right.1 {
        return Ok(());
    }
    let m = 0.5 * (left.0 + right.0);
    if right.0 - left.0 <= tolerance || m <= left.0 || m >= right.0 {
        breaks.push((m, (left.1, right.1)));
        return Ok(());
    }
    let mid = (m, at(m)?);
    bisect(at, left, mid, tolerance, breaks)?;
    bisect(at, mid, right, tolerance, breaks)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Side, ThbPatch, shapes};

    /// A change of piece inside two neighbouring doubles is located there: the
    /// bisection ends although its tolerance lies below their spacing (it
    /// recursed without end on the fine elements of a degree-1 2D adaptive
    /// level near ξ = 0.52, stop 101).
    #[test]
    fn a_break_below_the_spacing_of_doubles_ends_the_bisection() {
        let x: f64 = 0.52;
        let next = f64::from_bits(x.to_bits() + 1);
        let mut calls = 0;
        let mut at = |xi: f64| -> Result<Piece> {
            calls += 1;
            Ok((usize::from(xi > x), 0, false))
        };
        let mut breaks = Vec::new();
        let (a, b) = (x - 1e-6, x + 1e-6);
        let (left, right) = ((a, at(a).unwrap()), (b, at(b).unwrap()));
        bisect(&mut at, left, right, (b - a) * BREAK_TOLERANCE, &mut breaks).unwrap();
        assert_eq!(breaks.len(), 1);
        assert!(breaks[0].0 == x || breaks[0].0 == next, "{breaks:?}");
        assert!(calls < 100, "{calls} evaluations");
    }

    #[test]
    fn segments_split_at_the_pieces_and_integrate_the_length() {
        let face = ThbPatch::from(&shapes::rectangle(0.0, 2.0, 0.0, 1.0).face(1, Side::Low).0);
        let seg = Segmenter::new(Arc::new(face.clone()), 3);
        // Pieces of width 0.3 in x: breakpoints at 0.3, 0.6, ...
        let (pts, breaks) = seg
            .points(face.control_points(), |x| {
                Ok(((x[0] / 0.3).floor() as usize, 0, false))
            })
            .unwrap();
        assert_eq!(breaks.len(), 6);
        for (k, b) in breaks.iter().enumerate() {
            let x = face.point(&[b.xi])[0];
            assert!((x - 0.3 * (k + 1) as f64).abs() < 1e-12, "{b:?}");
            assert_eq!((b.pieces.0.0 + 1, b.pieces.1.0), (k + 1, k + 1));
        }
        let length: f64 = pts.iter().map(|p| p.weight).sum();
        assert!((length - 2.0).abs() < 1e-14);
        // ∫ x² dx over [0, 2] with a 3-point rule per segment: exact.
        let m2: f64 = pts
            .iter()
            .map(|p| {
                let xi: f64 = p
                    .conn
                    .iter()
                    .zip(&p.basis)
                    .map(|(&g, n)| n * face.control_points()[g][0])
                    .sum();
                p.weight * xi * xi
            })
            .sum();
        assert!((m2 - 8.0 / 3.0).abs() < 1e-13);
        // 7 pieces (0.3 × 6 = 1.8 < 2) → 7 segments of 3 points.
        assert_eq!(pts.len(), 21);
    }

    /// The z = 0 face of a degree-2 block `[x0, x0 + 1] × [0, 1]` with
    /// `n × n` elements on it (`Side::Low`: the slave, above; `High`: the
    /// master, below).
    fn flat_face(x0: f64, n: usize, side: Side) -> ThbPatch {
        let z = if side == Side::Low {
            [0.0, 1.0]
        } else {
            [-1.0, 0.0]
        };
        let mut block = shapes::cuboid([x0, 0.0, z[0]], [x0 + 1.0, 1.0, z[1]]);
        for d in 0..3 {
            block = block.elevate_degree(d, 1);
        }
        let block = block.refine_uniform(0, n).refine_uniform(1, n);
        ThbPatch::from(&block.face(2, side).0)
    }

    /// [`Segmenter::cells`] of `slave`'s reference points over `master`
    /// (non-periodic).
    fn clip_over(
        seg: &Segmenter,
        slave: &ThbPatch,
        master: &ThbPatch,
    ) -> (Vec<SlavePoint>, Clipping) {
        let surface = MasterSurface {
            face: master,
            points: master.control_points(),
            pieces: None,
        };
        let search = MasterSearch::new(&surface, [None, None]);
        let (points, _, clipping) = seg
            .cells(slave.control_points(), &surface, &search, false)
            .unwrap();
        (points, clipping)
    }

    #[test]
    fn clipped_slave_elements_integrate_piecewise_integrands_of_the_master_exactly() {
        let slave = flat_face(0.0, 3, Side::Low);
        let seg = Segmenter::new(Arc::new(slave.clone()), 4);
        let at = |p: &SlavePoint, k: usize| -> f64 {
            p.conn
                .iter()
                .zip(&p.basis)
                .map(|(&g, n)| n * slave.control_points()[g][k])
                .sum()
        };
        // Master breaks at x, y = 1/4, 1/2, 3/4: inside every slave element.
        let (points, count) = clip_over(&seg, &slave, &flat_face(0.0, 4, Side::High));
        assert_eq!(
            count,
            Clipping {
                whole: 0,
                clipped: 9,
                element_based: 0
            }
        );
        let area: f64 = points.iter().map(|p| p.weight).sum();
        assert!((area - 1.0).abs() < 1e-14, "{area}");
        // A kink of the second derivative at the master's break x = 1/4:
        // ∫∫ max(x − 1/4, 0)² (y + 1) = (3/4)³/3 · 3/2.
        let f = |p: &SlavePoint| (at(p, 0) - 0.25).max(0.0).powi(2) * (at(p, 1) + 1.0);
        let q: f64 = points.iter().map(|p| p.weight * f(p)).sum();
        assert!((q - 0.2109375).abs() < 1e-14, "{q}");
        // The element-based rule (what the whole elements get) is not exact.
        let (mut tensor, rule) = (Vec::new(), GaussLegendre::new(4));
        for (e, el) in slave.elements().iter().enumerate() {
            let pts = rule
                .on_interval(el.lower[1], el.upper[1])
                .flat_map(|(y, wy)| {
                    rule.on_interval(el.lower[0], el.upper[0])
                        .map(move |(x, wx)| ([x, y], wx * wy))
                });
            cell_points(&slave, e, pts, &mut tensor);
        }
        let qe: f64 = tensor.iter().map(|p| p.weight * f(p)).sum();
        assert!((qe - 0.2109375).abs() > 1e-5, "{qe}");
        // The same mesh: every element over one master element.
        let (_, count) = clip_over(&seg, &slave, &flat_face(0.0, 3, Side::High));
        assert_eq!((count.whole, count.clipped, count.element_based), (9, 0, 0));
        // A master shifted by 0.1 in x leaves 30 % of the slave's first
        // column over no master element (clamped projections): those keep
        // their element-based points; the others are clipped exactly.
        let (points, count) = clip_over(&seg, &slave, &flat_face(0.1, 4, Side::High));
        assert_eq!((count.clipped, count.element_based), (6, 3), "{count:?}");
        let area: f64 = points.iter().map(|p| p.weight).sum();
        assert!((area - 1.0).abs() < 1e-14, "{area}");
    }
}
