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

/// The gap and what it was evaluated from.
struct GapEval<D> {
    /// Normal gap `gN = (x_s − x_m)·n` (positive when apart).
    gap: D,
    /// Projection increment `δ = η − η0`.
    delta: D,
    /// Slave point.
    xs: [D; 2],
    /// Master curve at `η0 + δ`.
    master: MasterEval<D>,
}

fn gap_eval<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> GapEval<D> {
    let (xs, _) = slave_point(g, z);
    let delta = projection_delta(g, z, &xs);
    let m = master_eval(g, z, &delta);
    let len = (m.dx[0].clone() * &m.dx[0] + m.dx[1].clone() * &m.dx[1]).sqrt();
    // n = sign · (−t_y, t_x) / |t|
    let nx = -m.dx[1].clone() * g.normal_sign / &len;
    let ny = m.dx[0].clone() * g.normal_sign / &len;
    let r = [xs[0].clone() - &m.x[0], xs[1].clone() - &m.x[1]];
    let along_normal = r[0].clone() * nx + r[1].clone() * ny;
    let gap = if g.vertex {
        // At a corner: the distance, signed by the side (the normal cone lies
        // between the normals of the two segments, so either one tells it).
        let distance = (r[0].clone() * &r[0] + r[1].clone() * &r[1]).sqrt();
        if along_normal.re() >= 0.0 {
            distance
        } else {
            -distance
        }
    } else {
        along_normal
    };
    GapEval {
        gap,
        delta,
        xs,
        master: m,
    }
}

/// Normal gap and the projection increment `δ = η − η0` it was evaluated at.
fn gap_and_delta<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> (D, D) {
    let e = gap_eval(g, z);
    (e.gap, e.delta)
}

/// Normal gap `gN = (x_s − x_m)·n` (positive when apart).
pub fn normal_gap<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> D {
    gap_and_delta(g, z).0
}

/// Temperature jump `ϑc = θ_s − θ_m(η)` (4.1).
pub fn temperature_jump<D: DualNum<Primitive = f64>>(g: &PointGeometry, z: &[D]) -> D {
    let (xs, ths) = slave_point(g, z);
    let delta = projection_delta(g, z, &xs);
    let m = master_eval(g, z, &delta);
    ths - m.theta
}

/// Value, gradient and Hessian of a kinematic quantity with respect to the
/// local unknowns (`(ux, uy, θ)` in 2D, `(ux, uy, uz, θ)` in 3D, per slave,
/// then per master control point). The Hessian is `hess` (row-major `n × n`,
/// or empty) plus the low-rank part `Σ u vᵀ` over `factors` (3D: a few
/// outer products instead of `n²` numbers per point). An empty gradient
/// means "not asked for"; a gradient without any Hessian part means that the
/// Hessian is zero in the unknowns of the phase.
#[derive(Clone, Debug, Default)]
pub struct Derivatives {
    /// Value.
    pub value: f64,
    /// Gradient with respect to the local unknowns.
    pub grad: Vec<f64>,
    /// Dense part of the Hessian (row-major).
    pub hess: Vec<f64>,
    /// Low-rank part of the Hessian: `Σ u vᵀ` (the sum is symmetric).
    pub factors: Vec<(Vec<f64>, Vec<f64>)>,
}

impl Derivatives {
    /// Adds `w` times the Hessian to the row-major `nd × nd` matrix `out`,
    /// local unknown `a` going to `map[a]` (`None`: dropped).
    pub fn add_hessian(&self, w: f64, map: &[Option<usize>], nd: usize, out: &mut [f64]) {
        let m = map.len();
        if !self.hess.is_empty() {
            for (a, ia) in map.iter().enumerate() {
                let Some(ia) = *ia else { continue };
                for (b, ib) in map.iter().enumerate() {
                    let Some(ib) = *ib else { continue };
                    out[ia * nd + ib] += w * self.hess[a * m + b];
                }
            }
        }
        for (u, v) in &self.factors {
            for (a, ia) in map.iter().enumerate() {
                let (Some(ia), ua) = (*ia, u[a]) else {
                    continue;
                };
                if ua == 0.0 {
                    continue;
                }
                let row = &mut out[ia * nd..(ia + 1) * nd];
                for (b, ib) in map.iter().enumerate() {
                    if let Some(ib) = *ib {
                        row[ib] += w * ua * v[b];
                    }
                }
            }
        }
    }

