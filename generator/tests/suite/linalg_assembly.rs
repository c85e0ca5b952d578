//! Sparse assembly (`bulk::global::Assembly`): pattern, scatter, ties, prescribed dofs,
//! determinism across thread counts, error propagation.

use tcgen::Error;
use tcgen::bulk::global::{Assembly, Storage};

/// Dense n×n copy of a CSC matrix given by the assembly pattern and `values`.
fn dense(assembly: &Assembly, values: &[f64]) -> Vec<Vec<f64>> {
    let n = assembly.n_eq();
    let pattern = assembly.symbolic();
    let mut a = vec![vec![0.0; n]; n];
    for j in 0..n {
        for (&i, &v) in pattern.row_idx()[pattern.col_range(j)]
            .iter()
            .zip(&values[pattern.col_range(j)])
        {
            a[i][j] += v;
        }
    }
    a
}

/// Reference assembly: dense, sequential, straight from the definition.
fn dense_reference(
    n: usize,
    element_eqs: &[Vec<Option<usize>>],
    local: impl Fn(usize, &mut [f64], &mut [f64]),
) -> (Vec<Vec<f64>>, Vec<f64>) {
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![0.0; n];
    for (e, eqs) in element_eqs.iter().enumerate() {
        let m = eqs.len();
        let mut k = vec![0.0; m * m];
        let mut r = vec![0.0; m];
        local(e, &mut k, &mut r);
        for (bl, eq_b) in eqs.iter().enumerate() {
            if let Some(j) = eq_b {
                for (al, eq_a) in eqs.iter().enumerate() {
                    if let Some(i) = eq_a {
                        a[*i][*j] += k[bl * m + al];
                    }
                }
            }
        }
        for (al, eq_a) in eqs.iter().enumerate() {
            if let Some(i) = eq_a {
                b[*i] += r[al];
            }
        }
    }
    (a, b)
}

/// A deterministic, irregular element kernel: entries from a hash-like formula.
fn pseudo_random_local(e: usize, k: &mut [f64], r: &mut [f64]) {
    let m = r.len();
    for b in 0..m {
        for a in 0..m {
            k[b * m + a] = ((e * 131 + a * 17 + b * 7) as f64 * 0.618_033_988_749).sin() * 1e3
                + 1.0 / (1 + a + b) as f64;
        }
        r[b] = ((e * 29 + b) as f64 * 0.414_213_562).cos() * 1e-3;
    }
}

/// The assembly of [`pseudo_random_local`] over `element_eqs` equals the dense reference.
fn assert_matches_dense_reference(assembly: &Assembly, element_eqs: &[Vec<Option<usize>>]) {
    let n = assembly.n_eq();
    let mut values = vec![0.0; assembly.nnz()];
    let mut rhs = vec![0.0; n];
    assembly
        .assemble(&mut values, &mut rhs, |e, k, r| {
            pseudo_random_local(e, k, r);
            Ok(())
        })
        .unwrap();
    let (a_ref, b_ref) = dense_reference(n, element_eqs, pseudo_random_local);
    let a = dense(assembly, &values);
    for i in 0..n {
        for j in 0..n {
            assert!(
                (a[i][j] - a_ref[i][j]).abs() <= 1e-12 * (1.0 + a_ref[i][j].abs()),
                "entry ({i}, {j})"
            );
        }
        assert!((rhs[i] - b_ref[i]).abs() <= 1e-15, "rhs {i}");
    }
}

