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
use crate::geometry::fit::{ArealFit, fit_height_map, try_rough_volume};
use crate::geometry::{
    FitMethod, NurbsPatch, RoughFace, Side, SurfaceFit, ThbPatch, fit_height_function,
    try_rough_block,
};
use crate::material::Material;
use crate::sample::case::{Case, ElementCounts, LateralCondition, MasterBody, TopLateral};
use crate::solve::{Model, ModelBuilder, NonlinearProblem, Scales};
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
    let gap = |x: f64, y: f64| fit_lower.height_at(x, y) - fit_upper.height_at(x, y);
    let n = 16 * (nu.into_iter().chain(nl).max().unwrap_or(1) + 1);
    let h = w / n as f64;
    let (mut best, mut gb) = ([0.0, 0.0], f64::NEG_INFINITY);
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (h * i as f64, h * j as f64);
            let g = gap(x, y);
            if g > gb {
                (best, gb) = ([x, y], g);
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
            let g = gap(c[0], c[1]);
            if g > gb {
                (best, gb, moved) = (c, g, true);
            }
        }
        if !moved {
            step *= 0.5;
        }
    }
    Ok(SampleGeometry {
        fit_upper: SampleFit::Areal(fit_upper),
        fit_lower: SampleFit::Areal(fit_lower),
        g0: gb,
    })
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
    // First touch: g0 = max (f2 − f1) over a dense sampling of the fitted curves,
    // refined by golden-section search around the best sample.
    let n = 64 * (d.elements_upper.along(0).max(d.elements_lower.along(0)) + 1);
    let gap = |x: f64| fit_lower.height_at(x) - fit_upper.height_at(x);
    let (mut xb, mut gb) = (0.0, f64::NEG_INFINITY);
    for i in 0..=n {
        let x = w * i as f64 / n as f64;
        let g = gap(x);
        if g > gb {
            (xb, gb) = (x, g);
        }
    }
    let (mut a, mut b) = ((xb - w / n as f64).max(0.0), (xb + w / n as f64).min(w));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (c, e) = (b - r * (b - a), a + r * (b - a));
        if gap(c) > gap(e) { b = e } else { a = c }
    }
    let g0 = gb.max(gap(0.5 * (a + b)));
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
        [&self.lower, &self.upper].map(|b| b.mesh().n_levels() - 1)
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
        lower: interface_refined(&lower_patch, Side::High, d.interface_levels, periodic),
        upper: interface_refined(&upper_patch, Side::Low, d.interface_levels, periodic),
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
        // the offset where it first touches lowest (Newton then corrects it
        // for elasticity, instead of sliding a wavelength fraction itself).
        // (3D: no rigid pre-slide yet; Newton slides from the reference.)
        let s = match geo.fit_upper {
            SampleFit::Profile(_) => model.scales.len(rigid_sliding_offset(case, geo)),
            SampleFit::Areal(_) => 0.0,
        };
        let nf = model.dim + 1;
        let b = &model.bodies[UPPER];
        for n in b.node_offset..b.node_offset + b.patch.n_control_points() {
            model.state[n * nf] = s;
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
            }
            LateralCondition::Periodic => {
                mb.periodic(lo, lateral);
                mb.periodic(up, lateral);
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
/// the direction through the height), the mesh graded through the height.
/// Periodic (PR) bodies keep their lateral cell layers alike, so that their
/// periodic ties pair the two faces' functions one to one.
pub fn interface_refined(
    patch: &NurbsPatch,
    side: Side,
    levels: usize,
    periodic: bool,
) -> ThbPatch {
    let normal = patch.param_dim() - 1;
    let mut thb = ThbPatch::from_nurbs(patch);
    if periodic {
        for d in 0..normal {
            thb = thb.periodic(d);
        }
    }
    thb.refined_at_face(normal, side, levels)
}

/// The first-touch offset `g0(s) = max_x (f2(x) − f1(x − s))` (m) of the
/// fitted surfaces when the upper body is slid laterally by `s` (m), periodic
/// in `x` (PR): the best of `samples` points, refined by golden-section search.
pub fn first_touch_offset(geo: &SampleGeometry, width: f64, s: f64, samples: usize) -> f64 {
    let gap = |x: f64| {
        let xl = x.rem_euclid(width);
        let xu = (x - s).rem_euclid(width);
        geo.fit_lower.height_at(xl, 0.0) - geo.fit_upper.height_at(xu, 0.0)
    };
    let dx = width / samples as f64;
    let (mut xb, mut gb) = (0.0, f64::NEG_INFINITY);
    for i in 0..samples {
        let x = dx * i as f64;
        let g = gap(x);
        if g > gb {
            (xb, gb) = (x, g);
        }
    }
    let (mut a, mut b) = (xb - dx, xb + dx);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (c, e) = (b - r * (b - a), a + r * (b - a));
        if gap(c) > gap(e) { b = e } else { a = c }
    }
    gb.max(gap(0.5 * (a + b)))
}

