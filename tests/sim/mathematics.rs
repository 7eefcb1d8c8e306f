//! The assignment's mathematics, checked against nalgebra and against the
//! properties the method guarantees.
use crate::common;

use common::*;
use masssprings::linalg::LinalgError;
use masssprings::sim::local_step::project_springs;
use masssprings::sim::precomputation::MassSpringSystem;
use masssprings::sim::signed_incidence::{
    incidence_mul_points, incidence_transpose_mul_points, signed_incidence_matrix_dense,
    signed_incidence_matrix_sparse,
};
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::step::{solve_step, StepReport, StepState, StepWorkspace};
use masssprings::sim::textbook::{
    fast_mass_springs_precomputation_dense, fast_mass_springs_precomputation_sparse,
    fast_mass_springs_step_dense, fast_mass_springs_step_sparse,
};
use masssprings::sim::{
    Dense, LinearAlgebra, Simulation, SimulationError, Sparse, StepControl, StepMethod, DELTA_T,
    PIN_WEIGHT,
};
use nalgebra::DMatrix;
use proptest::prelude::*;

fn gravity(n: usize) -> Vec<[f64; 3]> {
    vec![[0.0, -9.8, 0.0]; n]
}

/// One step of the fast path with `iterations` plain iterations, its
/// energy and gradient measured for the report.
fn fast_step<B: LinearAlgebra>(
    system: &mut MassSpringSystem<B>,
    iterations: usize,
    state: [&[[f64; 3]]; 3],
    u_next: &mut [[f64; 3]],
) -> Result<StepReport, SimulationError> {
    let mut workspace = StepWorkspace::new(system);
    let control = StepControl {
        iterations,
        measure: true,
        ..StepControl::default()
    };
    let [f_ext, u_prev, u_cur] = state;
    let state = StepState {
        f_ext,
        u_prev,
        u_cur,
    };
    solve_step(system, &mut workspace, &control, state, u_next, None, None)
}

