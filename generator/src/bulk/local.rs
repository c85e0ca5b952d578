//! Element residuals and consistent tangents of quasi-static finite
//! thermoelasticity (paper Appendix A, Eq. (A.1): `Div P = 0`, `Div q0 = 0`),
//! total Lagrangian, in the coupled form and in the two decoupled forms of the
//! two-phase framework (paper Sect. 3.1).
//!
//! Residual convention (internal minus external), with `R` the rows and `N_a`
//! the basis functions:
//! ```text
//! R_u[a,i] =  ∫ P_iJ N_a,J dV − ∫ N_a B_i dV
//! R_θ[a]   = −∫ q0_J N_a,J dV − ∫ N_a R dV
//! ```
//! where `B` and `R` are body sources (zero in the physics; used by the
//! manufactured-solution verification). Boundary tractions and fluxes enter as
//! external vectors assembled elsewhere. Plane strain in 2D (`F33 = 1`).

use nalgebra::{Matrix3, Vector3};

use crate::geometry::ElementQuadrature;
use crate::material::Material;

/// Which fields are unknown in a bulk element.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coupling {
    /// Displacements and temperature, monolithic.
    Coupled,
    /// Displacements only; the temperature is a given field (the mechanical phase).
    Mechanical,
    /// Temperature only, on a given (frozen) deformation (the thermal phase).
    Thermal,
}

impl Coupling {
    /// Local unknowns per control point for spatial dimension `dim`.
    pub fn fields_per_node(self, dim: usize) -> usize {
        match self {
            Coupling::Coupled => dim + 1,
            Coupling::Mechanical => dim,
            Coupling::Thermal => 1,
        }
    }
}

/// Body force `B` and heat source `R` at a point, both per reference volume.
pub type Sources<'a> = &'a (dyn Fn(&[f64; 3]) -> (Vector3<f64>, f64) + Sync);

/// The element's nodal values: displacements (`[f64; 3]`, third 0 in 2D) and
/// temperatures, one per control point in the order of the element connectivity.
pub struct ElementFields<'a> {
    /// Nodal displacements.
    pub u: &'a [[f64; 3]],
    /// Nodal temperatures.
    pub theta: &'a [f64],
}

/// Deformation gradient `F = I + Grad u` at a quadrature point (`F33 = 1` in 2D).
#[inline]
pub fn deformation_gradient(dim: usize, u: &[[f64; 3]], dn: &[[f64; 3]]) -> Matrix3<f64> {
    let mut f = Matrix3::identity();
    for (ua, ga) in u.iter().zip(dn) {
        for i in 0..dim {
            for j in 0..dim {
                f[(i, j)] += ua[i] * ga[j];
            }
        }
    }
    f
}

/// Adds the element residual `r` and, when given, the tangent `k` (dense,
/// column-major, `n × n` with `n = n_cp · fields_per_node`) of one element.
/// Local unknowns are node-major: `a · nf + c`, displacement components first.
#[allow(clippy::too_many_arguments)]
pub fn element_residual_tangent(
    material: &Material,
    quad: &ElementQuadrature,
    dim: usize,
    coupling: Coupling,
    fields: &ElementFields<'_>,
    sources: Option<Sources<'_>>,
    k: Option<&mut [f64]>,
    r: &mut [f64],
) {
    let input = KernelInput {
        material,
        quad,
        coupling,
        fields,
        sources,
    };
    // The dimension as a constant: fixed loop bounds the compiler unrolls.
    match dim {
        2 => residual_tangent_widest::<2>(&input, k, r),
        3 => residual_tangent_widest::<3>(&input, k, r),
        _ => panic!("spatial dimension {dim} is not 2 or 3"),
    }
}

