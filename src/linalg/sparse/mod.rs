//! Sparse matrices and the sparse Cholesky pipeline.
//!
//! | step | file |
//! |---|---|
//! | triplets → CSC | [`triplets`] |
//! | the CSC type | [`csc`] |
//! | permutations | [`permutation`] |
//! | fill-reducing ordering (AMD) | [`amd`] |

pub mod amd;
pub mod csc;
pub mod permutation;
pub mod triplets;

pub use csc::{CscMatrix, Triangle};
pub use permutation::Permutation;
pub use triplets::TripletMatrix;
