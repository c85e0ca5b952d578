//! Manufactured solutions on a curved NURBS domain (spec §10.1): the quarter
//! annulus `1 ≤ r ≤ 2` (m), fields vanishing on its boundary, for nonlinear
//! conduction with `k(θ)` (5.1) and for finite-strain thermoelasticity.
//! Observed L2 and H1 rates over uniform refinements against `p + 1` and `p`.
//!
//! For `p ≥ 2` the annulus is exact (NURBS). For `p = 1` a curved boundary
//! cannot be represented: the domain is the inscribed polygon with vertices
//! on the two circles (the isoparametric bilinear approximation), whose
//! geometric error is of the same order as the discretization error.

use std::sync::Arc;

use nalgebra::Vector3;

use crate::analytical::manufactured::{
    ExactFields, annulus_fields, cube_fields, manufactured_sources,
};
use crate::bulk::Coupling;
use crate::geometry::{KnotVector, NurbsPatch, shapes};
use crate::material::Material;
use crate::solve::{
    LoadStepping, Model, ModelBuilder, Newton, NewtonSettings, Scales, SolveHistory,
};
use crate::verify::{Case, Check, fitted_rate, record_series};
use crate::{Error, Result};

/// The annulus discretized with degree `p` and `n` elements per direction.
pub fn annulus_mesh(p: usize, n: usize) -> Result<NurbsPatch> {
    if p == 1 {
        let kv = KnotVector::open_uniform(1, n, 0.0, 1.0);
        let mut pts = Vec::new();
        for j in 0..=n {
            let r = 1.0 + j as f64 / n as f64;
            for i in 0..=n {
                let phi = std::f64::consts::FRAC_PI_2 * i as f64 / n as f64;
                pts.push([r * phi.cos(), r * phi.sin(), 0.0]);
            }
        }
        let w = vec![1.0; pts.len()];
        return NurbsPatch::new(vec![kv.clone(), kv], pts, w);
    }
    let mut g = shapes::quarter_annulus(1.0, 2.0);
    g = g.elevate_degree(0, p - 2).elevate_degree(1, p - 1);
    if n > 1 {
        g = g.refine_uniform(0, n).refine_uniform(1, n);
    }
    Ok(g)
}

/// Which physics a manufactured solution exercises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MmsKind {
    /// Nonlinear conduction with `k(θ)` on the undeformed body.
    Conduction,
    /// Coupled finite-strain thermoelasticity.
    Thermoelastic,
}

/// Material and amplitudes of the manufactured fields.
pub fn mms_setup(kind: MmsKind) -> (Material, f64, f64) {
    let mut m = Material::default();
    match kind {
        MmsKind::Conduction => (m, 0.0, 60.0),
        MmsKind::Thermoelastic => {
            // A visible thermal strain (α0 Δθ ≈ 3 %) and strains of ≈ 10 %.
            m.thermal_expansion = 1e-3;
            (m, 0.02, 30.0)
        }
    }
}

/// Errors of one solve: (L2 u, H1 u, L2 θ, H1 θ), absolute, SI.
#[derive(Clone, Copy, Debug)]
pub struct MmsErrors {
    /// L2 norm of the displacement error (m·m).
    pub l2_u: f64,
    /// H1 seminorm of the displacement error.
    pub h1_u: f64,
    /// L2 norm of the temperature error.
    pub l2_t: f64,
    /// H1 seminorm of the temperature error.
    pub h1_t: f64,
}

/// Solves the manufactured problem on `mesh` and measures its errors.
pub fn solve_mms(kind: MmsKind, mesh: &NurbsPatch) -> Result<(MmsErrors, SolveHistory)> {
    solve_mms_with(kind, mesh, 2, annulus_fields)
}

/// The exact fields of a manufactured family: `(x, A_u, A_θ, θ0)`.
pub type FieldFamily = fn(&[f64; 3], f64, f64, f64) -> ExactFields;

