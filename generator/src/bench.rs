//! Performance figures printed by `tcgen bench`: the micro-sample path of the paper's Sect. 5.7
//! ([`micro_sample_bench`]), and sparse assembly and direct solvers on 2D,
//! p = 2 tensor-product control-point grids.
//!
//! A grid has `nx × ny` control points (`ny = nx / 2`) on `[0, 2] × [0, 1]`, open p = 2
//! B-spline elements of 3 × 3 control points, `fields` unknowns per control point (equation
//! `cp · fields + f`). Per system and size the benchmark times: pattern construction
//! ([`Assembly::new`]), one assembly with an element kernel, the fill-reducing ordering (nested
//! dissection only), the symbolic analysis ([`LinearSolver::new`]), the first numeric
//! factorization, a refactorization with new values (a second assembly with per-element
//! scaled blocks) and one solve (with its iterative refinement). Assembly, refactorization and
//! solve are the best of two runs, since the machine may be shared.

use crate::bulk::global::Assembly;
use crate::homogenize::path::{PhaseCost, PhaseCosts};
use crate::solve::linear::{Factorization, LinearSolver, Ordering};
use crate::solve::ordering::nested_dissection;
use crate::{Error, Result};
use std::time::Instant;

/// One bulk element of the benchmark grid, handed to the element kernel.
#[derive(Debug, Clone)]
pub struct BenchElement {
    /// Element index in the assembly.
    pub index: usize,
    /// Element position in the grid (knot span indices).
    pub span: [usize; 2],
    /// Unknowns per control point; local dof of control point a, field f: `a · fields + f`.
    pub fields: usize,
    /// The 3 × 3 control points, local index `a = lx + 3 ly`.
    pub control_points: [[f64; 2]; 9],
}

/// Element kernel: fills the zeroed column-major block `k_e` (9·fields square) and vector `r_e`.
pub type ElementKernel<'a> =
    dyn Fn(&BenchElement, &mut [f64], &mut [f64]) -> Result<()> + Sync + 'a;

/// The benchmarked linear systems.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BenchSystem {
    /// 1 field, SPD (conduction-like: ∇N·∇N + N N).
    Scalar,
    /// 2 fields, SPD (plane elasticity + mass).
    Vector,
    /// 2 fields + one Lagrange multiplier per top-edge control point tying u_y through a
    /// mortar-like 1D mass matrix: symmetric saddle point [K Bᵀ; B 0].
    SaddlePoint,
    /// 3 fields (u_x, u_y, θ) with nonsymmetric coupling and advection.
    Coupled,
}

impl BenchSystem {
    /// Unknowns per control point (multipliers excluded).
    pub fn fields(self) -> usize {
        match self {
            BenchSystem::Scalar => 1,
            BenchSystem::Vector | BenchSystem::SaddlePoint => 2,
            BenchSystem::Coupled => 3,
        }
    }

    fn label(self) -> &'static str {
        match self {
            BenchSystem::Scalar => "1-field SPD",
            BenchSystem::Vector => "2-field SPD",
            BenchSystem::SaddlePoint => "2-field+mult",
            BenchSystem::Coupled => "3-field nonsym",
        }
    }
}

/// Timings (seconds) and sizes of one benchmark case.
#[derive(Debug, Clone)]
pub struct BenchRow {
    /// Which system.
    pub system: BenchSystem,
    /// Control points per direction.
    pub grid: [usize; 2],
    /// Unknowns.
    pub n_eq: usize,
    /// Structural nonzeros of the matrix.
    pub nnz: usize,
    /// "Cholesky", "LDLT" or "LU".
    pub solver: &'static str,
    /// "AMD", "ND" (nested dissection) or "COLAMD".
    pub ordering: &'static str,
    /// Pattern, scatter map and coloring ([`Assembly::new`]).
    pub pattern_s: f64,
    /// One assembly of matrix and residual (best of two).
    pub assembly_s: f64,
    /// Nested dissection (0 for the solver's own ordering, which is inside `symbolic_s`).
    pub ordering_s: f64,
    /// Symbolic analysis.
    pub symbolic_s: f64,
    /// First numeric factorization (allocates the workspace).
    pub factorize_s: f64,
    /// Numeric refactorization with new values (best of two).
    pub refactorize_s: f64,
    /// One solve including iterative refinement (best of two).
    pub solve_s: f64,
    /// Stored entries of L (Cholesky/LDLᵀ), `None` for LU.
    pub factor_nnz: Option<usize>,
    /// ‖Ax − b‖∞ / ‖b‖∞ after the solve.
    pub relative_residual: f64,
}

/// Runs every benchmark case for each target number of unknowns in `sizes` with the built-in
/// [`synthetic_kernel`].
pub fn run_linear_solver_bench(sizes: &[usize]) -> Vec<BenchRow> {
    run_linear_solver_bench_with(sizes, &synthetic_kernel)
        .expect("the synthetic benchmark systems are nonsingular and their kernel cannot fail")
}

/// As [`run_linear_solver_bench`] with a caller-supplied bulk element kernel (the Lagrange
/// multiplier coupling of [`BenchSystem::SaddlePoint`] stays built in).
pub fn run_linear_solver_bench_with(
    sizes: &[usize],
    kernel: &ElementKernel<'_>,
) -> Result<Vec<BenchRow>> {
    let cases: [(BenchSystem, &str, &str); 7] = [
        (BenchSystem::Scalar, "Cholesky", "AMD"),
        (BenchSystem::Scalar, "Cholesky", "ND"),
        (BenchSystem::Vector, "Cholesky", "AMD"),
        (BenchSystem::Vector, "Cholesky", "ND"),
        (BenchSystem::SaddlePoint, "LDLT", "AMD"),
        (BenchSystem::SaddlePoint, "LDLT", "ND"),
        (BenchSystem::Coupled, "LU", "COLAMD"),
    ];
    let mut rows = Vec::new();
    for &size in sizes {
        for &(system, solver, ordering) in &cases {
            rows.push(run_case(system, size, solver, ordering, kernel)?);
        }
    }
    Ok(rows)
}

/// Runs the benchmark for `sizes` and prints its table to stdout (`tcgen bench`).
pub fn main_bench(sizes: &[usize]) -> Result<()> {
    println!(
        "tcgen bench: sparse assembly and direct solvers, 2D p = 2 grids, {} rayon threads",
        rayon::current_num_threads()
    );
    println!(
        "element kernel: the production finite-thermoelasticity kernel (bulk::local), 4 × 4 Gauss points"
    );
    let rows = run_linear_solver_bench_with(sizes, &thermoelastic_kernel)?;
    print!("{}", format_bench_table(&rows));
    Ok(())
}

