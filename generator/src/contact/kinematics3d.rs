//! Contact kinematics at one slave integration point in 3D (paper Sect. 4,
//! spec §6): the normal gap `gN = (x_s − x_m(η))·n` with `n` the master's
//! outward unit normal `± a_1 × a_2 / |a_1 × a_2|` (`a_α = ∂x_m/∂η_α`), and the
//! temperature jump `ϑc = θ_s − θ_m(η)` (4.1), `η ∈ R²` the closest-point
//! projection of the slave point onto the master surface
//! ([`crate::contact::projection3d`]), with exact first and second derivatives
//! in the local unknowns `(ux, uy, uz, θ)` per slave, then per master control
//! point, including the dependence of `η` and `n` on the displacements.
//!
//! Within one element the master's THB functions are polynomials of degree
//! `(p1, p2)`, exactly represented by their bivariate Taylor table at the
//! projection `η0` ([`crate::geometry::ThbPatch::surface_element_ders`]), so
//! the master and its derivatives of every order are available at `η0` and,
//! in dual arithmetic, at `η0 + δ`.
//!
//! Production derivatives are in closed form (the classical covariant
//! results, written for a set `F` of free parameters): with `δd = δx_s − Σ R_j
//! δv_j`, `D_i = δd·a_i`, `C_i = m·Σ R_j,i δv_j`, `M_il = a_i·a_l`,
//! `B_il = m·a_il`, `K = (M − gN B)⁻¹` over `F`:
//! ```text
//! δgN  = m·δd,            δη = K (D + gN C)
//! ΔδgN = −[ D·M⁻¹BK D + C·K D + D·K C + gN C·K C ]              (regular, F = {1, 2})
//! ΔδgN = [ δd·(I − m⊗m)Δd − D·K D ]/gN − C·K D − D·K C − gN C·K C   (edge, vertex)
//! ```
//! with `m = n` at a regular point and `m = r/gN` at a C0 edge or vertex of
//! the master, where the gap is the signed distance `±|r|` to it (`r = x_s −
//! x_m`); the second variation of `η` (for the jump in the coupled phase)
//! follows from differentiating `r·a_i = 0` twice. Hessians are returned as a
//! few outer products ([`Derivatives::factors`]). At a boundary of a
//! non-periodic master (clamped) the gap is the normal gap at the held
//! parameter, differentiated by forward-mode AD (`num_dual`) as in 2D; the
//! same generic evaluation is the tests' reference for every case.

use num_dual::DualNum;

use crate::contact::kinematics::{Derivatives, Needs};
use crate::contact::projection3d::SurfaceProjection;
use crate::geometry::ThbPatch;

/// Local unknowns per control point: `(ux, uy, uz, θ)`.
const NF: usize = 4;

/// Frozen data of one slave integration point and the master element it
/// projects onto (3D).
#[derive(Clone, Debug)]
pub struct SurfacePointGeometry {
    /// Slave basis values at the point (one per slave element control point).
    pub slave_basis: Vec<f64>,
    /// Reference positions of the slave element control points.
    pub slave_x: Vec<[f64; 3]>,
    /// Reference positions of the master element's control points, including
    /// the periodic shift of the image.
    pub master_x: Vec<[f64; 3]>,
    /// NURBS weights of the master element's control points.
    pub master_w: Vec<f64>,
    /// Taylor table of the master element's polynomial THB functions at `η0`:
    /// `master_ders[k1 (q + 1) + k2][j] = ∂^(k1+k2) T_j / ∂η1^k1 ∂η2^k2`, `k1, k2 ≤ q`.
    pub master_ders: Vec<Vec<f64>>,
    /// Order `q` of the table (the larger degree of the master).
    pub order: usize,
    /// +1 if the master's outward normal is `a_1 × a_2 / |a_1 × a_2|`, −1 otherwise.
    pub normal_sign: f64,
    /// Parameters held at the projection (C0 edge or vertex, or clamped).
    pub fixed: [bool; 2],
    /// The projection is clamped at a boundary of a non-periodic master.
    pub clamped: bool,
}

impl SurfacePointGeometry {
    /// The geometry of a slave point (basis values and reference control
    /// points of its element) projected by `pr` onto the master face `face`
    /// (reference configuration: `face.control_points()`).
    pub fn new(
        face: &ThbPatch,
        pr: &SurfaceProjection,
        normal_sign: f64,
        slave_basis: Vec<f64>,
        slave_x: Vec<[f64; 3]>,
    ) -> Self {
        let el = &face.elements()[pr.element];
        let order = face.degrees().into_iter().max().unwrap_or(1);
        let cp = face.control_points();
        SurfacePointGeometry {
            slave_basis,
            slave_x,
            master_x: el
                .functions
                .iter()
                .map(|&j| {
                    let x = cp[j];
                    [x[0] + pr.shift[0], x[1] + pr.shift[1], x[2] + pr.shift[2]]
                })
                .collect(),
            master_w: el.functions.iter().map(|&j| face.weights()[j]).collect(),
            master_ders: face.surface_element_ders(pr.element, pr.eta, order),
            order,
            normal_sign,
            fixed: pr.fixed,
            clamped: pr.clamped,
        }
    }

    /// Number of local unknowns: `(ux, uy, uz, θ)` per slave, then per master control point.
    pub fn n_local(&self) -> usize {
        NF * (self.slave_x.len() + self.master_x.len())
    }

    fn free(&self) -> Vec<usize> {
        (0..2).filter(|&d| !self.fixed[d]).collect()
    }
}

