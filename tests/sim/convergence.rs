//! The energy a step minimises, its gradient and Hessian, and the five
//! methods that minimise it: checked against nalgebra, finite differences,
//! an independent prototype, and each other.
use crate::common;

use common::*;
use masssprings::mesh::load_scene;
use masssprings::sim::energy::{start_lengths, StepEnergy};
use masssprings::sim::hessian::Hessian;
use masssprings::sim::monitor::Iterate;
use masssprings::sim::Start;
use masssprings::sim::{Pins, SimulationOptions};
use masssprings::sim::{
    Simulation, SimulationError, Sparse, StepControl, StepMethod, StepReport, Stop, DELTA_T,
};
use nalgebra::DMatrix;
use proptest::prelude::*;
use std::path::{Path, PathBuf};

/// One step's data for a random network: everything [`StepEnergy`] borrows.
#[derive(Debug, Clone)]
struct StepData {
    net: Network,
    r: Vec<f64>,
    pin_targets: Vec<[f64; 3]>,
    inertial_target: Vec<[f64; 3]>,
    f_ext: Vec<[f64; 3]>,
    start: Vec<[f64; 3]>,
    w: f64,
    start_lengths: Vec<f64>,
}

impl StepData {
    fn energy(&self) -> StepEnergy<'_> {
        StepEnergy {
            springs: &self.net.springs,
            r: &self.r,
            k: self.net.k,
            m: &self.net.masses,
            delta_t: DELTA_T,
            w: self.w,
            pinned: &self.net.pinned,
            pin_targets: &self.pin_targets,
            inertial_target: &self.inertial_target,
            f_ext: &self.f_ext,
            start: &self.start,
            start_lengths: &self.start_lengths,
        }
    }
}

/// A random network with a random start, inertial target and forces, and
/// a moderate pin weight (so that finite differences are well-conditioned).
fn step_data() -> impl Strategy<Value = (StepData, Vec<[f64; 3]>)> {
    step_data_up_to(7)
}

/// [`step_data`] with up to `max_n` vertices.
fn step_data_up_to(max_n: usize) -> impl Strategy<Value = (StepData, Vec<[f64; 3]>)> {
    network(max_n)
        .prop_flat_map(|net| {
            let n = net.v.len();
            let points = move || prop::collection::vec(prop::array::uniform3(-0.3f64..0.3), n);
            (Just(net), points(), points(), points(), points())
        })
        .prop_map(|(net, start_offset, target_offset, forces, p_offset)| {
            let r = net
                .springs
                .iter()
                .map(|&[i, j]| norm(sub(net.v[i], net.v[j])))
                .collect();
            let shifted = |offset: &[[f64; 3]]| -> Vec<[f64; 3]> {
                net.v
                    .iter()
                    .zip(offset)
                    .map(|(v, o)| [v[0] + o[0], v[1] + o[1], v[2] + o[2]])
                    .collect()
            };
            let p = shifted(&p_offset);
            let start = shifted(&start_offset);
            let mut lengths = vec![0.0; net.springs.len()];
            start_lengths(&net.springs, &start, &mut lengths);
            let data = StepData {
                start_lengths: lengths,
                pin_targets: net.pinned.iter().map(|&i| net.v[i]).collect(),
                start,
                inertial_target: shifted(&target_offset),
                f_ext: forces.iter().map(|f| f.map(|x| 10.0 * x)).collect(),
                r,
                w: 100.0,
                net,
            };
            (data, p)
        })
}

/// The energy from the handout directly (no cancellation care).
fn oracle_energy(data: &StepData, p: &[[f64; 3]]) -> f64 {
    let e = data.energy();
    let mut total = 0.0;
    for (&[i, j], &rest) in e.springs.iter().zip(e.r) {
        total += 0.5 * e.k * (norm(sub(p[i], p[j])) - rest).powi(2);
    }
    for i in 0..p.len() {
        let inertial = sub(p[i], e.inertial_target[i]);
        total += 0.5 * e.m[i] * dot(inertial, inertial) / (DELTA_T * DELTA_T);
        total -= dot(p[i], e.f_ext[i]);
    }
    for (&c, &t) in e.pinned.iter().zip(e.pin_targets) {
        total += 0.5 * e.w * dot(sub(p[c], t), sub(p[c], t));
    }
    total
}

