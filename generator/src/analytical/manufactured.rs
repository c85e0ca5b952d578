//! Manufactured solutions for finite thermoelasticity with nonlinear
//! conduction (spec §10.1).
//!
//! For exact fields `u(X)`, `θ(X)` the strong form `Div P + B = 0`,
//! `−Div q0 + R = 0` (with `P = P(F, θ)`, `q0 = q0(F, θ, Grad θ)`,
//! `F = I + Grad u`) holds with the body force `B = −Div P` and the heat
//! source `R = Div q0`, computed by the chain rule with the material tangents:
//!
//! `Div P_i = ∂P_iJ/∂F_kL ∂²u_k/∂X_L∂X_J + ∂P_iJ/∂θ ∂θ/∂X_J`,
//! `Div q0 = ∂q0_A/∂F_kL ∂²u_k/∂X_L∂X_A + ∂q0_A/∂θ ∂θ/∂X_A + ∂q0_A/∂G_B ∂²θ/∂X_B∂X_A`.
//!
//! Field families (each vanishing on the boundary of its domain, so that
//! homogeneous Dirichlet data apply): [`annulus_fields`] (2D, plane strain,
//! quarter annulus) and [`cube_fields`] (3D, unit cube).

use nalgebra::{Matrix3, Vector3};

use crate::material::{Material, flat_index};

/// Exact displacement and temperature fields at one reference point, with
/// their first and second derivatives.
#[derive(Clone, Debug, PartialEq)]
pub struct ExactFields {
    /// Displacement `u`.
    pub u: Vector3<f64>,
    /// `Grad u`, entry `(i, J) = ∂u_i/∂X_J`.
    pub grad_u: Matrix3<f64>,
    /// `hess_u[i][(J, K)] = ∂²u_i/∂X_J∂X_K`.
    pub hess_u: [Matrix3<f64>; 3],
    /// Temperature `θ`.
    pub theta: f64,
    /// `Grad θ`.
    pub grad_theta: Vector3<f64>,
    /// `∂²θ/∂X_J∂X_K`.
    pub hess_theta: Matrix3<f64>,
}

impl ExactFields {
    /// The deformation gradient `F = I + Grad u`.
    pub fn deformation_gradient(&self) -> Matrix3<f64> {
        Matrix3::identity() + self.grad_u
    }
}

/// The body force `B = −Div P` and the heat source `R = Div q0` that make the
/// exact fields `e` solve the strong form (module documentation).
pub fn manufactured_sources(m: &Material, e: &ExactFields) -> (Vector3<f64>, f64) {
    let f = e.deformation_gradient();
    let st = m.stress_tangent(&f, e.theta);
    let ht = m.heat_flux_tangent(&f, e.theta, &e.grad_theta);
    // ∂F_kL/∂X_J = ∂²u_k/∂X_L∂X_J.
    let df = |k: usize, l: usize, j: usize| e.hess_u[k][(l, j)];
    let mut div_p = st.dp_dtheta * e.grad_theta;
    let mut div_q = ht.dq_dtheta.dot(&e.grad_theta)
        + (ht.dq_dgrad.component_mul(&e.hess_theta.transpose())).sum();
    for k in 0..3 {
        for l in 0..3 {
            let col = flat_index(k, l);
            for i in 0..3 {
                for j in 0..3 {
                    div_p[i] += st.dp_df[(flat_index(i, j), col)] * df(k, l, j);
                }
            }
            for a in 0..3 {
                div_q += ht.dq_df[(a, col)] * df(k, l, a);
            }
        }
    }
    (-div_p, div_q)
}