    /// The Hessian as a dense row-major matrix (tests, small sizes).
    pub fn dense_hessian(&self) -> Vec<f64> {
        let n = self.grad.len();
        let map: Vec<Option<usize>> = (0..n).map(Some).collect();
        let mut out = vec![0.0; n * n];
        self.add_hessian(1.0, &map, n, &mut out);
        out
    }
}

/// Which derivatives of gap and jump the current phase needs (spec §6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Needs {
    /// Values only.
    Values,
    /// Mechanical phase: the gap to second order in the displacements.
    Mechanical,
    /// Thermal phase on a frozen configuration: the jump to first order in
    /// the temperatures (displacements are not unknowns; it is linear in
    /// the temperatures, so its Hessian there is zero).
    Thermal,
    /// Monolithic coupling: gap and jump to second order in all unknowns.
    Coupled,
}

impl Needs {
    /// From whether the mechanical and the thermal contact terms are assembled.
    pub fn from_terms(mechanical: bool, thermal: bool) -> Needs {
        match (mechanical, thermal) {
            (false, false) => Needs::Values,
            (true, false) => Needs::Mechanical,
            (false, true) => Needs::Thermal,
            (true, true) => Needs::Coupled,
        }
    }
}

/// The rational master basis `R_j`, `R_j'`, `R_j''` of the span at `η0 + δ`.
fn rational_basis(g: &PointGeometry, delta: f64) -> [Vec<f64>; 3] {
    let p1 = g.master_ders.len();
    let powers: Vec<f64> = (0..p1).map(|m| delta.powi(m as i32)).collect();
    let nm = g.master_x.len();
    let der = |k: usize, j: usize| {
        if k < p1 {
            taylor(&g.master_ders, k, j, &powers) * g.master_w[j]
        } else {
            0.0
        }
    };
    let n: [Vec<f64>; 3] = std::array::from_fn(|k| (0..nm).map(|j| der(k, j)).collect());
    let [w, dw, ddw] = n.each_ref().map(|v| v.iter().sum::<f64>());
    let r: Vec<f64> = n[0].iter().map(|a| a / w).collect();
    let dr: Vec<f64> = (0..nm).map(|j| (n[1][j] - r[j] * dw) / w).collect();
    let ddr: Vec<f64> = (0..nm)
        .map(|j| (n[2][j] - 2.0 * dr[j] * dw - r[j] * ddw) / w)
        .collect();
    [r, dr, ddr]
}

/// Index of displacement component `k` (`2·node + c`) in the local unknowns.
fn u_index(k: usize) -> usize {
    3 * (k / 2) + k % 2
}

/// Gap and projection increment with first and second derivatives in the
/// `2 (ns + nm)` displacements only (the temperatures enter neither), by one
/// forward-mode pass; `N` is their number, fixed (on the stack) or dynamic.
fn displacement_hessian<N: nalgebra::Dim>(
    g: &PointGeometry,
    z: &[f64],
    n: N,
) -> [(f64, Vec<f64>, Vec<f64>); 2]
where
    nalgebra::DefaultAllocator: nalgebra::allocator::Allocator<N>
        + nalgebra::allocator::Allocator<nalgebra::U1, N>
        + nalgebra::allocator::Allocator<N, N>,
{
    let u = nalgebra::OVector::<f64, N>::from_fn_generic(n, nalgebra::U1, |k, _| z[u_index(k)]);
    let ((gv, gg, gh), (dv, dg, dh)) = num_dual::hessian(
        |x: nalgebra::OVector<num_dual::Dual2Vec<f64, N>, N>| {
            gap_and_delta(g, &local_duals(z, x.as_slice()))
        },
        &u,
    );
    [
        (gv, gg.as_slice().to_vec(), gh.as_slice().to_vec()),
        (dv, dg.as_slice().to_vec(), dh.as_slice().to_vec()),
    ]
}

/// The local unknowns as dual numbers: the displacements `u` (variables),
/// the temperatures of `z` (constants).
fn local_duals<D: DualNum<Primitive = f64>>(z: &[f64], u: &[D]) -> Vec<D> {
    (0..z.len())
        .map(|i| match i % 3 {
            2 => D::from(z[i]),
            c => u[2 * (i / 3) + c].clone(),
        })
        .collect()
}

