//! Test helpers: random deformation gradients and generic (dual-number)
//! versions of the energy and the heat flux, written independently of the
//! hand-written stress and tangents, for forward-mode AD with `num-dual`.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use num_dual::{Dual2SVec64, DualNum, DualSVec64, hessian, jacobian};
use proptest::prelude::*;

use super::Material;

/// Deformation gradients `F = I + H`, `|H_iJ| ≤ scale`, with `det F ≥ 0.3`.
pub fn deformation_near_identity(scale: f64) -> impl Strategy<Value = Matrix3<f64>> {
    prop::array::uniform9(-scale..scale)
        .prop_map(|h| Matrix3::identity() + Matrix3::from_row_slice(&h))
        .prop_filter("det F >= 0.3", |f| f.determinant() >= 0.3)
}

fn determinant<D: DualNum<Primitive = f64> + Copy>(f: &[D; 9]) -> D {
    f[0] * (f[4] * f[8] - f[5] * f[7]) - f[1] * (f[3] * f[8] - f[5] * f[6])
        + f[2] * (f[3] * f[7] - f[4] * f[6])
}

/// ψ(F, θ) of spec §4 for any dual number type; `f` is row-major.
pub fn energy_generic<D: DualNum<Primitive = f64> + Copy>(m: &Material, f: &[D; 9], theta: D) -> D {
    let (mu, kappa, theta0, alpha) = (
        m.shear_modulus(),
        m.bulk_modulus(),
        m.reference_temperature,
        m.thermal_expansion,
    );
    let j = determinant(f);
    let i1 = f.iter().fold(D::from(0.0), |acc, &x| acc + x * x);
    let ln_j = j.ln();
    theta / theta0 * (mu / 2.0) * (j.powf(-2.0 / 3.0) * i1 - 3.0) + ln_j * ln_j * (kappa / 2.0)
        - (theta - theta0) * ln_j / j * (3.0 * alpha * kappa)
}

/// q0 = −J k(θ) C⁻¹ Grad θ for any dual number type; `f` is row-major.
pub fn heat_flux_generic<D: DualNum<Primitive = f64> + Copy>(
    m: &Material,
    f: &[D; 9],
    theta: D,
    grad: &[D; 3],
) -> [D; 3] {
    // C = Fᵀ F, inverted by cofactors.
    let mut c = [D::from(0.0); 9];
    for a in 0..3 {
        for b in 0..3 {
            for i in 0..3 {
                c[3 * a + b] += f[3 * i + a] * f[3 * i + b];
            }
        }
    }
    let det_c = determinant(&c);
    let cof = |r: usize, s: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (s1, s2) = ((s + 1) % 3, (s + 2) % 3);
        c[3 * r1 + s1] * c[3 * r2 + s2] - c[3 * r1 + s2] * c[3 * r2 + s1]
    };
    let j = determinant(f);
    let k = (theta - m.reference_temperature) * m.conductivity_slope + m.thermal_conductivity;
    let mut q = [D::from(0.0); 3];
    for (a, qa) in q.iter_mut().enumerate() {
        for (b, &g) in grad.iter().enumerate() {
            // (C⁻¹)_ab = cof(C)_ba / det C (C symmetric).
            *qa -= j * k * cof(b, a) / det_c * g;
        }
    }
    q
}

/// `(ψ, ∂ψ/∂x, ∂²ψ/∂x²)` over `x = (F row-major, θ)` by `num-dual` second-order AD.
pub fn energy_hessian_ad(
    m: &Material,
    f: &Matrix3<f64>,
    theta: f64,
) -> (f64, SVector<f64, 10>, SMatrix<f64, 10, 10>) {
    let mut x = SVector::<f64, 10>::zeros();
    for n in 0..9 {
        x[n] = f[(n / 3, n % 3)];
    }
    x[9] = theta;
    hessian(
        |x: SVector<Dual2SVec64<10>, 10>| {
            let fd: [Dual2SVec64<10>; 9] = std::array::from_fn(|n| x[n]);
            energy_generic(m, &fd, x[9])
        },
        &x,
    )
}

/// `(q0, ∂q0/∂x)` over `x = (F row-major, θ, Grad θ)` by `num-dual` forward AD.
pub fn heat_flux_jacobian_ad(
    m: &Material,
    f: &Matrix3<f64>,
    theta: f64,
    grad: &Vector3<f64>,
) -> (Vector3<f64>, SMatrix<f64, 3, 13>) {
    let mut x = SVector::<f64, 13>::zeros();
    for n in 0..9 {
        x[n] = f[(n / 3, n % 3)];
    }
    x[9] = theta;
    x.fixed_rows_mut::<3>(10).copy_from(grad);
    jacobian(
        |x: SVector<DualSVec64<13>, 13>| {
            let fd: [DualSVec64<13>; 9] = std::array::from_fn(|n| x[n]);
            let g = [x[10], x[11], x[12]];
            SVector::from(heat_flux_generic(m, &fd, x[9], &g))
        },
        &x,
    )
}
