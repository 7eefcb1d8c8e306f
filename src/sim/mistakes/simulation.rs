//! The student's loop over steps, as the assignment's `main.cpp` runs the
//! handout's step, with the student's precomputation and step in it:
//!
//! ```text
//! U_prev = U_cur = V                        at rest
//! every step: f_ext = gravity (+ wind)
//!             U_next = step(U_prev, U_cur)
//!             U_prev ← U_cur, U_cur ← U_next    (advance)
//! ```
//!
//! [`advance`] is the loop's line, with its mistake:
//!
//! ```text
//! velocity-lost    U_cur ← U_next, then U_prev ← U_cur: both are U_next
//! ```
//!
//! which leaves every step right, and starts each from rest: the velocity
//! is lost between the steps.
//!
//! Cost: the student's step's, per step.

#![allow(non_snake_case)] // the handout's names: U_prev, U_cur, U_next

use super::super::backend::Sparse;
use super::super::forces::{bounding_box_diagonal, external_forces};
use super::super::textbook::Precomputation;
use super::gallery::Mistake;
use super::step::step;

/// The loop's update after a step: `U_prev ← U_cur`, `U_cur ← U_next`,
/// with the mistake's change. `U_next` is left as it was or holds the
/// old `U_prev` (a work array for the next step either way).
pub fn advance(
    mistake: Option<Mistake>,
    U_prev: &mut Vec<[f64; 3]>,
    U_cur: &mut Vec<[f64; 3]>,
    U_next: &mut Vec<[f64; 3]>,
) {
    match mistake {
        Some(Mistake::VelocityLost) => {
            U_cur.copy_from_slice(U_next); // U_cur ← U_next
            U_prev.copy_from_slice(U_cur); // U_prev ← U_cur: U_next too
        }
        _ => {
            std::mem::swap(U_prev, U_cur); // U_prev ← U_cur
            std::mem::swap(U_cur, U_next); // U_cur ← U_next
        }
    }
}

/// A simulation that runs the student's code from rest.
#[derive(Debug, Clone)]
pub struct StudentSimulation {
    mistake: Mistake,
    pre: Precomputation<Sparse>,
    u_prev: Vec<[f64; 3]>,
    u_cur: Vec<[f64; 3]>,
    u_next: Vec<[f64; 3]>,
    f_ext: Vec<[f64; 3]>,
    wind: bool,
    scale: f64,
    steps: usize,
}

impl StudentSimulation {
    /// At rest (`U_prev = U_cur = V`) on the student's precomputation `pre`.
    pub fn new(mistake: Mistake, pre: Precomputation<Sparse>, wind: bool) -> StudentSimulation {
        let n = pre.V.len();
        StudentSimulation {
            mistake,
            u_prev: pre.V.clone(),
            u_cur: pre.V.clone(),
            u_next: vec![[0.0; 3]; n],
            f_ext: vec![[0.0; 3]; n],
            wind,
            scale: bounding_box_diagonal(&pre.V),
            steps: 0,
            pre,
        }
    }

    /// One step of the student's code. Returns whether every position is
    /// still finite (a mistake that blows up makes NaN or infinity).
    pub fn step(&mut self) -> bool {
        let time = self.steps as f64 * self.pre.delta_t;
        external_forces(&self.u_cur, time, self.wind, self.scale, &mut self.f_ext);
        let (u_prev, u_cur) = (&self.u_prev, &self.u_cur);
        step(
            self.mistake,
            &self.pre,
            &self.f_ext,
            u_prev,
            u_cur,
            &mut self.u_next,
        );
        let it = Some(self.mistake);
        advance(it, &mut self.u_prev, &mut self.u_cur, &mut self.u_next);
        self.steps += 1;
        self.u_cur.iter().flatten().all(|x| x.is_finite())
    }

    /// `U_cur`.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.u_cur
    }

    /// `U_prev`.
    pub fn previous_positions(&self) -> &[[f64; 3]] {
        &self.u_prev
    }

    /// The student's precomputation.
    pub fn precomputation(&self) -> &Precomputation<Sparse> {
        &self.pre
    }
}
