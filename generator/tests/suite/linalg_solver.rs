//! Sparse direct solvers (`solve::linear`), nested dissection (`solve::ordering`) and a smoke
//! test of the benchmark (`bench`).

use proptest::prelude::*;
use tcgen::Error;
use tcgen::bulk::global::{Assembly, Storage};
use tcgen::solve::linear::{
    FactorPrecision, Factorization, KRYLOV_TOLERANCE, LinearSolver, Ordering,
};
use tcgen::solve::ordering::{
    approximate_minimum_degree, factor_entries, fewest_entries_postordered, is_permutation,
    multipliers_after_neighbours, nested_dissection, node_minimum_degree, node_orders,
    node_orders_kept, postordered,
};

/// A Q1 grid of nx × ny nodes with `fields` unknowns per node, optionally followed by one
/// Lagrange multiplier per top-edge node coupled to that edge's field-0 unknowns.
struct GridSystem {
    assembly: Assembly,
    coords: Vec<[f64; 3]>,
    n_primal: usize,
    n_bulk: usize,
}

impl GridSystem {
    fn new(nx: usize, ny: usize, fields: usize, multipliers: bool) -> Self {
        Self::new_stored(nx, ny, fields, multipliers, Storage::Full)
    }

    /// [`GridSystem::new`], its assembly storing `storage`'s entries.
    fn new_stored(
        nx: usize,
        ny: usize,
        fields: usize,
        multipliers: bool,
        storage: Storage,
    ) -> Self {
        let n_primal = nx * ny * fields;
        let mut element_eqs: Vec<Vec<Option<usize>>> = Vec::new();
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let mut eqs = Vec::new();
                for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    eqs.extend((0..fields).map(|f| Some(((j + dj) * nx + i + di) * fields + f)));
                }
                element_eqs.push(eqs);
            }
        }
        let n_bulk = element_eqs.len();
        let mut coords: Vec<[f64; 3]> = (0..n_primal)
            .map(|k| [((k / fields) % nx) as f64, ((k / fields) / nx) as f64, 0.0])
            .collect();
        let mut n_eq = n_primal;
        if multipliers {
            for i in 0..nx - 1 {
                let top = |di: usize| ((ny - 1) * nx + i + di) * fields;
                element_eqs.push(vec![
                    Some(top(0)),
                    Some(top(1)),
                    Some(n_primal + i),
                    Some(n_primal + i + 1),
                ]);
            }
            coords.extend((0..nx).map(|i| [i as f64, (ny - 1) as f64, 0.0]));
            n_eq += nx;
        }
        Self {
            assembly: Assembly::new_stored(n_eq, element_eqs, storage),
            coords,
            n_primal,
            n_bulk,
        }
    }

    /// Assembles: bulk = `stiffness`·(∇N·∇N) + `shift`·N N per field, plus `advection`
    /// (nonsymmetric, field 0 ↔ last field coupling and convection); multiplier segments
    /// couple through the 1D mass matrix [2 1; 1 2]/6.
    fn assemble(&self, stiffness: f64, shift: f64, advection: f64) -> (Vec<f64>, Vec<f64>) {
        let mut values = vec![0.0; self.assembly.nnz()];
        let mut rhs = vec![0.0; self.assembly.n_eq()];
        let q1_grad = [[-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]];
        let q1_stiff = |a: usize, b: usize| {
            // exact ∫∇Na·∇Nb on the unit square: 2/3 diagonal, −1/6 edge, −1/3 opposite
            match (a == b, (a ^ b) == 3) {
                (true, _) => 2.0 / 3.0,
                (false, true) => -1.0 / 3.0,
                _ => -1.0 / 6.0,
            }
        };
        let q1_mass = |a: usize, b: usize| match (a == b, (a ^ b) == 3) {
            (true, _) => 4.0 / 36.0,
            (false, true) => 1.0 / 36.0,
            _ => 2.0 / 36.0,
        };
        self.assembly
            .assemble(&mut values, &mut rhs, |e, k, r| {
                let m = r.len();
                if e >= self.n_bulk {
                    for (a, b, v) in [(0, 2, 2.0), (0, 3, 1.0), (1, 2, 1.0), (1, 3, 2.0)] {
                        k[b * m + a] = v / 6.0;
                        k[a * m + b] = v / 6.0;
                    }
                    return Ok(());
                }
                let fields = m / 4;
                for a in 0..4 {
                    for b in 0..4 {
                        for f in 0..fields {
                            let w = 1.0 + 0.1 * f as f64 + 0.05 * ((e * 7) % 5) as f64;
                            k[(b * fields + f) * m + a * fields + f] +=
                                w * stiffness * q1_stiff(a, b) + shift * q1_mass(a, b);
                        }
                        if advection != 0.0 {
                            // convection ∫ Na ∂x Nb (≈ ¼ ∂x Nb at the centre) and a one-way coupling
                            let conv = 0.25 * q1_grad[b][0] * 0.5;
                            k[(b * fields) * m + a * fields] += advection * conv;
                            k[(b * fields) * m + a * fields + fields - 1] +=
                                advection * q1_mass(a, b);
                        }
                    }
                    for f in 0..fields {
                        r[a * fields + f] = 0.25 * (1.0 + ((e * 13 + a * 3 + f) % 7) as f64);
                    }
                }
                Ok(())
            })
            .unwrap();
        (values, rhs)
    }

    fn signs(&self) -> Vec<i8> {
        (0..self.assembly.n_eq())
            .map(|i| if i < self.n_primal { 1 } else { -1 })
            .collect()
    }
}

/// b − Ax with A the full CSC matrix, and the row sums of |A|.
fn residual(assembly: &Assembly, values: &[f64], x: &[f64], b: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let pattern = assembly.symbolic();
    let mut r = b.to_vec();
    let mut row_sums = vec![0.0f64; b.len()];
    for (j, &xj) in x.iter().enumerate() {
        for k in pattern.col_range(j) {
            r[pattern.row_idx()[k]] -= values[k] * xj;
            row_sums[pattern.row_idx()[k]] += values[k].abs();
        }
    }
    (r, row_sums)
}

/// ‖Ax − b‖₂ / ‖b‖₂ with A the full CSC matrix.
fn relative_residual(assembly: &Assembly, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let (r, _) = residual(assembly, values, x, b);
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    norm(&r) / norm(b)
}

/// An SPD system (Cholesky), a saddle point with multipliers (LDLᵀ) and a nonsymmetric system
/// (LU, with its advection factor).
fn three_kinds() -> [(GridSystem, Factorization, f64); 3] {
    let saddle = GridSystem::new(20, 14, 2, true);
    let signs = saddle.signs();
    [
        (
            GridSystem::new(25, 20, 1, false),
            Factorization::Cholesky,
            0.0,
        ),
        (saddle, Factorization::Ldlt { signs }, 0.0),
        (GridSystem::new(20, 14, 3, false), Factorization::Lu, 2.0),
    ]
}