/// `∇E = k Aᵀ(A P − D) + M (P − Ŷ)/Δt² − F + w Cᵀ(C P − T)` with nalgebra.
fn oracle_gradient(data: &StepData, p: &[[f64; 3]]) -> DMatrix<f64> {
    let e = data.energy();
    let (n, m) = (p.len(), e.springs.len());
    let mut a = DMatrix::zeros(m, n);
    for (s, &[i, j]) in e.springs.iter().enumerate() {
        a[(s, i)] += 1.0;
        a[(s, j)] -= 1.0;
    }
    let mut c = DMatrix::zeros(e.pinned.len(), n);
    for (row, &i) in e.pinned.iter().enumerate() {
        c[(row, i)] = 1.0;
    }
    let pp = points_to_nalgebra(p);
    let ap = &a * &pp;
    let d = DMatrix::from_fn(m, 3, |s, col| {
        let v = ap.row(s);
        e.r[s] * v[col] / v.norm()
    });
    let mass = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(e.m));
    let y_hat = points_to_nalgebra(e.inertial_target);
    let t = points_to_nalgebra(e.pin_targets);
    a.transpose() * (ap - d) * e.k + mass * (&pp - y_hat) / (DELTA_T * DELTA_T)
        - points_to_nalgebra(e.f_ext)
        + c.transpose() * (&c * &pp - t) * e.w
}

fn perturbed(p: &[[f64; 3]], index: usize, h: f64) -> Vec<[f64; 3]> {
    let mut q = p.to_vec();
    q[index / 3][index % 3] += h;
    q
}

proptest! {
    #![proptest_config(proptest_config(64))]

    #[test]
    fn energy_change_is_the_difference_of_the_energies((data, p) in step_data()) {
        let change = data.energy().change(&p).total();
        let oracle = oracle_energy(&data, &p) - oracle_energy(&data, &data.start);
        let scale = oracle_energy(&data, &p).abs() + oracle_energy(&data, &data.start).abs() + 1.0;
        prop_assert!((change - oracle).abs() <= 1e-10 * scale, "{change} vs {oracle}");
        prop_assert_eq!(data.energy().change(&data.start).total(), 0.0);
    }

    #[test]
    fn vertex_sums_four_at_a_time_agree_with_one_at_a_time((data, p) in step_data_up_to(30)) {
        let energy = data.energy();
        let fast = energy.vertex_sums(&p);
        let portable = energy.vertex_sums_portable(&p, 0);
        // each sum to the rounding of the sum of its terms' magnitudes
        let mut scale = [0.0; 2];
        for (i, pi) in p.iter().enumerate() {
            let (p0, y, f) = (data.start[i], data.inertial_target[i], data.f_ext[i]);
            for c in 0..3 {
                let moved = (pi[c] - p0[c]).abs();
                scale[0] += data.net.masses[i] * moved * ((pi[c] - y[c]).abs() + (p0[c] - y[c]).abs());
                scale[1] += moved * f[c].abs();
            }
        }
        for t in 0..2 {
            prop_assert!(
                (fast[t] - portable[t]).abs() <= 1e-13 * scale[t],
                "sum {}: {} vs {} (scale {})", t, fast[t], portable[t], scale[t]
            );
        }
        // from a vertex on: the sum of the rest
        let tail = energy.vertex_sums_portable(&p, p.len() / 2);
        let head_and_tail: f64 = p.iter().enumerate().skip(p.len() / 2)
            .map(|(i, pi)| (0..3).map(|c| (pi[c] - data.start[i][c]) * data.f_ext[i][c]).sum::<f64>())
            .sum();
        prop_assert!((tail[1] - head_and_tail).abs() <= 1e-13 * scale[1]);
    }

    #[test]
    fn gradient_matches_nalgebra((data, p) in step_data()) {
        prop_assume!(data.net.springs.iter().all(|&[i, j]| norm(sub(p[i], p[j])) > 1e-3));
        let mut g = vec![[0.0; 3]; p.len()];
        data.energy().gradient(&p, &mut g);
        let oracle = oracle_gradient(&data, &p);
        assert_close(&points_to_nalgebra(&g), &oracle, 1e-10);
    }

    #[test]
    fn gradient_is_the_derivative_of_the_energy((data, p) in step_data()) {
        prop_assume!(data.net.springs.iter().all(|&[i, j]| norm(sub(p[i], p[j])) > 1e-2));
        let mut g = vec![[0.0; 3]; p.len()];
        data.energy().gradient(&p, &mut g);
        let h = 1e-6;
        let scale = g.iter().flatten().fold(1.0f64, |a, x| a.max(x.abs()));
        for index in 0..3 * p.len() {
            let forward = data.energy().change(&perturbed(&p, index, h)).total();
            let backward = data.energy().change(&perturbed(&p, index, -h)).total();
            let numeric = (forward - backward) / (2.0 * h);
            let exact = g[index / 3][index % 3];
            prop_assert!((numeric - exact).abs() <= 1e-5 * scale, "{index}: {numeric} vs {exact}");
        }
    }

    #[test]
    fn hessian_is_the_derivative_of_the_gradient((data, p) in step_data()) {
        prop_assume!(data.net.springs.iter().all(|&[i, j]| norm(sub(p[i], p[j])) > 1e-2));
        let n = p.len();
        let mut hessian = Hessian::new(n, &data.net.springs);
        hessian.assemble(&data.energy(), &p);
        let dense = csc_to_nalgebra(&hessian.matrix);
        prop_assert!((&dense - dense.transpose()).amax() <= 1e-12 * dense.amax());
        let h = 1e-6;
        let (mut g_plus, mut g_minus) = (vec![[0.0; 3]; n], vec![[0.0; 3]; n]);
        for column in 0..3 * n {
            data.energy().gradient(&perturbed(&p, column, h), &mut g_plus);
            data.energy().gradient(&perturbed(&p, column, -h), &mut g_minus);
            for row in 0..3 * n {
                let numeric = (g_plus[row / 3][row % 3] - g_minus[row / 3][row % 3]) / (2.0 * h);
                prop_assert!((numeric - dense[(row, column)]).abs() <= 1e-5 * dense.amax(),
                    "({row}, {column}): {numeric} vs {}", dense[(row, column)]);
            }
        }
    }
}

