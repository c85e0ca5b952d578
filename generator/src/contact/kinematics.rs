//! Contact kinematics at one slave integration point (paper Sect. 4, spec §6):
//! the normal gap `gN = (x_s − x_m(η))·n` and the temperature jump
//! `ϑc = θ_s − θ_m(η)` (4.1), with `η` the closest-point projection of the
//! slave point onto the master curve and `n` the master's outward normal.
//!
//! Both are written for any [`DualNum`], so that forward-mode automatic
//! differentiation (`num_dual::hessian`) delivers their exact first and
//! second derivatives with respect to the local unknowns, *including* the
//! dependence of the projection point and of the master normal on the
//! displacements. The projection is converged in `f64` first; two Newton
//! steps in dual arithmetic from that point then carry the derivatives of the
//! implicit function `η(u)` exactly to second order.
//!
//! Within one knot span the master's B-spline basis is a polynomial of degree
//! `p`, so it is evaluated at `η0 + δ` exactly by its Taylor expansion with the
//! derivatives at `η0` (which is what lets `δ` be a dual number).

use num_dual::DualNum;

/// Frozen data of one slave integration point and the master span it projects onto.
#[derive(Clone, Debug)]
pub struct PointGeometry {
    /// Slave basis values at the point (one per slave element control point).
    pub slave_basis: Vec<f64>,
    /// Reference positions of the slave element control points (x, y).
    pub slave_x: Vec<[f64; 2]>,
    /// Reference positions of the master span's control points (x, y), including any periodic shift.
    pub master_x: Vec<[f64; 2]>,
    /// NURBS weights of the master span's control points.
    pub master_w: Vec<f64>,
    /// `ders[k][j]`: k-th derivative of the j-th B-spline function of the span at `eta0`, `k = 0..=p`.
    pub master_ders: Vec<Vec<f64>>,
    /// +1 if the master's outward normal is the tangent turned counter-clockwise, −1 otherwise.
    pub normal_sign: f64,
    /// The projection hit an end of a non-periodic master: `η` stays at the end.
    pub clamped: bool,
    /// The closest point is a corner of the master (the slave point lies in
    /// its normal cone): `η` stays at the corner and the gap is the signed
    /// distance to it.
    pub vertex: bool,
}

impl PointGeometry {
    /// Number of local unknowns: `(ux, uy, θ)` per slave, then per master control point.
    pub fn n_local(&self) -> usize {
        3 * (self.slave_x.len() + self.master_x.len())
    }
}

/// Position, first and second parametric derivative, and temperature of the
/// master curve at `η0 + δ`.
struct MasterEval<D> {
    x: [D; 2],
    dx: [D; 2],
    ddx: [D; 2],
    theta: D,
}

fn taylor<D: DualNum<Primitive = f64>>(ders: &[Vec<f64>], k: usize, j: usize, powers: &[D]) -> D {
    // d^k N_j (η0 + δ) = Σ_m N_j^(k+m)(η0) δ^m / m!
    let mut s = D::from(0.0);
    let mut fact = 1.0;
    for m in 0..ders.len() - k {
        if m > 0 {
            fact *= m as f64;
        }
        s += powers[m].clone() * (ders[k + m][j] / fact);
    }
    s
}

fn master_eval<D: DualNum<Primitive = f64>>(
    g: &PointGeometry,
    z: &[D],
    delta: &D,
) -> MasterEval<D> {
    let ns = g.slave_x.len();
    let p1 = g.master_ders.len();
    let mut powers = Vec::with_capacity(p1);
    powers.push(D::from(1.0));
    for m in 1..p1 {
        let next = powers[m - 1].clone() * delta;
        powers.push(next);
    }
    let zero = || D::from(0.0);
    let (mut w, mut dw, mut ddw) = (zero(), zero(), zero());
    let mut a = [zero(), zero()];
    let mut da = [zero(), zero()];
    let mut dda = [zero(), zero()];
    let mut th = zero();
    for j in 0..g.master_x.len() {
        let n0 = taylor(&g.master_ders, 0, j, &powers) * g.master_w[j];
        let n1 = if p1 > 1 {
            taylor(&g.master_ders, 1, j, &powers) * g.master_w[j]
        } else {
            zero()
        };
        let n2 = if p1 > 2 {
            taylor(&g.master_ders, 2, j, &powers) * g.master_w[j]
        } else {
            zero()
        };
        let off = 3 * (ns + j);
        for c in 0..2 {
            let xc = z[off + c].clone() + g.master_x[j][c];
            a[c] += n0.clone() * &xc;
            da[c] += n1.clone() * &xc;
            dda[c] += n2.clone() * &xc;
        }
        th += n0.clone() * &z[off + 2];
        w += n0;
        dw += n1;
        ddw += n2;
    }
    let winv = w.clone().recip();
    let x = [a[0].clone() * &winv, a[1].clone() * &winv];
    let dx = [
        (da[0].clone() - x[0].clone() * &dw) * &winv,
        (da[1].clone() - x[1].clone() * &dw) * &winv,
    ];
    let ddx = [
        (dda[0].clone() - dx[0].clone() * &dw * 2.0 - x[0].clone() * &ddw) * &winv,
        (dda[1].clone() - dx[1].clone() * &dw * 2.0 - x[1].clone() * &ddw) * &winv,
    ];
    MasterEval {
        x,
        dx,
        ddx,
        theta: th * &winv,
    }
}