/// Simple deterministic generator (xorshift) for element connectivities.
struct XorShift(u64);
impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// 2-node linear elements of a 1-D bar with node 0 prescribed assemble to the tridiagonal
/// matrix (2/h, −1/h; last diagonal 1/h) and the lumped load (h; last h/2).
#[test]
fn one_d_laplacian_assembles_to_known_matrix() {
    let n_el = 6;
    let h = 1.0 / n_el as f64;
    let eq = |node: usize| node.checked_sub(1); // node 0 prescribed
    let element_eqs: Vec<_> = (0..n_el).map(|e| vec![eq(e), eq(e + 1)]).collect();
    let assembly = Assembly::new(n_el, element_eqs);
    assert_eq!(assembly.n_elements(), n_el);
    assert_eq!(assembly.nnz(), 3 * n_el - 2);
    let mut values = vec![f64::NAN; assembly.nnz()];
    let mut rhs = vec![f64::NAN; n_el];
    assembly
        .assemble(&mut values, &mut rhs, |_, k, r| {
            k.copy_from_slice(&[1.0 / h, -1.0 / h, -1.0 / h, 1.0 / h]);
            r.copy_from_slice(&[h / 2.0, h / 2.0]);
            Ok(())
        })
        .unwrap();
    let a = dense(&assembly, &values);
    for (i, row) in a.iter().enumerate() {
        for (j, &a_ij) in row.iter().enumerate() {
            let expected = match (i, j) {
                _ if i == j && i == n_el - 1 => 1.0 / h,
                _ if i == j => 2.0 / h,
                _ if i.abs_diff(j) == 1 => -1.0 / h,
                _ => 0.0,
            };
            assert!(
                (a_ij - expected).abs() < 1e-12,
                "a[{i}][{j}] = {a_ij} ≠ {expected}"
            );
        }
        let expected = if i == n_el - 1 { h / 2.0 } else { h };
        assert!(
            (rhs[i] - expected).abs() < 1e-15,
            "rhs[{i}] = {} ≠ {expected}",
            rhs[i]
        );
    }
}

/// Two local dofs on one equation add all four of their block entries; a `None` dof drops
/// its row and column.
#[test]
fn tied_dofs_add_and_prescribed_dofs_are_dropped() {
    // Element 0: local dofs 0 and 1 both on equation 0, local 2 prescribed, local 3 on eq 1.
    let element_eqs = vec![
        vec![Some(0), Some(0), None, Some(1)],
        vec![Some(1), Some(2)],
    ];
    let assembly = Assembly::new(3, element_eqs);
    let mut values = vec![0.0; assembly.nnz()];
    let mut rhs = vec![0.0; 3];
    assembly
        .assemble(&mut values, &mut rhs, |e, k, r| {
            let m = r.len();
            for b in 0..m {
                for a in 0..m {
                    k[b * m + a] = (10 * e + 4 * a + b + 1) as f64; // distinct entries
                }
                r[b] = (100 * e + b + 1) as f64;
            }
            Ok(())
        })
        .unwrap();
    let a = dense(&assembly, &values);
    let k0 = |a: usize, b: usize| (4 * a + b + 1) as f64;
    let k1 = |a: usize, b: usize| (10 + 4 * a + b + 1) as f64;
    assert_eq!(a[0][0], k0(0, 0) + k0(0, 1) + k0(1, 0) + k0(1, 1));
    assert_eq!(a[0][1], k0(0, 3) + k0(1, 3));
    assert_eq!(a[1][0], k0(3, 0) + k0(3, 1));
    assert_eq!(a[1][1], k0(3, 3) + k1(0, 0));
    assert_eq!(a[1][2], k1(0, 1));
    assert_eq!(a[2][1], k1(1, 0));
    assert_eq!(a[2][2], k1(1, 1));
    assert_eq!(a[0][2], 0.0);
    assert_eq!(rhs, vec![1.0 + 2.0, 4.0 + 101.0, 102.0]);
}

/// An assembly describes exactly the unknowns and local-to-global maps it
/// was built from (the reuse test of the model's kept assemblies): any
/// changed equation, prescribed dof, element, element length or count of
/// unknowns makes it another one.
#[test]
fn an_assembly_describes_only_its_own_maps() {
    let element_eqs = vec![
        vec![Some(0), Some(0), None, Some(1)],
        vec![Some(1), Some(2)],
    ];
    let assembly = Assembly::new(3, element_eqs.clone());
    assert!(assembly.describes(3, &element_eqs, Storage::Full));
    assert!(!assembly.describes(3, &element_eqs, Storage::Lower));
    assert!(!assembly.describes(4, &element_eqs, Storage::Full));
    let mut other = element_eqs.clone();
    other[1][1] = Some(0);
    assert!(!assembly.describes(3, &other, Storage::Full));
    let mut other = element_eqs.clone();
    other[0][2] = Some(2);
    assert!(!assembly.describes(3, &other, Storage::Full));
    let mut other = element_eqs.clone();
    other[0][0] = None;
    assert!(!assembly.describes(3, &other, Storage::Full));
    let mut other = element_eqs.clone();
    other[1].push(Some(0));
    assert!(!assembly.describes(3, &other, Storage::Full));
    assert!(!assembly.describes(3, &element_eqs[..1], Storage::Full));
    let mut other = element_eqs.clone();
    other.push(vec![Some(2)]);
    assert!(!assembly.describes(3, &other, Storage::Full));
}