/// The kernel compiled for the widest vector instructions the CPU has (AVX-512F, else AVX2,
/// else the crate's baseline x86-64 or other target), chosen at run time: the crate is built
/// for the baseline target so that one binary runs everywhere. The code is the same and Rust
/// does not fuse `a * b + c` into FMAs, so every target gives the same bits (test
/// `element_tangent_3d_matches_finite_differences_and_the_baseline_kernel`). The 3D
/// mechanical block's product over the points ([`MechanicalProduct`]) is faer's, whose
/// kernels faer chooses at run time (as for the factorizations): the same for every target
/// on one CPU, possibly other last bits on another. A 3D p = 2
/// mechanical element with 27 points: 59 against 71 µs (thermal 15 against 30 µs, also by
/// its column-wise update; AMD EPYC, docs/3d.md "Stop 46").
fn residual_tangent_widest<const D: usize>(
    input: &KernelInput<'_, '_>,
    k: Option<&mut [f64]>,
    r: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has AVX-512F (checked above).
            unsafe { avx512::residual_tangent::<D>(input, k, r) };
            return;
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked above).
            unsafe { avx2::residual_tangent::<D>(input, k, r) };
            return;
        }
    }
    residual_tangent::<D>(input, k, r)
}

/// A module with [`residual_tangent`] compiled for the target feature `$feature`.
macro_rules! kernel_with_feature {
    ($module:ident, $feature:literal) => {
        #[cfg(target_arch = "x86_64")]
        mod $module {
            use super::*;

            /// [`super::residual_tangent`] with the target feature of this module.
            ///
            /// # Safety
            /// The CPU must have the feature.
            #[target_feature(enable = $feature)]
            pub(super) unsafe fn residual_tangent<const D: usize>(
                input: &KernelInput<'_, '_>,
                k: Option<&mut [f64]>,
                r: &mut [f64],
            ) {
                super::residual_tangent::<D>(input, k, r)
            }
        }
    };
}
kernel_with_feature!(avx512, "avx512f");
kernel_with_feature!(avx2, "avx2");

/// What an element's kernel reads ([`element_residual_tangent`]'s arguments).
#[derive(Clone, Copy)]
struct KernelInput<'a, 'b> {
    material: &'a Material,
    quad: &'a ElementQuadrature,
    coupling: Coupling,
    fields: &'a ElementFields<'b>,
    sources: Option<Sources<'a>>,
}

