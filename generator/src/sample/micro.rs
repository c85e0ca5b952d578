//! The micro-sample model (spec §3, §5, paper Fig. 2 and 5): body 2 (lower)
//! occupies `z ∈ [−H0, f2(x)]`, body 1 (upper) `z ∈ [f1(x) + g0, H0 + g0]`
//! (3D: `f(x, y)` on the cell `[0, W]²`, the height the last direction),
//! with `g0` such that they first touch at zero load; bottom of body 2 fixed,
//! rigid platen with `p̄N` on top of body 1 (held or free laterally, paper
//! Sect. 5.3), LN or PR lateral faces, mortar
//! contact with body 2 as master (or body 1, switchable), and the thermal
//! conditions of the θ̄c-projection (2.12): the master's external face at a
//! prescribed temperature, the slave's external face under `h̄`.

use crate::bulk::Coupling;
use crate::contact::mortar::ContactInterface;
use crate::geometry::fit::{ArealFit, fit_height_map, resolve_rough_face, try_rough_volume};
use crate::geometry::{
    FitMethod, HierarchicalMesh, NurbsPatch, RoughFace, Side, SurfaceFit, ThbPatch,
    fit_height_function, try_rough_block,
};
use crate::material::Material;
use crate::sample::case::{
    Case, ElementCounts, LateralCondition, MasterBody, RefinementPattern, TopLateral,
};
use crate::solve::{Model, ModelBuilder, NonlinearProblem, Scales, golden_search};
use crate::surface::Surface;
use crate::surface::areal::ArealSurface;
use crate::{Error, Result};

/// Index of the lower body (body 2) in the model.
pub const LOWER: usize = 0;
/// Index of the upper body (body 1) in the model.
pub const UPPER: usize = 1;

/// Geometry of a micro-sample: the fitted surfaces and the first-touch offset.
#[derive(Clone, Debug)]
pub struct SampleGeometry {
    /// Fit of the upper body's surface `f1`.
    pub fit_upper: SampleFit,
    /// Fit of the lower body's surface `f2`.
    pub fit_lower: SampleFit,
    /// Offset `g0` (m) that makes the bodies touch at zero load.
    pub g0: f64,
}

/// A fitted rough surface: a profile `z(x)` (2D) or a height map `z(x, y)` (3D).
#[derive(Clone, Debug, PartialEq)]
pub enum SampleFit {
    /// B-spline graph curve (2D samples).
    Profile(SurfaceFit),
    /// Bivariate B-spline graph surface (3D samples).
    Areal(ArealFit),
}

impl SampleFit {
    /// The fitted height at `(x, y)` (m; `y` unused in 2D).
    pub fn height_at(&self, x: f64, y: f64) -> f64 {
        match self {
            SampleFit::Profile(f) => f.height_at(x),
            SampleFit::Areal(f) => f.height_at(x, y),
        }
    }

    /// Largest height error of the fit (m).
    pub fn max_error(&self) -> f64 {
        match self {
            SampleFit::Profile(f) => f.max_error,
            SampleFit::Areal(f) => f.max_error,
        }
    }

    /// RMS height error of the fit (m).
    pub fn rms_error(&self) -> f64 {
        match self {
            SampleFit::Profile(f) => f.rms_error,
            SampleFit::Areal(f) => f.rms_error,
        }
    }

    /// The largest control height `max |h_i|` (m).
    pub fn peak(&self) -> f64 {
        let h = match self {
            SampleFit::Profile(f) => &f.heights,
            SampleFit::Areal(f) => &f.heights,
        };
        h.iter().fold(0.0f64, |m, z| m.max(z.abs()))
    }
}

/// Builds the case's surfaces, fits them and finds `g0`.
pub fn case_geometry(case: &Case) -> Result<SampleGeometry> {
    if case.dimension() == 3 {
        let (upper, lower) = case.areal_surfaces()?;
        return sample_geometry_3d(case, upper.as_ref(), lower.as_ref());
    }
    let (upper, lower) = case.surfaces()?;
    Ok(sample_geometry(case, upper.as_ref(), lower.as_ref()))
}

