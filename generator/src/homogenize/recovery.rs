//! The bulk-resolution indicator: gradient recovery (Zienkiewicz–Zhu) on the
//! bodies' bulk, for the adaptive levels (issue 11; docs/adaptivity.md,
//! "The bulk-resolution indicator").
//!
//! The contact-edge marks ([`super::adapt`]) refine at the interface; the
//! bulk away from it keeps the case mesh, and its error is invisible to the
//! differences between levels. Degree 1 in 3D showed it: trilinear elements
//! on the egg box's `[8, 8, 4]` case mesh are too stiff, the approach 4.7 %
//! short on every level (docs/3d.md, "Stop 74").
//!
//! **Recovery.** The displacement gradient `H = Grad u` and the temperature
//! gradient `G = Grad θ` of the solved state are projected onto the bodies'
//! own spline spaces by the lumped `L2` projection,
//! `H*_a = ∫ R_a H dV / ∫ R_a dV` (well defined: the THB basis is
//! non-negative and a partition of unity, so a constant gradient is
//! recovered exactly), and the element indicators are the energy norms of
//! the difference,
//! ```text
//! η_K,u² = ∫_K δε : C : δε dV,  δε = sym(H* − H),  C = 2μ I + λ 1⊗1
//! η_K,θ² = ∫_K k(θ) |G* − G|² dV
//! ```
//! with the small-strain moduli of the body's material. For a linear
//! problem under prescribed loads Galerkin orthogonality gives
//! `f(u) − f(u_h) = ‖u − u_h‖²_E`: the error of the work of the load, and so
//! of the approach under a prescribed pressure, is the squared energy error,
//! which `Σ η_K,u²` estimates (and likewise the total temperature drop under
//! a prescribed flux, `Σ η_K,θ²`).
//!
//! The adaptive levels use the mechanical part at degree 1
//! ([`super::adapt::bulk_indicator_applies`]): on its manufactured
//! solutions the indicators are the true errors to within 6 % (test
//! below); at degree 2 the lumped projection's own error at the boundaries
//! exceeds the error it would estimate (effectivity 10.7 and 15.2 on 8 and
//! 16 elements of the annulus). Periodic seams are treated as boundaries
//! (each side's control points recovered from its own elements).

use rayon::prelude::*;

use crate::solve::Model;

/// The recovered-gradient indicators of a solved model, per body (in the
/// model's order) and element, in the model's scaled units.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RecoveredErrors {
    /// `η_K,u²` (energy, scaled) per body and element.
    pub mechanical: Vec<Vec<f64>>,
    /// `η_K,θ²` (scaled) per body and element.
    pub thermal: Vec<Vec<f64>>,
}

impl RecoveredErrors {
    /// `Σ η_K,u²` over both bodies.
    pub fn mechanical_total(&self) -> f64 {
        self.mechanical.iter().flatten().sum()
    }

    /// `Σ η_K,θ²` over both bodies.
    pub fn thermal_total(&self) -> f64 {
        self.thermal.iter().flatten().sum()
    }
}

/// Components of a recovered point: `H` row-major (9), then `G` (3).
const COMPONENTS: usize = 12;

/// `H = Grad u` (row-major, zero beyond `dim`) and `G = Grad θ` at a point from
/// the element's nodal state (`nf` fields per node, displacements first).
fn gradients(
    dim: usize,
    nf: usize,
    state: &[f64],
    offset: usize,
    conn: &[usize],
    dr_dx: &[[f64; 3]],
) -> [f64; COMPONENTS] {
    let mut out = [0.0; COMPONENTS];
    for (&c, g) in conn.iter().zip(dr_dx) {
        let s = &state[(c + offset) * nf..][..nf];
        for i in 0..dim {
            for j in 0..dim {
                out[3 * i + j] += s[i] * g[j];
            }
            out[9 + i] += s[dim] * g[i];
        }
    }
    out
}

/// `δε : C : δε` for `δε = sym(δH)`, `δH` row-major.
fn strain_energy_density(dh: &[f64], mu: f64, lambda: f64) -> f64 {
    let mut sq = 0.0;
    let mut trace = 0.0;
    for i in 0..3 {
        trace += dh[4 * i];
        for j in 0..3 {
            let e = 0.5 * (dh[3 * i + j] + dh[3 * j + i]);
            sq += e * e;
        }
    }
    2.0 * mu * sq + lambda * trace * trace
}

