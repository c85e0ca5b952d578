//! A discretized boundary-value problem: NURBS bodies, their materials, the
//! boundary conditions of spec §5, and the state; it implements
//! [`NonlinearProblem`] for Newton's method.
//!
//! Every node (control point) carries `dim + 1` components, the displacement
//! then the temperature, whatever the [`Coupling`]: in the mechanical phase
//! the temperatures are prescribed (frozen), in the thermal phase the
//! displacements are. The input is in SI; the model works in the scaled units
//! of [`Scales`].

use std::sync::{Arc, Mutex, PoisonError};

use nalgebra::Vector3;
use rayon::prelude::*;

use crate::bulk::global::{Assembly, Storage};
use crate::bulk::local::{Coupling, ElementFields, element_residual_tangent};
use crate::contact::kinematics::Needs;
use crate::contact::{ContactInterface, ContactSettings, Unknowns};
use crate::geometry::{ElementQuadrature, Side, ThbPatch};
use crate::material::Material;
use crate::quadrature::default_bulk_points;
use crate::solve::dofs::{DofMap, DofMapBuilder};
use crate::solve::linear::{Factorization, Ordering};
use crate::solve::newton::{NonlinearProblem, OrderingJob};
use crate::solve::ordering::{KeptNodeOrders, node_orders_kept};
use crate::solve::scales::Scales;
use crate::{Error, Result};

/// Body sources `(B, R)` at a point, in SI, for manufactured solutions.
pub type SourceFn = Arc<dyn Fn(&[f64; 3]) -> (Vector3<f64>, f64) + Send + Sync>;

/// One NURBS body, in scaled units, with its precomputed bulk quadrature.
pub struct Body {
    /// Name used in messages and output.
    pub name: String,
    /// The geometry and discretization (scaled): a THB patch, locally refined or not.
    pub patch: ThbPatch,
    /// The material (scaled).
    pub material: Material,
    /// Index of the body's first control point among all nodes.
    pub node_offset: usize,
    /// Bulk quadrature of every element (connectivity local to the patch); empty while
    /// released ([`Model::release_caches`]).
    pub quadrature: Vec<ElementQuadrature>,
    /// Gauss points per direction of the bulk quadrature (`None`: the degree's default).
    bulk_points: Option<usize>,
}

/// A model that releases its caches ([`Model::release_caches`]) returns the
/// free pages to the system where its bulk quadrature held at least this many
/// bytes (the egg box's waiting second and third levels at 132 kPa, 0.14 and
/// 0.46 GB; its first, 34 MB, and the 2D levels' few MB stay with the
/// allocator).
const RETURNED_QUADRATURE_BYTES: usize = 64 << 20;

/// Gauss points per direction of `patch`'s bulk quadrature: `bulk_points`, or
/// [`default_bulk_points`] of each direction's degree.
fn bulk_points_per_direction(patch: &ThbPatch, bulk_points: Option<usize>) -> Vec<usize> {
    patch
        .knots()
        .iter()
        .map(|k| bulk_points.unwrap_or_else(|| default_bulk_points(k.degree())))
        .collect()
}

/// The bulk quadrature of every element of `patch`: `bulk_points` Gauss points per direction,
/// or [`default_bulk_points`] of each direction's degree.
fn bulk_quadrature(patch: &ThbPatch, bulk_points: Option<usize>) -> Vec<ElementQuadrature> {
    let nq = bulk_points_per_direction(patch, bulk_points);
    (0..patch.n_elements())
        .into_par_iter()
        .map(|e| patch.element_quadrature(e, &nq))
        .collect()
}

impl Body {
    /// The bulk quadrature of element `e`: the one kept, or one built for
    /// the call while it is released ([`Model::release_caches`]).
    pub fn element_quadrature(&self, e: usize) -> std::borrow::Cow<'_, ElementQuadrature> {
        match self.quadrature.get(e) {
            Some(q) => std::borrow::Cow::Borrowed(q),
            None => {
                let nq = bulk_points_per_direction(&self.patch, self.bulk_points);
                std::borrow::Cow::Owned(self.patch.element_quadrature(e, &nq))
            }
        }
    }

    /// Global node numbers of the control points on a face.
    pub fn face_nodes(&self, dir: usize, side: Side) -> Vec<usize> {
        self.patch
            .face(dir, side)
            .1
            .into_iter()
            .map(|i| i + self.node_offset)
            .collect()
    }
}

/// A boundary load on a body face, SI, at load factor 1.
#[derive(Clone, Debug)]
enum FaceLoad {
    /// Dead traction per reference area (Pa).
    Traction([f64; 3]),
    /// Heat flux into the body per reference area (W/m²).
    Flux(f64),
}

/// The node orders of a mesh's last analysed system and the phase they were
/// computed for ([`node_ordering`]).
type KeptOrders = Mutex<Option<(Coupling, KeptNodeOrders)>>;

/// [`Model::ordering`] of `pattern` (the equations at `coords`) for a
/// symmetric factorization: the other phase's node orders in `kept` where
/// they cover the nodes, else new ones, which `kept` then holds for
/// `coupling`.
fn node_ordering(
    pattern: faer::sparse::SymbolicSparseColMatRef<'_, usize>,
    coords: &[[f64; 3]],
    kept: &KeptOrders,
    coupling: Coupling,
) -> Ordering {
    let mut kept = kept.lock().unwrap_or_else(PoisonError::into_inner);
    // The other phase's orders of the same nodes, where they cover them.
    if let Some((other, orders)) = kept.as_ref()
        && *other != coupling
        && let Some(orders) = orders.orders(pattern, coords)
    {
        return Ordering::Fewest(orders);
    }
    let (orders, nodes) = node_orders_kept(pattern, coords);
    *kept = Some((coupling, nodes));
    Ordering::Fewest(orders)
}

/// Builds a [`Model`] from SI input.
pub struct ModelBuilder {
    dim: usize,
    scales: Scales,
    bodies: Vec<Body>,
    fixes: Vec<(usize, usize, f64)>,
    ties: Vec<((usize, usize), (usize, usize))>,
    loads: Vec<(usize, usize, Side, FaceLoad)>,
    point_loads: Vec<(usize, usize, f64)>,
    initial_temperature: f64,
    sources: Option<SourceFn>,
    bulk_points: Option<usize>,
    platens: Vec<Platen>,
    contact: Option<ContactInterface>,
    seams: Vec<(usize, usize, Smoothing)>,
}

/// Where [`ModelBuilder::smooth_seam`] and [`ModelBuilder::smooth_symmetry_planes`] act.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Smoothing {
    /// A periodic seam (PR).
    Seam,
    /// The two symmetry planes of LN conditions.
    SymmetryPlanes,
}

/// Relative tangent regularization of a [`ModelBuilder::sliding_platen`]
/// (stiffness `· E |A| / L` at the start of a load step, then scaled down
/// with the residual). It enters the tangent only, so it changes the Newton
/// path, never the converged state: too small and a slide resisted by one
/// contact point on a slope (first touch) takes an enormous step (1e-8
/// diverges on the mismatched sinusoids of Fig. 11); too large and kept
/// constant, Newton converges only linearly where the contact hardly resists
/// the slide (a sinusoid on a flat).
pub const SLIDING_REGULARIZATION: f64 = 1e-3;

/// A rigid platen: the face's nodes share the displacement component `field`.
#[derive(Clone, Debug)]
pub struct Platen {
    /// The (global) nodes of the face.
    pub nodes: Vec<usize>,
    /// The displacement component they share.
    pub field: usize,
    /// The face area (scaled).
    pub area: f64,
    /// Stiffness (scaled) added to the tangent of the shared unknown only,
    /// never to the residual: it makes a rigid mode without physical
    /// stiffness well-posed while the converged state satisfies the platen's
    /// force equation exactly (0 for a plain platen).
    pub regularization: f64,
}

impl ModelBuilder {
    /// An empty model of spatial dimension `dim` (2: plane strain, or 3).
    pub fn new(dim: usize, scales: Scales) -> Self {
        assert!(dim == 2 || dim == 3, "dimension must be 2 or 3");
        ModelBuilder {
            dim,
            scales,
            bodies: Vec::new(),
            fixes: Vec::new(),
            ties: Vec::new(),
            loads: Vec::new(),
            point_loads: Vec::new(),
            initial_temperature: f64::NAN,
            sources: None,
            bulk_points: None,
            platens: Vec::new(),
            contact: None,
            seams: Vec::new(),
        }
    }