fn solve(solver: &mut LinearSolver, b: &[f64]) -> Vec<f64> {
    let mut x = b.to_vec();
    solver.solve_in_place(&mut x).unwrap();
    x
}

/// Cholesky of an SPD grid Laplacian + mass solves to a relative residual ≤ 1e−12 with
/// faer's AMD and with nested dissection.
#[test]
fn cholesky_solves_spd_system_with_default_and_nd_orderings() {
    let system = GridSystem::new(40, 30, 1, false);
    let (values, rhs) = system.assemble(1.0, 0.01, 0.0);
    for ordering in [
        Ordering::Default,
        Ordering::Custom(nested_dissection(
            system.assembly.symbolic(),
            &system.coords,
        )),
    ] {
        let mut solver = LinearSolver::new(
            system.assembly.symbolic(),
            Factorization::Cholesky,
            ordering.clone(),
        )
        .unwrap();
        solver.factorize(&values).unwrap();
        let x = solve(&mut solver, &rhs);
        let res = relative_residual(&system.assembly, &values, &x, &rhs);
        assert!(res < 1e-12, "Cholesky {ordering:?}: residual {res:e}");
        assert!(solver.factor_nnz().unwrap() >= system.assembly.nnz() / 2);
    }
}

/// A solver on the assembly's shared pattern (`LinearSolver::with_pattern`) holds that pattern,
/// not a copy, and solves each of the three kinds to the bit as one on a copy (`new`).
#[test]
fn a_shared_pattern_is_held_not_copied_and_solves_the_same() {
    for (system, kind, advection) in three_kinds() {
        let (values, rhs) = system.assemble(1.0, 0.01, advection);
        let pattern = system.assembly.shared_pattern();
        let before = std::sync::Arc::strong_count(&pattern);
        let mut shared =
            LinearSolver::with_pattern(pattern.clone(), kind.clone(), Ordering::Default).unwrap();
        assert_eq!(std::sync::Arc::strong_count(&pattern), before + 1);
        let mut copied =
            LinearSolver::new(system.assembly.symbolic(), kind, Ordering::Default).unwrap();
        assert!(shared.analyses(system.assembly.symbolic()));
        shared.factorize(&values).unwrap();
        copied.factorize(&values).unwrap();
        let (x, y) = (solve(&mut shared, &rhs), solve(&mut copied, &rhs));
        assert!(x.iter().zip(&y).all(|(a, b)| a.to_bits() == b.to_bits()));
        drop(shared);
        assert_eq!(std::sync::Arc::strong_count(&pattern), before);
    }
}

/// LDLᵀ of the saddle point [K Bᵀ; B 0] (K SPD, multiplier rows with zero diagonal) solves
/// to ≤ 1e−12 with AMD and nested dissection; each multiplier is eliminated after the
/// displacements it couples to.
#[test]
fn ldlt_solves_saddle_point_with_default_and_nd_orderings() {
    let system = GridSystem::new(36, 24, 2, true);
    let (values, rhs) = system.assemble(1.0, 0.01, 0.0);
    let signs = system.signs();
    let nd = nested_dissection(system.assembly.symbolic(), &system.coords);
    for ordering in [
        Ordering::Default,
        Ordering::Custom(nd.clone()),
        Ordering::FewerEntries(nd),
    ] {
        let kind = Factorization::Ldlt {
            signs: signs.clone(),
        };
        let mut solver =
            LinearSolver::new(system.assembly.symbolic(), kind, ordering.clone()).unwrap();
        solver.factorize(&values).unwrap();
        let x = solve(&mut solver, &rhs);
        let res = relative_residual(&system.assembly, &values, &x, &rhs);
        assert!(res < 1e-12, "LDLT {ordering:?}: residual {res:e}");
        assert_eq!(solver.fallback(), None, "quasi-definite: no fallback");
        // the multipliers are active: the solution has a nonzero multiplier block
        assert!(x[system.n_primal..].iter().any(|l| l.abs() > 1e-8));
        let perm = solver.permutation();
        let mut position = vec![0; perm.len()];
        for (new, &old) in perm.iter().enumerate() {
            position[old] = new;
        }
        let pattern = system.assembly.symbolic();
        for m in system.n_primal..system.assembly.n_eq() {
            for &u in &pattern.row_idx()[pattern.col_range(m)] {
                if u < system.n_primal {
                    assert!(
                        position[u] < position[m],
                        "multiplier {m} eliminated before displacement {u}"
                    );
                }
            }
        }
    }
}

/// An LDLᵀ with an indefinite primal block keeps its pivots of the other sign (exact, counted);
/// one with a zero pivot in its ordering (regularized by faer) is replaced by LU: the solution
/// is exact, the reason is reported, and the next values use LDLᵀ again.
#[test]
fn ldlt_keeps_indefinite_pivots_and_falls_back_to_lu_on_zero_ones() {
    let system = GridSystem::new(16, 12, 2, true);
    let (indefinite, rhs) = system.assemble(1.0, -5.0, 0.0);
    let (good, _) = system.assemble(1.0, 0.01, 0.0);
    let kind = Factorization::Ldlt {
        signs: system.signs(),
    };
    let nd = nested_dissection(system.assembly.symbolic(), &system.coords);
    let mut solver =
        LinearSolver::new(system.assembly.symbolic(), kind, Ordering::Custom(nd)).unwrap();
    solver.factorize(&indefinite).unwrap();
    assert_eq!(solver.fallback(), None);
    assert!(solver.sign_mismatches() > 0);
    let x = solve(&mut solver, &rhs);
    let res = relative_residual(&system.assembly, &indefinite, &x, &rhs);
    assert!(res < 1e-12, "indefinite LDLT: residual {res:e}");
    solver.factorize(&good).unwrap();
    assert_eq!((solver.fallback(), solver.sign_mismatches()), (None, 0));

    // [0 1; 1 0] in the natural order: the first pivot is zero.
    let pattern = faer::sparse::SymbolicSparseColMat::new_checked(
        2,
        2,
        vec![0, 2, 4],
        None,
        vec![0, 1, 0, 1],
    );
    let kind = Factorization::Ldlt { signs: vec![1, -1] };
    let mut solver =
        LinearSolver::new(pattern.as_ref(), kind, Ordering::Custom(vec![0, 1])).unwrap();
    let values = [0.0, 1.0, 1.0, 0.0];
    for round in 1..=2 {
        solver.factorize(&values).unwrap();
        let reason = solver.fallback().expect("a zero pivot falls back");
        assert!(reason.contains("regularized"), "{reason}");
        let mut x = vec![2.0, 3.0];
        solver.solve_in_place(&mut x).unwrap();
        assert_eq!(x, [3.0, 2.0]);
        assert_eq!(solver.fallbacks(), round);
    }
    solver.factorize(&[1.0, 1.0, 1.0, -1.0]).unwrap();
    assert_eq!(solver.fallback(), None);
}

