//! Mortar contact interface in 2D and 3D (paper Sect. 4.2–4.3, spec §6):
//! element-based integration on the slave surface, projection of every
//! integration point onto the master, row-sum lumped weighted gaps and jumps
//! (4.8), Alart–Curnier augmented Lagrangian for normal contact, and the
//! thermal contact models (constraint by penalty (4.7) or augmented Lagrangian
//! (4.9)–(4.10), constitutive `h0 = −kθ pN^α ϑc`), or the pointwise
//! *continuum* thermal contact for comparison.
//!
//! All quantities are in the solver's scaled units. The contribution of slave
//! control point `I` is one "contact element" whose unknowns are the
//! displacements and temperatures of every control point that its integration
//! points see, and its multipliers. With `G^I = ∂⟨N^I gN⟩/∂u`,
//! `H^I = ∂²⟨N^I gN⟩/∂u²`, `A^I = ⟨N^I⟩` and `g^I = ⟨N^I gN⟩/A^I`:
//! ```text
//! pN^I = λN^I − εN g^I  > 0 (active):  R_u −= pN^I G^I,  R_λ = −A^I g^I
//!                          otherwise:  R_λ = −A^I λN^I / εN
//! ```
//! which is the gradient of the augmented Lagrangian, so the tangent is
//! symmetric (LDLᵀ-ready). The thermal terms have the same structure with
//! `γθ^I = ⟨N^I ϑc⟩/A^I` and `h0^I`, the flux *into* the slave.
//!
//! The same code serves both dimensions: nodes carry `dim + 1` unknowns
//! (displacement, temperature); in 3D the master is a surface
//! ([`crate::contact::projection3d`], periodic in x and y) and the gap and
//! jump come from [`crate::contact::kinematics3d`]. In 3D the integration is
//! element-based (`interface_points²` Gauss points per slave element), or
//! clipped by the master elements' preimages on request
//! ([`Segmenter::cells`]); the
//! contact area is measured on the interpolated pressure indicator with its
//! edges fitted to the point gaps just outside them (`edge3d`,
//! [`ContactInterface::contact_length`]). The thermal phase keeps the nodal
//! supports of the active set by default; with `thermal_zone = true` it
//! integrates over that contact area as in 2D (the Gauss rule in elements
//! wholly inside, the midpoint rule on the in-zone sub-cells of the
//! elements at its edge).

use std::collections::BTreeSet;
use std::sync::Arc;

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::basis::{RationalBasis, TensorBasis};
use crate::contact::kinematics::{Derivatives, Needs, PointGeometry, differentiate};
use crate::contact::kinematics3d::SurfacePointGeometry;
use crate::contact::pieces::FacePieces;
use crate::contact::projection::{
    MasterCurve, MasterSamples, Projection, project, project_on_element,
};
use crate::contact::projection3d::{self, Guess, MasterSearch, MasterSurface, SurfaceProjection};
use crate::contact::segments::{
    Breakpoint, Clipping, Crossing, MasterPiece, Segmenter, cell_points, interval_points,
};
use crate::contact::{
    ContactSettings, Integration, ThermalContact, ThermalEnforcement, ThermalMethod,
};
use crate::geometry::{Side, ThbPatch};
use crate::quadrature::GaussLegendre;
use crate::solve::dofs::DofMap;
use crate::solve::golden_search;
use crate::{Error, Result};

mod edge3d;

/// The share of the smallest slave element's size that the control points
/// may move before the 3D clipped cells are made again
/// ([`crate::contact::segments::Segmenter::cells`]). Kept cells, each with
/// its master piece, make the residual smooth, so Newton's last increments
/// converge quadratically on the points' own tangent; cells made again at
/// every iteration move with the configuration in ways the tangent holds
/// only in part (the crossings' term), and on the degree-1 egg box
/// (`[12, 12, 6]`, 100 kPa) a re-solve's residual went down to 4.1e-11 and
/// then grew by 13 % per iteration; with cells kept below 1e-6 of an
/// element, down to 2.9e-9 and then 11 % (the increments along soft
/// directions are larger than that); with 1e-3 it solves in 24 Newton
/// iterations (docs/3d.md, "Stop 64"). The converged
/// state's cells are those of a configuration within this share of an
/// element of it.
pub const CELL_MOTION_SHARE: f64 = 1e-3;

/// One slave integration point (reference data).
#[derive(Clone, Debug)]
pub struct SlavePoint {
    /// Slave face element index.
    pub element: usize,
    /// Slave control points of the element, as indices into the slave face nodes.
    pub conn: Vec<usize>,
    /// Basis values at the point.
    pub basis: Vec<f64>,
    /// Gauss weight × reference line Jacobian.
    pub weight: f64,
    /// The master piece `(element, image)` whose gap the point measures
    /// (3D clipped cells, [`crate::contact::segments`]); `None`: the
    /// closest point's.
    pub piece: Option<MasterPiece>,
}

impl SlavePoint {
    /// The point's position `Σ_A N^A x_A` on the slave face whose control
    /// points are at `nodes` (indexed as [`SlavePoint::conn`]).
    fn position(&self, nodes: &[[f64; 3]]) -> [f64; 3] {
        let mut x = [0.0; 3];
        for (&b, &c) in self.basis.iter().zip(&self.conn) {
            for (xk, nk) in x.iter_mut().zip(&nodes[c]) {
                *xk += b * nk;
            }
        }
        x
    }
}

/// The slave node whose contact element carries a point's continuum terms:
/// the one with the largest basis value.
fn owner_of(p: &SlavePoint) -> usize {
    let a = (0..p.basis.len()).fold(0, |b, a| if p.basis[a] > p.basis[b] { a } else { b });
    p.conn[a]
}

/// What one integration point sees in the current configuration.
#[derive(Clone, Debug, Default)]
pub struct PointState {
    /// Master face node indices (into the master face nodes) of the element.
    pub master: Vec<usize>,
    /// The projection (2D).
    pub projection: Projection,
    /// The projection onto the master surface (3D).
    pub surface: Option<SurfaceProjection>,
    /// Gap with derivatives.
    pub gap: Derivatives,
    /// Temperature jump with derivatives.
    pub jump: Derivatives,
}

/// Which multiplier families are unknowns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Unknowns {
    /// Normal contact multipliers λN.
    pub mechanical: bool,
    /// Thermal multipliers λθ (augmented Lagrangian constraint model).
    pub thermal: bool,
    /// Whether the thermal contact terms are assembled at all.
    pub thermal_terms: bool,
    /// Whether the mechanical contact terms are assembled at all.
    pub mechanical_terms: bool,
}

impl PointState {
    /// Bytes held (the derivatives' vectors included).
    pub fn storage_bytes(&self) -> usize {
        let d = |d: &Derivatives| {
            (d.grad.capacity() + d.hess.capacity()) * size_of::<f64>()
                + d.factors
                    .iter()
                    .map(|(u, v)| (u.capacity() + v.capacity()) * size_of::<f64>() + 48)
                    .sum::<usize>()
        };
        size_of::<Self>()
            + self.master.capacity() * size_of::<usize>()
            + d(&self.gap)
            + d(&self.jump)
    }

    /// The master face element the point projects onto.
    pub fn master_element(&self) -> usize {
        self.surface.map_or(self.projection.element, |s| s.element)
    }
}

/// A slave/master pair of curves (2D) or surfaces (3D) in contact.
pub struct ContactInterface {
    /// Spatial dimension (2 or 3); nodes carry `dim + 1` unknowns.
    dim: usize,
    /// Settings (penalties scaled).
    pub settings: ContactSettings,
    /// Global node numbers of the slave face control points.
    pub slave_nodes: Vec<usize>,
    /// Global node numbers of the master face control points.
    pub master_nodes: Vec<usize>,
    /// The master face (reference configuration).
    master_face: Arc<ThbPatch>,
    master_ref: Vec<[f64; 3]>,
    slave_ref: Vec<[f64; 3]>,
    /// Integration points.
    pub points: Vec<SlavePoint>,
    /// Lumped areas `⟨N^I⟩` (4.8).
    pub lumped_area: Vec<f64>,
    /// Points touching each slave node.
    node_points: Vec<Vec<usize>>,
    /// Mortar test weights `(node, weight · ψ^I)` of each point where they
    /// are not the slave basis (the contact zone, [`ContactInterface::freeze`]).
    test: Option<Vec<Vec<(usize, f64)>>>,
    /// The slave node whose contact element carries a point's continuum terms.
    owner: Vec<usize>,
    /// The slave node that carries each slave control point's multipliers:
    /// itself, or for a periodic copy (the control points on the seam faces
    /// `x = W`, `y = W` tied to those at 0) the first of its tie group
    /// ([`ContactInterface::merge_periodic_copies`]).
    copy_of: Vec<usize>,
    /// Period of the master (PR conditions), scaled.
    pub period: Option<f64>,
    normal_sign: f64,
    /// Mechanical penalty εN (scaled).
    pub eps_n: f64,
    /// Contact modulus `E*` of the two bodies (scaled; `1/E* = Σ (1 − ν²)/E`
    /// at the reference state), for the contact edges of the zone
    /// (`ContactInterface::locate_edge`); `None`: the indicator's
    /// crossings.
    pub e_star: Option<f64>,
    /// Thermal penalty εθ (scaled).
    pub eps_t: f64,
    /// Current point states.
    pub state: Vec<PointState>,
    /// Normal multipliers λN^I.
    pub lambda_n: Vec<f64>,
    /// Thermal multipliers λθ^I.
    pub lambda_t: Vec<f64>,
    /// Mechanical active set.
    pub active: Vec<bool>,
    /// Frozen mechanical pressure and active set (thermal phase).
    pub frozen: Option<(Vec<f64>, Vec<bool>)>,
    /// The contact zone of the frozen configuration, where the thermal
    /// contact is integrated (see [`ContactInterface::freeze`]).
    zone: Option<ContactZone>,
    /// The mechanical integration points, kept while the thermal phase
    /// integrates over the contact zone only.
    mechanical_points: Option<PointSet>,
    /// The slave face (reference configuration; its control points in the
    /// order of `slave_nodes`).
    slave_face: Arc<ThbPatch>,
    /// Master face nodes coupled to each slave node in the current pattern.
    pub band: Vec<BTreeSet<usize>>,
    /// 3D: the master elements touching each master element
    /// ([`touching_elements`]), found on the first widening of a band.
    touching: Option<Vec<Vec<usize>>>,
    /// Slave nodes whose contact elements couple their kinematic unknowns in
    /// the sparse pattern: the nodes in contact and their neighbours (grown
    /// when a node outside enters contact, reset at a change of phase). The
    /// elements of the others carry their multiplier equations only, which
    /// is all they hold out of contact; in 3D the kinematic blocks of every
    /// node made the contact rows dominate the pattern and its factors.
    coupled: Vec<bool>,
    /// Segment-based integration (then `points` follow the configuration).
    segmenter: Option<Segmenter>,
    /// Breakpoints of the current segmentation (2D).
    breakpoints: Vec<Breakpoint>,
    /// Points on the boundaries between master pieces of the current
    /// segmentation (3D).
    crossings: Vec<Crossing>,
    /// Slave and master control-point positions the segmentation was made for.
    segmented_at: Vec<[f64; 3]>,
    /// Motion of a control point below which the 3D cells are kept
    /// ([`CELL_MOTION_SHARE`] of the smallest slave element).
    cell_tolerance: f64,
    /// What the last 3D segmentation made of the slave elements.
    clipping: Clipping,
    /// Slave and master control-point positions of the last projections,
    /// which are reused while these do not move (the thermal phase).
    projected_at: Vec<[f64; 3]>,
    /// Second-derivative terms of the weighted gaps from moving breakpoints.
    break_terms: Vec<BreakTerm>,
    /// Whether the mechanical tangent holds the contact's curvature, the
    /// gaps' second variations weighted by the pressures
    /// (`−pN^I ⟨N^I H_g⟩`, [`ContactInterface::set_curvature`]).
    curvature: bool,
}

/// The unknowns of a contact element ([`ContactInterface::element_dofs`]:
/// `(node, field)` pairs, node-major and sorted, the same fields for every
/// node) by node: a point's unknowns map to their positions by one search
/// per node ([`ContactInterface::point_map`]).
struct DofIndex {
    /// The element's nodes, sorted.
    nodes: Vec<usize>,
    /// Position of each field among a node's unknowns.
    slot: [Option<usize>; 4],
    /// Unknowns per node.
    per_node: usize,
}

impl DofIndex {
    fn new(dofs: &[(usize, usize)], dim: usize) -> Self {
        let per_node = dofs.iter().take_while(|d| d.0 == dofs[0].0).count();
        let mut slot = [None; 4];
        for (s, d) in dofs.iter().take(per_node).enumerate() {
            slot[d.1] = Some(s);
        }
        debug_assert!(slot.iter().skip(dim + 1).all(Option::is_none));
        DofIndex {
            nodes: dofs.iter().step_by(per_node.max(1)).map(|d| d.0).collect(),
            slot,
            per_node,
        }
    }
}

/// The smallest share of a slave node's lumped area that its test function
/// on the contact zone may cover and carry a thermal multiplier: below it
/// the multiplier's row is a near-zero pivot of the thermal system, and the
/// node hands its part on (`zone_test_weights` says to whom, and when a
/// node in contact keeps it: at first touch, where no larger node is there).
pub const ZONE_MIN_SHARE: f64 = 0.05;

/// Per slave node, the factors of its points' gap and jump Hessians in the
/// tangent ([`ContactInterface::hessian_weights`]).
#[derive(Clone, Debug)]
pub struct HessianWeights {
    gap: Vec<f64>,
    jump: Vec<f64>,
}

/// The node that carries Hessians tested by `pairs` (node, test weight):
/// the one of largest weight, the first of equals; and `Σ w · f[j]` for
/// each of the nodes' `factors` `f`. Points and break terms alike: the
/// pattern couples every neighbour of a node in contact
/// ([`ContactInterface::cover_active`]), so a carrier has an element.
fn carried<const K: usize>(
    pairs: impl Iterator<Item = (usize, f64)>,
    factors: [&[f64]; K],
) -> (usize, [f64; K]) {
    let (mut carrier, mut best, mut sums) = (usize::MAX, f64::NEG_INFINITY, [0.0; K]);
    for (j, w) in pairs {
        if w > best {
            (carrier, best) = (j, w);
        }
        for (s, f) in sums.iter_mut().zip(&factors) {
            *s += w * f[j];
        }
    }
    (carrier, sums)
}

/// Adds the weight `w` of node `i` to `pairs` (one entry per node).
fn add_weight(pairs: &mut Vec<(usize, f64)>, i: usize, w: f64) {
    match pairs.iter_mut().find(|(j, _)| *j == i) {
        Some(e) => e.1 += w,
        None => pairs.push((i, w)),
    }
}