proptest! {
    #![proptest_config(proptest_config(128))]

    #[test]
    fn signed_incidence_times_positions_gives_spring_vectors(net in network(10)) {
        let a_dense = signed_incidence_matrix_dense(net.v.len(), &net.springs);
        let a_sparse = signed_incidence_matrix_sparse(net.v.len(), &net.springs);
        let oracle = DMatrix::from_fn(net.springs.len(), 3, |e, c| {
            let [i, j] = net.springs[e];
            net.v[i][c] - net.v[j][c]
        });
        let p = points_to_nalgebra(&net.v);
        assert_close(&(dense_to_nalgebra(&a_dense) * &p), &oracle, 1e-15);
        assert_close(&(csc_to_nalgebra(&a_sparse) * &p), &oracle, 1e-15);
    }

    #[test]
    fn products_with_a_from_the_spring_list_are_the_matrix_products_to_the_bit(
        n in 1usize..12,
        ends in prop::collection::vec((0usize..12, 0usize..12), 0..40),
        values in prop::collection::vec(prop::array::uniform3(-1e3f64..1e3), 40),
        x in prop::collection::vec(prop::array::uniform3(-1e3f64..1e3), 12),
    ) {
        // any springs: repeated ones, and a vertex joined to itself (a zero row of A)
        let springs: Vec<[usize; 2]> = ends.iter().map(|&(i, j)| [i % n, j % n]).collect();
        let d = &values[..springs.len()];
        let x = &x[..n];
        let a_sparse = signed_incidence_matrix_sparse(n, &springs);
        let a_dense = signed_incidence_matrix_dense(n, &springs);
        let (mut from_list, mut sparse, mut dense) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        incidence_transpose_mul_points(&springs, d, &mut from_list);
        a_sparse.transpose_mul_points(d, &mut sparse).unwrap();
        a_dense.transpose_mul_points(d, &mut dense).unwrap();
        prop_assert_eq!(&from_list, &sparse, "Aᵀd against the CSC product");
        prop_assert_eq!(&from_list, &dense, "Aᵀd against the dense product");
        let mut ax_list = vec![[0.0; 3]; springs.len()];
        let mut ax_sparse = vec![[0.0; 3]; springs.len()];
        incidence_mul_points(&springs, x, &mut ax_list);
        a_sparse.mul_points(x, &mut ax_sparse).unwrap();
        prop_assert_eq!(&ax_list, &ax_sparse, "A x against the CSC product");
    }

    #[test]
    fn q_is_k_at_a_plus_m_over_dt2_plus_w_ct_c(net in network(10)) {
        let n = net.v.len();
        let a = csc_to_nalgebra(&signed_incidence_matrix_sparse(n, &net.springs));
        let m = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(net.masses.clone()));
        let mut c = DMatrix::zeros(net.pinned.len(), n);
        for (p, &i) in net.pinned.iter().enumerate() { c[(p, i)] = 1.0; }
        let oracle = a.transpose() * &a * net.k + m / (DELTA_T * DELTA_T) + c.transpose() * &c * PIN_WEIGHT;
        let dense = fast_mass_springs_precomputation_dense(&net.v, &net.springs, net.k, &net.masses, &net.pinned, DELTA_T).unwrap();
        let sparse = fast_mass_springs_precomputation_sparse(&net.v, &net.springs, net.k, &net.masses, &net.pinned, DELTA_T).unwrap();
        assert_close(&dense_to_nalgebra(&dense.Q), &oracle, 1e-14);
        assert_close(&csc_to_nalgebra(&sparse.Q), &oracle, 1e-14);
        // the fast path's Q is the same matrix
        let fast = MassSpringSystem::<Sparse>::new(&net.v, &net.springs, net.k, &net.masses, &net.pinned, DELTA_T).unwrap();
        assert_close(&csc_to_nalgebra(&fast.Q), &oracle, 1e-14);
        // the pins' constant right-hand side, w CᵀC V, on both paths
        let pin_rhs = c.transpose() * &c * points_to_nalgebra(&net.v) * PIN_WEIGHT;
        assert_close(&points_to_nalgebra(&fast.pin_rhs), &pin_rhs, 1e-14);
        let handout_pins = masssprings::sim::textbook::pin_term(&sparse);
        assert_close(&points_to_nalgebra(&handout_pins), &pin_rhs, 1e-14);
        for (e, &[i, j]) in net.springs.iter().enumerate() {
            prop_assert!((sparse.r[e] - norm(sub(net.v[i], net.v[j]))).abs() < 1e-15);
        }
    }

    #[test]
    fn local_step_projects_every_spring_onto_its_rest_length(net in network(10), seed in prop::collection::vec(prop::array::uniform3(-1.0f64..1.0), 10)) {
        let p: Vec<[f64; 3]> = net.v.iter().zip(seed.iter().cycle()).map(|(v, s)| [v[0] + s[0], v[1] + s[1], v[2] + s[2]]).collect();
        let r: Vec<f64> = net.springs.iter().map(|&[i, j]| norm(sub(net.v[i], net.v[j]))).collect();
        let mut d = vec![[0.0; 3]; net.springs.len()];
        project_springs(&net.springs, &r, &p, &mut d);
        for (e, &[i, j]) in net.springs.iter().enumerate() {
            let spring = sub(p[i], p[j]);
            if norm(spring) > 1e-12 {
                prop_assert!((norm(d[e]) - r[e]).abs() <= 1e-12 * (1.0 + r[e]));
                // same direction: d · spring = |d| |spring|
                prop_assert!((dot(d[e], spring) - norm(d[e]) * norm(spring)).abs() <= 1e-12 * (1.0 + norm(spring)));
            }
        }
    }

    #[test]
    fn each_local_global_iteration_lowers_the_step_energy(net in network(8)) {
        let n = net.v.len();
        let mut system = MassSpringSystem::<Sparse>::new(&net.v, &net.springs, net.k, &net.masses, &net.pinned, DELTA_T).unwrap();
        let f_ext = gravity(n);
        let (u_prev, u_cur) = (net.v.clone(), net.v.clone());
        let mut previous = f64::INFINITY;
        for iterations in 1..=8 {
            let mut u_next = vec![[0.0; 3]; n];
            fast_step(&mut system, iterations, [&f_ext, &u_prev, &u_cur], &mut u_next).unwrap();
            let energy = step_energy(&net, &f_ext, &u_prev, &u_cur, &u_next);
            prop_assert!(energy <= previous + 1e-9 * previous.abs().max(1.0), "iteration {iterations}: {energy} > {previous}");
            previous = energy;
        }
    }

    #[test]
    fn dense_and_sparse_steps_agree(net in network(10)) {
        let n = net.v.len();
        let options = SimulationOptions::default();
        let mut dense = Simulation::<Dense>::new(&net.v, &net.springs, net.k, &net.masses, &net.pinned, options).unwrap();
        let mut sparse = Simulation::<Sparse>::new(&net.v, &net.springs, net.k, &net.masses, &net.pinned, options).unwrap();
        for _ in 0..5 {
            dense.step().unwrap();
            sparse.step().unwrap();
        }
        let scale = 1.0 + net.v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            for c in 0..3 {
                let (a, b) = (dense.positions()[i][c], sparse.positions()[i][c]);
                prop_assert!((a - b).abs() <= 1e-9 * scale, "vertex {i}: {a} vs {b}");
            }
        }
    }
}