/// The production bulk kernel (`bulk::local::element_residual_tangent`,
/// hand-written tangents, `p + 2 = 4` Gauss points per direction) on a bench
/// element: 1 field → thermal phase (constant k, SPD), 2 → mechanical phase,
/// 3 → coupled. The state is a smooth ~1 % strain and a temperature gradient.
/// A small mass shift (1e−6) keeps the unconstrained benchmark matrices
/// nonsingular without changing the cost.
pub fn thermoelastic_kernel(element: &BenchElement, k: &mut [f64], r: &mut [f64]) -> Result<()> {
    use crate::bulk::local::{Coupling, ElementFields, element_residual_tangent};
    use crate::geometry::{ElementQuadrature, QuadPoint};
    let nf = element.fields;
    let coupling = match nf {
        1 => Coupling::Thermal,
        2 => Coupling::Mechanical,
        3 => Coupling::Coupled,
        _ => return Err(Error::invalid("bench.fields", nf, "1, 2 or 3")),
    };
    let mut material = crate::material::Material::default().scaled(1.0e6, 293.15, 1.0);
    if nf == 1 {
        material.conductivity_slope = 0.0;
    }
    let gauss = crate::quadrature::GaussLegendre::new(4);
    let (mut points, mut values, mut gradients) = (
        Vec::with_capacity(16),
        Vec::with_capacity(16 * 9),
        Vec::with_capacity(16 * 9),
    );
    for (&ty, &wy) in gauss.points.iter().zip(&gauss.weights) {
        for (&tx, &wx) in gauss.points.iter().zip(&gauss.weights) {
            let ((nx, dx), (ny, dy)) = (
                quadratic_bspline(0.5 * (tx + 1.0)),
                quadratic_bspline(0.5 * (ty + 1.0)),
            );
            let mut jac = [[0.0; 2]; 2];
            let mut x = [0.0; 2];
            let first = gradients.len();
            for a in 0..9 {
                let (lx, ly) = (a % 3, a / 3);
                let r = nx[lx] * ny[ly];
                values.push(r);
                let dxi = [dx[lx] * ny[ly], nx[lx] * dy[ly]];
                for i in 0..2 {
                    x[i] += r * element.control_points[a][i];
                    for j in 0..2 {
                        jac[i][j] += element.control_points[a][i] * dxi[j];
                    }
                }
                gradients.push([dxi[0], dxi[1], 0.0]);
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            if det <= 0.0 {
                return Err(Error::Geometry(format!(
                    "bench element {}: Jacobian {det} ≤ 0",
                    element.index
                )));
            }
            for g in &mut gradients[first..] {
                let d = *g;
                g[0] = (jac[1][1] * d[0] - jac[1][0] * d[1]) / det;
                g[1] = (-jac[0][1] * d[0] + jac[0][0] * d[1]) / det;
            }
            points.push(QuadPoint {
                xi: [0.0; 3],
                x: [x[0], x[1], 0.0],
                weight: 0.25 * wx * wy * det,
                inverse_jacobian: [[0.0; 3]; 3],
                weight_function: 1.0,
            });
        }
    }
    let quad = ElementQuadrature::with_gradients(2, (0..9).collect(), points, values, gradients);
    {
        let u: Vec<[f64; 3]> = element
            .control_points
            .iter()
            .map(|p| [0.01 * p[0] * p[1], -0.01 * p[0], 0.0])
            .collect();
        let theta: Vec<f64> = element
            .control_points
            .iter()
            .map(|p| 1.0 + 0.01 * p[0])
            .collect();
        let fields = ElementFields {
            u: &u,
            theta: &theta,
        };
        element_residual_tangent(
            &material,
            &quad,
            2,
            coupling,
            &fields,
            None,
            Some(&mut *k),
            r,
        );
        let n = 9 * nf;
        for i in 0..n {
            k[i + n * i] += 1e-6;
        }
    }
    Ok(())
}

/// The benchmark table, one line per case, times in seconds.
pub fn format_bench_table(rows: &[BenchRow]) -> String {
    let mut out = format!(
        "{:<15} {:>9} {:>8} {:>10} {:<8} {:<6} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>11} {:>8}\n",
        "system",
        "grid",
        "n_eq",
        "nnz(A)",
        "solver",
        "order",
        "pattern",
        "assem",
        "ND",
        "symb",
        "fact",
        "refact",
        "solve",
        "nnz(L)",
        "resid"
    );
    for r in rows {
        let factor = r
            .factor_nnz
            .map_or_else(|| "-".to_string(), |n| n.to_string());
        out += &format!(
            "{:<15} {:>9} {:>8} {:>10} {:<8} {:<6} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>7.3} {:>11} {:>8.1e}\n",
            r.system.label(),
            format!("{}x{}", r.grid[0], r.grid[1]),
            r.n_eq,
            r.nnz,
            r.solver,
            r.ordering,
            r.pattern_s,
            r.assembly_s,
            r.ordering_s,
            r.symbolic_s,
            r.factorize_s,
            r.refactorize_s,
            r.solve_s,
            factor,
            r.relative_residual
        );
    }
    out
}

/// The benchmark mesh: control points, bulk elements and (for the saddle point) multipliers.
struct BenchMesh {
    nx: usize,
    ny: usize,
    fields: usize,
    n_bulk: usize,
    n_eq: usize,
    element_eqs: Vec<Vec<Option<usize>>>,
    coords: Vec<[f64; 3]>,
}

impl BenchMesh {
    fn new(system: BenchSystem, target_unknowns: usize) -> Self {
        let fields = system.fields();
        let nx = (((2 * target_unknowns) as f64 / fields as f64)
            .sqrt()
            .round() as usize)
            .max(6);
        let ny = nx / 2;
        let n_disp = fields * nx * ny;
        let mut element_eqs = Vec::with_capacity((nx - 2) * (ny - 2) + nx);
        for ey in 0..ny - 2 {
            for ex in 0..nx - 2 {
                let mut eqs = Vec::with_capacity(9 * fields);
                for ly in 0..3 {
                    for lx in 0..3 {
                        let cp = (ey + ly) * nx + ex + lx;
                        eqs.extend((0..fields).map(|f| Some(cp * fields + f)));
                    }
                }
                element_eqs.push(eqs);
            }
        }
        let n_bulk = element_eqs.len();
        let h = 2.0 / (nx - 1) as f64;
        let mut coords: Vec<[f64; 3]> = (0..n_disp)
            .map(|i| {
                let cp = i / fields;
                [(cp % nx) as f64 * h, (cp / nx) as f64 * h, 0.0]
            })
            .collect();
        let mut n_eq = n_disp;
        if system == BenchSystem::SaddlePoint {
            // Top-edge segments: u_y of 3 control points and their 3 multipliers.
            for ex in 0..nx - 2 {
                let top = |l: usize| (ny - 1) * nx + ex + l;
                let mut eqs: Vec<Option<usize>> =
                    (0..3).map(|l| Some(top(l) * fields + 1)).collect();
                eqs.extend((0..3).map(|l| Some(n_disp + ex + l)));
                element_eqs.push(eqs);
            }
            coords.extend((0..nx).map(|i| [i as f64 * h, (ny - 1) as f64 * h, 0.0]));
            n_eq += nx;
        }
        Self {
            nx,
            ny,
            fields,
            n_bulk,
            n_eq,
            element_eqs,
            coords,
        }
    }

    fn bulk_element(&self, e: usize) -> BenchElement {
        let (ex, ey) = (e % (self.nx - 2), e / (self.nx - 2));
        let h = 2.0 / (self.nx - 1) as f64;
        let mut control_points = [[0.0; 2]; 9];
        for (a, point) in control_points.iter_mut().enumerate() {
            *point = [(ex + a % 3) as f64 * h, (ey + a / 3) as f64 * h];
        }
        BenchElement {
            index: e,
            span: [ex, ey],
            fields: self.fields,
            control_points,
        }
    }

    fn signs(&self) -> Vec<i8> {
        let n_disp = self.fields * self.nx * self.ny;
        (0..self.n_eq)
            .map(|i| if i < n_disp { 1 } else { -1 })
            .collect()
    }
}

fn run_case(
    system: BenchSystem,
    size: usize,
    solver: &'static str,
    ordering: &'static str,
    kernel: &ElementKernel<'_>,
) -> Result<BenchRow> {
    let mut mesh = BenchMesh::new(system, size);
    let element_eqs = std::mem::take(&mut mesh.element_eqs);
    let h = 2.0 / (mesh.nx - 1) as f64;
    let t = Instant::now();
    let assembly = Assembly::new(mesh.n_eq, element_eqs);
    let pattern_s = t.elapsed().as_secs_f64();

    let element = |e: usize, k: &mut [f64], r: &mut [f64], scale: f64| -> Result<()> {
        if e < mesh.n_bulk {
            kernel(&mesh.bulk_element(e), k, r)?;
        } else {
            multiplier_coupling(h, k);
        }
        k.iter_mut().for_each(|v| *v *= scale);
        Ok(())
    };
    let mut values = vec![0.0; assembly.nnz()];
    let mut rhs = vec![0.0; assembly.n_eq()];
    let t = Instant::now();
    assembly.assemble(&mut values, &mut rhs, |e, k, r| element(e, k, r, 1.0))?;
    let assembly_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let order = match ordering {
        "ND" => Ordering::Custom(nested_dissection(assembly.symbolic(), &mesh.coords)),
        _ => Ordering::Default,
    };
    let ordering_s = if ordering == "ND" {
        t.elapsed().as_secs_f64()
    } else {
        0.0
    };
    let kind = match solver {
        "Cholesky" => Factorization::Cholesky,
        "LDLT" => Factorization::Ldlt {
            signs: mesh.signs(),
        },
        _ => Factorization::Lu,
    };
    let t = Instant::now();
    let mut linear = LinearSolver::new(assembly.symbolic(), kind, order)?;
    let symbolic_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    linear.factorize(&values)?;
    let factorize_s = t.elapsed().as_secs_f64();

    // New values, as after a Newton update: every element block rescaled differently. The
    // second assembly, the refactorization and the solve are timed best of two (shared machine).
    let mut values_new = vec![0.0; assembly.nnz()];
    let mut rhs_new = vec![0.0; assembly.n_eq()];
    let t = Instant::now();
    assembly.assemble(&mut values_new, &mut rhs_new, |e, k, r| {
        element(e, k, r, 1.0 + 0.25 * ((e * 7919) % 13) as f64 / 13.0)
    })?;
    let assembly_s = assembly_s.min(t.elapsed().as_secs_f64());
    let mut refactorize_s = f64::INFINITY;
    let mut solve_s = f64::INFINITY;
    let mut x = rhs_new.clone();
    for _ in 0..2 {
        let t = Instant::now();
        linear.factorize(&values_new)?;
        refactorize_s = refactorize_s.min(t.elapsed().as_secs_f64());
        x.copy_from_slice(&rhs_new);
        let t = Instant::now();
        linear.solve_in_place(&mut x)?;
        solve_s = solve_s.min(t.elapsed().as_secs_f64());
    }
    let relative_residual = relative_residual(&assembly, &values_new, &x, &rhs_new);
    if !relative_residual.is_finite() {
        return Err(Error::LinearSolver(format!(
            "bench {system:?} {solver}: non-finite residual"
        )));
    }
    Ok(BenchRow {
        system,
        grid: [mesh.nx, mesh.ny],
        n_eq: assembly.n_eq(),
        nnz: assembly.nnz(),
        solver,
        ordering,
        pattern_s,
        assembly_s,
        ordering_s,
        symbolic_s,
        factorize_s,
        refactorize_s,
        solve_s,
        factor_nnz: linear.factor_nnz(),
        relative_residual,
    })
}

/// ‖Ax − b‖∞ / ‖b‖∞.
fn relative_residual(assembly: &Assembly, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let pattern = assembly.symbolic();
    let mut r = b.to_vec();
    for (j, &xj) in x.iter().enumerate() {
        for k in pattern.col_range(j) {
            r[pattern.row_idx()[k]] -= values[k] * xj;
        }
    }
    let norm = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    norm(&r) / norm(b)
}

/// 1D quadratic B-spline basis on a knot span, t ∈ [0, 1]: values and d/dt.
fn quadratic_bspline(t: f64) -> ([f64; 3], [f64; 3]) {
    (
        [0.5 * (1.0 - t) * (1.0 - t), 0.5 + t - t * t, 0.5 * t * t],
        [t - 1.0, 1.0 - 2.0 * t, t],
    )
}

/// 3-point Gauss–Legendre rule on [0, 1].
const GAUSS_3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_31, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// Saddle-point coupling of a top-edge segment, local dofs [u_y(3), λ(3)]:
/// k = [0 Mᵀ; M 0], M the 1D mass matrix of the segment (length h).
fn multiplier_coupling(h: f64, k: &mut [f64]) {
    for &(t, w) in &GAUSS_3 {
        let (n, _) = quadratic_bspline(t);
        for a in 0..3 {
            for b in 0..3 {
                let m = w * h * n[a] * n[b];
                k[(3 + b) * 6 + a] += m; // row u_a, column λ_b
                k[b * 6 + 3 + a] += m; // row λ_a, column u_b
            }
        }
    }
}

/// Synthetic element kernel of realistic cost: 3 × 3 Gauss points, Jacobian from the control
/// points, then by `fields`: 1 — ∇N·∇N + N N (SPD); 2 — plane elasticity (λ = μ = 1) + mass
/// (SPD); 3 — elasticity, conduction with advection v = (1, ½), and nonsymmetric
/// displacement–temperature coupling. Residual: a constant body load.
pub fn synthetic_kernel(element: &BenchElement, k: &mut [f64], r: &mut [f64]) -> Result<()> {
    let nf = element.fields;
    let n = 9 * nf;
    if !(1..=3).contains(&nf) || k.len() != n * n || r.len() != n {
        return Err(Error::invalid(
            "bench.fields",
            nf,
            "1, 2 or 3 fields with a 9·fields element block",
        ));
    }
    let (lambda, mu, beta, gamma, velocity) = (1.0, 1.0, 0.3, 0.1, [1.0, 0.5]);
    let mut shape = [0.0; 9];
    let mut grad = [[0.0; 2]; 9];
    for &(ty, wy) in &GAUSS_3 {
        for &(tx, wx) in &GAUSS_3 {
            let ((nx, dx), (ny, dy)) = (quadratic_bspline(tx), quadratic_bspline(ty));
            let mut jac = [[0.0; 2]; 2]; // ∂x_i/∂ξ_j
            for a in 0..9 {
                let (lx, ly) = (a % 3, a / 3);
                shape[a] = nx[lx] * ny[ly];
                let dxi = [dx[lx] * ny[ly], nx[lx] * dy[ly]];
                for (row, x_i) in jac.iter_mut().zip(element.control_points[a]) {
                    for (entry, dxi_j) in row.iter_mut().zip(dxi) {
                        *entry += x_i * dxi_j;
                    }
                }
                grad[a] = dxi;
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            if det <= 0.0 {
                return Err(Error::Geometry(format!(
                    "bench element {}: Jacobian {det} ≤ 0",
                    element.index
                )));
            }
            let inv = [
                [jac[1][1] / det, -jac[0][1] / det],
                [-jac[1][0] / det, jac[0][0] / det],
            ];
            for g in grad.iter_mut() {
                let dxi = *g;
                *g = [
                    dxi[0] * inv[0][0] + dxi[1] * inv[1][0],
                    dxi[0] * inv[0][1] + dxi[1] * inv[1][1],
                ];
            }
            let w = wx * wy * det;
            for b in 0..9 {
                for a in 0..9 {
                    let dot = grad[a][0] * grad[b][0] + grad[a][1] * grad[b][1];
                    let mass = shape[a] * shape[b];
                    if nf == 1 {
                        k[b * n + a] += w * (dot + mass);
                        continue;
                    }
                    for i in 0..2 {
                        for j in 0..2 {
                            let delta = if i == j { dot + mass } else { 0.0 };
                            let elastic = lambda * grad[a][i] * grad[b][j]
                                + mu * (grad[a][j] * grad[b][i] + delta);
                            k[(b * nf + j) * n + a * nf + i] += w * elastic;
                        }
                    }
                    if nf == 3 {
                        let advection =
                            shape[a] * (velocity[0] * grad[b][0] + velocity[1] * grad[b][1]);
                        k[(b * nf + 2) * n + a * nf + 2] += w * (dot + mass + advection);
                        for i in 0..2 {
                            k[(b * nf + 2) * n + a * nf + i] -= w * beta * grad[a][i] * shape[b];
                            k[(b * nf + i) * n + a * nf + 2] += w * gamma * shape[a] * grad[b][i];
                        }
                    }
                }
            }
            for a in 0..9 {
                for f in 0..nf {
                    r[a * nf + f] += w * shape[a] * if f == 1 { -1.0 } else { 0.5 };
                }
            }
        }
    }
    Ok(())
}

/// The micro-sample path benchmark (`tcgen bench --micro`): the Sect. 5.7
/// sinusoid on a flat of `tables/sinusoid_on_flat.toml` (p = 2, meshes
/// 32 × 16 / 27 × 14, PR, two-phase self-consistent) along `pressures`
/// log-spaced pressures from 100 Pa to 0.35 MPa, with the solver's
/// factorizations (LDLᵀ for the phases with multipliers) and again with LU
/// in every phase (wall times best of two, alternating).
#[derive(Debug, Clone)]
pub struct MicroBench {
    /// Wall time of the whole path (s).
    pub wall_s: f64,
    /// Newton iterations per pressure (all phases).
    pub newton_iterations: Vec<usize>,
    /// Self-consistency iterations per pressure.
    pub self_consistency_iterations: Vec<usize>,
    /// Newton iterations whose LDLᵀ fell back to LU.
    pub linear_fallbacks: usize,
    /// Symbolic analyses of the path (one per new pattern and kind).
    pub analyses: usize,
    /// The path with LU in every phase: wall time (s), Newton iterations
    /// per pressure.
    pub lu_path: (f64, Vec<usize>),
    /// Largest relative difference of the jumps of the two paths.
    pub jump_difference: f64,
    /// Per phase (mechanical, thermal) at the last pressure: the parts of
    /// one Newton iteration (s, best of three).
    pub iteration: [IterationCost; 2],
    /// The same path adaptive to 1 % from 16 × 8: wall time (s), the largest
    /// relative estimate, the points that met the target, the largest
    /// number of unknowns.
    pub adaptive: (f64, f64, usize, usize),
}

/// The parts of one Newton iteration (s).
#[derive(Debug, Clone, Copy, Default)]
pub struct IterationCost {
    /// Contact projection and kinematics with their derivatives (`prepare`).
    pub contact_kinematics_s: f64,
    /// Assembly of residual and tangent (bulk and contact elements).
    pub assembly_s: f64,
    /// Numeric factorization and solve with the solver's factorization.
    pub factorize_solve_s: f64,
    /// Symbolic analysis of the pattern (once per pattern; with the ordering).
    pub symbolic_s: f64,
    /// Numeric factorization and solve by LU (COLAMD).
    pub lu_factorize_solve_s: f64,
    /// Symbolic analysis for LU.
    pub lu_symbolic_s: f64,
    /// The solver's factorization.
    pub kind: &'static str,
    /// Entries of its factor L (Cholesky/LDLᵀ; `None` for LU).
    pub factor_nnz: Option<usize>,
    /// Unknowns.
    pub n_eq: usize,
}

impl IterationCost {
    /// The named parts (s).
    pub fn parts(&self) -> [(&'static str, f64); 6] {
        [
            (
                "contact kinematics (projection, derivatives)",
                self.contact_kinematics_s,
            ),
            ("assembly (bulk and contact elements)", self.assembly_s),
            ("factorization and solve", self.factorize_solve_s),
            ("symbolic analysis (once per pattern)", self.symbolic_s),
            (
                "LU + COLAMD: factorization and solve",
                self.lu_factorize_solve_s,
            ),
            ("LU + COLAMD: symbolic analysis", self.lu_symbolic_s),
        ]
    }
}

/// The pressure range of the micro-sample path benchmark (Pa).
pub const MICRO_PRESSURES: (f64, f64) = (1.0e2, 3.5e5);

/// `pressures` (at least 2) geometrically spaced over [`MICRO_PRESSURES`].
fn micro_pressures(pressures: usize) -> Result<Vec<f64>> {
    if pressures < 2 {
        return Err(Error::invalid("bench.pressures", pressures, "at least 2"));
    }
    let (lo, hi) = MICRO_PRESSURES;
    Ok((0..pressures)
        .map(|i| lo * (hi / lo).powf(i as f64 / (pressures - 1) as f64))
        .collect())
}

/// The name of a factorization kind.
fn kind_name(kind: &Factorization) -> &'static str {
    match kind {
        Factorization::Lu => "LU + COLAMD",
        Factorization::Cholesky => "Cholesky + ND",
        Factorization::Ldlt { .. } => "LDLT + ND",
    }
}

/// A path of [`micro_sample_bench`] with the solver's factorizations
/// (`symmetric`) or LU everywhere: the wall time (s), the solver, and per
/// pressure the Newton and self-consistency iterations and the jump (K).
#[allow(clippy::type_complexity)]
fn micro_path<'a>(
    case: &'a crate::sample::Case,
    path: &[f64],
    symmetric: bool,
) -> Result<(
    f64,
    crate::homogenize::path::PathSolver<'a>,
    Vec<(usize, usize, f64)>,
)> {
    let t = Instant::now();
    let mut solver = crate::homogenize::path::PathSolver::new(case)?;
    solver.model.set_symmetric_solvers(symmetric);
    let mut points = Vec::new();
    for &p in path {
        let r = solver.solve_pressure(p)?;
        points.push((r.newton_iterations, r.self_consistency_iterations, r.jump));
    }
    Ok((t.elapsed().as_secs_f64(), solver, points))
}

/// Runs the micro-sample path benchmark.
pub fn micro_sample_bench(pressures: usize) -> Result<MicroBench> {
    use crate::bulk::Coupling;
    use crate::solve::NonlinearProblem;
    let path = micro_pressures(pressures)?;
    let case = crate::sample::Case::from_toml(
        include_str!("../../tables/sinusoid_on_flat.toml"),
        std::path::Path::new("."),
    )?;
    // Best of two, alternating (the machine may be shared).
    let (mut lu_wall_s, _, lu_points) = micro_path(&case, &path, false)?;
    let (mut wall_s, _, points) = micro_path(&case, &path, true)?;
    lu_wall_s = lu_wall_s.min(micro_path(&case, &path, false)?.0);
    let (again_s, mut solver, _) = micro_path(&case, &path, true)?;
    wall_s = wall_s.min(again_s);
    let jump_difference = points
        .iter()
        .zip(&lu_points)
        .map(|(a, b)| (a.2 - b.2).abs() / b.2.abs())
        .fold(0.0, f64::max);
    let (linear_fallbacks, analyses) = (solver.linear_fallbacks(), solver.analyses());
    let model = &mut solver.model;
    let best = |f: &mut dyn FnMut() -> Result<()>| -> Result<f64> {
        let mut b = f64::INFINITY;
        for _ in 0..3 {
            let t = Instant::now();
            f()?;
            b = b.min(t.elapsed().as_secs_f64());
        }
        Ok(b)
    };
    let mut iteration = [IterationCost::default(); 2];
    for (slot, coupling) in [Coupling::Mechanical, Coupling::Thermal]
        .into_iter()
        .enumerate()
    {
        model.set_coupling(coupling)?;
        if coupling == Coupling::Thermal {
            // As in the thermal phase of the path (Sect. 3.1).
            model.freeze_conductivity(case.load.contact_temperature);
        }
        let contact_kinematics_s = best(&mut || model.prepare())?;
        let n = model.n_eq();
        let nnz = model.pattern().row_idx().len();
        let (mut values, mut r) = (vec![0.0; nnz], vec![0.0; n]);
        let assembly_s = best(&mut || {
            values.iter_mut().for_each(|v| *v = 0.0);
            model.assemble(Some(&mut values), &mut r)
        })?;
        // LU takes both triangles (a symmetric tangent's assembly stores the lower one).
        let full = model.full_tangent(&values);
        let timed = |kind: Factorization| -> Result<(f64, f64, Option<usize>)> {
            let (pattern, values) = match kind {
                Factorization::Lu => (full.symbolic(), full.val()),
                _ => (model.pattern(), values.as_slice()),
            };
            let t = Instant::now();
            let ordering = model.ordering(&kind);
            let mut linear = LinearSolver::new(pattern, kind, ordering)?;
            let symbolic_s = t.elapsed().as_secs_f64();
            let factorize_solve_s = best(&mut || {
                linear.factorize(values)?;
                let mut x = r.clone();
                linear.solve_in_place(&mut x)?;
                match linear.fallback() {
                    Some(reason) => Err(Error::LinearSolver(format!("bench: {reason}"))),
                    None => Ok(()),
                }
            })?;
            Ok((symbolic_s, factorize_solve_s, linear.factor_nnz()))
        };
        let kind = model.factorization();
        let name = kind_name(&kind);
        let (symbolic_s, factorize_solve_s, factor_nnz) = timed(kind)?;
        let (lu_symbolic_s, lu_factorize_solve_s, _) = timed(Factorization::Lu)?;
        iteration[slot] = IterationCost {
            contact_kinematics_s,
            assembly_s,
            factorize_solve_s,
            symbolic_s,
            lu_factorize_solve_s,
            lu_symbolic_s,
            kind: name,
            factor_nnz,
            n_eq: n,
        };
        model.restore_materials();
    }
    model.set_coupling(Coupling::Mechanical)?;
    let mut adaptive_case = sect57_case(16, path[0], Some(0.01))?;
    adaptive_case.load.pressures = path.clone();
    let t = Instant::now();
    let adaptive_points = crate::homogenize::solve_case(&adaptive_case, None, |_| {})?;
    let adaptive = (
        t.elapsed().as_secs_f64(),
        adaptive_points
            .iter()
            .map(|r| r.jump_error.unwrap_or(f64::INFINITY) / r.jump)
            .fold(0.0, f64::max),
        adaptive_points
            .iter()
            .filter(|r| r.error_target_met == Some(true))
            .count(),
        adaptive_points.iter().map(|r| r.dofs).max().unwrap_or(0),
    );
    Ok(MicroBench {
        wall_s,
        newton_iterations: points.iter().map(|p| p.0).collect(),
        self_consistency_iterations: points.iter().map(|p| p.1).collect(),
        linear_fallbacks,
        analyses,
        lu_path: (lu_wall_s, lu_points.iter().map(|p| p.0).collect()),
        jump_difference,
        iteration,
        adaptive,
    })
}

/// The micro-sample benchmark as text.
pub fn format_micro_bench(b: &MicroBench) -> String {
    use std::fmt::Write;
    let n = b.newton_iterations.len().max(1);
    let (min, max) = b
        .newton_iterations
        .iter()
        .fold((usize::MAX, 0), |(a, c), &v| (a.min(v), c.max(v)));
    let mean = b.newton_iterations.iter().sum::<usize>() as f64 / n as f64;
    let mut s = String::new();
    let (lo, hi) = MICRO_PRESSURES;
    let _ = writeln!(
        s,
        "micro-sample path: Sect. 5.7 sinusoid on a flat (tables/sinusoid_on_flat.toml: p = 2, \
         32 x 16 / 27 x 14, PR, two-phase self-consistent), {n} pressures from {lo:e} to {hi:e} \
         Pa, {} rayon threads",
        rayon::current_num_threads()
    );
    let _ = writeln!(
        s,
        "  wall time {:.2} s ({:.3} s per pressure); Newton iterations per pressure {min}–{max} \
         (mean {mean:.1}); self-consistency iterations {}–{}",
        b.wall_s,
        b.wall_s / n as f64,
        b.self_consistency_iterations.iter().min().unwrap_or(&0),
        b.self_consistency_iterations.iter().max().unwrap_or(&0),
    );
    let (lu_wall, lu_newton) = &b.lu_path;
    let _ = writeln!(
        s,
        "  with LU + COLAMD in every phase: wall time {lu_wall:.2} s (LDLT/Cholesky path {:.2}x \
         of it); Newton iterations {} (LDLT path {}); largest relative jump difference {:.1e}; \
         LDLT fallbacks to LU {}; symbolic analyses {}",
        b.wall_s / lu_wall,
        lu_newton.iter().sum::<usize>(),
        b.newton_iterations.iter().sum::<usize>(),
        b.jump_difference,
        b.linear_fallbacks,
        b.analyses
    );
    let _ = writeln!(
        s,
        "  one Newton iteration at {hi:e} Pa (ms, best of 3):  {:>13} {:>13}",
        "mechanical", "thermal"
    );
    let _ = writeln!(
        s,
        "    {:<47}{:>13} {:>13}",
        "unknowns", b.iteration[0].n_eq, b.iteration[1].n_eq
    );
    let _ = writeln!(
        s,
        "    {:<47}{:>13} {:>13}",
        "factorization", b.iteration[0].kind, b.iteration[1].kind
    );
    let nnz = |c: &IterationCost| c.factor_nnz.map_or("n/a".into(), |z| z.to_string());
    let _ = writeln!(
        s,
        "    {:<47}{:>13} {:>13}",
        "entries of its factor L",
        nnz(&b.iteration[0]),
        nnz(&b.iteration[1])
    );
    let (m, t) = (b.iteration[0].parts(), b.iteration[1].parts());
    for ((name, a), (_, c)) in m.iter().zip(&t) {
        let _ = writeln!(s, "    {name:<47}{:>13.2} {:>13.2}", 1e3 * a, 1e3 * c);
    }
    let (wall, worst, met, dofs) = b.adaptive;
    let _ = writeln!(
        s,
        "  adaptive to target_error = 0.01 from 16 x 8 / 13 x 7: wall time {wall:.2} s; largest \
         estimate {:.2} % of the jump; target met at {met} of {n} pressures; at most {dofs} unknowns",
        100.0 * worst
    );
    s
}

/// One row of the accuracy-per-cost benchmark ([`adaptivity_bench`]).
#[derive(Debug, Clone)]
pub struct AccuracyRow {
    /// Pressure (Pa).
    pub pressure: f64,
    /// `"uniform NxM"` or `"adaptive 1e-2"`.
    pub mesh: String,
    /// Unknowns of the mesh of the jump.
    pub dofs: usize,
    /// Wall time of the solve from first touch (s).
    pub wall_s: f64,
    /// The jump (K).
    pub jump: f64,
    /// Its estimated error (K), adaptive only.
    pub estimate: Option<f64>,
    /// The reference jump (K).
    pub reference: f64,
}

/// The adaptive Sect. 5.7 case: `tables/sinusoid_on_flat.toml` on `elements`
/// (upper along x; lower and heights in proportion) at one pressure, with an
/// optional target error.
fn sect57_case(elements: usize, pressure: f64, target: Option<f64>) -> Result<crate::sample::Case> {
    let mut case = crate::sample::Case::from_toml(
        include_str!("../../tables/sinusoid_on_flat.toml"),
        std::path::Path::new("."),
    )?;
    let d = &mut case.discretization;
    d.elements_upper = [elements, elements / 2].into();
    d.elements_lower = [elements * 27 / 32, (elements * 14).div_ceil(32)].into();
    d.target_error = target;
    d.max_levels = crate::sample::case::MAX_LEVELS;
    case.load.pressures = vec![pressure];
    Ok(case)
}

/// Solves one pressure of a case from first touch: the result and the wall time.
fn timed_solve(case: &crate::sample::Case) -> Result<(crate::homogenize::PointResult, f64)> {
    let t = Instant::now();
    let mut solver = crate::homogenize::path::PathSolver::new(case)?;
    let r = solver.solve_pressure(case.load.pressures[0])?;
    Ok((r, t.elapsed().as_secs_f64()))
}

/// The accuracy-per-cost benchmark (`tcgen bench --only accuracy`): the
/// Sect. 5.7 sample at 300 Pa, 1 kPa, 10 kPa and 100 kPa on uniform meshes
/// of 16 to `finest` elements along x, and adaptive from 16 × 8 at targets
/// 5 %, 2 %, 1 % and 0.5 %; the reference is the adaptive solve at 1e-4
/// (its own estimate printed).
pub fn adaptivity_bench(finest: usize) -> Result<Vec<AccuracyRow>> {
    let mut rows = Vec::new();
    for p in [3.0e2, 1.0e3, 1.0e4, 1.0e5] {
        let (reference, _) = timed_solve(&sect57_case(16, p, Some(1.0e-4))?)?;
        let mut push = |mesh: String, r: crate::homogenize::PointResult, wall_s: f64| {
            rows.push(AccuracyRow {
                pressure: p,
                mesh,
                dofs: r.dofs,
                wall_s,
                jump: r.jump,
                estimate: r.jump_error,
                reference: reference.jump,
            })
        };
        push("reference 1e-4".into(), reference.clone(), f64::NAN);
        let mut n = 16;
        while n <= finest {
            let (r, t) = timed_solve(&sect57_case(n, p, None)?)?;
            push(format!("uniform {n} x {}", n / 2), r, t);
            n *= 2;
        }
        for target in [5.0e-2, 2.0e-2, 1.0e-2, 5.0e-3] {
            let (r, t) = timed_solve(&sect57_case(16, p, Some(target))?)?;
            push(format!("adaptive {target:e}"), r, t);
        }
    }
    Ok(rows)
}

/// The accuracy-per-cost benchmark as text.
pub fn format_accuracy_bench(rows: &[AccuracyRow]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "accuracy per cost: Sect. 5.7 sinusoid on a flat (tables/sinusoid_on_flat.toml, p = 2, \
         two-phase self-consistent), one pressure from first touch; reference: adaptive from \
         16 x 8 at target 1e-4"
    );
    let _ = writeln!(
        s,
        "  {:>9} {:<18} {:>8} {:>9} {:>11} {:>9} {:>9} {:>6}",
        "p/Pa", "mesh", "dofs", "wall/s", "jump/K", "error", "estimate", "eff."
    );
    for r in rows {
        let err = (r.jump - r.reference).abs() / r.reference;
        let est = r.estimate.map(|e| e / r.jump);
        let _ = writeln!(
            s,
            "  {:>9.3e} {:<18} {:>8} {:>9.2} {:>11.5} {:>8.2}% {:>9} {:>6}",
            r.pressure,
            r.mesh,
            r.dofs,
            r.wall_s,
            r.jump,
            100.0 * err,
            est.map_or("-".into(), |e| format!("{:.2}%", 100.0 * e)),
            match est {
                Some(e) if !r.mesh.starts_with("reference") && err > 0.0 =>
                    format!("{:.2}", e / err),
                _ => "-".into(),
            }
        );
    }
    s
}