/// The thermal test functions on a contact zone ([`ContactInterface::freeze`]):
/// per zone point, the `(node, weight · ψ^I)` pairs, from the points' slave
/// basis, the nodal indicator `indicator` (in contact where positive), the
/// nodes' whole lumped areas `surface_area` and the periodic copies
/// `copy_of`. The heir of a point is its node of highest rank (then largest
/// basis value); nodes of the heir's rank keep their weights, the others hand
/// them to the heir; rank 0 carries no multiplier (a point whose nodes are
/// all of rank 0 is left out). First the nodes in contact rank above the
/// others; where that leaves some node a share of the zone below
/// [`ZONE_MIN_SHARE`] of its area, the ranks are, from the top: in contact
/// with at least that share, in contact with less, out of contact with at
/// least that share, the rest.
///
/// Why: the `ψ^I` stay a partition of unity on the zone, and no edge element
/// gets more constraints than its jump can meet (which would lock it to zero
/// over the element); and a multiplier whose test function covers a sliver
/// of its node's area is a near-zero pivot of the thermal system (22 of them,
/// and no convergence, on the 3D egg box's first adaptive level; 4 where a
/// fitted edge inside a node in contact left it 0.04–0.17 % of its area, at
/// 39 kPa's fourth level, and LU took the thermal phase: 31 s against 1 s).
fn zone_test_weights(
    points: &[SlavePoint],
    copy_of: &[usize],
    indicator: &[f64],
    surface_area: &[f64],
) -> Vec<Vec<(usize, f64)>> {
    let root = |i: usize| copy_of[i];
    let assign = |rank: &dyn Fn(usize) -> u8| -> Vec<Vec<(usize, f64)>> {
        points
            .iter()
            .map(|sp| {
                let r = |a: usize| rank(root(sp.conn[a]));
                let heir = (0..sp.conn.len())
                    .max_by(|&a, &b| r(a).cmp(&r(b)).then(sp.basis[a].total_cmp(&sp.basis[b])));
                let mut pairs: Vec<(usize, f64)> = Vec::new();
                let Some(h) = heir.filter(|&h| r(h) > 0) else {
                    return pairs;
                };
                for (a, &i) in sp.conn.iter().enumerate() {
                    let to = if r(a) == r(h) { i } else { sp.conn[h] };
                    add_weight(&mut pairs, to, sp.weight * sp.basis[a]);
                }
                pairs
            })
            .collect()
    };
    let in_contact = |i: usize| indicator[i] > 0.0;
    let first = assign(&|i| if in_contact(i) { 2 } else { 1 });
    let mut share = vec![0.0; copy_of.len()];
    for &(i, w) in first.iter().flatten() {
        share[root(i)] += w;
    }
    // Nodes in contact always carry where no larger one is at their point
    // (at first touch the zone covers little of any node, and it must still
    // conduct).
    let large = |i: usize| share[i] >= ZONE_MIN_SHARE * surface_area[i];
    if (0..copy_of.len()).all(|i| share[i] == 0.0 || large(i)) {
        return first;
    }
    assign(&|i| match (large(i), in_contact(i)) {
        (true, true) => 3,
        (false, true) => 2,
        (true, false) => 1,
        (false, false) => 0,
    })
}

/// Integration points and what each slave node sees of them.
#[derive(Clone, Debug, Default)]
struct PointSet {
    points: Vec<SlavePoint>,
    node_points: Vec<Vec<usize>>,
    test: Option<Vec<Vec<(usize, f64)>>>,
    owner: Vec<usize>,
    lumped_area: Vec<f64>,
}

impl PointSet {
    /// The points, with the points touching each of `n_nodes` slave nodes,
    /// the owners and the lumped areas `⟨ψ^I⟩` over them; the test
    /// functions `ψ^I` are the slave basis `N^I` unless `test` gives their
    /// weights `(node, weight · ψ^I)` at each point.
    /// A periodic copy's test function is its node's (`copy_of`): the
    /// two are one function of the periodic slave space, whose weighted gap
    /// is one constraint.
    fn new(
        points: Vec<SlavePoint>,
        test: Option<Vec<Vec<(usize, f64)>>>,
        copy_of: &[usize],
    ) -> Self {
        let n_nodes = copy_of.len();
        let merged = |pairs: &mut dyn Iterator<Item = (usize, f64)>| {
            let mut out: Vec<(usize, f64)> = Vec::new();
            for (i, w) in pairs {
                let i = copy_of[i];
                add_weight(&mut out, i, w);
            }
            out
        };
        let has_copies = copy_of.iter().enumerate().any(|(i, &c)| c != i);
        // With periodic copies every point's weights are given (merged);
        // otherwise only where they are not the slave basis.
        let test: Option<Vec<Vec<(usize, f64)>>> = match test {
            Some(t) => Some(t.into_iter().map(|p| merged(&mut p.into_iter())).collect()),
            None if has_copies => Some(
                points
                    .iter()
                    .map(|p| {
                        merged(
                            &mut p
                                .conn
                                .iter()
                                .zip(&p.basis)
                                .map(|(&i, &n)| (i, p.weight * n)),
                        )
                    })
                    .collect(),
            ),
            None => None,
        };
        let mut node_points = vec![Vec::new(); n_nodes];
        let mut lumped_area = vec![0.0; n_nodes];
        for (id, p) in points.iter().enumerate() {
            let pairs: Vec<(usize, f64)> = match &test {
                Some(t) => t[id].clone(),
                None => p
                    .conn
                    .iter()
                    .zip(&p.basis)
                    .map(|(&i, &n)| (i, p.weight * n))
                    .collect(),
            };
            for (i, w) in pairs {
                node_points[i].push(id);
                lumped_area[i] += w;
            }
        }
        PointSet {
            owner: points.iter().map(|p| copy_of[owner_of(p)]).collect(),
            points,
            node_points,
            test,
            lumped_area,
        }
    }
}

/// The contact zone `{ξ : p_h(ξ) > 0}` on the slave surface, with the
/// pressure indicator interpolated from the lumped values,
/// `p_h = Σ_I (λN^I − εN g^I) R^I`: inside it is the contact pressure,
/// outside (scaled by −εN) the weighted gap, so its zero crossing locates
/// the contact edge inside an element instead of at a control point (the
/// nodal active set of the mechanical phase still places it about half an
/// element inside the exact one). In 2D a union of parameter intervals of
/// the slave face elements.
#[derive(Clone, Debug, Default)]
pub struct ContactZone {
    /// `(slave face element, ξ_start, ξ_end)`.
    pub intervals: Vec<(usize, f64, f64)>,
    /// Length of the zone projected on the mean plane (x), in the current
    /// configuration (scaled).
    pub projected_length: f64,
    /// Mean gap over the slave surface (scaled), penetrations counted as 0.
    pub mean_gap: f64,
    /// The lumped areas `⟨N^I⟩` over the whole surface (4.8).
    pub surface_area: Vec<f64>,
    /// Every edge located by the near-edge asymptotics
    /// (`ContactInterface::locate_edge`), none at the indicator's crossing.
    pub edges_fitted: bool,
}

/// Zero crossings of the pressure indicator are sought between this many
/// samples per slave element (more than the ≤ p roots a degree-p element
/// polynomial can have close together).
const ZONE_SAMPLES: usize = 16;

/// Gauss points per element in the means of the contact edge's asymptotics
/// ([`ContactInterface::locate_edge`]).
const EDGE_POINTS: usize = 24;

/// Elements that the ranges in and out of contact on both sides of an edge
/// must span for the edge to be fitted to the asymptotics
/// ([`ContactInterface::locate_edge`]).
const EDGE_MIN_RANGE: f64 = 4.0;

/// Sub-cells per slave element and direction on which the 3D contact zone of
/// the thermal phase is integrated (midpoint rule in the elements at its edge).
const ZONE_CELLS: usize = 8;

/// Unknowns per node in 3D: `(ux, uy, uz, θ)`.
const NF_3D: usize = 4;

/// Sub-cells per slave element and direction on which the 3D contact area
/// is measured (midpoint rule on the interpolated pressure indicator).
const AREA_SAMPLES: usize = 16;

/// The motion of a breakpoint `ξb` between two master pieces where the gap's
/// gradient jumps (two orthogonal projections at equal distance): it adds
/// `−N^I J (∇g_L − ∇g_R) ⊗ (∇g_L − ∇g_R) / ∂ξ(g_L − g_R)` to `H^I`, since
/// `∂ξb/∂u = −(∇g_L − ∇g_R) / ∂ξ(g_L − g_R)` (segment-based integration).
#[derive(Clone, Debug)]
struct BreakTerm {
    /// Slave face nodes and their `N^I(ξb) · J(ξb)`.
    nodes: Vec<(usize, f64)>,
    /// Unknowns of the gradient jump.
    dofs: Vec<(usize, usize)>,
    /// `∇g_L − ∇g_R` over `dofs`.
    jump: Vec<f64>,
    /// `∂ξ(g_L − g_R)`.
    slope: f64,
}

/// One side of a [`BreakTerm`]: the unknowns, the gap's gradient over them
/// and `∂g/∂x_s` ([`ContactInterface::break_side`]).
type BreakSide = (Vec<(usize, usize)>, Vec<f64>, Vec<f64>);

impl BreakTerm {
    /// Adds `w` times the term, `−(∇g_L − ∇g_R) ⊗ (∇g_L − ∇g_R) / ∂ξ(g_L − g_R)`,
    /// to the `nd × nd` matrix `h` over `dofs` (its unknowns outside them
    /// left out).
    fn add_to(&self, w: f64, dofs: &[(usize, usize)], h: &mut [f64]) {
        let nd = dofs.len();
        let map: Vec<Option<usize>> = self
            .dofs
            .iter()
            .map(|d| dofs.binary_search(d).ok())
            .collect();
        for (a, ia) in map.iter().enumerate() {
            let Some(ia) = *ia else { continue };
            for (b, ib) in map.iter().enumerate() {
                let Some(ib) = *ib else { continue };
                h[ia * nd + ib] -= w * self.jump[a] * self.jump[b] / self.slope;
            }
        }
    }

    /// The term at a point where the closest point passes from master piece
    /// L to R: `sides` are each piece's unknowns, gap gradient over them and
    /// `∂g/∂x_s` (its normal); `tangent` the slave's current tangent across
    /// the boundary, from L towards R; `nodes` the slave nodes' weights.
    /// `None` where the normals agree (the gap's gradient is continuous).
    fn new(nodes: Vec<(usize, f64)>, sides: [BreakSide; 2], tangent: &[f64]) -> Option<Self> {
        let dn: Vec<f64> = sides[0]
            .2
            .iter()
            .zip(&sides[1].2)
            .map(|(l, r)| l - r)
            .collect();
        if dn.iter().map(|v| v * v).sum::<f64>().sqrt() < 1e-8 {
            return None;
        }
        let slope: f64 = dn.iter().zip(tangent).map(|(d, t)| d * t).sum();
        // A boundary along which the normals' jump lies (no crossing) or a
        // state that is not finite: no term.
        let scale = dn.iter().map(|v| v * v).sum::<f64>().sqrt()
            * tangent.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !slope.is_finite() || slope.abs() <= 1e-8 * scale {
            return None;
        }
        let mut dofs: Vec<(usize, usize)> = sides[0].0.iter().chain(&sides[1].0).copied().collect();
        dofs.sort_unstable();
        dofs.dedup();
        let mut jump = vec![0.0; dofs.len()];
        for (side, sign) in [(&sides[0], 1.0), (&sides[1], -1.0)] {
            for (d, g) in side.0.iter().zip(&side.1) {
                let k = dofs.binary_search(d).expect("dof of a side");
                jump[k] += sign * g;
            }
        }
        Some(BreakTerm {
            nodes,
            dofs,
            jump,
            slope,
        })
    }
}

impl ContactInterface {
    /// Sets up the interface between face (`dir`, `side`) of the slave patch
    /// and of the master patch (both given with their global node offsets),
    /// in scaled units (settings from [`ContactSettings::scaled`]).
    pub fn new(
        slave: (&ThbPatch, usize, usize, Side),
        master: (&ThbPatch, usize, usize, Side),
        settings: ContactSettings,
        period: Option<f64>,
    ) -> Result<Self> {
        settings.validate()?;
        let (sp, soff, sdir, sside) = slave;
        let (mp, moff, mdir, mside) = master;
        let (slave_face, sidx) = sp.face(sdir, sside);
        let slave_face = Arc::new(slave_face);
        let (master_face, midx) = mp.face(mdir, mside);
        let dim = mp.param_dim();
        if !(2..=3).contains(&dim) || sp.param_dim() != dim {
            return Err(Error::Geometry(format!(
                "contact needs two bodies of dimension 2 or 3 (got {} and {})",
                sp.param_dim(),
                dim
            )));
        }
        let slave_nodes: Vec<usize> = sidx.iter().map(|i| i + soff).collect();
        let master_nodes: Vec<usize> = midx.iter().map(|i| i + moff).collect();
        let local_of = |g: usize| {
            slave_nodes
                .iter()
                .position(|&n| n == g + soff)
                .expect("face node")
        };
        let mut points = Vec::new();
        let mut lumped = vec![0.0; slave_nodes.len()];
        let mut node_points = vec![Vec::new(); slave_nodes.len()];
        let mut h_min = f64::INFINITY;
        for (e, fe) in sp
            .face_quadrature(sdir, sside, settings.interface_points)
            .into_iter()
            .enumerate()
        {
            let conn: Vec<usize> = fe.conn.iter().map(|&c| local_of(c)).collect();
            // The element's size: its length (2D) or the root of its area (3D).
            let len: f64 = fe.points.iter().map(|q| q.weight).sum();
            h_min = h_min.min(len.powf(1.0 / (dim - 1) as f64));
            for q in fe.points {
                let id = points.len();
                for (a, &i) in conn.iter().enumerate() {
                    lumped[i] += q.weight * q.r[a];
                    node_points[i].push(id);
                }
                points.push(SlavePoint {
                    element: e,
                    conn: conn.clone(),
                    basis: q.r,
                    weight: q.weight,
                    piece: None,
                });
            }
        }
        let owner = points.iter().map(owner_of).collect();
        if lumped.iter().any(|&a| a <= 0.0) {
            return Err(Error::Geometry(
                "a lumped mortar area ⟨N^I⟩ is not positive".into(),
            ));
        }
        // The master's outward normal: in 2D the tangent (increasing
        // parameter) turned counter-clockwise if the body lies to its right;
        // in 3D `a_1 × a_2` if it points out of the body.
        let fq = mp.face_quadrature(mdir, mside, 2);
        let q = &fq[fq.len() / 2].points[0];
        let nrm = q.normal;
        let outward = if dim == 2 {
            let master_curve = MasterCurve {
                face: &master_face,
                points: master_face.control_points(),
                pieces: None,
            };
            let eta = q.xi[1 - mdir];
            let tangent = master_curve.eval(master_curve.locate(eta), eta)[1];
            -tangent[1] * nrm[0] + tangent[0] * nrm[1]
        } else {
            let surface = MasterSurface {
                face: &master_face,
                points: master_face.control_points(),
                pieces: None,
            };
            let dirs: Vec<usize> = (0..3).filter(|&d| d != mdir).collect();
            let eta = [q.xi[dirs[0]], q.xi[dirs[1]]];
            let [a1, a2] = projection3d::SurfaceEvaluator::new(surface)
                .at(master_face.locate(&eta), eta)
                .a
                .map(Vector3::from);
            a1.cross(&a2).dot(&Vector3::from(nrm))
        };
        let normal_sign = if outward > 0.0 { 1.0 } else { -1.0 };
        let c0_master = master_face.knots().iter().any(|kv_m| {
            kv_m.degree() == 1
                || kv_m
                    .breaks()
                    .iter()
                    .skip(1)
                    .take(kv_m.n_elements().saturating_sub(1))
                    .any(|&u| kv_m.multiplicity(u) >= kv_m.degree())
        });
        // In 3D "auto" is element-based: the clipping (segments::Segmenter::
        // cells) costs projections of a sample grid per slave element
        // whenever the cells are made, and is asked for by name. On
        // degree-1 masters it solves the egg box where element-based
        // points stall, but fails earlier on a finer mesh (docs/3d.md,
        // "Stop 64").
        let segmenter = match settings.integration {
            Integration::Segment => true,
            Integration::Auto => c0_master && dim == 2,
            Integration::Element => false,
        }
        .then(|| Segmenter::new(Arc::clone(&slave_face), settings.interface_points));
        let n_s = slave_nodes.len();
        let eps_n = settings.mechanical_penalty.unwrap_or(1.0) / h_min;
        let eps_t = match settings.thermal {
            ThermalContact::Constraint {
                penalty: Some(e), ..
            } => e,
            _ => 10.0 / h_min,
        };
        Ok(ContactInterface {
            dim,
            slave_ref: sidx.iter().map(|&i| sp.control_points()[i]).collect(),
            master_ref: midx.iter().map(|&i| mp.control_points()[i]).collect(),
            master_face: Arc::new(master_face),
            settings,
            slave_nodes,
            master_nodes,
            points,
            lumped_area: lumped,
            node_points,
            test: None,
            owner,
            copy_of: (0..n_s).collect(),
            period,
            normal_sign,
            eps_n,
            e_star: None,
            eps_t,
            state: Vec::new(),
            lambda_n: vec![0.0; n_s],
            lambda_t: vec![0.0; n_s],
            active: vec![false; n_s],
            frozen: None,
            zone: None,
            mechanical_points: None,
            slave_face,
            band: vec![BTreeSet::new(); n_s],
            touching: None,
            coupled: vec![false; n_s],
            segmenter,
            breakpoints: Vec::new(),
            crossings: Vec::new(),
            segmented_at: Vec::new(),
            cell_tolerance: CELL_MOTION_SHARE * h_min,
            clipping: Clipping::default(),
            projected_at: Vec::new(),
            break_terms: Vec::new(),
            curvature: true,
        })
    }