    /// Mortar contact between a face of the `slave` body and a face of the
    /// `master` body (spec §6). `period`: the sample width (m) for PR conditions.
    pub fn contact(
        &mut self,
        slave: (usize, usize, Side),
        master: (usize, usize, Side),
        settings: &ContactSettings,
        period: Option<f64>,
    ) -> Result<()> {
        let scaled = settings.scaled(&self.scales);
        let (s, m) = (&self.bodies[slave.0], &self.bodies[master.0]);
        let mut interface = ContactInterface::new(
            (&s.patch, s.node_offset, slave.1, slave.2),
            (&m.patch, m.node_offset, master.1, master.2),
            scaled,
            period.map(|w| self.scales.len(w)),
        )?;
        let compliance: f64 = [&s.material, &m.material]
            .iter()
            .map(|b| (1.0 - b.poisson_ratio.powi(2)) / b.youngs_modulus)
            .sum();
        interface.e_star = Some(1.0 / compliance);
        self.contact = Some(interface);
        Ok(())
    }

    /// The scales in use.
    pub fn scales(&self) -> &Scales {
        &self.scales
    }

    /// Overrides the bulk Gauss points per direction (default `p + 2`).
    pub fn bulk_points(mut self, n: usize) -> Self {
        self.bulk_points = Some(n);
        self
    }

    /// Adds a body (geometry in m, material in SI): a NURBS patch, or a THB patch
    /// (locally refined); returns its index.
    pub fn add_body(
        &mut self,
        name: &str,
        patch: impl Into<ThbPatch>,
        material: &Material,
    ) -> Result<usize> {
        material.validate(&format!("material.{name}"))?;
        let patch = patch.into();
        if patch.param_dim() != self.dim {
            return Err(Error::Geometry(format!(
                "body `{name}` has {} parametric directions, the model is {}D",
                patch.param_dim(),
                self.dim
            )));
        }
        let l = self.scales.length;
        let scaled = patch.map_points(|p| [p[0] / l, p[1] / l, p[2] / l]);
        let node_offset = self.bodies.iter().map(|b| b.patch.n_control_points()).sum();
        let quadrature = bulk_quadrature(&scaled, self.bulk_points);
        self.bodies.push(Body {
            name: name.to_string(),
            material: self.scales.material(material),
            patch: scaled,
            node_offset,
            quadrature,
            bulk_points: self.bulk_points,
        });
        Ok(self.bodies.len() - 1)
    }

    /// The bodies added so far.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    fn scale_field(&self, field: usize, value: f64) -> f64 {
        if field < self.dim {
            self.scales.len(value)
        } else {
            self.scales.temp(value)
        }
    }

    /// Prescribes component `field` (0..dim displacement in m, dim temperature in K) on a face.
    pub fn fix_face(&mut self, body: usize, dir: usize, side: Side, field: usize, value: f64) {
        let v = self.scale_field(field, value);
        for n in self.bodies[body].face_nodes(dir, side) {
            self.fixes.push((n, field, v));
        }
    }

    /// Prescribes component `field` of one global node.
    pub fn fix_node(&mut self, node: usize, field: usize, value: f64) {
        let v = self.scale_field(field, value);
        self.fixes.push((node, field, v));
    }

    /// Periodic (PR) lateral condition (2.3) across parametric direction
    /// `dir`: every component of the High face equals that of the Low face.
    pub fn periodic(&mut self, body: usize, dir: usize) {
        let lo = self.bodies[body].face_nodes(dir, Side::Low);
        let hi = self.bodies[body].face_nodes(dir, Side::High);
        for (a, b) in lo.into_iter().zip(hi) {
            for f in 0..=self.dim {
                self.ties.push(((a, f), (b, f)));
            }
        }
    }

    /// Smooths the periodic seam of `body` across `dir` (after
    /// [`Self::periodic`]): a penalty `½ β ∫ |[[∂u/∂x_dir]]|² dA` on the jump
    /// of the displacement's normal derivative between the two faces, `β =`
    /// [`SEAM_PENALTY`]` · E · h` (`h` the element width across the seam),
    /// and the same on the temperature with `k` for `E`.
    /// The open basis is only C0 where the cell's faces meet, so the deformed
    /// surface creases there, while the exact periodic solution is as smooth
    /// across the seam as anywhere (the term vanishes on it): the penalty
    /// pulls the discrete displacement towards the C^1 periodic space. A
    /// crease of the master splits the closest point of a slave point above
    /// it into two, between which the contact residual jumps.
    pub fn smooth_seam(&mut self, body: usize, dir: usize) {
        self.seams.push((body, dir, Smoothing::Seam));
    }

    /// The LN counterpart of [`Self::smooth_seam`] (after
    /// [`Self::linear_lateral`]): on both faces across `dir`, a penalty
    /// `½ (2β) ∫ |∂u_t/∂x_dir|² dA` on the normal derivative of the tangential
    /// displacements, which vanishes on the exact LN solution (a mirror
    /// symmetry: `u_n = 0` and no shear give `∂u_t/∂n = 0`). With `2β`, a
    /// mirror-symmetric cell gives the same discrete problem with PR and LN
    /// (Fig. 10's symmetric case).
    pub fn smooth_symmetry_planes(&mut self, body: usize, dir: usize) {
        self.seams.push((body, dir, Smoothing::SymmetryPlanes));
    }

    /// Linear (LN) lateral condition (2.3) on the faces across `dir`: normal
    /// displacement component `normal_field` zero, tangentially free,
    /// adiabatic (natural).
    pub fn linear_lateral(&mut self, body: usize, dir: usize, normal_field: usize) {
        for side in [Side::Low, Side::High] {
            self.fix_face(body, dir, side, normal_field, 0.0);
        }
    }

    /// Rigid platen on a face: its nodes share displacement component
    /// `field`, whose conjugate equation is the total force `pressure · |A|`
    /// pushing into the body (spec §5). Returns the platen index.
    pub fn platen(
        &mut self,
        body: usize,
        dir: usize,
        side: Side,
        field: usize,
        pressure: f64,
    ) -> usize {
        let nodes = self.bodies[body].face_nodes(dir, side);
        for w in nodes.windows(2) {
            self.ties.push(((w[0], field), (w[1], field)));
        }
        let area: f64 = self.bodies[body]
            .patch
            .face_quadrature(dir, side, 4)
            .iter()
            .flat_map(|e| e.points.iter().map(|p| p.weight))
            .sum();
        let sign = if side == Side::High { -1.0 } else { 1.0 };
        let force = sign * self.scales.pres(pressure) * area;
        self.point_loads.push((nodes[0], field, force));
        self.platens.push(Platen {
            nodes,
            field,
            area,
            regularization: 0.0,
        });
        self.platens.len() - 1
    }

    /// Sliding platen on a face: its nodes share displacement component
    /// `field` and no force acts on it, so that its conjugate equation is a
    /// vanishing total force (e.g. the lateral force on a body free to slide,
    /// spec §5). The shared unknown's tangent is regularized by the stiffness
    /// [`SLIDING_REGULARIZATION`]` · E · |A| / L` of the body, which leaves
    /// the residual and hence the converged state untouched (a rigid mode
    /// without contact stiffness, e.g. at first touch, stays solvable).
    /// Returns the platen index.
    pub fn sliding_platen(&mut self, body: usize, dir: usize, side: Side, field: usize) -> usize {
        let i = self.platen(body, dir, side, field, 0.0);
        let p = &mut self.platens[i];
        // Scaled: L = 1 (the sample width), E of the body.
        p.regularization =
            SLIDING_REGULARIZATION * self.bodies[body].material.youngs_modulus * p.area;
        i
    }

    /// Uniform dead traction (Pa, per reference area) on a face.
    pub fn traction(&mut self, body: usize, dir: usize, side: Side, t: [f64; 3]) {
        let s = self.scales.stress;
        self.loads.push((
            body,
            dir,
            side,
            FaceLoad::Traction([t[0] / s, t[1] / s, t[2] / s]),
        ));
    }

    /// Uniform heat flux into the body (W/m², per reference area) on a face.
    pub fn flux(&mut self, body: usize, dir: usize, side: Side, h_in: f64) {
        let h = self.scales.heat(h_in);
        self.loads.push((body, dir, side, FaceLoad::Flux(h)));
    }

    /// The uniform initial temperature (K); default the first body's θ0.
    pub fn initial_temperature(&mut self, theta: f64) {
        self.initial_temperature = theta;
    }

    /// Body sources in SI (N/m³, W/m³) as functions of the SI position.
    pub fn sources(&mut self, s: SourceFn) {
        self.sources = Some(s);
    }

    /// Builds the model with the given coupling; the initial state is
    /// `u = 0`, `θ` uniform.
    pub fn build(self, coupling: Coupling) -> Result<Model> {
        if self.bodies.is_empty() {
            return Err(Error::Geometry("a model needs at least one body".into()));
        }
        let theta_init = if self.initial_temperature.is_nan() {
            self.bodies[0].material.reference_temperature
        } else {
            self.scales.temp(self.initial_temperature)
        };
        let nf = self.dim + 1;
        let n_nodes: usize = self.bodies.iter().map(|b| b.patch.n_control_points()).sum();
        let mut state = vec![0.0; n_nodes * nf];
        for n in 0..n_nodes {
            state[n * nf + self.dim] = theta_init;
        }
        let mut f_mech = vec![0.0; n_nodes * nf];
        let mut f_therm = vec![0.0; n_nodes * nf];
        for (body, dir, side, load) in &self.loads {
            let b = &self.bodies[*body];
            for fe in b
                .patch
                .face_quadrature(*dir, *side, b.patch.knots()[0].degree() + 2)
            {
                for qp in &fe.points {
                    for (a, &c) in fe.conn.iter().enumerate() {
                        let node = b.node_offset + c;
                        match load {
                            FaceLoad::Traction(t) => {
                                for i in 0..self.dim {
                                    f_mech[node * nf + i] += qp.weight * qp.r[a] * t[i];
                                }
                            }
                            FaceLoad::Flux(h) => {
                                f_therm[node * nf + self.dim] += qp.weight * qp.r[a] * h
                            }
                        }
                    }
                }
            }
        }
        for &(node, field, f) in &self.point_loads {
            f_mech[node * nf + field] += f;
        }
        // One multiplier per periodic tie group of slave control points (the
        // temperature ties are the periodic ones).
        let mut contact = self.contact;
        if let Some(c) = contact.as_mut() {
            let t = self.dim;
            c.merge_periodic_copies(
                self.ties
                    .iter()
                    .filter(|((_, f), (_, g))| *f == t && *g == t)
                    .map(|&((a, _), (b, _))| (a, b)),
            );
        }
        let seams = self
            .seams
            .iter()
            .flat_map(|&(body, dir, kind)| seam_elements(&self.bodies[body], body, dir, kind))
            .collect();
        let mut model = Model {
            dim: self.dim,
            scales: self.scales,
            base_materials: self.bodies.iter().map(|b| b.material.clone()).collect(),
            bodies: self.bodies,
            fixes: self.fixes,
            ties: self.ties,
            platens: self.platens,
            sources: self.sources,
            f_mech,
            f_therm,
            path: ([0.0, 0.0], [1.0, 1.0]),
            load: [0.0, 0.0],
            initial: state.clone(),
            state,
            load_factor: 0.0,
            step_residual: None,
            coupling,
            contact,
            n_bulk_eq: 0,
            mult_eq: (None, None),
            pattern_version: 0,
            numberings: Vec::new(),
            dofs: DofMapBuilder::new(0, 1).build()?,
            assembly: Assembly::new(0, Vec::new()),
            assembly_coupling: coupling,
            assembly_coverage: Vec::new(),
            assembly_stale: false,
            assembly_builds: 0,
            quadrature_builds: 0,
            kept_assembly: None,
            elements: Vec::new(),
            eq_class: Vec::new(),
            eq_coords: Arc::new(Vec::new()),
            kept_node_orders: Arc::new(Mutex::new(None)),
            symmetric_solvers: true,
            seams,
        };
        model.renumber()?;
        Ok(model)
    }
}

