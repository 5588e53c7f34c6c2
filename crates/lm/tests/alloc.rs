//! Proves that repeated solves of the same or a smaller size allocate nothing: a counting global
//! allocator counts allocations made by this thread while the flag is set.

mod common;

use bounded_lm::{ForwardDifference, Options, SecantScaling, Solver, StepModel};
use common::expsum::ExpSum;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
thread_local! {
    static COUNT_THIS_THREAD: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNT_THIS_THREAD.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNT_THIS_THREAD.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn counted<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    COUNT_THIS_THREAD.with(|c| c.set(true));
    let out = f();
    COUNT_THIS_THREAD.with(|c| c.set(false));
    (out, ALLOCATIONS.load(Ordering::Relaxed) - before)
}

#[test]
fn repeated_solves_do_not_allocate() {
    let mut big = ExpSum::new(200, 6);
    let mut small = ExpSum::new(25, 4);
    let lower = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let upper = [10.0; 6];
    let mut solver = Solver::new();
    let adaptive = StepModel::Adaptive { delay: 2 };
    for (model, secant_scaling) in [
        (StepModel::GaussNewton, SecantScaling::Off),
        (adaptive, SecantScaling::Off),
        (StepModel::GaussNewton, SecantScaling::After { delay: 2 }),
        (adaptive, SecantScaling::After { delay: 0 }),
        (StepModel::GaussNewton, SecantScaling::After { delay: 0 }),
    ] {
        let mut options = Options {
            model,
            ..Options::default()
        };
        options.scaling.secant = secant_scaling;
        let start = [1.0, 0.3, 1.0, 1.5, 1.0, 4.0];
        // Warm-up solve sizes the workspace.
        let mut x = start;
        solver
            .solve(&mut big, &mut x, &lower, &upper, &options)
            .unwrap();
        for _ in 0..3 {
            let mut x = start;
            let (rep, n) = counted(|| {
                solver
                    .solve(&mut big, &mut x, &lower, &upper, &options)
                    .unwrap()
            });
            assert!(rep.iterations > 1);
            assert_eq!(
                n, 0,
                "same-size solve allocated ({model:?}, secant scaling {secant_scaling:?})"
            );
            let mut x = [1.0, 0.3, 1.0, 1.5];
            let (_, n) = counted(|| {
                solver
                    .solve(&mut small, &mut x, &lower[..4], &upper[..4], &options)
                    .unwrap()
            });
            assert_eq!(
                n, 0,
                "smaller solve allocated ({model:?}, secant scaling {secant_scaling:?})"
            );
        }
    }
    // A tall problem takes the blocked QR (`tall_qr`); after it, the smaller ones above take the
    // in-place QR again: neither allocates.
    let mut tall = ExpSum::new(2000, 6);
    const { assert!(2000 >= bounded_lm::qr::TALL_QR_MIN_ROWS) };
    let options = Options::default();
    let start = [1.0, 0.3, 1.0, 1.5, 1.0, 4.0];
    let mut x = start;
    solver
        .solve(&mut tall, &mut x, &lower, &upper, &options)
        .unwrap();
    for prob in [&mut tall, &mut big] {
        let mut x = start;
        let (rep, n) = counted(|| {
            solver
                .solve(prob, &mut x, &lower, &upper, &options)
                .unwrap()
        });
        assert!(rep.iterations > 1);
        assert_eq!(n, 0, "solve after a tall one allocated");
    }
    // The forward-difference adapter allocates only in its constructor.
    let mut fd = ForwardDifference::new(ExpSum::new(25, 4));
    let options = Options::default();
    let mut x = [1.0, 0.3, 1.0, 1.5];
    solver
        .solve(&mut fd, &mut x, &lower[..4], &upper[..4], &options)
        .unwrap();
    let mut x = [1.0, 0.3, 1.0, 1.5];
    let (_, n) = counted(|| {
        solver
            .solve(&mut fd, &mut x, &lower[..4], &upper[..4], &options)
            .unwrap()
    });
    assert_eq!(n, 0, "forward-difference solve allocated");
    // The counter works: a Vec allocation is seen.
    let (_, n) = counted(|| std::hint::black_box(vec![1.0f64; 10]));
    assert!(n >= 1);
}

/// A workspace sized up front by `Solver::with_capacity` (from `Workspace::required`) covers
/// every buffer: even the first solve allocates nothing, for the in-place and the tall QR.
#[test]
fn first_solve_with_capacity_does_not_allocate() {
    let lower = [0.0; 6];
    let upper = [10.0; 6];
    for rows in [200, 2000] {
        let mut problem = ExpSum::new(rows, 6);
        let mut solver = Solver::with_capacity(rows, 6);
        let mut x = [1.0, 0.3, 1.0, 1.5, 1.0, 4.0];
        let options = Options::default();
        let (rep, n) = counted(|| {
            solver
                .solve(&mut problem, &mut x, &lower, &upper, &options)
                .unwrap()
        });
        assert!(rep.iterations > 1);
        assert_eq!(n, 0, "first solve of {rows} rows allocated");
    }
}