/// A symmetric system stored as its lower triangle ([`Storage::Lower`]): the
/// assembly holds exactly the full assembly's entries from each node's first
/// equation down (to the bit: the nodes' diagonal blocks whole, the others
/// below the diagonal) and mirrors them back ([`Assembly::full_matrix`]);
/// Cholesky and LDLᵀ (with multipliers, nested dissection) on it have the
/// full pattern's ordering and factor and solve the same, GMRES on its
/// products takes the same iterations to the same solution, and its fallback
/// LU (a zero pivot) solves the full matrix.
#[test]
fn a_lower_triangle_solves_as_both_triangles() {
    for (fields, multipliers) in [(1, false), (2, true)] {
        let full = GridSystem::new(24, 18, fields, multipliers);
        let lower = GridSystem::new_stored(24, 18, fields, multipliers, Storage::Lower);
        assert_eq!(lower.assembly.storage(), Storage::Lower);
        let (fv, rhs) = full.assemble(1.0, 0.02, 0.0);
        let (lv, lrhs) = lower.assemble(1.0, 0.02, 0.0);
        assert_eq!(rhs, lrhs);
        let (fp, lp) = (full.assembly.symbolic(), lower.assembly.symbolic());
        // Each column from its group's first equation on (the consecutive equations with the
        // same rows: a node's fields, but for those a multiplier couples), each entry the full
        // assembly's to the bit.
        let rows = |j: usize| &fp.row_idx()[fp.col_range(j)];
        for j in 0..fp.ncols() {
            let mut node_first = j;
            while node_first > 0 && rows(node_first - 1) == rows(j) {
                node_first -= 1;
            }
            if j < full.n_primal && rows(j).len() > 1 {
                assert!(j - node_first < fields, "column {j}");
            }
            let below: Vec<(usize, u64)> = fp
                .col_range(j)
                .filter(|&k| fp.row_idx()[k] >= node_first)
                .map(|k| (fp.row_idx()[k], fv[k].to_bits()))
                .collect();
            let stored: Vec<(usize, u64)> = lp
                .col_range(j)
                .map(|k| (lp.row_idx()[k], lv[k].to_bits()))
                .collect();
            assert_eq!(stored, below, "column {j}");
        }
        assert!(
            2 * lv.len() < fv.len() + 4 * fp.ncols(),
            "about half the entries"
        );
        let above = (0..lp.ncols())
            .flat_map(|j| {
                lp.row_idx()[lp.col_range(j)]
                    .iter()
                    .filter(move |&&i| i < j)
            })
            .count();
        assert_eq!(above > 0, fields > 1, "the nodes' diagonal blocks whole");
        // The columns of a node share their run lists.
        assert!(lower.assembly.scatter_map_bytes() < full.assembly.scatter_map_bytes());
        let mirrored = lower.assembly.full_matrix(&lv);
        assert_eq!(mirrored.symbolic().col_ptr(), fp.col_ptr());
        assert_eq!(mirrored.symbolic().row_idx(), fp.row_idx());
        assert_eq!(mirrored.val(), fv.as_slice());

        let kind = match multipliers {
            true => Factorization::Ldlt {
                signs: full.signs(),
            },
            false => Factorization::Cholesky,
        };
        let nd = |s: &GridSystem| nested_dissection(s.assembly.symbolic(), &s.coords);
        assert_eq!(nd(&full), nd(&lower), "the same nested dissection");
        let factorized = |s: &GridSystem, values: &[f64]| {
            let mut solver =
                LinearSolver::new(s.assembly.symbolic(), kind.clone(), Ordering::Custom(nd(s)))
                    .unwrap();
            solver.factorize(values).unwrap();
            assert_eq!(solver.fallback(), None);
            solver
        };
        let (mut a, mut b) = (factorized(&full, &fv), factorized(&lower, &lv));
        assert_eq!(a.permutation(), b.permutation());
        assert_eq!(a.factor_nnz(), b.factor_nnz());
        let (x, y) = (solve(&mut a, &rhs), solve(&mut b, &rhs));
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (p, q) in x.iter().zip(&y) {
            assert!((p - q).abs() <= 1e-12 * scale, "{p} vs {q}");
        }
        assert!(relative_residual(&full.assembly, &fv, &y, &rhs) < 1e-12);

        // A nearby symmetric matrix by GMRES on the factors.
        let nearby = |s: &GridSystem, values: &[f64]| -> Vec<f64> {
            let p = s.assembly.symbolic();
            let mut v = values.to_vec();
            for j in 0..p.ncols() {
                for k in p.col_range(j) {
                    v[k] *= 1.0 + 0.05 * ((p.row_idx()[k] + j) as f64).cos();
                }
            }
            v
        };
        let (fn_, ln) = (nearby(&full, &fv), nearby(&lower, &lv));
        let (mut x, mut y) = (rhs.clone(), rhs.clone());
        let ia = a.solve_preconditioned(&fn_, &mut x, 60).unwrap();
        let ib = b.solve_preconditioned(&ln, &mut y, 60).unwrap();
        assert!(ia.is_some_and(|i| i > 1), "{ia:?}");
        assert_eq!(ia, ib);
        for (p, q) in x.iter().zip(&y) {
            assert!((p - q).abs() <= 1e-9 * scale, "{p} vs {q}");
        }
        assert!(relative_residual(&full.assembly, &fn_, &y, &rhs) < 1e-10);
        // Factors of one storage do not precondition a pattern of the other (its product
        // would be misread): the caller factorizes instead.
        let (mut x, mut y) = (rhs.clone(), rhs.clone());
        let lower_on_full = b.solve_preconditioned_on(fp, &fn_, &mut x, 60, KRYLOV_TOLERANCE);
        let full_on_lower = a.solve_preconditioned_on(lp, &ln, &mut y, 60, KRYLOV_TOLERANCE);
        assert_eq!(
            (lower_on_full.unwrap(), full_on_lower.unwrap()),
            (None, None)
        );
        assert_eq!(
            (x, y),
            (rhs.clone(), rhs.clone()),
            "right-hand sides unchanged"
        );
    }

    // [0 1; 1 0] as its lower triangle: the first pivot is zero, and LU solves
    // the full matrix; as the lower triangle of a 2 × 2 block with a third
    // equation coupled to it (so that the pattern is a lower one), the same.
    let pattern =
        faer::sparse::SymbolicSparseColMat::new_checked(2, 2, vec![0, 2, 3], None, vec![0, 1, 1]);
    let kind = Factorization::Ldlt { signs: vec![1, -1] };
    let mut solver =
        LinearSolver::new(pattern.as_ref(), kind, Ordering::Custom(vec![0, 1])).unwrap();
    solver.factorize(&[0.0, 1.0, 0.0]).unwrap();
    assert!(solver.fallback().is_some_and(|r| r.contains("regularized")));
    let mut x = vec![2.0, 3.0];
    solver.solve_in_place(&mut x).unwrap();
    assert_eq!(x, [3.0, 2.0]);
    // [0 1 1; 1 0 0; 1 0 2] with the block of equations 0, 1 whole.
    let pattern = faer::sparse::SymbolicSparseColMat::new_checked(
        3,
        3,
        vec![0, 3, 5, 6],
        None,
        vec![0, 1, 2, 0, 1, 2],
    );
    assert!(tcgen::solve::linear::stores_lower(pattern.as_ref()));
    let values = [0.0, 1.0, 1.0, 1.0, 0.0, 2.0];
    let kind = Factorization::Ldlt {
        signs: vec![1, -1, 1],
    };
    let mut solver =
        LinearSolver::new(pattern.as_ref(), kind, Ordering::Custom(vec![0, 1, 2])).unwrap();
    solver.factorize(&values).unwrap();
    assert!(solver.fallback().is_some());
    // x = (1, 2, 3): b = (0·1 + 2 + 3, 1, 1 + 6).
    let mut x = vec![5.0, 1.0, 7.0];
    solver.solve_in_place(&mut x).unwrap();
    for (a, b) in x.iter().zip([1.0, 2.0, 3.0]) {
        assert!((a - b).abs() < 1e-14, "{x:?}");
    }
}

