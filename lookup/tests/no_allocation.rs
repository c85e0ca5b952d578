//! `Law::eval` and `Law::eval_at_jump` never allocate, on success or failure
//! (a counting global allocator, counted per thread).

mod common;

use common::*;
use lookup::Extrapolation;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: forwards to the system allocator; the counter is a const-initialised
// thread-local Cell (no allocation, no destructor).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn eval_never_allocates() {
    let law = physical_law(Extrapolation::Linear);
    let mut rng = Lcg(5);
    let queries: Vec<(f64, f64, f64)> = (0..10_000)
        .map(|i| match i % 4 {
            0 => (
                rng.range(1e2, 1e9),
                rng.range(0.0, 3e6),
                rng.range(250.0, 450.0),
            ),
            1 => (f64::NAN, 1e5, 300.0),
            2 => (-1.0, 1e5, 300.0),
            _ => interior_query(&law, &mut rng, 0.0),
        })
        .collect();
    let before = ALLOCATIONS.with(Cell::get);
    let mut ok = 0usize;
    for &(p, h, t) in &queries {
        ok += law.eval(p, h, t).is_ok() as usize;
        ok += law.eval_at_jump(p, h * 1e-5, t).is_ok() as usize;
    }
    let after = ALLOCATIONS.with(Cell::get);
    assert!(ok > 5_000, "too few successful evaluations: {ok}");
    assert_eq!(after - before, 0, "eval allocated");
    // The counter does see allocations.
    let boxed = std::hint::black_box(Box::new(after));
    assert_eq!(ALLOCATIONS.with(Cell::get), after + 1, "{boxed}");
}