/// Target of the references of [`effectivity_bench`]: the same case adaptive
/// to this relative error (and up to [`crate::sample::case::MAX_LEVELS`]),
/// from a case mesh of [`EFFECTIVITY_REFERENCE_ELEMENTS`] elements along x.
pub const EFFECTIVITY_REFERENCE: f64 = 1.0e-4;

/// Elements along x of the case mesh of the references of
/// [`effectivity_bench`] (the case's counts scaled in proportion). The
/// contact's interior is refined only to a third of the edges' level
/// ([`crate::homogenize::adapt::INTERIOR_LEVEL_RATIO`]), so part of its
/// case-mesh error stays out of the differences between levels: before
/// that rule, deep solves of Westergaard at 0.9 `p*` from 16, 32 and 64
/// elements gave 0.33393, 0.33615, 0.33650 K, each with an estimate near
/// 1e-4 (docs/adaptivity.md). The references start from the finer mesh.
pub const EFFECTIVITY_REFERENCE_ELEMENTS: usize = 64;

/// One point of the estimator's effectivity benchmark ([`effectivity_bench`]).
#[derive(Debug, Clone)]
pub struct EffectivityRow {
    /// `"Sect. 5.7"`, `"Westergaard"` or `"random profile"`.
    pub case: &'static str,
    /// Pressure (Pa).
    pub pressure: f64,
    /// The jump adaptive to the target (K).
    pub jump: f64,
    /// Its estimated error (K).
    pub estimate: f64,
    /// Its unknowns.
    pub dofs: usize,
    /// Whether it met the target.
    pub met: bool,
    /// The reference jump (K): the same case adaptive to [`EFFECTIVITY_REFERENCE`].
    pub reference: f64,
    /// The reference's own estimate (K).
    pub reference_estimate: f64,
    /// Why the point or its reference failed, if one did (then not counted).
    pub failure: Option<String>,
}