/// The multipliers' couplings are read from a lower triangle as from both.
#[test]
fn multipliers_follow_their_displacements_from_a_lower_triangle() {
    let full = GridSystem::new(12, 9, 2, true);
    let lower = GridSystem::new_stored(12, 9, 2, true, Storage::Lower);
    let signs = full.signs();
    let n = signs.len();
    for perm in [(0..n).rev().collect::<Vec<_>>(), (0..n).collect()] {
        assert_eq!(
            multipliers_after_neighbours(full.assembly.symbolic(), perm.clone(), &signs),
            multipliers_after_neighbours(lower.assembly.symbolic(), perm, &signs)
        );
    }
}

/// Supernodal LU of a nonsymmetric 3-field system solves to ≤ 1e−12.
#[test]
fn lu_solves_nonsymmetric_system() {
    let system = GridSystem::new(30, 20, 3, false);
    let (values, rhs) = system.assemble(1.0, 0.05, 2.0);
    let mut solver = LinearSolver::new(
        system.assembly.symbolic(),
        Factorization::Lu,
        Ordering::Default,
    )
    .unwrap();
    solver.factorize(&values).unwrap();
    let x = solve(&mut solver, &rhs);
    let res = relative_residual(&system.assembly, &values, &x, &rhs);
    assert!(res < 1e-12, "LU residual {res:e}");
    assert_eq!(solver.factor_nnz(), None);
    assert!(is_permutation(
        &solver.permutation(),
        system.assembly.n_eq()
    ));
}

/// Refactorizing with new values (same pattern) reuses the symbolic analysis and gives the
/// same solution as a fresh solver, for LU, Cholesky and LDLᵀ.
#[test]
fn refactorization_with_new_values_matches_a_fresh_factorization() {
    for (system, kind, advection) in &three_kinds() {
        let (kind, advection) = (kind.clone(), *advection);
        let (v1, b1) = system.assemble(1.0, 0.01, advection);
        let (v2, b2) = system.assemble(3.5, 0.2, 0.7 * advection);
        let mut solver =
            LinearSolver::new(system.assembly.symbolic(), kind.clone(), Ordering::Default).unwrap();
        solver.factorize(&v1).unwrap();
        let x1 = solve(&mut solver, &b1);
        solver.factorize(&v2).unwrap();
        let x2 = solve(&mut solver, &b2);
        let res = relative_residual(&system.assembly, &v2, &x2, &b2);
        assert!(
            res < 1e-12,
            "{kind:?} after refactorization: residual {res:e}"
        );
        assert!(
            x1.iter().zip(&x2).any(|(a, b)| (a - b).abs() > 1e-3),
            "new values must change the solution"
        );
        let mut fresh =
            LinearSolver::new(system.assembly.symbolic(), kind.clone(), Ordering::Default).unwrap();
        fresh.factorize(&v2).unwrap();
        let x_fresh = solve(&mut fresh, &b2);
        let scale = x_fresh.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for (a, b) in x2.iter().zip(&x_fresh) {
            assert!(
                (a - b).abs() <= 1e-10 * scale,
                "{kind:?}: refactorized {a} vs fresh {b}"
            );
        }
    }
}

/// GMRES preconditioned by the factors of an earlier matrix of the same pattern solves a nearby
/// matrix (a Newton tangent a few percent away) to the Krylov tolerance in a few iterations,
/// leaves the factors and the kept matrix alone (a direct solve afterwards still solves the
/// factorized matrix), and gives up (`None`, right-hand side unchanged) on a matrix far away
/// within a small iteration budget, or without factors.
#[test]
fn gmres_preconditioned_by_an_earlier_factorization() {
    for (system, kind, advection) in &three_kinds() {
        let (kind, advection) = (kind.clone(), *advection);
        let (v1, b1) = system.assemble(1.0, 0.01, advection);
        let (near, b2) = system.assemble(1.03, 0.0103, 1.02 * advection);
        let (far, _) = system.assemble(8.0, 3.0, 0.1 * advection);
        let mut solver =
            LinearSolver::new(system.assembly.symbolic(), kind.clone(), Ordering::Default).unwrap();
        let mut x = b2.clone();
        assert_eq!(
            solver.solve_preconditioned(&near, &mut x, 40).unwrap(),
            None,
            "{kind:?}: no factors yet"
        );
        assert_eq!(x, b2, "{kind:?}: unchanged without factors");
        solver.factorize(&v1).unwrap();
        let x1_before = solve(&mut solver, &b1);
        let iterations = solver
            .solve_preconditioned(&near, &mut x, 40)
            .unwrap()
            .unwrap_or_else(|| panic!("{kind:?}: GMRES on the nearby matrix"));
        let res = relative_residual(&system.assembly, &near, &x, &b2);
        assert!(
            res <= tcgen::solve::linear::KRYLOV_TOLERANCE,
            "{kind:?}: residual {res:e}"
        );
        assert!(
            (1..=12).contains(&iterations),
            "{kind:?}: {iterations} iterations"
        );
        // the factors and the kept matrix are still those of v1
        assert_eq!(
            solve(&mut solver, &b1),
            x1_before,
            "{kind:?}: factors changed"
        );
        let mut y = b2.clone();
        assert_eq!(
            solver.solve_preconditioned(&far, &mut y, 2).unwrap(),
            None,
            "{kind:?}: two iterations on a matrix far away"
        );
        assert_eq!(y, b2, "{kind:?}: unchanged when GMRES gives up");
    }
}

