//! The time step and the solves allocate nothing: every buffer is sized at
//! precomputation (the design's performance shape). A counting allocator
//! checks it.

use masssprings::linalg::sparse::{Method, Ordering, SparseCholesky, SymbolicCholesky};
use masssprings::mesh::load_scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, Sparse, StepMethod};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering as AtomicOrdering};

/// The system allocator, counting the allocations this thread asks for.
struct CountingAllocator;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static COUNTING: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, AtomicOrdering::SeqCst);
        }
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.with(|c| c.get()) {
            ALLOCATIONS.fetch_add(1, AtomicOrdering::SeqCst);
        }
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: CountingAllocator = CountingAllocator;

/// How many allocations `work` makes on this thread.
fn allocations_during(work: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.load(AtomicOrdering::SeqCst);
    COUNTING.with(|c| c.set(true));
    work();
    COUNTING.with(|c| c.set(false));
    ALLOCATIONS.load(AtomicOrdering::SeqCst) - before
}

fn step_allocations<B: LinearAlgebra>(scene: &str) -> usize {
    let options = SimulationOptions {
        wind: true,
        ..SimulationOptions::default()
    };
    step_allocations_with::<B>(scene, options)
}

fn step_allocations_with<B: LinearAlgebra>(scene: &str, options: SimulationOptions) -> usize {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(scene);
    let scene = load_scene(&path).unwrap();
    let mut simulation = Simulation::<B>::from_scene(&scene, options).unwrap();
    simulation.step().unwrap(); // the first step may touch pages, not allocate
    allocations_during(|| {
        for _ in 0..3 {
            simulation.step().unwrap();
        }
    })
}

#[test]
fn a_sparse_step_allocates_nothing() {
    assert_eq!(step_allocations::<Sparse>("flag.json"), 0);
}

#[test]
fn a_step_on_the_textbook_path_allocates_nothing() {
    let options = SimulationOptions {
        ordering: Ordering::Natural,
        factorization: Method::Simplicial,
        ..SimulationOptions::default()
    };
    assert_eq!(step_allocations_with::<Sparse>("net.json", options), 0);
}

#[test]
fn a_dense_step_allocates_nothing() {
    assert_eq!(step_allocations::<Dense>("net.json"), 0);
}

#[test]
fn no_method_allocates_after_its_first_step() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/net.json");
    let scene = load_scene(&path).unwrap();
    for method in StepMethod::ALL {
        let options = SimulationOptions {
            step: masssprings::sim::StepControl {
                method,
                tolerance: Some(1e-9),
                energy_tolerance: Some(1e-12),
                at_least_plain: Some(2.0),
                iterations: 30,
                ..masssprings::sim::StepControl::default()
            },
            ..SimulationOptions::default()
        };
        let mut simulation = Simulation::<Sparse>::from_scene(&scene, options).unwrap();
        simulation.step().unwrap(); // sizes the method's work arrays
        let count = allocations_during(|| {
            for _ in 0..3 {
                simulation.step().unwrap();
            }
        });
        assert_eq!(count, 0, "{method}");
    }
}

#[test]
fn solves_and_refactorizations_allocate_nothing() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/skirt.json");
    let scene = load_scene(&path).unwrap();
    let system = masssprings::sim::precomputation::MassSpringSystem::<Sparse>::new(
        &scene.vertices,
        &scene.springs,
        scene.k,
        &scene.masses,
        &scene.pinned,
        masssprings::sim::DELTA_T,
    )
    .unwrap();
    let q = system.Q;
    for method in [Method::Supernodal, Method::Simplicial] {
        let symbolic = SymbolicCholesky::analyze(&q, Ordering::Amd).unwrap();
        let mut cholesky = SparseCholesky::factor(symbolic, &q, method).unwrap();
        let mut points = vec![[1.0, 2.0, 3.0]; q.ncols()];
        let mut column = vec![1.0; q.ncols()];
        let count = allocations_during(|| {
            cholesky.refactor(&q).unwrap();
            cholesky.solve_points_in_place(&mut points);
            cholesky.solve_in_place(&mut column);
        });
        assert_eq!(count, 0, "{method:?}");
    }
}