/// Fits both height maps of a 3D sample at the discretization's resolution
/// (elements `[nx, ny]` of each body) and finds `g0 = max (f2 − f1)`: the
/// best of a dense grid, refined by a compass search.
pub fn sample_geometry_3d(
    case: &Case,
    upper: &dyn ArealSurface,
    lower: &dyn ArealSurface,
) -> Result<SampleGeometry> {
    let w = case.sample.width;
    let d = &case.discretization;
    let lateral = |c: &ElementCounts| [c.along(0), c.along(1)];
    let (nu, nl) = (lateral(&d.elements_upper), lateral(&d.elements_lower));
    let fu = |x: f64, y: f64| upper.height(x, y);
    let fl = |x: f64, y: f64| lower.height(x, y);
    let fit_upper = fit_height_map(&fu, w, d.degree, nu)?;
    let fit_lower = fit_height_map(&fl, w, d.degree, nl)?;
    let g0 = first_touch(case, |x, y| {
        fit_lower.height_at(x, y) - fit_upper.height_at(x, y)
    });
    Ok(SampleGeometry {
        fit_upper: SampleFit::Areal(fit_upper),
        fit_lower: SampleFit::Areal(fit_lower),
        g0,
    })
}

/// The maximum of `f(x, y)` over the cell `[0, W]²`: the best of an
/// `(n + 1)²` grid, refined by a compass search (steps halved to `1e-12 W`).
fn maximum_on_cell(f: impl Fn(f64, f64) -> f64, w: f64, n: usize) -> f64 {
    let h = w / n as f64;
    let (mut best, mut fb) = ([0.0, 0.0], f64::NEG_INFINITY);
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (h * i as f64, h * j as f64);
            let v = f(x, y);
            if v > fb {
                (best, fb) = ([x, y], v);
            }
        }
    }
    let mut step = h;
    while step > 1e-12 * w {
        let mut moved = false;
        for d in [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]] {
            let c = [
                (best[0] + step * d[0]).clamp(0.0, w),
                (best[1] + step * d[1]).clamp(0.0, w),
            ];
            let v = f(c[0], c[1]);
            if v > fb {
                (best, fb, moved) = (c, v, true);
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    fb
}

/// The maximum of `f(x)` over `[0, W]`: the best of `n + 1` samples, refined
/// by golden-section search around it ([`golden_search`]).
fn maximum_on_interval(f: impl Fn(f64) -> f64, w: f64, n: usize) -> f64 {
    let (mut xb, mut gb) = (0.0, f64::NEG_INFINITY);
    for i in 0..=n {
        let x = w * i as f64 / n as f64;
        let g = f(x);
        if g > gb {
            (xb, gb) = (x, g);
        }
    }
    let bracket = ((xb - w / n as f64).max(0.0), (xb + w / n as f64).min(w));
    gb.max(f(golden_search(|x| -f(x), bracket, 80).midpoint()))
}

/// The first-touch offset `max (f2 − f1)` of the exact surfaces `heights =
/// (f1, f2)` (the fits' is [`SampleGeometry::g0`]), searched as for the fits.
pub fn exact_first_touch(case: &Case, heights: &(Height, Height)) -> f64 {
    first_touch(case, |x, y| (heights.1)(x, y) - (heights.0)(x, y))
}

/// The maximum over the cell of a gap `f2 − f1` (`y` unused in 2D): on a grid
/// finer than the case's elements (16 samples per element in 3D, 64 in 2D),
/// refined by a compass search (3D) or golden-section search (2D).
fn first_touch(case: &Case, gap: impl Fn(f64, f64) -> f64) -> f64 {
    let (w, d) = (case.sample.width, &case.discretization);
    let axes = case.dimension() - 1;
    let n = (0..axes)
        .flat_map(|a| [d.elements_upper.along(a), d.elements_lower.along(a)])
        .max()
        .unwrap_or(1)
        + 1;
    if axes == 2 {
        maximum_on_cell(gap, w, 16 * n)
    } else {
        maximum_on_interval(|x| gap(x, 0.0), w, 64 * n)
    }
}

/// Fits both surfaces at the discretization's resolution and finds `g0`.
pub fn sample_geometry(case: &Case, upper: &dyn Surface, lower: &dyn Surface) -> SampleGeometry {
    let w = case.sample.width;
    let d = &case.discretization;
    let fu = |x: f64| upper.height(x);
    let fl = |x: f64| lower.height(x);
    let fit_upper = fit_height_function(
        &fu,
        w,
        d.degree,
        d.elements_upper.along(0),
        FitMethod::Interpolation,
    );
    let fit_lower = fit_height_function(
        &fl,
        w,
        d.degree,
        d.elements_lower.along(0),
        FitMethod::Interpolation,
    );
    let g0 = first_touch(case, |x, _| fit_lower.height_at(x) - fit_upper.height_at(x));
    SampleGeometry {
        fit_upper: SampleFit::Profile(fit_upper),
        fit_lower: SampleFit::Profile(fit_lower),
        g0,
    }
}

/// Thermal boundary conditions of the micro-sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThermalBc {
    /// Temperature prescribed on the master's external face (K).
    pub master_face_temperature: f64,
    /// Flux magnitude through the slave's external face (W/m²), upper to lower.
    pub flux: f64,
}