    /// Re-segments the slave surface for the current configuration
    /// (segment-based integration; `slave_cur`: the slave face's current
    /// control points): new points, and which points each slave node and
    /// each continuum element sees.
    fn segment(
        &mut self,
        slave_cur: &[[f64; 3]],
        curve: &MasterCurve,
        samples: &MasterSamples,
    ) -> Result<()> {
        let Some(seg) = &self.segmenter else {
            return Ok(());
        };
        let period = self.period;
        let (points, breakpoints) = seg.points(slave_cur, |x| {
            let pr = project(curve, x, None, period, samples)?;
            let image = period.map_or(0, |w| (pr.shift / w).round() as i64);
            Ok((pr.element, image, pr.vertex))
        })?;
        self.take_points(points);
        self.breakpoints = breakpoints;
        Ok(())
    }

    /// Makes `points` the integration points (segment-based integration):
    /// which points each slave node and each continuum element sees. The
    /// lumped areas are the element-based ones (the same integrals).
    fn take_points(&mut self, points: Vec<SlavePoint>) {
        let set = PointSet::new(points, None, &self.copy_of);
        self.owner = set.owner;
        self.node_points = set.node_points;
        self.test = set.test;
        self.points = set.points;
    }

    /// The [`BreakTerm`]s of the current breakpoints.
    fn break_terms(&self, state: &[f64], curve: &MasterCurve) -> Vec<BreakTerm> {
        let Some(seg) = &self.segmenter else {
            return Vec::new();
        };
        let face = seg.face();
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        let mut out = Vec::new();
        for b in &self.breakpoints {
            let (l, r) = b.pieces;
            if l.2 || r.2 {
                // A corner on either side: the gap's gradient is continuous there.
                continue;
            }
            face.element_basis_into(b.element, &[b.xi], 1, &mut scratch, &mut basis);
            let (mut x, mut dx, mut dx_ref) = ([0.0; 2], [0.0; 2], [0.0; 2]);
            for (a, &c) in basis.indices.iter().enumerate() {
                for k in 0..2 {
                    let cur = self.slave_coordinate(c, k, state);
                    x[k] += basis.values[a] * cur;
                    dx[k] += basis.d1[a][0] * cur;
                    dx_ref[k] += basis.d1[a][0] * self.slave_ref[c][k];
                }
            }
            let shift = |piece: (usize, i64, bool)| self.period.map_or(0.0, |w| piece.1 as f64 * w);
            let (Some(pl), Some(pr)) = (
                project_on_element(curve, x, l.0, shift(l)),
                project_on_element(curve, x, r.0, shift(r)),
            ) else {
                continue;
            };
            let sides = [pl, pr].map(|p| {
                let st =
                    self.point_state(state, (&basis.values, &basis.indices), p, Needs::Mechanical);
                self.break_side(&basis.indices, st)
            });
            let jac = dx_ref[0].hypot(dx_ref[1]);
            let mut nodes: Vec<(usize, f64)> = Vec::new();
            for (&c, &n) in basis.indices.iter().zip(&basis.values) {
                add_weight(&mut nodes, self.copy_of[c], n * jac);
            }
            out.extend(BreakTerm::new(nodes, sides, &dx));
        }
        out
    }

    /// One side of a [`BreakTerm`]: the unknowns of the point of slave
    /// nodes `conn` whose state on that side's master piece is `st`, the
    /// gap's gradient over them and `∂g/∂x_s` (the sum of the slave
    /// displacements' gradients: the normal).
    fn break_side(&self, conn: &[usize], st: PointState) -> BreakSide {
        let nf = self.dim + 1;
        let mut dofs = Vec::new();
        for n in conn
            .iter()
            .map(|&c| self.slave_nodes[c])
            .chain(st.master.iter().map(|&j| self.master_nodes[j]))
        {
            dofs.extend((0..nf).map(|f| (n, f)));
        }
        let normal = (0..self.dim)
            .map(|k| (0..conn.len()).map(|a| st.gap.grad[nf * a + k]).sum())
            .collect();
        (dofs, st.gap.grad, normal)
    }

    /// The [`BreakTerm`]s of the 3D segmentation's [`Crossing`]s at the
    /// slave nodes in contact (`active`).
    fn crossing_terms(
        &self,
        state: &[f64],
        slave_cur: &[[f64; 3]],
        (surface, search): (&MasterSurface, &MasterSearch),
        active: &[bool],
    ) -> Vec<BreakTerm> {
        self.crossings
            .par_iter()
            .filter(|c| c.point.conn.iter().any(|&n| active[self.copy_of[n]]))
            .filter_map(|c| {
                let sp = &c.point;
                let x = sp.position(slave_cur);
                let mut tangent = [0.0; 3];
                for (a, &n) in sp.conn.iter().enumerate() {
                    for k in 0..3 {
                        tangent[k] += c.normal_basis[a] * slave_cur[n][k];
                    }
                }
                let sides = c.pieces.map(|piece| {
                    let pr = projection3d::project_on_element(surface, search, x, piece);
                    let st = self.surface_point_state(state, sp, pr, Needs::Mechanical);
                    self.break_side(&sp.conn, st)
                });
                let mut nodes: Vec<(usize, f64)> = Vec::new();
                for (&c, &n) in sp.conn.iter().zip(&sp.basis) {
                    add_weight(&mut nodes, self.copy_of[c], n * sp.weight);
                }
                BreakTerm::new(nodes, sides, &tangent)
            })
            .collect()
    }

    /// The slave face (reference configuration), its control points in the
    /// order of `slave_nodes`.
    pub fn slave_face(&self) -> &ThbPatch {
        &self.slave_face
    }

    /// The master face (reference configuration), its control points in the
    /// order of `master_nodes`.
    pub fn master_face(&self) -> &ThbPatch {
        &self.master_face
    }

    /// Number of slave control points (= multipliers per family).
    pub fn n_slave(&self) -> usize {
        self.slave_nodes.len()
    }

    /// Whether slave control point `i` is a periodic copy: its multipliers
    /// are placeholders held at zero, and its node's (`copy_of`) carry the
    /// merged test function; its accessors report that node's values.
    pub fn is_copy(&self, i: usize) -> bool {
        self.copy_of[i] != i
    }

    /// The slave node that carries control point `i`'s multipliers (`i`
    /// itself unless it is a periodic copy, [`ContactInterface::is_copy`]).
    pub fn copy_of(&self, i: usize) -> usize {
        self.copy_of[i]
    }

    /// Merges the periodic copies among the slave control points: `ties`
    /// are pairs of global nodes tied by the periodic conditions. The open
    /// basis has a control point on each seam face where the periodic slave
    /// space has one function, `N^I + N^J`; with a multiplier on each, a
    /// contact line along a seam direction (ridges, full contact) gave two
    /// constraints where the space holds one, dependent wherever the master
    /// represents the gap in the same space (matching meshes in that
    /// direction, or flat on flat): a singular system. One multiplier per
    /// tie group, on the merged test function, is the lumped mortar (4.8)
    /// of the periodic space.
    pub fn merge_periodic_copies(&mut self, ties: impl IntoIterator<Item = (usize, usize)>) {
        let n = self.n_slave();
        let local: std::collections::HashMap<usize, usize> = self
            .slave_nodes
            .iter()
            .enumerate()
            .map(|(i, &g)| (g, i))
            .collect();
        // Union-find over the slave control points, the smallest index the root.
        let mut root: Vec<usize> = (0..n).collect();
        fn find(root: &mut [usize], mut i: usize) -> usize {
            while root[i] != i {
                root[i] = root[root[i]];
                i = root[i];
            }
            i
        }
        for (a, b) in ties {
            let (Some(&a), Some(&b)) = (local.get(&a), local.get(&b)) else {
                continue;
            };
            let (ra, rb) = (find(&mut root, a), find(&mut root, b));
            if ra != rb {
                root[ra.max(rb)] = ra.min(rb);
            }
        }
        let copy_of: Vec<usize> = (0..n).map(|i| find(&mut root, i)).collect();
        if copy_of == self.copy_of {
            return;
        }
        self.copy_of = copy_of;
        let set = PointSet::new(std::mem::take(&mut self.points), None, &self.copy_of);
        self.swap_points(set);
        self.state.clear();
    }

