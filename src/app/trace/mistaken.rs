//! `masssprings trace SCENE.json --mistake NAME -o DIR`: the folder a
//! student with that mistake would write, to see what `trace --compare`
//! says about it:
//!
//! ```text
//! precomputation: A, r, M, C, Q, P, L   the student's (sim::mistakes::precomputation)
//! state:          U_prev, U_cur          ours: K − 1 handout steps from rest, as the
//!                                        trace's README asks a student to start from
//! step K:         y, then d_k, b_k, p_k  the student's step (sim::mistakes::step)
//! ```
//!
//! `r` is the rest lengths the student's step uses (for `r-from-deformed`,
//! `U_cur`'s). A mistake that only changes the step shows only from `y`
//! or `d` on, and `prev-cur-swapped`, `r-from-deformed` and
//! `d-from-u-cur` not at all at step 1, where `U_prev = U_cur = V`: trace
//! a later step to see them.

use super::compute::{points, precomputed, state_before, TraceOptions, Value};
use super::quantities::quantities;
use crate::app::error::AppError;
use masssprings::linalg::dense::DenseMatrix;
use masssprings::mesh::Scene;
use masssprings::sim::forces::GRAVITY;
use masssprings::sim::mistakes::precomputation::precomputation;
use masssprings::sim::mistakes::step::StudentStep;
use masssprings::sim::mistakes::Mistake;
use masssprings::sim::textbook::precomputation_ordered;
use masssprings::sim::DELTA_T;

/// Every quantity of a trace, in the order of [`quantities`], as the
/// student with `mistake` computes them from our state at step K.
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
    let student = precomputation(
        mistake,
        v,
        springs,
        scene.k,
        m,
        pins,
        DELTA_T,
        options.ordering,
    )
    .map_err(|e| failed(&format!("the precomputation with the mistake {mistake}"), e))?;
    let f_ext = vec![GRAVITY; v.len()];
    let (u_prev, u_cur) = state_before(&ours, &f_ext, options.step);
    let mut step = StudentStep::start(mistake, &student, &f_ext, &u_prev, &u_cur);
    let mut values = precomputed(&student);
    let r = DenseMatrix::from_row_major(step.r().len(), 1, step.r().to_vec())
        .expect("one rest length per row");
    let at_r = quantities(options.iterations)
        .iter()
        .position(|q| q.spec.symbol == "r");
    values[at_r.expect("a trace writes r")] = Value::Dense(r); // the r the step uses
    values.extend([&u_prev, &u_cur, step.y()].map(points));
    for _ in 0..options.iterations {
        step.iterate();
        values.extend([step.d(), step.b(), step.p()].map(points));
    }
    debug_assert_eq!(values.len(), quantities(options.iterations).len());
    Ok(values)
}