fn data_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
}

/// The simulation of a bundled scene after `steps` canonical steps.
fn simulation_after(scene: &str, steps: usize) -> Simulation<Sparse> {
    let scene = load_scene(&data_path(scene)).unwrap();
    let mut simulation =
        Simulation::<Sparse>::from_scene(&scene, SimulationOptions::default()).unwrap();
    for _ in 0..steps {
        simulation.step().unwrap();
    }
    simulation
}

/// (iteration, E(p) − E(p⁰), relative gradient).
type Row = (usize, f64, f64);

/// The rows of every iterate of the
/// next step of `simulation` (a copy moves), and the positions reached.
fn trace(simulation: &Simulation<Sparse>, control: StepControl) -> (Vec<Row>, Vec<[f64; 3]>) {
    let mut copy = simulation.clone();
    let mut rows = Vec::new();
    let mut g = vec![[0.0; 3]; copy.positions().len()];
    let mut g0 = 0.0;
    let mut record = |it: &Iterate<'_>| {
        it.energy.gradient(it.positions, &mut g);
        let norm = masssprings::sim::energy::free_norm(&g, it.pinned);
        if it.iteration == 0 {
            g0 = norm;
        }
        rows.push((
            it.iteration,
            it.energy.change(it.positions).total(),
            norm / g0,
        ));
    };
    copy.step_with(&control, Some(&mut record)).unwrap();
    (rows, copy.positions().to_vec())
}

fn control(method: StepMethod, iterations: usize, tolerance: Option<f64>) -> StepControl {
    StepControl {
        method,
        iterations,
        tolerance,
        measure: true, // the tests read every report's energy and gradient
        ..StepControl::default()
    }
}

/// The prototype's `(iteration, energy, relative gradient)` rows.
fn prototype_rows(file: &str) -> Vec<(usize, f64, f64)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/convergence")
        .join(file);
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            (
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                f[3].parse().unwrap(),
            )
        })
        .collect()
}

fn assert_matches_prototype(ours: &[(usize, f64, f64)], prototype: &[(usize, f64, f64)]) {
    assert_eq!(ours.len(), prototype.len());
    for (&(i, e, g), &(j, pe, pg)) in ours.iter().zip(prototype) {
        assert_eq!(i, j);
        // the prototype prints 12 significant digits
        assert!(
            (e - pe).abs() <= 1e-8 * pe.abs().max(1e-300) + 1e-11 * pe.abs(),
            "iteration {i}: energy {e} vs {pe}"
        );
        assert!(
            (g - pg).abs() <= 1e-8 * pg.abs(),
            "iteration {i}: relative gradient {g} vs {pg}"
        );
    }
}