impl EffectivityRow {
    /// The true error `|J − J_ref|` (K).
    pub fn error(&self) -> f64 {
        (self.jump - self.reference).abs()
    }

    /// The effectivity index, estimate / true error, where the true error is
    /// resolved by the reference (more than twice the reference's own
    /// estimate); `None` where it is not, or where a solve failed.
    pub fn effectivity(&self) -> Option<f64> {
        (self.failure.is_none() && self.error() > 2.0 * self.reference_estimate)
            .then(|| self.estimate / self.error())
    }
}

/// The distribution of the effectivity indices of a set of points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EffectivitySummary {
    /// Points.
    pub points: usize,
    /// Points whose true error the reference resolves.
    pub resolved: usize,
    /// Median effectivity of the resolved points.
    pub median: f64,
    /// Smallest and largest effectivity.
    pub range: (f64, f64),
    /// Resolved points with an effectivity in the band 0.5–3 (issue 11).
    pub in_band: usize,
    /// Resolved points whose estimate bounds the true error (effectivity ≥ 1).
    pub bounded: usize,
}

impl EffectivitySummary {
    /// The summary of `rows`.
    pub fn of<'a>(rows: impl IntoIterator<Item = &'a EffectivityRow>) -> Self {
        let mut points = 0;
        let mut eff = Vec::new();
        for r in rows {
            points += 1;
            eff.extend(r.effectivity());
        }
        eff.sort_by(f64::total_cmp);
        let n = eff.len();
        let median = match n {
            0 => f64::NAN,
            _ if n % 2 == 1 => eff[n / 2],
            _ => 0.5 * (eff[n / 2 - 1] + eff[n / 2]),
        };
        EffectivitySummary {
            points,
            resolved: n,
            median,
            range: (
                eff.first().copied().unwrap_or(f64::NAN),
                eff.last().copied().unwrap_or(f64::NAN),
            ),
            in_band: eff.iter().filter(|e| (0.5..=3.0).contains(*e)).count(),
            bounded: eff.iter().filter(|e| **e >= 1.0).count(),
        }
    }
}

