//! The handout's functions as written (`sim::textbook`, what `--textbook`
//! runs) against the fast path the program runs by default:
//!
//! * one step from the same state: within 1e-11 (max vertex distance) on
//!   every bundled scene, 1e-12 on the dense path. The sparse paths add
//!   the same terms in different orders (the fast factor merges small
//!   supernodes, the textbook one goes row by row): about 1e-12 apart;
//!   the reference implementation, a third order, lands up to 6e-12 from
//!   either (`docs/fidelity.md`), and a wrong term (a mass, a spring)
//!   moves the flag's first step by 1e-5 or more;
//! * 100 steps from rest: within 1e-8 on every bundled scene that is not
//!   chaotic (all but the skirt, whose buckling turns rounding into
//!   centimetres);
//! * with the natural ordering and the simplicial factor on both paths,
//!   the same bits: the only difference between the paths is then where
//!   the code lives, not what it computes;
//! * a `Simulation` with `textbook` set runs exactly these functions.

use masssprings::linalg::sparse::{Method, Ordering};
use masssprings::mesh::{load_scene, Scene};
use masssprings::sim::textbook::{
    fast_mass_springs_precomputation_dense, fast_mass_springs_step_dense,
    fast_mass_springs_step_sparse, precomputation_ordered,
};
use masssprings::sim::{
    Dense, LinearAlgebra, Simulation, SimulationError, SimulationOptions, Sparse, StepMethod,
    DELTA_T,
};
use std::path::Path;

/// The bundled scenes, and whether each is chaotic.
const SCENES: [(&str, bool); 5] = [
    ("single-spring-horizontal", false),
    ("horizontal-chain", false),
    ("net", false),
    ("flag", false),
    ("skirt", true),
];

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("data/{name}.json"));
    load_scene(&path).unwrap()
}

fn gravity(n: usize) -> Vec<[f64; 3]> {
    vec![[0.0, -9.8, 0.0]; n]
}

fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (0..3).map(|c| (p[c] - q[c]).powi(2)).sum::<f64>().sqrt())
        .fold(0.0, f64::max)
}

/// The fast path's simulation of `scene` with the default options but
/// `ordering` and `factorization`.
fn fast<B: LinearAlgebra>(
    scene: &Scene,
    ordering: Ordering,
    factorization: Method,
) -> Simulation<B> {
    let options = SimulationOptions {
        ordering,
        factorization,
        ..SimulationOptions::default()
    };
    Simulation::<B>::from_scene(scene, options).unwrap()
}

/// One step of the handout's sparse functions from `(u_prev, u_cur)`.
fn handout_step_sparse(
    scene: &Scene,
    ordering: Ordering,
    state: [&[[f64; 3]]; 2],
) -> Vec<[f64; 3]> {
    let pre = precomputation_ordered(
        &scene.vertices,
        &scene.springs,
        scene.k,
        &scene.masses,
        &scene.pinned,
        DELTA_T,
        ordering,
    )
    .unwrap();
    let mut u_next = vec![[0.0; 3]; scene.vertices.len()];
    let [u_prev, u_cur] = state;
    fast_mass_springs_step_sparse(&pre, &gravity(u_cur.len()), u_prev, u_cur, &mut u_next);
    u_next
}

/// The state after `steps` steps of the fast path, as `(U_prev, U_cur)`.
fn moving_state(scene: &Scene, steps: usize) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut simulation = fast::<Sparse>(scene, Ordering::Amd, Method::Supernodal);
    for _ in 0..steps {
        simulation.step().unwrap();
    }
    let previous = simulation.previous_positions().to_vec();
    (previous, simulation.positions().to_vec())
}

#[test]
fn one_textbook_step_lands_within_1e_11_of_the_fast_path_on_every_bundled_scene() {
    for (name, _) in SCENES {
        let scene = scene(name);
        for steps_before in [0, 5] {
            let (u_prev, u_cur) = moving_state(&scene, steps_before);
            let mut fast = fast::<Sparse>(&scene, Ordering::Amd, Method::Supernodal);
            fast.set_state(&u_prev, &u_cur, steps_before).unwrap();
            fast.step().unwrap();
            let textbook = handout_step_sparse(&scene, Ordering::Amd, [&u_prev, &u_cur]);
            let distance = max_distance(&textbook, fast.positions());
            assert!(
                distance <= 1e-11,
                "{name}, step {}: {distance:e}",
                steps_before + 1
            );
        }
    }
}