/// The two bodies of a micro-sample as THB patches, before any refinement
/// driven by the solution: the rough blocks of the case's meshes refined
/// `interface_levels` times at the interface.
#[derive(Clone, Debug)]
pub struct Bodies {
    /// Body 2, below the interface.
    pub lower: ThbPatch,
    /// Body 1, above it.
    pub upper: ThbPatch,
}

impl Bodies {
    /// The body of index [`LOWER`] or [`UPPER`].
    pub fn get(&self, body: usize) -> &ThbPatch {
        if body == LOWER {
            &self.lower
        } else {
            &self.upper
        }
    }

    /// Control points of both bodies.
    pub fn n_control_points(&self) -> usize {
        self.lower.n_control_points() + self.upper.n_control_points()
    }

    /// The finest refinement level of each body, `[lower, upper]`.
    pub fn levels(&self) -> [usize; 2] {
        [&self.lower, &self.upper].map(|b| b.mesh().depth())
    }
}

/// A surface height `z = f(x, y)` (m; `y` unused in 2D).
pub type Height = Box<dyn Fn(f64, f64) -> f64 + Send + Sync>;

/// The exact heights of a case's surfaces, `(upper f1, lower f2)`: what the
/// fits of [`SampleGeometry`] approximate at the case's resolution.
pub fn case_heights(case: &Case) -> Result<(Height, Height)> {
    if case.dimension() == 3 {
        let (u, l) = case.areal_surfaces()?;
        Ok((
            Box::new(move |x, y| u.height(x, y)),
            Box::new(move |x, y| l.height(x, y)),
        ))
    } else {
        let (u, l) = case.surfaces()?;
        Ok((
            Box::new(move |x, _| u.height(x)),
            Box::new(move |x, _| l.height(x)),
        ))
    }
}

impl Bodies {
    /// The bodies with their rough faces resolved on the exact surfaces
    /// `heights = (f1, f2)` ([`resolve_rough_face`]): the upper body's face
    /// towards `z = f1 + g0`, the lower body's towards `z = f2`. Refined
    /// regions follow the surfaces at their own resolution instead of keeping
    /// the case mesh's fit.
    pub fn resolved(&self, heights: &(Height, Height), g0: f64) -> Result<Bodies> {
        // The two bodies at once (each face's quasi-interpolant in one thread).
        let (lower, upper) = rayon::join(
            || resolve_rough_face(&self.lower, RoughFace::Top, 0.0, &heights.1),
            || resolve_rough_face(&self.upper, RoughFace::Bottom, g0, &heights.0),
        );
        Ok(Bodies {
            lower: lower?,
            upper: upper?,
        })
    }
}

/// The bodies of a case (see [`Bodies`]).
pub fn case_bodies(case: &Case, geo: &SampleGeometry) -> Result<Bodies> {
    let h = case.sample.height;
    let d = &case.discretization;
    // A surface taller than the body would fold it: a clear error naming
    // the key (random samples are only known here).
    let block = |fit: &SampleFit, z: (f64, f64), face: RoughFace, n: usize| {
        match fit {
            SampleFit::Profile(f) => try_rough_block(f, z.0, z.1, face, d.degree, n),
            SampleFit::Areal(f) => try_rough_volume(f, z.0, z.1, face, d.degree, n),
        }
        .map_err(|_| {
            let peak = fit.peak();
            Error::invalid(
                "sample.height",
                format!("{h:e} m"),
                format!(
                    "more than the rough surface's largest control height {peak:e} m \
                     (surface.{} reaches through its body)",
                    if face == RoughFace::Top {
                        "lower"
                    } else {
                        "upper"
                    }
                ),
            )
        })
    };
    let lower_patch = block(
        &geo.fit_lower,
        (0.0, -h),
        RoughFace::Top,
        d.elements_lower.through_height(),
    )?;
    let upper_patch = block(
        &geo.fit_upper,
        (geo.g0, h + geo.g0),
        RoughFace::Bottom,
        d.elements_upper.through_height(),
    )?;
    let periodic = case.sample.lateral == LateralCondition::Periodic;
    Ok(Bodies {
        lower: interface_refined(
            &lower_patch,
            Side::High,
            d.interface_levels,
            periodic,
            d.refinement,
        ),
        upper: interface_refined(
            &upper_patch,
            Side::Low,
            d.interface_levels,
            periodic,
            d.refinement,
        ),
    })
}