/// A discretized problem ready for Newton's method.
pub struct Model {
    /// Spatial dimension.
    pub dim: usize,
    /// Unit scales.
    pub scales: Scales,
    /// The bodies.
    pub bodies: Vec<Body>,
    base_materials: Vec<Material>,
    fixes: Vec<(usize, usize, f64)>,
    ties: Vec<((usize, usize), (usize, usize))>,
    platens: Vec<Platen>,
    sources: Option<SourceFn>,
    /// External nodal forces at the nominal pressure (state layout, scaled).
    f_mech: Vec<f64>,
    /// External nodal heat inputs at the nominal flux (state layout, scaled).
    f_therm: Vec<f64>,
    /// Load path: (mechanical, thermal) multipliers of the nominal loads at
    /// load factor 0 and 1.
    path: ([f64; 2], [f64; 2]),
    /// Current (mechanical, thermal) load multipliers.
    load: [f64; 2],
    /// The contact interface, if any.
    pub contact: Option<ContactInterface>,
    n_bulk_eq: usize,
    mult_eq: (Option<usize>, Option<usize>),
    pattern_version: u64,
    /// The equations of the last renumbering of each coupling, with their identifier
    /// ([`NonlinearProblem::numbering_version`]): a value no other model has had, kept while
    /// the renumberings of that coupling give the same equations.
    numberings: Vec<Numbering>,
    /// The state at load factor 0 (prescribed values ramp from it).
    initial: Vec<f64>,
    /// Current state: `dim + 1` components per node (scaled).
    pub state: Vec<f64>,
    load_factor: f64,
    /// Mechanical residual norm at the first assembly of the load step.
    step_residual: Option<f64>,
    coupling: Coupling,
    dofs: DofMap,
    assembly: Assembly,
    /// The phase `assembly` was built for.
    assembly_coupling: Coupling,
    /// The slave nodes its contact elements couple
    /// ([`ContactInterface::cover_active`]).
    assembly_coverage: Vec<bool>,
    /// Whether `assembly` is out of date (new equations or contact
    /// pattern): rebuilt at the next [`NonlinearProblem::prepare`] or
    /// assembly ([`Model::ensure_assembly`]), once for any number of changes
    /// in between.
    assembly_stale: bool,
    /// Assemblies built so far ([`Model::assembly_builds`]).
    assembly_builds: usize,
    /// Bulk quadratures recomputed after [`Model::release_quadrature`].
    quadrature_builds: usize,
    /// The last assembly of another phase, with the slave nodes it couples,
    /// reused when the phases alternate (the self-consistent iterations) on
    /// an unchanged pattern ([`Model::set_coupling`]).
    kept_assembly: Option<(Coupling, Assembly, Vec<bool>)>,
    elements: Vec<(usize, usize)>,
    eq_class: Vec<usize>,
    /// Shared with the ordering jobs of the analyses ([`NonlinearProblem::ordering_job`]).
    eq_coords: Arc<Vec<[f64; 3]>>,
    /// The node orders of the last analysis, with the phase they were computed for: the other
    /// phase's analyses of the same mesh reuse them ([`KeptNodeOrders`]).
    kept_node_orders: Arc<KeptOrders>,
    /// Whether symmetric tangents get Cholesky/LDLᵀ (else always LU).
    symmetric_solvers: bool,
    /// Seam penalty elements ([`ModelBuilder::smooth_seam`]), assembled
    /// after the bulk elements and before the contact elements.
    seams: Vec<SeamElement>,
}

/// Relative stiffness of the seam penalty ([`ModelBuilder::smooth_seam`]):
/// `β = SEAM_PENALTY · E · h`, against the bulk's `E h^(d−2)` per unknown
/// (the temperature's: `· k` for `E`). Measured (docs/3d.md): 1 (displacement
/// only) already moves the results most of the way, 10 makes every sample of
/// the random-surface robustness cases converge, 1e3 leaves a round-off floor
/// above the thermal phase's absolute tolerance.
pub const SEAM_PENALTY: f64 = 10.0;

/// The equations of one renumbering ([`NonlinearProblem::numbering_version`]).
struct Numbering {
    coupling: Coupling,
    dofs: DofMap,
    mult_eq: (Option<usize>, Option<usize>),
    eq_class: Vec<usize>,
    id: u64,
}

/// The penalty points of a seam between one pair of volume elements (or of
/// a symmetry plane on one element): the functions (of the low element, then
/// the high one), the penalized displacement components, and at each point
/// `(β w, s)` with `s` the coefficients of the penalized derivative (seam:
/// the jump, `−∂R/∂x_dir` low and `+∂R/∂x_dir` high; plane: `∂R/∂x_dir`).
struct SeamElement {
    body: usize,
    conn: Vec<usize>,
    components: Vec<usize>,
    points: Vec<(f64, Vec<f64>)>,
    /// `k / E`: the temperature's penalty relative to the displacement's.
    thermal_ratio: f64,
}