/// Solves the manufactured problem of `family` on `mesh` in dimension `dim`
/// (every face fixed to the exact, vanishing, boundary values).
pub fn solve_mms_with(
    kind: MmsKind,
    mesh: &NurbsPatch,
    dim: usize,
    family: FieldFamily,
) -> Result<(MmsErrors, SolveHistory)> {
    solve_mms_with_points(kind, mesh, dim, family, None)
}

/// [`solve_mms_with`] with `bulk_points` Gauss points per direction (default `p + 2`).
pub fn solve_mms_with_points(
    kind: MmsKind,
    mesh: &NurbsPatch,
    dim: usize,
    family: FieldFamily,
    bulk_points: Option<usize>,
) -> Result<(MmsErrors, SolveHistory)> {
    let (model, hist) = solve_mms_family(kind, mesh, dim, family, bulk_points)?;
    Ok((errors(&model, &exact_fields(kind, family)), hist))
}

/// The exact fields of `family` with the amplitudes of [`mms_setup`]`(kind)`.
pub fn exact_fields(
    kind: MmsKind,
    family: FieldFamily,
) -> impl Fn(&[f64; 3]) -> ExactFields + Send + Sync + 'static {
    let (m, au, at) = mms_setup(kind);
    let theta0 = m.reference_temperature;
    move |x: &[f64; 3]| family(x, au, at, theta0)
}

/// The solved manufactured model of the annulus (2D, [`annulus_fields`]).
pub fn solve_mms_model(kind: MmsKind, mesh: &NurbsPatch) -> Result<Model> {
    Ok(solve_mms_family(kind, mesh, 2, annulus_fields, None)?.0)
}

/// Solves the manufactured problem of `family` on `mesh` in dimension `dim`
/// (`bulk_points` Gauss points per direction, default `p + 2`).
fn solve_mms_family(
    kind: MmsKind,
    mesh: &NurbsPatch,
    dim: usize,
    family: FieldFamily,
    bulk_points: Option<usize>,
) -> Result<(Model, SolveHistory)> {
    let m = mms_setup(kind).0;
    let theta0 = m.reference_temperature;
    let ms = m.clone();
    let exact = exact_fields(kind, family);
    let sources = Arc::new(move |x: &[f64; 3]| -> (Vector3<f64>, f64) {
        manufactured_sources(&ms, &exact(x))
    });
    let mut b = ModelBuilder::new(dim, Scales::new(1.0, &m));
    if let Some(n) = bulk_points {
        b = b.bulk_points(n);
    }
    let body = b.add_body("domain", mesh, &m)?;
    for dir in 0..dim {
        for side in [crate::geometry::Side::Low, crate::geometry::Side::High] {
            for f in 0..=dim {
                let v = if f == dim { theta0 } else { 0.0 };
                b.fix_face(body, dir, side, f, v);
            }
        }
    }
    b.sources(sources);
    let coupling = match kind {
        MmsKind::Conduction => Coupling::Thermal,
        MmsKind::Thermoelastic => Coupling::Coupled,
    };
    let mut model = b.build(coupling)?;
    let mut newton = Newton::new(NewtonSettings::default(), LoadStepping::default());
    let hist = newton.solve(&mut model)?;
    Ok((model, hist))
}

/// The unit cube `[0, 1]³` with degree `p` and `n` (even) elements per
/// direction, not affinely parametrized: the interior control points of the
/// coarsest mesh (degree `min(p, 2)`, 2 elements per direction) are moved by a
/// smooth warp, then the patch is degree-elevated and refined by knot
/// insertion, so the geometry is the same on every level (nested spaces) and
/// the faces stay the cube's (the 3D manufactured fields vanish on them).
pub fn warped_cube_mesh(p: usize, n: usize) -> Result<NurbsPatch> {
    if p == 0 || n < 2 || !n.is_multiple_of(2) {
        return Err(Error::Geometry(format!(
            "warped cube: need p >= 1 and an even n >= 2, got {p}, {n}"
        )));
    }
    let q = p.min(2);
    let mut g = shapes::cuboid([0.0; 3], [1.0; 3]);
    for dir in 0..3 {
        g = g.elevate_degree(dir, q - 1).refine_uniform(dir, 2);
    }
    let counts = g.n_per_dir();
    let mut points = g.control_points().to_vec();
    for (a, x) in points.iter_mut().enumerate() {
        let ijk = g.ijk(a);
        if (0..3).any(|d| ijk[d] == 0 || ijk[d] + 1 == counts[d]) {
            continue;
        }
        let y = *x;
        x[0] += 0.08 * (std::f64::consts::TAU * y[1]).cos();
        x[1] += 0.08 * (std::f64::consts::TAU * y[2]).sin();
        x[2] -= 0.08 * (std::f64::consts::TAU * y[0]).cos();
    }
    let mut g = NurbsPatch::new(g.knots().to_vec(), points, g.weights().to_vec())?;
    for dir in 0..3 {
        g = g.elevate_degree(dir, p - q).refine_uniform(dir, n / 2);
    }
    Ok(g)
}