/// A factorization of an owned matrix solves as one of a borrowed one; once the matrix is
/// released the factors still precondition GMRES (to a looser tolerance in no more
/// iterations, and fewer in all: 1, 2 and 3 against 1, 2 and 6), a direct solve is refused with an error, the storage shrinks by the matrix,
/// and the next factorization solves again.
#[test]
fn a_released_matrix_leaves_the_factors_for_gmres() {
    use tcgen::solve::linear::KRYLOV_TOLERANCE;
    let mut fewer = 0;
    for (system, kind, advection) in &three_kinds() {
        let (kind, advection) = (kind.clone(), *advection);
        let (v1, b1) = system.assemble(1.0, 0.01, advection);
        let (near, b2) = system.assemble(1.03, 0.0103, 1.02 * advection);
        let pattern = system.assembly.symbolic();
        let mut borrowed = LinearSolver::new(pattern, kind.clone(), Ordering::Default).unwrap();
        borrowed.factorize(&v1).unwrap();
        let mut owned = LinearSolver::new(pattern, kind.clone(), Ordering::Default).unwrap();
        owned.factorize_owned(v1.clone()).unwrap();
        assert_eq!(
            solve(&mut owned, &b1),
            solve(&mut borrowed, &b1),
            "{kind:?}"
        );
        let kept = owned.storage_bytes();
        owned.release_matrix();
        assert!(
            owned.storage_bytes() + 8 * v1.len() <= kept,
            "{kind:?}: {} of {kept} bytes kept",
            owned.storage_bytes()
        );
        let mut x = b1.clone();
        assert!(owned.solve_in_place(&mut x).is_err(), "{kind:?}: released");
        let solve_to = |tolerance: f64| {
            let mut x = b2.clone();
            let iterations = owned
                .solve_preconditioned_on(pattern, &near, &mut x, 40, tolerance)
                .unwrap()
                .unwrap_or_else(|| panic!("{kind:?}: GMRES to {tolerance:e}"));
            let res = relative_residual(&system.assembly, &near, &x, &b2);
            assert!(
                res <= tolerance,
                "{kind:?}: residual {res:e} for {tolerance:e}"
            );
            iterations
        };
        let (tight, loose) = (solve_to(KRYLOV_TOLERANCE), solve_to(1e-4));
        assert!(
            loose <= tight,
            "{kind:?}: {loose} against {tight} iterations"
        );
        fewer += tight - loose;
        owned.factorize(&near).unwrap();
        let mut x = b2.clone();
        owned.solve_in_place(&mut x).unwrap();
        let res = relative_residual(&system.assembly, &near, &x, &b2);
        assert!(res <= 1e-10, "{kind:?}: refactorized, residual {res:e}");
    }
    assert!(fewer > 0, "a looser tolerance takes fewer iterations");
}

/// Factors of one pattern precondition GMRES on a nearby matrix of another pattern of the
/// same equations (here without the couplings of the first column, as a contact pattern
/// loses a node's when it leaves the active set): the true residual on the new pattern meets
/// the tolerance, and a pattern of other dimensions is refused.
#[test]
fn gmres_on_another_pattern_of_the_same_equations() {
    use faer::sparse::SymbolicSparseColMat;
    for (system, kind, advection) in &three_kinds() {
        let (kind, advection) = (kind.clone(), *advection);
        let (v1, _) = system.assemble(1.0, 0.01, advection);
        let (near, b) = system.assemble(1.03, 0.0103, 1.02 * advection);
        let old = system.assembly.symbolic();
        let n = old.ncols();
        // Drop every off-diagonal entry of row and column 0.
        let keep = |i: usize, j: usize| i == j || (i != 0 && j != 0);
        let (mut col_ptr, mut row_idx, mut values) = (vec![0], Vec::new(), Vec::new());
        for j in 0..n {
            for k in old.col_range(j) {
                let i = old.row_idx()[k];
                if keep(i, j) {
                    row_idx.push(i);
                    values.push(near[k]);
                }
            }
            col_ptr.push(row_idx.len());
        }
        assert!(
            row_idx.len() < old.row_idx().len(),
            "{kind:?}: a smaller pattern"
        );
        let new = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        let mut solver = LinearSolver::new(old, kind.clone(), Ordering::Default).unwrap();
        solver.factorize(&v1).unwrap();
        let mut x = b.clone();
        let iterations = solver
            .solve_preconditioned_on(new.as_ref(), &values, &mut x, 40, KRYLOV_TOLERANCE)
            .unwrap()
            .unwrap_or_else(|| panic!("{kind:?}: GMRES on the new pattern"));
        let mut r = b.clone();
        for (j, xj) in x.iter().enumerate() {
            for k in new.col_range(j) {
                r[new.row_idx()[k]] -= values[k] * xj;
            }
        }
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        let res = norm(&r) / norm(&b);
        assert!(res <= KRYLOV_TOLERANCE, "{kind:?}: residual {res:e}");
        assert!(
            (1..=40).contains(&iterations),
            "{kind:?}: {iterations} iterations"
        );
        let smaller = SymbolicSparseColMat::new_checked(1, 1, vec![0, 1], None, vec![0]);
        let refused = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let mut y = vec![1.0];
            solver.solve_preconditioned_on(smaller.as_ref(), &[1.0], &mut y, 5, KRYLOV_TOLERANCE)
        }));
        assert!(refused.is_err(), "{kind:?}: another number of equations");
    }
}

/// ‖b − Ax‖∞ / (‖A‖∞‖x‖∞ + ‖b‖∞): the backward error of a solution.
fn backward_error(assembly: &Assembly, values: &[f64], x: &[f64], b: &[f64]) -> f64 {
    let (r, row_sums) = residual(assembly, values, x, b);
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    inf(&r) / (inf(&row_sums) * inf(x) + inf(b))
}

/// Cholesky and LDLᵀ factors stored in single precision solve to the Krylov tolerance by
/// GMRES (the matrix and residuals in double), agree with the double-precision solution, stay
/// single (no escalation) on well-conditioned matrices and refactorizations, and hold half
/// the factor's bytes; LU ignores the setting.
#[test]
fn single_precision_factors_solve_to_double_accuracy() {
    for (system, kind, advection) in &three_kinds() {
        let (kind, advection) = (kind.clone(), *advection);
        let (v1, b1) = system.assemble(1.0, 0.01, advection);
        let (v2, b2) = system.assemble(3.5, 0.2, 0.7 * advection);
        let pattern = system.assembly.symbolic();
        let mut double = LinearSolver::new(pattern, kind.clone(), Ordering::Default).unwrap();
        let mut single = LinearSolver::new(pattern, kind.clone(), Ordering::Default).unwrap();
        single.set_precision(FactorPrecision::Single);
        if kind == Factorization::Lu {
            assert_eq!(
                single.precision(),
                FactorPrecision::Double,
                "LU stays double"
            );
            continue;
        }
        assert_eq!(single.precision(), FactorPrecision::Single);
        for (values, rhs) in [(&v1, &b1), (&v2, &b2)] {
            double.factorize(values).unwrap();
            single.factorize(values).unwrap();
            let exact = solve(&mut double, rhs);
            let x = solve(&mut single, rhs);
            let res = relative_residual(&system.assembly, values, &x, rhs);
            assert!(res <= KRYLOV_TOLERANCE, "{kind:?} single: residual {res:e}");
            let scale = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in x.iter().zip(&exact) {
                assert!((a - b).abs() <= 1e-9 * scale, "{kind:?}: {a} against {b}");
            }
            assert_eq!(single.fallback(), None);
        }
        assert_eq!(single.precision(), FactorPrecision::Single);
        assert_eq!(single.precision_escalations(), 0);
        let half_factor = single.factor_nnz().unwrap() * 4;
        assert!(
            single.storage_bytes() + half_factor <= double.storage_bytes(),
            "{kind:?}: {} against {} bytes",
            single.storage_bytes(),
            double.storage_bytes()
        );
    }
}