/// Random connectivities with ties and prescribed dofs match the dense reference assembly,
/// and the pattern is sorted, full and contains the diagonal.
#[test]
fn random_assembly_matches_dense_reference() {
    let mut rng = XorShift(0x9e37_79b9_7f4a_7c15);
    let n = 60;
    let element_eqs: Vec<Vec<Option<usize>>> = (0..80)
        .map(|_| {
            let m = 1 + rng.below(9);
            (0..m)
                .map(|_| {
                    if rng.below(6) == 0 {
                        None
                    } else {
                        Some(rng.below(n))
                    }
                })
                .collect()
        })
        .collect();
    let assembly = Assembly::new(n, element_eqs.clone());
    assert_matches_dense_reference(&assembly, &element_eqs);
    let pattern = assembly.symbolic();
    for j in 0..n {
        let rows = &pattern.row_idx()[pattern.col_range(j)];
        assert!(
            rows.windows(2).all(|w| w[0] < w[1]),
            "column {j} not sorted"
        );
        assert!(rows.binary_search(&j).is_ok(), "diagonal {j} missing");
        for &i in rows {
            let ri = &pattern.row_idx()[pattern.col_range(i)];
            assert!(
                ri.binary_search(&j).is_ok(),
                "pattern not symmetric at ({i}, {j})"
            );
        }
    }
}

/// The assembly of Q1 elements on an nx × ny node grid (one equation per node).
fn q1_grid(nx: usize, ny: usize) -> Assembly {
    let element_eqs: Vec<Vec<Option<usize>>> = (0..(nx - 1) * (ny - 1))
        .map(|e| {
            let (i, j) = (e % (nx - 1), e / (nx - 1));
            [(0, 0), (1, 0), (0, 1), (1, 1)]
                .iter()
                .map(|(di, dj)| Some((j + dj) * nx + i + di))
                .collect()
        })
        .collect();
    Assembly::new(nx * ny, element_eqs)
}

/// Q1 elements on an nx × ny node grid: the pattern is the 9-point stencil,
/// nnz = (3nx − 2)(3ny − 2), and the residual-only assembly equals the full one; on a
/// grid of several of the pattern's column chunks (built in parallel) every column holds
/// exactly its stencil, sorted.
#[test]
fn grid_pattern_is_the_nine_point_stencil_and_vector_assembly_agrees() {
    let (nx, ny) = (71, 59);
    let assembly = q1_grid(nx, ny);
    assert_eq!(assembly.nnz(), (3 * nx - 2) * (3 * ny - 2));
    let pattern = assembly.symbolic();
    for c in 0..nx * ny {
        let (i, j) = (c % nx, c / nx);
        let mut stencil = Vec::new();
        for jj in j.saturating_sub(1)..(j + 2).min(ny) {
            for ii in i.saturating_sub(1)..(i + 2).min(nx) {
                stencil.push(jj * nx + ii);
            }
        }
        assert_eq!(pattern.row_idx_of_col_raw(c), stencil, "column {c}");
    }
    let (nx, ny) = (23, 17);
    let assembly = q1_grid(nx, ny);
    assert_eq!(assembly.nnz(), (3 * nx - 2) * (3 * ny - 2));
    assert!(
        assembly.n_colors() >= 4,
        "neighbouring Q1 elements need at least 4 colors"
    );
    let mut values = vec![0.0; assembly.nnz()];
    let mut rhs = vec![0.0; nx * ny];
    let mut rhs_only = vec![1.0; nx * ny];
    let local = |e: usize, k: &mut [f64], r: &mut [f64]| {
        pseudo_random_local(e, k, r);
        Ok(())
    };
    assembly.assemble(&mut values, &mut rhs, local).unwrap();
    assembly
        .assemble_vector(&mut rhs_only, |e, r| local(e, &mut [0.0; 16], r))
        .unwrap();
    assert_eq!(rhs, rhs_only);
}