#[test]
fn a_network_at_rest_without_forces_stays_at_rest() {
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let springs = vec![[0, 1], [1, 2], [2, 0]];
    let handout =
        fast_mass_springs_precomputation_sparse(&v, &springs, 100.0, &[1.0; 3], &[0], DELTA_T)
            .unwrap();
    let mut system =
        MassSpringSystem::<Sparse>::new(&v, &springs, 100.0, &[1.0; 3], &[0], DELTA_T).unwrap();
    let (mut textbook, mut fast) = (vec![[0.0; 3]; 3], vec![[0.0; 3]; 3]);
    let still = [[0.0; 3]; 3];
    fast_mass_springs_step_sparse(&handout, &still, &v, &v, &mut textbook);
    let report = fast_step(&mut system, 50, [&still, &v, &v], &mut fast).unwrap();
    assert_eq!(report.iterations, 50);
    assert!(report.relative_gradient.unwrap() < 1e-12, "{report:?}");
    for u_next in [textbook, fast] {
        for i in 0..3 {
            for c in 0..3 {
                assert!((u_next[i][c] - v[i][c]).abs() < 1e-12);
            }
        }
    }
}

#[test]
fn the_dense_and_sparse_entry_points_are_the_same_algorithm() {
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let springs = vec![[0, 1]];
    let dense =
        fast_mass_springs_precomputation_dense(&v, &springs, 500.0, &[1.0; 2], &[0], DELTA_T)
            .unwrap();
    let sparse =
        fast_mass_springs_precomputation_sparse(&v, &springs, 500.0, &[1.0; 2], &[0], DELTA_T)
            .unwrap();
    let (mut a, mut b) = (vec![[0.0; 3]; 2], vec![[0.0; 3]; 2]);
    fast_mass_springs_step_dense(&dense, &gravity(2), &v, &v, &mut a);
    fast_mass_springs_step_sparse(&sparse, &gravity(2), &v, &v, &mut b);
    assert!(a[1][1] < 0.0, "the free end falls");
    for i in 0..2 {
        for c in 0..3 {
            assert!((a[i][c] - b[i][c]).abs() < 1e-12);
        }
    }
}

#[test]
fn pinned_vertices_stay_within_a_micrometre_of_rest() {
    let side = 8;
    let (v, springs) = cloth(side);
    let masses = vec![1.0 / (side * side) as f64; v.len()];
    let pinned = vec![0, side - 1];
    let mut sim = Simulation::<Sparse>::new(
        &v,
        &springs,
        1e4,
        &masses,
        &pinned,
        SimulationOptions::default(),
    )
    .unwrap();
    for _ in 0..30 {
        sim.step().unwrap();
        for &i in &pinned {
            assert!(norm(sub(sim.positions()[i], v[i])) < 1e-6);
        }
    }
}