    /// The slave and master face control points in the configuration
    /// `state` (`dim + 1` components per node).
    fn current_positions(&self, state: &[f64]) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let (dim, nf) = (self.dim, self.dim + 1);
        let cur = |nodes: &[usize], refx: &[[f64; 3]]| -> Vec<[f64; 3]> {
            nodes
                .iter()
                .zip(refx)
                .map(|(&n, x)| {
                    std::array::from_fn(|k| {
                        if k < dim {
                            x[k] + state[n * nf + k]
                        } else {
                            0.0
                        }
                    })
                })
                .collect()
        };
        (
            cur(&self.slave_nodes, &self.slave_ref),
            cur(&self.master_nodes, &self.master_ref),
        )
    }

    /// The lumped temperature jump `⟨N^I ϑc⟩ / ⟨N^I⟩` (4.1, 4.8) of every
    /// slave node over its whole support on the slave surface, in the
    /// configuration and at the temperatures of `state` (the state the
    /// contact was last prepared at): for output, where
    /// [`ContactInterface::weighted_jump`] is the thermal contact's own
    /// measure. While the thermal phase integrates over the contact zone
    /// ([`ContactInterface::freeze`]) the zone's points reach only the nodes
    /// in contact; the kept mechanical points are then projected here, so
    /// that the jump is defined at every node, across the gaps too (and the
    /// live points too where their states are not those of `state`'s last
    /// preparation, e.g. cleared by a change of phase). A periodic copy
    /// takes its node's value.
    pub fn surface_jumps(&self, state: &[f64]) -> Result<Vec<f64>> {
        let (points, jumps): (&[SlavePoint], Vec<f64>) = match &self.mechanical_points {
            None if self.state.len() == self.points.len() => (
                &self.points,
                self.state.iter().map(|s| s.jump.value).collect(),
            ),
            None => (&self.points, self.point_jumps(state, &self.points)?),
            Some(set) => (&set.points, self.point_jumps(state, &set.points)?),
        };
        let n = self.n_slave();
        let (mut num, mut den) = (vec![0.0; n], vec![0.0; n]);
        for (sp, jump) in points.iter().zip(jumps) {
            for (&c, &b) in sp.conn.iter().zip(&sp.basis) {
                num[self.copy_of[c]] += sp.weight * b * jump;
                den[self.copy_of[c]] += sp.weight * b;
            }
        }
        Ok((0..n)
            .map(|i| num[self.copy_of[i]] / den[self.copy_of[i]])
            .collect())
    }

    /// The temperature jump `ϑc` (4.1) at each of `points`, projected onto
    /// the master in the configuration `state` (each from no earlier guess).
    fn point_jumps(&self, state: &[f64], points: &[SlavePoint]) -> Result<Vec<f64>> {
        let (slave_cur, master_cur) = self.current_positions(state);
        let face = &*self.master_face;
        let pieces = FacePieces::new(face, &master_cur);
        if self.dim == 3 {
            let surface = MasterSurface {
                face,
                points: &master_cur,
                pieces: Some(&pieces),
            };
            let search = MasterSearch::new(&surface, [self.period, self.period]);
            return points
                .par_iter()
                .map(|sp| {
                    let xs = sp.position(&slave_cur);
                    let pr = match sp.piece {
                        Some(piece) => {
                            projection3d::project_on_element(&surface, &search, xs, piece)
                        }
                        None => projection3d::project(&surface, &search, xs, None)?,
                    };
                    Ok(self
                        .surface_point_state(state, sp, pr, Needs::Values)
                        .jump
                        .value)
                })
                .collect();
        }
        let curve = MasterCurve {
            face,
            points: &master_cur,
            pieces: Some(&pieces),
        };
        let samples = MasterSamples::new(&curve);
        points
            .iter()
            .map(|sp| {
                let xs = sp.position(&slave_cur);
                let pr = project(&curve, [xs[0], xs[1]], None, self.period, &samples)?;
                Ok(self
                    .point_state(state, (&sp.basis, &sp.conn), pr, Needs::Values)
                    .jump
                    .value)
            })
            .collect()
    }

    /// Projects every integration point in the current configuration and
    /// evaluates gap and jump, differentiated as far as the phase `needs`.
    /// `state` holds `dim + 1` components per node.
    pub fn prepare(&mut self, state: &[f64], needs: Needs) -> Result<()> {
        let (slave_cur, master_cur) = self.current_positions(state);
        if self.dim == 3 {
            return self.prepare_3d(state, needs, &slave_cur, &master_cur);
        }
        // The segmentation depends on the positions only: it is kept while
        // they do not move (the thermal phase on a frozen configuration).
        let positions: Vec<[f64; 3]> = slave_cur.iter().chain(&master_cur).copied().collect();
        let resegment = self.segmenter.is_some() && positions != self.segmented_at;
        let face = Arc::clone(&self.master_face);
        let mut previous = std::mem::take(&mut self.state);
        // On a configuration that has not moved (the thermal phase) the
        // projections are the previous ones; only the gaps and jumps are
        // re-evaluated.
        let unmoved =
            !resegment && previous.len() == self.points.len() && positions == self.projected_at;
        // The projections evaluate the curve by its polynomial pieces.
        let pieces = (!unmoved).then(|| FacePieces::new(&face, &master_cur));
        let curve = MasterCurve {
            face: &face,
            points: &master_cur,
            pieces: pieces.as_ref(),
        };
        let samples = (!unmoved).then(|| MasterSamples::new(&curve));
        if resegment && let Some(samples) = &samples {
            self.segment(&slave_cur, &curve, samples)?;
            self.segmented_at = positions.clone();
            // The points moved: no previous projection to start from.
            previous.clear();
        }
        let mut out = Vec::with_capacity(self.points.len());
        for (i, sp) in self.points.iter().enumerate() {
            let pr = match &samples {
                None => previous[i].projection,
                Some(samples) => {
                    let xs = sp.position(&slave_cur);
                    let guess = previous.get(i).map(|s| s.projection.eta);
                    project(&curve, [xs[0], xs[1]], guess, self.period, samples)?
                }
            };
            out.push(self.point_state(state, (&sp.basis, &sp.conn), pr, needs));
        }
        self.projected_at = positions;
        self.state = out;
        self.break_terms = if matches!(needs, Needs::Mechanical | Needs::Coupled) {
            self.break_terms(state, &curve)
        } else {
            Vec::new()
        };
        Ok(())
    }

    /// [`ContactInterface::prepare`] in 3D: projection onto the master
    /// surface and its periodic images in x and y, element-based points.
    /// The derivatives are evaluated only where the contact elements use
    /// them: at the points of the nodes in contact (their terms; the
    /// others' multiplier rows need the weighted gap only), found from the
    /// values at every point first (the points of the nodes out of contact
    /// keep values only: memory and time where little is in contact).
    fn prepare_3d(
        &mut self,
        state: &[f64],
        needs: Needs,
        slave_cur: &[[f64; 3]],
        master_cur: &[[f64; 3]],
    ) -> Result<()> {
        let face = Arc::clone(&self.master_face);
        let mut previous = std::mem::take(&mut self.state);
        // On a configuration that has not moved the projections are the
        // previous ones; only the gaps and jumps are re-evaluated.
        let positions: Vec<[f64; 3]> = slave_cur.iter().chain(master_cur).copied().collect();
        // The clipped cells are kept while no control point has moved by
        // more than the cell tolerance since they were made
        // ([`CELL_MOTION_SHARE`]; the thermal phase on a frozen
        // configuration does not move at all).
        let tol = self.cell_tolerance;
        let moved = positions.len() != self.segmented_at.len()
            || positions
                .iter()
                .zip(&self.segmented_at)
                .any(|(a, b)| (0..3).any(|k| (a[k] - b[k]).abs() > tol));
        let resegment = self.segmenter.is_some() && moved;
        let unmoved =
            !resegment && previous.len() == self.points.len() && positions == self.projected_at;
        // The projections evaluate the surface by its polynomial pieces.
        let pieces = (!unmoved).then(|| FacePieces::new(&face, master_cur));
        let surface = MasterSurface {
            face: &face,
            points: master_cur,
            pieces: pieces.as_ref(),
        };
        let search = MasterSearch::new(&surface, [self.period, self.period]);
        if resegment && let Some(seg) = &self.segmenter {
            let (points, crossings, clipping) =
                seg.cells(slave_cur, &surface, &search, self.period.is_some())?;
            self.take_points(points);
            self.crossings = crossings;
            self.clipping = clipping;
            self.segmented_at = positions.clone();
            // The points moved: no previous projection to start from.
            previous.clear();
        }
        let this = &*self;
        let out = this
            .points
            .par_iter()
            .enumerate()
            .map(|(i, sp)| -> Result<PointState> {
                let last = previous.get(i).and_then(|s| s.surface);
                let pr = match last {
                    Some(pr) if unmoved => pr,
                    _ => {
                        let xs = sp.position(slave_cur);
                        match sp.piece {
                            Some(piece) => {
                                projection3d::project_on_element(&surface, &search, xs, piece)
                            }
                            None => {
                                let guess = last.as_ref().map(Guess::from);
                                projection3d::project(&surface, &search, xs, guess)?
                            }
                        }
                    }
                };
                Ok(this.surface_point_state(state, sp, pr, Needs::Values))
            })
            .collect::<Result<Vec<_>>>()?;
        self.projected_at = positions;
        self.state = out;
        self.break_terms = Vec::new();
        if needs == Needs::Values {
            return Ok(());
        }
        // The nodes in contact at these values (`is_active` reads them), as
        // the contact elements will find them.
        let active: Vec<bool> = (0..self.n_slave()).map(|i| self.is_active(i)).collect();
        let mut wanted = vec![false; self.points.len()];
        for i in (0..self.n_slave()).filter(|&i| active[i]) {
            for &q in &self.node_points[i] {
                wanted[q] = true;
            }
        }
        // The continuum method's points: any of their nodes in contact.
        if self.settings.thermal_method == ThermalMethod::Continuum {
            for (q, sp) in self.points.iter().enumerate() {
                wanted[q] |= sp.conn.iter().any(|&c| active[c]);
            }
        }
        let this = &*self;
        let derived: Vec<(usize, PointState)> = wanted
            .par_iter()
            .enumerate()
            .filter(|(_, w)| **w)
            .map(|(q, _)| {
                let pr = this.state[q].surface.expect("projected above");
                (
                    q,
                    this.surface_point_state(state, &this.points[q], pr, needs),
                )
            })
            .collect();
        for (q, st) in derived {
            self.state[q] = st;
        }
        // The crossings' terms stand for the cells' motion: only where
        // they moved (kept cells make the residual smooth, its tangent
        // the points' alone).
        if matches!(needs, Needs::Mechanical | Needs::Coupled) && resegment {
            self.break_terms = self.crossing_terms(state, slave_cur, (&surface, &search), &active);
        }
        Ok(())
    }

    /// Gap and jump at slave point `sp` projected at `pr` (3D),
    /// differentiated as far as `needs`.
    fn surface_point_state(
        &self,
        state: &[f64],
        sp: &SlavePoint,
        pr: SurfaceProjection,
        needs: Needs,
    ) -> PointState {
        let face = &self.master_face;
        let geo = SurfacePointGeometry::new(
            face,
            &pr,
            self.normal_sign,
            sp.basis.clone(),
            sp.conn.iter().map(|&c| self.slave_ref[c]).collect(),
        );
        let master = face.elements()[pr.element].functions.clone();
        let mut z = Vec::with_capacity(geo.n_local());
        for n in sp
            .conn
            .iter()
            .map(|&c| self.slave_nodes[c])
            .chain(master.iter().map(|&j| self.master_nodes[j]))
        {
            z.extend_from_slice(&state[n * NF_3D..(n + 1) * NF_3D]);
        }
        let (gap, jump) = crate::contact::kinematics3d::differentiate(&geo, &z, needs);
        PointState {
            master,
            projection: Projection::default(),
            surface: Some(pr),
            gap,
            jump,
        }
    }

    /// Gap and jump at a slave point (basis values and face nodes) whose
    /// projection is `pr`, differentiated as far as `needs`.
    fn point_state(
        &self,
        state: &[f64],
        (basis, conn): (&[f64], &[usize]),
        pr: Projection,
        needs: Needs,
    ) -> PointState {
        let p = self.master_face.knots()[0].degree();
        let master = self.master_face.elements()[pr.element].functions.clone();
        let geo = PointGeometry {
            slave_basis: basis.to_vec(),
            slave_x: conn
                .iter()
                .map(|&c| [self.slave_ref[c][0], self.slave_ref[c][1]])
                .collect(),
            master_x: master
                .iter()
                .map(|&j| [self.master_ref[j][0] + pr.shift, self.master_ref[j][1]])
                .collect(),
            master_w: master
                .iter()
                .map(|&j| self.master_face.weights()[j])
                .collect(),
            master_ders: self.master_face.curve_element_ders(pr.element, pr.eta, p),
            normal_sign: self.normal_sign,
            clamped: pr.clamped,
            vertex: pr.vertex,
        };
        let mut z = Vec::with_capacity(geo.n_local());
        for n in conn
            .iter()
            .map(|&c| self.slave_nodes[c])
            .chain(master.iter().map(|&j| self.master_nodes[j]))
        {
            z.extend_from_slice(&state[n * 3..n * 3 + 3]);
        }
        let (gap, jump) = differentiate(&geo, &z, needs);
        PointState {
            gap,
            jump,
            master,
            projection: pr,
            surface: None,
        }
    }

    /// The positions in a contact element's unknowns (`index`) of point
    /// `q`'s [`ContactInterface::point_dofs`], in their order (`None`:
    /// not an unknown of the element): one search per node.
    fn point_map(&self, q: usize, index: &DofIndex, map: &mut Vec<Option<usize>>) {
        let nf = self.dim + 1;
        map.clear();
        let slave = self.points[q].conn.iter().map(|&c| self.slave_nodes[c]);
        let master = self.state[q].master.iter().map(|&j| self.master_nodes[j]);
        for n in slave.chain(master) {
            let at = index.nodes.binary_search(&n).ok();
            map.extend((0..nf).map(|f| at.zip(index.slot[f]).map(|(a, s)| a * index.per_node + s)));
        }
    }

    /// Local unknowns `(node, field)` of integration point `q`, in the order of its kinematics.
    fn point_dofs(&self, q: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        let nf = self.dim + 1;
        let slave = self.points[q].conn.iter().map(|&c| self.slave_nodes[c]);
        let master = self.state[q].master.iter().map(|&j| self.master_nodes[j]);
        slave
            .chain(master)
            .flat_map(move |n| (0..nf).map(move |f| (n, f)))
    }

    /// Whether the current projections stay within the coupling band of the
    /// pattern; if not, widens or renews the bands and returns `true` where the
    /// pattern changed.
    ///
    /// A node that sees master elements outside its band gets the master
    /// elements its points see now with their neighbours (`p + 1` elements on
    /// either side on 2D curves, the touching elements on 3D surfaces,
    /// [`touching_elements`]); where its band would then exceed
    /// [`BAND_RENEWAL_FACTOR`] times those, they replace it. Where that changes
    /// the pattern, every coupled node's band over that bound is renewed so.
    ///
    /// Bounded: a node's contact block is dense in its band (the augmented
    /// Lagrangian's `εN G Gᵀ / A`), and a band that kept every element an
    /// iterate's points had seen held the far projections of a level's first
    /// increments for good (the steep height map's second level at 30 kPa:
    /// 3.5e9 block entries, where the bands of the converging iterates'
    /// projections take 0.48e9; docs/3d.md, "Stop 106"). Widened within the
    /// bound: renewed every time, bands whose points move to and fro across
    /// an element boundary changed the pattern at every iteration.
    pub fn update_band(&mut self) -> bool {
        let out: Vec<bool> = (0..self.n_slave()).map(|i| self.outgrown(i)).collect();
        if !out.contains(&true) {
            return false;
        }
        let changed = (0..self.n_slave()).any(|i| out[i] && self.coupled[i]);
        if self.dim == 3 && self.touching.is_none() {
            let periodic = self.period.is_some();
            self.touching = Some(touching_elements(&self.master_face, periodic));
        }
        // The bands of the nodes the pattern couples enter it; the others'
        // are renewed when they outgrow them.
        let renewed = |i: usize| out[i] || (changed && self.coupled[i]);
        for i in (0..self.n_slave()).filter(|&i| renewed(i)) {
            let fresh = self.fresh_band(i);
            let bound = BAND_RENEWAL_FACTOR * fresh.len();
            if out[i] && self.band[i].union(&fresh).count() <= bound {
                self.band[i].extend(fresh);
            } else if out[i] || self.band[i].len() > bound {
                self.band[i] = fresh;
            }
        }
        changed
    }

    /// The master functions of the elements that slave node `i`'s points see
    /// and of their neighbours: on 2D curves `p + 1` elements on either side
    /// (across the seam for periodic masters); on 3D surfaces the elements
    /// touching them in the parameter plane ([`touching_elements`], across
    /// the seams of a periodic master). In 3D the band grows with its area,
    /// and wider margins made the contact blocks dominate the sparse pattern
    /// (egg box at 100 kPa, two adaptive levels: one element width 47 M
    /// element-block entries against 23 M in the bulk, touching elements
    /// 28 M; `p + 1`, as on 2D curves, more still).
    fn fresh_band(&self, i: usize) -> BTreeSet<usize> {
        let els = self.master_face.elements();
        let seen: BTreeSet<usize> = self.node_points[i]
            .iter()
            .map(|&q| self.state[q].master_element())
            .collect();
        let seen = seen.into_iter();
        if let Some(touching) = &self.touching {
            return seen
                .flat_map(|e| touching[e].iter())
                .flat_map(|&f| els[f].functions.iter().copied())
                .collect();
        }
        let n_el = els.len() as i64;
        let widen = self.master_face.knots()[0].degree() as i64 + 1;
        let period = self.period;
        seen.flat_map(|e| e as i64 - widen..=e as i64 + widen)
            .filter_map(|k| match period {
                Some(_) => Some(k.rem_euclid(n_el)),
                None => (0..n_el).contains(&k).then_some(k),
            })
            .flat_map(|f| els[f as usize].functions.iter().copied())
            .collect()
    }

    /// Whether slave node `i`'s points need master functions outside its band.
    fn outgrown(&self, i: usize) -> bool {
        self.node_points[i]
            .iter()
            .flat_map(|&q| self.state[q].master.iter())
            .any(|f| !self.band[i].contains(f))
    }

    /// Adds the nodes in contact and their neighbours (the slave nodes
    /// sharing an integration point) that the pattern does not couple;
    /// `true` if the pattern changed. With `reset`, the coupled nodes are
    /// exactly the nodes in contact and their neighbours.
    ///
    /// The neighbours of every node in contact, not only of the nodes
    /// entering the pattern: in 3D a point's Hessians are assembled in the
    /// element of its carrier, the node of largest test weight there
    /// ([`ContactInterface::element`]), which may be a neighbour without an
    /// element of its own unless the pattern couples it. Until stop 65 a
    /// node first coupled as a neighbour kept its other neighbours out of
    /// the pattern when it came into contact, and the Hessians its points
    /// had there were dropped: on the degree-1 egg box (`[12, 12, 6]`,
    /// 30 kPa) half the points of the nodes in contact had such a
    /// neighbour, and the tangent was 2.8e-4 off its finite differences
    /// (docs/3d.md, "Stop 65").
    pub fn cover_active(&mut self, reset: bool) -> bool {
        let n = self.n_slave();
        let mut coupled = if reset {
            vec![false; n]
        } else {
            self.coupled.clone()
        };
        for i in (0..n).filter(|&i| self.is_active(i)) {
            for &q in &self.node_points[i] {
                for &c in &self.points[q].conn {
                    coupled[self.copy_of[c]] = true;
                }
            }
            coupled[i] = true;
        }
        let changed = coupled != self.coupled;
        self.coupled = coupled;
        changed
    }

    /// Empties the coupling band and the coupled nodes, which the next preparation widens to
    /// what the state then needs ([`ContactInterface::update_band`],
    /// [`ContactInterface::cover_active`]); `true` if they held anything. After a load step
    /// is cut back: its failed iterates may have projected far off, and a band is renewed only
    /// once it exceeds [`BAND_RENEWAL_FACTOR`] times what its node needs, at a change of the
    /// pattern (a node's contact block is dense in the band, so its entries grow with its
    /// square: from rest, the degree-1 egg box's fifth level reached 42–46 M entries against
    /// 21 M from its carried-over state at the same load; docs/3d.md, "Stop 77").
    pub fn reset_coupling(&mut self) -> bool {
        let held = self.coupled.iter().any(|&c| c) || self.band.iter().any(|b| !b.is_empty());
        self.band.iter_mut().for_each(BTreeSet::clear);
        self.coupled.fill(false);
        held
    }

    /// The slave nodes the pattern couples ([`ContactInterface::cover_active`]).
    pub fn coverage(&self) -> &[bool] {
        &self.coupled
    }

    /// Couples the slave nodes of `coverage` (another pattern's), where they
    /// include every node coupled now: the pattern then equals that one's.
    pub fn cover_at_least(&mut self, coverage: &[bool]) {
        let includes = coverage.len() == self.coupled.len()
            && self
                .coupled
                .iter()
                .zip(coverage)
                .all(|(&now, &c)| c || !now);
        if includes {
            self.coupled.copy_from_slice(coverage);
        }
    }

    /// Unknowns `(node, field)` of the contact element of slave node `i`
    /// (multipliers not included), in a fixed order: the fields of the
    /// phase's `unknowns` only (the terms in the others are not assembled);
    /// none for a node the pattern does not couple
    /// ([`ContactInterface::cover_active`]).
    pub fn element_dofs(&self, i: usize, unknowns: Unknowns) -> Vec<(usize, usize)> {
        if !self.coupled[i] {
            return Vec::new();
        }
        let dim = self.dim;
        let fields: Vec<usize> = (0..=dim)
            .filter(|&f| {
                if f < dim {
                    unknowns.mechanical_terms
                } else {
                    unknowns.thermal_terms
                }
            })
            .collect();
        let mut nodes: Vec<usize> = self.node_points[i]
            .iter()
            .flat_map(|&q| self.points[q].conn.iter().map(|&c| self.slave_nodes[c]))
            .chain(self.band[i].iter().map(|&j| self.master_nodes[j]))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
            .into_iter()
            .flat_map(|n| fields.iter().map(move |&f| (n, f)))
            .collect()
    }

    /// Equations of the contact element of slave node `i`: its unknowns, then
    /// λN^I and λθ^I when they are unknowns (`mult_eq`: first equation of each family).
    pub fn element_eqs(
        &self,
        i: usize,
        dofs: &DofMap,
        mult_eq: (Option<usize>, Option<usize>),
        unknowns: Unknowns,
    ) -> Vec<Option<usize>> {
        let mut v: Vec<Option<usize>> = self
            .element_dofs(i, unknowns)
            .into_iter()
            .map(|(n, f)| dofs.eq(n, f))
            .collect();
        if let Some(e) = mult_eq.0 {
            v.push(Some(e + i));
        }
        if let Some(e) = mult_eq.1 {
            v.push(Some(e + i));
        }
        v
    }

    /// The factors of the points' Hessians in the point-major 3D tangent
    /// ([`ContactInterface::element`]), per slave node: `−pN^I` where it is
    /// in contact and the mechanical terms are assembled (the Alart–Curnier
    /// term `−pN^I ⟨N^I H_g⟩`), `−h0^I` where it is in contact and the
    /// mortar thermal terms are (`−h0^I ⟨N^I H_γ⟩`); zero elsewhere. `None`
    /// in 2D, whose elements accumulate the Hessians per node.
    pub fn hessian_weights(&self, unknowns: Unknowns) -> Option<HessianWeights> {
        if self.dim != 3 {
            return None;
        }
        let n = self.n_slave();
        let mechanical = unknowns.mechanical_terms && self.frozen.is_none();
        let thermal =
            unknowns.thermal_terms && self.settings.thermal_method == ThermalMethod::Mortar;
        let mut w = HessianWeights {
            gap: vec![0.0; n],
            jump: vec![0.0; n],
        };
        for i in (0..n).filter(|&i| !self.is_copy(i) && self.is_active(i)) {
            if mechanical && self.curvature {
                w.gap[i] = -self.pressure(i);
            }
            if thermal {
                w.jump[i] = -self.heat_flux(i);
            }
        }
        Some(w)
    }

    /// Leaves the contact's curvature out of the mechanical tangent
    /// (`false`) or puts it back (`true`, the default): the gaps' second
    /// variations weighted by the pressures, `−pN^I ⟨N^I H_g⟩` of the
    /// Alart–Curnier tangent (spec §6), which the tangent of the lumped
    /// constraints keeps otherwise. Under pressures of the order of `E` on a
    /// small spot of a steep surface that term makes the displacement block
    /// indefinite, and Newton's increment from a state out of equilibrium can
    /// follow the resulting saddle far out of the bodies' domain
    /// ([`crate::solve::NonlinearProblem::set_contact_curvature`]; docs/3d.md,
    /// "Stop 103"). The residual does not change.
    pub fn set_curvature(&mut self, on: bool) {
        self.curvature = on;
    }

    /// The node that carries point `q`'s Hessians (the one of largest test
    /// weight there, the first of equals) and their factors
    /// `Σ_I w^I(q) · weights^I` for the gap and the jump.
    fn point_hessian_factors(&self, q: usize, weights: &HessianWeights) -> (usize, f64, f64) {
        let factors = [&weights.gap[..], &weights.jump[..]];
        let (carrier, [cg, cj]) = match &self.test {
            Some(t) => carried(t[q].iter().copied(), factors),
            None => {
                let p = &self.points[q];
                carried(
                    p.conn
                        .iter()
                        .zip(&p.basis)
                        .map(|(&j, &n)| (j, p.weight * n)),
                    factors,
                )
            }
        };
        (carrier, cg, cj)
    }

    /// Weighted gap `g^I` (4.8) at the current state.
    pub fn weighted_gap(&self, i: usize) -> f64 {
        let i = self.copy_of[i];
        let s: f64 = self.node_points[i]
            .iter()
            .map(|&q| self.weight_of(q, i) * self.state[q].gap.value)
            .sum();
        s / self.lumped_area[i]
    }

    /// Lumped mortar temperature jump `γθ^I` (4.8).
    pub fn weighted_jump(&self, i: usize) -> f64 {
        let i = self.copy_of[i];
        let s: f64 = self.node_points[i]
            .iter()
            .map(|&q| self.weight_of(q, i) * self.state[q].jump.value)
            .sum();
        s / self.lumped_area[i]
    }

    fn weight_of(&self, q: usize, i: usize) -> f64 {
        if let Some(t) = &self.test {
            return t[q].iter().find(|(j, _)| *j == i).map_or(0.0, |e| e.1);
        }
        let sp = &self.points[q];
        let a = sp
            .conn
            .iter()
            .position(|&c| c == i)
            .expect("point touches node");
        sp.weight * sp.basis[a]
    }

    /// Contact pressure `pN^I = λN^I − εN g^I` (positive in compression).
    pub fn pressure(&self, i: usize) -> f64 {
        let i = self.copy_of[i];
        if let Some((p, _)) = &self.frozen {
            return p[i];
        }
        self.lambda_n[i] - self.eps_n * self.weighted_gap(i)
    }

    /// Lumped interface heat flux into the slave `h0^I` (scaled), as the
    /// thermal contact model defines it at the current state; zero outside
    /// the active set.
    pub fn heat_flux(&self, i: usize) -> f64 {
        let i = self.copy_of[i];
        if !self.is_active(i) {
            return 0.0;
        }
        let gamma = self.weighted_jump(i);
        match self.settings.thermal {
            ThermalContact::Constraint {
                enforcement: ThermalEnforcement::AugmentedLagrangian,
                ..
            } if self.settings.thermal_method == ThermalMethod::Mortar => {
                self.lambda_t[i] - self.eps_t * gamma
            }
            ThermalContact::Constraint { .. } => -self.eps_t * gamma,
            ThermalContact::Constitutive {
                conductance_coefficient: kt,
                pressure_exponent: a,
            } => -kt * self.pressure(i).max(0.0).powf(a) * gamma,
        }
    }

    /// Whether slave node `i` is in contact: in the mechanical active set,
    /// or, in the thermal phase on a contact zone, whether the zone covers a
    /// part of its support (`⟨N^I⟩` over the zone above 1e-10 of the whole).
    pub fn is_active(&self, i: usize) -> bool {
        let i = self.copy_of[i];
        match (&self.frozen, &self.zone) {
            (Some(_), Some(z)) => self.lumped_area[i] > 1e-10 * z.surface_area[i],
            (Some((_, a)), None) => a[i],
            _ => self.pressure(i) > 0.0,
        }
    }

    /// The pressure indicator of slave node `i`: the contact pressure
    /// `λN^I − εN g^I` where positive, `−εc g^I` otherwise (frozen in the
    /// thermal phase), with the augmentation of the default factor
    /// `εc = E/h` (`ContactInterface::zone_augmentation`) whatever
    /// `mechanical_penalty` is: the contact zone's edges, interpolated from
    /// it, then do not depend on the factor, as the mechanical solution does
    /// not.
    pub fn indicator(&self, i: usize) -> f64 {
        let i = self.copy_of[i];
        match &self.frozen {
            Some((p, _)) => p[i],
            None => {
                let v = self.lambda_n[i] - self.eps_n * self.weighted_gap(i);
                if v > 0.0 {
                    v
                } else {
                    v * self.zone_augmentation() / self.eps_n
                }
            }
        }
    }

    /// `εc`, the augmentation of the indicator out of contact
    /// ([`ContactInterface::indicator`]): `εN` at `mechanical_penalty = 1`.
    fn zone_augmentation(&self) -> f64 {
        self.eps_n / self.settings.mechanical_penalty.unwrap_or(1.0)
    }

    /// `⟨N^I⟩` over the whole slave surface (4.8), also while the thermal
    /// phase integrates over the contact zone.
    pub fn surface_area(&self, i: usize) -> f64 {
        match &self.zone {
            Some(z) => z.surface_area[i],
            None => self.lumped_area[i],
        }
    }

    /// Freezes pressures and the active set (the thermal phase on a frozen
    /// configuration, `state` the solved mechanical one) and moves the
    /// thermal contact integrals onto the contact zone [`ContactZone`]: the
    /// lumped thermal quantities (4.8) become `⟨N^I ·⟩` over the zone, split
    /// at its edges (and at the segments' breakpoints), so that the
    /// conducting area is the zone's to the accuracy of the pressure field.
    /// Only for the constraint models with `thermal_zone` set: the
    /// constitutive model's lumped pressures are forces per full support
    /// (`Σ ⟨N^I⟩ pN^I` is the load), so it keeps the supports.
    pub fn freeze(&mut self, state: &[f64]) {
        self.thaw();
        // Unclamped: outside the active set the indicator is −εN g (a gap);
        // physics clamps at 0.
        let p: Vec<f64> = (0..self.n_slave()).map(|i| self.indicator(i)).collect();
        let a: Vec<bool> = (0..self.n_slave()).map(|i| self.is_active(i)).collect();
        let constraint = matches!(self.settings.thermal, ThermalContact::Constraint { .. });
        if !(self.settings.thermal_zone_in(self.dim) && constraint) {
            self.frozen = Some((p, a));
            return;
        }
        if self.dim == 3 {
            let level = self.contact_level_3d(p.clone(), state);
            let zone = ContactZone {
                intervals: Vec::new(),
                projected_length: level.area(self, state, AREA_SAMPLES),
                mean_gap: self.mean_gap(),
                surface_area: self.lumped_area.clone(),
                edges_fitted: level.edges_fitted(),
            };
            let points = self.zone_points_3d(&p, &level, state);
            self.freeze_on_zone(points, zone, p, a);
            return;
        }
        let mut zone = self.contact_zone(&p, state);
        // A node in contact whose support the interpolated indicator does not
        // reach (a single touching node between deep gaps, e.g. first touch
        // at p = 3) keeps its whole support, as without a zone.
        let face = Arc::clone(&self.slave_face);
        let reached: BTreeSet<usize> = zone
            .intervals
            .iter()
            .flat_map(|&(e, _, _)| face.elements()[e].functions.iter().copied())
            .collect();
        let mut extra: BTreeSet<usize> = BTreeSet::new();
        for (e, el) in face.elements().iter().enumerate() {
            if el
                .functions
                .iter()
                .any(|&i| p[i] > 0.0 && !reached.contains(&i))
            {
                extra.insert(e);
            }
        }
        if !extra.is_empty() {
            zone.intervals.retain(|iv| !extra.contains(&iv.0));
            for &e in &extra {
                let el = &face.elements()[e];
                zone.intervals.push((e, el.lower[0], el.upper[0]));
            }
            zone.intervals
                .sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
            zone.projected_length = self.projected_length(&zone.intervals, state);
        }
        zone.mean_gap = self.mean_gap();
        zone.surface_area = self.lumped_area.clone();
        let rule = GaussLegendre::new(self.settings.interface_points);
        let mut points = Vec::new();
        for &(e, a, b) in &zone.intervals {
            let mut cuts = vec![a];
            cuts.extend(
                self.breakpoints
                    .iter()
                    .filter(|bp| bp.element == e && bp.xi > a && bp.xi < b)
                    .map(|bp| bp.xi),
            );
            cuts.push(b);
            cuts.sort_by(f64::total_cmp);
            for w in cuts.windows(2) {
                interval_points(&self.slave_face, e, (w[0], w[1]), &rule, &mut points);
            }
        }
        self.freeze_on_zone(points, zone, p, a);
    }

    /// The thermal points of the 3D contact zone of `level` (nodal
    /// indicator values `p`, configuration `state`): a slave element whose
    /// [`ZONE_CELLS`]² sub-cell centres all lie in the zone keeps its
    /// (mechanical) Gauss points; one with some in it gets the midpoint rule
    /// on those sub-cells (the zone's edge, fitted to the near-edge
    /// asymptotics (`edge3d`), to a sub-cell); and, as in 2D, an element
    /// holding a node in contact whose support the zone does not reach
    /// keeps its Gauss points. Called on the mechanical points (after
    /// [`ContactInterface::thaw`]).
    fn zone_points_3d(
        &self,
        p: &[f64],
        level: &edge3d::ContactLevel3d,
        state: &[f64],
    ) -> Vec<SlavePoint> {
        let els = self.slave_face.elements();
        let n = ZONE_CELLS;
        // Per element: the sub-cells in the zone (parameters, parametric area).
        let mut inside: Vec<Vec<([f64; 2], f64)>> = vec![Vec::new(); els.len()];
        let mut full = vec![0usize; els.len()];
        level.visit_cells(self, state, n, |e, xi, fraction, _| {
            let el = &els[e];
            let cell = (el.upper[0] - el.lower[0]) * (el.upper[1] - el.lower[1]);
            inside[e].push((xi, fraction * cell / (n * n) as f64));
            if fraction == 1.0 {
                full[e] += 1;
            }
        });
        let reached: BTreeSet<usize> = inside
            .iter()
            .enumerate()
            .filter(|(_, c)| !c.is_empty())
            .flat_map(|(e, _)| els[e].functions.iter().copied())
            .collect();
        let whole: Vec<bool> = els
            .iter()
            .enumerate()
            .map(|(e, el)| {
                full[e] == n * n
                    || el
                        .functions
                        .iter()
                        .any(|&i| p[i] > 0.0 && !reached.contains(&i))
            })
            .collect();
        let mut points: Vec<SlavePoint> = self
            .points
            .iter()
            .filter(|q| whole[q.element])
            .cloned()
            .collect();
        for (e, cells) in inside.iter().enumerate() {
            if !whole[e] && !cells.is_empty() {
                cell_points(&self.slave_face, e, cells.iter().copied(), &mut points);
            }
        }
        points
    }

    /// Moves the thermal contact integrals onto the zone's `points` (the
    /// frozen indicator `p` and active set `a`): see [`ContactInterface::freeze`].
    fn freeze_on_zone(
        &mut self,
        points: Vec<SlavePoint>,
        zone: ContactZone,
        p: Vec<f64>,
        a: Vec<bool>,
    ) {
        // Multipliers on the nodes of positive indicator, slivers handed
        // on: the rule and its reasons at [`zone_test_weights`].
        let test = zone_test_weights(&points, &self.copy_of, &p, &zone.surface_area);
        let set = PointSet::new(points, Some(test), &self.copy_of);
        let mechanical = self.swap_points(set);
        self.mechanical_points = Some(mechanical);
        self.zone = Some(zone);
        self.frozen = Some((p, a));
        // Point states belong to the previous points.
        self.state.clear();
    }

    /// Undoes [`ContactInterface::freeze`]: the mechanical points and a live
    /// active set.
    pub fn thaw(&mut self) {
        if let Some(set) = self.mechanical_points.take() {
            self.swap_points(set);
            self.state.clear();
        }
        self.zone = None;
        self.frozen = None;
    }

    fn swap_points(&mut self, set: PointSet) -> PointSet {
        // The projections belong to the previous points.
        self.projected_at.clear();
        PointSet {
            points: std::mem::replace(&mut self.points, set.points),
            node_points: std::mem::replace(&mut self.node_points, set.node_points),
            test: std::mem::replace(&mut self.test, set.test),
            owner: std::mem::replace(&mut self.owner, set.owner),
            lumped_area: std::mem::replace(&mut self.lumped_area, set.lumped_area),
        }
    }

    /// The contact zone where the indicator interpolated from the nodal
    /// values `ind` is positive, in the configuration `state` (its mean gap
    /// and surface areas left empty), each edge moved to the contact edge of
    /// the near-edge asymptotics ([`ContactInterface::locate_edge`]).
    fn contact_zone(&self, ind: &[f64], state: &[f64]) -> ContactZone {
        let face = &*self.slave_face;
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        let mut eval = |e: usize, xi: f64| -> f64 {
            face.element_basis_into(e, &[xi], 0, &mut scratch, &mut basis);
            basis
                .indices
                .iter()
                .zip(&basis.values)
                .map(|(&c, &n)| n * ind[c])
                .sum()
        };
        // Zero crossings `(element, ξ)` of the interpolated indicator,
        // between samples by bisection, in increasing ξ.
        let mut crossings: Vec<(usize, f64)> = Vec::new();
        let mut start_inside = false;
        for (e, el) in face.elements().iter().enumerate() {
            let (a, b) = (el.lower[0], el.upper[0]);
            let mut left = (a, eval(e, a));
            if a == 0.0 {
                start_inside = left.1 > 0.0;
            }
            for k in 1..=ZONE_SAMPLES {
                let xi = a + (b - a) * k as f64 / ZONE_SAMPLES as f64;
                let right = (xi, eval(e, xi));
                if (left.1 > 0.0) != (right.1 > 0.0) {
                    let (mut lo, mut hi) = (left.0, right.0);
                    // To round-off (a fixed count: a relative width may
                    // lie below the spacing of doubles near ξ).
                    for _ in 0..64 {
                        if hi - lo <= (b - a) * 1e-14 {
                            break;
                        }
                        let m = 0.5 * (lo + hi);
                        if (eval(e, m) > 0.0) == (left.1 > 0.0) {
                            lo = m;
                        } else {
                            hi = m;
                        }
                    }
                    crossings.push((e, 0.5 * (lo + hi)));
                }
                left = right;
            }
        }
        crossings.sort_by(|a, b| a.1.total_cmp(&b.1));
        let found: Vec<f64> = crossings.iter().map(|c| c.1).collect();
        // The ranges in contact alternate with those out of contact.
        let inside_before = |k: usize| start_inside != (k % 2 == 1);
        // Widths (ξ) of the ranges before and after each crossing, across
        // the ends (periodic faces; elsewhere a safe overestimate).
        let n = found.len();
        let width = |k: usize, after: bool| -> f64 {
            match (after, k) {
                (true, k) if k + 1 < n => found[k + 1] - found[k],
                (true, _) => found[0] + 1.0 - found[k],
                (false, 0) => found[0] + 1.0 - found[n - 1],
                (false, k) => found[k] - found[k - 1],
            }
        };
        let located: Vec<Option<f64>> = crossings
            .iter()
            .enumerate()
            .map(|(k, &(e, xi))| {
                let (before, after) = (width(k, false), width(k, true));
                let below = inside_before(k);
                let (inside, outside) = if below {
                    (before, after)
                } else {
                    (after, before)
                };
                self.locate_edge(ind, state, e, xi, below, [inside, outside])
            })
            .collect();
        let mut fitted = located.iter().all(Option::is_some);
        let mut edges: Vec<f64> = located
            .iter()
            .zip(&found)
            .map(|(l, &f)| l.unwrap_or(f))
            .collect();
        // Moved edges keep their order (a spot or gap narrower than the
        // asymptotics' reach keeps the interpolated edges).
        if edges.windows(2).any(|w| w[1] <= w[0]) {
            edges = found;
            fitted = false;
        }
        let mut bounds = vec![0.0];
        bounds.extend(&edges);
        bounds.push(1.0);
        let mut zone = ContactZone::default();
        for (e, el) in face.elements().iter().enumerate() {
            let (a, b) = (el.lower[0], el.upper[0]);
            for (k, w) in bounds.windows(2).enumerate() {
                if start_inside != (k % 2 == 0) {
                    continue;
                }
                let (lo, hi) = (w[0].max(a), w[1].min(b));
                if hi - lo > (b - a) * 1e-13 {
                    zone.intervals.push((e, lo, hi));
                }
            }
        }
        zone.intervals
            .sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        zone.projected_length = self.projected_length(&zone.intervals, state);
        zone.edges_fitted = fitted;
        zone
    }

    /// Whether [`ContactInterface::zone_edges_fitted`] can hold: the 2D
    /// thermal contact zone of the constraint models.
    pub fn zone_edges_can_fit(&self) -> bool {
        let constraint = matches!(self.settings.thermal, ThermalContact::Constraint { .. });
        self.dim == 2 && self.settings.thermal_zone_in(self.dim) && constraint
    }

    /// Whether the thermal phase integrates over a contact zone whose every
    /// edge is fitted to the near-edge asymptotics
    /// (`ContactInterface::locate_edge`) in the configuration `state` (the
    /// frozen zone's, in the thermal phase): the
    /// regime in which the jump's error is that of the fitted edges (2D
    /// constraint models with `thermal_zone`; no edges counts as fitted).
    /// Always `false` in 3D, whose zone's edges are fitted too but whose
    /// adaptive sequence has not been measured in that regime.
    pub fn zone_edges_fitted(&self, state: &[f64]) -> bool {
        if !self.zone_edges_can_fit() {
            return false;
        }
        // The thermal phase's zone, where it is frozen (the same edges).
        if let Some(z) = &self.zone {
            return z.edges_fitted;
        }
        let ind: Vec<f64> = (0..self.n_slave()).map(|i| self.indicator(i)).collect();
        self.contact_zone(&ind, state).edges_fitted
    }

    /// The nodal data of the edge fits (2D [`ContactInterface::locate_edge`],
    /// 3D `edge3d`) for the nodes `index`: `λN^I` where in contact,
    /// `3E* g^J/(4h)` elsewhere (`g^J = −indicator/εc`), `h` the edge
    /// element's size, so that both are pressures of one amplitude `A`.
    fn edge_fit_data(&self, index: &[usize], ind: &[f64], e_star: f64, h: f64) -> Vec<f64> {
        index
            .iter()
            .map(|&c| {
                if ind[c] > 0.0 {
                    ind[c]
                } else {
                    -3.0 * e_star * ind[c] / (self.zone_augmentation() * 4.0 * h)
                }
            })
            .collect()
    }

    /// The contact edge near a zero crossing `ξc` (in slave face element
    /// `e`) of the interpolated indicator, from the near-edge asymptotics of
    /// frictionless elastic contact: pressure `A √s` at a distance `s`
    /// inside, gap `(4A/3E*) t^(3/2)` at a distance `t` outside (the edge of
    /// a Hertzian or Westergaard contact), with `s`, `t` replaced by
    /// `s (1 − s/L)`, `L` the length of the range in or out of contact
    /// (`widths`, in ξ; exact for a Hertzian spot and for the gaps of nearly
    /// full contact). The lumped pressures `λN^I` of the in-contact nodes and
    /// the weighted gaps `g^J` (4.8) of the others are these fields weighted
    /// by their basis functions over their supports; the edge and `A` are
    /// fitted to the nodes whose supports meet the elements within one
    /// element of `ξc` (least squares on `λN^I` and `3E* g^J/(4h)`; distances
    /// are chords of the deformed slave curve), the edge kept on the supports
    /// of the in-contact nodes. The crossing itself lies where the
    /// indicator's augmentation puts it, a fraction of an element inside or
    /// outside the edge. `None` (keep the crossing) without `E*`, without
    /// nodes on both sides, or where a range spans fewer than
    /// [`EDGE_MIN_RANGE`] elements. 2D (slave curves).
    fn locate_edge(
        &self,
        ind: &[f64],
        state: &[f64],
        e: usize,
        xi_c: f64,
        inside_below: bool,
        widths: [f64; 2],
    ) -> Option<f64> {
        let e_star = self.e_star?;
        let face = &*self.slave_face;
        let elements = face.elements();
        let h = elements[e].upper[0] - elements[e].lower[0];
        // The asymptotics hold a few elements from the other edge of the
        // range only: narrower spots and gaps keep the indicator's crossing.
        if widths[0].min(widths[1]) < EDGE_MIN_RANGE * h {
            return None;
        }
        let near = |k: usize| {
            elements[k].upper[0] > xi_c - (1.0 + 1e-6) * h
                && elements[k].lower[0] < xi_c + (1.0 + 1e-6) * h
        };
        let nodes: BTreeSet<usize> = (0..elements.len())
            .filter(|&k| near(k))
            .flat_map(|k| elements[k].functions.iter().copied())
            .collect();
        if !nodes.iter().any(|&c| ind[c] > 0.0) || nodes.iter().all(|&c| ind[c] > 0.0) {
            return None;
        }
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        let current = |c: usize, d: usize| self.slave_coordinate(c, d, state);
        let rule = GaussLegendre::new(EDGE_POINTS);
        // Quadrature of the nodes' supports: (ξ, x, weight·|x'|, N^c of each node).
        let support: BTreeSet<usize> = (0..elements.len())
            .filter(|&k| elements[k].functions.iter().any(|c| nodes.contains(c)))
            .collect();
        let index: Vec<usize> = nodes.iter().copied().collect();
        let mut points: Vec<(f64, [f64; 2], f64, Vec<f64>)> = Vec::new();
        let mut length_e = 0.0;
        for &k in &support {
            let (a, b) = (elements[k].lower[0], elements[k].upper[0]);
            for (&t, &w) in rule.points.iter().zip(&rule.weights) {
                let xi = 0.5 * (a + b) + 0.5 * (b - a) * t;
                face.element_basis_into(k, &[xi], 1, &mut scratch, &mut basis);
                let (mut x, mut dx) = ([0.0; 2], [0.0; 2]);
                let mut n = vec![0.0; index.len()];
                for (q, &c) in basis.indices.iter().enumerate() {
                    for d in 0..2 {
                        x[d] += basis.values[q] * current(c, d);
                        dx[d] += basis.d1[q][0] * current(c, d);
                    }
                    if let Ok(m) = index.binary_search(&c) {
                        n[m] = basis.values[q];
                    }
                }
                let weight = 0.5 * (b - a) * w * dx[0].hypot(dx[1]);
                if k == e {
                    length_e += weight;
                }
                points.push((xi, x, weight, n));
            }
        }
        let area: Vec<f64> = (0..index.len())
            .map(|m| points.iter().map(|p| p.2 * p.3[m]).sum())
            .collect();
        let data = self.edge_fit_data(&index, ind, e_star, length_e);
        let at = |xi: f64| -> Option<[f64; 2]> {
            let k = (0..elements.len())
                .find(|&k| elements[k].lower[0] <= xi && xi <= elements[k].upper[0])?;
            let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
            face.element_basis_into(k, &[xi], 0, &mut scratch, &mut basis);
            let mut x = [0.0; 2];
            for (q, &c) in basis.indices.iter().enumerate() {
                for (d, v) in x.iter_mut().enumerate() {
                    *v += basis.values[q] * current(c, d);
                }
            }
            Some(x)
        };
        // Lengths of the ranges in contact and out of contact (ξ widths in
        // the edge element's length per ξ).
        let widths_len = widths.map(|w| w * length_e / h);
        // Squared misfit of the best amplitude for an edge at ξa (the fixed
        // quadrature smears the kink at ξa over a point spacing; the fields
        // vanish at the edge, so the misfit is continuous in ξa).
        let misfit = |xa: f64| -> Option<f64> {
            let p = at(xa)?;
            let mut model = vec![0.0; index.len()];
            for (xi, x, w, n) in &points {
                let d = (x[0] - p[0]).hypot(x[1] - p[1]);
                let inside = (*xi < xa) == inside_below;
                // The range's finite width: d (1 − d/L) (exact for Hertz
                // and for the gaps of nearly full contact).
                let d = d * (1.0 - d / if inside { widths_len[0] } else { widths_len[1] }).max(0.0);
                for (m, &c) in index.iter().enumerate() {
                    if n[m] == 0.0 || (ind[c] > 0.0) != inside {
                        continue;
                    }
                    model[m] += w
                        * n[m]
                        * if inside {
                            d.sqrt()
                        } else {
                            d * d.sqrt() / length_e
                        };
                }
            }
            model.iter_mut().zip(&area).for_each(|(v, a)| *v /= a);
            amplitude_misfit(&model, &data)
        };
        // The zone stays on the supports of the in-contact nodes (beyond
        // them its test functions would have no in-contact heir).
        let reach = |c: usize| {
            let ks = (0..elements.len()).filter(|&k| elements[k].functions.contains(&c));
            if inside_below {
                ks.map(|k| elements[k].upper[0]).fold(f64::MIN, f64::max)
            } else {
                ks.map(|k| elements[k].lower[0]).fold(f64::MAX, f64::min)
            }
        };
        let in_contact = index.iter().copied().filter(|&c| ind[c] > 0.0);
        let (mut lo, mut hi) = ((xi_c - 1.5 * h).max(0.0), (xi_c + 1.5 * h).min(1.0));
        if inside_below {
            hi = hi.min(in_contact.map(reach).fold(f64::MIN, f64::max));
        } else {
            lo = lo.max(in_contact.map(reach).fold(f64::MAX, f64::min));
        }
        if hi <= lo {
            return None;
        }
        minimize_on(misfit, lo, hi, 96)
    }

    /// Length (scaled) of slave face intervals projected on x in the
    /// configuration `state`.
    fn projected_length(&self, intervals: &[(usize, f64, f64)], state: &[f64]) -> f64 {
        let (mut scratch, mut basis) = (TensorBasis::default(), RationalBasis::default());
        let mut x = |e: usize, xi: f64| -> f64 {
            self.slave_face
                .element_basis_into(e, &[xi], 0, &mut scratch, &mut basis);
            basis
                .indices
                .iter()
                .zip(&basis.values)
                .map(|(&c, &n)| n * self.slave_coordinate(c, 0, state))
                .sum()
        };
        intervals
            .iter()
            .map(|&(e, a, b)| (x(e, b) - x(e, a)).abs())
            .sum()
    }

    /// Length (2D) or area (3D) of the contact zone [`ContactZone`],
    /// projected on the mean plane and scaled, in the configuration `state`:
    /// the frozen zone in the thermal phase, else the zone of the current
    /// indicator. In 3D the indicator interpolated from the slave control
    /// points is sampled at the midpoints of `AREA_SAMPLES`² sub-cells of
    /// every slave element (the frozen indicator in the thermal phase), the
    /// edges fitted to the near-edge asymptotics (`edge3d`).
    pub fn contact_length(&self, state: &[f64]) -> f64 {
        if let Some(z) = &self.zone {
            return z.projected_length;
        }
        let ind: Vec<f64> = (0..self.n_slave()).map(|i| self.indicator(i)).collect();
        if self.dim == 3 {
            self.contact_area(&ind, state)
        } else {
            self.contact_zone(&ind, state).projected_length
        }
    }

    /// Projected area (scaled) of the slave surface in contact for the
    /// nodal indicator `ind` (3D), in the configuration `state`: the
    /// midpoint rule on `AREA_SAMPLES`² sub-cells of every slave element,
    /// the edges fitted to the near-edge asymptotics (`edge3d`).
    fn contact_area(&self, ind: &[f64], state: &[f64]) -> f64 {
        self.contact_level_3d(ind.to_vec(), state)
            .area(self, state, AREA_SAMPLES)
    }

    /// What the last 3D segment-based integration made of the slave
    /// elements (all zero without one).
    pub fn clipping(&self) -> Clipping {
        self.clipping
    }

    /// The frozen contact zone (thermal phase).
    pub fn zone(&self) -> Option<&ContactZone> {
        self.zone.as_ref()
    }

    /// Coordinate `d` of slave control point `c` in the configuration `state`
    /// (reference plus displacement, scaled).
    fn slave_coordinate(&self, c: usize, d: usize, state: &[f64]) -> f64 {
        self.slave_ref[c][d] + state[self.slave_nodes[c] * (self.dim + 1) + d]
    }

    /// Mean gap over the slave surface (scaled), penetrations counted as 0
    /// (frozen in the thermal phase).
    pub fn mean_gap(&self) -> f64 {
        if let Some(z) = &self.zone {
            return z.mean_gap;
        }
        let (mut g, mut w) = (0.0, 0.0);
        for (q, st) in self.state.iter().enumerate() {
            g += self.points[q].weight * st.gap.value.max(0.0);
            w += self.points[q].weight;
        }
        if w > 0.0 { g / w } else { 0.0 }
    }

    /// The gap distribution: for each of `levels` (scaled), the fraction of
    /// the slave surface whose gap at the integration points is at most that
    /// level, in the current point states. Above the oscillation of the
    /// lumped constraint inside the contact (a fraction of a per cent of the
    /// roughness here) it measures the solution near the contact edges
    /// without locating them.
    pub fn gap_fractions(&self, levels: &[f64]) -> Vec<f64> {
        let total: f64 = self.points.iter().map(|p| p.weight).sum();
        levels
            .iter()
            .map(|&level| {
                let below: f64 = self
                    .points
                    .iter()
                    .zip(&self.state)
                    .filter(|(_, st)| st.gap.value <= level)
                    .map(|(p, _)| p.weight)
                    .sum();
                if total > 0.0 { below / total } else { 0.0 }
            })
            .collect()
    }

    /// Adds the contact element of slave node `i` to `k` (column-major, n×n) and `r`.
    /// `unknowns` says which multipliers the element carries (see
    /// [`ContactInterface::element_eqs`]); with `hessians`
    /// ([`ContactInterface::hessian_weights`], 3D tangents) the points'
    /// Hessians are assembled point-major, each once, by the node carrying
    /// the point.
    pub fn element(
        &self,
        i: usize,
        unknowns: Unknowns,
        hessians: Option<&HessianWeights>,
        mut k: Option<&mut [f64]>,
        r: &mut [f64],
    ) {
        let dofs = self.element_dofs(i, unknowns);
        let nd = dofs.len();
        let n = r.len();
        let iln = if unknowns.mechanical { Some(nd) } else { None };
        let ilt = if unknowns.thermal {
            Some(nd + usize::from(unknowns.mechanical))
        } else {
            None
        };
        if self.is_copy(i) {
            // A periodic copy: placeholder multipliers held at zero (rows
            // `−A λ/ε`, `A` its node's area for the scale).
            let a = self.surface_area(self.copy_of[i]);
            let rows = [
                (
                    iln,
                    unknowns.mechanical_terms && self.frozen.is_none(),
                    self.lambda_n[i],
                    self.eps_n,
                ),
                (ilt, unknowns.thermal_terms, self.lambda_t[i], self.eps_t),
            ];
            for (il, on, lam, eps) in rows {
                if let (Some(il), true) = (il, on) {
                    r[il] -= a * lam / eps;
                    if let Some(k) = k.as_deref_mut() {
                        k[il + n * il] -= a / eps;
                    }
                }
            }
            return;
        }
        let area = self.lumped_area[i];
        // The multiplier rows of nodes out of contact (the zone may not
        // reach them in the thermal phase).
        let surface_area = self.surface_area(i);
        // Accumulate G, H (gap) and Gt, Ht (jump) over the node's points;
        // the Hessians enter the terms of nodes in contact only.
        let (mut g, mut gt) = (vec![0.0; nd], vec![0.0; nd]);
        let active = self.is_active(i);
        let want_h = k.is_some() && active;
        // Per node (2D): the node's points' Hessians, weighted by its test
        // function, enter its own terms. Point-major (`hessians`, 3D): each
        // point's Hessians enter once, in the element of the node that
        // carries the point, weighted by all its nodes' factors.
        let node_h = want_h && hessians.is_none();
        let (mut h, mut ht) = if node_h {
            (vec![0.0; nd * nd], vec![0.0; nd * nd])
        } else {
            (Vec::new(), Vec::new())
        };
        debug_assert!(
            !active || nd > 0,
            "slave node {i} is in contact but not coupled in the pattern"
        );
        // Out of the pattern (out of contact): the multiplier rows only.
        let points: &[usize] = if nd > 0 { &self.node_points[i] } else { &[] };
        let (mut gs, mut gts) = (0.0, 0.0);
        let mut map: Vec<Option<usize>> = Vec::new();
        let (mut hp, mut hpt) = (Vec::new(), Vec::new());
        let index = DofIndex::new(&dofs, self.dim);
        for &q in points {
            let w = self.weight_of(q, i);
            self.point_map(q, &index, &mut map);
            debug_assert!(
                self.point_dofs(q)
                    .map(|d| dofs.binary_search(&d).ok())
                    .eq(map.iter().copied()),
                "point map of node {i}"
            );
            let st = &self.state[q];
            if let (Some(hw), true) = (hessians, k.is_some()) {
                let (carrier, cg, cj) = self.point_hessian_factors(q, hw);
                if carrier == i {
                    for (d, c, out) in [(&st.gap, cg, &mut hp), (&st.jump, cj, &mut hpt)] {
                        if c != 0.0 {
                            out.resize(nd * nd, 0.0);
                            d.add_hessian(c, &map, nd, out);
                        }
                    }
                }
            }
            gs += w * st.gap.value;
            gts += w * st.jump.value;
            // Only the derivatives the current phase asked for are present.
            for (d, gv, hv) in [(&st.gap, &mut g, &mut h), (&st.jump, &mut gt, &mut ht)] {
                if d.grad.is_empty() {
                    continue;
                }
                for (a, ia) in map.iter().enumerate() {
                    if let Some(ia) = *ia {
                        gv[ia] += w * d.grad[a];
                    }
                }
                // An empty Hessian is zero in the unknowns of the phase.
                if node_h {
                    d.add_hessian(w, &map, nd, hv);
                }
            }
        }
        if let (Some(hw), true) = (hessians, k.is_some()) {
            // Point-major: each break term once, in the element of the node
            // of its largest weight, with its nodes' factors.
            for t in &self.break_terms {
                let (carrier, [c]) = carried(t.nodes.iter().copied(), [&hw.gap[..]]);
                if carrier != i || c == 0.0 {
                    continue;
                }
                hp.resize(nd * nd, 0.0);
                t.add_to(c, &dofs, &mut hp);
            }
        }
        if let Some(k) = k.as_deref_mut() {
            // The gap's Hessian in every row; the jump's in the temperature
            // rows only (the energy balance varies the temperatures).
            for (m, rows_of) in [(&hp, None), (&hpt, Some(self.dim))] {
                if m.is_empty() {
                    continue;
                }
                for a in (0..nd).filter(|&a| rows_of.is_none_or(|f| dofs[a].1 == f)) {
                    for b in 0..nd {
                        k[a + n * b] += m[a * nd + b];
                    }
                }
            }
        }
        // An unset per-node Hessian is zero (point-major assembly).
        let at = |m: &[f64], ab: usize| m.get(ab).copied().unwrap_or(0.0);
        if node_h {
            for t in &self.break_terms {
                if let Some(&(_, w)) = t.nodes.iter().find(|(c, _)| *c == i) {
                    t.add_to(w, &dofs, &mut h);
                }
            }
        }
        let mut add_k = |row: usize, col: usize, v: f64| {
            if let Some(k) = k.as_deref_mut() {
                k[row + n * col] += v;
            }
        };
        // Mechanical: Alart–Curnier augmented Lagrangian.
        let frozen = self.frozen.is_some();
        if unknowns.mechanical_terms && !frozen {
            let lam = self.lambda_n[i];
            let gi = gs / area;
            let pn = lam - self.eps_n * gi;
            if active {
                for a in 0..nd {
                    r[a] -= pn * g[a];
                }
                if let Some(il) = iln {
                    r[il] -= gs;
                }
                if want_h {
                    // Without the curvature (2D: the node's own Hessians).
                    let curved = if self.curvature { pn } else { 0.0 };
                    for a in 0..nd {
                        for b in 0..nd {
                            add_k(
                                a,
                                b,
                                -curved * at(&h, a * nd + b) + self.eps_n * g[a] * g[b] / area,
                            );
                        }
                        if let Some(il) = iln {
                            add_k(a, il, -g[a]);
                            add_k(il, a, -g[a]);
                        }
                    }
                }
            } else if let Some(il) = iln {
                r[il] -= area * lam / self.eps_n;
                add_k(il, il, -area / self.eps_n);
            }
        }
        if !unknowns.thermal_terms {
            return;
        }
        if self.settings.thermal_method == ThermalMethod::Continuum {
            for &q in &self.node_points[i] {
                if self.owner[q] != i {
                    continue;
                }
                let mut cols = Vec::new();
                self.point_map(q, &index, &mut cols);
                // The temperature unknowns only, in the rows.
                let map: Vec<Option<usize>> = cols
                    .iter()
                    .enumerate()
                    .map(|(a, c)| c.filter(|_| a % (self.dim + 1) == self.dim))
                    .collect();
                self.continuum_point(q, &map, &cols, &mut add_k, r);
            }
            return;
        }
        let gamma = gts / area;
        // The energy balance Σ_I h0^I ⟨N^I δϑc⟩ varies the temperatures only
        // (δϑc = δθ_slave − δθ_master, spec §6): its rows are the temperature
        // unknowns. In the coupled method ⟨N^I ϑc⟩ also depends on the
        // displacements (projection, mortar weights); that enters the tangent
        // of the temperature rows (and of the λθ row), not the mechanical
        // equilibrium.
        let thermal_row: Vec<bool> = dofs.iter().map(|d| d.1 == self.dim).collect();
        match self.settings.thermal {
            ThermalContact::Constraint {
                enforcement: ThermalEnforcement::AugmentedLagrangian,
                ..
            } => {
                let il =
                    ilt.expect("thermal multipliers are unknowns with the augmented Lagrangian");
                let lam = self.lambda_t[i];
                if active {
                    let h0 = lam - self.eps_t * gamma;
                    for a in (0..nd).filter(|&a| thermal_row[a]) {
                        r[a] -= h0 * gt[a];
                    }
                    r[il] -= gts;
                    if want_h {
                        for a in 0..nd {
                            if thermal_row[a] {
                                for b in 0..nd {
                                    add_k(
                                        a,
                                        b,
                                        -h0 * at(&ht, a * nd + b)
                                            + self.eps_t * gt[a] * gt[b] / area,
                                    );
                                }
                                add_k(a, il, -gt[a]);
                            }
                            add_k(il, a, -gt[a]);
                        }
                    }
                } else {
                    r[il] -= surface_area * lam / self.eps_t;
                    add_k(il, il, -surface_area / self.eps_t);
                }
            }
            ThermalContact::Constraint {
                enforcement: ThermalEnforcement::Penalty,
                ..
            } => {
                if active {
                    // h0 = −εθ γθ (4.7)
                    let h0 = -self.eps_t * gamma;
                    for a in (0..nd).filter(|&a| thermal_row[a]) {
                        r[a] -= h0 * gt[a];
                    }
                    if want_h {
                        for a in (0..nd).filter(|&a| thermal_row[a]) {
                            for b in 0..nd {
                                add_k(
                                    a,
                                    b,
                                    -h0 * at(&ht, a * nd + b) + self.eps_t * gt[a] * gt[b] / area,
                                );
                            }
                        }
                    }
                }
            }
            ThermalContact::Constitutive {
                conductance_coefficient: kt,
                pressure_exponent: alpha,
            } => {
                if active {
                    let pn = self.pressure(i).max(0.0);
                    let c = kt * pn.powf(alpha);
                    let h0 = -c * gamma;
                    for a in (0..nd).filter(|&a| thermal_row[a]) {
                        r[a] -= h0 * gt[a];
                    }
                    if want_h {
                        // dpN/du = −εN G/A, dpN/dλN = 1 (when not frozen)
                        let dc = if pn > 0.0 {
                            kt * alpha * pn.powf(alpha - 1.0)
                        } else {
                            0.0
                        };
                        for a in (0..nd).filter(|&a| thermal_row[a]) {
                            for b in 0..nd {
                                let mut v = c * (gt[a] * gt[b] / area) - h0 * at(&ht, a * nd + b);
                                if !frozen {
                                    v += dc * gamma * gt[a] * (-self.eps_n * g[b] / area);
                                }
                                add_k(a, b, v);
                            }
                            if !frozen && let Some(il) = iln {
                                add_k(a, il, dc * gamma * gt[a]);
                            }
                        }
                    }
                }
            }
        }
    }

    /// Continuum (pointwise) thermal contact at integration point `q` (paper
    /// Sects. 5.1–5.2): `h0 = −εθ ϑc` or `−kθ pN^α ϑc` at the point, the
    /// pressure interpolated from the slave control points (frozen in its
    /// linearization). `map` takes the point's temperature unknowns to the
    /// element's rows (the energy balance varies the temperatures only),
    /// `cols` all its unknowns to the element's columns.
    fn continuum_point(
        &self,
        q: usize,
        map: &[Option<usize>],
        cols: &[Option<usize>],
        add_k: &mut impl FnMut(usize, usize, f64),
        r: &mut [f64],
    ) {
        let sp = &self.points[q];
        let st = &self.state[q];
        let pn: f64 = sp
            .conn
            .iter()
            .zip(&sp.basis)
            .map(|(&c, n)| n * self.pressure(c).max(0.0))
            .sum();
        // In contact where a slave control point of the element is active
        // (for positive pressures the same as `pn > 0`; it also holds at
        // zero pressure, e.g. a frozen active set).
        if !sp.conn.iter().any(|&c| self.is_active(c)) {
            return;
        }
        let c = match self.settings.thermal {
            ThermalContact::Constraint { .. } => self.eps_t,
            ThermalContact::Constitutive {
                conductance_coefficient,
                pressure_exponent,
            } => conductance_coefficient * pn.powf(pressure_exponent),
        };
        let m = map.len();
        let h0 = -c * st.jump.value;
        // An empty Hessian is zero in the unknowns of the phase.
        let dense = if st.jump.hess.is_empty() && st.jump.factors.is_empty() {
            Vec::new()
        } else {
            st.jump.dense_hessian()
        };
        let hess = |a: usize, b: usize| dense.get(a * m + b).copied().unwrap_or(0.0);
        for (a, ia) in map.iter().enumerate() {
            let Some(ia) = *ia else { continue };
            r[ia] -= sp.weight * h0 * st.jump.grad[a];
            for (b, ib) in cols.iter().enumerate() {
                let Some(ib) = *ib else { continue };
                add_k(
                    ia,
                    ib,
                    sp.weight * (c * st.jump.grad[a] * st.jump.grad[b] - h0 * hess(a, b)),
                );
            }
        }
    }
}