#[test]
fn plain_energies_match_the_independent_prototype_at_step_1() {
    let simulation = simulation_after("flag.json", 0);
    let (ours, _) = trace(&simulation, control(StepMethod::Plain, 60, None));
    assert_matches_prototype(&ours, &prototype_rows("flag-step1.csv"));
}

#[test]
fn plain_energies_match_the_independent_prototype_at_step_11() {
    // the prototype starts step 11 from eigen-ref's steps 9 and 10
    let mut simulation = simulation_after("flag.json", 0);
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/convergence");
    let u_prev = read_points(&fixtures.join("flag.step9.txt"));
    let u_cur = read_points(&fixtures.join("flag.step10.txt"));
    simulation.set_state(&u_prev, &u_cur, 10).unwrap();
    let (ours, _) = trace(&simulation, control(StepMethod::Plain, 60, None));
    assert_matches_prototype(&ours, &prototype_rows("flag-step11.csv"));
}

#[test]
fn every_method_reaches_newtons_minimiser_on_the_small_scenes() {
    for scene in [
        "single-spring-horizontal.json",
        "horizontal-chain.json",
        "net.json",
    ] {
        for steps in [0, 10] {
            let simulation = simulation_after(scene, steps);
            let (newton_rows, minimiser) =
                trace(&simulation, control(StepMethod::Newton, 100, Some(1e-12)));
            let reached = newton_rows.last().unwrap().2;
            assert!(
                reached <= 1e-10,
                "{scene} step {}: Newton reached {reached:e}",
                steps + 1
            );
            let size = minimiser
                .iter()
                .flatten()
                .fold(1.0f64, |a, x| a.max(x.abs()));
            for method in StepMethod::ALL {
                let (rows, p) = trace(&simulation, control(method, 5000, Some(1e-11)));
                let distance = p
                    .iter()
                    .zip(&minimiser)
                    .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
                    .fold(0.0, f64::max);
                assert!(distance <= 1e-8 * size, "{scene} step {}: {method} ends {distance:e} from Newton's minimiser after {} iterations", steps + 1, rows.len() - 1);
            }
        }
    }
}

#[test]
fn anderson_lbfgs_and_chebyshev_never_raise_the_energy() {
    for scene in ["flag.json", "skirt.json"] {
        for steps in [0, 10] {
            let simulation = simulation_after(scene, steps);
            for method in [
                StepMethod::Anderson,
                StepMethod::Lbfgs,
                StepMethod::Chebyshev,
            ] {
                let (rows, _) = trace(&simulation, control(method, 30, None));
                for pair in rows.windows(2) {
                    assert!(
                        pair[1].1 <= pair[0].1,
                        "{scene} step {} {method}: energy rose at iteration {}: {:e} → {:e}",
                        steps + 1,
                        pair[1].0,
                        pair[0].1,
                        pair[1].1
                    );
                }
            }
        }
    }
}

#[test]
fn a_tolerance_stops_the_step_early_and_says_so() {
    let simulation = simulation_after("net.json", 3);
    for method in StepMethod::ALL {
        let mut copy = simulation.clone();
        let report = copy
            .step_with(&control(method, 10_000, Some(1e-6)), None)
            .unwrap();
        assert_eq!(report.stop, Stop::Tolerance, "{method}: {report:?}");
        assert!(
            report.relative_gradient.unwrap() <= 1e-6 && report.iterations < 10_000,
            "{method}: {report:?}"
        );
        assert!(
            report.energy_decrease.unwrap() > 0.0,
            "{method}: {report:?}"
        );
    }
}

#[test]
fn a_tolerance_that_cannot_be_met_stops_at_the_budget_and_says_so() {
    let simulation = simulation_after("flag.json", 0);
    for method in StepMethod::ALL {
        let mut copy = simulation.clone();
        let report = copy
            .step_with(&control(method, 3, Some(1e-14)), None)
            .unwrap();
        assert_eq!(
            (report.stop, report.iterations),
            (Stop::Iterations, 3),
            "{method}: {report:?}"
        );
        assert!(
            report.relative_gradient.unwrap() > 1e-14,
            "{method}: {report:?}"
        );
    }
}

