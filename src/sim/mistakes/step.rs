//! The handout's step with a mistake in it: the loop of
//! [`fast_mass_springs_step_sparse`](super::super::textbook::fast_mass_springs_step_sparse),
//! `y`, then 50 times `d`, `b`, `p = Q⁻¹ b`, but for the one line the
//! [`Mistake`] writes wrong. Each line is a function that takes the
//! mistake (`None`: the handout's line) and its inputs, so that `trace
//! --compare` can recompute a student's quantity under every mistake from
//! the student's own inputs:
//!
//! ```text
//! inertial_term    dt-not-squared           y = M (2 U_cur − U_prev)/Δt + f_ext
//!                  prev-cur-swapped         y = M (2 U_prev − U_cur)/Δt² + f_ext
//!                  gravity-sign             y = M (2 U_cur − U_prev)/Δt² + f_ext, gravity (0, +9.8, 0)
//!                  gravity-times-mass       y = M (2 U_cur − U_prev)/Δt² + M f_ext
//!                  dt-squared-missing-in-y  y = M (2 U_cur − U_prev) + f_ext
//!                  inertia-minus-prev       y = M (2 U_cur + U_prev)/Δt² + f_ext
//!                  inertia-sign             y = −M (2 U_cur − U_prev)/Δt² + f_ext
//!                  inertia-half-missing     y = 2M (2 U_cur − U_prev)/Δt² + f_ext
//! step_rest_lengths r-from-deformed         rᵢⱼ = ‖U_curᵢ − U_curⱼ‖ (every step)
//! local_step       d-not-normalised         dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)
//!                  d-against-a              dᵢⱼ = rᵢⱼ (pⱼ − pᵢ)/‖pⱼ − pᵢ‖
//!                  d-from-u-cur             dᵢⱼ = rᵢⱼ (U_curᵢ − U_curⱼ)/‖U_curᵢ − U_curⱼ‖
//! right_hand_side  pins-not-in-b            b = k Aᵀd + y
//!                  pins-without-w           b = k Aᵀd + y + CᵀC V
//!                  w-on-y                   b = k Aᵀd + w y + CᵀC V
//!                  a-transposed             b = k A d + y + w CᵀC V (A being n × m)
//! ```
//!
//! The mistakes of the precomputation ([`precomputation`](super::precomputation))
//! reach the step through its `M`, `A`, `C` and factor of `Q`.
//! [`StudentStep`] keeps every iteration's `d`, `b` and `p` for `trace`.
//!
//! Cost: the handout's step's.

#![allow(non_snake_case)] // the handout's names: U_prev, U_cur, U_next