/// The estimator's effectivity benchmark (`tcgen bench --only effectivity`):
/// every point of three cases adaptive to `target`, against the same case
/// adaptive to [`EFFECTIVITY_REFERENCE`] from a finer case mesh
/// ([`EFFECTIVITY_REFERENCE_ELEMENTS`]; the references' own estimates
/// printed; a true error below twice that is not resolved and not counted):
/// - the Sect. 5.7 sample (two-phase self-consistent, from 16 × 8) along
///   `pressures` pressures of [`MICRO_PRESSURES`];
/// - Westergaard (`A/λ = 5e-4`, small strain, plain two-phase, from 16 × 8)
///   at `WESTERGAARD_LEVELS` of `p*`;
/// - the random profile of the boundary-element check
///   (`generator/tests/data/random_profile.toml`, from 32 × 16) at its four
///   pressures.
pub fn effectivity_bench(target: f64, pressures: usize) -> Result<Vec<EffectivityRow>> {
    use crate::sample::Case;
    if !(target > EFFECTIVITY_REFERENCE && target < 1.0) {
        return Err(Error::invalid(
            "bench.target",
            target,
            format!("a relative error in ({EFFECTIVITY_REFERENCE:e}, 1)"),
        ));
    }
    let path = micro_pressures(pressures)?;
    let mut sect57 = sect57_case(16, path[0], Some(target))?;
    sect57.load.pressures = path;
    let wavy = crate::verify::contact::wavy::WavySample {
        amplitude: 5.0e-9,
        ..Default::default()
    };
    let westergaard = wavy.case(
        &crate::verify::contact::wavy::WESTERGAARD_LEVELS,
        [16, 8],
        [14, 7],
        &format!("target_error = {target:e}"),
        "",
    )?;
    let mut random = Case::from_toml(
        include_str!("../tests/data/random_profile.toml"),
        std::path::Path::new("."),
    )?;
    random.discretization.target_error = Some(target);
    let mut rows = Vec::new();
    for (name, case) in [
        ("Sect. 5.7", sect57),
        ("Westergaard", westergaard),
        ("random profile", random),
    ] {
        let mut deep = case.clone();
        let d = &mut deep.discretization;
        d.target_error = Some(EFFECTIVITY_REFERENCE);
        d.max_levels = crate::sample::case::MAX_LEVELS;
        let factor = (EFFECTIVITY_REFERENCE_ELEMENTS / d.elements_upper.along(0)).max(1);
        d.elements_upper = d.elements_upper.scaled(factor);
        d.elements_lower = d.elements_lower.scaled(factor);
        let points = crate::homogenize::solve_case(&case, None, |_| {})?;
        let references = crate::homogenize::solve_case(&deep, None, |_| {})?;
        for (r, d) in points.iter().zip(&references) {
            let failure = [r, d]
                .iter()
                .find(|x| !x.converged)
                .map(|x| format!("{:?}", x.status));
            rows.push(EffectivityRow {
                case: name,
                pressure: r.pressure,
                jump: r.jump,
                estimate: r.jump_error.unwrap_or(f64::INFINITY),
                dofs: r.dofs,
                met: r.error_target_met == Some(true),
                reference: d.jump,
                reference_estimate: d.jump_error.unwrap_or(f64::INFINITY),
                failure,
            });
        }
    }
    Ok(rows)
}