/// `min_A |data − A model|²`, the squared misfit of the best amplitude
/// (`None` for a vanishing model).
fn amplitude_misfit(model: &[f64], data: &[f64]) -> Option<f64> {
    let mm: f64 = model.iter().map(|v| v * v).sum();
    if mm <= 0.0 {
        return None;
    }
    let amp = model.iter().zip(data).map(|(v, d)| v * d).sum::<f64>() / mm;
    Some(
        model
            .iter()
            .zip(data)
            .map(|(v, d)| (d - amp * v).powi(2))
            .sum(),
    )
}

/// The minimizer of `f` on `[lo, hi]` (`None` where `f` is undefined):
/// the best of `samples + 1` equally spaced samples, then golden-section
/// search between its neighbours (41 evaluations, [`golden_search`]); the
/// middle of the last bracket.
fn minimize_on(f: impl Fn(f64) -> Option<f64>, lo: f64, hi: f64, samples: usize) -> Option<f64> {
    let step = (hi - lo) / samples as f64;
    let best = (0..=samples)
        .map(|k| lo + step * k as f64)
        .filter_map(|x| f(x).map(|m| (x, m)))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let bracket = ((best.0 - step).max(lo), (best.0 + step).min(hi));
    Some(golden_search(|x| f(x).unwrap_or(f64::MAX), bracket, 39).midpoint())
}

