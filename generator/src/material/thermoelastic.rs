//! Modified entropic thermoelasticity (Chadwick), spec §4:
//!
//! `ψ(F, θ) = (θ/θ0) μ/2 (tr C̄ − 3) + κ/2 (ln J)² − 3 α0 κ (θ − θ0) (ln J)/J`,
//! `C̄ = J^(−2/3) C`, with the stress `P = ∂ψ/∂F` and its tangents written by hand
//! (the hot path of assembly: no allocation, one inverse per call).
//!
//! With `G = F⁻ᵀ`, `I1 = tr C = F : F`, `a = (θ/θ0) μ J^(−2/3)` and the
//! volumetric energy `U(J) = κ/2 (ln J)² − 3 α0 κ (θ−θ0) ln J / J`:
//!
//! `P = a (F − I1/3 G) + s G`, `s = J U'(J) = κ ln J − 3 α0 κ (θ−θ0) (1 − ln J)/J`,
//!
//! and, using `∂J/∂F = J G`, `∂G_iJ/∂F_kL = −G_iL G_kJ`,
//!
//! `∂P_iJ/∂F_kL = a [δ_ik δ_JL − 2/3 (F_iJ G_kL + G_iJ F_kL) + 2/9 I1 G_iJ G_kL + I1/3 G_iL G_kJ]`
//! `            + J s'(J) G_iJ G_kL − s G_iL G_kJ`,
//!
//! `J s'(J) = κ − 3 α0 κ (θ−θ0) (ln J − 2)/J`. The tangent has major symmetry.
//!
//! All functions need `J = det F > 0`; otherwise the results are NaN (which
//! the Newton solver detects as a non-finite residual).

use nalgebra::{Matrix3, SMatrix};

use super::{Material, flat_index};

/// The first Piola–Kirchhoff stress and its derivatives at one point.
#[derive(Clone, Debug, PartialEq)]
pub struct StressTangent {
    /// `P = ∂ψ/∂F`.
    pub p: Matrix3<f64>,
    /// `∂P_iJ/∂F_kL` at `(3i+J, 3k+L)`; symmetric (major symmetry).
    pub dp_df: SMatrix<f64, 9, 9>,
    /// `∂P/∂θ`.
    pub dp_dtheta: Matrix3<f64>,
}

/// Kinematic quantities shared by the energy, the stress and the tangent.
struct Kinematics {
    j: f64,
    ln_j: f64,
    /// `G = F⁻ᵀ`.
    g: Matrix3<f64>,
    /// `I1 = tr C`.
    i1: f64,
    /// `J^(−2/3)`.
    j_m23: f64,
}

#[inline]
fn kinematics(f: &Matrix3<f64>) -> Kinematics {
    let j = f.determinant();
    // Cofactor matrix: F⁻ᵀ = cof(F) / J.
    let cof = Matrix3::new(
        f[(1, 1)] * f[(2, 2)] - f[(1, 2)] * f[(2, 1)],
        f[(1, 2)] * f[(2, 0)] - f[(1, 0)] * f[(2, 2)],
        f[(1, 0)] * f[(2, 1)] - f[(1, 1)] * f[(2, 0)],
        f[(0, 2)] * f[(2, 1)] - f[(0, 1)] * f[(2, 2)],
        f[(0, 0)] * f[(2, 2)] - f[(0, 2)] * f[(2, 0)],
        f[(0, 1)] * f[(2, 0)] - f[(0, 0)] * f[(2, 1)],
        f[(0, 1)] * f[(1, 2)] - f[(0, 2)] * f[(1, 1)],
        f[(0, 2)] * f[(1, 0)] - f[(0, 0)] * f[(1, 2)],
        f[(0, 0)] * f[(1, 1)] - f[(0, 1)] * f[(1, 0)],
    );
    let ln_j = j.ln();
    Kinematics {
        j,
        ln_j,
        g: cof / j,
        i1: f.norm_squared(),
        j_m23: (-2.0 / 3.0 * ln_j).exp(),
    }
}

/// `F⁻ᵀ` (by cofactors), for the conduction module.
#[inline]
pub(crate) fn inverse_transpose(f: &Matrix3<f64>) -> (f64, Matrix3<f64>) {
    let k = kinematics(f);
    (k.j, k.g)
}

