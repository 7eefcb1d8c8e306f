//! Hand-written linear algebra: everything the mass-spring solver needs, and
//! nothing about springs. It imports only `std` and itself (checked by
//! `tests/repository/layers.rs`), so it could be lifted out as a crate of its own.
//!
//! * [`dense`]: a row-major matrix and a dense Cholesky factorization.
//! * [`sparse`]: triplets → CSC, CSC operations, orderings (AMD), the sparse
//!   Cholesky pipeline (analyse once, factor, solve).
//! * [`huge_pages`]: asking Linux for 2 MB pages under large arrays.
//! * [`kernels`]: the native kernels (AVX2, FMA) or the portable loops.
//! * [`cancel`]: a flag that stops the long dense operations from another
//!   thread.
//! * [`threads`]: a pool of threads kept for a whole simulation, its
//!   barrier, and arrays its threads share.
//!
//! The pipeline from triplets to a solve is walked through in
//! `docs/sparse-cholesky.md`. Reading and writing its matrices as Matrix
//! Market files is `crate::matrix_market`, beside the crate's other readers:
//! a reader of files follows the crate's rules for files (size caps, errors
//! naming file and line, the memory limit), which are not linear algebra.

pub mod cancel;
pub mod dense;
pub mod error;
pub mod huge_pages;
pub mod kernels;
pub mod sparse;
pub mod threads;

pub use cancel::Cancel;
pub use error::LinalgError;

/// The fixed, varied `n × 3` right-hand side every solve benchmark uses
/// (`analyze`, `bench`, the criterion benches; the peers' harnesses under
/// `benches/peers/` write the same formula), so that their figures are
/// for the same solve.
pub fn benchmark_right_hand_side(n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let t = i as f64;
            [
                1.0 + (t * 0.37).sin(),
                (t * 0.11).cos(),
                0.5 - (t * 0.23).sin(),
            ]
        })
        .collect()
}