/// Builds the micro-sample model for a case with materials (upper, lower):
/// the bodies of [`case_bodies`], positioned at first touch.
pub fn build_model(
    case: &Case,
    geo: &SampleGeometry,
    materials: (&Material, &Material),
    bc: ThermalBc,
    coupling: Coupling,
) -> Result<Model> {
    let bodies = case_bodies(case, geo)?;
    let mut model = build_model_on(case, bodies, materials, bc, coupling)?;
    place_at_first_touch(case, geo, &mut model)?;
    Ok(model)
}

/// Moves the upper body of a model in its reference position to first
/// touch (after the rigid slide to equilibrium with a free sliding top, PR).
pub fn place_at_first_touch(case: &Case, geo: &SampleGeometry, model: &mut Model) -> Result<()> {
    if case.sample.lateral == LateralCondition::Periodic
        && case.sample.top_lateral == TopLateral::Free
    {
        // Start from the rigid bodies' equilibrium: the upper body slid to
        // the offset (x, and y in 3D) where it first touches lowest (Newton
        // then corrects it for elasticity, instead of sliding a wavelength
        // fraction itself).
        let s = rigid_sliding_offset(case, geo).map(|s| model.scales.len(s));
        let nf = model.dim + 1;
        let b = &model.bodies[UPPER];
        for n in b.node_offset..b.node_offset + b.patch.n_control_points() {
            for (d, &sd) in s.iter().enumerate().take(model.dim - 1) {
                model.state[n * nf + d] = sd;
            }
        }
    }
    let vertical = model.dim - 1;
    model.touch(UPPER, vertical)
}

/// The micro-sample model on given bodies, in their reference positions
/// (no first-touch positioning: a refined model takes its state from the
/// coarser one, `homogenize::adapt`).
pub fn build_model_on(
    case: &Case,
    bodies: Bodies,
    materials: (&Material, &Material),
    bc: ThermalBc,
    coupling: Coupling,
) -> Result<Model> {
    let w = case.sample.width;
    let d = &case.discretization;
    let (lower_patch, upper_patch) = (bodies.lower, bodies.upper);
    // The height is the last direction (and displacement component): 1 in
    // plane strain, 2 in 3D; the temperature is the field `dim`.
    let dim = lower_patch.param_dim();
    let hd = dim - 1;
    let mut mb = ModelBuilder::new(dim, Scales::new(w, materials.1));
    if let Some(n) = d.bulk_points {
        mb = mb.bulk_points(n);
    }
    let lo = mb.add_body("lower", lower_patch, materials.1)?;
    let up = mb.add_body("upper", upper_patch, materials.0)?;
    debug_assert_eq!((lo, up), (LOWER, UPPER));
    // Mechanics (Fig. 5): bottom fixed, platen on top.
    for f in 0..dim {
        mb.fix_face(lo, hd, Side::Low, f, 0.0);
    }
    mb.platen(up, hd, Side::High, hd, 1.0);
    for lateral in 0..hd {
        match case.sample.lateral {
            LateralCondition::Linear => {
                mb.linear_lateral(lo, lateral, lateral);
                mb.linear_lateral(up, lateral, lateral);
                if dim == 3 {
                    mb.smooth_symmetry_planes(lo, lateral);
                    mb.smooth_symmetry_planes(up, lateral);
                }
            }
            LateralCondition::Periodic => {
                mb.periodic(lo, lateral);
                mb.periodic(up, lateral);
                if dim == 3 {
                    mb.smooth_seam(lo, lateral);
                    mb.smooth_seam(up, lateral);
                }
            }
        }
    }
    // The top face laterally: held (no macroscopic sliding), or free. Free
    // with PR: the upper body's rigid lateral translation is the unknown of
    // a sliding platen whose equation is a zero net lateral force, i.e. the
    // net tangential contact force vanishes (frictionless sliding, spec §5).
    let sliding = case.sample.lateral == LateralCondition::Periodic
        && case.sample.top_lateral == TopLateral::Free;
    for lateral in 0..hd {
        match case.sample.top_lateral {
            TopLateral::Fixed => mb.fix_face(up, hd, Side::High, lateral, 0.0),
            TopLateral::Free if sliding => {
                mb.sliding_platen(up, hd, Side::High, lateral);
            }
            TopLateral::Free => {}
        }
    }
    // Thermal: θ̄c-projection (2.12); the nominal flux load is |h̄| (multiplier 1).
    let (master, slave) = match case.homogenization.master {
        MasterBody::Lower => ((lo, Side::Low), (up, Side::High)),
        MasterBody::Upper => ((up, Side::High), (lo, Side::Low)),
    };
    mb.fix_face(master.0, hd, master.1, dim, bc.master_face_temperature);
    let into_slave = if slave.0 == UPPER { bc.flux } else { -bc.flux };
    mb.flux(slave.0, hd, slave.1, into_slave);
    mb.initial_temperature(case.load.contact_temperature);
    let period = (case.sample.lateral == LateralCondition::Periodic).then_some(w);
    let (cs, cm) = match case.homogenization.master {
        MasterBody::Lower => ((up, hd, Side::Low), (lo, hd, Side::High)),
        MasterBody::Upper => ((lo, hd, Side::High), (up, hd, Side::Low)),
    };
    mb.contact(cs, cm, &case.contact, period)?;
    mb.build(coupling)
}