#[inline(always)]
fn residual_tangent<const D: usize>(
    input: &KernelInput<'_, '_>,
    mut k: Option<&mut [f64]>,
    r: &mut [f64],
) {
    let KernelInput {
        material,
        quad,
        coupling,
        fields,
        sources,
    } = *input;
    let nf = coupling.fields_per_node(D);
    let ncp = quad.conn.len();
    let n = ncp * nf;
    debug_assert_eq!(r.len(), n);
    let t_off = match coupling {
        Coupling::Coupled => D,
        Coupling::Thermal => 0,
        Coupling::Mechanical => usize::MAX,
    };
    let has_u = coupling != Coupling::Thermal;
    let has_t = coupling != Coupling::Mechanical;
    // Per quadrature point, columns of the tangent's factors (rows of the
    // element block; zero in the rows of other fields).
    let with_k = k.is_some();
    // The mechanical tangent is symmetric (hyperelastic, `∂P/∂F` has major
    // symmetry): assemble the blocks above the diagonal and mirror them (in
    // 3D as products over the points, [`MechanicalProduct`]).
    let symmetric = coupling == Coupling::Mechanical;
    let product = with_k && symmetric && D == 3;
    let mut gcols = vec![
        0.0;
        if with_k && has_u && !product {
            D * D * n
        } else {
            0
        }
    ];
    let mut gth = vec![0.0; if with_k && has_u && has_t { n } else { 0 }];
    // Per quadrature point, the thermal rows' factors by columns: −Σ_J N_a,J ∂q_J/∂θ, then
    // −Σ_J N_a,J ∂q_J/∂(∇θ)_L for each L.
    let mut tth = vec![0.0; if with_k && has_t { (1 + D) * ncp } else { 0 }];
    let before: Vec<f64> = match k.as_deref() {
        Some(k) if symmetric && !product => k.to_vec(),
        _ => Vec::new(),
    };
    let mut scratch = Vec::new();
    let nq = quad.points.len();
    // Kept per thread between elements (taken here, put back at the end).
    let mut mp = if product {
        let mut mp = MECHANICAL_PRODUCT.with_borrow_mut(std::mem::take);
        mp.reset(n, ncp, nq);
        mp
    } else {
        MechanicalProduct::default()
    };
    for (q, (qp, nn, dn)) in quad.points_with_basis(&mut scratch).enumerate() {
        let w = qp.weight;
        let f = deformation_gradient(D, fields.u, dn);
        let mut theta = 0.0;
        let mut grad = Vector3::zeros();
        for a in 0..ncp {
            theta += nn[a] * fields.theta[a];
            for j in 0..D {
                grad[j] += fields.theta[a] * dn[a][j];
            }
        }
        let (b, rsrc) = match sources {
            Some(s) => s(&qp.x),
            None => (Vector3::zeros(), 0.0),
        };
        if has_u {
            let st = material.stress_tangent_in(&f, theta, D);
            for a in 0..ncp {
                for i in 0..D {
                    let mut v = 0.0;
                    for j in 0..D {
                        v += st.p[(i, j)] * dn[a][j];
                    }
                    r[a * nf + i] += w * (v - nn[a] * b[i]);
                }
            }
            if let Some(k) = k.as_deref_mut() {
                // gcols[kk][l] = Σ_J N_a,J ∂P_iJ/∂F_kL in rows (a, i) of the
                // block; column (b, kk) gets Σ_L N_b,L gcols[kk][L], a
                // contiguous update (the thermal rows of gcols stay zero).
                // ∂P/∂F by rows (i, J), the columns (k, L) of a row contiguous.
                let a_rows: [[f64; 9]; 9] =
                    std::array::from_fn(|rr| std::array::from_fn(|cc| st.dp_df[(rr, cc)]));
                for a in 0..ncp {
                    for i in 0..D {
                        let row = a * nf + i;
                        // The sums over J in order, for all (k, L) at once.
                        let mut s = [0.0; 9];
                        for j in 0..D {
                            let (x, ar) = (dn[a][j], &a_rows[3 * i + j]);
                            for kk in 0..D {
                                for l in 0..D {
                                    s[3 * kk + l] += x * ar[3 * kk + l];
                                }
                            }
                        }
                        if product {
                            mp.set_factor(q, row, &s);
                        } else {
                            for kk in 0..D {
                                for l in 0..D {
                                    gcols[(kk * D + l) * n + row] = s[3 * kk + l];
                                }
                            }
                        }
                        if has_t {
                            let mut s = 0.0;
                            for j in 0..D {
                                s += dn[a][j] * st.dp_dtheta[(i, j)];
                            }
                            gth[row] = s;
                        }
                    }
                }
                if product {
                    mp.set_gradients(q, w, dn);
                }
                for bb in (0..ncp).filter(|_| !product) {
                    // Symmetric: the blocks a ≤ b only (mirrored below).
                    let rows = if symmetric { (bb + 1) * nf } else { n };
                    for kk in 0..D {
                        let c0 = n * (bb * nf + kk);
                        let col = &mut k[c0..c0 + rows];
                        // The D terms of the column in one pass over it.
                        let c: [f64; D] = std::array::from_fn(|l| w * dn[bb][l]);
                        let g = &gcols[kk * D * n..(kk + 1) * D * n];
                        add_column::<D>(col, &c, g, n);
                    }
                    if has_t {
                        let c0 = n * (bb * nf + t_off);
                        let c = w * nn[bb];
                        for (x, y) in k[c0..c0 + n].iter_mut().zip(&gth) {
                            *x += c * y;
                        }
                    }
                }
            }
        }
        if has_t {
            let ht = material.heat_flux_tangent(&f, theta, &grad);
            for a in 0..ncp {
                let mut v = 0.0;
                for j in 0..D {
                    v += ht.q[j] * dn[a][j];
                }
                r[a * nf + t_off] += w * (-v - nn[a] * rsrc);
            }
            if let Some(k) = k.as_deref_mut() {
                // Per row a: −Σ_J N_a,J dq_J/d(·), by columns of a's.
                let dq_dgrad: [[f64; 3]; 3] =
                    std::array::from_fn(|j| std::array::from_fn(|l| ht.dq_dgrad[(j, l)]));
                tth.iter_mut().for_each(|v| *v = 0.0);
                for a in 0..ncp {
                    for j in 0..D {
                        tth[a] -= dn[a][j] * ht.dq_dtheta[j];
                        for l in 0..D {
                            tth[(1 + l) * ncp + a] -= dn[a][j] * dq_dgrad[j][l];
                        }
                    }
                }
                // Column (b, θ): the rows a in one pass (contiguous for the thermal phase).
                let (dth, dg) = tth.split_at(ncp);
                for bb in 0..ncp {
                    let c0 = n * (bb * nf + t_off) + t_off;
                    let c = [nn[bb], dn[bb][0], dn[bb][1], dn[bb][2]];
                    if nf == 1 {
                        thermal_column::<D>(&mut k[c0..c0 + ncp], w, &c, dth, dg);
                    } else {
                        for a in 0..ncp {
                            let mut s = dth[a] * c[0];
                            for l in 0..D {
                                s += dg[l * ncp + a] * c[1 + l];
                            }
                            k[c0 + a * nf] += w * s;
                        }
                    }
                }
                if has_u {
                    for a in 0..ncp {
                        let row = a * nf + t_off;
                        let mut df = [[0.0; 3]; 3];
                        for j in 0..D {
                            for (kk, dfk) in df.iter_mut().enumerate().take(D) {
                                for (l, dfkl) in dfk.iter_mut().enumerate().take(D) {
                                    *dfkl -= dn[a][j] * ht.dq_df[(j, 3 * kk + l)];
                                }
                            }
                        }
                        for bb in 0..ncp {
                            for (kk, dfk) in df.iter().enumerate().take(D) {
                                let mut s = 0.0;
                                for l in 0..D {
                                    s += dfk[l] * dn[bb][l];
                                }
                                k[row + n * (bb * nf + kk)] += w * s;
                            }
                        }
                    }
                }
            }
        }
    }
    if product {
        if let Some(k) = k.as_deref_mut() {
            mp.add_to(k);
        }
        MECHANICAL_PRODUCT.with_borrow_mut(|kept| *kept = mp);
    }
    if let Some(k) = k
        && symmetric
        && !product
    {
        for bb in 0..ncp {
            for a in 0..bb {
                for kk in 0..D {
                    for i in 0..D {
                        let (row, col) = (a * nf + i, bb * nf + kk);
                        k[col + n * row] += k[row + n * col] - before[row + n * col];
                    }
                }
            }
        }
    }
}