/// The lateral offset (m) to which rigid bodies under a normal load slide
/// from the reference position (PR, frictionless): the local minimum of the
/// first-touch height [`first_touch_offset`] reached downhill from `s = 0`
/// (on a grid of `W/512`, refined by golden-section search; the lower
/// neighbour decides at a maximum, `+` on a tie). Within `(−W, W)`.
pub fn rigid_sliding_offset(case: &Case, geo: &SampleGeometry) -> f64 {
    let w = case.sample.width;
    let d = &case.discretization;
    let samples = 64 * (d.elements_upper.along(0).max(d.elements_lower.along(0)) + 1);
    let n = 512;
    let h = w / n as f64;
    let z = |s: f64| first_touch_offset(geo, w, s, samples);
    let (mut k, mut zk) = (0i64, z(0.0));
    let (zp, zm) = (z(h), z(-h));
    let step = if zp <= zm { 1 } else { -1 };
    let tol = 1e-9 * w;
    if zp.min(zm) < zk - tol {
        while k.abs() < n {
            let zn = z((k + step) as f64 * h);
            if zn >= zk - tol {
                break;
            }
            (k, zk) = (k + step, zn);
        }
    } else {
        return 0.0;
    }
    let (mut a, mut b) = ((k - 1) as f64 * h, (k + 1) as f64 * h);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (c, e) = (b - r * (b - a), a + r * (b - a));
        if z(c) < z(e) { b = e } else { a = c }
    }
    0.5 * (a + b)
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
}

/// Measures the interface of a solved model; `alpha` the exponent of `[pN^α]`.
pub fn measure(model: &Model, alpha: f64) -> Result<InterfaceMeasures> {
    let c = model
        .contact
        .as_ref()
        .ok_or_else(|| Error::Geometry("the model has no contact interface".into()))?;
    let s = model.scales;
    let ns = c.n_slave();
    // Contact fraction: the projected length (area in 3D) of the contact
    // zone, where the pressure indicator interpolated from the slave control
    // points is positive (edges inside elements,
    // [`crate::contact::mortar::ContactZone`]), over the projected area
    // |A| of the slave surface: the product of its reference extents along
    // the lateral directions.
    let width: f64 = (0..model.dim - 1)
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
        .product();
    let contact = c.contact_length(&model.state);
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
    let lateral_offset =
        top.iter().map(|&n| model.displacement(n, 0)).sum::<f64>() / top.len() as f64;
    Ok(InterfaceMeasures {
        contact_fraction: if width > 0.0 { contact / width } else { 0.0 },
        mean_gap: c.mean_gap() * s.length,
        mean_pressure_power: ppow * s.stress.powf(alpha),
        max_active_jump: max_jump * s.temperature,
        approach: -model.displacement(pl.nodes[0], pl.field),
        lateral_offset,
    })
}

/// The net lateral force on the upper body along x (N per m of depth in 2D, N in 3D) when its top
/// face slides freely (PR, `top_lateral = "free"`): the residual of the
/// sliding platen's equation, i.e. the net tangential contact force, which
/// equilibrium makes zero. `None` without a sliding platen or outside the
/// mechanical unknowns (thermal phase).
pub fn net_lateral_force(model: &mut Model) -> Result<Option<f64>> {
    let Some(eq) = model
        .platens()
        .iter()
        .find(|p| p.regularization > 0.0)
        .and_then(|p| model.dofs().eq(p.nodes[0], p.field))
    else {
        return Ok(None);
    };
    model.prepare()?;
    let mut r = vec![0.0; model.n_eq()];
    model.assemble(None, &mut r)?;
    let area = model.scales.length.powi(model.dim as i32 - 1);
    Ok(Some(r[eq] * model.scales.stress * area))
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
            assert!((s - expected).abs() < 1e-3 * w, "phase {phase}: {s}");
            // There the surfaces match (up to the fits).
            assert!(first_touch_offset(&geo, w, s, 4096) < 1e-8);
        }
        // A sinusoid on a flat is neutral: no slide.
        let (case, geo) = geometry(&sin(0.3), "kind = \"flat\"");
        assert_eq!(rigid_sliding_offset(&case, &geo), 0.0);
    }
}