fn slave_point<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> ([D; 2], D) {
    let mut x = [D::from(0.0), D::from(0.0)];
    let mut th = D::from(0.0);
    for (a, &n) in g.slave_basis.iter().enumerate() {
        for c in 0..2 {
            x[c] += (z[3 * a + c].clone() + g.slave_x[a][c]) * n;
        }
        th += z[3 * a + 2].clone() * n;
    }
    (x, th)
}

/// Projection parameter increment `δ = η − η0` after two Newton steps on
/// `φ(η) = (x_s − x_m(η))·x_m'(η) = 0` from `δ = 0`.
fn projection_delta<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D], xs: &[D; 2]) -> D {
    let mut delta = D::from(0.0);
    if g.clamped || g.vertex {
        return delta;
    }
    for _ in 0..2 {
        let m = master_eval(g, z, &delta);
        let r = [xs[0].clone() - &m.x[0], xs[1].clone() - &m.x[1]];
        let phi = r[0].clone() * &m.dx[0] + r[1].clone() * &m.dx[1];
        let dphi = -(m.dx[0].clone() * &m.dx[0] + m.dx[1].clone() * &m.dx[1])
            + r[0].clone() * &m.ddx[0]
            + r[1].clone() * &m.ddx[1];
        delta -= phi / dphi;
    }
    delta
}

/// Normal gap `gN = (x_s − x_m)·n` (positive when apart).
pub fn normal_gap<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> D {
    let (xs, _) = slave_point(g, z);
    let delta = projection_delta(g, z, &xs);
    let m = master_eval(g, z, &delta);
    let len = (m.dx[0].clone() * &m.dx[0] + m.dx[1].clone() * &m.dx[1]).sqrt();
    // n = sign · (−t_y, t_x) / |t|
    let nx = -m.dx[1].clone() * g.normal_sign / &len;
    let ny = m.dx[0].clone() * g.normal_sign / &len;
    let r = [xs[0].clone() - &m.x[0], xs[1].clone() - &m.x[1]];
    let along_normal = r[0].clone() * nx + r[1].clone() * ny;
    if g.vertex {
        // At a corner: the distance, signed by the side (the normal cone lies
        // between the normals of the two segments, so either one tells it).
        let distance = (r[0].clone() * &r[0] + r[1].clone() * &r[1]).sqrt();
        return if along_normal.re() >= 0.0 {
            distance
        } else {
            -distance
        };
    }
    along_normal
}

/// Temperature jump `ϑc = θ_s − θ_m(η)` (4.1).
pub fn temperature_jump<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> D {
    let (xs, ths) = slave_point(g, z);
    let delta = projection_delta(g, z, &xs);
    let m = master_eval(g, z, &delta);
    ths - m.theta
}

/// Value, gradient and Hessian (row-major `n × n`) of a kinematic quantity.
#[derive(Clone, Debug, Default)]
pub struct Derivatives {
    /// Value.
    pub value: f64,
    /// Gradient with respect to the local unknowns.
    pub grad: Vec<f64>,
    /// Hessian (row-major).
    pub hess: Vec<f64>,
}

/// Which kinematic quantity to differentiate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quantity {
    /// The normal gap `gN`.
    Gap,
    /// The temperature jump `ϑc`.
    Jump,
}

fn evaluate<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D], q: Quantity) -> D {
    match q {
        Quantity::Gap => normal_gap(g, z),
        Quantity::Jump => temperature_jump(g, z),
    }
}

fn pack(v: f64, grad: &[f64], hess_col_major: &[f64]) -> Derivatives {
    // The Hessian is symmetric: column-major equals row-major.
    Derivatives {
        value: v,
        grad: grad.to_vec(),
        hess: hess_col_major.to_vec(),
    }
}

fn hessian_fixed<const N: usize>(g: &PointGeometry, z: &[f64], q: Quantity) -> Derivatives {
    let zv = nalgebra::SVector::<f64, N>::from_column_slice(z);
    let (v, gr, h) = num_dual::hessian(
        |x: nalgebra::SVector<_, N>| evaluate(g, x.as_slice(), q),
        &zv,
    );
    pack(v, gr.as_slice(), h.as_slice())
}

fn hessian_dynamic(g: &PointGeometry, z: &[f64], q: Quantity) -> Derivatives {
    let zv = nalgebra::DVector::from_column_slice(z);
    let (v, gr, h) = num_dual::hessian(|x: nalgebra::DVector<_>| evaluate(g, x.as_slice(), q), &zv);
    pack(v, gr.as_slice(), h.as_slice())
}