/// The THB patch of a body refined `levels` times at its rough face (`side` of
/// the direction through the height), the mesh graded through the height;
/// its levels halve the directions as `refinement` says. Periodic (PR) bodies
/// keep their lateral cell layers alike, so that their periodic ties pair the
/// two faces' functions one to one.
pub fn interface_refined(
    patch: &NurbsPatch,
    side: Side,
    levels: usize,
    periodic: bool,
    refinement: RefinementPattern,
) -> ThbPatch {
    let normal = patch.param_dim() - 1;
    let mut thb = match refinement {
        RefinementPattern::Dyadic => ThbPatch::from_nurbs(patch),
        RefinementPattern::Alternating => ThbPatch::from_nurbs_with_pattern(
            patch,
            HierarchicalMesh::alternating_pattern(patch.param_dim(), normal),
        ),
    };
    if periodic {
        for d in 0..normal {
            thb = thb.periodic(d);
        }
    }
    thb.refined_at_face(normal, side, levels)
}

/// The first-touch offset `g0(s) = max_x (f2(x) − f1(x − s))` (m) of the
/// fitted surfaces when the upper body is slid laterally by `s` (m; `s[1]`
/// along y, 3D only), periodic in x (and y) (PR). Profiles: the best of
/// `samples` points, refined by golden-section search; height maps: the best
/// of a `samples × samples` grid, refined by a compass search.
pub fn first_touch_offset(geo: &SampleGeometry, width: f64, s: [f64; 2], samples: usize) -> f64 {
    let gap = |x: f64, y: f64| {
        let (xl, yl) = (x.rem_euclid(width), y.rem_euclid(width));
        let (xu, yu) = ((x - s[0]).rem_euclid(width), (y - s[1]).rem_euclid(width));
        geo.fit_lower.height_at(xl, yl) - geo.fit_upper.height_at(xu, yu)
    };
    if let SampleFit::Areal(_) = geo.fit_upper {
        return maximum_on_cell(gap, width, samples);
    }
    let dx = width / samples as f64;
    let (mut xb, mut gb) = (0.0, f64::NEG_INFINITY);
    for i in 0..samples {
        let x = dx * i as f64;
        let g = gap(x, 0.0);
        if g > gb {
            (xb, gb) = (x, g);
        }
    }
    let (mut a, mut b) = (xb - dx, xb + dx);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (c, e) = (b - r * (b - a), a + r * (b - a));
        if gap(c, 0.0) > gap(e, 0.0) {
            b = e
        } else {
            a = c
        }
    }
    gb.max(gap(0.5 * (a + b), 0.0))
}