/// The effectivity benchmark as text: every point, then the distribution
/// per case and over all.
pub fn format_effectivity_bench(target: f64, rows: &[EffectivityRow]) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "effectivity of the two-level estimate at target_error = {target:e}: estimate / true \
         error, the true error against the same case adaptive to {EFFECTIVITY_REFERENCE:e} \
         from {EFFECTIVITY_REFERENCE_ELEMENTS} elements along x (unresolved where below twice \
         the reference's own estimate)"
    );
    let _ = writeln!(
        s,
        "  {:<15} {:>10} {:>6} {:>11} {:>9} {:>4} {:>11} {:>9} {:>9} {:>6}",
        "case", "p/Pa", "dofs", "jump/K", "estimate", "met", "ref/K", "ref.est.", "error", "eff."
    );
    for r in rows {
        let rel = |x: f64| format!("{:.3}%", 100.0 * x / r.reference.abs());
        let _ = writeln!(
            s,
            "  {:<15} {:>10.3e} {:>6} {:>11.5} {:>9} {:>4} {:>11.5} {:>9} {:>9} {:>6}",
            r.case,
            r.pressure,
            r.dofs,
            r.jump,
            rel(r.estimate),
            if r.met { "yes" } else { "NO" },
            r.reference,
            rel(r.reference_estimate),
            rel(r.error()),
            match (&r.failure, r.effectivity()) {
                (Some(_), _) => "FAILED".into(),
                (None, Some(e)) => format!("{e:.2}"),
                (None, None) => "unres.".into(),
            },
        );
        if let Some(f) = &r.failure {
            let _ = writeln!(s, "    failed: {f}");
        }
    }
    let mut names: Vec<&str> = rows.iter().map(|r| r.case).collect();
    names.dedup();
    names.push("all");
    for name in names {
        let e = EffectivitySummary::of(rows.iter().filter(|r| name == "all" || r.case == name));
        let _ = writeln!(
            s,
            "  {name}: {} of {} points resolved; effectivity median {:.2}, range {:.2}–{:.2}; \
             {} in 0.5–3; {} bounded (≥ 1)",
            e.resolved, e.points, e.median, e.range.0, e.range.1, e.in_band, e.bounded
        );
    }
    s
}

/// One row of the 3D direct-solver benchmark (`tcgen bench --only solvers3d`).
#[derive(Clone, Debug)]
pub struct Solver3dRow {
    /// The system: phase, factorization and ordering.
    pub system: &'static str,
    /// Elements per direction of the p = 2 cube.
    pub elements: usize,
    /// Unknowns.
    pub unknowns: usize,
    /// Nonzeros of the matrix.
    pub matrix_nnz: usize,
    /// Nonzeros of the Cholesky factor (`None` for LU: faer does not expose them).
    pub factor_nnz: Option<usize>,
    /// Bytes per factor value: 8, or 4 for the single-precision factor.
    pub factor_value_bytes: usize,
    /// One assembly of the tangent and residual, s.
    pub assembly_s: f64,
    /// Symbolic analysis (ordering and structure), s.
    pub symbolic_s: f64,
    /// Numeric factorization, s.
    pub numeric_s: f64,
    /// Its floating-point operations (`None` for LU: faer does not expose its factor).
    pub factor_flops: Option<f64>,
    /// GMRES iterations and seconds of [`LinearSolver::solve_preconditioned`] on a nearby
    /// matrix (entries scaled by `1 + 0.03 cos(i + j)`, symmetric), preconditioned by the
    /// factorization: what a Newton iteration that keeps the factors pays instead of
    /// `numeric_s` (`None`: no convergence within the Newton budget).
    pub krylov: Option<(usize, f64)>,
}

/// The 3D direct-solver benchmark (issue 12 item 4): the tangent of a
/// p = 2 NURBS cube (warped, `n³` elements, every face fixed) of the
/// mechanical phase (3 fields, SPD), the thermal phase with `k(θ)` (1
/// field, nonsymmetric) and the coupled thermoelastic system (4 fields), each
/// with the factorization the solver picks (Cholesky with nested dissection
/// for SPD, LU with COLAMD otherwise), and the mechanical phase also with its
/// Cholesky factor in single precision ([`crate::solve::linear::FactorPrecision`])
/// and with LU, to measure what each saves. Times are the first numeric
/// factorization on one thread below 20 000 unknowns.
pub fn solver_3d_bench(degree: usize, elements: &[usize]) -> Result<Vec<Solver3dRow>> {
    use crate::bulk::Coupling;
    use crate::solve::linear::FactorPrecision::{Double, Single};
    use crate::solve::{ModelBuilder, NonlinearProblem, Scales};
    let m = crate::material::Material::default();
    let mut rows = Vec::new();
    for &n in elements {
        let mesh = crate::verify::mms::warped_cube_mesh(degree, n)?;
        for (system, coupling, force_lu, precision) in [
            (
                "mechanical, Cholesky + ND",
                Coupling::Mechanical,
                false,
                Double,
            ),
            (
                "mechanical, Cholesky f32",
                Coupling::Mechanical,
                false,
                Single,
            ),
            (
                "mechanical, LU + COLAMD",
                Coupling::Mechanical,
                true,
                Double,
            ),
            (
                "thermal k(θ), LU + COLAMD",
                Coupling::Thermal,
                false,
                Double,
            ),
            ("coupled, LU + COLAMD", Coupling::Coupled, false, Double),
        ] {
            let mut b = ModelBuilder::new(3, Scales::new(1.0, &m));
            let body = b.add_body("cube", &mesh, &m)?;
            // Field indices are global: 0..3 displacement, 3 temperature.
            let fields = match coupling {
                Coupling::Mechanical => 0..3,
                Coupling::Thermal => 3..4,
                Coupling::Coupled => 0..4,
            };
            for dir in 0..3 {
                for side in [crate::geometry::Side::Low, crate::geometry::Side::High] {
                    for f in fields.clone() {
                        b.fix_face(body, dir, side, f, 0.0);
                    }
                }
            }
            let mut model = b.build(coupling)?;
            model.prepare()?;
            model.set_load(1.0);
            let n_eq = model.n_eq();
            let nnz = model.pattern().row_idx().len();
            let mut values = vec![0.0; nnz];
            let mut residual = vec![0.0; n_eq];
            let t = Instant::now();
            model.assemble(Some(&mut values), &mut residual)?;
            let assembly_s = t.elapsed().as_secs_f64();
            let kind = if force_lu {
                Factorization::Lu
            } else {
                model.factorization()
            };
            let ordering = model.ordering(&kind);
            // LU takes both triangles (a symmetric tangent's assembly stores the lower one).
            let full = matches!(kind, Factorization::Lu).then(|| model.full_tangent(&values));
            let (pattern, values) = match &full {
                Some(full) => (full.symbolic(), full.val().to_vec()),
                None => (model.pattern(), values),
            };
            let t = Instant::now();
            let mut solver = LinearSolver::new(pattern, kind, ordering)?;
            solver.set_precision(precision);
            let symbolic_s = t.elapsed().as_secs_f64();
            let t = Instant::now();
            solver.factorize(&values)?;
            let numeric_s = t.elapsed().as_secs_f64();
            let mut nearby = values.clone();
            for j in 0..n_eq {
                for k in pattern.col_range(j) {
                    nearby[k] *= 1.0 + 0.03 * ((pattern.row_idx()[k] + j) as f64).cos();
                }
            }
            let t = Instant::now();
            let krylov = solver
                .solve_preconditioned(&nearby, &mut vec![1.0; n_eq], 25)?
                .map(|iterations| (iterations, t.elapsed().as_secs_f64()));
            rows.push(Solver3dRow {
                system,
                elements: n,
                unknowns: n_eq,
                matrix_nnz: nnz,
                factor_nnz: solver.factor_nnz(),
                factor_value_bytes: solver.precision().value_bytes(),
                assembly_s,
                symbolic_s,
                numeric_s,
                factor_flops: solver.factor_flops(),
                krylov,
            });
        }
    }
    Ok(rows)
}

