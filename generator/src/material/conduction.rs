//! Conduction on the deformed configuration (spec §4): the referential heat
//! flux `q0 = −J k(θ) C⁻¹ Grad θ`, `k(θ) = k0 + k1 (θ − θ0)` (5.1), i.e. the
//! Fourier law `q = −k grad θ` pulled back to the reference configuration.
//!
//! With `F⁻¹` (entries `F⁻¹_Ai`), the spatial gradient `v = F⁻ᵀ Grad θ`,
//! `w = C⁻¹ Grad θ = F⁻¹ v` and `G = F⁻ᵀ`:
//!
//! `∂q0_A/∂F_kL = q0_A G_kL + J k (F⁻¹_Ak w_L + C⁻¹_AL v_k)`,
//! `∂q0/∂θ = −J k'(θ) w`, `∂q0/∂Grad θ = −J k C⁻¹`.

use nalgebra::{Matrix3, SMatrix, Vector3};

use super::thermoelastic::inverse_transpose;
use super::{Material, flat_index};

/// The referential heat flux and its derivatives at one point.
#[derive(Clone, Debug, PartialEq)]
pub struct HeatFluxTangent {
    /// `q0 = −J k(θ) C⁻¹ Grad θ`.
    pub q: Vector3<f64>,
    /// `∂q0_A/∂F_kL` at `(A, 3k+L)`.
    pub dq_df: SMatrix<f64, 3, 9>,
    /// `∂q0/∂θ`.
    pub dq_dtheta: Vector3<f64>,
    /// `∂q0_A/∂(Grad θ)_B` at `(A, B)`; symmetric negative definite when `k > 0`.
    pub dq_dgrad: Matrix3<f64>,
}

impl Material {
    /// The referential heat flux `q0 = −J k(θ) C⁻¹ Grad θ` (spec §4, Eq. (5.1)).
    pub fn heat_flux(
        &self,
        f: &Matrix3<f64>,
        theta: f64,
        grad_theta: &Vector3<f64>,
    ) -> Vector3<f64> {
        let (j, g) = inverse_transpose(f);
        let (k, _) = self.conductivity(theta);
        // C⁻¹ Grad θ = F⁻¹ F⁻ᵀ Grad θ = Gᵀ (G Grad θ).
        let v = g * grad_theta;
        -(j * k) * g.tr_mul(&v)
    }