/// The lateral offset `s` (m; `[sx, 0]` in 2D, `[sx, sy]` in 3D) to which
/// rigid bodies under a normal load slide from the reference position (PR,
/// frictionless): the local minimum of the first-touch height
/// [`first_touch_offset`] reached downhill from `s = 0`. A walk with steps
/// of `h = W/512` (each step to the lowest of the neighbours `s ± h e_x` in
/// 2D, and in 3D also `s ± h e_y` and the four diagonal ones at distance
/// `h`: the height is a maximum over the cell, not smooth, and its valleys
/// need not follow the axes; on a tie the first of them; at most 512 steps,
/// so within `(−W, W)` per axis; a step must lower the height by more than
/// `1e-9 W`), then the same search with the step halved to `1e-9 W`.
/// `[0, 0]` exactly when no neighbour of the reference is lower (a neutral
/// cell: a sinusoid on a flat).
pub fn rigid_sliding_offset(case: &Case, geo: &SampleGeometry) -> [f64; 2] {
    let w = case.sample.width;
    let d = &case.discretization;
    let areal = matches!(geo.fit_upper, SampleFit::Areal(_));
    let axes = if areal { 2 } else { 1 };
    let finest = (0..axes)
        .map(|a| d.elements_upper.along(a).max(d.elements_lower.along(a)))
        .max()
        .unwrap_or(1);
    // Profiles: 64 points per element; height maps: an 8-per-element grid
    // (the compass search refines the maximum of each evaluation).
    let samples = if areal { 8 } else { 64 } * (finest + 1);
    let z = |s: [f64; 2]| first_touch_offset(geo, w, s, samples);
    let tol = 1e-9 * w;
    let r = std::f64::consts::FRAC_1_SQRT_2;
    let directions: Vec<[f64; 2]> = [
        [1.0, 0.0],
        [-1.0, 0.0],
        [0.0, 1.0],
        [0.0, -1.0],
        [r, r],
        [-r, -r],
        [r, -r],
        [-r, r],
    ]
    .into_iter()
    .take(if areal { 8 } else { 2 })
    .collect();
    // The lowest neighbour of s at distance h, if lower than z(s) − tol.
    let descend = |s: [f64; 2], zs: f64, h: f64, tol: f64| {
        directions
            .iter()
            .map(|e| {
                let c = [s[0] + h * e[0], s[1] + h * e[1]];
                (c, z(c))
            })
            .fold(None, |best: Option<([f64; 2], f64)>, (c, zc)| match best {
                Some((_, zb)) if zb <= zc => best,
                _ if zc < zs - tol => Some((c, zc)),
                _ => best,
            })
    };
    let n = 512;
    let h = w / n as f64;
    let (mut s, mut zs) = ([0.0, 0.0], z([0.0, 0.0]));
    for _ in 0..n {
        match descend(s, zs, h, tol) {
            Some(next) => (s, zs) = next,
            None => break,
        }
    }
    if s == [0.0, 0.0] {
        return s;
    }
    let mut step = 0.5 * h;
    while step > tol {
        match descend(s, zs, step, 0.0) {
            Some(next) => (s, zs) = next,
            None => step *= 0.5,
        }
    }
    s
}

/// The slave body's index for a case.
pub fn slave_body(case: &Case) -> usize {
    match case.homogenization.master {
        MasterBody::Lower => UPPER,
        MasterBody::Upper => LOWER,
    }
}

/// Interface measurements of a solved micro-sample.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct InterfaceMeasures {
    /// Real contact area fraction (projected on the mean plane).
    pub contact_fraction: f64,
    /// Mean gap over the slave surface (m), non-contact parts included, penetrations counted as 0.
    pub mean_gap: f64,
    /// `[pN^α] = |A|⁻¹ ∫ pN^α dA` (Pa^α) with the lumped referential pressures.
    pub mean_pressure_power: f64,
    /// Largest lumped temperature jump `|γθ^I|` over the active set (K).
    pub max_active_jump: f64,
    /// Approach of the platen (m), positive in compression (with a free
    /// sliding top, PR, it includes the rigid descent of the initial slide).
    pub approach: f64,
    /// Lateral offset of the upper body: the mean `ux` of its top control
    /// points (m); zero when the top face is held laterally.
    pub lateral_offset: f64,
    /// The same along y: the mean `uy` (m; 3D, zero in 2D).
    pub lateral_offset_y: f64,
}