/// The energy rule, checked against the energies of every iterate (as the
/// observer measures them): the step stops at the first iteration `k ≥ 1`
/// with `0 ≤ Eₖ₋₁ − Eₖ ≤ T (E₀ − Eₖ)`, and says so.
fn assert_stops_by_the_energy_rule(simulation: &Simulation<Sparse>, method: StepMethod, t: f64) {
    let control = StepControl {
        energy_tolerance: Some(t),
        ..control(method, 500, None)
    };
    let mut copy = simulation.clone();
    let mut energies = Vec::new();
    let mut record = |it: &Iterate<'_>| energies.push(it.energy.change(it.positions).total());
    let report = copy.step_with(&control, Some(&mut record)).unwrap();
    assert_eq!(report.stop, Stop::EnergyTolerance, "{method}: {report:?}");
    assert_eq!(energies.len(), report.iterations + 1, "{method}");
    let met = |k: usize| {
        let decrease = energies[k - 1] - energies[k];
        decrease >= 0.0 && decrease <= t * (energies[0] - energies[k])
    };
    let first = (1..energies.len()).find(|&k| met(k));
    assert_eq!(first, Some(report.iterations), "{method}: {energies:?}");
    assert_eq!(
        report.energy_decrease.unwrap(),
        -energies[report.iterations],
        "{method}"
    );
}

#[test]
fn an_energy_tolerance_stops_at_the_first_small_enough_progress_and_says_so() {
    let net = simulation_after("net.json", 3);
    for method in StepMethod::ALL {
        assert_stops_by_the_energy_rule(&net, method, 0.01);
    }
    let flag = simulation_after("flag.json", 11);
    for method in [
        StepMethod::Plain,
        StepMethod::Chebyshev,
        StepMethod::Anderson,
        StepMethod::Lbfgs,
    ] {
        assert_stops_by_the_energy_rule(&flag, method, 0.1);
    }
}

#[test]
fn an_energy_tolerance_that_is_not_met_changes_neither_the_iterates_nor_the_report() {
    let simulation = simulation_after("flag.json", 12);
    for method in StepMethod::ALL {
        let run = |energy_tolerance| {
            let mut copy = simulation.clone();
            let control = StepControl {
                energy_tolerance,
                ..control(method, 4, None)
            };
            let report = copy.step_with(&control, None).unwrap();
            (report, copy.positions().to_vec())
        };
        let (free, free_positions) = run(None);
        let (tested, tested_positions) = run(Some(1e-300));
        assert_eq!(free_positions, tested_positions, "{method}");
        assert_eq!(
            (tested.stop, tested.iterations),
            (Stop::Iterations, 4),
            "{method}"
        );
        assert_eq!(free.energy_decrease, tested.energy_decrease, "{method}");
        assert_eq!(free.relative_gradient, tested.relative_gradient, "{method}");
    }
}

/// `E(p⁰) − E(G(p⁰))`: what the first plain iteration of the next step
/// takes off.
fn first_plain_decrease(simulation: &Simulation<Sparse>) -> f64 {
    let mut copy = simulation.clone();
    let report = copy.step_with(&control(StepMethod::Plain, 1, None), None);
    report.unwrap().energy_decrease.unwrap()
}

/// The energies of every iterate of the next step under `control`, and
/// its report.
fn energies_of(simulation: &Simulation<Sparse>, control: &StepControl) -> (Vec<f64>, StepReport) {
    let mut copy = simulation.clone();
    let mut energies = Vec::new();
    let mut record = |it: &Iterate<'_>| energies.push(it.energy.change(it.positions).total());
    let report = copy.step_with(control, Some(&mut record)).unwrap();
    (energies, report)
}

/// The floor alone: the step stops at the first iterate whose energy is
/// `N` first plain decreases below the first iterate's, whatever the
/// method, and says so.
#[test]
fn at_least_plain_alone_stops_at_the_first_iterate_below_the_floor() {
    for (scene, steps, multiple) in [("flag.json", 11, 20.0), ("net.json", 3, 1.02)] {
        let simulation = simulation_after(scene, steps);
        let floor = -multiple * first_plain_decrease(&simulation);
        for method in StepMethod::ALL {
            let control = StepControl {
                at_least_plain: Some(multiple),
                ..control(method, 300, None)
            };
            let (energies, report) = energies_of(&simulation, &control);
            let first = (1..energies.len()).find(|&k| energies[k] <= floor);
            assert_eq!(
                first,
                Some(report.iterations),
                "{scene} {method}: {energies:?}"
            );
            assert_eq!(
                report.stop,
                Stop::AtLeastPlain,
                "{scene} {method}: {report:?}"
            );
        }
    }
}