// ---------------------------------------------------------------------------
// Generic evaluation (dual numbers): the reference, and the clamped case.

/// Position, tangents, second derivatives and temperature of the master at `η0 + δ`.
struct MasterEval<D> {
    x: [D; 3],
    a: [[D; 3]; 2],
    aa: [[[D; 3]; 2]; 2],
    theta: D,
}

fn master_eval<D: DualNum<Primitive = f64>>(
    g: &SurfacePointGeometry,
    z: &[D],
    delta: &[D; 2],
) -> MasterEval<D> {
    let q = g.order;
    let ns = g.slave_x.len();
    // δ_d^m / m! for m = 0..=q.
    let scaled_powers = |d: &D| {
        let mut v = vec![D::from(1.0)];
        for m in 1..=q {
            let next = v[m - 1].clone() * d / m as f64;
            v.push(next);
        }
        v
    };
    let (p0, p1) = (scaled_powers(&delta[0]), scaled_powers(&delta[1]));
    // The derivative α of T_j at η0 + δ from the Taylor table.
    let taylor = |alpha: [usize; 2], j: usize| {
        let mut s = D::from(0.0);
        if alpha[0] > q || alpha[1] > q {
            return s;
        }
        for m0 in 0..=q - alpha[0] {
            for m1 in 0..=q - alpha[1] {
                let c = g.master_ders[(alpha[0] + m0) * (q + 1) + alpha[1] + m1][j];
                if c != 0.0 {
                    s += p0[m0].clone() * &p1[m1] * c;
                }
            }
        }
        s
    };
    let zero = || D::from(0.0);
    let alphas = [[0, 0], [1, 0], [0, 1], [2, 0], [1, 1], [0, 2]];
    let mut w: [D; 6] = std::array::from_fn(|_| zero());
    let mut h: [[D; 3]; 6] = std::array::from_fn(|_| std::array::from_fn(|_| zero()));
    let mut th = zero();
    for j in 0..g.master_x.len() {
        let off = NF * (ns + j);
        for (k, &alpha) in alphas.iter().enumerate() {
            let n = taylor(alpha, j) * g.master_w[j];
            for c in 0..3 {
                h[k][c] += n.clone() * (z[off + c].clone() + g.master_x[j][c]);
            }
            if k == 0 {
                th += n.clone() * &z[off + 3];
            }
            w[k] += n;
        }
    }
    // x = A/W and its derivatives (quotient rule).
    let winv = w[0].clone().recip();
    let x: [D; 3] = std::array::from_fn(|c| h[0][c].clone() * &winv);
    let a: [[D; 3]; 2] = std::array::from_fn(|i| {
        std::array::from_fn(|c| (h[1 + i][c].clone() - x[c].clone() * &w[1 + i]) * &winv)
    });
    let second = |i: usize, l: usize| 3 + i + l;
    let aa: [[[D; 3]; 2]; 2] = std::array::from_fn(|i| {
        std::array::from_fn(|l| {
            std::array::from_fn(|c| {
                (h[second(i, l)][c].clone()
                    - a[i][c].clone() * &w[1 + l]
                    - a[l][c].clone() * &w[1 + i]
                    - x[c].clone() * &w[second(i, l)])
                    * &winv
            })
        })
    });
    MasterEval {
        x,
        a,
        aa,
        theta: th * winv,
    }
}

fn slave_point<D: DualNum<Primitive = f64>>(g: &SurfacePointGeometry, z: &[D]) -> ([D; 3], D) {
    let mut x: [D; 3] = std::array::from_fn(|_| D::from(0.0));
    let mut th = D::from(0.0);
    for (a, &n) in g.slave_basis.iter().enumerate() {
        for c in 0..3 {
            x[c] += (z[NF * a + c].clone() + g.slave_x[a][c]) * n;
        }
        th += z[NF * a + 3].clone() * n;
    }
    (x, th)
}

fn dot3<D: DualNum<Primitive = f64>>(a: &[D; 3], b: &[D; 3]) -> D {
    a[0].clone() * &b[0] + a[1].clone() * &b[1] + a[2].clone() * &b[2]
}

/// The projection increment `δ = η − η0` after two Newton steps on
/// `r·a_i = 0` (free `i`) from `δ = 0`: exact to second order in the unknowns.
fn projection_delta<D: DualNum<Primitive = f64>>(
    g: &SurfacePointGeometry,
    z: &[D],
    xs: &[D; 3],
) -> [D; 2] {
    let mut delta = [D::from(0.0), D::from(0.0)];
    let free = g.free();
    for _ in 0..2 {
        let m = master_eval(g, z, &delta);
        let r: [D; 3] = std::array::from_fn(|c| xs[c].clone() - &m.x[c]);
        let phi: Vec<D> = free.iter().map(|&i| dot3(&r, &m.a[i])).collect();
        let jac = |i: usize, l: usize| -dot3(&m.a[i], &m.a[l]) + dot3(&r, &m.aa[i][l]);
        match free.len() {
            2 => {
                let (j00, j01, j11) = (jac(0, 0), jac(0, 1), jac(1, 1));
                let det = j00.clone() * &j11 - j01.clone() * &j01;
                let s0 = (j11 * &phi[0] - j01.clone() * &phi[1]) / &det;
                let s1 = (j00 * &phi[1] - j01 * &phi[0]) / &det;
                delta[0] -= s0;
                delta[1] -= s1;
            }
            1 => {
                let i = free[0];
                let s = phi[0].clone() / jac(i, i);
                delta[i] -= s;
            }
            _ => {}
        }
    }
    delta
}