/// A matrix whose condition defeats a single-precision factor (a Laplacian with a shift of
/// 1e-12 of its largest eigenvalue: f32 rounds the shift away) is factorized again in double
/// precision, which the solver keeps: the solution has a double-precision backward error, and
/// the next factorization starts in double.
#[test]
fn single_precision_escalates_to_double_where_it_cannot_precondition() {
    let system = GridSystem::new(30, 24, 1, false);
    let (values, rhs) = system.assemble(1.0, 1e-12, 0.0);
    let mut solver = LinearSolver::new(
        system.assembly.symbolic(),
        Factorization::Cholesky,
        Ordering::Default,
    )
    .unwrap();
    solver.set_precision(FactorPrecision::Single);
    solver.factorize(&values).unwrap();
    let x = solve(&mut solver, &rhs);
    assert_eq!(solver.precision_escalations(), 1);
    assert_eq!(solver.precision(), FactorPrecision::Double);
    let error = backward_error(&system.assembly, &values, &x, &rhs);
    assert!(error < 1e-14, "backward error {error:e}");
    solver.factorize(&values).unwrap();
    assert_eq!(solve(&mut solver, &rhs), x, "double from now on");
    assert_eq!(solver.precision_escalations(), 1);
}

/// An indefinite matrix given to Cholesky returns `Error::LinearSolver` naming the pivot, and a
/// later solve fails cleanly instead of using stale factors.
#[test]
fn cholesky_of_indefinite_matrix_is_an_error_not_a_panic() {
    let system = GridSystem::new(15, 10, 1, false);
    let (good, rhs) = system.assemble(1.0, 0.01, 0.0);
    let (bad, _) = system.assemble(1.0, -5.0, 0.0); // mass shift below −λ_min: indefinite
    let mut solver = LinearSolver::new(
        system.assembly.symbolic(),
        Factorization::Cholesky,
        Ordering::Default,
    )
    .unwrap();
    solver.factorize(&good).unwrap();
    match solver.factorize(&bad) {
        Err(Error::LinearSolver(msg)) => assert!(msg.contains("not positive definite"), "{msg}"),
        other => panic!("expected a LinearSolver error, got {other:?}"),
    }
    let mut x = rhs.clone();
    assert!(matches!(
        solver.solve_in_place(&mut x),
        Err(Error::LinearSolver(_))
    ));
    // and the solver recovers with good values
    solver.factorize(&good).unwrap();
    solver.solve_in_place(&mut x).unwrap();
    assert!(relative_residual(&system.assembly, &good, &x, &rhs) < 1e-12);
}

/// A numerically singular matrix given to LU yields an error (from factorize or solve), no panic;
/// non-finite values are rejected up front.
#[test]
fn singular_or_non_finite_matrices_are_errors() {
    let system = GridSystem::new(8, 6, 1, false);
    let zeros = vec![0.0; system.assembly.nnz()];
    let mut solver = LinearSolver::new(
        system.assembly.symbolic(),
        Factorization::Lu,
        Ordering::Default,
    )
    .unwrap();
    let outcome = solver
        .factorize(&zeros)
        .and_then(|_| solver.solve_in_place(&mut vec![1.0; system.assembly.n_eq()]));
    assert!(
        matches!(outcome, Err(Error::LinearSolver(_))),
        "{outcome:?}"
    );
    let mut nan = vec![1.0; system.assembly.nnz()];
    nan[3] = f64::NAN;
    assert!(
        matches!(solver.factorize(&nan), Err(Error::LinearSolver(m)) if m.contains("not finite"))
    );
}

/// Invalid inputs are reported with the field name: custom ordering for LU, a custom ordering
/// that is not a permutation, an LDLᵀ sign vector of the wrong length.
#[test]
fn invalid_solver_inputs_are_rejected() {
    let system = GridSystem::new(6, 5, 1, false);
    let p = system.assembly.symbolic();
    let n = system.assembly.n_eq();
    let identity: Vec<usize> = (0..n).collect();
    let field = |r: tcgen::Result<LinearSolver>| match r {
        Err(Error::InvalidInput { field, .. }) => field,
        other => panic!("expected InvalidInput, got {other:?}"),
    };
    assert_eq!(
        field(LinearSolver::new(
            p,
            Factorization::Lu,
            Ordering::Custom(identity.clone())
        )),
        "ordering"
    );
    let mut not_perm = identity.clone();
    not_perm[1] = 0;
    assert_eq!(
        field(LinearSolver::new(
            p,
            Factorization::Cholesky,
            Ordering::Custom(not_perm)
        )),
        "ordering"
    );
    assert_eq!(
        field(LinearSolver::new(
            p,
            Factorization::Ldlt {
                signs: vec![1; n - 1]
            },
            Ordering::Default
        )),
        "signs"
    );
    assert!(LinearSolver::new(p, Factorization::Cholesky, Ordering::Custom(identity)).is_ok());
}

/// The multiplier reordering keeps every non-multiplier in place relative to the others and
/// moves each multiplier right after its last coupled displacement.
#[test]
fn multipliers_are_moved_after_their_displacements() {
    let system = GridSystem::new(10, 6, 1, true);
    let pattern = system.assembly.symbolic();
    let n = system.assembly.n_eq();
    let reversed: Vec<usize> = (0..n).rev().collect(); // multipliers first: worst case
    let perm = multipliers_after_neighbours(pattern, reversed.clone(), &system.signs());
    assert!(is_permutation(&perm, n));
    let primal = |p: &[usize]| {
        p.iter()
            .copied()
            .filter(|&i| i < system.n_primal)
            .collect::<Vec<_>>()
    };
    assert_eq!(primal(&perm), primal(&reversed));
    for (k, &m) in perm
        .iter()
        .enumerate()
        .filter(|(_, m)| **m >= system.n_primal)
    {
        let neighbours = &pattern.row_idx()[pattern.col_range(m)];
        let last = perm
            .iter()
            .rposition(|u| *u < system.n_primal && neighbours.contains(u))
            .unwrap();
        assert!(
            last < k && perm[last + 1..k].iter().all(|&i| i >= system.n_primal),
            "multiplier {m} at {k}"
        );
    }
}