/// The [`SeamElement`]s of `body`'s seam (or symmetry planes) across `dir`.
fn seam_elements(body: &Body, index: usize, dir: usize, kind: Smoothing) -> Vec<SeamElement> {
    let patch = &body.patch;
    let dim = patch.param_dim();
    let n_gauss = patch.knots()[dir].degree() + 1;
    let beta = |width: f64| SEAM_PENALTY * body.material.youngs_modulus * width;
    let mut by_pair: std::collections::BTreeMap<(usize, usize), SeamElement> =
        std::collections::BTreeMap::new();
    let mut add = |key: (usize, usize), conn: Vec<usize>, components: &[usize], point| {
        by_pair
            .entry(key)
            .or_insert_with(|| SeamElement {
                body: index,
                conn,
                components: components.to_vec(),
                points: Vec::new(),
                thermal_ratio: body.material.thermal_conductivity / body.material.youngs_modulus,
            })
            .points
            .push(point);
    };
    match kind {
        Smoothing::Seam => {
            let all: Vec<usize> = (0..=dim).collect();
            for sp in patch.seam_points(dir, n_gauss) {
                let [lo, hi] = &sp.sides;
                let s = lo
                    .normal_derivative
                    .iter()
                    .map(|d| -d)
                    .chain(hi.normal_derivative.iter().copied())
                    .collect();
                let conn = lo.conn.iter().chain(&hi.conn).copied().collect();
                let bw = beta(lo.width.min(hi.width)) * sp.weight;
                add((lo.element, hi.element), conn, &all, (bw, s));
            }
        }
        Smoothing::SymmetryPlanes => {
            let tangential: Vec<usize> = (0..=dim).filter(|&c| c != dir).collect();
            for side in [Side::Low, Side::High] {
                for fe in patch.face_quadrature(dir, side, n_gauss) {
                    for qp in fe.points {
                        let at = patch.normal_derivatives(qp.xi, dir);
                        let bw = 2.0 * beta(at.width) * qp.weight;
                        let key = (at.element, usize::from(side == Side::High));
                        add(key, at.conn, &tangential, (bw, at.normal_derivative));
                    }
                }
            }
        }
    }
    by_pair.into_values().collect()
}

impl Model {
    /// Whether the assembled tangent is symmetric: the gradient of a
    /// potential in the unknowns of the phase. The mechanical phase is
    /// (hyperelastic bulk at frozen temperatures, the augmented Lagrangian
    /// normal contact (4.9)–(4.10), ties and platens through the equation
    /// numbering, the sliding platens' diagonal regularization); so is the
    /// thermal phase with constant conductivities (`k1 = 0` (5.1), or
    /// frozen): every thermal contact model is quadratic in the temperatures
    /// there (frozen configuration and pressures). The coupled problem and
    /// `k(θ)` conduction are not.
    pub fn symmetric_tangent(&self) -> bool {
        match self.coupling {
            Coupling::Mechanical => true,
            Coupling::Thermal => self
                .bodies
                .iter()
                .all(|b| b.material.conductivity_slope == 0.0),
            Coupling::Coupled => false,
        }
    }

    /// The first equations of the mechanical and the thermal contact
    /// multipliers in the current phase (`λN^I`, `λθ^I` of slave node `I`
    /// are those plus `I`), None where the phase has none.
    pub fn multiplier_equations(&self) -> (Option<usize>, Option<usize>) {
        self.mult_eq
    }

    /// The reference position of each equation's node (a multiplier at its
    /// slave node), as the nested dissection orders them.
    pub fn equation_positions(&self) -> &[[f64; 3]] {
        &self.eq_coords
    }

    /// Turns the symmetric factorizations (Cholesky, LDLᵀ) of symmetric
    /// tangents on (the default) or off (LU for every phase, e.g. to compare).
    /// The assembly then stores the lower triangle of symmetric tangents, or
    /// both ([`crate::bulk::global::Storage`]).
    pub fn set_symmetric_solvers(&mut self, on: bool) {
        self.symmetric_solvers = on;
    }

    /// Which entries of the tangent the assembly stores: the lower triangle
    /// where the phase's tangent is symmetric and factorized symmetrically
    /// ([`Model::symmetric_tangent`], [`Model::set_symmetric_solvers`]), else
    /// both triangles. Valid after [`Model::prepare`].
    pub fn tangent_storage(&self) -> Storage {
        self.assembly.storage()
    }

    /// The storage [`Model::tangent_storage`] is to have now: an assembly of
    /// the other is built again at the next preparation (a toggled solver
    /// choice, a frozen or restored conductivity), so that a lower triangle
    /// never reaches LU.
    fn needed_storage(&self) -> Storage {
        match self.symmetric_solvers && self.symmetric_tangent() {
            true => Storage::Lower,
            false => Storage::Full,
        }
    }

    /// The tangent with both triangles from `values` on the pattern
    /// ([`NonlinearProblem::pattern`]; mirrored where it stores the lower
    /// triangle, [`Model::tangent_storage`]): e.g. for LU, or to compare
    /// with finite differences. Valid after [`Model::prepare`].
    pub fn full_tangent(&self, values: &[f64]) -> faer::sparse::SparseColMat<usize, f64> {
        self.assembly.full_matrix(values)
    }

    /// Whether symmetric tangents get Cholesky/LDLᵀ ([`Model::set_symmetric_solvers`]).
    pub fn symmetric_solvers(&self) -> bool {
        self.symmetric_solvers
    }

    /// Which contact unknowns and terms the current coupling carries.
    fn contact_unknowns(&self) -> Option<Unknowns> {
        let c = self.contact.as_ref()?;
        let thermal_mult = c.settings.thermal_multipliers();
        Some(match self.coupling {
            Coupling::Coupled => Unknowns {
                mechanical: true,
                thermal: thermal_mult,
                mechanical_terms: true,
                thermal_terms: true,
            },
            Coupling::Mechanical => Unknowns {
                mechanical: true,
                thermal: false,
                mechanical_terms: true,
                thermal_terms: false,
            },
            Coupling::Thermal => Unknowns {
                mechanical: false,
                thermal: thermal_mult,
                mechanical_terms: false,
                thermal_terms: true,
            },
        })
    }

    fn renumber(&mut self) -> Result<()> {
        let nf = self.dim + 1;
        let n_nodes = self.state.len() / nf;
        let mut b = DofMapBuilder::new(n_nodes, nf);
        for &(a, c) in &self.ties {
            b.tie(a, c);
        }
        for &(n, f, v) in &self.fixes {
            b.fix(n, f, v);
        }
        // Frozen fields: prescribed at their current values.
        for n in 0..n_nodes {
            match self.coupling {
                Coupling::Mechanical => b.fix(n, self.dim, self.state[n * nf + self.dim]),
                Coupling::Thermal => {
                    (0..self.dim).for_each(|f| b.fix(n, f, self.state[n * nf + f]))
                }
                Coupling::Coupled => {}
            }
        }
        self.dofs = b.build()?;
        self.n_bulk_eq = self.dofs.n_eq();
        let mut n_eq = self.n_bulk_eq;
        let mut classes: Vec<usize> = self
            .dofs
            .eq_fields()
            .iter()
            .map(|&f| usize::from(f == self.dim))
            .collect();
        self.mult_eq = (None, None);
        if let (Some(u), Some(c)) = (self.contact_unknowns(), self.contact.as_ref()) {
            let ns = c.n_slave();
            if u.mechanical {
                self.mult_eq.0 = Some(n_eq);
                n_eq += ns;
                classes.extend(std::iter::repeat_n(2, ns));
            }
            if u.thermal {
                self.mult_eq.1 = Some(n_eq);
                n_eq += ns;
                classes.extend(std::iter::repeat_n(3, ns));
            }
        }
        self.eq_class = classes;
        self.identify_numbering();
        let mut coords = vec![[f64::NAN; 3]; n_eq];
        for body in &self.bodies {
            for (i, x) in body.patch.control_points().iter().enumerate() {
                for f in 0..nf {
                    if let Some(e) = self.dofs.eq(body.node_offset + i, f)
                        && coords[e][0].is_nan()
                    {
                        coords[e] = *x;
                    }
                }
            }
        }
        if let Some(c) = &self.contact {
            for (i, &n) in c.slave_nodes.iter().enumerate() {
                let x = self.node_position(n);
                for e in [self.mult_eq.0, self.mult_eq.1].into_iter().flatten() {
                    coords[e + i] = x;
                }
            }
        }
        self.eq_coords = Arc::new(coords);
        self.mark_assembly_stale();
        Ok(())
    }

    /// Records the current equations as this coupling's last renumbering: with the
    /// identifier of the one before if it numbered the same equations, else a new one.
    fn identify_numbering(&mut self) {
        let last = self
            .numberings
            .iter()
            .position(|m| m.coupling == self.coupling);
        if let Some(i) = last {
            let m = &self.numberings[i];
            if m.dofs.same_equations(&self.dofs)
                && m.mult_eq == self.mult_eq
                && m.eq_class == self.eq_class
            {
                return;
            }
            self.numberings.swap_remove(i);
        }
        // Unique over all models: a solver kept across models must not take another
        // model's equations for these.
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        self.numberings.push(Numbering {
            coupling: self.coupling,
            dofs: self.dofs.clone(),
            mult_eq: self.mult_eq,
            eq_class: self.eq_class.clone(),
            id: NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
        });
    }

    /// Reference position of a global node (scaled).
    fn node_position(&self, node: usize) -> [f64; 3] {
        let b = self
            .bodies
            .iter()
            .rev()
            .find(|b| b.node_offset <= node)
            .expect("node in a body");
        b.patch.control_points()[node - b.node_offset]
    }