/// Element counts per direction of the 3D refinement study for degree `p`.
pub fn levels_3d(p: usize) -> Vec<usize> {
    match p {
        1 => vec![4, 8, 16],
        _ => vec![2, 4, 8],
    }
}

/// L2 and H1 errors against exact fields, with `p + 3` Gauss points.
pub fn errors(model: &Model, exact: &dyn Fn(&[f64; 3]) -> ExactFields) -> MmsErrors {
    let (mut l2u, mut h1u, mut l2t, mut h1t) = (0.0, 0.0, 0.0, 0.0);
    let nf = model.dim + 1;
    let (ls, ts) = (model.scales.length, model.scales.temperature);
    for body in &model.bodies {
        let nq: Vec<usize> = body.patch.knots().iter().map(|k| k.degree() + 3).collect();
        for e in 0..body.patch.n_elements() {
            let q = body.patch.element_quadrature(e, &nq);
            let mut scratch = Vec::new();
            for (qp, r, dr) in q.points_with_basis(&mut scratch) {
                let d = model.dim;
                let x = [qp.x[0] * ls, qp.x[1] * ls, qp.x[2] * ls];
                let e = exact(&x);
                let mut u = [0.0; 3];
                let mut gu = [[0.0; 3]; 3];
                let (mut t, mut gt) = (0.0, [0.0; 3]);
                for (a, &c) in q.conn.iter().enumerate() {
                    let s = &model.state[(c + body.node_offset) * nf..];
                    for i in 0..d {
                        u[i] += r[a] * s[i] * ls;
                        for j in 0..d {
                            gu[i][j] += s[i] * dr[a][j];
                        }
                        gt[i] += s[d] * dr[a][i] * ts / ls;
                    }
                    t += r[a] * s[d] * ts;
                }
                let w = qp.weight * ls.powi(d as i32);
                for i in 0..d {
                    l2u += w * (u[i] - e.u[i]).powi(2);
                    h1t += w * (gt[i] - e.grad_theta[i]).powi(2);
                    for j in 0..d {
                        h1u += w * (gu[i][j] - e.grad_u[(i, j)]).powi(2);
                    }
                }
                l2t += w * (t - e.theta).powi(2);
            }
        }
    }
    MmsErrors {
        l2_u: l2u.sqrt(),
        h1_u: h1u.sqrt(),
        l2_t: l2t.sqrt(),
        h1_t: h1t.sqrt(),
    }
}

/// Element counts per direction of the refinement study for degree `p`.
pub fn levels(p: usize) -> Vec<usize> {
    match p {
        1 => vec![4, 8, 16, 32, 64],
        2 => vec![2, 4, 8, 16, 32],
        _ => vec![2, 4, 8, 16],
    }
}

/// The refinement study: errors per level and fitted rates, as checks.
pub fn convergence_study(kind: MmsKind, p: usize) -> Result<Vec<Check>> {
    convergence_study_in(kind, p, 2)
}

/// The refinement study in dimension `dim`: 2, the curved annulus; 3, the
/// warped cube with the fields of [`crate::analytical::manufactured::cube_fields`].
pub fn convergence_study_in(kind: MmsKind, p: usize, dim: usize) -> Result<Vec<Check>> {
    study(kind, p, dim, None)
}