impl Material {
    /// The Helmholtz energy per reference volume `ψ(F, θ)` (spec §4).
    pub fn energy(&self, f: &Matrix3<f64>, theta: f64) -> f64 {
        let k = kinematics(f);
        let (mu, kappa, theta0) = (
            self.shear_modulus(),
            self.bulk_modulus(),
            self.reference_temperature,
        );
        theta / theta0 * mu / 2.0 * (k.j_m23 * k.i1 - 3.0) + kappa / 2.0 * k.ln_j * k.ln_j
            - 3.0 * self.thermal_expansion * kappa * (theta - theta0) * k.ln_j / k.j
    }

    /// The isochoric factor `a = (θ/θ0) μ J^(−2/3)` and `s = J U'(J)`.
    #[inline]
    fn stress_factors(&self, k: &Kinematics, theta: f64) -> (f64, f64) {
        let kappa = self.bulk_modulus();
        let a = theta / self.reference_temperature * self.shear_modulus() * k.j_m23;
        let thermal = 3.0 * self.thermal_expansion * kappa * (theta - self.reference_temperature);
        let s = kappa * k.ln_j - thermal * (1.0 - k.ln_j) / k.j;
        (a, s)
    }

    /// The first Piola–Kirchhoff stress `P = ∂ψ/∂F`.
    pub fn stress(&self, f: &Matrix3<f64>, theta: f64) -> Matrix3<f64> {
        let k = kinematics(f);
        let (a, s) = self.stress_factors(&k, theta);
        (f - k.g * (k.i1 / 3.0)) * a + k.g * s
    }

    /// `P`, `∂P/∂F` and `∂P/∂θ` (see the module documentation for the formulas).
    pub fn stress_tangent(&self, f: &Matrix3<f64>, theta: f64) -> StressTangent {
        self.stress_tangent_in(f, theta, 3)
    }

    /// [`Material::stress_tangent`] with `∂P_iJ/∂F_kL` only for indices
    /// below `dim` (the in-plane block in 2D, plane strain; the other
    /// entries are left zero).
    pub fn stress_tangent_in(&self, f: &Matrix3<f64>, theta: f64, dim: usize) -> StressTangent {
        let k = kinematics(f);
        let (a, s) = self.stress_factors(&k, theta);
        let kappa = self.bulk_modulus();
        let theta0 = self.reference_temperature;
        let thermal = 3.0 * self.thermal_expansion * kappa * (theta - theta0);
        let g = &k.g;
        let p = (f - g * (k.i1 / 3.0)) * a + g * s;

        // Coefficients of the dyadic terms.
        let c_fg = -2.0 / 3.0 * a; // F⊗G + G⊗F
        let c_gg = 2.0 / 9.0 * a * k.i1 + kappa - thermal * (k.ln_j - 2.0) / k.j; // G⊗G
        let c_gt = a * k.i1 / 3.0 - s; // G_iL G_kJ
        let mut dp_df = SMatrix::<f64, 9, 9>::zeros();
        for i in 0..dim {
            for jj in 0..dim {
                let row = flat_index(i, jj);
                let (f_ij, g_ij) = (f[(i, jj)], g[(i, jj)]);
                for kk in 0..dim {
                    for l in 0..dim {
                        let col = flat_index(kk, l);
                        if col < row {
                            continue;
                        }
                        let mut v = c_fg * (f_ij * g[(kk, l)] + g_ij * f[(kk, l)])
                            + c_gg * g_ij * g[(kk, l)]
                            + c_gt * g[(i, l)] * g[(kk, jj)];
                        if i == kk && jj == l {
                            v += a;
                        }
                        dp_df[(row, col)] = v;
                        dp_df[(col, row)] = v;
                    }
                }
            }
        }

        // ∂a/∂θ = a/θ, written without dividing by θ.
        let da = self.shear_modulus() / theta0 * k.j_m23;
        let ds = -3.0 * self.thermal_expansion * kappa * (1.0 - k.ln_j) / k.j;
        let dp_dtheta = f * da + g * (ds - da * k.i1 / 3.0);
        StressTangent {
            p,
            dp_df,
            dp_dtheta,
        }
    }