use super::super::backend::{LinearAlgebra, Sparse};
use super::super::forces::GRAVITY;
use super::super::local_step::project_springs;
use super::super::precomputation::rest_lengths;
use super::super::textbook::{pin_term, solve_sparse, Precomputation};
use super::gallery::Mistake;
use crate::linalg::sparse::CscMatrix;

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
        let it = Some(mistake);
        let n = U_cur.len();
        StudentStep {
            mistake,
            pre,
            U_cur,
            r: step_rest_lengths(it, &pre.r, &pre.springs, U_cur),
            y: inertial_term(it, &pre.M, f_ext, U_prev, U_cur, pre.delta_t),
            pins: pin_term(pre), // w CᵀC V
            d: vec![[0.0; 3]; pre.springs.len()],
            b: vec![[0.0; 3]; n],
            p: U_cur.to_vec(),
            x: vec![[0.0; 3]; n],
        }
    }

    /// One local/global iteration: `d`, `b`, then `p = Q⁻¹ b`.
    pub fn iterate(&mut self) {
        let (pre, it) = (self.pre, Some(self.mistake));
        local_step(it, &pre.springs, &self.r, &self.p, self.U_cur, &mut self.d);
        let rhs = RightHandSide {
            k: pre.k,
            A: &pre.A,
            w: pre.w,
        };
        rhs.compute(it, &self.d, &self.y, &self.pins, &mut self.b);
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

/// `y = M (2 U_cur − U_prev)/Δt² + f_ext`, with the mistake's change.
pub fn inertial_term(
    mistake: Option<Mistake>,
    M: &CscMatrix,
    f_ext: &[[f64; 3]],
    U_prev: &[[f64; 3]],
    U_cur: &[[f64; 3]],
    delta_t: f64,
) -> Vec<[f64; 3]> {
    let dt2 = delta_t * delta_t;
    let (mut cur, mut prev) = (U_cur, U_prev);
    let mut forces = f_ext.to_vec();
    // (the coefficient of U_prev, what M (2 U_cur ± U_prev) is divided by)
    let (sign, divisor) = match mistake {
        Some(Mistake::DtNotSquared) => (-1.0, delta_t),
        Some(Mistake::DtSquaredMissingInY) => (-1.0, 1.0),
        Some(Mistake::InertiaMinusPrev) => (1.0, dt2),
        Some(Mistake::InertiaSign) => (-1.0, -dt2),
        Some(Mistake::InertiaHalfMissing) => (-1.0, dt2 / 2.0),
        _ => (-1.0, dt2),
    };
    match mistake {
        Some(Mistake::PrevCurSwapped) => (cur, prev) = (U_prev, U_cur), // the two swapped
        Some(Mistake::GravityTimesMass) => Sparse::mul_points(M, f_ext, &mut forces), // M f_ext
        Some(Mistake::GravitySign) => {
            for f in &mut forces {
                *f = std::array::from_fn(|c| f[c] - 2.0 * GRAVITY[c]); // (0, +9.8, 0)
            }
        }
        _ => {}
    }
    let inertia: Vec<[f64; 3]> = cur
        .iter()
        .zip(prev)
        .map(|(cur, old)| std::array::from_fn(|c| 2.0 * cur[c] + sign * old[c]))
        .collect();
    let mut y = vec![[0.0; 3]; cur.len()];
    Sparse::mul_points(M, &inertia, &mut y); // M (2 U_cur − U_prev)
    for (y, f) in y.iter_mut().zip(&forces) {
        *y = std::array::from_fn(|c| y[c] / divisor + f[c]);
    }
    y
}

/// The rest lengths the step uses: the precomputation's `r`, or
/// (`r-from-deformed`) measured again on `U_cur`.
pub fn step_rest_lengths(
    mistake: Option<Mistake>,
    r: &[f64],
    springs: &[[usize; 2]],
    U_cur: &[[f64; 3]],
) -> Vec<f64> {
    match mistake {
        Some(Mistake::RFromDeformed) => rest_lengths(U_cur, springs), // ‖U_curᵢ − U_curⱼ‖
        _ => r.to_vec(),
    }
}

/// The local step: `dᵢⱼ = rᵢⱼ (pᵢ − pⱼ)/‖pᵢ − pⱼ‖` for each spring
/// `(i, j)`, with the mistake's change.
pub fn local_step(
    mistake: Option<Mistake>,
    springs: &[[usize; 2]],
    r: &[f64],
    p: &[[f64; 3]],
    U_cur: &[[f64; 3]],
    d: &mut [[f64; 3]],
) {
    match mistake {
        Some(Mistake::DNotNormalised) => {
            for ((d, &[i, j]), &r) in d.iter_mut().zip(springs).zip(r) {
                *d = std::array::from_fn(|c| r * (p[i][c] - p[j][c])); // not rescaled
            }
        }
        Some(Mistake::DAgainstA) => {
            let reversed: Vec<[usize; 2]> = springs.iter().map(|&[i, j]| [j, i]).collect();
            project_springs(&reversed, r, p, d); // from pⱼ − pᵢ
        }
        Some(Mistake::DFromUCur) => project_springs(springs, r, U_cur, d),
        _ => project_springs(springs, r, p, d),
    }
}

/// What `b` is made of besides `d`, `y` and the pins' `w CᵀC V`: `k`, `A`
/// and `w`.
#[derive(Debug, Clone, Copy)]
pub struct RightHandSide<'a> {
    pub k: f64,
    pub A: &'a CscMatrix,
    pub w: f64,
}

impl RightHandSide<'_> {
    /// `b = k Aᵀd + y + w CᵀC V`, with the mistake's change (`pins` is
    /// `w CᵀC V`).
    pub fn compute(
        &self,
        mistake: Option<Mistake>,
        d: &[[f64; 3]],
        y: &[[f64; 3]],
        pins: &[[f64; 3]],
        b: &mut [[f64; 3]],
    ) {
        match mistake {
            Some(Mistake::ATransposed) => Sparse::mul_points(self.A, d, b), // A d, A n × m
            _ => Sparse::transpose_mul_points(self.A, d, b),                // Aᵀd
        }
        let (k, w) = (self.k, self.w);
        for ((b, y), pin) in b.iter_mut().zip(y).zip(pins) {
            *b = match mistake {
                Some(Mistake::PinsNotInB) => std::array::from_fn(|c| k * b[c] + y[c]),
                Some(Mistake::PinsWithoutW) => {
                    std::array::from_fn(|c| k * b[c] + y[c] + pin[c] / w)
                }
                Some(Mistake::WOnY) => std::array::from_fn(|c| k * b[c] + w * y[c] + pin[c] / w),
                _ => std::array::from_fn(|c| k * b[c] + y[c] + pin[c]),
            };
        }
    }
}