/// Fields `u = φ a`, `θ = θ_ref + T φ` from a scalar shape `φ` with its gradient and Hessian.
fn from_shape(
    phi: f64,
    grad: Vector3<f64>,
    hess: Matrix3<f64>,
    a: Vector3<f64>,
    amplitude_theta: f64,
    theta_ref: f64,
) -> ExactFields {
    ExactFields {
        u: a * phi,
        grad_u: a * grad.transpose(),
        hess_u: [hess * a[0], hess * a[1], hess * a[2]],
        theta: theta_ref + amplitude_theta * phi,
        grad_theta: grad * amplitude_theta,
        hess_theta: hess * amplitude_theta,
    }
}

/// Plane-strain fields on the quarter annulus `1 ≤ r ≤ 2`, `x, y ≥ 0`, vanishing
/// on all four edges: with `φ = (x²+y²−1)(4−x²−y²) x y`,
/// `u = φ (A, −A/2, 0)`, `θ = θ_ref + T φ`; no dependence on `z`.
///
/// `x` is the reference point (its `z` is ignored), `A = amplitude_u`,
/// `T = amplitude_theta`, `θ_ref = theta0`. `|φ| ≤ 2.9` and `|Grad φ| ≲ 15` on the domain.
pub fn annulus_fields(
    x: &[f64; 3],
    amplitude_u: f64,
    amplitude_theta: f64,
    theta0: f64,
) -> ExactFields {
    let (px, py) = (x[0], x[1]);
    let s = px * px + py * py;
    // g(s) = (s−1)(4−s), g' = 5 − 2s, g'' = −2.
    let g = (s - 1.0) * (4.0 - s);
    let g1 = 5.0 - 2.0 * s;
    let g2 = -2.0;
    let phi = g * px * py;
    let grad = Vector3::new(
        2.0 * px * px * py * g1 + py * g,
        2.0 * px * py * py * g1 + px * g,
        0.0,
    );
    let hxx = 6.0 * px * py * g1 + 4.0 * px.powi(3) * py * g2;
    let hyy = 6.0 * px * py * g1 + 4.0 * px * py.powi(3) * g2;
    let hxy = g + 2.0 * (px * px + py * py) * g1 + 4.0 * px * px * py * py * g2;
    let hess = Matrix3::new(hxx, hxy, 0.0, hxy, hyy, 0.0, 0.0, 0.0, 0.0);
    from_shape(
        phi,
        grad,
        hess,
        Vector3::new(amplitude_u, -amplitude_u / 2.0, 0.0),
        amplitude_theta,
        theta0,
    )
}