/// The table of [`solver_3d_bench`].
pub fn format_solver_3d_bench(degree: usize, rows: &[Solver3dRow]) -> String {
    let mut s = format!(
        "3D direct solvers (p = {degree} warped cube, n^3 elements, first factorization)\n\
         system                       n  unknowns   nnz(A)  L values MB  assembly s  symbolic s  numeric s    Gflop  Gflop/s  GMRES (nearby matrix)\n",
    );
    for r in rows {
        let factor = r.factor_nnz.map_or_else(
            || "n/a".to_string(),
            |z| format!("{:.1}", (r.factor_value_bytes * z) as f64 / 1e6),
        );
        let (work, rate) = r.factor_flops.map_or(("n/a".into(), "n/a".into()), |f| {
            (
                format!("{:.2}", f / 1e9),
                format!("{:.1}", f / r.numeric_s / 1e9),
            )
        });
        s.push_str(&format!(
            "{:<27} {:>3} {:>9} {:>8.2e} {:>12} {:>11.3} {:>11.3} {:>10.3} {:>8} {:>8}  {}\n",
            r.system,
            r.elements,
            r.unknowns,
            r.matrix_nnz as f64,
            factor,
            r.assembly_s,
            r.symbolic_s,
            r.numeric_s,
            work,
            rate,
            r.krylov.map_or_else(
                || "no convergence".to_string(),
                |(k, t)| format!("{k} its, {t:.3} s")
            )
        ));
    }
    s
}

/// One pressure of the 3D egg-box benchmark (`tcgen bench --only egg-box`).
#[derive(Clone, Debug)]
pub struct EggBoxBenchRow {
    /// Pressure (Pa).
    pub pressure: f64,
    /// Jump (K).
    pub jump: f64,
    /// Estimated discretization error of the jump (K; adaptive runs).
    pub jump_error: Option<f64>,
    /// Whether the estimate met the target (adaptive runs).
    pub error_target_met: Option<bool>,
    /// Unknowns of the mesh of the jump (the last adaptive level's).
    pub dofs: usize,
    /// Refinement levels (upper, lower body) of that mesh.
    pub levels: [usize; 2],
    /// Contact fraction.
    pub contact_fraction: f64,
    /// Newton iterations of the point (all phases and levels).
    pub newton_iterations: usize,
    /// Self-consistency iterations.
    pub self_consistency_iterations: usize,
    /// Wall time of the point (s).
    pub wall_s: f64,
    /// Why the refinement ended (adaptive runs; printed for the points that
    /// missed the target: [`crate::homogenize::path::PointResult::refinement_stop`]).
    pub refinement_stop: Option<String>,
}

/// The adaptive settings of the 3D benchmark ([`egg_box_case`]).
#[derive(Clone, Copy, Debug)]
pub struct EggBoxAdaptive {
    /// Target relative error of the jump (`--target`).
    pub target: f64,
    /// Refinement levels at most per pressure (`--max-levels`).
    pub max_levels: usize,
    /// Unknowns at most of a level (`--max-dofs`; `None`: the case's, the
    /// default 200 000).
    pub max_dofs: Option<usize>,
    /// Mark the contact-edge elements' neighbours on every level
    /// (`--edge-neighbours`: `[discretization] edge_neighbours = true`; the
    /// 3D default marks them on levels 1–2 only since stop 98, on none in
    /// stops 85–97).
    pub edge_neighbours: bool,
}

/// Refinement levels at most of the 3D benchmark of issue 12 (`tcgen bench
/// --only egg-box`; docs/3d.md, "The benchmark adaptive to 1 %"). Five since
/// stop 86 (four before): with the case's `max_dofs` (200 000) the most
/// accurate run within the targets, 9:22 and 5.5 GB on the 2-core
/// AMD EPYC; its ten jumps are within 0.51 % of a six-level run's
/// (`--max-levels 6 --max-dofs 400000`, every estimate within 1 %), while
/// its own estimates meet 1 % at 5 of 10 pressures (docs/3d.md, "Stop 86").
pub const EGG_BOX_BENCH_MAX_LEVELS: usize = 5;

/// The mesh of the 3D benchmark ([`egg_box_case`]): adaptive, or the
/// case's fixed mesh refined `interface_levels` times at the interface.
#[derive(Clone, Copy, Debug)]
pub enum EggBoxMesh {
    /// Adaptive refinement to a target.
    Adaptive(EggBoxAdaptive),
    /// The case's mesh (`--fixed`), refined at the interface (`--levels`).
    Fixed {
        /// Interface refinement levels.
        interface_levels: usize,
    },
}

impl EggBoxMesh {
    /// From the options of `tcgen bench --only egg-box`: adaptive unless
    /// `fixed`; `--levels` (`interface_levels` above 0) only with `--fixed`,
    /// and `--max-dofs` only without (it bounds the adaptive levels), each
    /// given where it does not apply an error naming it.
    pub fn from_options(
        fixed: bool,
        interface_levels: usize,
        adaptive: EggBoxAdaptive,
    ) -> Result<Self> {
        if !fixed && interface_levels > 0 {
            return Err(Error::invalid(
                "--levels",
                interface_levels,
                "0 unless --fixed (the adaptive benchmark refines by itself)",
            ));
        }
        if fixed && adaptive.edge_neighbours {
            return Err(Error::invalid(
                "--edge-neighbours",
                "given",
                "absent with --fixed (it applies to the adaptive levels)",
            ));
        }
        if fixed && let Some(n) = adaptive.max_dofs {
            return Err(Error::invalid(
                "--max-dofs",
                n,
                "absent with --fixed (it bounds the adaptive levels)",
            ));
        }
        Ok(if fixed {
            EggBoxMesh::Fixed { interface_levels }
        } else {
            EggBoxMesh::Adaptive(adaptive)
        })
    }
}

/// The 3D benchmark case of issue 12: `tables/egg_box_on_flat.toml` (the
/// egg box on a flat, Table I material, p = 2, two-phase self-consistent,
/// 10 pressures from 1 kPa to `p*/2`) on the mesh `mesh`.
pub fn egg_box_case(mesh: EggBoxMesh) -> Result<crate::sample::Case> {
    let mut case = crate::sample::Case::from_toml(
        include_str!("../../tables/egg_box_on_flat.toml"),
        std::path::Path::new("."),
    )?;
    match mesh {
        EggBoxMesh::Adaptive(a) => {
            crate::sample::case::check_target_error("--target", a.target)?;
            crate::sample::case::check_max_levels("--max-levels", a.max_levels)?;
            case.discretization.target_error = Some(a.target);
            case.discretization.max_levels = a.max_levels;
            if a.edge_neighbours {
                case.discretization.edge_neighbours =
                    Some(crate::sample::case::EdgeNeighbours::Every(true));
            }
            if let Some(n) = a.max_dofs {
                crate::sample::case::check_max_dofs("--max-dofs", n)?;
                case.discretization.max_dofs = n;
            }
        }
        EggBoxMesh::Fixed { interface_levels } => {
            case.discretization.interface_levels = interface_levels
        }
    }
    case.validate()?;
    Ok(case)
}

/// The 3D egg-box benchmark: the path of a case (`egg_box_case`), per
/// pressure the jump, its estimate, the unknowns, contact fraction,
/// iterations and wall time; and the time per phase, every adaptive level
/// included.
pub fn egg_box_bench(case: &crate::sample::Case) -> Result<(PhaseCosts, Vec<EggBoxBenchRow>)> {
    let mut solver = crate::homogenize::path::PathSolver::new(case)?;
    let mut rows = Vec::new();
    for &p in &case.load.pressures {
        let t = Instant::now();
        let r = solver.solve_pressure(p)?;
        rows.push(EggBoxBenchRow {
            pressure: p,
            jump: r.jump,
            jump_error: r.jump_error,
            error_target_met: r.error_target_met,
            dofs: r.dofs,
            levels: r.levels,
            contact_fraction: r.interface.contact_fraction,
            newton_iterations: r.newton_iterations,
            self_consistency_iterations: r.self_consistency_iterations,
            wall_s: t.elapsed().as_secs_f64(),
            refinement_stop: r.refinement_stop.clone(),
        });
    }
    Ok((solver.phase_cost(), rows))
}

/// A phase's cost as text: its wall time and Newton iterations, then where
/// the iterations' time went (preparation, residuals, tangents, linear
/// solves) and the time, work and rate of the numeric factorizations among
/// the linear solves (the rate compares machines and days where seconds
/// alone do not).
fn format_phase_cost(c: &PhaseCost) -> String {
    let t = &c.parts;
    let rate = match t.factorizations > 0.0 {
        true => format!(
            ", {:.1} Gflop/s",
            t.factorization_flops / t.factorizations / 1e9
        ),
        false => String::new(),
    };
    format!(
        "{:.1} s ({} Newton iterations: preparation {:.1} s, residuals {:.1} s, tangents {:.1} s, linear solves {:.1} s, of which numeric factorizations {:.1} s, {:.3} Tflop{rate})",
        c.seconds,
        c.newton_iterations,
        t.preparation,
        t.residuals,
        t.tangents,
        t.linear_solves,
        t.factorizations,
        t.factorization_flops / 1e12
    )
}

/// Peak resident memory of this process (bytes; Linux `VmHWM`), if known.
pub fn peak_resident_bytes() -> Option<u64> {
    crate::solve::resources::process_memory("VmHWM:")
}