/// Scatters a value, gradient and Hessian in the displacements into the
/// layout of all local unknowns (zeros in the temperatures).
fn scatter(n: usize, (v, grad, hess): &(f64, Vec<f64>, Vec<f64>)) -> Derivatives {
    let m = grad.len();
    let mut d = Derivatives {
        value: *v,
        grad: vec![0.0; n],
        hess: vec![0.0; n * n],
        ..Derivatives::default()
    };
    for k in 0..m {
        d.grad[u_index(k)] = grad[k];
        for l in 0..m {
            // Symmetric: column-major equals row-major.
            d.hess[u_index(k) * n + u_index(l)] = hess[k * m + l];
        }
    }
    d
}

/// Value, exact gradient and Hessian of gap and temperature jump at the
/// local state `z`, as far as `needs` asks (the other entries hold values
/// only), including the dependence of the projection point and the master
/// normal on the displacements (spec §6).
///
/// One forward-mode pass over the displacements gives the gap and the
/// projection increment `δ(u)` to second order (stack-allocated duals for
/// degrees 1–4); the jump `ϑc = Σ N_a θ_a − Σ R_j(η) θ_j`, linear in the
/// temperatures, then follows in closed form:
/// `∂ϑc/∂u = −θm' ∂δ`, `∂²ϑc/∂u∂u = −θm'' ∂δ⊗∂δ − θm' ∂²δ`,
/// `∂²ϑc/∂θ_j∂u = −R_j' ∂δ`.
pub fn differentiate(g: &PointGeometry, z: &[f64], needs: Needs) -> (Derivatives, Derivatives) {
    let n = z.len();
    match needs {
        Needs::Values => {
            let (gap, delta) = gap_and_delta(g, z);
            let [r, _, _] = rational_basis(g, delta);
            (value_only(gap), value_only(jump_value(g, z, &r)))
        }
        Needs::Thermal => {
            let (gap, delta) = gap_and_delta(g, z);
            let [r, _, _] = rational_basis(g, delta);
            let jump = Derivatives {
                value: jump_value(g, z, &r),
                grad: jump_temperature_gradient(g, n, &r),
                ..Derivatives::default()
            };
            (value_only(gap), jump)
        }
        Needs::Mechanical if !g.clamped => {
            let e = gap_eval(g, z);
            let [r, dr, _] = rational_basis(g, e.delta);
            let gap_d = gap_second_variation(g, n, &e, &r, &dr);
            (gap_d, value_only(jump_value(g, z, &r)))
        }
        Needs::Mechanical | Needs::Coupled => {
            use nalgebra::Const;
            let [gap, delta] = match n {
                12 => displacement_hessian(g, z, Const::<8>),
                18 => displacement_hessian(g, z, Const::<12>),
                24 => displacement_hessian(g, z, Const::<16>),
                30 => displacement_hessian(g, z, Const::<20>),
                _ => displacement_hessian(g, z, nalgebra::Dyn(2 * n / 3)),
            };
            let gap_d = scatter(n, &gap);
            if needs == Needs::Mechanical {
                let [r, _, _] = rational_basis(g, delta.0);
                return (gap_d, value_only(jump_value(g, z, &r)));
            }
            (gap_d, jump_derivatives(g, z, &delta))
        }
    }
}