/// Nested dissection on a 2D Q1 grid gives far less fill than the natural (row-by-row)
/// ordering and is competitive with AMD. `FewerEntries` keeps the better of its permutation
/// and AMD: given the natural order, it takes AMD's factor (the LDLᵀ saddle point with it:
/// `ldlt_solves_saddle_point_with_default_and_nd_orderings`).
#[test]
fn nested_dissection_reduces_fill_on_a_2d_grid() {
    let system = GridSystem::new(90, 90, 1, false);
    let p = system.assembly.symbolic();
    let n = system.assembly.n_eq();
    let fill = |ordering: Ordering| {
        LinearSolver::new(p, Factorization::Cholesky, ordering)
            .unwrap()
            .factor_nnz()
            .unwrap()
    };
    let natural = fill(Ordering::Custom((0..n).collect()));
    let nd = fill(Ordering::Custom(nested_dissection(p, &system.coords)));
    let amd = fill(Ordering::Custom(approximate_minimum_degree(p)));
    println!("nnz(L) on a 90×90 grid: natural {natural}, nested dissection {nd}, AMD {amd}");
    assert!(
        (nd as f64) < 0.5 * natural as f64,
        "ND {nd} vs natural {natural}"
    );
    assert!((nd as f64) < 1.5 * amd as f64, "ND {nd} vs AMD {amd}");
    let order: Vec<usize> = (0..n).collect();
    assert!(factor_entries(p, &order) > 2 * factor_entries(p, &approximate_minimum_degree(p)));
    assert_eq!(fill(Ordering::FewerEntries(order.clone())), amd);
    // `Fewest` takes the candidate with the fewest entries, whatever its place.
    let amd_order = approximate_minimum_degree(p);
    assert_eq!(
        fill(Ordering::Fewest(vec![order.clone(), amd_order.clone()])),
        amd
    );
    assert_eq!(fill(Ordering::Fewest(vec![amd_order, order])), amd);
    assert!(LinearSolver::new(p, Factorization::Cholesky, Ordering::Fewest(Vec::new())).is_err());
}

/// Nested dissection (METIS on the node graph) of a 3D grid with three equations per node (the
/// 27-point couplings of trilinear hexahedra, 18 × 18 × 18 nodes) gives a factor far smaller
/// than AMD's, as for the adaptive egg box (docs/3d.md, "Stop 40"), and keeps the equations of
/// a node consecutive; so does AMD of the nodes' graph, whose factor is AMD's of the equations
/// within 10 % (the same here).
#[test]
fn nested_dissection_beats_amd_on_a_3d_grid_and_keeps_nodes_together() {
    let m = 18;
    let node = |i: usize, j: usize, k: usize| (k * m + j) * m + i;
    let near = |a: usize| a.saturating_sub(1)..(a + 2).min(m);
    let mut columns = Vec::new();
    let mut coords = Vec::new();
    for k in 0..m {
        for j in 0..m {
            for i in 0..m {
                for _field in 0..3 {
                    let mut rows = Vec::new();
                    for kk in near(k) {
                        for jj in near(j) {
                            for ii in near(i) {
                                rows.extend((0..3).map(|f| 3 * node(ii, jj, kk) + f));
                            }
                        }
                    }
                    rows.sort_unstable();
                    columns.push(rows);
                    coords.push([i as f64, j as f64, k as f64]);
                }
            }
        }
    }
    let (col_ptr, row_idx) = csc(columns);
    let n = coords.len();
    let p = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
    // Both node orders keep a node's equations consecutive; AMD's of the nodes' graph gives
    // a factor within 10 % of AMD's of the equations.
    let (nd, node_amd) = (
        nested_dissection(p, &coords),
        node_minimum_degree(p, &coords),
    );
    for order in [&nd, &node_amd] {
        assert!(is_permutation(order, n));
        for group in order.chunks(3) {
            assert!(
                group.iter().all(|&e| e / 3 == group[0] / 3),
                "a node's equations apart: {group:?}"
            );
        }
    }
    let (nd, amd, node_amd) = (
        factor_entries(p, &nd),
        factor_entries(p, &approximate_minimum_degree(p)),
        factor_entries(p, &node_amd),
    );
    println!(
        "factor entries on an 18³ grid, 3 fields: nested dissection {nd}, AMD {amd}, AMD of the nodes {node_amd}"
    );
    assert!((nd as f64) < 0.8 * amd as f64, "ND {nd} vs AMD {amd}");
    assert!(
        (node_amd as f64 - amd as f64).abs() < 0.1 * amd as f64,
        "AMD of the nodes {node_amd} vs of the equations {amd}"
    );
}

/// The node orders of a three-field system, kept, order the scalar system of the same nodes
/// (the thermal phase of the mechanical phase's mesh) node for node, and the system itself as
/// computed; nodes they do not hold are placed beside their neighbours, or, many, declined.
#[test]
fn kept_node_orders_order_the_other_phase_of_the_same_nodes() {
    // 90 × 90 nodes: 24 300 equations with three fields (METIS's and AMD's node orders), 8 100
    // with one (where a fresh analysis would take AMD's order of the equations instead).
    let (mech, therm) = (
        GridSystem::new(90, 90, 3, true),
        GridSystem::new(90, 90, 1, true),
    );
    let (p3, p1) = (mech.assembly.symbolic(), therm.assembly.symbolic());
    let (orders, kept) = node_orders_kept(p3, &mech.coords);
    assert_eq!(orders, node_orders(p3, &mech.coords));
    assert_eq!(orders.len(), 2);
    assert_eq!(kept.orders(p3, &mech.coords), Some(orders.clone()));
    let reused = kept.orders(p1, &therm.coords).expect("the same nodes");
    assert_eq!(reused.len(), 2);
    for (scalar, vector) in reused.iter().zip(&orders) {
        assert!(is_permutation(scalar, therm.coords.len()));
        // Node for node: the vector order's nodes, first appearances, are the scalar order's.
        let mut seen = std::collections::HashSet::new();
        let nodes: Vec<[u64; 3]> = vector
            .iter()
            .map(|&e| mech.coords[e].map(f64::to_bits))
            .filter(|c| seen.insert(*c))
            .collect();
        let scalar_nodes: Vec<[u64; 3]> = scalar
            .iter()
            .map(|&e| therm.coords[e].map(f64::to_bits))
            .collect::<Vec<_>>()
            .chunk_by(|a, b| a == b)
            .map(|group| group[0])
            .collect();
        assert_eq!(scalar_nodes, nodes);
    }
    // As good an order of the scalar system as its own analysis's (within 5 %).
    let as_good_as_own = |system: &GridSystem, orders: &[Vec<usize>], what: &str| {
        let p = system.assembly.symbolic();
        assert!(
            orders
                .iter()
                .all(|o| is_permutation(o, system.coords.len()))
        );
        let fewest = |orders: &[Vec<usize>]| orders.iter().map(|o| factor_entries(p, o)).min();
        let (own, kept) = (fewest(&node_orders(p, &system.coords)), fewest(orders));
        let (own, kept) = (own.unwrap(), kept.unwrap());
        println!("{what}: its own orders {own} factor entries, the kept ones {kept}");
        assert!((kept as f64) < 1.05 * own as f64, "{what}: {kept} vs {own}");
    };
    as_good_as_own(&therm, &reused, "the scalar system");
    // Nodes the kept orders do not hold: a row more (1 % of the nodes) is placed beside its
    // neighbours, as good an order as the system's own; twenty rows more (18 %) are declined.
    let more = GridSystem::new(90, 91, 1, false);
    let placed = kept.orders(more.assembly.symbolic(), &more.coords);
    as_good_as_own(&more, &placed.expect("1 % new nodes"), "with a new row");
    let larger = GridSystem::new(90, 110, 1, true);
    assert_eq!(
        kept.orders(larger.assembly.symbolic(), &larger.coords),
        None
    );
}

