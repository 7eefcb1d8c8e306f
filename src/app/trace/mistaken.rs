//! `masssprings trace SCENE.json --mistake NAME -o DIR`: the folder a
//! student with that mistake would write, to see what `trace --compare`
//! says about it:
//!
//! ```text
//! precomputation: A, r, M, C, Q, P, L   the student's (sim::mistakes::precomputation)
//! state:          U_prev, U_cur          a mistake of the precomputation or the step:
//!                                        ours, K − 1 handout steps from rest, as the
//!                                        trace's README asks a student to start from;
//!                                        a mistake of the loop: the student's own
//!                                        K − 1 steps from rest (sim::mistakes::simulation)
//! step K:         y, then d_k, b_k, p_k  the student's step (sim::mistakes::step)
//! ```
//!
//! A mistake that only changes the step shows only from `y` or `d` on, and
//! some not at all at step 1, where `U_prev = U_cur = V` (the gallery's
//! entries say from which step each shows).

use super::compute::{points, precomputed, state_before, TraceOptions, Value};
use super::quantities::quantities;
use crate::app::error::AppError;
use masssprings::mesh::Scene;
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::mistakes::precomputation::precomputation;
use masssprings::sim::mistakes::simulation::StudentSimulation;
use masssprings::sim::mistakes::step::StudentStep;
use masssprings::sim::mistakes::{Mistake, Part};
use masssprings::sim::textbook::{precomputation_ordered, Precomputation};
use masssprings::sim::{Sparse, DELTA_T};

/// Every quantity of a trace, in the order of [`quantities`], as the
/// student with `mistake` computes them at step K.
pub fn trace(
    scene: &Scene,
    options: TraceOptions,
    mistake: Mistake,
) -> Result<Vec<Value>, AppError> {
    let (v, springs, m, pins) = (
        &scene.vertices,
        &scene.springs,
        &scene.masses,
        &scene.pinned,
    );
    let failed = |who: &str, e| AppError::Failed(format!("{}: {who}: {e}", scene.name));
    let ours = precomputation_ordered(v, springs, scene.k, m, pins, DELTA_T, options.ordering)
        .map_err(|e| failed("the handout's precomputation", e))?;
    let ordering = options.ordering;
    let student = precomputation(mistake, v, springs, scene.k, m, pins, DELTA_T, ordering)
        .map_err(|e| failed(&format!("the precomputation with the mistake {mistake}"), e))?;
    let f_ext = vec![GRAVITY; v.len()];
    let (u_prev, u_cur) = match mistake.entry().part {
        Part::Loop => own_state(mistake, student.clone(), options.step),
        _ => state_before(&ours, &f_ext, options.step),
    };
    let mut values = precomputed(&student);
    let mut step = StudentStep::start(mistake, &student, &f_ext, &u_prev, &u_cur);
    values.extend([&u_prev, &u_cur, step.y()].map(points));
    for _ in 0..options.iterations {
        step.iterate();
        values.extend([step.d(), step.b(), step.p()].map(points));
    }
    assert_eq!(values.len(), quantities(options.iterations).len());
    Ok(values)
}

/// `(U_prev, U_cur)` of the student's own loop at the start of `step`:
/// `step − 1` of the student's steps from rest.
fn own_state(
    mistake: Mistake,
    student: Precomputation<Sparse>,
    step: usize,
) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut simulation = StudentSimulation::new(mistake, student, false);
    for _ in 1..step {
        simulation.step();
    }
    let positions = simulation.positions().to_vec();
    (simulation.previous_positions().to_vec(), positions)
}