/// The gap's first and second variations in closed form at a converged
/// projection (the classical 2D result): with `t = x_m'`, `a = t·t`,
/// `b = n·x_m''`, `D = a − gN b`, and per virtual displacement
/// `A(δ) = (δx_s − Σ R_j δv_j)·t`, `C(δ) = n·Σ R_j' δv_j`,
/// ```text
/// δgN   = (δx_s − Σ R_j δv_j)·n
/// ΔδgN  = −[ (b/a) A(δ)A(Δ) + C(δ)A(Δ) + A(δ)C(Δ) + gN C(δ)C(Δ) ] / D
/// ```
/// (`δη = (A(δ) + gN C(δ))/D`). At a corner (`η` fixed, the gap the signed
/// distance `gN = ±|r|`, `m = r/gN`): `δgN = m·δr`,
/// `ΔδgN = (δr·Δr − (m·δr)(m·Δr))/gN`. `r`, `dr` are the rational master
/// basis and its derivative at the projection; `n` the number of local
/// unknowns.
fn gap_second_variation(
    g: &PointGeometry,
    n: usize,
    e: &GapEval<f64>,
    r: &[f64],
    dr: &[f64],
) -> Derivatives {
    let ns = g.slave_x.len();
    let (gap, xs, m) = (e.gap, e.xs, &e.master);
    // Displacement dof index of node `k`, component `c`, and the weight of
    // its virtual displacement in x_s − x_m.
    let weight = |k: usize| {
        if k < ns { g.slave_basis[k] } else { -r[k - ns] }
    };
    let nodes = ns + g.master_x.len();
    let mut d = Derivatives {
        value: gap,
        grad: vec![0.0; n],
        hess: vec![0.0; n * n],
        ..Derivatives::default()
    };
    if g.vertex {
        let rv = [xs[0] - m.x[0], xs[1] - m.x[1]];
        let normal = [rv[0] / gap, rv[1] / gap];
        for k in 0..nodes {
            for c in 0..2 {
                d.grad[3 * k + c] = weight(k) * normal[c];
            }
        }
        // (δr·Δr − (m·δr)(m·Δr))/gN, δr = Σ weight δu.
        for k in 0..nodes {
            for l in 0..nodes {
                let w = weight(k) * weight(l) / gap;
                for c in 0..2 {
                    for e in 0..2 {
                        let id = if c == e { 1.0 } else { 0.0 };
                        d.hess[(3 * k + c) * n + 3 * l + e] = w * (id - normal[c] * normal[e]);
                    }
                }
            }
        }
        return d;
    }
    let t = m.dx;
    let a = t[0] * t[0] + t[1] * t[1];
    let len = a.sqrt();
    let normal = [-t[1] * g.normal_sign / len, t[0] * g.normal_sign / len];
    let b = normal[0] * m.ddx[0] + normal[1] * m.ddx[1];
    let denom = a - gap * b;
    // A and C per displacement dof.
    let mut av = vec![0.0; n];
    let mut cv = vec![0.0; n];
    for k in 0..nodes {
        for c in 0..2 {
            let i = 3 * k + c;
            d.grad[i] = weight(k) * normal[c];
            av[i] = weight(k) * t[c];
            if k >= ns {
                cv[i] = dr[k - ns] * normal[c];
            }
        }
    }
    for i in (0..n).filter(|i| i % 3 != 2) {
        for j in (0..n).filter(|j| j % 3 != 2) {
            d.hess[i * n + j] =
                -(b / a * av[i] * av[j] + cv[i] * av[j] + av[i] * cv[j] + gap * cv[i] * cv[j])
                    / denom;
        }
    }
    d
}

fn value_only(value: f64) -> Derivatives {
    Derivatives {
        value,
        ..Derivatives::default()
    }
}

/// `ϑc = Σ N_a θ_a − Σ R_j θ_j` with the rational master basis `r`.
fn jump_value(g: &PointGeometry, z: &[f64], r: &[f64]) -> f64 {
    let ns = g.slave_x.len();
    let slave: f64 = (0..ns).map(|a| g.slave_basis[a] * z[3 * a + 2]).sum();
    let master: f64 = r
        .iter()
        .enumerate()
        .map(|(j, rj)| rj * z[3 * (ns + j) + 2])
        .sum();
    slave - master
}

/// `∂ϑc/∂θ`: `N_a` at the slave temperatures, `−R_j` at the master's (zero
/// at the displacements), of length `n`.
fn jump_temperature_gradient(g: &PointGeometry, n: usize, r: &[f64]) -> Vec<f64> {
    let ns = g.slave_x.len();
    let mut grad = vec![0.0; n];
    for (a, &na) in g.slave_basis.iter().enumerate() {
        grad[3 * a + 2] = na;
    }
    for (j, rj) in r.iter().enumerate() {
        grad[3 * (ns + j) + 2] = -rj;
    }
    grad
}

