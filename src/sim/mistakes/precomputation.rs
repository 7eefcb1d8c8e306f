//! The handout's precomputation with a mistake in it: `r`, `M`, `A`, `C`,
//! `Q` and the factor of `Q`, as
//! [`fast_mass_springs_precomputation_sparse`](super::super::textbook::fast_mass_springs_precomputation_sparse)
//! makes them, but for the one line the [`Mistake`] writes wrong. Each
//! line is a function that takes the mistake (`None`: the handout's line),
//! so that `trace --compare` can recompute a student's quantity under
//! every mistake from the student's own inputs:
//!
//! ```text
//! masses      mass-doubled          mᵢ · 2
//!             uniform-masses        1
//!             masses-from-lengths   ½ Σ rₑ over the springs e at i
//! incidence   a-sign                A(e, i) = +1, A(e, j) = +1
//!             a-transposed          A n × m: a row per vertex, a column per spring
//! pins        pins-one-based        the pins as the file counts them (from 1)
//! q           pins-not-in-q         Q = k AᵀA + M/Δt²
//!             pins-without-w        Q = k AᵀA + M/Δt² + CᵀC
//!             dt-not-squared        Q = k AᵀA + M/Δt  + w CᵀC
//!             k-on-inertia          Q = k (AᵀA + M/Δt²) + w CᵀC
//!             inertia-sign          Q = k AᵀA − M/Δt² + w CᵀC
//!             inertia-half-missing  Q = k AᵀA + 2M/Δt² + w CᵀC
//!             a-transposed          Q = k A Aᵀ + M/Δt² + w CᵀC (A being n × m)
//! ```
//!
//! The other mistakes are in the step ([`step`](super::step)) or the loop
//! ([`simulation`](super::simulation)); their precomputation is the
//! handout's. `Q` may then not be positive definite (`inertia-sign` on a
//! scene whose springs are weak against its masses): the factorization
//! fails, as Eigen's `SimplicialLLT` does.
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
use super::gallery::Mistake;
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
    let (n, it) = (V.len(), Some(mistake));
    check_inputs(V, springs, m)?;
    let pinned = pins(it, pinned);
    check_pins(n, &pinned, pinned.len())?;
    let w = PIN_WEIGHT;
    let r = rest_lengths(V, springs); // rᵢⱼ = ‖Vᵢ − Vⱼ‖
    let M = mass_matrix::<Sparse>(&masses(it, m, springs, &r));
    let A = incidence(it, n, springs);
    let C = selection_matrix::<Sparse>(n, &pinned);
    let Q = q(it, k, &A, &M, delta_t, w, &C);
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
pub fn pins(mistake: Option<Mistake>, pinned: &[usize]) -> Vec<usize> {
    match mistake {
        Some(Mistake::PinsOneBased) => pinned.iter().map(|&i| i + 1).collect(),
        _ => pinned.to_vec(),
    }
}

/// The masses `m` of the scene as the student takes them, with the
/// springs and their rest lengths `r` at hand.
pub fn masses(mistake: Option<Mistake>, m: &[f64], springs: &[[usize; 2]], r: &[f64]) -> Vec<f64> {
    match mistake {
        Some(Mistake::MassDoubled) => m.iter().map(|&mi| 2.0 * mi).collect(),
        Some(Mistake::UniformMasses) => vec![1.0; m.len()],
        Some(Mistake::MassesFromLengths) => {
            let mut from_lengths = vec![0.0; m.len()];
            for (&[i, j], &r) in springs.iter().zip(r) {
                from_lengths[i] += r / 2.0; // half of each spring at i
                from_lengths[j] += r / 2.0;
            }
            from_lengths
        }
        _ => m.to_vec(),
    }
}

/// `A`: `a-sign` writes `+1` where the handout writes `−1`;
/// `a-transposed` builds the `n × m` transpose.
pub fn incidence(mistake: Option<Mistake>, n: usize, springs: &[[usize; 2]]) -> CscMatrix {
    match mistake {
        Some(Mistake::ASign) => {
            let entries = springs.iter().enumerate();
            let entries = entries.flat_map(|(e, &[i, j])| [(e, i, 1.0), (e, j, 1.0)]);
            Sparse::from_entries(springs.len(), n, entries)
        }
        Some(Mistake::ATransposed) => signed_incidence_matrix::<Sparse>(n, springs).transpose(),
        _ => signed_incidence_matrix::<Sparse>(n, springs),
    }
}

/// `Q` from the student's `A`, `M` and `C`, with the mistake's term
/// changed or left out.
pub fn q(
    mistake: Option<Mistake>,
    k: f64,
    A: &CscMatrix,
    M: &CscMatrix,
    delta_t: f64,
    w: f64,
    C: &CscMatrix,
) -> CscMatrix {
    let dt2 = delta_t * delta_t;
    // (the mass term, the pins' weight)
    let (mass_term, w) = match mistake {
        Some(Mistake::PinsNotInQ) => (Sparse::divide(M, dt2), 0.0), // no w CᵀC
        Some(Mistake::PinsWithoutW) => (Sparse::divide(M, dt2), 1.0), // CᵀC
        Some(Mistake::DtNotSquared) => (Sparse::divide(M, delta_t), w), // M/Δt
        Some(Mistake::KOnInertia) => (Sparse::divide(M, dt2 / k), w), // k M/Δt²
        Some(Mistake::InertiaSign) => (Sparse::divide(M, -dt2), w), // −M/Δt²
        Some(Mistake::InertiaHalfMissing) => (Sparse::divide(M, dt2 / 2.0), w), // 2M/Δt²
        Some(Mistake::ATransposed) => (Sparse::divide(M, dt2), w),
        _ => return assemble_q::<Sparse>(k, A, M, delta_t, w, C), // k AᵀA + M/Δt² + w CᵀC
    };
    let AtA = match mistake {
        Some(Mistake::ATransposed) => Sparse::gram(&A.transpose()), // A Aᵀ of the n × m A
        _ => Sparse::gram(A),
    };
    let springs_and_mass = Sparse::combine(k, &AtA, 1.0, &mass_term);
    if w == 0.0 {
        return springs_and_mass;
    }
    Sparse::combine(1.0, &springs_and_mass, w, &Sparse::gram(C))
}