/// 3D fields on the unit cube `[0, 1]³`, vanishing on all six faces: with
/// `φ = sin(πx) sin(πy) sin(πz)`, `u = φ (A, −A/2, A/3)`, `θ = θ_ref + T φ`.
pub fn cube_fields(
    x: &[f64; 3],
    amplitude_u: f64,
    amplitude_theta: f64,
    theta0: f64,
) -> ExactFields {
    use std::f64::consts::PI;
    let (s, c): (Vec<f64>, Vec<f64>) = x.iter().map(|v| (PI * v).sin_cos()).unzip();
    let phi = s[0] * s[1] * s[2];
    let grad = Vector3::new(c[0] * s[1] * s[2], s[0] * c[1] * s[2], s[0] * s[1] * c[2]) * PI;
    let hess = Matrix3::new(
        -phi,
        c[0] * c[1] * s[2],
        c[0] * s[1] * c[2],
        c[0] * c[1] * s[2],
        -phi,
        s[0] * c[1] * c[2],
        c[0] * s[1] * c[2],
        s[0] * c[1] * c[2],
        -phi,
    ) * (PI * PI);
    from_shape(
        phi,
        grad,
        hess,
        Vector3::new(amplitude_u, -amplitude_u / 2.0, amplitude_u / 3.0),
        amplitude_theta,
        theta0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    type Family = fn(&[f64; 3], f64, f64, f64) -> ExactFields;

    fn shifted(x: &[f64; 3], axis: usize, t: f64) -> [f64; 3] {
        let mut y = *x;
        y[axis] += t;
        y
    }

    /// Fourth-order central difference of `g` along the axis.
    fn derivative<T>(x: &[f64; 3], axis: usize, h: f64, g: impl Fn(&[f64; 3]) -> T) -> T
    where
        T: std::ops::Sub<Output = T> + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        (g(&shifted(x, axis, -2.0 * h)) - g(&shifted(x, axis, 2.0 * h))
            + (g(&shifted(x, axis, h)) - g(&shifted(x, axis, -h))) * 8.0)
            * (1.0 / (12.0 * h))
    }

    fn annulus_points() -> Vec<[f64; 3]> {
        let mut points = Vec::new();
        for r in [1.1, 1.37, 1.5, 1.83, 1.95] {
            for angle in [0.1, 0.5, 0.9, 1.3] {
                points.push([r * f64::cos(angle), r * f64::sin(angle), 0.3]);
            }
        }
        points
    }

    fn cube_points() -> Vec<[f64; 3]> {
        vec![
            [0.1, 0.2, 0.3],
            [0.5, 0.5, 0.5],
            [0.77, 0.31, 0.9],
            [0.45, 0.93, 0.12],
        ]
    }

    fn check_derivatives(family: Family, points: &[[f64; 3]]) {
        let field = |x: &[f64; 3]| family(x, 0.013, 7.0, 300.0);
        for x in points {
            let e = field(x);
            for axis in 0..3 {
                let h = 1e-4;
                let du = derivative(x, axis, h, |y| field(y).u);
                assert!(
                    (du - e.grad_u.column(axis)).amax() < 1e-10,
                    "Grad u at {x:?}"
                );
                let dt = derivative(x, axis, h, |y| field(y).theta);
                assert!((dt - e.grad_theta[axis]).abs() < 1e-8, "Grad θ at {x:?}");
                let dg = derivative(x, axis, h, |y| field(y).grad_u);
                for i in 0..3 {
                    assert!(
                        (dg.row(i).transpose() - e.hess_u[i].column(axis)).amax() < 1e-9,
                        "Hess u_{i} at {x:?}"
                    );
                }
                let dgt = derivative(x, axis, h, |y| field(y).grad_theta);
                assert!(
                    (dgt - e.hess_theta.column(axis)).amax() < 1e-7,
                    "Hess θ at {x:?}"
                );
            }
            assert_eq!(e.hess_theta, e.hess_theta.transpose());
        }
    }

    #[test]
    fn annulus_fields_have_exact_derivatives() {
        check_derivatives(annulus_fields, &annulus_points());
    }

    #[test]
    fn cube_fields_have_exact_derivatives() {
        check_derivatives(cube_fields, &cube_points());
    }

    #[test]
    fn fields_vanish_on_the_boundary() {
        for t in [0.0, 0.2, 0.7, 1.1, std::f64::consts::FRAC_PI_2] {
            for r in [1.0, 2.0] {
                let e = annulus_fields(&[r * t.cos(), r * t.sin(), 0.0], 0.1, 5.0, 300.0);
                assert!(
                    e.u.amax() < 1e-15 && (e.theta - 300.0).abs() < 1e-13,
                    "r = {r}, angle {t}"
                );
            }
            let r = 1.0 + t / 2.0;
            for x in [[r, 0.0, 0.0], [0.0, r, 0.0]] {
                let e = annulus_fields(&x, 0.1, 5.0, 300.0);
                assert!(e.u.amax() == 0.0 && e.theta == 300.0);
                assert_eq!(e.u[2], 0.0);
            }
            let s = t / 2.0;
            for x in [
                [0.0, s, 0.3],
                [1.0, s, 0.3],
                [s, 0.0, 0.6],
                [s, 1.0, 0.6],
                [0.4, s, 0.0],
                [0.4, s, 1.0],
            ] {
                let e = cube_fields(&x, 0.1, 5.0, 300.0);
                assert!(
                    e.u.amax() < 1e-16 && (e.theta - 300.0).abs() < 1e-13,
                    "{x:?}"
                );
            }
        }
    }

    /// `B = −Div P` and `R = Div q0` against central differences of `P(X)` and `q0(X)`.
    fn check_sources(
        m: &Material,
        family: Family,
        points: &[[f64; 3]],
        amplitude_u: f64,
        amplitude_theta: f64,
    ) {
        let theta_ref = m.reference_temperature + 20.0;
        let field = |x: &[f64; 3]| family(x, amplitude_u, amplitude_theta, theta_ref);
        let stress = |x: &[f64; 3]| {
            let e = field(x);
            m.stress(&e.deformation_gradient(), e.theta)
        };
        let flux = |x: &[f64; 3]| {
            let e = field(x);
            m.heat_flux(&e.deformation_gradient(), e.theta, &e.grad_theta)
        };
        for x in points {
            let e = field(x);
            assert!(e.deformation_gradient().determinant() > 0.5);
            let (b, r) = manufactured_sources(m, &e);
            let h = 1e-4;
            let mut div_p = Vector3::zeros();
            let mut div_q = 0.0;
            for axis in 0..3 {
                div_p += derivative(x, axis, h, stress).column(axis);
                div_q += derivative(x, axis, h, flux)[axis];
            }
            let b_scale = m.youngs_modulus * amplitude_u;
            assert!(
                (b + div_p).amax() < 1e-7 * b_scale,
                "B at {x:?}: {b} vs {}",
                -div_p
            );
            let r_scale = m.thermal_conductivity * amplitude_theta;
            assert!(
                (r - div_q).abs() < 1e-7 * r_scale,
                "R at {x:?}: {r} vs {div_q}"
            );
            // Nontrivial sources: the check can fail.
            assert!(b.amax() > 1e-3 * b_scale && r.abs() > 0.0);
        }
    }

    #[test]
    fn sources_match_finite_differences_on_the_annulus() {
        let m = Material {
            thermal_expansion: 1e-3,
            ..Material::default()
        };
        check_sources(&m, annulus_fields, &annulus_points(), 0.01, 10.0);
    }

    #[test]
    fn sources_match_finite_differences_on_the_cube() {
        let m = Material {
            thermal_expansion: 1e-3,
            poisson_ratio: 0.4,
            ..Material::default()
        };
        check_sources(&m, cube_fields, &cube_points(), 0.05, 30.0);
    }

    /// In the small-strain, linear-conduction limit the sources are those of
    /// linear thermoelasticity: `B = −(μ Δu + (λ+μ) Grad Div u − 3κα0 Grad θ)`, `R = −k0 Δθ`.
    #[test]
    fn sources_reduce_to_linear_thermoelasticity() {
        let m = Material {
            conductivity_slope: 0.0,
            ..Material::default()
        };
        let (mu, lambda, kappa) = (m.shear_modulus(), m.lame_lambda(), m.bulk_modulus());
        for x in cube_points() {
            let e = cube_fields(&x, 1e-9, 1e-4, m.reference_temperature);
            let (b, r) = manufactured_sources(&m, &e);
            let laplace_u = Vector3::from_fn(|i, _| e.hess_u[i].trace());
            let grad_div_u =
                Vector3::from_fn(|j, _| (0..3).map(|i| e.hess_u[i][(i, j)]).sum::<f64>());
            let linear_b = -(laplace_u * mu + grad_div_u * (lambda + mu)
                - e.grad_theta * (3.0 * kappa * m.thermal_expansion));
            assert!(
                (b - linear_b).amax() < 1e-6 * linear_b.amax(),
                "{b} vs {linear_b}"
            );
            let linear_r = -m.thermal_conductivity * e.hess_theta.trace();
            assert!(
                (r - linear_r).abs() < 1e-6 * linear_r.abs(),
                "{r} vs {linear_r}"
            );
        }
    }
}