#[test]
fn non_finite_forces_are_reported_not_propagated() {
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let mut system =
        MassSpringSystem::<Sparse>::new(&v, &[[0, 1]], 500.0, &[1.0; 2], &[0], DELTA_T).unwrap();
    let mut u_next = vec![[0.0; 3]; 2];
    let forces = [[0.0; 3], [f64::NAN, 0.0, 0.0]];
    let error = fast_step(&mut system, 50, [&forces, &v, &v], &mut u_next).unwrap_err();
    assert!(
        matches!(error, SimulationError::NotFinite { .. }),
        "{error}"
    );
}

#[test]
fn a_q_that_is_not_positive_definite_is_reported() {
    // a negative stiffness makes Q indefinite
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    for result in [
        MassSpringSystem::<Sparse>::new(&v, &[[0, 1]], -1e6, &[1.0; 2], &[], DELTA_T).map(|_| ()),
        MassSpringSystem::<Dense>::new(&v, &[[0, 1]], -1e6, &[1.0; 2], &[], DELTA_T).map(|_| ()),
    ] {
        assert!(
            matches!(
                result,
                Err(SimulationError::Linalg(
                    LinalgError::NotPositiveDefinite { .. }
                ))
            ),
            "{result:?}"
        );
    }
}

#[test]
fn inconsistent_inputs_are_rejected() {
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let nan = vec![[0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0]];
    // (positions, springs, masses, pins): each with one thing wrong
    type Inputs<'a> = (&'a [[f64; 3]], &'a [[usize; 2]], &'a [f64], &'a [usize]);
    let cases: [Inputs; 5] = [
        (&v, &[[0, 2]], &[1.0; 2], &[]), // a spring to a vertex that is not there
        (&v, &[[0, 1]], &[1.0; 3], &[]), // one mass too many
        (&v, &[[0, 1]], &[1.0, 0.0], &[]), // a zero mass
        (&v, &[[0, 1]], &[1.0; 2], &[5]), // a pin beyond the vertices
        (&nan, &[[0, 1]], &[1.0; 2], &[]), // a NaN coordinate
    ];
    for (positions, springs, masses, pins) in cases {
        let result =
            MassSpringSystem::<Sparse>::new(positions, springs, 1.0, masses, pins, DELTA_T);
        assert!(
            matches!(result, Err(SimulationError::InvalidInput(_))),
            "{springs:?} {masses:?} {pins:?}"
        );
    }
}

#[test]
fn changing_pins_refactors_to_the_same_system_as_precomputing_afresh() {
    let (v, springs) = cloth(6);
    let masses = vec![0.05; v.len()];
    let mut moved =
        MassSpringSystem::<Sparse>::new(&v, &springs, 1e3, &masses, &[0], DELTA_T).unwrap();
    moved.set_pins(&[0, 5, 30], &[v[0], v[5], v[30]]).unwrap();
    let fresh =
        MassSpringSystem::<Sparse>::new(&v, &springs, 1e3, &masses, &[0, 5, 30], DELTA_T).unwrap();
    assert_close(&csc_to_nalgebra(&moved.Q), &csc_to_nalgebra(&fresh.Q), 0.0);
    assert_close(
        &points_to_nalgebra(&moved.pin_rhs),
        &points_to_nalgebra(&fresh.pin_rhs),
        0.0,
    );
    let (mut a, mut b) = (moved.clone(), fresh.clone());
    let (mut ua, mut ub) = (vec![[0.0; 3]; v.len()], vec![[0.0; 3]; v.len()]);
    let f = gravity(v.len());
    fast_step(&mut a, 5, [&f, &v, &v], &mut ua).unwrap();
    fast_step(&mut b, 5, [&f, &v, &v], &mut ub).unwrap();
    assert_close(&points_to_nalgebra(&ua), &points_to_nalgebra(&ub), 1e-12);
}

