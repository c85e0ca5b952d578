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

use crate::analytical::manufactured::{ExactFields, annulus_fields, manufactured_sources};
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
    let (m, au, at) = mms_setup(kind);
    let theta0 = m.reference_temperature;
    let exact = move |x: &[f64; 3]| annulus_fields(x, au, at, theta0);
    let ms = m.clone();
    let sources = Arc::new(move |x: &[f64; 3]| -> (Vector3<f64>, f64) {
        let f = annulus_fields(x, au, at, theta0);
        manufactured_sources(&ms, &f)
    });
    let mut b = ModelBuilder::new(2, Scales::new(1.0, &m));
    let body = b.add_body("annulus", mesh, &m)?;
    for dir in 0..2 {
        for side in [crate::geometry::Side::Low, crate::geometry::Side::High] {
            for f in 0..3 {
                let v = if f == 2 { theta0 } else { 0.0 };
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
    Ok((errors(&model, &exact), hist))
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
            for qp in &q.points {
                let x = [qp.x[0] * ls, qp.x[1] * ls, 0.0];
                let e = exact(&x);
                let mut u = [0.0; 2];
                let mut gu = [[0.0; 2]; 2];
                let (mut t, mut gt) = (0.0, [0.0; 2]);
                for (a, &c) in q.conn.iter().enumerate() {
                    let s = &model.state[(c + body.node_offset) * nf..];
                    for i in 0..2 {
                        u[i] += qp.r[a] * s[i] * ls;
                        for j in 0..2 {
                            gu[i][j] += s[i] * qp.dr_dx[a][j];
                        }
                        gt[i] += s[2] * qp.dr_dx[a][i] * ts / ls;
                    }
                    t += qp.r[a] * s[2] * ts;
                }
                let w = qp.weight * ls * ls;
                for i in 0..2 {
                    l2u += w * (u[i] - e.u[i]).powi(2);
                    h1t += w * (gt[i] - e.grad_theta[i]).powi(2);
                    for j in 0..2 {
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
    let name = match kind {
        MmsKind::Conduction => format!("mms_conduction_p{p}"),
        MmsKind::Thermoelastic => format!("mms_thermoelastic_p{p}"),
    };
    let ns = levels(p);
    let mut hs = Vec::new();
    let mut es = Vec::new();
    for &n in &ns {
        let mesh = annulus_mesh(p, n)?;
        let (e, _) = solve_mms(kind, &mesh)?;
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
    // Rates from the three finest levels (the asymptotic range).
    let k = hs.len().saturating_sub(3);
    let rate = |f: &dyn Fn(&MmsErrors) -> f64| {
        let e: Vec<f64> = es[k..].iter().map(f).collect();
        (fitted_rate(&hs[k..], &e), *e.last().unwrap())
    };
    let pf = p as f64;
    let tol = 0.15;
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
            name: "newton_quadratic",
            description: "Newton order on finite strain",
            run: newton_case,
        },
    ]
}
