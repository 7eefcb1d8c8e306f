//! The handout's precomputation with a mistake in it: `r`, `M`, `A`, `C`,
//! `Q` and the factor of `Q`, as
//! [`fast_mass_springs_precomputation_sparse`](super::super::textbook::fast_mass_springs_precomputation_sparse)
//! makes them, but for the one line the [`Mistake`] writes wrong:
//!
//! ```text
//! mass-doubled          M = 2 diag(m)
//! a-sign                A(e, i) = +1, A(e, j) = +1
//! pins-one-based        C from the pins as the file counts them (from 1)
//! pins-not-in-q         Q = k AᵀA + M/Δt²
//! dt-not-squared        Q = k AᵀA + M/Δt  + w CᵀC
//! inertia-sign          Q = k AᵀA − M/Δt² + w CᵀC
//! inertia-half-missing  Q = k AᵀA + 2M/Δt² + w CᵀC
//! ```
//!
//! The other mistakes are in the step ([`step`](super::step)); their
//! precomputation is the handout's. `Q` may then not be positive definite
//! (`inertia-sign` on a scene whose springs are weak against its masses):
//! the factorization fails, as Eigen's `SimplicialLLT` does.
//!
//! Cost: the handout's precomputation's.

#![allow(non_snake_case)] // the handout's names: V, M, A, C, Q

use super::super::backend::{LinearAlgebra, Sparse};
use super::super::control::ITERATIONS;
use super::super::error::SimulationError;
use super::super::precomputation::{
    assemble_q, check_inputs, check_pins, mass_matrix, rest_lengths, selection_matrix, PIN_WEIGHT,
};
use super::super::signed_incidence::signed_incidence_matrix;
use super::super::textbook::{factored_as_eigen, Precomputation};
use super::Mistake;
use crate::linalg::sparse::{CscMatrix, Ordering};

/// The handout's precomputation with `mistake` made in it, the sparse `Q`
/// ordered by `ordering` and factored by the simplicial method (as
/// [`precomputation_ordered`](super::super::textbook::precomputation_ordered)).
///
/// # Errors
/// As the handout's: [`SimulationError::InvalidInput`] for inconsistent
/// inputs (`pins-one-based` on a scene whose last vertex is pinned names a
/// vertex beyond the last), [`SimulationError::Linalg`] when the mistaken
/// `Q` is not positive definite.
#[allow(clippy::too_many_arguments)] // the handout's six inputs, the mistake and the ordering
pub fn precomputation(
    mistake: Mistake,
    V: &[[f64; 3]],
    springs: &[[usize; 2]],
    k: f64,
    m: &[f64],
    pinned: &[usize],
    delta_t: f64,
    ordering: Ordering,
) -> Result<Precomputation<Sparse>, SimulationError> {
    let n = V.len();
    check_inputs(V, springs, m)?;
    let pinned = student_pins(mistake, pinned);
    check_pins(n, &pinned, pinned.len())?;
    let w = PIN_WEIGHT;
    let r = rest_lengths(V, springs); // rᵢⱼ = ‖Vᵢ − Vⱼ‖
    let M = mass_matrix::<Sparse>(&student_masses(mistake, m));
    let A = student_incidence(mistake, n, springs);
    let C = selection_matrix::<Sparse>(n, &pinned);
    let Q = student_q(mistake, k, &A, &M, delta_t, w, &C);
    let prefactorization = Sparse::factor(&Q, factored_as_eigen(ordering))?;
    Ok(Precomputation {
        V: V.to_vec(),
        springs: springs.to_vec(),
        k,
        pinned,
        delta_t,
        w,
        r,
        M,
        A,
        C,
        Q,
        prefactorization,
        iterations: ITERATIONS,
        stop: None,
    })
}

/// The pins: `pins-one-based` takes the scene's (0-based) pins back to the
/// file's count from 1, as a reader that forgets `b − 1` does.
fn student_pins(mistake: Mistake, pinned: &[usize]) -> Vec<usize> {
    match mistake {
        Mistake::PinsOneBased => pinned.iter().map(|&i| i + 1).collect(),
        _ => pinned.to_vec(),
    }
}

/// The masses: `mass-doubled` doubles them.
fn student_masses(mistake: Mistake, m: &[f64]) -> Vec<f64> {
    match mistake {
        Mistake::MassDoubled => m.iter().map(|&mi| 2.0 * mi).collect(),
        _ => m.to_vec(),
    }
}

/// `A`: `a-sign` writes `+1` where the handout writes `−1`.
fn student_incidence(mistake: Mistake, n: usize, springs: &[[usize; 2]]) -> CscMatrix {
    match mistake {
        Mistake::ASign => {
            let entries = springs.iter().enumerate();
            let entries = entries.flat_map(|(e, &[i, j])| [(e, i, 1.0), (e, j, 1.0)]);
            Sparse::from_entries(springs.len(), n, entries)
        }
        _ => signed_incidence_matrix::<Sparse>(n, springs),
    }
}

/// `Q`, with the mistake's term changed or left out.
fn student_q(
    mistake: Mistake,
    k: f64,
    A: &CscMatrix,
    M: &CscMatrix,
    delta_t: f64,
    w: f64,
    C: &CscMatrix,
) -> CscMatrix {
    let AtA = Sparse::gram(A);
    let dt2 = delta_t * delta_t;
    let with_pins = |mass_term: CscMatrix| {
        let springs_and_mass = Sparse::combine(k, &AtA, 1.0, &mass_term);
        Sparse::combine(1.0, &springs_and_mass, w, &Sparse::gram(C))
    };
    match mistake {
        Mistake::PinsNotInQ => Sparse::combine(k, &AtA, 1.0, &Sparse::divide(M, dt2)), // no w CᵀC
        Mistake::DtNotSquared => with_pins(Sparse::divide(M, delta_t)),                // M/Δt
        Mistake::InertiaSign => with_pins(Sparse::divide(M, -dt2)),                    // −M/Δt²
        Mistake::InertiaHalfMissing => with_pins(Sparse::divide(M, dt2 / 2.0)),        // 2M/Δt²
        _ => assemble_q::<Sparse>(k, A, M, delta_t, w, C),
    }
}