/// The 3D mechanical element tangent as a matrix product over the quadrature
/// points: column `(b, k)` of the block is `Σ_(q, L) G_q[·, (k, L)] w_q N_b,L(x_q)`
/// with `G_q[(a, i), (k, L)] = Σ_J N_a,J ∂P_iJ/∂F_kL` at point `q`, so the three
/// column classes `k` are three products `(n × 3 n_q) (3 n_q × n_cp)` summed at
/// once (faer's matrix product, with FMAs), instead of `n_q` rank-3 updates of
/// the block's upper triangle each read and written through the cache. The
/// products run by chunks of columns down to the chunk's last node (about
/// two thirds of the whole block's multiplications), and the upper part is
/// mirrored ([`Self::add_to`]); test
/// `element_tangent_3d_matches_finite_differences_and_the_baseline_kernel`.
/// The buffers are kept per thread between elements.
#[derive(Default)]
struct MechanicalProduct {
    /// `G` for `k = 0, 1, 2`: each `n × 3 n_q`, column-major, column `3q + L`.
    factors: Vec<f64>,
    /// `3 n_q × n_cp`, column-major: row `3q + L`, column `b`, `w_q N_b,L`.
    gradients: Vec<f64>,
    /// The block's products (`n × n`, column-major; the entries at and above
    /// the nodes' diagonal blocks are written before they are read).
    block: Vec<f64>,
    n: usize,
    ncp: usize,
    nq: usize,
}

impl MechanicalProduct {
    /// Sizes the buffers for an element of `n` unknowns, `ncp` functions and
    /// `nq` points (every entry is written before the product reads it).
    fn reset(&mut self, n: usize, ncp: usize, nq: usize) {
        (self.n, self.ncp, self.nq) = (n, ncp, nq);
        self.factors.resize(3 * n * 3 * nq, 0.0);
        self.gradients.resize(3 * nq * ncp, 0.0);
    }

    /// Row `row` of point `q`'s `G` (`s[3k + L]`).
    #[inline(always)]
    fn set_factor(&mut self, q: usize, row: usize, s: &[f64; 9]) {
        let (n, nq) = (self.n, self.nq);
        for k in 0..3 {
            let g = &mut self.factors[k * n * 3 * nq..(k + 1) * n * 3 * nq];
            for l in 0..3 {
                g[(3 * q + l) * n + row] = s[3 * k + l];
            }
        }
    }