/// The premise of the floor on a step where the plain iteration's decrease
/// does not grow: `N` plain iterations take off at most `N` times the
/// first one's, so plain itself needs at least `N` to pass the floor.
#[test]
fn plain_needs_at_least_n_iterations_to_pass_n_first_decreases() {
    let simulation = simulation_after("flag.json", 11);
    for multiple in [2.0, 10.0, 40.0] {
        let control = StepControl {
            at_least_plain: Some(multiple),
            ..control(StepMethod::Plain, 300, None)
        };
        let (_, report) = energies_of(&simulation, &control);
        assert_eq!(report.stop, Stop::AtLeastPlain, "{report:?}");
        assert!(
            report.iterations as f64 >= multiple,
            "{multiple}: {report:?}"
        );
    }
}

/// With the energy rule as well, a step stops at the first iterate that
/// meets both: past the floor, and with small enough progress.
#[test]
fn at_least_plain_holds_back_the_energy_rule() {
    let simulation = simulation_after("flag.json", 11);
    let (multiple, fraction) = (30.0, 0.15);
    let floor = -multiple * first_plain_decrease(&simulation);
    let mut held_back = 0;
    for method in [
        StepMethod::Plain,
        StepMethod::Chebyshev,
        StepMethod::Anderson,
        StepMethod::Lbfgs,
    ] {
        let control = StepControl {
            at_least_plain: Some(multiple),
            energy_tolerance: Some(fraction),
            ..control(method, 300, None)
        };
        let (energies, report) = energies_of(&simulation, &control);
        let both = |k: usize| {
            let decrease = energies[k - 1] - energies[k];
            let progress_small = (0.0..=fraction * (energies[0] - energies[k])).contains(&decrease);
            progress_small && energies[k] <= floor
        };
        let first = (1..energies.len()).find(|&k| both(k));
        assert_eq!(first, Some(report.iterations), "{method}: {energies:?}");
        assert_eq!(report.stop, Stop::EnergyTolerance, "{method}: {report:?}");
        // the floor can only hold the rule back
        let (_, alone) = energies_of(
            &simulation,
            &StepControl {
                at_least_plain: None,
                ..control
            },
        );
        assert!(alone.iterations <= report.iterations, "{method}: {alone:?}");
        held_back += usize::from(alone.iterations < report.iterations);
    }
    assert!(held_back > 0, "the floor held no method back");
}

#[test]
fn plain_is_the_assignments_step_bit_for_bit() {
    // The same 50 iterations through the old entry point and the new one.
    let simulation = simulation_after("flag.json", 2);
    let (_, through_methods) = trace(&simulation, control(StepMethod::Plain, 50, None));
    let mut assignment = simulation.clone();
    assignment.step().unwrap();
    assert_eq!(through_methods, assignment.positions());
}

#[test]
fn a_non_finite_step_is_reported_by_every_method() {
    // a vertex at 1e300 overflows y = M ŷ / Δt²
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    for method in StepMethod::ALL {
        let mut simulation = Simulation::<Sparse>::new(
            &v,
            &[[0, 1], [1, 2]],
            10.0,
            &[1.0; 3],
            &[0],
            SimulationOptions::default(),
        )
        .unwrap();
        let far = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1e300, 0.0, 0.0]];
        simulation.set_state(&v, &far, 1).unwrap();
        let error = simulation
            .step_with(&control(method, 20, Some(1e-8)), None)
            .unwrap_err();
        assert!(
            matches!(
                error,
                SimulationError::NotFinite { .. } | SimulationError::EnergyNotFinite
            ),
            "{method}: {error:?}"
        );
    }
}

fn simulation_with(scene: &str, options: SimulationOptions) -> Simulation<Sparse> {
    let scene = load_scene(&data_path(scene)).unwrap();
    Simulation::<Sparse>::from_scene(&scene, options).unwrap()
}

#[test]
fn exact_pins_stay_exactly_at_their_targets_for_every_method() {
    for method in StepMethod::ALL {
        let options = SimulationOptions {
            step: masssprings::sim::StepControl {
                method,
                iterations: 20,
                ..masssprings::sim::StepControl::default()
            },
            pins: Pins::Exact,
            ..SimulationOptions::default()
        };
        let mut simulation = simulation_with("flag.json", options);
        for _ in 0..3 {
            simulation.step().unwrap();
        }
        for &c in simulation.pinned() {
            assert_eq!(
                simulation.positions()[c],
                simulation.rest_positions()[c],
                "{method}"
            );
        }
        simulation.start_drag(3000, [0.5, 0.5, 0.5]).unwrap();
        simulation.step().unwrap();
        assert_eq!(simulation.positions()[3000], [0.5, 0.5, 0.5], "{method}");
    }
}