/// A node's coupling band is renewed, not widened, where widening would make
/// it more than this many times the master functions of the elements its
/// points see and their neighbours ([`ContactInterface::update_band`]).
pub const BAND_RENEWAL_FACTOR: usize = 2;

/// For each element of a 3D master face, the elements whose parameter boxes
/// touch or overlap its own in both directions (across the seams of a
/// periodic master), itself included: what [`ContactInterface`]'s band
/// takes in around a master element that a slave node sees.
///
/// One sweep over the elements sorted by their lower bound in the first
/// direction: a box touching `e` there starts at most one element width
/// (the widest) below `e`'s, so only that window is tested, once per image
/// across the seam; the test itself is the exact one of every pair.
pub fn touching_elements(face: &ThbPatch, periodic: bool) -> Vec<Vec<usize>> {
    let els = face.elements();
    let kv = face.knots();
    let domain: Vec<(f64, f64)> = kv.iter().map(|k| (k.first(), k.last())).collect();
    // Distance between the intervals [a0, a1] and [b0, b1] on direction
    // d, across the seam for periodic masters.
    let gap = |d: usize, a: (f64, f64), b: (f64, f64)| -> f64 {
        let direct = (b.0 - a.1).max(a.0 - b.1).max(0.0);
        if !periodic {
            return direct;
        }
        let len = domain[d].1 - domain[d].0;
        [len, -len]
            .iter()
            .map(|s| (b.0 + s - a.1).max(a.0 - b.1 - s).max(0.0))
            .fold(direct, f64::min)
    };
    let touch = |a: usize, b: usize| {
        let (el, f) = (&els[a], &els[b]);
        (0..2).all(|d| gap(d, (el.lower[d], el.upper[d]), (f.lower[d], f.upper[d])) <= 0.0)
    };
    let mut order: Vec<usize> = (0..els.len()).collect();
    order.sort_by(|&a, &b| els[a].lower[0].total_cmp(&els[b].lower[0]));
    let lows: Vec<f64> = order.iter().map(|&e| els[e].lower[0]).collect();
    let len = domain[0].1 - domain[0].0;
    let widest = els
        .iter()
        .map(|e| e.upper[0] - e.lower[0])
        .fold(0.0, f64::max);
    // Round-off in the widths and shifts: a wider window only tests more.
    let slack = widest + 1e-9 * len.abs().max(widest);
    let shifts: &[f64] = if periodic { &[0.0, len, -len] } else { &[0.0] };
    let mut candidates = Vec::new();
    els.iter()
        .enumerate()
        .map(|(e, el)| {
            candidates.clear();
            for &s in shifts {
                // `f` with f.lower[0] in [el.lower[0] − s − widest, el.upper[0] − s].
                let from = lows.partition_point(|&x| x < el.lower[0] - s - slack);
                let to = lows.partition_point(|&x| x <= el.upper[0] - s + slack);
                candidates.extend_from_slice(&order[from..to.max(from)]);
            }
            candidates.sort_unstable();
            candidates.dedup();
            candidates
                .iter()
                .copied()
                .filter(|&f| touch(e, f))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::shapes::cuboid;

    /// The zone's test functions: a node in contact whose part of the zone
    /// is below `ZONE_MIN_SHARE` of its area hands it to a node in contact
    /// with a larger part at the same point (its multiplier would be a
    /// near-zero pivot: on the 3D egg box's fourth level at 39 kPa four of
    /// them sent the thermal phase to LU), and keeps it where no such node
    /// is (first touch must conduct); a node out of contact with a sliver
    /// hands its part to the point's node in contact, as before.
    #[test]
    fn a_sliver_of_the_zone_goes_to_the_larger_node_in_contact() {
        let point = |conn: Vec<usize>, basis: Vec<f64>, weight: f64| SlavePoint {
            element: 0,
            conn,
            basis,
            weight,
            piece: None,
        };
        // Node 0 in contact with most of the zone, node 1 in contact with a
        // sliver at the first point and a small part at the second (3 % of
        // its area in all), node 2 out of contact.
        let points = vec![
            point(vec![0, 1], vec![0.99, 0.01], 1.0),
            point(vec![1, 2], vec![0.5, 0.5], 0.02),
        ];
        let copy_of = [0, 1, 2];
        let weights = zone_test_weights(&points, &copy_of, &[1.0, 1.0, -1.0], &[1.0; 3]);
        let total = |node: usize| -> f64 {
            weights
                .iter()
                .flatten()
                .filter(|(i, _)| *i == node)
                .map(|(_, w)| w)
                .sum()
        };
        // The first point all to node 0; the second to node 1, the only node
        // in contact there (node 2's half included).
        assert!((total(0) - 1.0).abs() < 1e-15, "node 0: {}", total(0));
        assert!((total(1) - 0.02).abs() < 1e-15, "node 1: {}", total(1));
        assert_eq!(total(2), 0.0);
        // The weights are a partition of the zone's: nothing lost.
        assert!((total(0) + total(1) - 1.02).abs() < 1e-15);
        // Where every part is large, each node keeps its own.
        let points = vec![point(vec![0, 1], vec![0.6, 0.4], 1.0)];
        let weights = zone_test_weights(&points, &copy_of, &[1.0, 1.0, -1.0], &[1.0; 3]);
        assert_eq!(weights, vec![vec![(0, 0.6), (1, 0.4)]]);
    }

    /// The sampled golden-section search finds the minimizer to a few
    /// parts in 10⁹ of the bracket and evaluates the function once per
    /// golden step (`samples + 1` samples, then 41 evaluations), also with
    /// a minimum at the interval's end and where the function is undefined
    /// on part of the interval.
    #[test]
    fn minimize_on_evaluates_once_per_golden_step() {
        let calls = std::cell::Cell::new(0usize);
        let cases: [(f64, f64, f64, Option<f64>); 3] = [
            (-1.0, 2.0, 0.3, None),
            (0.0, 1.0, 1.0, None),
            (-1.0, 1.0, 0.6, Some(0.5)),
        ];
        for (lo, hi, at, defined_from) in cases {
            calls.set(0);
            let f = |x: f64| {
                calls.set(calls.get() + 1);
                let defined = defined_from.is_none_or(|d| x >= d);
                defined.then(|| (x - at).powi(2) + 0.1 * (x - at).powi(4))
            };
            let x = minimize_on(f, lo, hi, 64).expect("defined somewhere");
            assert!((x - at).abs() < 1e-8 * (hi - lo), "{x} for {at}");
            assert_eq!(calls.get(), 65 + 41);
        }
        assert!(minimize_on(|_| None, 0.0, 1.0, 8).is_none());
    }

    /// The touching elements of a locally refined face (three levels,
    /// refined at both ends of the x seam) are those of the test of every
    /// pair, with and without periodicity.
    #[test]
    fn touching_elements_agree_with_every_pair() {
        let mut nurbs = cuboid([0.0; 3], [1.0, 1.0, 0.5]);
        for d in 0..3 {
            nurbs = nurbs.elevate_degree(d, 1).refine_uniform(d, [7, 6, 2][d]);
        }
        let mut mesh = ThbPatch::from_nurbs(&nurbs).mesh().clone();
        mesh.refine_where(|_, lo, hi| hi[0] > 0.7 && lo[1] < 0.4 && hi[2] > 0.4);
        mesh.refine_where(|_, lo, hi| (hi[0] > 0.85 || lo[0] < 0.1) && hi[2] > 0.45);
        let volume = ThbPatch::from_nurbs(&nurbs).with_mesh(mesh);
        let (face, _) = volume.face(2, Side::High);
        let els = face.elements();
        assert!(els.len() > 42, "refined: {} elements", els.len());
        for periodic in [false, true] {
            let len = 1.0;
            let gap = |a: (f64, f64), b: (f64, f64)| -> f64 {
                let shifts: &[f64] = if periodic { &[0.0, len, -len] } else { &[0.0] };
                shifts
                    .iter()
                    .map(|s| (b.0 + s - a.1).max(a.0 - b.1 - s).max(0.0))
                    .fold(f64::INFINITY, f64::min)
            };
            let touching = touching_elements(&face, periodic);
            for (e, el) in els.iter().enumerate() {
                let every: Vec<usize> = (0..els.len())
                    .filter(|&f| {
                        (0..2).all(|d| {
                            gap(
                                (el.lower[d], el.upper[d]),
                                (els[f].lower[d], els[f].upper[d]),
                            ) <= 0.0
                        })
                    })
                    .collect();
                assert_eq!(touching[e], every, "element {e}, periodic {periodic}");
                assert!(every.contains(&e));
            }
            // Across the seam: an element at x = 0 touches one at x = 1.
            let first = (0..els.len()).find(|&e| els[e].lower[0] == 0.0).unwrap();
            let across = touching[first].iter().any(|&f| els[f].upper[0] == 1.0);
            assert_eq!(across, periodic);
        }
    }
}
