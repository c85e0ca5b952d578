//! The memory guard (`solve::resources::ensure_memory`): a factorization
//! whose values or workspace, or an assembly whose pattern and scatter map,
//! the memory left cannot hold is refused with
//! `Error::OutOfMemory` before it is allocated (on Linux the allocation
//! itself would succeed and the process be killed later), and that error
//! ends a Newton solve at once instead of cutting the load step back.
//!
//! This file holds one test: it sets `TCGEN_MEMORY_LIMIT` for its process.

use std::path::Path;

use tcgen::Error;
use tcgen::bulk::global::Assembly;
use tcgen::homogenize::path::solve_case;
use tcgen::sample::Case;
use tcgen::solve::linear::{Factorization, LinearSolver, Ordering};
use tcgen::solve::resources::process_memory;

/// `TCGEN_MEMORY_LIMIT` at `bytes` above the resident memory now.
fn limit_above_resident(bytes: u64) {
    let resident = process_memory("VmRSS:").expect("VmRSS on Linux");
    // SAFETY: the only test of this process; nothing else reads the
    // environment concurrently.
    unsafe { std::env::set_var("TCGEN_MEMORY_LIMIT", (resident + bytes).to_string()) };
}

/// A shifted 2D grid Laplacian (`n × n` nodes): its pattern, values and a
/// right-hand side.
fn laplacian(n: usize) -> (Assembly, Vec<f64>, Vec<f64>) {
    let id = |i: usize, j: usize| Some(j * n + i);
    let mut edges = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if i + 1 < n {
                edges.push(vec![id(i, j), id(i + 1, j)]);
            }
            if j + 1 < n {
                edges.push(vec![id(i, j), id(i, j + 1)]);
            }
        }
    }
    let assembly = Assembly::new(n * n, edges);
    let mut values = vec![0.0; assembly.nnz()];
    let mut rhs = vec![0.0; n * n];
    assembly
        .assemble(&mut values, &mut rhs, |e, k, r| {
            k.copy_from_slice(&[1.01, -1.0, -1.0, 1.01]);
            r.copy_from_slice(&[1.0, 0.5 * (e % 3) as f64]);
            Ok(())
        })
        .unwrap();
    (assembly, values, rhs)
}

#[test]
fn a_factorization_beyond_the_memory_left_is_refused_before_it_is_allocated() {
    // A direct solver: refused below its factor's bytes, solved above them.
    let (assembly, values, rhs) = laplacian(60);
    let mut solver = LinearSolver::new(
        assembly.symbolic(),
        Factorization::Cholesky,
        Ordering::Default,
    )
    .unwrap();
    let factor_bytes = 8 * solver.factor_nnz().expect("a Cholesky factor") as u64;
    assert!(factor_bytes > 100_000, "{factor_bytes} bytes");
    limit_above_resident(factor_bytes / 2);
    match solver.factorize(&values) {
        Err(e @ Error::OutOfMemory { .. }) => {
            let text = e.to_string();
            println!("{text}");
            assert!(
                text.contains("the factorization's values") && text.contains("TCGEN_MEMORY_LIMIT"),
                "{text}"
            );
            if let Error::OutOfMemory { needed, left, .. } = e {
                assert_eq!(needed, factor_bytes as f64);
                assert!(left < needed, "{left} left for {needed}");
            }
        }
        other => panic!("expected out of memory, got {other:?}"),
    }
    limit_above_resident(1 << 30);
    solver.factorize(&values).unwrap();
    let mut x = rhs.clone();
    solver.solve_in_place(&mut x).unwrap();
    assert!(x.iter().all(|v| v.is_finite()));

    // An assembly: refused where even its counted pattern does not fit (the
    // dense blocks of a diverged iterate's contact couplings), built where the
    // cheap bound on its pattern (the blocks' entries) does not fit but the
    // counted one does (20 identical blocks of 500 unknowns among 10 000).
    let blocks = || -> Vec<Vec<Option<usize>>> { vec![(0..500).map(Some).collect(); 20] };
    let (n_eq, block_entries, dofs) = (10_000, 20 * 500 * 500, 20 * 500);
    let counted = Assembly::bytes_for(block_entries, 500 * 500 + (n_eq - 500), dofs) as u64;
    let bound = Assembly::bytes_for(block_entries, block_entries, dofs) as u64;
    assert!(bound > 4 * counted, "{bound} against {counted}");
    limit_above_resident(counted / 4);
    match Assembly::try_new(n_eq, blocks()) {
        Err(e @ Error::OutOfMemory { .. }) => {
            let text = e.to_string();
            println!("{text}");
            assert!(text.contains("the assembly's pattern"), "{text}");
            if let Error::OutOfMemory { needed, .. } = e {
                assert_eq!(needed, counted as f64);
            }
        }
        other => panic!("expected out of memory, got {:?}", other.map(|a| a.nnz())),
    }
    limit_above_resident(2 * counted);
    let assembly = Assembly::try_new(n_eq, blocks()).expect("the counted pattern fits");
    assert_eq!(assembly.nnz(), 500 * 500 + (n_eq - 500));

    // A micro-sample: the point fails with the memory's message, without
    // load-step cut-backs (a stalled stepping would say so).
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables/sinusoid_on_flat.toml");
    let mut case = Case::read(&path).unwrap();
    case.discretization.elements_upper = [16, 8].into();
    case.discretization.elements_lower = [14, 7].into();
    case.load.pressures = vec![1.0e4];
    limit_above_resident(1);
    let r = &solve_case(&case, None, |_| {}).unwrap()[0];
    let message = format!("{:?}", r.status);
    println!("{message}");
    assert!(!r.converged);
    assert!(
        message.contains("out of memory") && !message.contains("stalled"),
        "{message}"
    );
}