/// 27-node (triquadratic) elements with 3 fields per node, node-major, on a 3 × 3 × 2 element
/// grid, periodic in x, the bottom's vertical field prescribed: the assembly matches the dense
/// reference, and the scatter map (runs of offsets shared by a node's columns) takes less than a
/// quarter of one 16-bit offset per element-block entry.
#[test]
fn node_major_fields_assemble_exactly_from_a_compact_scatter_map() {
    let (ex, ey, ez) = (3, 3, 2);
    let (nx, ny, nz) = (2 * ex + 1, 2 * ey + 1, 2 * ez + 1);
    let node = |i: usize, j: usize, k: usize| ((k * ny + j) * (nx - 1)) + i % (nx - 1);
    let element_eqs: Vec<Vec<Option<usize>>> = (0..ex * ey * ez)
        .map(|e| {
            let (i, j, k) = (2 * (e % ex), 2 * ((e / ex) % ey), 2 * (e / (ex * ey)));
            let mut eqs = Vec::new();
            for dk in 0..3 {
                for dj in 0..3 {
                    for di in 0..3 {
                        for f in 0..3 {
                            let prescribed = k + dk == 0 && f == 2;
                            eqs.push((!prescribed).then(|| 3 * node(i + di, j + dj, k + dk) + f));
                        }
                    }
                }
            }
            eqs
        })
        .collect();
    let n = 3 * (nx - 1) * ny * nz;
    let assembly = Assembly::new(n, element_eqs.clone());
    assert_matches_dense_reference(&assembly, &element_eqs);
    let one_offset_per_entry: usize = element_eqs.iter().map(|e| 2 * e.len() * e.len()).sum();
    assert!(
        4 * assembly.scatter_map_bytes() < one_offset_per_entry,
        "scatter map {} B against {one_offset_per_entry} B",
        assembly.scatter_map_bytes()
    );
}

/// A 2-field, 20 000-element assembly with periodic ties and prescribed dofs gives
/// bit-identical values and residuals on 1, 2 and 3 rayon threads.
#[test]
fn assembly_is_bit_identical_for_any_thread_count() {
    let (nx, ny) = (201, 101); // nodes; periodic in x: node column nx−1 tied to column 0
    let node_eq = |i: usize, j: usize, f: usize| -> Option<usize> {
        if j == 0 && f == 1 {
            return None; // prescribed u_y on the bottom
        }
        let i = if i == nx - 1 { 0 } else { i };
        Some(2 * (j * (nx - 1) + i) + f)
    };
    let element_eqs: Vec<Vec<Option<usize>>> = (0..(nx - 1) * (ny - 1))
        .map(|e| {
            let (i, j) = (e % (nx - 1), e / (nx - 1));
            let mut eqs = Vec::new();
            for (di, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                for f in 0..2 {
                    eqs.push(node_eq(i + di, j + dj, f));
                }
            }
            eqs
        })
        .collect();
    assert!(element_eqs.len() >= 20_000);
    let assembly = Assembly::new(2 * (nx - 1) * ny, element_eqs);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut values = vec![0.0; assembly.nnz()];
            let mut rhs = vec![0.0; assembly.n_eq()];
            assembly
                .assemble(&mut values, &mut rhs, |e, k, r| {
                    pseudo_random_local(e, k, r);
                    Ok(())
                })
                .unwrap();
            (values, rhs)
        })
    };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let (v1, r1) = run(1);
    for threads in [2, 3] {
        let (v, r) = run(threads);
        assert_eq!(
            bits(&v1),
            bits(&v),
            "matrix differs between 1 and {threads} threads"
        );
        assert_eq!(
            bits(&r1),
            bits(&r),
            "residual differs between 1 and {threads} threads"
        );
    }
    // Ties really summed several contributions in different orders: the data is not trivial.
    assert!(v1.iter().filter(|x| **x != 0.0).count() > assembly.nnz() / 2);
}

