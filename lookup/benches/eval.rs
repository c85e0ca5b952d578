//! Benchmark of `Law::eval` (value, conductance and all derivatives) on a
//! 40 × 8 × 4 table: `cargo bench -p lookup`. Prints ns per call (best of 7
//! rounds of 2·10⁶ calls over 4096 random queries).

#[path = "../tests/common/mod.rs"]
mod common;

use common::*;
use lookup::{Extrapolation, Law};
use std::hint::black_box;
use std::time::Instant;

const CALLS: usize = 2_000_000;

fn best_ns_per_call(mut f: impl FnMut(usize) -> f64) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..7 {
        let start = Instant::now();
        let mut acc = 0.0;
        for i in 0..CALLS {
            acc += f(i);
        }
        black_box(acc);
        best = best.min(start.elapsed().as_nanos() as f64 / CALLS as f64);
    }
    best
}

fn main() {
    let law: Law = physical_law(Extrapolation::Clamp);
    let mut rng = Lcg(42);
    let inside: Vec<(f64, f64, f64)> = (0..4096)
        .map(|_| interior_query(&law, &mut rng, 0.0))
        .collect();
    let jumps: Vec<f64> = inside
        .iter()
        .map(|&(p, h, t)| law.eval(p, h, t).unwrap().jump)
        .collect();
    let outside: Vec<(f64, f64, f64)> = (0..4096)
        .map(|_| {
            (
                10f64.powf(rng.range(1.0, 10.0)),
                rng.range(0.0, 4e6),
                rng.range(200.0, 500.0),
            )
        })
        .collect();
    let mask = inside.len() - 1;

    let eval = best_ns_per_call(|i| {
        let (p, h, t) = black_box(inside[i & mask]);
        let v = law.eval(p, h, t).unwrap();
        v.conductance + v.d_conductance_dp + v.d_conductance_dh + v.d_conductance_dtheta
    });
    let clamped = best_ns_per_call(|i| {
        let (p, h, t) = black_box(outside[i & mask]);
        law.eval(p, h, t).map(|v| v.conductance).unwrap_or(0.0)
    });
    let at_jump = best_ns_per_call(|i| {
        let (p, _, t) = black_box(inside[i & mask]);
        let w = law.eval_at_jump(p, jumps[i & mask], t).unwrap();
        w.conductance + w.d_conductance_dp
    });
    println!("lookup eval benchmark, 40 x 8 x 4 table, best of 7 x {CALLS} calls:");
    println!("  eval (inside, value + conductance + derivatives): {eval:6.1} ns/call");
    println!("  eval (mixed in/out of range, clamp):              {clamped:6.1} ns/call");
    println!("  eval_at_jump (flux from the jump, + derivatives): {at_jump:6.1} ns/call");
}