/// Value, exact gradient and Hessian of a kinematic quantity at the local
/// state `z` (stack-allocated dual numbers for degrees 1–4).
pub fn differentiate_one(g: &PointGeometry, z: &[f64], q: Quantity) -> Derivatives {
    match z.len() {
        12 => hessian_fixed::<12>(g, z, q),
        18 => hessian_fixed::<18>(g, z, q),
        24 => hessian_fixed::<24>(g, z, q),
        30 => hessian_fixed::<30>(g, z, q),
        _ => hessian_dynamic(g, z, q),
    }
}

/// The value only (no derivatives; empty gradient and Hessian).
pub fn value_only(g: &PointGeometry, z: &[f64], q: Quantity) -> Derivatives {
    Derivatives {
        value: evaluate(g, z, q),
        grad: Vec::new(),
        hess: Vec::new(),
    }
}

/// Gap and jump with exact first and second derivatives at the local state `z`.
pub fn differentiate(g: &PointGeometry, z: &[f64]) -> (Derivatives, Derivatives) {
    (
        differentiate_one(g, z, Quantity::Gap),
        differentiate_one(g, z, Quantity::Jump),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::bspline::basis_ders;
    use crate::geometry::KnotVector;

    /// A slave point above a curved quadratic master span, with non-unit weights.
    fn geometry(eta0: f64) -> (PointGeometry, Vec<f64>) {
        let kv = KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).unwrap();
        let span = kv.find_span(eta0);
        let ders = basis_ders(&kv, span, eta0, 2);
        let g = PointGeometry {
            slave_basis: vec![0.3, 0.5, 0.2],
            slave_x: vec![[0.1, 0.62], [0.4, 0.55], [0.8, 0.6]],
            master_x: vec![[0.0, 0.0], [0.5, 0.4], [1.0, 0.1]],
            master_w: vec![1.0, 0.8, 1.1],
            master_ders: ders,
            normal_sign: 1.0,
            clamped: false,
            vertex: false,
        };
        let z = vec![
            0.01, -0.02, 1.1, 0.03, 0.01, 1.05, -0.01, 0.02, 1.0, 0.02, -0.01, 0.9, 0.0, 0.03,
            0.95, -0.02, 0.0, 1.02,
        ];
        (g, z)
    }

    /// Converges η by Newton in f64 (the production code does the same, more robustly).
    fn converge(g: &mut PointGeometry, z: &[f64]) {
        let kv = KnotVector::new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).unwrap();
        let mut eta = 0.5;
        for _ in 0..50 {
            g.master_ders = basis_ders(&kv, kv.find_span(eta), eta, 2);
            let xs = slave_point(g, z).0;
            let d = projection_delta(g, z, &xs);
            eta += d;
        }
        g.master_ders = basis_ders(&kv, kv.find_span(eta), eta, 2);
    }

    #[test]
    fn fixed_and_dynamic_sizes_agree() {
        let (mut g, z) = geometry(0.5);
        converge(&mut g, &z);
        for q in [Quantity::Gap, Quantity::Jump] {
            let a = hessian_fixed::<18>(&g, &z, q);
            let b = hessian_dynamic(&g, &z, q);
            assert_eq!(a.value, b.value);
            assert!(
                a.grad
                    .iter()
                    .zip(&b.grad)
                    .all(|(x, y)| (x - y).abs() <= 1e-15 * (1.0 + x.abs()))
            );
            assert!(
                a.hess
                    .iter()
                    .zip(&b.hess)
                    .all(|(x, y)| (x - y).abs() <= 1e-14 * (1.0 + x.abs()))
            );
        }
    }

    #[test]
    fn gap_derivatives_match_finite_differences() {
        let (mut g, z) = geometry(0.5);
        converge(&mut g, &z);
        let (gap, jump) = differentiate(&g, &z);
        let n = z.len();
        let h = 1e-6;
        for d in [&gap, &jump] {
            let f = |zz: &[f64]| {
                let mut gg = g.clone();
                converge(&mut gg, zz);
                if std::ptr::eq(d, &gap) {
                    normal_gap(&gg, zz)
                } else {
                    temperature_jump(&gg, zz)
                }
            };
            for i in 0..n {
                let mut zp = z.clone();
                zp[i] += h;
                let mut zm = z.clone();
                zm[i] -= h;
                let fd = (f(&zp) - f(&zm)) / (2.0 * h);
                assert!(
                    (fd - d.grad[i]).abs() < 1e-7,
                    "grad {i}: {fd} vs {}",
                    d.grad[i]
                );
                // Hessian column i by differences of the AD gradient at converged states.
                let mut gp = g.clone();
                converge(&mut gp, &zp);
                let mut gm = g.clone();
                converge(&mut gm, &zm);
                let (a, b) = if std::ptr::eq(d, &gap) {
                    (differentiate(&gp, &zp).0, differentiate(&gm, &zm).0)
                } else {
                    (differentiate(&gp, &zp).1, differentiate(&gm, &zm).1)
                };
                for j in 0..n {
                    let fd2 = (a.grad[j] - b.grad[j]) / (2.0 * h);
                    assert!(
                        (fd2 - d.hess[i * n + j]).abs() < 1e-6,
                        "hess ({i},{j}): {fd2} vs {}",
                        d.hess[i * n + j]
                    );
                }
            }
        }
        assert!(gap.value > 0.0);
    }
}