/// Gap and projection increment in any dual arithmetic (the reference).
fn gap_and_delta<D: DualNum<Primitive = f64>>(g: &SurfacePointGeometry, z: &[D]) -> (D, [D; 2]) {
    let (xs, _) = slave_point(g, z);
    let delta = projection_delta(g, z, &xs);
    let m = master_eval(g, z, &delta);
    let t = &m.a;
    let cross: [D; 3] = [
        t[0][1].clone() * &t[1][2] - t[0][2].clone() * &t[1][1],
        t[0][2].clone() * &t[1][0] - t[0][0].clone() * &t[1][2],
        t[0][0].clone() * &t[1][1] - t[0][1].clone() * &t[1][0],
    ];
    let len = dot3(&cross, &cross).sqrt();
    let n: [D; 3] = std::array::from_fn(|c| cross[c].clone() * g.normal_sign / &len);
    let r: [D; 3] = std::array::from_fn(|c| xs[c].clone() - &m.x[c]);
    let along = dot3(&r, &n);
    let feature = !g.clamped && g.fixed.iter().any(|&f| f);
    let gap = if feature {
        let d = dot3(&r, &r).sqrt();
        if along.re() >= 0.0 { d } else { -d }
    } else {
        along
    };
    (gap, delta)
}

/// Normal gap (positive when apart), generic.
pub fn normal_gap<D: DualNum<Primitive = f64>>(g: &SurfacePointGeometry, z: &[D]) -> D {
    gap_and_delta(g, z).0
}

/// Temperature jump `ϑc = θ_s − θ_m(η)` (4.1), generic.
pub fn temperature_jump<D: DualNum<Primitive = f64>>(g: &SurfacePointGeometry, z: &[D]) -> D {
    let (xs, ths) = slave_point(g, z);
    let delta = projection_delta(g, z, &xs);
    ths - master_eval(g, z, &delta).theta
}

// ---------------------------------------------------------------------------
// Closed form.

/// Multi-indices `(α1, α2)` with `|α| ≤ 3`, by total order.
const ORDER3: usize = 10;

fn mi(a1: usize, a2: usize) -> usize {
    let s = a1 + a2;
    s * (s + 1) / 2 + a2
}

fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |b, i| b * (n - i) as f64 / (i + 1) as f64)
}