    /// The fields the current phase solves for (each element's local
    /// unknowns are node-major over these).
    fn phase_fields(&self) -> Vec<usize> {
        match self.coupling {
            Coupling::Coupled => (0..=self.dim).collect(),
            Coupling::Mechanical => (0..self.dim).collect(),
            Coupling::Thermal => vec![self.dim],
        }
    }

    /// Frees what the model keeps only to go faster: the bulk quadrature of its elements and
    /// the assemblies (pattern, scatter map) of both phases. They come back, the same, when
    /// next needed (the quadrature and the phase's assembly at the next preparation or
    /// assembly, the other phase's at its next change of phase), and the freed pages go back
    /// to the system ([`super::resources::return_free_memory`]). For a model that waits: an
    /// adaptive level while the next one solves (the 72 kPa egg box's peak 12.5 → 12.0 GB,
    /// docs/3d.md, "Stop 40"; the assembly too since "Stop 47").
    pub fn release_caches(&mut self) {
        let quadrature = self.quadrature_bytes();
        self.kept_assembly = None;
        self.assembly = Assembly::new(0, Vec::new());
        self.assembly_coverage = Vec::new();
        self.mark_assembly_stale();
        self.release_quadrature();
        // The return costs a walk over the heaps (milliseconds), which the
        // small levels of 2D points solved in parallel would pay many times.
        if quadrature >= RETURNED_QUADRATURE_BYTES {
            super::resources::return_free_memory();
        }
    }

    /// Bytes held by the bulk quadrature.
    fn quadrature_bytes(&self) -> usize {
        self.bodies
            .iter()
            .flat_map(|b| &b.quadrature)
            .map(|q| q.storage_bytes())
            .sum()
    }

    /// Frees the bulk quadrature of the elements ([`Model::release_caches`]
    /// without the assemblies, whose rebuild costs more); the next assembly
    /// recomputes it, the same.
    pub fn release_quadrature(&mut self) {
        for body in &mut self.bodies {
            body.quadrature = Vec::new();
        }
    }

    /// Bulk quadratures recomputed since the model was built (each after a
    /// [`Model::release_quadrature`] or [`Model::release_caches`]).
    pub fn quadrature_builds(&self) -> usize {
        self.quadrature_builds
    }

    /// Recomputes the bulk quadrature that [`Model::release_caches`] freed.
    fn restore_quadrature(&mut self) {
        let clock = std::time::Instant::now();
        let mut rebuilt = false;
        for body in &mut self.bodies {
            if body.quadrature.is_empty() && body.patch.n_elements() > 0 {
                body.quadrature = bulk_quadrature(&body.patch, body.bulk_points);
                rebuilt = true;
            }
        }
        self.quadrature_builds += usize::from(rebuilt);
        if rebuilt && std::env::var_os("TCGEN_TRACE").is_some() {
            eprintln!(
                "  bulk quadrature rebuilt in {:.2} s",
                clock.elapsed().as_secs_f64()
            );
        }
    }

    /// Marks the assembly out of date; [`Model::ensure_assembly`] builds it.
    /// A new adaptive level's model builds its equations before the state
    /// is transferred to it, and the first preparation then widens the
    /// contact band to that state: built at once, the first pattern and
    /// scatter map were thrown away (2.7 s of the 72 kPa egg box's level-4
    /// build; docs/3d.md, "Stop 42").
    fn mark_assembly_stale(&mut self) {
        self.assembly_stale = true;
    }

    /// Assemblies (pattern, scatter map, coloring) built so far: a change of
    /// equations or of the contact pattern builds one at the next
    /// preparation or assembly, unless the current or the kept one of
    /// another phase describes the new equations.
    pub fn assembly_builds(&self) -> usize {
        self.assembly_builds
    }

    /// Builds the assembly if it is out of date ([`Model::mark_assembly_stale`]); an error
    /// where the memory left cannot hold it ([`Assembly::try_new`]; the assembly stays out of
    /// date).
    fn ensure_assembly(&mut self) -> Result<()> {
        let storage = self.needed_storage();
        if !self.assembly_stale && self.assembly.storage() == storage {
            return Ok(());
        }
        self.assembly_stale = false;
        self.restore_quadrature();
        let fields = self.phase_fields();
        self.elements.clear();
        let mut element_eqs = Vec::new();
        for (bi, body) in self.bodies.iter().enumerate() {
            for (ei, q) in body.quadrature.iter().enumerate() {
                self.elements.push((bi, ei));
                let conn: Vec<usize> = q.conn.iter().map(|c| c + body.node_offset).collect();
                element_eqs.push(self.dofs.element_eqs(&conn, &fields));
            }
        }
        for sm in &self.seams {
            let offset = self.bodies[sm.body].node_offset;
            let conn: Vec<usize> = sm.conn.iter().map(|c| c + offset).collect();
            element_eqs.push(self.dofs.element_eqs(&conn, &fields));
        }
        if let (Some(c), Some(unknowns)) = (&self.contact, self.contact_unknowns()) {
            for i in 0..c.n_slave() {
                element_eqs.push(c.element_eqs(i, &self.dofs, self.mult_eq, unknowns));
            }
        }
        let n_eq = self.eq_class.len();
        // The current assembly or the kept one of another phase, where
        // either is this pattern; one of another phase is kept.
        let previous = std::mem::replace(&mut self.assembly, Assembly::new(0, Vec::new()));
        let mut candidates = [
            Some((
                self.assembly_coupling,
                previous,
                std::mem::take(&mut self.assembly_coverage),
            )),
            self.kept_assembly.take(),
        ];
        let found = candidates
            .iter_mut()
            .find_map(|c| c.take_if(|(_, a, _)| a.describes(n_eq, &element_eqs, storage)));
        self.assembly = match found {
            Some((_, a, _)) => a,
            None => match Assembly::try_new_stored(n_eq, element_eqs, storage) {
                Ok(built) => {
                    self.assembly_builds += 1;
                    built
                }
                Err(e) => {
                    // Out of date still, the assemblies built so far kept.
                    let [current, kept] = candidates;
                    if let Some((coupling, assembly, coverage)) = current {
                        self.assembly = assembly;
                        self.assembly_coupling = coupling;
                        self.assembly_coverage = coverage;
                    }
                    self.kept_assembly = kept;
                    self.assembly_stale = true;
                    return Err(e);
                }
            },
        };
        self.assembly_coupling = self.coupling;
        self.assembly_coverage = self
            .contact
            .as_ref()
            .map_or_else(Vec::new, |c| c.coverage().to_vec());
        self.kept_assembly = candidates
            .into_iter()
            .flatten()
            .find(|(c, _, _)| *c != self.coupling);
        self.pattern_version += 1;
        Ok(())
    }

    /// The same problem with another coupling, keeping the current state
    /// (e.g. the thermal phase on the deformation of the mechanical phase:
    /// the contact pressures and active set are then frozen).
    pub fn set_coupling(&mut self, coupling: Coupling) -> Result<()> {
        if coupling == Coupling::Thermal
            && let Some(c) = self.contact.as_mut()
        {
            c.prepare(&self.state, Needs::Values)?;
            c.freeze(&self.state);
            // The thermal points (the contact zone) in this configuration.
            c.prepare(&self.state, Needs::Values)?;
        }
        if coupling != Coupling::Thermal
            && let Some(c) = self.contact.as_mut()
            && c.frozen.is_some()
        {
            c.thaw();
            c.prepare(&self.state, Needs::Values)?;
        }
        if let Some(c) = self.contact.as_mut() {
            c.cover_active(true);
            // The kept assembly of this phase, where it couples every node
            // the reset does: its pattern holds this one's (the Newton
            // iterations of its phase grew it), and reusing it saves its
            // rebuild (the mechanical one of the 72 kPa egg box's level 4,
            // 57 M entries: 3.2 s per self-consistency iteration; docs/3d.md,
            // "Stop 43").
            if let Some((_, _, coverage)) = self
                .kept_assembly
                .as_ref()
                .filter(|(kept, _, _)| *kept == coupling)
            {
                c.cover_at_least(coverage);
            }
        }
        self.coupling = coupling;
        self.initial = self.state.clone();
        self.renumber()
    }

    /// Sets the load path: (pressure, flux) multipliers of the nominal loads
    /// at load factor 0 and at load factor 1.
    /// Prescribed values ramp from the current state to their targets along
    /// the path (they stay put once reached).
    pub fn set_path(&mut self, from: [f64; 2], to: [f64; 2]) {
        self.path = (from, to);
        self.initial = self.state.clone();
    }

    /// The current (pressure, flux) multipliers of the nominal loads.
    pub fn load(&self) -> [f64; 2] {
        self.load
    }

