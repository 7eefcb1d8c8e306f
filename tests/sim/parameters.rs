//! `Simulation::set_parameters`: changing k, Δt and the masses of a running
//! simulation refactors `Q` in place and then steps exactly as a simulation
//! built with those values from the start (sparse and dense).
use masssprings::mesh::load_scene;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, SimulationError, Sparse};
use std::path::Path;

fn net() -> masssprings::mesh::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/net.json");
    load_scene(&path).expect("the bundled net loads")
}

fn same_as_built_with_the_new_values<B: LinearAlgebra>() {
    let scene = net();
    let (k, delta_t, scale) = (3.0 * scene.k, 0.02, 2.5);
    let mut changed = Simulation::<B>::from_scene(&scene, SimulationOptions::default()).unwrap();
    changed.set_parameters(k, delta_t, scale).unwrap();
    assert_eq!(changed.mass_scale(), scale);
    assert_eq!(changed.options().delta_t, delta_t);
    assert_eq!(changed.k(), k);

    let masses: Vec<f64> = scene.masses.iter().map(|m| m * scale).collect();
    let options = SimulationOptions {
        delta_t,
        ..SimulationOptions::default()
    };
    let mut built = Simulation::<B>::new(
        &scene.vertices,
        &scene.springs,
        k,
        &masses,
        &scene.pinned,
        options,
    )
    .unwrap();
    for _ in 0..5 {
        changed.step().unwrap();
        built.step().unwrap();
    }
    for (a, b) in changed.positions().iter().zip(built.positions()) {
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-12 * (1.0 + b[c].abs()),
                "{a:?} vs {b:?}"
            );
        }
    }
    // The stiffer, heavier net sags differently from the original one.
    let mut original = Simulation::<B>::from_scene(&scene, SimulationOptions::default()).unwrap();
    for _ in 0..5 {
        original.step().unwrap();
    }
    assert_ne!(original.positions(), changed.positions());
}

#[test]
fn sparse_refactorization_steps_as_a_fresh_precomputation() {
    same_as_built_with_the_new_values::<Sparse>();
}

#[test]
fn dense_refactorization_steps_as_a_fresh_precomputation() {
    same_as_built_with_the_new_values::<Dense>();
}

#[test]
fn values_that_are_not_positive_are_refused_and_change_nothing() {
    let scene = net();
    let mut simulation =
        Simulation::<Sparse>::from_scene(&scene, SimulationOptions::default()).unwrap();
    for (k, delta_t, scale) in [
        (0.0, 0.03, 1.0),
        (-1.0, 0.03, 1.0),
        (f64::NAN, 0.03, 1.0),
        (1.0, 0.0, 1.0),
        (1.0, f64::INFINITY, 1.0),
        (1.0, 0.03, 0.0),
    ] {
        let refused = simulation.set_parameters(k, delta_t, scale);
        assert!(
            matches!(refused, Err(SimulationError::InvalidInput(_))),
            "{k} {delta_t} {scale}: {refused:?}"
        );
    }
    assert_eq!(simulation.k(), scene.k);
    assert_eq!(simulation.mass_scale(), 1.0);
}