/// The rational master basis `R_j` and its derivatives of total order ≤ 3 at
/// `η0`: `R_j^(α) = (N_j^(α) − Σ_{β<α} binom(α, β) R_j^(β) W^(α−β)) / W` with
/// `N_j = w_j T_j`, `W = Σ N_j`.
fn rational_jets(g: &SurfacePointGeometry) -> Vec<[f64; ORDER3]> {
    let q = g.order;
    let nm = g.master_x.len();
    let indices: Vec<[usize; 2]> = (0..=3)
        .flat_map(|s| (0..=s).map(move |k| [s - k, k]))
        .collect();
    let n: Vec<[f64; ORDER3]> = (0..nm)
        .map(|j| {
            std::array::from_fn(|k| {
                let [a1, a2] = indices[k];
                if a1 <= q && a2 <= q {
                    g.master_w[j] * g.master_ders[a1 * (q + 1) + a2][j]
                } else {
                    0.0
                }
            })
        })
        .collect();
    let w: [f64; ORDER3] = std::array::from_fn(|k| n.iter().map(|v| v[k]).sum());
    n.iter()
        .map(|nj| {
            let mut r = [0.0; ORDER3];
            for (k, &[a1, a2]) in indices.iter().enumerate() {
                let mut v = nj[k];
                for b1 in 0..=a1 {
                    for b2 in 0..=a2 {
                        if (b1, b2) != (a1, a2) {
                            v -= binomial(a1, b1)
                                * binomial(a2, b2)
                                * r[mi(b1, b2)]
                                * w[mi(a1 - b1, a2 - b2)];
                        }
                    }
                }
                r[k] = v / w[0];
            }
            r
        })
        .collect()
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Inverse of the symmetric matrix `a` over the index set `free` (0, 1 or 2 entries).
fn inverse(a: [[f64; 2]; 2], free: &[usize]) -> [[f64; 2]; 2] {
    let mut k = [[0.0; 2]; 2];
    match free {
        [i] => k[*i][*i] = 1.0 / a[*i][*i],
        [_, _] => {
            let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
            k = [
                [a[1][1] / det, -a[0][1] / det],
                [-a[1][0] / det, a[0][0] / det],
            ];
        }
        _ => {}
    }
    k
}

/// `Σ_l c[l] v[l]` over vectors of equal length.
fn combine(c: &[f64], v: &[&Vec<f64>]) -> Vec<f64> {
    let mut out = vec![0.0; v[0].len()];
    for (cl, vl) in c.iter().zip(v) {
        if *cl != 0.0 {
            for (o, x) in out.iter_mut().zip(vl.iter()) {
                *o += cl * x;
            }
        }
    }
    out
}

/// Everything the closed-form derivatives share.
struct Frame {
    /// Rational basis jets per master function.
    r: Vec<[f64; ORDER3]>,
    /// Geometry jets `x^(α)` and temperature jets `θ^(α)`.
    x: [[f64; 3]; ORDER3],
    theta: [f64; ORDER3],
    theta_s: f64,
    /// Feature normal `m` and the gap.
    m: [f64; 3],
    gap: f64,
    free: Vec<usize>,
}

impl Frame {
    fn new(g: &SurfacePointGeometry, z: &[f64]) -> Frame {
        let ns = g.slave_x.len();
        let r = rational_jets(g);
        let mut x = [[0.0; 3]; ORDER3];
        let mut theta = [0.0; ORDER3];
        for (j, rj) in r.iter().enumerate() {
            let off = NF * (ns + j);
            for k in 0..ORDER3 {
                for c in 0..3 {
                    x[k][c] += rj[k] * (g.master_x[j][c] + z[off + c]);
                }
                theta[k] += rj[k] * z[off + 3];
            }
        }
        let (xs, theta_s) = slave_point(g, z);
        let (a0, a1) = (x[mi(1, 0)], x[mi(0, 1)]);
        let cross = [
            a0[1] * a1[2] - a0[2] * a1[1],
            a0[2] * a1[0] - a0[0] * a1[2],
            a0[0] * a1[1] - a0[1] * a1[0],
        ];
        let len = dot(cross, cross).sqrt();
        let n = cross.map(|c| c * g.normal_sign / len);
        let rv = [xs[0] - x[0][0], xs[1] - x[0][1], xs[2] - x[0][2]];
        let free = g.free();
        let along = dot(rv, n);
        // The normal gap, except at a C0 edge or vertex: the signed distance.
        let (m, gap) = if g.clamped || free.len() == 2 {
            (n, along)
        } else {
            let d = dot(rv, rv).sqrt();
            let gap = if along >= 0.0 { d } else { -d };
            if d > 0.0 {
                (rv.map(|c| c / gap), gap)
            } else {
                (n, 0.0)
            }
        };
        Frame {
            r,
            x,
            theta,
            theta_s,
            m,
            gap,
            free,
        }
    }

    fn a(&self, i: usize) -> [f64; 3] {
        self.x[if i == 0 { mi(1, 0) } else { mi(0, 1) }]
    }

    fn aa(&self, i: usize, l: usize) -> [f64; 3] {
        self.x[mi(2 - i - l, i + l)]
    }

    fn aaa(&self, i: usize, l: usize, k: usize) -> [f64; 3] {
        let s = i + l + k;
        self.x[mi(3 - s, s)]
    }

    /// Rational basis derivative `∂R_j/∂η_i`, `∂²R_j/∂η_i∂η_l`.
    fn dr(&self, j: usize, i: usize) -> f64 {
        self.r[j][if i == 0 { mi(1, 0) } else { mi(0, 1) }]
    }

    fn ddr(&self, j: usize, i: usize, l: usize) -> f64 {
        self.r[j][mi(2 - i - l, i + l)]
    }
}

/// The closed-form derivatives of gap and jump (not for clamped points).
fn closed_form(g: &SurfacePointGeometry, z: &[f64], needs: Needs) -> (Derivatives, Derivatives) {
    let n = z.len();
    let ns = g.slave_x.len();
    let nm = g.master_x.len();
    let f = Frame::new(g, z);
    let jump_value = f.theta_s - f.theta[0];
    let value = |v: f64| Derivatives {
        value: v,
        ..Derivatives::default()
    };
    // Temperature gradient of the jump.
    let jump_temperature_gradient = || {
        let mut grad = vec![0.0; n];
        for (a, &na) in g.slave_basis.iter().enumerate() {
            grad[NF * a + 3] = na;
        }
        for j in 0..nm {
            grad[NF * (ns + j) + 3] = -f.r[j][0];
        }
        grad
    };
    match needs {
        Needs::Values => return (value(f.gap), value(jump_value)),
        Needs::Thermal => {
            let jump = Derivatives {
                value: jump_value,
                grad: jump_temperature_gradient(),
                ..Derivatives::default()
            };
            return (value(f.gap), jump);
        }
        Needs::Mechanical | Needs::Coupled => {}
    }
    let (m, gap, free) = (f.m, f.gap, &f.free);
    // Per displacement unknown: the weight w of δd = w e_c (slave N_a, master
    // −R_j); W^c (w on component c), D^i, C^i, and the master vectors.
    let mut wc: [Vec<f64>; 3] = std::array::from_fn(|_| vec![0.0; n]);
    let mut d: [Vec<f64>; 2] = std::array::from_fn(|_| vec![0.0; n]);
    let mut cv: [Vec<f64>; 2] = std::array::from_fn(|_| vec![0.0; n]);
    let mut grad = vec![0.0; n];
    let a = [f.a(0), f.a(1)];
    for node in 0..ns + nm {
        let w = if node < ns {
            g.slave_basis[node]
        } else {
            -f.r[node - ns][0]
        };
        for c in 0..3 {
            let k = NF * node + c;
            wc[c][k] = w;
            grad[k] = w * m[c];
            for i in 0..2 {
                d[i][k] = w * a[i][c];
                if node >= ns {
                    cv[i][k] = f.dr(node - ns, i) * m[c];
                }
            }
        }
    }
    let mut mm = [[0.0; 2]; 2];
    let mut bb = [[0.0; 2]; 2];
    let mut aam = [[0.0; 2]; 2];
    for i in 0..2 {
        for l in 0..2 {
            mm[i][l] = dot(a[i], a[l]);
            bb[i][l] = dot(m, f.aa(i, l));
            aam[i][l] = mm[i][l] - gap * bb[i][l];
        }
    }
    let k = inverse(aam, free);
    let dv: Vec<&Vec<f64>> = d.iter().collect();
    let cvv: Vec<&Vec<f64>> = cv.iter().collect();
    // δη^i = K_il (D^l + g C^l).
    let eta: [Vec<f64>; 2] = std::array::from_fn(|i| {
        combine(
            &[k[i][0], k[i][1], gap * k[i][0], gap * k[i][1]],
            &[dv[0], dv[1], cvv[0], cvv[1]],
        )
    });
    // The Hessian's rows C^i: −C·K D − g C·K C = −C^i ⊗ δη^i.
    let mut factors: Vec<(Vec<f64>, Vec<f64>)> = free
        .iter()
        .map(|&i| (cv[i].clone(), eta[i].iter().map(|x| -x).collect()))
        .collect();
    if free.len() == 2 {
        // −D·Q D − D·K C, Q = M⁻¹ B K (= (K − M⁻¹)/g, without the division).
        let minv = inverse(mm, free);
        let mut q = [[0.0; 2]; 2];
        for i in 0..2 {
            for l in 0..2 {
                q[i][l] = (0..2)
                    .flat_map(|s| (0..2).map(move |t| (s, t)))
                    .map(|(s, t)| minv[i][s] * bb[s][t] * k[t][l])
                    .sum();
            }
        }
        for i in 0..2 {
            let v = combine(
                &[-q[i][0], -q[i][1], -k[i][0], -k[i][1]],
                &[dv[0], dv[1], cvv[0], cvv[1]],
            );
            factors.push((d[i].clone(), v));
        }
    } else if gap != 0.0 {
        // [δd·(I − m⊗m)Δd − D·K D]/g − D·K C = Σ_c W^c⊗W^c/g − ∇g⊗∇g/g − D^i⊗δη^i/g.
        for w in &wc {
            factors.push((w.clone(), w.iter().map(|x| x / gap).collect()));
        }
        factors.push((grad.clone(), grad.iter().map(|x| -x / gap).collect()));
        for &i in free {
            factors.push((d[i].clone(), eta[i].iter().map(|x| -x / gap).collect()));
        }
    }
    let gap_d = Derivatives {
        value: gap,
        grad,
        hess: Vec::new(),
        factors,
    };
    let theta_d = |i: usize| f.theta[if i == 0 { mi(1, 0) } else { mi(0, 1) }];
    let theta_dd = |i: usize, l: usize| f.theta[mi(2 - i - l, i + l)];
    let mut jgrad = jump_temperature_gradient();
    for (kk, gk) in jgrad.iter_mut().enumerate() {
        if kk % NF != 3 {
            *gk = -(0..2).map(|i| theta_d(i) * eta[i][kk]).sum::<f64>();
        }
    }
    if needs == Needs::Mechanical {
        return (gap_d, value(jump_value));
    }
    // The jump's Hessian (coupled phase).
    let mut jf: Vec<(Vec<f64>, Vec<f64>)> = Vec::new();
    // Master temperature vectors R_j,i at the temperature unknowns.
    let rtheta: [Vec<f64>; 2] = std::array::from_fn(|i| {
        let mut v = vec![0.0; n];
        for j in 0..nm {
            v[NF * (ns + j) + 3] = f.dr(j, i);
        }
        v
    });
    // λ_l = −Σ_i θ_,i K_il: the covector of −θ_,i Δδη^i = λ·(K⁻¹ Δδη).
    let lambda: [f64; 2] =
        std::array::from_fn(|l| -(0..2).map(|i| theta_d(i) * k[i][l]).sum::<f64>());
    // E_lm per unknown, T_lmn.
    let mut e_lm: [[Vec<f64>; 2]; 2] =
        std::array::from_fn(|_| std::array::from_fn(|_| vec![0.0; n]));
    for &l in free {
        for &mdir in free {
            let all = f.aa(l, mdir);
            for node in 0..ns + nm {
                for c in 0..3 {
                    let kk = NF * node + c;
                    let w = wc[c][kk];
                    let mut v = w * all[c];
                    if node >= ns {
                        let j = node - ns;
                        v += -f.dr(j, mdir) * a[l][c] - a[mdir][c] * f.dr(j, l)
                            + gap * m[c] * f.ddr(j, l, mdir);
                    }
                    e_lm[l][mdir][kk] = v;
                }
            }
        }
    }
    // S_mn = −θ_,mn + Σ_l λ_l T_lmn.
    let mut s = [[0.0; 2]; 2];
    for &mdir in free {
        for &ndir in free {
            let mut v = -theta_dd(mdir, ndir);
            for &l in free {
                let t = -dot(f.aa(mdir, ndir), a[l])
                    - dot(a[mdir], f.aa(l, ndir))
                    - dot(a[ndir], f.aa(l, mdir))
                    + gap * dot(m, f.aaa(l, mdir, ndir));
                v += lambda[l] * t;
            }
            s[mdir][ndir] = v;
        }
    }
    let ev: Vec<&Vec<f64>> = eta.iter().collect();
    for &mdir in free {
        jf.push((eta[mdir].clone(), combine(&s[mdir], &ev)));
        // Displacement–temperature: −R_j,i δη^i.
        jf.push((eta[mdir].clone(), rtheta[mdir].iter().map(|x| -x).collect()));
        jf.push((rtheta[mdir].iter().map(|x| -x).collect(), eta[mdir].clone()));
        // λ_l (E_lm(δ) δη^m(Δ) + E_lm(Δ) δη^m(δ)).
        let fm = combine(&[lambda[0], lambda[1]], &[&e_lm[0][mdir], &e_lm[1][mdir]]);
        jf.push((fm.clone(), eta[mdir].clone()));
        jf.push((eta[mdir].clone(), fm));
    }
    // λ_l X_l(δ, Δ) = λ_l Σ_c (W^c ⊗ A^{l,c} + A^{l,c} ⊗ W^c), A^{l,c} = R_j,l on (j, c).
    if !free.is_empty() {
        for (c, w) in wc.iter().enumerate() {
            let mut lam_a = vec![0.0; n];
            for j in 0..nm {
                lam_a[NF * (ns + j) + c] = free.iter().map(|&l| lambda[l] * f.dr(j, l)).sum();
            }
            jf.push((w.clone(), lam_a.clone()));
            jf.push((lam_a, w.clone()));
        }
    }
    let jump_d = Derivatives {
        value: jump_value,
        grad: jgrad,
        hess: Vec::new(),
        factors: jf,
    };
    (gap_d, jump_d)
}

// ---------------------------------------------------------------------------
// Forward-mode AD (clamped points).

/// Index of displacement component `k` (`3·node + c`) in the local unknowns.
fn u_index(k: usize) -> usize {
    NF * (k / 3) + k % 3
}

/// Gap and projection increments with first and second derivatives in the
/// displacements, by forward-mode AD.
fn displacement_ad(g: &SurfacePointGeometry, z: &[f64]) -> [(f64, Vec<f64>, Vec<f64>); 3] {
    let nu = 3 * z.len() / NF;
    let u = nalgebra::DVector::from_fn(nu, |k, _| z[u_index(k)]);
    let ((gv, gg, gh), (d0, d0g, d0h), (d1, d1g, d1h)) = num_dual::hessian(
        |x: nalgebra::DVector<num_dual::Dual2Vec<f64, nalgebra::Dyn>>| {
            let zz: Vec<_> = (0..z.len())
                .map(|i| match i % NF {
                    3 => num_dual::Dual2Vec::from_re(z[i]),
                    c => x[3 * (i / NF) + c].clone(),
                })
                .collect();
            let (gap, delta) = gap_and_delta(g, &zz);
            let [a, b] = delta;
            (gap, a, b)
        },
        &u,
    );
    let pack = |v: f64, gr: nalgebra::DVector<f64>, h: nalgebra::DMatrix<f64>| {
        (v, gr.as_slice().to_vec(), h.as_slice().to_vec())
    };
    [pack(gv, gg, gh), pack(d0, d0g, d0h), pack(d1, d1g, d1h)]
}

/// Scatters derivatives in the displacements to all local unknowns.
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
            d.hess[u_index(k) * n + u_index(l)] = hess[k * m + l];
        }
    }
    d
}