/// The number of factor entries by symbolic elimination (the elimination game): eliminating
/// a vertex joins its remaining neighbours into a clique.
fn elimination_game(n: usize, edges: &[(usize, usize)], perm: &[usize]) -> usize {
    eliminate(n, edges, perm).0
}

/// The elimination game: the factor's entries, and the parent of each column (in the order
/// `perm`) in the elimination tree, the first later vertex the eliminated one is joined to.
fn eliminate(n: usize, edges: &[(usize, usize)], perm: &[usize]) -> (usize, Vec<Option<usize>>) {
    let mut position = vec![0; n];
    for (k, &v) in perm.iter().enumerate() {
        position[v] = k;
    }
    let mut later: Vec<std::collections::BTreeSet<usize>> = vec![Default::default(); n];
    for &(a, b) in edges {
        let (a, b) = (position[a], position[b]);
        if a != b {
            later[a.min(b)].insert(a.max(b));
        }
    }
    let mut entries = 0;
    let mut parent = vec![None; n];
    for k in 0..n {
        let row: Vec<usize> = later[k].iter().copied().collect();
        entries += 1 + row.len();
        parent[k] = row.first().copied();
        for (i, &u) in row.iter().enumerate() {
            for &w in &row[i + 1..] {
                later[u].insert(w);
            }
        }
    }
    (entries, parent)
}

/// The CSC arrays (column pointers, row indices) of `columns`, each a column's sorted rows.
fn csc<C: IntoIterator<Item = usize>>(
    columns: impl IntoIterator<Item = C>,
) -> (Vec<usize>, Vec<usize>) {
    let mut col_ptr = vec![0usize];
    let mut row_idx = Vec::new();
    for c in columns {
        row_idx.extend(c);
        col_ptr.push(row_idx.len());
    }
    (col_ptr, row_idx)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]
    /// Nested dissection returns a permutation for any pattern and any coordinates,
    /// including duplicated, infinite and NaN ones.
    #[test]
    fn nested_dissection_is_a_permutation_for_any_input(
        n in 1usize..400,
        edges in proptest::collection::vec((0usize..400, 0usize..400), 0..1500),
        raw in proptest::collection::vec((0u8..8, -3.0f64..3.0), 1200),
    ) {
        let mut columns = vec![Vec::new(); n];
        for (a, b) in edges {
            columns[b % n].push(a % n); // deliberately unsymmetric, with duplicates
        }
        let (col_ptr, row_idx) = csc(columns.into_iter().map(|mut c| {
            c.sort_unstable();
            c.dedup();
            c
        }));
        let pattern = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let value = |(kind, x): (u8, f64)| match kind {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => 0.0,
            3 => x.round(),
            _ => x,
        };
        let coords: Vec<[f64; 3]> = (0..n).map(|i| [value(raw[3 * i]), value(raw[3 * i + 1]), value(raw[3 * i + 2])]).collect();
        let perm = nested_dissection(pattern, &coords);
        prop_assert!(is_permutation(&perm, n));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]
    /// `factor_entries` (elimination tree column counts) equals the elimination game on
    /// random symmetric patterns (lower triangle read) and random orders.
    #[test]
    fn factor_entries_match_the_elimination_game(
        n in 1usize..60,
        edges in proptest::collection::vec((0usize..60, 0usize..60), 0..300),
        keys in proptest::collection::vec(0u32..1000, 60),
    ) {
        let edges: Vec<(usize, usize)> = edges.into_iter().map(|(a, b)| (a % n, b % n)).collect();
        let mut columns = vec![std::collections::BTreeSet::new(); n];
        for (j, c) in columns.iter_mut().enumerate() {
            c.insert(j);
        }
        for &(a, b) in &edges {
            columns[a.min(b)].insert(a.max(b));
        }
        let (col_ptr, row_idx) = csc(columns);
        let pattern = faer::sparse::SymbolicSparseColMatRef::new_checked(n, n, &col_ptr, None, &row_idx);
        let mut perm: Vec<usize> = (0..n).collect();
        perm.sort_by_key(|&i| (keys[i], i));
        prop_assert_eq!(factor_entries(pattern, &perm), elimination_game(n, &edges, &perm));
        // Postordered: the same fill, and every subtree of the elimination tree numbered
        // contiguously, ending at its root.
        let post = postordered(pattern, perm.clone());
        prop_assert!(is_permutation(&post, n));
        // Of two candidates, the one with the fewer entries (the first on a tie),
        // postordered from the tree its count computed: as `postordered` does it.
        let natural: Vec<usize> = (0..n).collect();
        let best = match elimination_game(n, &edges, &natural) < elimination_game(n, &edges, &perm) {
            true => natural.clone(),
            false => perm.clone(),
        };
        prop_assert_eq!(
            fewest_entries_postordered(pattern, vec![perm.clone(), natural]),
            postordered(pattern, best)
        );
        prop_assert_eq!(elimination_game(n, &edges, &post), elimination_game(n, &edges, &perm));
        let parent = eliminate(n, &edges, &post).1;
        let mut size = vec![1usize; n];
        for (k, p) in parent.iter().enumerate() {
            if let Some(p) = *p {
                prop_assert!(p > k);
                size[p] += size[k];
            }
        }
        for (k, &size) in size.iter().enumerate() {
            for j in k + 1 - size..k {
                let mut a = j;
                while a < k {
                    a = parent[a].unwrap_or(n);
                }
                prop_assert_eq!(a, k, "column {} in the range of {}'s subtree but not in it", j, k);
            }
        }
    }
}

/// The benchmark runs end to end on tiny grids and every case solves accurately.
#[test]
fn bench_smoke_test() {
    let rows = tcgen::bench::run_linear_solver_bench(&[600]);
    assert_eq!(rows.len(), 7);
    for row in &rows {
        assert!(row.relative_residual < 1e-10, "{row:?}");
        assert!(row.n_eq >= 400 && row.nnz > row.n_eq);
    }
    let table = tcgen::bench::format_bench_table(&rows);
    assert_eq!(table.lines().count(), 8);
}

/// The solver and the assembly can be shared between threads.
#[test]
fn solver_and_assembly_are_send_and_sync() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<LinearSolver>();
    assert_send_sync::<Assembly>();
}