    /// The Cauchy stress `σ = P Fᵀ / J`.
    pub fn cauchy_stress(&self, f: &Matrix3<f64>, theta: f64) -> Matrix3<f64> {
        self.stress(f, theta) * f.transpose() / f.determinant()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::material::test_support::*;
    use nalgebra::{Rotation3, Vector3};
    use proptest::prelude::*;

    /// The in-plane tangent equals the full one in its block.
    #[test]
    fn in_plane_tangent_is_the_block_of_the_full_one() {
        let m = Material::default().scaled(1.0e6, 293.15, 1.0);
        let f = Matrix3::new(1.1, 0.2, 0.0, -0.05, 0.93, 0.0, 0.0, 0.0, 1.0);
        let (full, plane) = (m.stress_tangent(&f, 1.02), m.stress_tangent_in(&f, 1.02, 2));
        assert_eq!(full.p, plane.p);
        assert_eq!(full.dp_dtheta, plane.dp_dtheta);
        for (i, j, k, l) in (0..16).map(|n| (n / 8, (n / 4) % 2, (n / 2) % 2, n % 2)) {
            let (r, c) = (flat_index(i, j), flat_index(k, l));
            assert_eq!(full.dp_df[(r, c)], plane.dp_df[(r, c)]);
        }
    }

    /// Fourth-order central difference of `g` at `x` along the 9-vector entry `n` of `F`.
    fn central_difference_f<T>(
        f: &Matrix3<f64>,
        n: usize,
        h: f64,
        g: impl Fn(&Matrix3<f64>) -> T,
    ) -> T
    where
        T: std::ops::Sub<Output = T> + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let at = |t: f64| {
            let mut fp = *f;
            fp[(n / 3, n % 3)] += t;
            g(&fp)
        };
        (at(-2.0 * h) - at(2.0 * h) + (at(h) - at(-h)) * 8.0) * (1.0 / (12.0 * h))
    }

    fn check_stress_against_energy(m: &Material, f: &Matrix3<f64>, theta: f64) -> f64 {
        let p = m.stress(f, theta);
        let scale = p.amax() + 1e-4 * m.shear_modulus();
        let mut err: f64 = 0.0;
        for n in 0..9 {
            let d = central_difference_f(f, n, 1e-4, |fp| m.energy(fp, theta));
            err = err.max((d - p[(n / 3, n % 3)]).abs() / scale);
        }
        err
    }