/// Measures the interface of a solved model; `alpha` the exponent of `[pN^α]`.
pub fn measure(model: &Model, alpha: f64) -> Result<InterfaceMeasures> {
    let mut m = measure_but_contact(model, alpha)?;
    m.contact_fraction = contact_fraction(model)?;
    Ok(m)
}

/// The contact interface of a model, or the error that it has none.
fn interface(model: &Model) -> Result<&ContactInterface> {
    model
        .contact
        .as_ref()
        .ok_or_else(|| Error::Geometry("the model has no contact interface".into()))
}

/// The projected area |A| of the slave surface (scaled): the product of its reference
/// extents along the lateral directions.
fn projected_area(model: &Model, c: &ContactInterface) -> f64 {
    (0..model.dim - 1)
        .map(|d| {
            let (lo, hi) = c
                .slave_nodes
                .iter()
                .map(|&n| model.node_reference(n)[d])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x), b.max(x))
                });
            hi - lo
        })
        .product()
}

/// The real contact area fraction of a solved model: the projected length (area in 3D) of
/// the contact zone, where the pressure indicator interpolated from the slave control points
/// is positive (edges inside elements, [`crate::contact::mortar::ContactZone`]), over the
/// projected area |A| of the slave surface. In 3D the edges' fits make it the costliest of
/// the measurements (about 1.2 s on the 72 kPa egg box's level 3, 59 824 unknowns), so the
/// path solver takes it only where a result keeps it.
pub fn contact_fraction(model: &Model) -> Result<f64> {
    let c = interface(model)?;
    let width = projected_area(model, c);
    let contact = c.contact_length(&model.state);
    Ok(if width > 0.0 { contact / width } else { 0.0 })
}

/// [`measure`] without the contact fraction ([`contact_fraction`]), which is `NaN`.
pub fn measure_but_contact(model: &Model, alpha: f64) -> Result<InterfaceMeasures> {
    let c = interface(model)?;
    let s = model.scales;
    let ns = c.n_slave();
    let width = projected_area(model, c);
    // [pN^α] (3.5): the integral over the rough reference surface divided by
    // the *projected* area |A| (the width in 2D).
    let ppow: f64 = (0..ns)
        .map(|i| c.surface_area(i) * c.pressure(i).max(0.0).powf(alpha))
        .sum::<f64>()
        / width;
    let max_jump = (0..ns)
        .filter(|&i| c.is_active(i))
        .map(|i| c.weighted_jump(i).abs())
        .fold(0.0, f64::max);
    let pl = &model.platens()[0];
    let top = model.bodies[UPPER].face_nodes(model.dim - 1, Side::High);
    let offset =
        |d: usize| top.iter().map(|&n| model.displacement(n, d)).sum::<f64>() / top.len() as f64;
    Ok(InterfaceMeasures {
        contact_fraction: f64::NAN,
        mean_gap: c.mean_gap() * s.length,
        mean_pressure_power: ppow * s.stress.powf(alpha),
        max_active_jump: max_jump * s.temperature,
        approach: -model.displacement(pl.nodes[0], pl.field),
        lateral_offset: offset(0),
        lateral_offset_y: if model.dim == 3 { offset(1) } else { 0.0 },
    })
}

