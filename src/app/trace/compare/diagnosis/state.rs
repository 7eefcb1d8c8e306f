//! The state a student's step starts from, `U_prev` and `U_cur`: ours when
//! the student started from our files, else what their own loop over steps
//! made. Their loop's mistakes show there, and nowhere else:
//!
//! ```text
//! velocity-lost   your U_prev = your U_cur (U_cur ← U_next, then U_prev ← U_cur)
//! swapped         your U_prev = our U_cur and your U_cur = our U_prev
//! ```
//!
//! Any other state of their own is not a mistake by itself (their earlier
//! steps went another way): the diagnosis then goes on to the step, whose
//! quantities it recomputes from that state.

use super::inputs::Inputs;
use super::recompute::{reproduces, Value};
use super::text::Diagnosis;
use crate::app::trace::quantities::Quantity;
use masssprings::sim::mistakes::Mistake;

/// A mistake of the loop or a swap, when the student's state shows one.
pub fn diagnose(state: &Quantity, inputs: &Inputs) -> Option<Diagnosis> {
    let mine = |name: &str| inputs.their_dense(name).map(Value::Dense);
    let ours = |name: &str| inputs.ours_dense(name).map(Value::Dense);
    let (their_prev, their_cur) = (mine("U_prev.mtx")?, mine("U_cur.mtx")?);
    let (our_prev, our_cur) = (ours("U_prev.mtx")?, ours("U_cur.mtx")?);
    let same = |a: &Value, b: &Value| reproduces(state, a, b, inputs);
    if same(&their_cur, &their_prev) && !same(&our_cur, &our_prev) {
        return Some(Diagnosis::named(Mistake::VelocityLost, "U_prev"));
    }
    if same(&our_cur, &their_prev) && same(&our_prev, &their_cur) {
        return Some(Diagnosis::unexplained(
            "U_prev",
            "your U_prev is our U_cur and your U_cur our U_prev: the two are swapped, \
             in the call of your step or in the files you wrote",
        ));
    }
    None
}
