//! The handout's step with a mistake in it: the loop of
//! [`fast_mass_springs_step_sparse`](super::super::textbook::fast_mass_springs_step_sparse),
//! `y`, then 50 times `d`, `b`, `p = Q⁻¹ b`, but for the one line the
//! [`Mistake`] writes wrong:
//!
//! ```text
//! r-from-deformed       rᵢⱼ = ‖U_curᵢ − U_curⱼ‖                (every step)
//! dt-not-squared        y = M (2 U_cur − U_prev)/Δt + f_ext
//! prev-cur-swapped      y = M (2 U_prev − U_cur)/Δt² + f_ext
//! gravity-times-mass    y = M (2 U_cur − U_prev)/Δt² + M f_ext
//! inertia-minus-prev    y = M (2 U_cur + U_prev)/Δt² + f_ext
//! inertia-sign          y = −M (2 U_cur − U_prev)/Δt² + f_ext
//! inertia-half-missing  y = 2M (2 U_cur − U_prev)/Δt² + f_ext
//! d-not-normalised      dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)
//! d-from-u-cur          dᵢⱼ = rᵢⱼ (U_curᵢ − U_curⱼ)/‖U_curᵢ − U_curⱼ‖
//! pins-not-in-b         b = k Aᵀd + y
//! ```
//!
//! The mistakes of the precomputation ([`precomputation`](super::precomputation))
//! reach the step through its `M`, `A`, `C` and factor of `Q`.
//! [`StudentStep`] keeps every iteration's `d`, `b` and `p` for `trace`;
//! [`StudentSimulation`] runs step after step from rest for `render`.
//!
//! Cost: the handout's step's.

#![allow(non_snake_case)] // the handout's names: U_prev, U_cur, U_next

use super::super::backend::{LinearAlgebra, Sparse};
use super::super::forces::{bounding_box_diagonal, external_forces};
use super::super::local_step::project_springs;
use super::super::precomputation::rest_lengths;
use super::super::textbook::{
    inertial_term, pin_term, right_hand_side, solve_sparse, Precomputation,
};
use super::Mistake;

/// One step of the student's code, iteration by iteration.
#[derive(Debug, Clone)]
pub struct StudentStep<'a> {
    mistake: Mistake,
    pre: &'a Precomputation<Sparse>,
    U_cur: &'a [[f64; 3]],
    /// The rest lengths the step uses (`r-from-deformed`: `U_cur`'s).
    r: Vec<f64>,
    y: Vec<[f64; 3]>,
    pins: Vec<[f64; 3]>,
    d: Vec<[f64; 3]>,
    b: Vec<[f64; 3]>,
    p: Vec<[f64; 3]>,
    x: Vec<[f64; 3]>,
}

impl<'a> StudentStep<'a> {
    /// The step's start: `r`, `y`, the pins' part of `b`, and `p = U_cur`.
    pub fn start(
        mistake: Mistake,
        pre: &'a Precomputation<Sparse>,
        f_ext: &[[f64; 3]],
        U_prev: &[[f64; 3]],
        U_cur: &'a [[f64; 3]],
    ) -> StudentStep<'a> {
        let r = match mistake {
            Mistake::RFromDeformed => rest_lengths(U_cur, &pre.springs), // ‖U_curᵢ − U_curⱼ‖
            _ => pre.r.clone(),
        };
        let n = U_cur.len();
        StudentStep {
            mistake,
            pre,
            U_cur,
            r,
            y: student_inertial_term(mistake, pre, f_ext, U_prev, U_cur),
            pins: pin_term(pre), // w CᵀC V
            d: vec![[0.0; 3]; pre.springs.len()],
            b: vec![[0.0; 3]; n],
            p: U_cur.to_vec(),
            x: vec![[0.0; 3]; n],
        }
    }

    /// One local/global iteration: `d`, `b`, then `p = Q⁻¹ b`.
    pub fn iterate(&mut self) {
        let (pre, springs) = (self.pre, &self.pre.springs);
        match self.mistake {
            Mistake::DNotNormalised => not_normalised(springs, &self.r, &self.p, &mut self.d),
            Mistake::DFromUCur => project_springs(springs, &self.r, self.U_cur, &mut self.d),
            _ => project_springs(springs, &self.r, &self.p, &mut self.d),
        }
        match self.mistake {
            Mistake::PinsNotInB => {
                Sparse::transpose_mul_points(&pre.A, &self.d, &mut self.b); // Aᵀd
                for (b, y) in self.b.iter_mut().zip(&self.y) {
                    *b = std::array::from_fn(|c| pre.k * b[c] + y[c]); // no w CᵀC V
                }
            }
            _ => right_hand_side(pre, &self.d, &self.y, &self.pins, &mut self.b),
        }
        solve_sparse(pre, &self.b, &mut self.x, &mut self.p);
    }

    /// The rest lengths this step uses.
    pub fn r(&self) -> &[f64] {
        &self.r
    }

    /// `y`.
    pub fn y(&self) -> &[[f64; 3]] {
        &self.y
    }

    /// The last iteration's `d`.
    pub fn d(&self) -> &[[f64; 3]] {
        &self.d
    }

    /// The last iteration's `b`.
    pub fn b(&self) -> &[[f64; 3]] {
        &self.b
    }

    /// The last iteration's `p` (`U_cur` before the first).
    pub fn p(&self) -> &[[f64; 3]] {
        &self.p
    }
}