#[test]
fn a_simulation_holds_q_only_for_a_method_that_multiplies_by_it() {
    let (v, springs) = cloth(6);
    let masses = vec![0.05; v.len()];
    let fresh = |pins: &[usize]| {
        MassSpringSystem::<Sparse>::new(&v, &springs, 1e3, &masses, pins, DELTA_T).unwrap()
    };
    let with = |method| SimulationOptions {
        step: masssprings::sim::StepControl {
            method,
            ..masssprings::sim::StepControl::default()
        },
        ..SimulationOptions::default()
    };
    let mut plain =
        Simulation::<Sparse>::new(&v, &springs, 1e3, &masses, &[0], with(StepMethod::Plain))
            .unwrap();
    let mut lbfgs =
        Simulation::<Sparse>::new(&v, &springs, 1e3, &masses, &[0], with(StepMethod::Lbfgs))
            .unwrap();
    assert!(fresh(&[0]).holds_q());
    assert!(!plain.system().unwrap().holds_q() && lbfgs.system().unwrap().holds_q());
    assert_eq!(
        plain.system().unwrap().Q.nnz(),
        0,
        "a released Q holds no entries"
    );
    // Q is still there to read, assembled anew, the same to the bit
    assert_close(
        &csc_to_nalgebra(&plain.system().unwrap().q()),
        &csc_to_nalgebra(&fresh(&[0]).Q),
        0.0,
    );
    // a drag refactors a released Q, and leaves it released
    plain.start_drag(30, v[30]).unwrap();
    assert!(!plain.system().unwrap().holds_q());
    assert_close(
        &csc_to_nalgebra(&plain.system().unwrap().q()),
        &csc_to_nalgebra(&fresh(&[0, 30]).Q),
        0.0,
    );
    plain.end_drag().unwrap();
    // an L-BFGS step holds Q again, and steps as a simulation made for it
    let control = StepControl {
        method: StepMethod::Lbfgs,
        tolerance: Some(1e-8),
        ..StepControl::default()
    };
    for _ in 0..3 {
        plain.step_with(&control, None).unwrap();
        lbfgs.step_with(&control, None).unwrap();
    }
    assert!(plain.system().unwrap().holds_q());
    assert_eq!(plain.positions(), lbfgs.positions());
}

#[test]
fn a_dragged_vertex_follows_its_target_and_is_released() {
    let (v, springs) = cloth(6);
    let masses = vec![0.05; v.len()];
    let mut sim = Simulation::<Sparse>::new(
        &v,
        &springs,
        1e3,
        &masses,
        &[0, 5],
        SimulationOptions::default(),
    )
    .unwrap();
    let target = [0.5, 0.5, 1.0];
    sim.start_drag(35, target).unwrap();
    sim.step().unwrap();
    assert!(norm(sub(sim.positions()[35], target)) < 1e-6);
    let target = [0.2, 0.1, 0.7];
    sim.drag_to(target).unwrap();
    sim.step().unwrap();
    assert!(norm(sub(sim.positions()[35], target)) < 1e-6);
    sim.end_drag().unwrap();
    assert_eq!(sim.dragged(), None);
    sim.step().unwrap();
    assert!(
        norm(sub(sim.positions()[35], target)) > 1e-3,
        "released, it moves on"
    );
    sim.reset().unwrap();
    assert_eq!(sim.positions(), v.as_slice());
    assert_eq!(sim.steps(), 0);
}

#[test]
fn wind_pushes_the_cloth_along_x_and_repeats_exactly() {
    let (v, springs) = cloth(6);
    let masses = vec![0.05; v.len()];
    let options = SimulationOptions {
        wind: true,
        ..SimulationOptions::default()
    };
    let run = || {
        let mut sim =
            Simulation::<Sparse>::new(&v, &springs, 1e3, &masses, &[0, 5], options).unwrap();
        for _ in 0..10 {
            sim.step().unwrap();
        }
        sim.positions().to_vec()
    };
    let (first, second) = (run(), run());
    assert_eq!(first, second);
    let mean_x = |p: &[[f64; 3]]| p.iter().map(|q| q[0]).sum::<f64>() / p.len() as f64;
    let mut calm = Simulation::<Sparse>::new(
        &v,
        &springs,
        1e3,
        &masses,
        &[0, 5],
        SimulationOptions::default(),
    )
    .unwrap();
    for _ in 0..10 {
        calm.step().unwrap();
    }
    assert!(mean_x(&first) > mean_x(calm.positions()));
}