/// Derivatives at a clamped point by AD: the gap, and the jump from the
/// derivatives of `δ(u)` (`ϑc` is linear in the temperatures).
fn clamped(g: &SurfacePointGeometry, z: &[f64], needs: Needs) -> (Derivatives, Derivatives) {
    let n = z.len();
    let ns = g.slave_x.len();
    let nm = g.master_x.len();
    if matches!(needs, Needs::Values | Needs::Thermal) {
        return closed_form(g, z, needs);
    }
    let [gap, d0, d1] = displacement_ad(g, z);
    let gap_d = scatter(n, &gap);
    let f = Frame::new(g, z);
    let jump_value = f.theta_s - f.theta[0];
    if needs == Needs::Mechanical {
        return (
            gap_d,
            Derivatives {
                value: jump_value,
                ..Derivatives::default()
            },
        );
    }
    let theta_d = [f.theta[mi(1, 0)], f.theta[mi(0, 1)]];
    let theta_dd = |i: usize, l: usize| f.theta[mi(2 - i - l, i + l)];
    let deltas = [&d0, &d1];
    let mu = d0.1.len();
    let mut jump = Derivatives {
        value: jump_value,
        grad: vec![0.0; n],
        hess: vec![0.0; n * n],
        ..Derivatives::default()
    };
    for (a, &na) in g.slave_basis.iter().enumerate() {
        jump.grad[NF * a + 3] = na;
    }
    for j in 0..nm {
        jump.grad[NF * (ns + j) + 3] = -f.r[j][0];
    }
    for kk in 0..mu {
        let ik = u_index(kk);
        jump.grad[ik] = -(0..2).map(|i| theta_d[i] * deltas[i].1[kk]).sum::<f64>();
        for ll in 0..mu {
            let mut v = 0.0;
            for i in 0..2 {
                v -= theta_d[i] * deltas[i].2[kk * mu + ll];
                for l in 0..2 {
                    v -= theta_dd(i, l) * deltas[i].1[kk] * deltas[l].1[ll];
                }
            }
            jump.hess[ik * n + u_index(ll)] = v;
        }
        for j in 0..nm {
            let it = NF * (ns + j) + 3;
            let v = -(0..2).map(|i| f.dr(j, i) * deltas[i].1[kk]).sum::<f64>();
            jump.hess[ik * n + it] = v;
            jump.hess[it * n + ik] = v;
        }
    }
    (gap_d, jump)
}