/// The recovered-gradient indicators of `model` at its state (module
/// documentation). Bodies whose bulk quadrature is released are integrated
/// on a quadrature built for the purpose.
pub fn recovered_errors(model: &Model) -> RecoveredErrors {
    let (dim, nf) = (model.dim, model.dim + 1);
    let mut out = RecoveredErrors::default();
    for body in &model.bodies {
        let n_el = body.patch.n_elements();
        let quad = |e: usize| body.element_quadrature(e);
        let m = &body.material;
        let (mu, lambda) = (m.shear_modulus(), m.lame_lambda());
        // The lumped projection: numerators (COMPONENTS per control point)
        // and the basis functions' integrals. Each element's share is
        // computed in parallel and added in element order, so that the sums,
        // and the marks that follow from them, do not depend on the threads'
        // timing (a parallel fold's grouping does).
        let n_cp = body.patch.n_control_points();
        let shares: Vec<(Vec<usize>, Vec<f64>)> = (0..n_el)
            .into_par_iter()
            .map(|e| {
                let q = quad(e);
                let mut share = vec![0.0; q.conn.len() * (COMPONENTS + 1)];
                let mut scratch = Vec::new();
                for (p, r, dr) in q.points_with_basis(&mut scratch) {
                    let g = gradients(dim, nf, &model.state, body.node_offset, &q.conn, dr);
                    for (a, &r) in r.iter().enumerate() {
                        let w = p.weight * r;
                        let s = &mut share[a * (COMPONENTS + 1)..][..COMPONENTS + 1];
                        s[COMPONENTS] += w;
                        for (n, v) in s.iter_mut().zip(g) {
                            *n += w * v;
                        }
                    }
                }
                (q.conn.clone(), share)
            })
            .collect();
        let (mut num, mut den) = (vec![0.0; n_cp * COMPONENTS], vec![0.0; n_cp]);
        for (conn, share) in &shares {
            for (&c, s) in conn.iter().zip(share.chunks(COMPONENTS + 1)) {
                den[c] += s[COMPONENTS];
                for (n, v) in num[c * COMPONENTS..][..COMPONENTS].iter_mut().zip(s) {
                    *n += v;
                }
            }
        }
        drop(shares);
        let recovered: Vec<f64> = num
            .chunks(COMPONENTS)
            .zip(&den)
            .flat_map(|(n, &d)| n.iter().map(move |v| if d > 0.0 { v / d } else { 0.0 }))
            .collect();
        // Per element: η_u² and η_θ².
        let per_element: Vec<[f64; 2]> = (0..n_el)
            .into_par_iter()
            .map(|e| {
                let q = quad(e);
                let mut acc = [0.0; 2];
                let mut scratch = Vec::new();
                for (p, r, dr) in q.points_with_basis(&mut scratch) {
                    let g = gradients(dim, nf, &model.state, body.node_offset, &q.conn, dr);
                    let mut star = [0.0; COMPONENTS];
                    for (&c, &r) in q.conn.iter().zip(r) {
                        for (s, v) in star
                            .iter_mut()
                            .zip(&recovered[c * COMPONENTS..][..COMPONENTS])
                        {
                            *s += r * v;
                        }
                    }
                    let theta = (0..r.len())
                        .map(|a| r[a] * model.state[(q.conn[a] + body.node_offset) * nf + dim])
                        .sum::<f64>();
                    let k = m.conductivity(theta).0.max(0.0);
                    let dh: [f64; 9] = std::array::from_fn(|i| star[i] - g[i]);
                    let dg: f64 = (9..COMPONENTS).map(|i| (star[i] - g[i]).powi(2)).sum();
                    acc[0] += p.weight * strain_energy_density(&dh, mu, lambda);
                    acc[1] += p.weight * k * dg;
                }
                acc
            })
            .collect();
        out.mechanical
            .push(per_element.iter().map(|a| a[0]).collect());
        out.thermal.push(per_element.iter().map(|a| a[1]).collect());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analytical::manufactured::annulus_fields;
    use crate::verify::mms::{MmsKind, annulus_mesh, exact_fields, solve_mms_model};

    /// The true energy errors `(‖u − u_h‖²_E, ‖θ − θ_h‖²_k)` of a solved
    /// manufactured model (scaled, as the indicators).
    fn true_errors(model: &Model, kind: MmsKind) -> (f64, f64) {
        let exact_at = exact_fields(kind, annulus_fields);
        let (dim, nf) = (model.dim, model.dim + 1);
        let (ls, ts) = (model.scales.length, model.scales.temperature);
        let (mut eu, mut et) = (0.0, 0.0);
        for body in &model.bodies {
            let (mu, lambda) = (body.material.shear_modulus(), body.material.lame_lambda());
            for e in 0..body.patch.n_elements() {
                let q = body.element_quadrature(e);
                let mut scratch = Vec::new();
                for (p, r, dr) in q.points_with_basis(&mut scratch) {
                    let x = p.x.map(|v| v * ls);
                    let exact = exact_at(&x);
                    let g = gradients(dim, nf, &model.state, body.node_offset, &q.conn, dr);
                    let theta = (0..r.len())
                        .map(|a| r[a] * model.state[(q.conn[a] + body.node_offset) * nf + dim])
                        .sum::<f64>();
                    let k = body.material.conductivity(theta).0;
                    let mut dh = [0.0; 9];
                    let mut dg = 0.0;
                    for i in 0..dim {
                        for j in 0..dim {
                            dh[3 * i + j] = g[3 * i + j] - exact.grad_u[(i, j)];
                        }
                        dg += (g[9 + i] - exact.grad_theta[i] * ls / ts).powi(2);
                    }
                    eu += p.weight * strain_energy_density(&dh, mu, lambda);
                    et += p.weight * k * dg;
                }
            }
        }
        (eu, et)
    }

    /// The indicators do not depend on the number of threads, bit for bit
    /// (the adaptive marks follow from them).
    #[test]
    fn recovered_errors_do_not_depend_on_the_threads() {
        let model = solve_mms_model(MmsKind::Thermoelastic, &annulus_mesh(1, 16).unwrap()).unwrap();
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| recovered_errors(&model))
        };
        let one = on(1);
        for threads in [2, 3, 5] {
            assert_eq!(on(threads), one, "{threads} threads");
        }
    }

    /// On the manufactured solutions of degree 1 (the annulus) the
    /// indicators are the true energy errors to within a few percent
    /// (effectivity `η / ‖e‖` 1.056, 1.028, 1.011 for conduction on 8, 16,
    /// 32 elements per direction; 1.005, 1.013, 1.008 for the
    /// thermoelastic displacements), which fall at the optimal rate `h`.
    #[test]
    fn recovered_errors_match_the_true_energy_errors_of_manufactured_solutions() {
        for kind in [MmsKind::Conduction, MmsKind::Thermoelastic] {
            let mut previous: Option<f64> = None;
            for n in [8, 16, 32] {
                let model = solve_mms_model(kind, &annulus_mesh(1, n).unwrap()).unwrap();
                let r = recovered_errors(&model);
                let (eu, et) = true_errors(&model, kind);
                let (true_error, estimate) = match kind {
                    MmsKind::Conduction => (et, r.thermal_total()),
                    MmsKind::Thermoelastic => (eu, r.mechanical_total()),
                };
                let effectivity = (estimate / true_error).sqrt();
                eprintln!("{kind:?} n {n}: error {true_error:.3e}, effectivity {effectivity:.3}");
                if n >= 16 {
                    assert!(
                        (0.95..=1.1).contains(&effectivity),
                        "{kind:?} on {n} elements: effectivity {effectivity}"
                    );
                }
                if let Some(prev) = previous {
                    // ‖e‖² falls 4-fold per halving (first order in ‖e‖).
                    let rate = (prev / true_error).log2() / 2.0;
                    assert!((0.9..=1.2).contains(&rate), "{kind:?}: rate {rate}");
                }
                previous = Some(true_error);
            }
        }
    }
}