/// A `side × side` cloth with all six corner pairs of each quad as springs.
fn cloth(side: usize) -> (Vec<[f64; 3]>, Vec<[usize; 2]>) {
    let mut v = Vec::new();
    for j in 0..side {
        for i in 0..side {
            v.push([
                i as f64 / (side - 1) as f64,
                1.0 - j as f64 / (side - 1) as f64,
                0.0,
            ]);
        }
    }
    let mut springs = std::collections::BTreeSet::new();
    for j in 0..side - 1 {
        for i in 0..side - 1 {
            let c = [
                j * side + i,
                (j + 1) * side + i,
                (j + 1) * side + i + 1,
                j * side + i + 1,
            ];
            for a in 0..4 {
                for b in a + 1..4 {
                    springs.insert([c[a].min(c[b]), c[a].max(c[b])]);
                }
            }
        }
    }
    (v, springs.into_iter().collect())
}

#[test]
fn the_supernodes_option_reaches_the_simulations_factor() {
    use masssprings::linalg::sparse::SupernodeMerging;
    use masssprings::mesh::procedural;
    let scene = procedural::grid(16).to_scene().unwrap();
    let supernodes = |merging: SupernodeMerging| {
        let options = SimulationOptions {
            supernodes: merging,
            ..SimulationOptions::default()
        };
        let simulation =
            masssprings::sim::Simulation::<masssprings::sim::Sparse>::from_scene(&scene, options)
                .unwrap();
        let factor = &simulation.system().unwrap().prefactorization;
        (
            factor.symbolic().supernodes().len(),
            factor.symbolic().explicit_zeros(),
        )
    };
    let (fundamental, small) = (
        supernodes(SupernodeMerging::Fundamental),
        supernodes(SupernodeMerging::Small),
    );
    assert_eq!(
        SimulationOptions::default().supernodes,
        SupernodeMerging::Small
    );
    assert_eq!(fundamental.1, 0, "fundamental supernodes store no zeros");
    assert!(small.0 < fundamental.0, "{small:?} against {fundamental:?}");
    assert!(small.1 > 0, "merging stores some zeros");
}

/// A simulation of a 6 × 6 cloth hanging from two corners, solved as
/// `options` say, on backend `B`.
fn hanging_cloth<B: LinearAlgebra>(options: SimulationOptions) -> Simulation<B> {
    let (v, springs) = cloth(6);
    let masses = vec![0.05; v.len()];
    Simulation::<B>::new(&v, &springs, 1e3, &masses, &[0, 5], options).unwrap()
}