    /// Point `q`'s weighted gradients `w N_b,L`.
    #[inline(always)]
    fn set_gradients(&mut self, q: usize, w: f64, dn: &[[f64; 3]]) {
        let m = 3 * self.nq;
        for (b, d) in dn.iter().enumerate().take(self.ncp) {
            for l in 0..3 {
                self.gradients[b * m + 3 * q + l] = w * d[l];
            }
        }
    }

    /// Adds the block to `k` (`n × n`, column-major, columns `(b, k)` with
    /// three fields per node): the columns of node `b` down to node `b`'s rows
    /// (the products over chunks of [`PRODUCT_CHUNK_NODES`] columns' nodes,
    /// each down to its last node's rows), then the upper part mirrored, so
    /// that the block is symmetric to the bit off its nodes' diagonal blocks,
    /// as the rank-3 updates made it. With both triangles from the products
    /// (equal only to rounding) the 3D Hertz radius differed in its last bits
    /// between one thread and two (test
    /// `the_3d_area_is_the_same_on_any_number_of_threads`).
    fn add_to(&mut self, k: &mut [f64]) {
        use faer::{Accum, MatMut, MatRef, Par};
        let (n, ncp, m) = (self.n, self.ncp, 3 * self.nq);
        self.block.resize(n * n, 0.0);
        let block = &mut self.block;
        for b0 in (0..ncp).step_by(PRODUCT_CHUNK_NODES) {
            let b1 = (b0 + PRODUCT_CHUNK_NODES).min(ncp);
            let rows = 3 * b1;
            let rhs = MatRef::from_column_major_slice(&self.gradients[b0 * m..b1 * m], m, b1 - b0);
            for kk in 0..3 {
                let g = &self.factors[kk * n * m..(kk + 1) * n * m];
                let lhs = MatRef::from_column_major_slice_with_stride(g, rows, m, n);
                let dst = MatMut::from_column_major_slice_with_stride_mut(
                    &mut block[(3 * b0 + kk) * n..],
                    rows,
                    b1 - b0,
                    3 * n,
                );
                faer::linalg::matmul::matmul(dst, Accum::Replace, lhs, rhs, 1.0, Par::Seq);
            }
        }
        for b in 0..ncp {
            for kk in 0..3 {
                let col = 3 * b + kk;
                for row in 0..3 * (b + 1) {
                    let v = block[row + n * col];
                    k[row + n * col] += v;
                    if row < 3 * b {
                        k[col + n * row] += v;
                    }
                }
            }
        }
    }
}

/// Nodes per chunk of columns in [`MechanicalProduct::add_to`]: a chunk's
/// product runs down to its last node's rows, so smaller chunks compute less
/// of the block below its diagonal, in more calls.
const PRODUCT_CHUNK_NODES: usize = 8;

thread_local! {
    /// The buffers of [`MechanicalProduct`], one per thread.
    static MECHANICAL_PRODUCT: std::cell::RefCell<MechanicalProduct> =
        std::cell::RefCell::new(MechanicalProduct::default());
}

/// `col[a] += w (c[0] · dth[a] + Σ_l c[1 + l] · dg[l·ncp + a])` over the rows of `col`
/// (`ncp`), the terms summed in that order; written with equal-length chunks so that the
/// compiler sees no bounds to check and vectorizes the rows.
#[inline(always)]
fn thermal_column<const D: usize>(col: &mut [f64], w: f64, c: &[f64; 4], dth: &[f64], dg: &[f64]) {
    let m = col.len();
    let dth = &dth[..m];
    match D {
        2 => {
            let (g0, g1) = (&dg[..m], &dg[m..2 * m]);
            for (((x, t), a), b) in col.iter_mut().zip(dth).zip(g0).zip(g1) {
                *x += w * (t * c[0] + a * c[1] + b * c[2]);
            }
        }
        3 => {
            let (g0, g1, g2) = (&dg[..m], &dg[m..2 * m], &dg[2 * m..3 * m]);
            for ((((x, t), a), b), d) in col.iter_mut().zip(dth).zip(g0).zip(g1).zip(g2) {
                *x += w * (t * c[0] + a * c[1] + b * c[2] + d * c[3]);
            }
        }
        _ => unreachable!("spatial dimension {D}"),
    }
}

