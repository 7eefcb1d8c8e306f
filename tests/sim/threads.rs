//! Trajectories on 1, 2, 3 and 4 threads (more than a small machine's
//! cores): the same positions to the bit after every step, for every
//! iteration method, both kinds of pins, with the wind, and with the
//! portable kernels.
use masssprings::linalg::kernels::Kernels;
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::{Pins, Simulation, SimulationOptions, Sparse, StepMethod};

/// A scene of `data/`.
fn scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name);
    load_scene(&path).unwrap()
}

/// The bits of every position after each of `steps` steps.
fn trajectory(scene: &Scene, options: SimulationOptions, steps: usize) -> Vec<Vec<u64>> {
    let mut simulation = Simulation::<Sparse>::from_scene(scene, options).unwrap();
    assert_eq!(simulation.threads(), options.threads, "{options:?}");
    (0..steps)
        .map(|_| {
            simulation.step().unwrap();
            simulation
                .positions()
                .iter()
                .flatten()
                .map(|v| v.to_bits())
                .collect()
        })
        .collect()
}

/// The trajectory of `options` on 2, 3 and 4 threads is that on one.
fn same_on_any_threads(scene: &Scene, options: SimulationOptions, steps: usize, what: &str) {
    let one = trajectory(
        scene,
        SimulationOptions {
            threads: 1,
            ..options
        },
        steps,
    );
    for threads in [2, 3, 4] {
        let many = trajectory(scene, SimulationOptions { threads, ..options }, steps);
        for (step, (a, b)) in one.iter().zip(&many).enumerate() {
            assert!(
                a == b,
                "{what}: step {} differs on {threads} threads",
                step + 1
            );
        }
    }
}

#[test]
fn every_method_steps_to_the_same_bits_on_any_threads() {
    let flag = scene("flag.json");
    for method in StepMethod::ALL {
        let mut options = SimulationOptions::default();
        options.step.method = method;
        options.step.iterations = 10;
        same_on_any_threads(&flag, options, 3, method.name());
    }
}

#[test]
fn the_skirt_in_the_wind_with_exact_or_penalty_pins_is_the_same_on_any_threads() {
    let skirt = scene("skirt.json");
    for pins in [Pins::Penalty, Pins::Exact] {
        let options = SimulationOptions {
            wind: true,
            pins,
            ..SimulationOptions::default()
        };
        same_on_any_threads(&skirt, options, 3, &format!("skirt {pins:?}"));
    }
}

#[test]
fn the_portable_kernels_give_their_own_bits_on_any_threads() {
    let options = SimulationOptions {
        kernels: Kernels::Portable,
        ..SimulationOptions::default()
    };
    same_on_any_threads(&scene("flag.json"), options, 5, "portable");
}

#[test]
fn a_scene_gets_at_most_one_thread_per_vertices_per_thread() {
    let asked = SimulationOptions {
        threads: 4,
        ..SimulationOptions::default()
    };
    let threads = |name: &str| {
        Simulation::<Sparse>::from_scene(&scene(name), asked)
            .unwrap()
            .threads()
    };
    assert_eq!(threads("net.json"), 1, "81 vertices");
    assert_eq!(threads("horizontal-chain.json"), 1, "11 vertices");
    assert_eq!(threads("flag.json"), 4, "3,200 vertices");
}