    fn check_tangent(m: &Material, f: &Matrix3<f64>, theta: f64) -> (f64, f64, f64) {
        let t = m.stress_tangent(f, theta);
        // Finite differences of P.
        let mut fd_err: f64 = 0.0;
        let scale = t.dp_df.amax();
        for col in 0..9 {
            let d = central_difference_f(f, col, 1e-4, |fp| m.stress(fp, theta));
            for row in 0..9 {
                fd_err = fd_err.max((d[(row / 3, row % 3)] - t.dp_df[(row, col)]).abs() / scale);
            }
        }
        let h = 1e-2;
        let d_theta = (m.stress(f, theta - 2.0 * h) - m.stress(f, theta + 2.0 * h)
            + (m.stress(f, theta + h) - m.stress(f, theta - h)) * 8.0)
            / (12.0 * h);
        let theta_scale = t.dp_dtheta.amax();
        fd_err = fd_err.max((d_theta - t.dp_dtheta).amax() / theta_scale);

        // Forward-mode AD (Hessian of the generic energy over (F, θ)).
        let (_, grad, hess) = energy_hessian_ad(m, f, theta);
        let mut ad_err: f64 = 0.0;
        for row in 0..9 {
            ad_err =
                ad_err.max((grad[row] - t.p[(row / 3, row % 3)]).abs() / (t.p.amax() + 1e-300));
            for col in 0..9 {
                ad_err = ad_err.max((hess[(row, col)] - t.dp_df[(row, col)]).abs() / scale);
            }
            ad_err =
                ad_err.max((hess[(row, 9)] - t.dp_dtheta[(row / 3, row % 3)]).abs() / theta_scale);
        }
        let sym_err = (t.dp_df - t.dp_df.transpose()).amax() / scale;
        assert_eq!(
            t.p,
            m.stress(f, theta),
            "stress_tangent.p differs from stress"
        );
        (fd_err, ad_err, sym_err)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn stress_is_energy_derivative(f in deformation_near_identity(0.3), theta in 250.0..400.0f64) {
            let m = Material::default();
            let err = check_stress_against_energy(&m, &f, theta);
            prop_assert!(err < 1e-7, "relative error {err:e}");
        }

        #[test]
        fn tangent_matches_finite_differences_and_ad(f in deformation_near_identity(0.3), theta in 250.0..400.0f64) {
            let m = Material::default();
            let (fd, ad, sym) = check_tangent(&m, &f, theta);
            prop_assert!(fd < 1e-7, "finite differences: relative error {fd:e}");
            prop_assert!(ad < 1e-10, "AD: relative error {ad:e}");
            prop_assert!(sym < 1e-14, "major symmetry: {sym:e}");
        }

        #[test]
        fn tangent_holds_at_large_strain(f in deformation_near_identity(0.8), theta in 250.0..400.0f64) {
            let m = Material { poisson_ratio: 0.45, thermal_expansion: 1e-3, ..Material::default() };
            let (fd, ad, sym) = check_tangent(&m, &f, theta);
            prop_assert!(fd < 1e-6, "finite differences: relative error {fd:e}");
            prop_assert!(ad < 1e-10, "AD: relative error {ad:e}");
            prop_assert!(sym < 1e-14, "major symmetry: {sym:e}");
        }

        #[test]
        fn stress_is_frame_indifferent(
            f in deformation_near_identity(0.5),
            axis in prop::array::uniform3(-1.0..1.0f64),
            angle in -3.0..3.0f64,
            theta in 250.0..400.0f64,
        ) {
            let m = Material::default();
            let q = Rotation3::new(Vector3::from(axis).normalize() * angle).into_inner();
            let p = m.stress(&f, theta);
            let pq = m.stress(&(q * f), theta);
            prop_assert!((pq - q * p).amax() < 1e-10 * p.amax());
            prop_assert!((m.energy(&(q * f), theta) - m.energy(&f, theta)).abs() < 1e-10 * m.energy(&f, theta).abs().max(1.0));
            // Cauchy stress is symmetric and rotates as Q σ Qᵀ.
            let s = m.cauchy_stress(&f, theta);
            prop_assert!((s - s.transpose()).amax() < 1e-10 * s.amax());
            prop_assert!((m.cauchy_stress(&(q * f), theta) - q * s * q.transpose()).amax() < 1e-10 * s.amax());
        }

        #[test]
        fn small_strain_limit_is_linear_thermoelasticity(
            grad in prop::array::uniform9(-1.0..1.0f64),
            theta in 250.0..400.0f64,
        ) {
            let m = Material::default();
            // Strain and thermal stress of the same small order: 3κα0 Δθ ~ E ε.
            let eps = 1e-8;
            let h = Matrix3::from_row_slice(&grad) * eps;
            let strain = (h + h.transpose()) / 2.0;
            let dt = (theta - m.reference_temperature) / 100.0 * 4.0e4 * eps;
            let kappa = m.bulk_modulus();
            let linear = Matrix3::identity() * (m.lame_lambda() * strain.trace() - 3.0 * kappa * m.thermal_expansion * dt)
                + strain * (2.0 * m.shear_modulus());
            let p = m.stress(&(Matrix3::identity() + h), m.reference_temperature + dt);
            // The error is quadratic in (ε, Δθ): relative O(ε + Δθ/θ0) (the
            // entropic shear modulus is μ θ/θ0).
            prop_assert!((p - linear).amax() < 1e-5 * linear.amax(), "{:e}", (p - linear).amax() / linear.amax());
        }
    }

    #[test]
    fn stress_free_at_reference_state() {
        let m = Material::default();
        let t = m.stress_tangent(&Matrix3::identity(), m.reference_temperature);
        assert_eq!(t.p, Matrix3::zeros());
        assert_eq!(m.energy(&Matrix3::identity(), m.reference_temperature), 0.0);
        // Thermal stress at F = I: −3 κ α0 (θ − θ0) I.
        let dt = 50.0;
        let p = m.stress(&Matrix3::identity(), m.reference_temperature + dt);
        let expected = -3.0 * m.bulk_modulus() * m.thermal_expansion * dt;
        assert!((p - Matrix3::identity() * expected).amax() < 1e-12 * expected.abs());
        // Small-strain elasticity tensor at the reference state: λ δ_iJ δ_kL + μ (δ_ik δ_JL + δ_iL δ_Jk).
        let (lambda, mu) = (m.lame_lambda(), m.shear_modulus());
        for (i, jj, kk, l) in itertools_4() {
            let d = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
            let c = lambda * d(i, jj) * d(kk, l) + mu * (d(i, kk) * d(jj, l) + d(i, l) * d(jj, kk));
            assert!(
                (t.dp_df[(3 * i + jj, 3 * kk + l)] - c).abs() < 1e-9 * mu,
                "{i}{jj}{kk}{l}"
            );
        }
    }