#[test]
fn the_named_solvers_are_one_rule_and_read_back() {
    use masssprings::sim::{Accuracy, Pins, Solver, Start};
    let measured = SimulationOptions {
        step: StepControl {
            measure: true,
            method: StepMethod::Newton,
            tolerance: Some(1e-3),
            iterations: 7,
            ..StepControl::default()
        },
        pins: Pins::Exact,
        wind: true,
        ..SimulationOptions::default()
    };
    assert_eq!(
        measured.solver(),
        None,
        "Newton to a tolerance is no named solver"
    );
    for solver in Solver::ALL {
        let options = measured.solved_by(solver);
        assert_eq!(options.solver(), Some(solver));
        assert_eq!(solver.name().parse::<Solver>(), Ok(solver));
        assert!(options.step.measure && options.wind, "kept: {options:?}");
        assert_eq!(options.pins, Pins::Penalty);
        assert!(options.check_textbook().is_ok());
    }
    let fast = measured.solved_by(Solver::Accuracy(Accuracy::Assignment));
    assert_eq!(fast.step.method, StepMethod::Lbfgs);
    assert!(fast.step.plain_first && !fast.textbook);
    let budget = SimulationOptions {
        step: StepControl {
            iterations: 5,
            ..fast.step
        },
        ..fast
    };
    assert_eq!(
        budget.solver(),
        fast.solver(),
        "an accuracy whatever its budget"
    );
    let assignment = measured.solved_by(Solver::Assignment);
    assert_eq!(
        (assignment.step.iterations, assignment.textbook),
        (50, false)
    );
    let more = |step: StepControl| SimulationOptions { step, ..assignment }.solver();
    assert_eq!(
        more(StepControl {
            iterations: 51,
            ..assignment.step
        }),
        None
    );
    assert_eq!(
        more(StepControl {
            start: Start::Inertial,
            ..assignment.step
        }),
        None
    );
    let textbook = measured.solved_by(Solver::Textbook);
    let inertial = SimulationOptions {
        step: StepControl {
            start: Start::Inertial,
            ..textbook.step
        },
        ..textbook
    };
    assert!(
        inertial.check_textbook().is_err(),
        "the handout's rules hold"
    );
    assert!("newton".parse::<Solver>().is_err());
}

/// Steps `simulation` once with its cancel flag already set: the step is
/// refused as cancelled and the state is the one before it.
fn cancelled_step<B: LinearAlgebra>(simulation: &mut Simulation<B>) {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    simulation.step().unwrap();
    let (before, previous) = (
        simulation.positions().to_vec(),
        simulation.previous_positions().to_vec(),
    );
    let flag = Arc::new(AtomicBool::new(true));
    simulation.set_cancel(Some(Arc::clone(&flag)));
    assert_eq!(simulation.step(), Err(SimulationError::Cancelled));
    assert_eq!(simulation.steps(), 1);
    assert_eq!(simulation.positions(), before.as_slice());
    assert_eq!(simulation.previous_positions(), previous.as_slice());
    flag.store(false, Ordering::Relaxed);
    simulation.step().unwrap();
    assert_eq!(simulation.steps(), 2, "cleared, the flag stops nothing");
}

#[test]
fn a_cancelled_step_leaves_the_state_at_the_last_completed_step() {
    use masssprings::sim::{Accuracy, Solver};
    for method in StepMethod::ALL {
        let step = StepControl {
            method,
            ..StepControl::default()
        };
        let options = SimulationOptions {
            step,
            ..SimulationOptions::default()
        };
        cancelled_step(&mut hanging_cloth::<Sparse>(options));
    }
    for solver in [Solver::Textbook, Solver::Accuracy(Accuracy::Assignment)] {
        let options = SimulationOptions::default().solved_by(solver);
        cancelled_step(&mut hanging_cloth::<Sparse>(options));
        cancelled_step(&mut hanging_cloth::<Dense>(options));
    }
}

#[test]
fn a_long_step_stops_between_iterations_when_cancelled_from_another_thread() {
    use masssprings::sim::Solver;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    use std::time::{Duration, Instant};
    let long = |options: SimulationOptions| SimulationOptions {
        step: StepControl {
            iterations: 100_000_000, // hours
            ..options.step
        },
        ..options
    };
    let fast = long(SimulationOptions::default());
    let textbook = long(SimulationOptions::default().solved_by(Solver::Textbook));
    for options in [fast, textbook] {
        let mut simulation = hanging_cloth::<Sparse>(options);
        let flag = Arc::new(AtomicBool::new(false));
        simulation.set_cancel(Some(Arc::clone(&flag)));
        let started = Instant::now();
        let result = std::thread::scope(|scope| {
            scope.spawn(|| {
                std::thread::sleep(Duration::from_millis(100));
                flag.store(true, Ordering::Relaxed);
            });
            simulation.step()
        });
        assert_eq!(result, Err(SimulationError::Cancelled));
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "{:?}",
            started.elapsed()
        );
        assert_eq!(simulation.steps(), 0);
        assert_eq!(simulation.positions(), cloth(6).0.as_slice());
    }
}