#[test]
fn exact_pins_and_the_penalty_agree_to_the_penaltys_drift() {
    let run = |pins| {
        let options = SimulationOptions {
            pins,
            ..SimulationOptions::default()
        };
        let mut simulation = simulation_with("flag.json", options);
        for _ in 0..10 {
            simulation.step().unwrap();
        }
        simulation.positions().to_vec()
    };
    let (penalty, exact) = (run(Pins::Penalty), run(Pins::Exact));
    let largest = penalty
        .iter()
        .zip(&exact)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
        .fold(0.0, f64::max);
    // the penalty's pins drift by about force / w ~ 1e-7..1e-6 (docs/fidelity.md)
    assert!(largest > 0.0 && largest < 1e-5, "{largest:e}");
}

#[test]
fn with_exact_pins_every_method_reaches_newtons_minimiser() {
    let options = SimulationOptions {
        pins: Pins::Exact,
        ..SimulationOptions::default()
    };
    let mut simulation = simulation_with("net.json", options);
    simulation.step().unwrap();
    let (_, minimiser) = trace(&simulation, control(StepMethod::Newton, 100, Some(1e-12)));
    let size = minimiser
        .iter()
        .flatten()
        .fold(1.0f64, |a, x| a.max(x.abs()));
    for method in StepMethod::ALL {
        let (_, p) = trace(&simulation, control(method, 5000, Some(1e-11)));
        let distance = p
            .iter()
            .zip(&minimiser)
            .flat_map(|(a, b)| (0..3).map(move |c| (a[c] - b[c]).abs()))
            .fold(0.0, f64::max);
        assert!(distance <= 1e-8 * size, "{method}: {distance:e}");
    }
}

/// Where every trial's energy is rounding (a cloth at rest), the search
/// gives up once the decrease it could still see, `t |s|`, is below the
/// energy's rounding `η`, after a few evaluations, instead of halving `t`
/// down to 10⁻¹⁰ (34 evaluations) to reject each trial by its rounding.
#[test]
fn the_line_search_stops_halving_at_the_rounding_of_the_energy() {
    use masssprings::sim::methods::line_search::{line_search, Search};
    let (slope, rounding) = (-1e-12, 1e-13);
    let mut evaluations = 0;
    let found = line_search(Search::Expanding, 1.0, slope, 0.0, rounding, |_| {
        evaluations += 1;
        1e-14 // every trial a little higher: rounding
    });
    assert_eq!(found, None, "no decrease to see");
    assert!(evaluations <= 5, "{evaluations} evaluations");
    let mut evaluations = 0;
    let found = line_search(Search::Expanding, 1.0, slope, 0.0, 0.0, |_| {
        evaluations += 1;
        1e-14
    });
    assert_eq!(found, None);
    assert!(evaluations > 30, "without η: {evaluations} evaluations");
}

proptest! {
    /// On a parabola `E(t) = c t² + s t` (what the energy along a direction
    /// nearly is), the expanding search lands on the minimum `−s / 2c` in at
    /// most two evaluations when the minimum lies well beyond the first
    /// trial, keeps the first trial otherwise, and backtracks (halving)
    /// when the first trial fails Armijo's condition.
    #[test]
    fn the_line_search_finds_a_parabolas_minimum(
        curvature in 1e-3f64..1e3,
        slope in -1e3f64..-1e-3,
        first in prop::sample::select(vec![1.0, 2.0, 4.0]),
    ) {
        use masssprings::sim::methods::line_search::{line_search, Search, ARMIJO, LONGEST_STEP};
        let mut evaluations = 0;
        let energy = |t: f64| curvature * t * t + slope * t;
        let (t, e) = line_search(Search::Expanding, first, slope, 0.0, 0.0, |t| {
            evaluations += 1;
            energy(t)
        })
        .expect("a parabola that falls at 0 has a sufficient decrease somewhere");
        prop_assert_eq!(e, energy(t));
        prop_assert!(e <= ARMIJO * t * slope, "Armijo at t = {}", t);
        let minimum = -slope / (2.0 * curvature);
        if first <= minimum / 1.5 {
            // the parabola is exact: its minimum, capped
            let want = minimum.min(LONGEST_STEP);
            prop_assert!((t - want).abs() <= 1e-9 * want, "t = {} against {}", t, want);
            prop_assert!(evaluations <= 2);
        } else if energy(first) <= ARMIJO * first * slope {
            prop_assert_eq!(t, first);
            prop_assert_eq!(evaluations, 1);
        } else {
            prop_assert!(t < first && t >= 0.5f64.powi(40) * first);
        }
    }
}