/// The jump's derivatives in all local unknowns from those of `δ(u)`.
fn jump_derivatives(
    g: &PointGeometry,
    z: &[f64],
    (delta, dd, ddd): &(f64, Vec<f64>, Vec<f64>),
) -> Derivatives {
    let n = z.len();
    let ns = g.slave_x.len();
    let [r, dr, ddr] = rational_basis(g, *delta);
    let theta = |j: usize| z[3 * (ns + j) + 2];
    let dtheta: f64 = dr.iter().enumerate().map(|(j, v)| v * theta(j)).sum();
    let ddtheta: f64 = ddr.iter().enumerate().map(|(j, v)| v * theta(j)).sum();
    let m = dd.len();
    let mut d = Derivatives {
        value: jump_value(g, z, &r),
        grad: jump_temperature_gradient(g, n, &r),
        hess: vec![0.0; n * n],
        ..Derivatives::default()
    };
    for k in 0..m {
        let ik = u_index(k);
        d.grad[ik] = -dtheta * dd[k];
        for l in 0..m {
            d.hess[ik * n + u_index(l)] = -ddtheta * dd[k] * dd[l] - dtheta * ddd[k * m + l];
        }
        for (j, drj) in dr.iter().enumerate() {
            let it = 3 * (ns + j) + 2;
            d.hess[ik * n + it] = -drj * dd[k];
            d.hess[it * n + ik] = -drj * dd[k];
        }
    }
    d
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

    /// Gap or jump with first and second derivatives in *all* local
    /// unknowns by plain forward-mode AD (the reference of the split pass).
    fn full_ad(g: &PointGeometry, z: &[f64], gap: bool) -> Derivatives {
        let zv = nalgebra::DVector::from_column_slice(z);
        let (v, gr, h) = num_dual::hessian(
            |x: nalgebra::DVector<_>| {
                if gap {
                    normal_gap(g, x.as_slice())
                } else {
                    temperature_jump(g, x.as_slice())
                }
            },
            &zv,
        );
        Derivatives {
            value: v,
            grad: gr.as_slice().to_vec(),
            hess: h.as_slice().to_vec(),
            ..Derivatives::default()
        }
    }

    fn assert_close(a: &[f64], b: &[f64], tol: f64) {
        assert_eq!(a.len(), b.len());
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            assert!((x - y).abs() <= tol * (1.0 + x.abs()), "{i}: {x} vs {y}");
        }
    }

    #[test]
    fn split_pass_equals_full_ad_in_every_phase() {
        for (clamped, vertex) in [(false, false), (true, false), (false, true)] {
            let (mut g, z) = geometry(0.5);
            converge(&mut g, &z);
            (g.clamped, g.vertex) = (clamped, vertex);
            let (rg, rj) = (full_ad(&g, &z, true), full_ad(&g, &z, false));
            let (gap, jump) = differentiate(&g, &z, Needs::Coupled);
            assert_eq!(gap.value, rg.value);
            assert!((jump.value - rj.value).abs() < 1e-15);
            assert_close(&gap.grad, &rg.grad, 1e-14);
            assert_close(&gap.hess, &rg.hess, 1e-13);
            assert_close(&jump.grad, &rj.grad, 1e-14);
            assert_close(&jump.hess, &rj.hess, 1e-13);
            // The closed-form second variation of the mechanical phase.
            let (gm, jm) = differentiate(&g, &z, Needs::Mechanical);
            assert_eq!(gm.value, gap.value);
            assert_close(&gm.grad, &rg.grad, 1e-13);
            assert_close(&gm.hess, &rg.hess, 1e-12);
            assert!(jm.grad.is_empty() && jm.value == jump.value);
            // The thermal phase: the temperature entries of the gradient.
            let (gt, jt) = differentiate(&g, &z, Needs::Thermal);
            assert!(gt.grad.is_empty() && gt.value == gap.value && jt.hess.is_empty());
            for (i, (x, y)) in jt.grad.iter().zip(&rj.grad).enumerate() {
                if i % 3 == 2 {
                    assert!((x - y).abs() < 1e-15, "{i}: {x} vs {y}");
                } else {
                    assert_eq!(*x, 0.0);
                }
            }
            let (gv, jv) = differentiate(&g, &z, Needs::Values);
            assert_eq!((gv.value, jv.value), (gap.value, jump.value));
        }
    }

    #[test]
    fn fixed_and_dynamic_sizes_agree() {
        let (mut g, z) = geometry(0.5);
        converge(&mut g, &z);
        let a = displacement_hessian(&g, &z, nalgebra::Const::<12>);
        let b = displacement_hessian(&g, &z, nalgebra::Dyn(12));
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.0, y.0);
            assert_close(&x.1, &y.1, 1e-15);
            assert_close(&x.2, &y.2, 1e-14);
        }
    }

    #[test]
    fn gap_derivatives_match_finite_differences() {
        let (mut g, z) = geometry(0.5);
        converge(&mut g, &z);
        let (gap, jump) = differentiate(&g, &z, Needs::Coupled);
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
                    (
                        differentiate(&gp, &zp, Needs::Coupled).0,
                        differentiate(&gm, &zm, Needs::Coupled).0,
                    )
                } else {
                    (
                        differentiate(&gp, &zp, Needs::Coupled).1,
                        differentiate(&gm, &zm, Needs::Coupled).1,
                    )
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