/// The 3D refinement study with the reduced rule of `p` Gauss points per
/// direction (one fewer than the full `p + 1`; the least `[discretization]
/// bulk_points` accepts, docs/3d.md, "Stop 97"): the same optimal rates. On
/// these maximally smooth splines its stiffness has no spurious zero-energy
/// modes (test `the_least_accepted_rule_keeps_only_the_rigid_modes`).
pub fn convergence_study_reduced(kind: MmsKind, p: usize) -> Result<Vec<Check>> {
    study(kind, p, 3, Some(p))
}

fn study(kind: MmsKind, p: usize, dim: usize, bulk_points: Option<usize>) -> Result<Vec<Check>> {
    let prefix = match (dim, bulk_points) {
        (3, Some(_)) => "mms3d_reduced",
        (3, None) => "mms3d",
        _ => "mms",
    };
    let name = match kind {
        MmsKind::Conduction => format!("{prefix}_conduction_p{p}"),
        MmsKind::Thermoelastic => format!("{prefix}_thermoelastic_p{p}"),
    };
    let ns = if dim == 3 { levels_3d(p) } else { levels(p) };
    let mut hs = Vec::new();
    let mut es = Vec::new();
    for &n in &ns {
        let (e, _) = if dim == 3 {
            solve_mms_with_points(kind, &warped_cube_mesh(p, n)?, 3, cube_fields, bulk_points)?
        } else {
            solve_mms(kind, &annulus_mesh(p, n)?)?
        };
        hs.push(1.0 / n as f64);
        es.push(e);
    }
    // The error curves of the plots (docs/validation.md).
    let fields: &[&str] = if kind == MmsKind::Thermoelastic {
        &["temperature", "displacement"]
    } else {
        &["temperature"]
    };
    for &field in fields {
        let (l2, h1): (Vec<f64>, Vec<f64>) = es
            .iter()
            .map(|e| match field {
                "temperature" => (e.l2_t, e.h1_t),
                _ => (e.l2_u, e.h1_u),
            })
            .unzip();
        let labels = ("h = 1/n", "error norm");
        record_series(&name, &format!("L2 {field}"), labels, &hs, &l2);
        record_series(&name, &format!("H1 {field}"), labels, &hs, &h1);
    }
    // Rates from the three finest levels (the asymptotic range); in 3D,
    // where the meshes are coarse, from the two finest (the rates approach
    // the optimal ones from above: p = 2, L2 3.35 then 3.19).
    let k = hs.len().saturating_sub(if dim == 3 { 2 } else { 3 });
    let rate = |f: &dyn Fn(&MmsErrors) -> f64| {
        let e: Vec<f64> = es[k..].iter().map(f).collect();
        (fitted_rate(&hs[k..], &e), *e.last().unwrap())
    };
    let pf = p as f64;
    let tol = if dim == 3 { 0.25 } else { 0.15 };
    let mut checks = Vec::new();
    let mut push = |q: &str, f: &dyn Fn(&MmsErrors) -> f64, expected: f64| {
        let (r, e) = rate(f);
        checks.push(Check::rate(&name, q, e, r, expected, tol));
    };
    push("L2 rate temperature", &|e| e.l2_t, pf + 1.0);
    push("H1 rate temperature", &|e| e.h1_t, pf);
    if kind == MmsKind::Thermoelastic {
        push("L2 rate displacement", &|e| e.l2_u, pf + 1.0);
        push("H1 rate displacement", &|e| e.h1_u, pf);
    }
    if es.iter().any(|e| !e.l2_t.is_finite()) {
        return Err(Error::Geometry("non-finite error norm".into()));
    }
    Ok(checks)
}