#[test]
fn a_tolerance_changes_neither_the_iterates_nor_the_report() {
    // With a tolerance, the local step at each iterate also makes the
    // gradient the rule tests, the step's start shares one pass with the
    // initial gradient, and the methods report the energy they measured:
    // none of it may change what is computed.
    // (The flag after 12 steps: its inertial prediction is below pᵗ in
    // energy, so the inertial start begins there.)
    for (pins, start) in [
        (Pins::Penalty, Start::Current),
        (Pins::Exact, Start::Current),
        (Pins::Penalty, Start::Inertial),
        (Pins::Exact, Start::Inertial),
    ] {
        let options = SimulationOptions {
            pins,
            ..SimulationOptions::default()
        };
        let mut simulation = simulation_with("flag.json", options);
        for _ in 0..12 {
            simulation.step().unwrap();
        }
        for method in StepMethod::ALL {
            let run = |tolerance| {
                let mut copy = simulation.clone();
                let (mut last, mut initial) = ((f64::NAN, f64::NAN), f64::NAN);
                let mut g = vec![[0.0; 3]; copy.positions().len()];
                let mut record = |it: &Iterate<'_>| {
                    if it.iteration == 0 {
                        it.energy.gradient(it.energy.start, &mut g);
                        initial = masssprings::sim::energy::free_norm(&g, it.pinned);
                    }
                    it.energy.gradient(it.positions, &mut g);
                    let norm = masssprings::sim::energy::free_norm(&g, it.pinned);
                    last = (it.energy.change(it.positions).total(), norm / initial);
                };
                let control = StepControl {
                    start,
                    ..control(method, 7, tolerance)
                };
                let report = copy.step_with(&control, Some(&mut record)).unwrap();
                (report, copy.positions().to_vec(), last)
            };
            let (free, free_positions, (energy, relative_gradient)) = run(None);
            let (tested, tested_positions, _) = run(Some(1e-14));
            let what = format!("{method}, {pins:?}, {start:?}");
            assert_eq!(free_positions, tested_positions, "{what}");
            assert_eq!(
                (free.iterations, tested.iterations, tested.stop),
                (7, 7, Stop::Iterations),
                "{what}"
            );
            assert_eq!(free.energy_decrease.unwrap(), -energy, "{what}");
            assert_eq!(tested.energy_decrease.unwrap(), -energy, "{what}");
            assert_eq!(free.relative_gradient.unwrap(), relative_gradient, "{what}");
            assert_eq!(
                tested.relative_gradient.unwrap(),
                relative_gradient,
                "{what}"
            );
        }
    }
}

#[test]
fn the_inertial_start_begins_at_the_prediction_only_when_it_is_lower() {
    // From rest the prediction 2pᵗ − pᵗ⁻¹ is pᵗ itself; after 12 steps
    // of the flag it is below pᵗ in energy, and the step begins exactly there.
    for (steps, expect_prediction) in [(0, false), (12, true)] {
        let simulation = simulation_after("flag.json", steps);
        assert_eq!(
            simulation.positions() == simulation.previous_positions(),
            steps == 0,
            "the flag moves"
        );
        let prediction: Vec<[f64; 3]> = simulation
            .positions()
            .iter()
            .zip(simulation.previous_positions())
            .map(|(c, p)| std::array::from_fn(|x| 2.0 * c[x] - p[x]))
            .collect();
        for method in StepMethod::ALL {
            let mut copy = simulation.clone();
            let mut first = None;
            let mut record = |it: &Iterate<'_>| {
                if it.iteration == 0 {
                    first = Some((
                        it.positions.to_vec(),
                        it.energy.change(it.positions).total(),
                    ));
                }
            };
            let control = StepControl {
                start: Start::Inertial,
                ..control(method, 3, None)
            };
            copy.step_with(&control, Some(&mut record)).unwrap();
            let (positions, energy) = first.unwrap();
            let what = format!("{method} after {steps} steps");
            assert!(energy <= 0.0, "{what}: {energy}");
            let expected = match expect_prediction {
                true => &prediction[..],
                false => simulation.positions(),
            };
            assert_eq!(positions, expected, "{what}");
            assert_eq!(energy < 0.0, expect_prediction, "{what}");
        }
    }
}