    /// `q0` with `∂q0/∂F`, `∂q0/∂θ` and `∂q0/∂Grad θ` (formulas in the module documentation).
    pub fn heat_flux_tangent(
        &self,
        f: &Matrix3<f64>,
        theta: f64,
        grad_theta: &Vector3<f64>,
    ) -> HeatFluxTangent {
        let (j, g) = inverse_transpose(f);
        let (k, dk) = self.conductivity(theta);
        let v = g * grad_theta;
        let w = g.tr_mul(&v);
        let c_inv = g.tr_mul(&g);
        let jk = j * k;
        let q = -jk * w;
        let mut dq_df = SMatrix::<f64, 3, 9>::zeros();
        for a in 0..3 {
            for kk in 0..3 {
                for l in 0..3 {
                    // F⁻¹_Ak = G_kA.
                    dq_df[(a, flat_index(kk, l))] =
                        q[a] * g[(kk, l)] + jk * (g[(kk, a)] * w[l] + c_inv[(a, l)] * v[kk]);
                }
            }
        }
        HeatFluxTangent {
            q,
            dq_df,
            dq_dtheta: -(j * dk) * w,
            dq_dgrad: -jk * c_inv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_support::*;
    use proptest::prelude::*;

    fn max_rel(a: f64, b: f64, scale: f64) -> f64 {
        (a - b).abs() / scale
    }

    fn check(m: &Material, f: &Matrix3<f64>, theta: f64, grad: &Vector3<f64>) -> (f64, f64) {
        let t = m.heat_flux_tangent(f, theta, grad);
        assert_eq!(t.q, m.heat_flux(f, theta, grad));
        let mut analytic = SMatrix::<f64, 3, 13>::zeros();
        analytic.fixed_columns_mut::<9>(0).copy_from(&t.dq_df);
        analytic.set_column(9, &t.dq_dtheta);
        analytic.fixed_columns_mut::<3>(10).copy_from(&t.dq_dgrad);
        let x0: [f64; 13] = std::array::from_fn(|n| match n {
            0..9 => f[(n / 3, n % 3)],
            9 => theta,
            _ => grad[n - 10],
        });
        let eval = |x: &[f64; 13]| {
            let f = Matrix3::from_row_slice(&x[..9]);
            m.heat_flux(&f, x[9], &Vector3::new(x[10], x[11], x[12]))
        };
        let (q_ad, jac_ad) = heat_flux_jacobian_ad(m, f, theta, grad);
        let mut fd_err: f64 = 0.0;
        let mut ad_err: f64 = (q_ad - t.q).amax() / t.q.amax();
        for col in 0..13 {
            let h = if col == 9 { 1e-2 } else { 1e-4 };
            let at = |s: f64| {
                let mut x = x0;
                x[col] += s;
                eval(&x)
            };
            let d = (at(-2.0 * h) - at(2.0 * h) + (at(h) - at(-h)) * 8.0) / (12.0 * h);
            let scale = analytic.column(col).amax().max(1e-12 * analytic.amax());
            for row in 0..3 {
                fd_err = fd_err.max(max_rel(d[row], analytic[(row, col)], scale));
                ad_err = ad_err.max(max_rel(jac_ad[(row, col)], analytic[(row, col)], scale));
            }
        }
        (fd_err, ad_err)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn heat_flux_tangent_matches_finite_differences_and_ad(
            f in deformation_near_identity(0.5),
            theta in 250.0..400.0f64,
            grad in prop::array::uniform3(-1.0e3..1.0e3f64),
        ) {
            prop_assume!(Vector3::from(grad).amax() > 1.0);
            let m = Material::default();
            let (fd, ad) = check(&m, &f, theta, &Vector3::from(grad));
            prop_assert!(fd < 1e-7, "finite differences: relative error {fd:e}");
            prop_assert!(ad < 1e-10, "AD: relative error {ad:e}");
        }

        /// `q0` is the pull-back of the spatial Fourier law: `q0 = J F⁻¹ q`, `q = −k F⁻ᵀ Grad θ`.
        #[test]
        fn heat_flux_is_pulled_back_fourier_law(
            f in deformation_near_identity(0.5),
            theta in 250.0..400.0f64,
            grad in prop::array::uniform3(-1.0..1.0f64),
        ) {
            let m = Material::default();
            let grad = Vector3::from(grad);
            let f_inv = f.try_inverse().unwrap();
            let spatial = -m.conductivity(theta).0 * f_inv.transpose() * grad;
            let expected = f.determinant() * f_inv * spatial;
            let q = m.heat_flux(&f, theta, &grad);
            prop_assert!((q - expected).amax() <= 1e-12 * expected.amax().max(1e-300));
            // Dissipation: −q0 · Grad θ ≥ 0.
            prop_assert!(-q.dot(&grad) >= -1e-14 * q.norm() * grad.norm());
        }
    }

    #[test]
    fn undeformed_flux_is_fourier_with_eq_5_1() {
        let m = Material::default();
        let grad = Vector3::new(3.0, -1.0, 2.0);
        let theta = m.reference_temperature + 100.0;
        let q = m.heat_flux(&Matrix3::identity(), theta, &grad);
        assert!((q + 2.0 * grad).amax() < 1e-13);
        let t = m.heat_flux_tangent(&Matrix3::identity(), theta, &grad);
        assert!((t.dq_dtheta + 0.01 * grad).amax() < 1e-15);
        assert!((t.dq_dgrad + Matrix3::<f64>::identity() * 2.0).amax() < 1e-14);
    }
}