/// Quadratic convergence of Newton's method on the finite-strain
/// manufactured problem solved in one load step: the estimated order
/// `log(r_{k+1}/r_k) / log(r_k/r_{k−1})` of the last iterations above round-off.
pub fn newton_order() -> Result<(Vec<f64>, Vec<f64>)> {
    let mesh = annulus_mesh(2, 8)?;
    let (_, hist) = solve_mms(MmsKind::Thermoelastic, &mesh)?;
    let step = &hist.steps[0];
    let r: Vec<f64> = step
        .iterations
        .iter()
        .map(|i| i.residuals.iter().map(|v| v * v).sum::<f64>().sqrt())
        .collect();
    let mut orders = Vec::new();
    for k in 1..r.len().saturating_sub(1) {
        // Only where the next residual is well above round-off.
        if r[k + 1] > 1e-11 * r[0] {
            orders.push((r[k + 1] / r[k]).ln() / (r[k] / r[k - 1]).ln());
        }
    }
    Ok((r, orders))
}

fn newton_case() -> Result<Vec<Check>> {
    let (r, orders) = newton_order()?;
    // The last order before round-off is the asymptotic one.
    let best = orders.last().copied().unwrap_or(f64::NAN);
    let mut c = Check::with_error(
        "newton_quadratic",
        &format!(
            "order, residuals {}",
            r.iter()
                .map(|v| format!("{v:.1e}"))
                .collect::<Vec<_>>()
                .join(" ")
        ),
        best,
        2.0,
        (2.0 - best).max(0.0),
        0.2,
    );
    c.rate = Some(best);
    Ok(vec![c])
}

/// The manufactured-solution cases.
pub fn cases() -> Vec<Case> {
    vec![
        Case {
            name: "mms_conduction_p1",
            description: "k(θ) conduction, annulus, p=1",
            run: || convergence_study(MmsKind::Conduction, 1),
        },
        Case {
            name: "mms_conduction_p2",
            description: "k(θ) conduction, annulus, p=2",
            run: || convergence_study(MmsKind::Conduction, 2),
        },
        Case {
            name: "mms_conduction_p3",
            description: "k(θ) conduction, annulus, p=3",
            run: || convergence_study(MmsKind::Conduction, 3),
        },
        Case {
            name: "mms_thermoelastic_p1",
            description: "finite thermoelasticity, annulus, p=1",
            run: || convergence_study(MmsKind::Thermoelastic, 1),
        },
        Case {
            name: "mms_thermoelastic_p2",
            description: "finite thermoelasticity, annulus, p=2",
            run: || convergence_study(MmsKind::Thermoelastic, 2),
        },
        Case {
            name: "mms_thermoelastic_p3",
            description: "finite thermoelasticity, annulus, p=3",
            run: || convergence_study(MmsKind::Thermoelastic, 3),
        },
        Case {
            name: "mms3d_conduction_p1",
            description: "k(θ) conduction, warped cube (3D), p=1",
            run: || convergence_study_in(MmsKind::Conduction, 1, 3),
        },
        Case {
            name: "mms3d_conduction_p2",
            description: "k(θ) conduction, warped cube (3D), p=2",
            run: || convergence_study_in(MmsKind::Conduction, 2, 3),
        },
        Case {
            name: "mms3d_conduction_p3",
            description: "k(θ) conduction, warped cube (3D), p=3",
            run: || convergence_study_in(MmsKind::Conduction, 3, 3),
        },
        Case {
            name: "mms3d_thermoelastic_p1",
            description: "finite thermoelasticity, warped cube (3D), p=1",
            run: || convergence_study_in(MmsKind::Thermoelastic, 1, 3),
        },
        Case {
            name: "mms3d_thermoelastic_p2",
            description: "finite thermoelasticity, warped cube (3D), p=2",
            run: || convergence_study_in(MmsKind::Thermoelastic, 2, 3),
        },
        Case {
            name: "mms3d_thermoelastic_p3",
            description: "finite thermoelasticity, warped cube (3D), p=3",
            run: || convergence_study_in(MmsKind::Thermoelastic, 3, 3),
        },
        Case {
            name: "mms3d_reduced_thermoelastic_p2",
            description: "finite thermoelasticity, warped cube (3D), p=2, 2 x 2 x 2 Gauss points",
            run: || convergence_study_reduced(MmsKind::Thermoelastic, 2),
        },
        Case {
            name: "newton_quadratic",
            description: "Newton order on finite strain",
            run: newton_case,
        },
    ]
}
