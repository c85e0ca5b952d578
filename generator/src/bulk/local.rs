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
    // The dimension as a constant: fixed loop bounds the compiler unrolls.
    match dim {
        2 => residual_tangent::<2>(material, quad, coupling, fields, sources, k, r),
        3 => residual_tangent::<3>(material, quad, coupling, fields, sources, k, r),
        _ => panic!("spatial dimension {dim} is not 2 or 3"),
    }
}

#[allow(clippy::too_many_arguments)]
fn residual_tangent<const D: usize>(
    material: &Material,
    quad: &ElementQuadrature,
    coupling: Coupling,
    fields: &ElementFields<'_>,
    sources: Option<Sources<'_>>,
    mut k: Option<&mut [f64]>,
    r: &mut [f64],
) {
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
    let mut gcols = vec![0.0; if with_k && has_u { D * D * n } else { 0 }];
    let mut gth = vec![0.0; if with_k && has_u && has_t { n } else { 0 }];
    // The mechanical tangent is symmetric (hyperelastic, `∂P/∂F` has major
    // symmetry): assemble the blocks above the diagonal and mirror them.
    let symmetric = coupling == Coupling::Mechanical;
    let before: Vec<f64> = match k.as_deref() {
        Some(k) if symmetric => k.to_vec(),
        _ => Vec::new(),
    };
    for qp in &quad.points {
        let w = qp.weight;
        let dn = &qp.dr_dx;
        let nn = &qp.r;
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
                for a in 0..ncp {
                    for i in 0..D {
                        let row = a * nf + i;
                        for kk in 0..D {
                            for l in 0..D {
                                let mut s = 0.0;
                                for j in 0..D {
                                    s += dn[a][j] * st.dp_df[(3 * i + j, 3 * kk + l)];
                                }
                                gcols[(kk * D + l) * n + row] = s;
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
                for bb in 0..ncp {
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
                for a in 0..ncp {
                    let row = a * nf + t_off;
                    // −Σ_J N_a,J dq_J/d(·)
                    let mut dth = 0.0;
                    let mut dg = [0.0; 3];
                    let mut df = [[0.0; 3]; 3];
                    for j in 0..D {
                        dth -= dn[a][j] * ht.dq_dtheta[j];
                        for l in 0..D {
                            dg[l] -= dn[a][j] * ht.dq_dgrad[(j, l)];
                        }
                        if has_u {
                            for (kk, dfk) in df.iter_mut().enumerate().take(D) {
                                for (l, dfkl) in dfk.iter_mut().enumerate().take(D) {
                                    *dfkl -= dn[a][j] * ht.dq_df[(j, 3 * kk + l)];
                                }
                            }
                        }
                    }
                    for bb in 0..ncp {
                        let mut s = dth * nn[bb];
                        for l in 0..D {
                            s += dg[l] * dn[bb][l];
                        }
                        k[row + n * (bb * nf + t_off)] += w * s;
                        if has_u {
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
    if let Some(k) = k
        && symmetric
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
            let h = 1e-6;
            let mut max_err: f64 = 0.0;
            let mut max_k: f64 = 0.0;
            for col in 0..n {
                let (a, c) = (col / nf, col % nf);
                let is_t =
                    coupling == Coupling::Thermal || (coupling == Coupling::Coupled && c == 2);
                let bump = |u: &mut Vec<[f64; 3]>, th: &mut Vec<f64>, d: f64| {
                    if is_t { th[a] += d } else { u[a][c] += d }
                };
                bump(&mut u, &mut th, h);
                let rp = eval(&u, &th, None);
                bump(&mut u, &mut th, -2.0 * h);
                let rm = eval(&u, &th, None);
                bump(&mut u, &mut th, h);
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
    }
}