/// The student's step: [`StudentStep`] iterated `pre.iterations` times,
/// `U_next` its last `p`.
pub fn step(
    mistake: Mistake,
    pre: &Precomputation<Sparse>,
    f_ext: &[[f64; 3]],
    U_prev: &[[f64; 3]],
    U_cur: &[[f64; 3]],
    U_next: &mut [[f64; 3]],
) {
    let mut step = StudentStep::start(mistake, pre, f_ext, U_prev, U_cur);
    for _ in 0..pre.iterations {
        step.iterate();
    }
    U_next.copy_from_slice(step.p());
}

/// `y`, with the mistake's change (the others: the handout's
/// [`inertial_term`], on the student's `M`).
fn student_inertial_term(
    mistake: Mistake,
    pre: &Precomputation<Sparse>,
    f_ext: &[[f64; 3]],
    U_prev: &[[f64; 3]],
    U_cur: &[[f64; 3]],
) -> Vec<[f64; 3]> {
    let dt2 = pre.delta_t * pre.delta_t;
    // (coefficient of U_prev, what M (2 U_cur ± U_prev) is divided by)
    let (prev, divisor) = match mistake {
        Mistake::PrevCurSwapped => return inertial_term(pre, f_ext, U_cur, U_prev), // the two swapped
        Mistake::GravityTimesMass => {
            let mut weighed = vec![[0.0; 3]; f_ext.len()];
            Sparse::mul_points(&pre.M, f_ext, &mut weighed); // M f_ext
            return inertial_term(pre, &weighed, U_prev, U_cur);
        }
        Mistake::DtNotSquared => (-1.0, pre.delta_t),
        Mistake::InertiaMinusPrev => (1.0, dt2),
        Mistake::InertiaSign => (-1.0, -dt2),
        Mistake::InertiaHalfMissing => (-1.0, dt2 / 2.0),
        _ => return inertial_term(pre, f_ext, U_prev, U_cur),
    };
    let inertia: Vec<[f64; 3]> = U_cur
        .iter()
        .zip(U_prev)
        .map(|(cur, old)| std::array::from_fn(|c| 2.0 * cur[c] + prev * old[c]))
        .collect();
    let mut y = vec![[0.0; 3]; U_cur.len()];
    Sparse::mul_points(&pre.M, &inertia, &mut y);
    for (y, f) in y.iter_mut().zip(f_ext) {
        *y = std::array::from_fn(|c| y[c] / divisor + f[c]);
    }
    y
}

/// `d-not-normalised`: `d[e] = r[e] (p[i] − p[j])`, the spring vector
/// scaled by the rest length instead of rescaled to it.
fn not_normalised(springs: &[[usize; 2]], r: &[f64], p: &[[f64; 3]], d: &mut [[f64; 3]]) {
    for ((d, &[i, j]), &r) in d.iter_mut().zip(springs).zip(r) {
        *d = std::array::from_fn(|c| r * (p[i][c] - p[j][c]));
    }
}

/// A simulation that runs the student's step from rest, as the
/// assignment's `main.cpp` runs the handout's: `U_prev ← U_cur`,
/// `U_cur ← U_next` after each step, gravity (and the wind) as forces.
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
        std::mem::swap(&mut self.u_prev, &mut self.u_cur); // U_prev ← U_cur
        std::mem::swap(&mut self.u_cur, &mut self.u_next); // U_cur ← U_next
        self.steps += 1;
        self.u_cur.iter().flatten().all(|x| x.is_finite())
    }

    /// `U_cur`.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.u_cur
    }
}