/// Value, exact gradient and Hessian of gap and temperature jump at the
/// local state `z` (`(ux, uy, uz, θ)` per slave, then per master control
/// point), as far as `needs` asks, including the dependence of the projection
/// point and the master normal on the displacements (spec §6).
pub fn differentiate(
    g: &SurfacePointGeometry,
    z: &[f64],
    needs: Needs,
) -> (Derivatives, Derivatives) {
    if g.clamped {
        clamped(g, z, needs)
    } else {
        closed_form(g, z, needs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::projection3d::{MasterSearch, MasterSurface, project};
    use crate::contact::testing::rng;
    use crate::geometry::{KnotVector, NurbsPatch};

    /// A master face: degree `p`, `n × n` elements over `[0, 1]²`, heights
    /// `amplitude · (random)`, weights random in [0.8, 1.2] (rational) or 1.
    fn master(p: usize, n: usize, amplitude: f64, rational: bool) -> ThbPatch {
        let kv = KnotVector::open_uniform(p, n, 0.0, 1.0);
        let m = kv.n_basis();
        let g = kv.greville();
        let mut r = rng(17);
        let mut points = Vec::new();
        let mut weights = Vec::new();
        for j in 0..m {
            for i in 0..m {
                points.push([g[i], g[j], amplitude * (2.0 * r() - 1.0)]);
                weights.push(if rational { 0.8 + 0.4 * r() } else { 1.0 });
            }
        }
        ThbPatch::from(&NurbsPatch::new(vec![kv.clone(), kv], points, weights).unwrap())
    }

    /// A slave point: a biquadratic element's basis at a fixed parameter, its
    /// control points around `centre`.
    fn slave(centre: [f64; 3]) -> (Vec<f64>, Vec<[f64; 3]>) {
        let kv = KnotVector::open_uniform(2, 1, 0.0, 1.0);
        let (u, v) = (0.3, 0.6);
        let bu = crate::basis::basis_ders(&kv, 2, u, 0)[0].clone();
        let bv = crate::basis::basis_ders(&kv, 2, v, 0)[0].clone();
        let mut basis = Vec::new();
        let mut xs = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                basis.push(bu[i] * bv[j]);
                xs.push([
                    centre[0] + 0.1 * (i as f64 - u * 2.0),
                    centre[1] + 0.1 * (j as f64 - v * 2.0),
                    centre[2] + 0.01 * (i * j) as f64,
                ]);
            }
        }
        (basis, xs)
    }

    /// The kinematics of `(face, slave)` at the local state `z`: the master
    /// element and its control points from the projection of the current
    /// slave point (the projection converged anew, as in the contact layer).
    struct Setup {
        face: ThbPatch,
        basis: Vec<f64>,
        slave_x: Vec<[f64; 3]>,
        periods: [Option<f64>; 2],
    }

    impl Setup {
        /// Projection at state `z` (master unknowns: those of element `e`'s
        /// functions; the rest of the master stays put).
        fn geometry(
            &self,
            z: &[f64],
            element: usize,
        ) -> Option<(SurfacePointGeometry, SurfaceProjection)> {
            let ns = self.slave_x.len();
            let funcs = &self.face.elements()[element].functions;
            let mut cur: Vec<[f64; 3]> = self.face.control_points().to_vec();
            for (j, &f) in funcs.iter().enumerate() {
                for c in 0..3 {
                    cur[f][c] += z[NF * (ns + j) + c];
                }
            }
            let mut x = [0.0; 3];
            for (a, n) in self.basis.iter().enumerate() {
                for c in 0..3 {
                    x[c] += n * (self.slave_x[a][c] + z[NF * a + c]);
                }
            }
            let s = MasterSurface {
                face: &self.face,
                points: &cur,
                pieces: None,
            };
            let search = MasterSearch::new(&s, self.periods);
            let mut pr = project(&s, &search, x, None).ok()?;
            // On an element boundary (a C0 edge or vertex) any element holding
            // the point describes it: keep the one whose unknowns are perturbed.
            let (lo, hi) = s.bounds(element);
            if (0..2).all(|d| pr.eta[d] >= lo[d] && pr.eta[d] <= hi[d])
                && pr.fixed.iter().any(|&f| f)
            {
                pr.element = element;
            }
            let g = SurfacePointGeometry::new(
                &self.face,
                &pr,
                1.0,
                self.basis.clone(),
                self.slave_x.clone(),
            );
            (pr.element == element).then_some((g, pr))
        }
    }

    /// Dense full-AD reference of gap or jump in all local unknowns.
    fn full_ad(g: &SurfacePointGeometry, z: &[f64], gap: bool) -> Derivatives {
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

    fn assert_close(what: &str, a: &[f64], b: &[f64], tol: f64) {
        assert_eq!(a.len(), b.len(), "{what}");
        let scale = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (i, (x, y)) in a.iter().zip(b).enumerate() {
            assert!(
                (x - y).abs() <= tol * scale,
                "{what} [{i}]: {x} vs {y} (scale {scale})"
            );
        }
    }

    /// A random local state near zero displacement, temperatures ~ 1.
    fn state(n: usize, seed: u64, size: f64) -> Vec<f64> {
        let mut r = rng(seed);
        (0..n)
            .map(|i| {
                if i % NF == 3 {
                    1.0 + 0.2 * r()
                } else {
                    size * (2.0 * r() - 1.0)
                }
            })
            .collect()
    }

    /// The closed form against full AD, and AD against central differences
    /// of the re-projected kinematics.
    fn check(
        setup: &Setup,
        element: usize,
        z: &[f64],
        expect_fixed: [bool; 2],
        expect_clamped: bool,
    ) {
        let (g, pr) = setup
            .geometry(z, element)
            .expect("projects onto the element");
        assert_eq!(pr.fixed, expect_fixed, "{pr:?}");
        assert_eq!(pr.clamped, expect_clamped, "{pr:?}");
        let n = g.n_local();
        assert_eq!(n, z.len());
        let (gap, jump) = differentiate(&g, z, Needs::Coupled);
        let (rg, rj) = (full_ad(&g, z, true), full_ad(&g, z, false));
        assert!((gap.value - rg.value).abs() < 1e-14);
        assert!((jump.value - rj.value).abs() < 1e-14);
        assert_close("gap grad", &gap.grad, &rg.grad, 1e-12);
        assert_close("gap hess", &gap.dense_hessian(), &rg.hess, 1e-10);
        assert_close("jump grad", &jump.grad, &rj.grad, 1e-12);
        assert_close("jump hess", &jump.dense_hessian(), &rj.hess, 1e-10);
        // The mechanical and thermal phases give the same entries.
        let (gm, _) = differentiate(&g, z, Needs::Mechanical);
        assert_close("mech grad", &gm.grad, &rg.grad, 1e-12);
        assert_close("mech hess", &gm.dense_hessian(), &rg.hess, 1e-10);
        let (_, jt) = differentiate(&g, z, Needs::Thermal);
        for i in (3..n).step_by(NF) {
            assert!((jt.grad[i] - rj.grad[i]).abs() < 1e-14);
        }
        // Central differences of the values with the projection converged anew.
        let h = 1e-6;
        let eval = |zz: &[f64]| {
            let (gg, _) = setup.geometry(zz, element).expect("perturbed projection");
            (normal_gap(&gg, zz), temperature_jump(&gg, zz))
        };
        for i in 0..n {
            let (mut zp, mut zm) = (z.to_vec(), z.to_vec());
            zp[i] += h;
            zm[i] -= h;
            let (fp, fm) = (eval(&zp), eval(&zm));
            let fd = [(fp.0 - fm.0) / (2.0 * h), (fp.1 - fm.1) / (2.0 * h)];
            assert!(
                (fd[0] - gap.grad[i]).abs() < 1e-7,
                "gap grad {i}: {} vs {}",
                fd[0],
                gap.grad[i]
            );
            assert!(
                (fd[1] - jump.grad[i]).abs() < 1e-7,
                "jump grad {i}: {} vs {}",
                fd[1],
                jump.grad[i]
            );
            // Hessian column i: differences of the exact gradients.
            let (gp, _) = setup.geometry(&zp, element).unwrap();
            let (gm, _) = setup.geometry(&zm, element).unwrap();
            let (ap, bp) = differentiate(&gp, &zp, Needs::Coupled);
            let (am, bm) = differentiate(&gm, &zm, Needs::Coupled);
            let (hg, hj) = (gap.dense_hessian(), jump.dense_hessian());
            for j in 0..n {
                let d2 = [
                    (ap.grad[j] - am.grad[j]) / (2.0 * h),
                    (bp.grad[j] - bm.grad[j]) / (2.0 * h),
                ];
                assert!(
                    (d2[0] - hg[i * n + j]).abs() < 2e-6 * (1.0 + hg[i * n + j].abs()),
                    "gap hess ({i},{j}): {} vs {}",
                    d2[0],
                    hg[i * n + j]
                );
                assert!(
                    (d2[1] - hj[i * n + j]).abs() < 2e-6 * (1.0 + hj[i * n + j].abs()),
                    "jump hess ({i},{j}): {} vs {}",
                    d2[1],
                    hj[i * n + j]
                );
            }
        }
    }

    #[test]
    fn derivatives_at_regular_points_match_ad_and_finite_differences() {
        // A curved rational biquadratic master, the slave point above and below it.
        for (centre, seed) in [([0.45, 0.55, 0.12], 1), ([0.6, 0.4, -0.08], 2)] {
            let (basis, slave_x) = slave(centre);
            let setup = Setup {
                face: master(2, 2, 0.1, true),
                basis,
                slave_x,
                periods: [None, None],
            };
            let z0 = vec![0.0; NF * 18];
            let (_, pr) = (0..4)
                .find_map(|e| setup.geometry(&z0, e))
                .expect("some element");
            let z = state(NF * 18, seed, 0.01);
            check(&setup, pr.element, &z, [false, false], false);
        }
    }

    /// A degree-1 master with kinks (C0 edges): the tent of
    /// [`crate::contact::projection3d`]'s tests, scaled to `[0, 1]²`.
    fn tent() -> ThbPatch {
        let kv = KnotVector::new(1, vec![0.0, 0.0, 0.5, 1.0, 1.0]).unwrap();
        let mut points = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                let z = if i == 1 && j == 1 { 0.5 } else { 0.0 };
                points.push([0.5 * i as f64, 0.5 * j as f64, z]);
            }
        }
        ThbPatch::from(&NurbsPatch::new(vec![kv.clone(), kv], points, vec![1.0; 9]).unwrap())
    }

    #[test]
    fn derivatives_at_edges_vertices_and_clamped_points_match_ad_and_finite_differences() {
        let face = tent();
        // Above the kink x = 0.5 (edge), above the apex (vertex), beyond the rim (clamped).
        let cases = [
            ([0.5, 0.15, 0.45], [true, false], false),
            ([0.5, 0.5, 0.9], [true, true], false),
            ([1.15, 0.3, 0.1], [true, false], true),
        ];
        for (centre, fixed, clamped) in cases {
            let (basis, slave_x) = slave(centre);
            let setup = Setup {
                face: face.clone(),
                basis,
                slave_x,
                periods: [None, None],
            };
            let z0 = vec![0.0; NF * 13];
            let (_, pr) = (0..4)
                .find_map(|e| setup.geometry(&z0, e))
                .expect("some element");
            let z = state(NF * 13, 5, 0.003);
            check(&setup, pr.element, &z, fixed, clamped);
        }
    }
}