#[test]
fn the_mechanical_energy_is_kinetic_plus_spring_plus_gravity_and_zero_at_rest() {
    let vertices = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let (k, masses) = (500.0, [1.0, 2.0]);
    let mut sim = Simulation::<Sparse>::new(
        &vertices,
        &[[0, 1]],
        k,
        &masses,
        &[0],
        SimulationOptions::default(),
    )
    .unwrap();
    assert_eq!(sim.mechanical_energy(), 0.0);
    for _ in 0..3 {
        sim.step().unwrap();
    }
    sim.set_parameters(k, DELTA_T, 3.0).unwrap(); // masses × 3
    let (now, before) = (sim.positions(), sim.previous_positions());
    let mut expected = 0.0;
    for i in 0..2 {
        let v = sub(now[i], before[i]);
        expected += 0.5 * 3.0 * masses[i] * dot(v, v) / (DELTA_T * DELTA_T);
        expected += 9.8 * (now[i][1] - vertices[i][1]);
    }
    let stretch = norm(sub(now[1], now[0])) - 1.0;
    expected += 0.5 * k * stretch * stretch;
    let energy = sim.mechanical_energy();
    assert!(
        (energy - expected).abs() <= 1e-12 * expected.abs().max(1.0),
        "{energy} {expected}"
    );
}

#[test]
fn a_set_flag_stops_the_precomputation_on_both_backends_and_paths_and_their_steps() {
    use masssprings::mesh::procedural;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let scene = procedural::grid(6).to_scene().unwrap();
    let textbook = SimulationOptions {
        textbook: true,
        ..SimulationOptions::default()
    };
    for options in [SimulationOptions::default(), textbook] {
        let set = Arc::new(AtomicBool::new(true));
        let dense = Simulation::<Dense>::from_scene_cancellable(&scene, options, Arc::clone(&set));
        assert_eq!(dense.err(), Some(SimulationError::Cancelled), "{options:?}");
        let sparse =
            Simulation::<Sparse>::from_scene_cancellable(&scene, options, Arc::clone(&set));
        assert_eq!(
            sparse.err(),
            Some(SimulationError::Cancelled),
            "{options:?}"
        );
        set.store(false, Ordering::Relaxed);
        let made = |cancel| Simulation::<Sparse>::from_scene_cancellable(&scene, options, cancel);
        let mut sparse = made(Arc::clone(&set)).unwrap();
        let mut dense =
            Simulation::<Dense>::from_scene_cancellable(&scene, options, Arc::clone(&set)).unwrap();
        // Their steps look at the same flag.
        set.store(true, Ordering::Relaxed);
        assert_eq!(sparse.step().err(), Some(SimulationError::Cancelled));
        assert_eq!(dense.step().err(), Some(SimulationError::Cancelled));
        set.store(false, Ordering::Relaxed);
        dense.step().unwrap();
        sparse.step().unwrap();
        let apart = dense
            .positions()
            .iter()
            .zip(sparse.positions())
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0, f64::max);
        assert!(apart < 1e-9, "{options:?}: {apart}");
    }
}

#[test]
fn the_simulated_time_adds_each_steps_own_time_step() {
    let mut sim = hanging_cloth::<Sparse>(SimulationOptions::default());
    for _ in 0..3 {
        sim.step().unwrap();
    }
    assert_eq!(sim.time(), 3.0 * DELTA_T);
    sim.set_parameters(sim.k(), 0.01, 1.0).unwrap();
    sim.step().unwrap();
    sim.step().unwrap();
    assert!(
        (sim.time() - (3.0 * DELTA_T + 0.02)).abs() < 1e-15,
        "{}",
        sim.time()
    );
    sim.set_time(5.0);
    sim.step().unwrap();
    assert!((sim.time() - 5.01).abs() < 1e-12, "{}", sim.time());
    sim.reset().unwrap();
    assert_eq!(sim.time(), 0.0);
}