/// The egg-box benchmark as text: per pressure, then the accuracy reached
/// (the pressures whose estimate met the target, the largest estimate), the
/// wall time per phase and the peak resident memory.
pub fn format_egg_box_bench(
    case: &crate::sample::Case,
    phases: PhaseCosts,
    rows: &[EggBoxBenchRow],
) -> String {
    use std::fmt::Write;
    let d = &case.discretization;
    let mesh = match d.target_error {
        Some(t) => format!(
            "adaptive to {} % with at most {} levels, marking {}",
            100.0 * t,
            d.max_levels,
            d.edge_marks_in(case.dimension())
        ),
        None => format!("fixed mesh, interface_levels = {}", d.interface_levels),
    };
    let mesh = format!("{mesh}{}", d.refinement.clause());
    let mut s = String::new();
    let _ = writeln!(
        s,
        "3D egg box on a flat (tables/egg_box_on_flat.toml, p = 2, two-phase self-consistent), {mesh}"
    );
    let _ = writeln!(
        s,
        "{:>10} {:>10} {:>9} {:>4} {:>8} {:>7} {:>9} {:>7} {:>4} {:>8}",
        "p (Pa)",
        "jump (K)",
        "estimate",
        "met",
        "unknowns",
        "levels",
        "fraction",
        "Newton",
        "SC",
        "wall s"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:>10.4e} {:>10.5} {:>9} {:>4} {:>8} {:>7} {:>9.4} {:>7} {:>4} {:>8.2}",
            r.pressure,
            r.jump,
            r.jump_error
                .map_or("-".into(), |e| format!("{:.2}%", 100.0 * e / r.jump.abs())),
            match r.error_target_met {
                Some(true) => "yes",
                Some(false) => "no",
                None => "-",
            },
            r.dofs,
            format!("{},{}", r.levels[0], r.levels[1]),
            r.contact_fraction,
            r.newton_iterations,
            r.self_consistency_iterations,
            r.wall_s
        );
    }
    if let Some(target) = d.target_error {
        let met = rows
            .iter()
            .filter(|r| r.error_target_met == Some(true))
            .count();
        let largest = rows
            .iter()
            .filter_map(|r| r.jump_error.map(|e| e / r.jump.abs()))
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "accuracy: estimate within {} % at {met} of {} pressures; largest estimate {:.2} % of the jump",
            100.0 * target,
            rows.len(),
            100.0 * largest
        );
        for r in rows.iter().filter(|r| r.error_target_met == Some(false)) {
            let why = r.refinement_stop.as_deref().unwrap_or("no reason recorded");
            let _ = writeln!(s, "  not met at {:.4e} Pa: {why}", r.pressure);
        }
    }
    let total: f64 = rows.iter().map(|r| r.wall_s).sum();
    let _ = write!(
        s,
        "total {total:.1} s; mechanical phase {}, thermal phase {}",
        format_phase_cost(&phases[0]),
        format_phase_cost(&phases[1])
    );
    match peak_resident_bytes() {
        Some(b) => {
            let _ = writeln!(s, "; peak resident memory {:.0} MB", b as f64 / 1e6);
        }
        None => s.push('\n'),
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The adaptive egg-box benchmark reports each point's estimate, levels
    /// and unknowns, and its time per phase counts the Newton iterations of
    /// every level (the refined levels' solvers included) and of the
    /// self-consistency iterations.
    #[test]
    fn egg_box_bench_counts_every_adaptive_level() {
        let adaptive = |target, max_levels, max_dofs| EggBoxAdaptive {
            target,
            max_levels,
            max_dofs,
            edge_neighbours: false,
        };
        let mesh = |fixed, levels, a| EggBoxMesh::from_options(fixed, levels, a);
        let case_of = |a| egg_box_case(EggBoxMesh::Adaptive(a));
        let mut case = case_of(adaptive(0.01, 2, None)).unwrap();
        case.load.pressures = vec![1.0e3];
        let (phases, rows) = egg_box_bench(&case).unwrap();
        let r = &rows[0];
        assert_eq!(r.levels, [2, 2]);
        // Two levels do not resolve a spot of 1 % of the cell to 1 %.
        assert!(r.jump_error.is_some_and(|e| e > 0.01 * r.jump));
        assert_eq!(r.error_target_met, Some(false));
        let counted: usize = phases.iter().map(|p| p.newton_iterations).sum();
        assert_eq!(counted, r.newton_iterations);
        // Every phase factorized at least once (its first iteration); the
        // factorizations are among the linear solves, and the iterations'
        // parts within the phase's time.
        for p in &phases[..2] {
            let t = &p.parts;
            assert!(t.factorization_flops > 0.0, "{p:?}");
            assert!(t.factorizations > 0.0, "{p:?}");
            assert!(t.factorizations <= t.linear_solves, "{p:?}");
            let parts = t.preparation + t.residuals + t.tangents + t.linear_solves;
            assert!(parts > 0.0 && parts <= p.seconds, "{p:?}");
        }
        let text = format_egg_box_bench(&case, phases, &rows);
        assert!(text.contains("at 0 of 1 pressures"), "{text}");
        // The point that missed the target says why: the levels ran out.
        assert_eq!(r.refinement_stop.as_deref(), Some("max_levels"));
        assert!(
            text.contains("not met at 1.0000e3 Pa: max_levels"),
            "{text}"
        );
        assert!(case_of(adaptive(0.0, 4, None)).is_err());
        assert!(case_of(adaptive(0.01, 13, None)).is_err());
        let e = case_of(adaptive(0.01, 4, Some(8))).unwrap_err();
        assert!(e.to_string().contains("--max-dofs"), "{e}");
        let c = case_of(adaptive(0.01, 4, Some(400_000))).unwrap();
        assert_eq!(c.discretization.max_dofs, 400_000);
        // The options that do not apply to the mesh asked for.
        let a = adaptive(0.01, 4, None);
        let e = mesh(false, 1, a).unwrap_err().to_string();
        assert!(e.contains("--levels") && e.contains("--fixed"), "{e}");
        let e = mesh(true, 0, adaptive(0.01, 4, Some(400_000)))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--max-dofs") && e.contains("--fixed"), "{e}");
        // The 3D default marks the edge elements' neighbours on levels 1–2;
        // `--edge-neighbours` on every level, and is refused with `--fixed`.
        let with = EggBoxAdaptive {
            edge_neighbours: true,
            ..a
        };
        let e = mesh(true, 0, with).unwrap_err().to_string();
        assert!(
            e.contains("--edge-neighbours") && e.contains("--fixed"),
            "{e}"
        );
        use crate::sample::case::EdgeNeighbours;
        let c = case_of(a).unwrap();
        assert_eq!(c.discretization.edge_neighbours, None);
        assert_eq!(
            c.discretization.edge_neighbours_in(3),
            EdgeNeighbours::FirstLevels(2)
        );
        let text = format_egg_box_bench(&c, Default::default(), &[]);
        assert!(
            text.contains("elements, with their neighbours on levels 1–2"),
            "{text}"
        );
        let c = case_of(with).unwrap();
        assert_eq!(
            c.discretization.edge_neighbours,
            Some(EdgeNeighbours::Every(true))
        );
        let text = format_egg_box_bench(&c, Default::default(), &[]);
        assert!(text.contains("elements and their neighbours"), "{text}");
        let c = egg_box_case(mesh(true, 1, a).unwrap()).unwrap();
        assert_eq!(c.discretization.interface_levels, 1);
        assert_eq!(c.discretization.target_error, None);
        assert!(matches!(
            mesh(false, 0, a).unwrap(),
            EggBoxMesh::Adaptive(_)
        ));
    }

    /// The effectivity summary counts only resolved points of converged
    /// solves: its median, band and bound follow the indices.
    #[test]
    fn effectivity_summary_counts_resolved_points() {
        let row = |jump: f64, estimate: f64, failure: Option<&str>| EffectivityRow {
            case: "test",
            pressure: 1.0,
            jump,
            estimate,
            dofs: 10,
            met: true,
            reference: 10.0,
            reference_estimate: 0.001,
            failure: failure.map(str::to_string),
        };
        let rows = [
            row(10.01, 0.02, None),    // 2
            row(10.1, 0.04, None),     // 0.4
            row(9.99, 0.05, None),     // 5
            row(10.0015, 0.02, None),  // unresolved (below twice 0.001)
            row(10.1, 0.1, Some("x")), // failed
            row(10.02, 0.02, None),    // 1
        ];
        assert_eq!(rows[3].effectivity(), None);
        assert_eq!(rows[4].effectivity(), None);
        let e = EffectivitySummary::of(&rows);
        assert_eq!((e.points, e.resolved, e.in_band, e.bounded), (6, 4, 2, 3));
        assert!((e.median - 1.5).abs() < 1e-9, "{}", e.median);
        assert!((e.range.0 - 0.4).abs() < 1e-9 && (e.range.1 - 5.0).abs() < 1e-9);
        let none = EffectivitySummary::of(&rows[3..5]);
        assert_eq!(none.resolved, 0);
        assert!(none.median.is_nan());
    }

    /// The 3D benchmark runs on a small cube: the unknowns are the interior
    /// control points (every face fixed) times the fields, and the SPD
    /// mechanical system gets its Cholesky factor, in f64 and in f32.
    #[test]
    fn solver_3d_bench_counts_the_interior_unknowns() {
        let rows = solver_3d_bench(2, &[4]).unwrap();
        let interior = (4 + 2 - 2usize).pow(3);
        let unknowns: Vec<usize> = rows.iter().map(|r| r.unknowns).collect();
        assert_eq!(
            unknowns,
            vec![
                3 * interior,
                3 * interior,
                3 * interior,
                interior,
                4 * interior
            ]
        );
        assert!(rows[0].factor_nnz.is_some_and(|z| z >= rows[0].unknowns));
        // The single-precision row: the same factor, half the bytes per value.
        assert_eq!(rows[1].factor_nnz, rows[0].factor_nnz);
        assert_eq!(
            (rows[0].factor_value_bytes, rows[1].factor_value_bytes),
            (8, 4)
        );
        assert!(rows[2].factor_nnz.is_none());
        for r in &rows {
            assert!(
                r.krylov.is_some_and(|(k, _)| (1..=25).contains(&k)),
                "{}: {:?}",
                r.system,
                r.krylov
            );
        }
        let table = format_solver_3d_bench(2, &rows);
        assert!(
            table.contains("coupled, LU + COLAMD") && table.contains("n/a"),
            "{table}"
        );
    }
}