#[test]
fn the_dense_textbook_step_lands_within_1e_12_of_the_dense_fast_path() {
    for name in ["single-spring-horizontal", "horizontal-chain", "net"] {
        let scene = scene(name);
        let (u_prev, u_cur) = moving_state(&scene, 5);
        let pre = fast_mass_springs_precomputation_dense(
            &scene.vertices,
            &scene.springs,
            scene.k,
            &scene.masses,
            &scene.pinned,
            DELTA_T,
        )
        .unwrap();
        let mut textbook = vec![[0.0; 3]; u_cur.len()];
        fast_mass_springs_step_dense(&pre, &gravity(u_cur.len()), &u_prev, &u_cur, &mut textbook);
        let mut fast = fast::<Dense>(&scene, Ordering::Amd, Method::Supernodal);
        fast.set_state(&u_prev, &u_cur, 5).unwrap();
        fast.step().unwrap();
        let distance = max_distance(&textbook, fast.positions());
        assert!(distance <= 1e-12, "{name}: {distance:e}");
    }
}

#[test]
fn a_hundred_textbook_steps_stay_within_1e_8_of_the_fast_path_where_the_motion_is_not_chaotic() {
    for (name, chaotic) in SCENES {
        if chaotic {
            continue;
        }
        let scene = scene(name);
        let options = SimulationOptions {
            textbook: true,
            ..SimulationOptions::default()
        };
        let mut textbook = Simulation::<Sparse>::from_scene(&scene, options).unwrap();
        let mut fast = fast::<Sparse>(&scene, Ordering::Amd, Method::Supernodal);
        for _ in 0..100 {
            textbook.step().unwrap();
            fast.step().unwrap();
        }
        let distance = max_distance(textbook.positions(), fast.positions());
        assert!(distance <= 1e-8, "{name}: {distance:e}");
    }
}

#[test]
fn in_natural_order_with_the_simplicial_factor_both_paths_give_the_same_bits() {
    for name in ["horizontal-chain", "net", "flag"] {
        let scene = scene(name);
        let (u_prev, u_cur) = moving_state(&scene, 3);
        let mut fast = fast::<Sparse>(&scene, Ordering::Natural, Method::Simplicial);
        fast.set_state(&u_prev, &u_cur, 3).unwrap();
        fast.step().unwrap();
        let textbook = handout_step_sparse(&scene, Ordering::Natural, [&u_prev, &u_cur]);
        for (i, (a, b)) in textbook.iter().zip(fast.positions()).enumerate() {
            assert_eq!(
                a.map(f64::to_bits),
                b.map(f64::to_bits),
                "{name}, vertex {i}"
            );
        }
    }
}

#[test]
fn a_textbook_simulation_runs_the_handout_functions_and_reports_nothing_measured() {
    let scene = scene("net");
    let options = SimulationOptions {
        textbook: true,
        ..SimulationOptions::default()
    };
    let mut simulation = Simulation::<Sparse>::from_scene(&scene, options).unwrap();
    assert!(
        simulation.system().is_none(),
        "no fast-path system is built"
    );
    let report = simulation.step().unwrap();
    assert_eq!((report.method, report.iterations), (StepMethod::Plain, 50));
    assert_eq!(
        (report.energy_decrease, report.relative_gradient),
        (None, None)
    );
    let v = &scene.vertices;
    let by_hand = handout_step_sparse(&scene, Ordering::Amd, [v, v]);
    assert_eq!(simulation.positions(), &by_hand[..]);
}

#[test]
fn the_textbook_path_refuses_what_the_handout_does_not_do() {
    let scene = scene("net");
    let mut options = SimulationOptions {
        textbook: true,
        ..SimulationOptions::default()
    };
    options.step.method = StepMethod::Lbfgs;
    let refused = Simulation::<Sparse>::from_scene(&scene, options).unwrap_err();
    assert!(
        matches!(&refused, SimulationError::InvalidInput(why) if why.contains("textbook")),
        "{refused}"
    );
}

#[test]
fn dragging_on_the_textbook_path_moves_the_vertex_as_on_the_fast_path() {
    let scene = scene("net");
    let textbook_options = SimulationOptions {
        textbook: true,
        ..SimulationOptions::default()
    };
    let mut textbook = Simulation::<Sparse>::from_scene(&scene, textbook_options).unwrap();
    let mut fast = fast::<Sparse>(&scene, Ordering::Amd, Method::Supernodal);
    let vertex = scene.vertices.len() / 2;
    let target = [0.3, -0.2, 0.5];
    for simulation in [&mut textbook, &mut fast] {
        simulation.start_drag(vertex, target).unwrap();
        for _ in 0..3 {
            simulation.step().unwrap();
        }
        simulation.drag_to([0.2, -0.1, 0.4]).unwrap();
        simulation.step().unwrap();
        simulation.end_drag().unwrap();
        simulation.step().unwrap();
    }
    let distance = max_distance(textbook.positions(), fast.positions());
    assert!(distance <= 1e-10, "{distance:e}");
}