    /// Moves `body` (the one under the platen) rigidly by the smallest
    /// weighted gap along `vertical` (downwards), so that the surfaces touch
    /// at one slave control point (weighted gap zero), and seeds that point's
    /// multiplier so that the vertical position is determined from the first
    /// iteration (loading starts at first touch, spec §5). Whichever body is
    /// the slave, closing the gap moves the free upper body down.
    pub fn touch(&mut self, body: usize, vertical: usize) -> Result<()> {
        let Some(c) = self.contact.as_mut() else {
            return Ok(());
        };
        let b = &self.bodies[body];
        let nodes: Vec<usize> = (b.node_offset..b.node_offset + b.patch.n_control_points())
            .filter(|&n| matches!(self.dofs.dof(n, vertical), crate::solve::Dof::Free(_)))
            .collect();
        let nf = self.dim + 1;
        // The normal varies over a node's support: repeat the rigid shift
        // until the smallest weighted gap is zero to round-off.
        let mut imin = 0;
        for _ in 0..20 {
            c.prepare(&self.state, Needs::Values)?;
            let (i, gmin) = (0..c.n_slave())
                .map(|i| (i, c.weighted_gap(i)))
                .fold((0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
            imin = i;
            for &n in &nodes {
                self.state[n * nf + vertical] -= gmin;
            }
            if gmin.abs() < 1e-13 {
                break;
            }
        }
        self.initial = self.state.clone();
        c.prepare(&self.state, Needs::Values)?;
        // Seed every point that touches (conforming surfaces touch everywhere).
        for i in 0..c.n_slave() {
            let g = c.weighted_gap(i);
            if !c.is_copy(i) && (i == imin || g < 1e-10) {
                c.lambda_n[i] = c.lambda_n[i].max(c.eps_n * (2.0 * g.max(0.0) + 1e-9));
            }
        }
        Ok(())
    }

    /// Projects the contact points at the current state (gaps, jumps and
    /// the pressure indicator up to date, e.g. after a restore).
    pub fn prepare_contact(&mut self) -> Result<()> {
        if let Some(c) = self.contact.as_mut() {
            c.prepare(&self.state, Needs::Values)?;
        }
        Ok(())
    }

    /// The current coupling.
    pub fn coupling(&self) -> Coupling {
        self.coupling
    }

    /// Replaces every body's conductivity by its value at `theta` (K),
    /// constant: the thermal phase of the two-phase framework (Sect. 3.1).
    pub fn freeze_conductivity(&mut self, theta: f64) {
        let t = self.scales.temp(theta);
        for b in &mut self.bodies {
            let (k, _) = b.material.conductivity(t);
            b.material.thermal_conductivity = k;
            b.material.conductivity_slope = 0.0;
        }
    }

    /// Reference position of a node (scaled).
    pub fn node_reference(&self, node: usize) -> [f64; 3] {
        self.node_position(node)
    }

    /// Reference x coordinate of a node (scaled).
    pub fn node_x(&self, node: usize) -> f64 {
        self.node_position(node)[0]
    }

    /// Changes a prescribed value on a face (SI; temperature for `field == dim`).
    /// The new value is reached along the next load path.
    pub fn prescribe_face(
        &mut self,
        body: usize,
        dir: usize,
        side: Side,
        field: usize,
        value: f64,
    ) {
        let v = if field < self.dim {
            self.scales.len(value)
        } else {
            self.scales.temp(value)
        };
        let nodes = self.bodies[body].face_nodes(dir, side);
        for f in self.fixes.iter_mut() {
            if f.1 == field && nodes.contains(&f.0) {
                f.2 = v;
            }
        }
        for n in nodes {
            self.dofs.set_fixed(n, field, v);
        }
    }

    /// In the mechanical phase: sets the frozen (uniform) temperature of a
    /// body, reached along the next load path (the first-order corrector of
    /// the self-consistent scheme, Sect. 3.3).
    pub fn set_frozen_temperature(&mut self, body: usize, theta: f64) {
        let t = self.scales.temp(theta);
        let b = &self.bodies[body];
        for n in b.node_offset..b.node_offset + b.patch.n_control_points() {
            self.dofs.set_fixed(n, self.dim, t);
        }
    }

    /// Sets a body's temperature field to a uniform value (SI), state and
    /// prescribed values alike (before a solve).
    pub fn set_uniform_temperature(&mut self, body: usize, theta: f64) {
        let t = self.scales.temp(theta);
        let nf = self.dim + 1;
        let b = &self.bodies[body];
        for n in b.node_offset..b.node_offset + b.patch.n_control_points() {
            self.state[n * nf + self.dim] = t;
            self.dofs.set_fixed(n, self.dim, t);
        }
        self.initial = self.state.clone();
    }

    /// Freezes one body's conductivity at its value at `theta` (K).
    pub fn freeze_body_conductivity(&mut self, body: usize, theta: f64) {
        let t = self.scales.temp(theta);
        let m = &mut self.bodies[body].material;
        let (k, _) = m.conductivity(t);
        m.thermal_conductivity = k;
        m.conductivity_slope = 0.0;
    }

    /// Restores the bodies' materials as built (undoes the freezes).
    pub fn restore_materials(&mut self) {
        for (b, m) in self.bodies.iter_mut().zip(&self.base_materials) {
            b.material = m.clone();
        }
    }

    /// Sets every prescribed component of the state to its value exactly.
    pub fn hold_prescribed(&mut self) {
        self.dofs.hold(&mut self.state);
    }

    /// The degrees of freedom.
    pub fn dofs(&self) -> &DofMap {
        &self.dofs
    }

    /// The platens.
    pub fn platens(&self) -> &[Platen] {
        &self.platens
    }

    /// Displacement component `field` of node `node`, in m.
    pub fn displacement(&self, node: usize, field: usize) -> f64 {
        self.state[node * (self.dim + 1) + field] * self.scales.length
    }

    /// Temperature of node `node`, in K.
    pub fn temperature(&self, node: usize) -> f64 {
        self.state[node * (self.dim + 1) + self.dim] * self.scales.temperature
    }

    /// Area average of the temperature over a face (K): the measured `θ(1)` of spec §5.
    pub fn face_mean_temperature(&self, body: usize, dir: usize, side: Side) -> f64 {
        let b = &self.bodies[body];
        let nf = self.dim + 1;
        let (mut a, mut s) = (0.0, 0.0);
        for fe in b
            .patch
            .face_quadrature(dir, side, b.patch.knots()[0].degree() + 2)
        {
            for qp in &fe.points {
                let th: f64 = fe
                    .conn
                    .iter()
                    .zip(&qp.r)
                    .map(|(&c, r)| r * self.state[(c + b.node_offset) * nf + self.dim])
                    .sum();
                a += qp.weight;
                s += qp.weight * th;
            }
        }
        s / a * self.scales.temperature
    }

    fn gather_nodes(&self, body: &Body, conn: &[usize], u: &mut Vec<[f64; 3]>, th: &mut Vec<f64>) {
        let nf = self.dim + 1;
        u.clear();
        th.clear();
        for &c in conn {
            let n = (c + body.node_offset) * nf;
            let mut v = [0.0; 3];
            v[..self.dim].copy_from_slice(&self.state[n..n + self.dim]);
            u.push(v);
            th.push(self.state[n + self.dim]);
        }
    }

    /// External loads at the current multipliers, gathered into equation space.
    fn external(&self) -> Vec<f64> {
        let mut f = vec![0.0; self.n_bulk_eq];
        let v: Vec<f64> = self
            .f_mech
            .iter()
            .zip(&self.f_therm)
            .map(|(m, t)| m * self.load[0] + t * self.load[1])
            .collect();
        self.dofs.gather(&v, &mut f);
        f.resize(self.eq_class.len(), 0.0);
        f
    }

    /// Residual (and tangent) of bulk and contact, minus the external loads.
    fn assemble_all(&self, values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()> {
        let scales = self.scales;
        let src_fn = self.sources.clone();
        let scaled_src = move |x: &[f64; 3]| {
            let f = src_fn.as_ref().expect("sources present");
            let l = scales.length;
            let (b, r) = f(&[x[0] * l, x[1] * l, x[2] * l]);
            (
                b * (l / scales.stress),
                r * (l * l / (scales.conductivity * scales.temperature)),
            )
        };
        let src: Option<crate::bulk::local::Sources<'_>> = if self.sources.is_some() {
            Some(&scaled_src)
        } else {
            None
        };
        let n_bulk = self.elements.len();
        let n_seam = self.seams.len();
        let unknowns = self.contact_unknowns();
        let fields = self.phase_fields();
        // Point-major contact Hessians (3D): the nodes' factors, once.
        let hessians = match (&self.contact, unknowns, values.is_some()) {
            (Some(c), Some(u), true) => c.hessian_weights(u),
            _ => None,
        };
        let local = |e: usize, k: Option<&mut [f64]>, r: &mut [f64]| -> Result<()> {
            if e >= n_bulk + n_seam {
                let c = self
                    .contact
                    .as_ref()
                    .expect("contact elements come from an interface");
                c.element(
                    e - n_bulk - n_seam,
                    unknowns.expect("contact present"),
                    hessians.as_ref(),
                    k,
                    r,
                );
                return Ok(());
            }
            if e >= n_bulk {
                self.seam_element(&self.seams[e - n_bulk], &fields, k, r);
                return Ok(());
            }
            let (bi, ei) = self.elements[e];
            let body = &self.bodies[bi];
            let q = &body.quadrature[ei];
            let (mut u, mut th) = (Vec::new(), Vec::new());
            self.gather_nodes(body, &q.conn, &mut u, &mut th);
            let fields = ElementFields { u: &u, theta: &th };
            element_residual_tangent(
                &body.material,
                q,
                self.dim,
                self.coupling,
                &fields,
                src,
                k,
                r,
            );
            Ok(())
        };
        match values {
            Some(v) => {
                self.assembly
                    .assemble(v, residual, |e, k, r| local(e, Some(k), r))?;
            }
            None => self
                .assembly
                .assemble_vector(residual, |e, r| local(e, None, r))?,
        }
        for (r, f) in residual.iter_mut().zip(self.external()) {
            *r -= f;
        }
        Ok(())
    }

    /// Adds the sliding platens' regularization to the tangent's diagonal
    /// (never to the residual), scaled by the mechanical residual relative to
    /// the first one of the load step, within `[1e-6, 1]`: full at the start
    /// of a step (bounded steps along a slide without contact stiffness),
    /// vanishing as Newton converges (its quadratic rate is kept where the
    /// contact resists the slide only weakly), Levenberg–Marquardt-like.
    fn regularize_platens(&mut self, values: &mut [f64], residual: &[f64]) {
        if self.platens.iter().all(|p| p.regularization == 0.0) {
            return;
        }
        let norm = residual
            .iter()
            .zip(&self.eq_class)
            .filter(|(_, c)| **c == 0)
            .map(|(r, _)| r * r)
            .sum::<f64>()
            .sqrt();
        let first = *self.step_residual.get_or_insert(norm);
        let ratio = if first > 0.0 {
            (norm / first).clamp(1e-6, 1.0)
        } else {
            1.0
        };
        let pattern = self.assembly.symbolic();
        for p in self.platens.iter().filter(|p| p.regularization > 0.0) {
            let Some(e) = self.dofs.eq(p.nodes[0], p.field) else {
                continue;
            };
            let range = pattern.col_ptr()[e]..pattern.col_ptr()[e + 1];
            let k = range
                .clone()
                .find(|&k| pattern.row_idx()[k] == e)
                .expect("the pattern holds the diagonal");
            values[k] += p.regularization * ratio;
        }
    }

    /// Residual and tangent of a seam penalty element: `β w J s` and
    /// `β w s sᵀ` per penalized field of the phase (the temperature's `β`
    /// scaled by `k/E`), `J = s·u` the jump of the normal derivative, or the
    /// derivative (local dofs node-major over the phase's `fields`,
    /// [`Model::phase_fields`]).
    fn seam_element(
        &self,
        sm: &SeamElement,
        fields: &[usize],
        mut k: Option<&mut [f64]>,
        r: &mut [f64],
    ) {
        let nf = self.dim + 1;
        let nl = fields.len();
        let n_local = sm.conn.len() * nl;
        let offset = self.bodies[sm.body].node_offset;
        for (pos, &c) in fields.iter().enumerate() {
            if !sm.components.contains(&c) {
                continue;
            }
            let scale = if c == self.dim { sm.thermal_ratio } else { 1.0 };
            for (bw, s) in &sm.points {
                let bw = bw * scale;
                let jump: f64 = s
                    .iter()
                    .zip(&sm.conn)
                    .map(|(si, &a)| si * self.state[(offset + a) * nf + c])
                    .sum();
                for (i, si) in s.iter().enumerate() {
                    r[i * nl + pos] += bw * jump * si;
                }
                if let Some(k) = k.as_deref_mut() {
                    for (j, sj) in s.iter().enumerate() {
                        let col = (j * nl + pos) * n_local;
                        for (i, si) in s.iter().enumerate() {
                            k[col + i * nl + pos] += bw * si * sj;
                        }
                    }
                }
            }
        }
    }

    /// Contact multipliers as a state vector (λN then λθ).
    fn multipliers(&self) -> Vec<f64> {
        match &self.contact {
            Some(c) => c.lambda_n.iter().chain(&c.lambda_t).copied().collect(),
            None => Vec::new(),
        }
    }
}

impl NonlinearProblem for Model {
    fn n_eq(&self) -> usize {
        self.eq_class.len()
    }

    fn eq_fields(&self) -> &[usize] {
        &self.eq_class
    }

    fn field_names(&self) -> &[&'static str] {
        &["mechanical", "thermal", "normal contact", "thermal contact"]
    }

    fn pattern(&self) -> faer::sparse::SymbolicSparseColMatRef<'_, usize> {
        debug_assert!(!self.assembly_stale, "Model::pattern before prepare");
        self.assembly.symbolic()
    }

    fn shared_pattern(&self) -> Option<std::sync::Arc<faer::sparse::SymbolicSparseColMat<usize>>> {
        debug_assert!(!self.assembly_stale, "Model::shared_pattern before prepare");
        Some(self.assembly.shared_pattern())
    }

    fn pattern_version(&self) -> u64 {
        self.pattern_version
    }

    fn storage_report(&self) -> Option<String> {
        let mb = |b: usize| b >> 20;
        let quadrature = self.quadrature_bytes();
        let kept = self
            .kept_assembly
            .as_ref()
            .map_or(0, |(_, a, _)| a.storage_bytes());
        let (points, point_states) = self.contact.as_ref().map_or((0, 0), |c| {
            (
                c.points
                    .iter()
                    .map(|p| {
                        size_of_val(p)
                            + p.conn.capacity() * size_of::<usize>()
                            + p.basis.capacity() * size_of::<f64>()
                    })
                    .sum::<usize>(),
                c.state.iter().map(|s| s.storage_bytes()).sum::<usize>(),
            )
        });
        Some(format!(
            "contact points {} MB, their states {} MB, bulk quadrature {} MB ({} elements), assembly {} MB (scatter map {} MB), other phase's assembly {} MB",
            mb(points),
            mb(point_states),
            mb(quadrature),
            self.bodies
                .iter()
                .map(|b| b.quadrature.len())
                .sum::<usize>(),
            mb(self.assembly.storage_bytes()),
            mb(self.assembly.scatter_map_bytes()),
            mb(kept)
        ))
    }

    fn numbering_version(&self) -> u64 {
        self.numberings
            .iter()
            .find(|m| m.coupling == self.coupling)
            .map_or(0, |m| m.id)
    }

    /// Cholesky without multipliers and LDLᵀ with them where the tangent is
    /// symmetric ([`Model::symmetric_tangent`]), LU elsewhere or when
    /// [`Model::set_symmetric_solvers`] turned them off.
    fn factorization(&self) -> Factorization {
        if !(self.symmetric_solvers && self.symmetric_tangent()) {
            return Factorization::Lu;
        }
        if self.mult_eq == (None, None) {
            return Factorization::Cholesky;
        }
        // Quasi-definite: +1 for the bulk unknowns, −1 for λN and λθ.
        let signs = self
            .eq_class
            .iter()
            .map(|&c| if c < 2 { 1 } else { -1 })
            .collect();
        Factorization::Ldlt { signs }
    }

    /// For Cholesky and LDLᵀ, METIS's nested dissection of the nodes (the
    /// equations grouped by their reference coordinates, a multiplier at its
    /// slave node) or AMD (of the nodes too from 20 000 equations,
    /// [`crate::solve::ordering::node_orders`]), whichever gives the factor
    /// fewer entries; COLAMD for LU. On the adaptive 3D egg box the nested
    /// dissection's factor is 31 % (level 3) and 36 % (level 4) smaller than
    /// AMD's (docs/3d.md, "Stop 40"). The other phase's node orders of the
    /// same mesh are reused where they hold all but a few of the nodes
    /// ([`KeptNodeOrders`]).
    fn ordering(&self, kind: &Factorization) -> Ordering {
        match kind {
            Factorization::Lu => Ordering::Default,
            _ => node_ordering(
                self.assembly.symbolic(),
                &self.eq_coords,
                &self.kept_node_orders,
                self.assembly_coupling,
            ),
        }
    }

    fn ordering_job(&self, kind: &Factorization) -> Option<OrderingJob> {
        if matches!(kind, Factorization::Lu) {
            return None;
        }
        let pattern = self.assembly.shared_pattern();
        let coords = Arc::clone(&self.eq_coords);
        let kept = Arc::clone(&self.kept_node_orders);
        let coupling = self.assembly_coupling;
        Some(Box::new(move || {
            node_ordering((*pattern).as_ref(), &coords, &kept, coupling)
        }))
    }

    fn prepare(&mut self) -> Result<()> {
        let needs = self
            .contact_unknowns()
            .map(|u| Needs::from_terms(u.mechanical_terms, u.thermal_terms));
        if let (Some(c), Some(needs)) = (self.contact.as_mut(), needs) {
            c.prepare(&self.state, needs)?;
            let widened = c.update_band();
            if c.cover_active(false) || widened {
                self.mark_assembly_stale();
            }
        }
        self.ensure_assembly()
    }

    fn set_load(&mut self, load_factor: f64) {
        self.step_residual = None;
        self.load_factor = load_factor;
        let (a, b) = self.path;
        self.load = [
            a[0] + load_factor * (b[0] - a[0]),
            a[1] + load_factor * (b[1] - a[1]),
        ];
        self.dofs
            .impose(&mut self.state, &self.initial, load_factor);
    }

    fn load_varies(&self) -> bool {
        self.path.0 != self.path.1 || !self.dofs.prescribed_in(&self.initial)
    }

    fn assemble(&mut self, mut values: Option<&mut [f64]>, residual: &mut [f64]) -> Result<()> {
        self.ensure_assembly()?;
        self.restore_quadrature();
        self.assemble_all(values.as_deref_mut(), residual)?;
        if let Some(v) = values {
            self.regularize_platens(v, residual);
        }
        Ok(())
    }

    /// The slave nodes in contact at the prepared state
    /// (`ContactInterface::is_active`; a periodic seam's copies counted with
    /// their nodes), hashed in order.
    fn active_set(&self) -> Option<(usize, u64)> {
        use std::hash::{Hash, Hasher};
        let c = self.contact.as_ref()?;
        let mut h = std::collections::hash_map::DefaultHasher::new();
        let mut n = 0;
        for i in (0..c.n_slave()).filter(|&i| c.is_active(i)) {
            i.hash(&mut h);
            n += 1;
        }
        Some((n, h.finish()))
    }

    fn set_contact_curvature(&mut self, on: bool) -> bool {
        let mechanical = self.contact_unknowns().is_some_and(|u| u.mechanical_terms);
        match self.contact.as_mut() {
            Some(c) if mechanical || on => {
                c.set_curvature(on);
                mechanical
            }
            _ => false,
        }
    }

    fn load_norms(&self) -> Vec<f64> {
        let mut s = [0.0; 4];
        for (v, &c) in self.external().iter().zip(&self.eq_class) {
            s[c] += v * v;
        }
        let mut s: Vec<f64> = s.iter().map(|x| x.sqrt()).collect();
        // The multiplier equations carry no external load; their residual
        // `A^I g^I` (`A^I γθ^I`) is a nodal force (heat input) over εN (εθ),
        // which sets their reference magnitude.
        if let Some(c) = &self.contact {
            s[2] = s[0] / c.eps_n;
            s[3] = s[1] / c.eps_t;
        }
        s
    }

    fn update(&mut self, dx: &[f64]) {
        self.dofs
            .add_increment(&dx[..self.n_bulk_eq], &mut self.state);
        let (m0, m1) = self.mult_eq;
        if let Some(c) = self.contact.as_mut() {
            let ns = c.n_slave();
            if let Some(e) = m0 {
                c.lambda_n
                    .iter_mut()
                    .zip(&dx[e..e + ns])
                    .for_each(|(l, d)| *l += d);
            }
            if let Some(e) = m1 {
                c.lambda_t
                    .iter_mut()
                    .zip(&dx[e..e + ns])
                    .for_each(|(l, d)| *l += d);
            }
        }
    }

    fn save(&self) -> Vec<f64> {
        let mut v = self.state.clone();
        v.extend(self.multipliers());
        v
    }

    fn restore(&mut self, saved: &[f64]) {
        let n = self.state.len();
        self.state.copy_from_slice(&saved[..n]);
        if let Some(c) = self.contact.as_mut() {
            let ns = c.n_slave();
            c.lambda_n.copy_from_slice(&saved[n..n + ns]);
            c.lambda_t.copy_from_slice(&saved[n + ns..n + 2 * ns]);
        }
    }

    /// The contact's coupling band and coupled nodes as the restored state needs them
    /// ([`ContactInterface::reset_coupling`]): a failed step's iterates may have projected
    /// far off and widened them for good.
    fn after_cutback(&mut self) {
        if let Some(c) = self.contact.as_mut()
            && c.reset_coupling()
        {
            self.mark_assembly_stale();
        }
    }

    /// The bulk quadrature (1.15 GB against a 2.5 GB factor on the 3D egg
    /// box's fourth level), returned to the system.
    fn release_caches_for_factorization(&mut self) {
        self.release_quadrature();
        super::resources::return_free_memory();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solve::{LoadStepping, Newton, NewtonSettings};
    use crate::verify::bulk::block_mesh;

    /// A block, bottom `uy = 0`; bottom `ux` fixed (`fixed_base`) or a
    /// sliding platen (a rigid lateral mode without stiffness); top `ux` a
    /// sliding platen under the shear `τ` (a traction), or a plain platen
    /// pushed by `τ`.
    fn sheared_block(fixed_base: bool, sliding_top: bool, tau: f64) -> Model {
        let m = Material::default();
        let mut b = ModelBuilder::new(2, Scales::new(1.0, &m));
        let body = b
            .add_body("block", &block_mesh(1.0, 0.5, 2, 3, 2), &m)
            .unwrap();
        b.fix_face(body, 1, Side::Low, 1, 0.0);
        if fixed_base {
            b.fix_face(body, 1, Side::Low, 0, 0.0);
        } else {
            b.sliding_platen(body, 1, Side::Low, 0);
        }
        if sliding_top {
            b.sliding_platen(body, 1, Side::High, 0);
            b.traction(body, 1, Side::High, [tau, 0.0, 0.0]);
        } else {
            // A platen pushing with −τ on a High face: the force +τ|A| in x.
            b.platen(body, 1, Side::High, 0, -tau);
        }
        let mut model = b.build(Coupling::Mechanical).unwrap();
        model.set_path([0.0, 0.0], [1.0, 0.0]);
        Newton::new(NewtonSettings::default(), LoadStepping::default())
            .solve(&mut model)
            .unwrap();
        model
    }

    /// The load varies along a path between different loads, or towards a
    /// prescribed value not yet held (a new frozen temperature), and not
    /// along a path that starts where it ends.
    #[test]
    fn a_path_varies_the_load_where_its_ends_differ() {
        let mut model = sheared_block(true, true, 1.0e3);
        model.set_path([1.0, 0.0], [1.0, 0.0]);
        assert!(!model.load_varies());
        model.set_path([0.0, 0.0], [1.0, 0.0]);
        assert!(model.load_varies());
        model.set_path([1.0, 0.0], [1.0, 0.0]);
        model.set_frozen_temperature(0, 300.0);
        assert!(model.load_varies());
    }

    /// A phase's equations keep their identifier when the phases alternate
    /// (the frozen field's values change, not which unknowns there are), each
    /// phase has its own, and no two models share one.
    #[test]
    fn the_equations_keep_their_identifier_while_the_phases_alternate() {
        let mut model = sheared_block(true, true, 1.0e3);
        let mechanical = model.numbering_version();
        model.set_coupling(Coupling::Thermal).unwrap();
        let thermal = model.numbering_version();
        assert_ne!(thermal, mechanical);
        model.state.iter_mut().for_each(|v| *v += 1e-3);
        model.set_coupling(Coupling::Mechanical).unwrap();
        assert_eq!(model.numbering_version(), mechanical);
        model.set_coupling(Coupling::Thermal).unwrap();
        assert_eq!(model.numbering_version(), thermal);
        let other = sheared_block(true, true, 1.0e3);
        assert_ne!(other.numbering_version(), mechanical);
    }

    #[test]
    fn sliding_platen_regularizes_the_tangent_only() {
        // Singular without the regularization, and no force: no motion.
        let still = sheared_block(false, true, 0.0);
        assert!(still.state.iter().step_by(3).all(|u| u.abs() < 1e-12));
        // Sheared: the sliding platen's equation is the total force, exactly
        // as for a plain platen (no regularization) with the same force.
        let tau = 2.0e4;
        let (a, b) = (
            sheared_block(true, true, tau),
            sheared_block(true, false, tau),
        );
        let ux = a.state[a.platens()[0].nodes[0] * 3];
        assert!(ux > 1e-3, "ux {ux}");
        for (x, y) in a.state.iter().zip(&b.state) {
            assert!((x - y).abs() <= 1e-10 * ux, "{x} vs {y}");
        }
    }
}