/// `col[r] += Σ_l c[l] · g[l·n + r]` over the rows of `col`, the `D` terms summed in order
/// (the same rounding as a loop over `l`); written with equal-length chunks so that the
/// compiler sees no bounds to check and vectorizes the rows.
#[inline(always)]
fn add_column<const D: usize>(col: &mut [f64], c: &[f64; D], g: &[f64], n: usize) {
    let rows = col.len();
    match D {
        2 => {
            let (g0, g1) = (&g[..rows], &g[n..n + rows]);
            for ((x, a), b) in col.iter_mut().zip(g0).zip(g1) {
                *x += c[0] * a + c[1] * b;
            }
        }
        3 => {
            let (g0, g1, g2) = (&g[..rows], &g[n..n + rows], &g[2 * n..2 * n + rows]);
            for (((x, a), b), d) in col.iter_mut().zip(g0).zip(g1).zip(g2) {
                *x += c[0] * a + c[1] * b + c[2] * d;
            }
        }
        _ => unreachable!("spatial dimension {D}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{NurbsPatch, shapes};

    fn patch() -> NurbsPatch {
        let p = shapes::quarter_annulus(1.0, 2.0);
        let p = p.elevate_degree(1, 1);
        p.refine_uniform(0, 2)
    }

    /// Checks the element tangent `k` (`n × n`, `nf` fields per node, the temperature the
    /// field `dim`) against central differences of the residual `eval` at (`u`, `th`).
    fn assert_tangent_matches_differences(
        coupling: Coupling,
        dim: usize,
        k: &[f64],
        u: &mut [[f64; 3]],
        th: &mut [f64],
        eval: impl Fn(&[[f64; 3]], &[f64]) -> Vec<f64>,
    ) {
        let nf = coupling.fields_per_node(dim);
        let n = th.len() * nf;
        let h = 1e-6;
        let (mut max_err, mut max_k): (f64, f64) = (0.0, 0.0);
        for col in 0..n {
            let (a, c) = (col / nf, col % nf);
            let is_t = coupling == Coupling::Thermal || (coupling == Coupling::Coupled && c == dim);
            let bump = |u: &mut [[f64; 3]], th: &mut [f64], d: f64| {
                if is_t { th[a] += d } else { u[a][c] += d }
            };
            bump(u, th, h);
            let rp = eval(u, th);
            bump(u, th, -2.0 * h);
            let rm = eval(u, th);
            bump(u, th, h);
            for row in 0..n {
                let fd = (rp[row] - rm[row]) / (2.0 * h);
                max_err = max_err.max((fd - k[row + n * col]).abs());
                max_k = max_k.max(k[row + n * col].abs());
            }
        }
        assert!(
            max_err < 1e-6 * max_k,
            "{coupling:?}: tangent error {max_err:e} vs {max_k:e}"
        );
    }

    /// The element tangent equals central finite differences of the residual,
    /// for every coupling, at a finite-strain, non-uniform-temperature state.
    #[test]
    fn element_tangent_matches_finite_differences() {
        let mut m = Material::default().scaled(1.0e6, 293.15, 1.0);
        m.thermal_expansion *= 1000.0; // make the coupling visible
        let p = patch();
        let el = &p.elements()[1];
        let q = p.element_quadrature(el, &[4, 4]);
        let ncp = q.conn.len();
        let mut u: Vec<[f64; 3]> = (0..ncp)
            .map(|a| {
                let x = p.control_points()[q.conn[a]];
                [0.1 * (x[1] * 1.3).sin(), -0.08 * (x[0] * 0.7).cos(), 0.0]
            })
            .collect();
        let mut th: Vec<f64> = (0..ncp)
            .map(|a| 1.0 + 0.05 * (p.control_points()[q.conn[a]][0] - 1.2))
            .collect();
        let src = |x: &[f64; 3]| (Vector3::new(x[0], 0.5, 0.0), 0.3 * x[1]);
        for coupling in [Coupling::Coupled, Coupling::Mechanical, Coupling::Thermal] {
            let nf = coupling.fields_per_node(2);
            let n = ncp * nf;
            let eval = |u: &[[f64; 3]], th: &[f64], k: Option<&mut [f64]>| {
                let mut r = vec![0.0; n];
                let fields = ElementFields { u, theta: th };
                element_residual_tangent(&m, &q, 2, coupling, &fields, Some(&src), k, &mut r);
                r
            };
            let mut k = vec![0.0; n * n];
            eval(&u, &th, Some(&mut k));
            assert_tangent_matches_differences(coupling, 2, &k, &mut u, &mut th, |u, th| {
                eval(u, th, None)
            });
        }
    }

    /// In 3D (p = 2 element of a cube, 27 Gauss points) the element tangent equals central
    /// finite differences of the residual for every coupling, and the kernel the CPU's
    /// instruction set selects (`residual_tangent_widest`: AVX-512 or AVX2 where present) gives
    /// the same bits as the baseline one, residual and tangent.
    #[test]
    fn element_tangent_3d_matches_finite_differences_and_the_baseline_kernel() {
        let mut m = Material::default().scaled(1.0e6, 293.15, 1.0);
        m.thermal_expansion *= 1000.0;
        let mut p = shapes::cuboid([0.0; 3], [1.0, 1.2, 0.8]);
        for d in 0..3 {
            p = p.elevate_degree(d, 1).refine_uniform(d, 1);
        }
        let el = &p.elements()[0];
        let q = p.element_quadrature(el, &[3, 3, 3]);
        let ncp = q.conn.len();
        let x = |a: usize| p.control_points()[q.conn[a]];
        let mut u: Vec<[f64; 3]> = (0..ncp)
            .map(|a| {
                let x = x(a);
                [
                    0.05 * (x[1] * 1.3).sin(),
                    -0.04 * (x[0] * 0.7).cos(),
                    0.03 * x[0] * x[2],
                ]
            })
            .collect();
        let mut th: Vec<f64> = (0..ncp).map(|a| 1.0 + 0.05 * (x(a)[0] - x(a)[2])).collect();
        // The coupled tangent's displacement block, which the coupled kernel
        // computes entry by entry (all rows of every column): the mechanical
        // tangent (products over the points, `MechanicalProduct`) equals it
        // to rounding.
        let mut coupled_uu = Vec::new();
        for coupling in [Coupling::Coupled, Coupling::Mechanical, Coupling::Thermal] {
            let nf = coupling.fields_per_node(3);
            let n = ncp * nf;
            let eval = |u: &[[f64; 3]], th: &[f64], k: Option<&mut [f64]>| {
                let mut r = vec![0.0; n];
                let fields = ElementFields { u, theta: th };
                element_residual_tangent(&m, &q, 3, coupling, &fields, None, k, &mut r);
                r
            };
            let mut k = vec![0.0; n * n];
            let r = eval(&u, &th, Some(&mut k));
            // The baseline kernel, compiled for the crate's target only.
            let (mut k0, mut r0) = (vec![0.0; n * n], vec![0.0; n]);
            let fields = ElementFields { u: &u, theta: &th };
            let input = KernelInput {
                material: &m,
                quad: &q,
                coupling,
                fields: &fields,
                sources: None,
            };
            residual_tangent::<3>(&input, Some(&mut k0), &mut r0);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&k), bits(&k0), "{coupling:?}: tangent bits");
            assert_eq!(bits(&r), bits(&r0), "{coupling:?}: residual bits");
            let uu = |k: &[f64], nf: usize| -> Vec<f64> {
                let idx = |a: usize, i: usize| a * nf + i;
                let mut out = Vec::new();
                for (b, kk) in (0..ncp).flat_map(|b| (0..3).map(move |kk| (b, kk))) {
                    for (a, i) in (0..ncp).flat_map(|a| (0..3).map(move |i| (a, i))) {
                        out.push(k[idx(a, i) + ncp * nf * idx(b, kk)]);
                    }
                }
                out
            };
            match coupling {
                Coupling::Coupled => coupled_uu = uu(&k, nf),
                Coupling::Mechanical => {
                    let scale = coupled_uu.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                    for (x, y) in uu(&k, nf).iter().zip(&coupled_uu) {
                        assert!((x - y).abs() <= 1e-13 * scale, "{x} against {y}");
                    }
                }
                Coupling::Thermal => {}
            }
            assert_tangent_matches_differences(coupling, 3, &k, &mut u, &mut th, |u, th| {
                eval(u, th, None)
            });
        }
    }
}