    fn itertools_4() -> impl Iterator<Item = (usize, usize, usize, usize)> {
        (0..81).map(|n| (n / 27, (n / 9) % 3, (n / 3) % 3, n % 3))
    }

    /// Uniaxial stress by Newton on the lateral stretch, `F = diag(1+ε, λ, λ)`:
    /// Young's modulus and Poisson's ratio come back from the finite-strain model.
    #[test]
    fn uniaxial_stress_recovers_youngs_modulus_and_poisson_ratio() {
        for (e, nu) in [(1.0e6, 0.3), (2.0e11, 0.25), (5.0e3, 0.45), (1.0, -0.2)] {
            let m = Material {
                youngs_modulus: e,
                poisson_ratio: nu,
                ..Material::default()
            };
            let eps = 1e-6;
            let theta = m.reference_temperature;
            let f = |lat: f64| Matrix3::from_diagonal(&Vector3::new(1.0 + eps, lat, lat));
            let mut lat = 1.0;
            for _ in 0..20 {
                let t = m.stress_tangent(&f(lat), theta);
                // d P_yy / d λ with both lateral stretches moving.
                let slope = t.dp_df[(4, 4)] + t.dp_df[(4, 8)];
                lat -= t.p[(1, 1)] / slope;
            }
            let p = m.stress(&f(lat), theta);
            assert!(
                p[(1, 1)].abs() < 1e-8 * p[(0, 0)].abs()
                    && p[(2, 2)].abs() < 1e-8 * p[(0, 0)].abs()
            );
            let e_num = p[(0, 0)] / eps;
            let nu_num = -(lat - 1.0) / eps;
            assert!((e_num / e - 1.0).abs() < 1e-5, "E: {e_num} vs {e}");
            assert!((nu_num - nu).abs() < 1e-5, "ν: {nu_num} vs {nu}");
        }
    }

    /// Free thermal expansion: `P(λ I, θ0 + Δθ) = 0` gives `λ − 1 = α0 Δθ (1 + O(α0 Δθ))`
    /// (the exact solution of `ln J = 3 α0 Δθ (1 − ln J)/J` deviates by about `5.5 α0 Δθ`).
    #[test]
    fn free_thermal_expansion_strain_is_alpha_delta_theta() {
        let m = Material::default();
        for dt in [-40.0, 1.0, 100.0] {
            let theta = m.reference_temperature + dt;
            let f = |s: f64| Matrix3::identity() * s;
            let mut s = 1.0;
            for _ in 0..20 {
                let t = m.stress_tangent(&f(s), theta);
                let slope = t.dp_df[(0, 0)] + t.dp_df[(0, 4)] + t.dp_df[(0, 8)];
                s -= t.p[(0, 0)] / slope;
            }
            assert!(m.stress(&f(s), theta).amax() < 1e-12 * m.youngs_modulus);
            let strain = s - 1.0;
            let expected = m.thermal_expansion * dt;
            assert!(
                (strain / expected - 1.0).abs() < 6.0 * m.thermal_expansion * dt.abs(),
                "{strain} vs {expected}"
            );
        }
    }

    #[test]
    fn energy_matches_generic_ad_energy() {
        let m = Material::default();
        let f = Matrix3::new(1.1, 0.2, 0.0, -0.1, 0.9, 0.05, 0.0, 0.1, 1.2);
        let (psi, _, _) = energy_hessian_ad(&m, &f, 320.0);
        assert!((psi - m.energy(&f, 320.0)).abs() < 1e-12 * psi.abs());
    }

    #[test]
    fn non_positive_jacobian_gives_nan() {
        let m = Material::default();
        let f = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, 1.0));
        assert!(m.stress(&f, 300.0).iter().any(|v| v.is_nan()));
    }
}