/// The net lateral forces on the upper body along x (and y in 3D) (N per m
/// of depth in 2D, N in 3D) when its top face slides freely (PR,
/// `top_lateral = "free"`): the residuals of the sliding platens'
/// equations, i.e. the net tangential contact force, which equilibrium makes
/// zero. `None` without a sliding platen or outside the mechanical unknowns
/// (thermal phase).
pub fn net_lateral_force(model: &mut Model) -> Result<Option<Vec<f64>>> {
    let eqs: Vec<usize> = model
        .platens()
        .iter()
        .filter(|p| p.regularization > 0.0)
        .filter_map(|p| model.dofs().eq(p.nodes[0], p.field))
        .collect();
    if eqs.is_empty() {
        return Ok(None);
    }
    model.prepare()?;
    let mut r = vec![0.0; model.n_eq()];
    model.assemble(None, &mut r)?;
    let area = model.scales.length.powi(model.dim as i32 - 1);
    Ok(Some(
        eqs.iter()
            .map(|&eq| r[eq] * model.scales.stress * area)
            .collect(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry(upper: &str, lower: &str) -> (Case, SampleGeometry) {
        let text = format!(
            "[surface.upper]\n{upper}\n[surface.lower]\n{lower}\n\
             [discretization]\nelements_upper = [16, 4]\nelements_lower = [12, 4]\n"
        );
        let case = Case::from_toml(&text, std::path::Path::new(".")).unwrap();
        let (su, sl) = case.surfaces().unwrap();
        let geo = sample_geometry(&case, su.as_ref(), sl.as_ref());
        (case, geo)
    }

    #[test]
    fn rigid_sliding_offset_matches_shifted_sinusoids() {
        let sin = |phase: f64| {
            format!("kind = \"sinusoid\"\nrms = 1e-6\nwavelength = 1e-5\nphase = {phase:e}")
        };
        let w = 1.0e-5;
        for (phase, expected) in [
            (std::f64::consts::FRAC_PI_2, 0.25 * w),
            (-std::f64::consts::FRAC_PI_2, -0.25 * w),
            (0.0, 0.0),
        ] {
            let (case, geo) = geometry(&sin(phase), &sin(0.0));
            let s = rigid_sliding_offset(&case, &geo);
            assert!(
                (s[0] - expected).abs() < 1e-3 * w && s[1] == 0.0,
                "phase {phase}: {s:?}"
            );
            // There the surfaces match (up to the fits).
            assert!(first_touch_offset(&geo, w, s, 4096) < 1e-8);
        }
        // A sinusoid on a flat is neutral: no slide.
        let (case, geo) = geometry(&sin(0.3), "kind = \"flat\"");
        assert_eq!(rigid_sliding_offset(&case, &geo), [0.0, 0.0]);
    }

    /// 3D: an egg box shifted by the phases `(φx, φy)` slides back by
    /// `(φx, φy)λ/2π` along x and y (the matched pair nearest downhill; the
    /// egg box repeats after `(λ/2, λ/2)` as well), where the fitted surfaces
    /// match; an egg box on a flat does not slide.
    #[test]
    fn rigid_sliding_offset_matches_shifted_egg_boxes_in_3d() {
        let egg = |px: f64, py: f64| {
            format!(
                "kind = \"sinusoid\"\npattern = \"egg-box\"\nrms = 1e-6\nwavelength = 1e-5\n\
                 phase = {px:e}\nphase_y = {py:e}"
            )
        };
        let w = 1.0e-5;
        let geometry_3d = |upper: &str, lower: &str| {
            let text = format!(
                "[sample]\ndimension = 3\nlateral = \"periodic\"\n\
                 [surface.upper]\n{upper}\n[surface.lower]\n{lower}\n\
                 [discretization]\nelements_upper = [6, 6, 3]\nelements_lower = [5, 5, 3]\n"
            );
            let case = Case::from_toml(&text, std::path::Path::new(".")).unwrap();
            let (su, sl) = case.areal_surfaces().unwrap();
            let geo = sample_geometry_3d(&case, su.as_ref(), sl.as_ref()).unwrap();
            (case, geo)
        };
        use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
        for (px, py) in [
            (FRAC_PI_2, 0.0),
            (FRAC_PI_2, FRAC_PI_4),
            (-FRAC_PI_4, FRAC_PI_2),
        ] {
            let (case, geo) = geometry_3d(&egg(px, py), &egg(0.0, 0.0));
            let s = rigid_sliding_offset(&case, &geo);
            let expected = [px, py].map(|p| p / std::f64::consts::TAU * w);
            // Off the exact offset by δ, the exact surfaces' first touch rises
            // by at least δ times the least directional slope bound of the
            // egg box, √2·rms·2π/λ; the fits move it by their errors.
            let fits = geo.fit_upper.max_error() + geo.fit_lower.max_error();
            let slope = 2f64.sqrt() * 1e-6 * std::f64::consts::TAU / w;
            for a in 0..2 {
                assert!(
                    (s[a] - expected[a]).abs() <= 2.0 * fits / slope,
                    "phases ({px}, {py}): {s:?}, expected {expected:?}"
                );
            }
            // There the exact surfaces match: the first-touch height of the
            // fitted ones is bounded by the fits' errors.
            let at = |s: [f64; 2]| first_touch_offset(&geo, w, s, 56);
            assert!(at(s) <= fits, "{} vs the fits' {fits}", at(s));
        }
        let (case, geo) = geometry_3d(&egg(0.3, 0.2), "kind = \"flat\"");
        assert_eq!(rigid_sliding_offset(&case, &geo), [0.0, 0.0]);
    }
}