/// When several element kernels fail, the error of the lowest element index is returned,
/// whatever the scheduling.
#[test]
fn first_failing_element_in_element_order_is_reported() {
    let n_el = 5000;
    let element_eqs: Vec<_> = (0..n_el).map(|e| vec![Some(e), Some(e + 1)]).collect();
    let assembly = Assembly::new(n_el + 1, element_eqs);
    let failing = [4321, 777, 3000, 778];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let result = pool.install(|| {
            let mut values = vec![0.0; assembly.nnz()];
            let mut rhs = vec![0.0; assembly.n_eq()];
            assembly.assemble(&mut values, &mut rhs, |e, _, _| {
                if failing.contains(&e) {
                    Err(Error::Geometry(format!("element {e} inverted")))
                } else {
                    Ok(())
                }
            })
        });
        match result {
            Err(Error::Geometry(msg)) => assert_eq!(msg, "element 777 inverted"),
            other => panic!("expected the error of element 777, got {other:?}"),
        }
        let mut rhs = vec![0.0; assembly.n_eq()];
        let result = pool.install(|| {
            assembly.assemble_vector(&mut rhs, |e, _| {
                if failing.contains(&e) {
                    Err(Error::Geometry(format!("element {e}")))
                } else {
                    Ok(())
                }
            })
        });
        assert!(matches!(result, Err(Error::Geometry(m)) if m == "element 777"));
    }
}

/// A column longer than the 16-bit scatter map holds (an equation coupled to 70 000 others,
/// like a tie to a whole face) is scattered by 32-bit positions instead: every entry, the
/// hub's diagonal sum and the prescribed dofs as in the definition.
#[test]
fn a_column_too_long_for_16_bit_offsets_is_scattered_by_position() {
    let spokes = 70_000;
    let hub = spokes;
    // Element e couples spoke e, the hub and a prescribed dof.
    let element_eqs: Vec<Vec<Option<usize>>> = (0..spokes)
        .map(|e| vec![Some(e), Some(hub), None])
        .collect();
    let assembly = Assembly::new(spokes + 1, element_eqs);
    let local = |e: usize, k: &mut [f64], r: &mut [f64]| {
        for (i, v) in k.iter_mut().enumerate() {
            *v = 1.0 + i as f64 + 1e-3 * e as f64;
        }
        r.iter_mut().for_each(|v| *v = 1.0);
        Ok(())
    };
    let mut values = vec![0.0; assembly.nnz()];
    let mut rhs = vec![0.0; assembly.n_eq()];
    assembly.assemble(&mut values, &mut rhs, local).unwrap();
    let pattern = assembly.symbolic();
    let entry = |i: usize, j: usize| {
        let rows = &pattern.row_idx()[pattern.col_range(j)];
        let k = rows.binary_search(&i).expect("entry in the pattern");
        values[pattern.col_range(j).start + k]
    };
    // Local block (3 × 3, column-major): k[b·3 + a] = 1 + (b·3 + a) + 1e-3 e.
    for e in [0, 1, 12_345, spokes - 1] {
        let shift = 1e-3 * e as f64;
        assert_eq!(entry(e, e), 1.0 + shift);
        assert_eq!(entry(hub, e), 2.0 + shift);
        assert_eq!(entry(e, hub), 4.0 + shift);
    }
    let diagonal: f64 = (0..spokes).map(|e| 5.0 + 1e-3 * e as f64).sum();
    assert!((entry(hub, hub) - diagonal).abs() <= 1e-9 * diagonal);
    assert_eq!(rhs[hub], spokes as f64);
    assert!(rhs[..spokes].iter().all(|&r| r == 1.0));
    assert_eq!(pattern.col_range(hub).len(), spokes + 1);
}
