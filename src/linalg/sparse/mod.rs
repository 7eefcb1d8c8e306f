//! Sparse matrices and the sparse Cholesky pipeline.
//!
//! | step | file |
//! |---|---|
//! | the CSC type | [`csc`] |
//! | triplets → CSC | [`triplets`] |
//! | `Aᵀ` | [`transpose`] |
//! | `A x`, `A X`, `Aᵀ X` | [`multiply`] |
//! | `α A + β B`, `s A` | [`add`] |
//! | `A B`, `AᵀA` | [`product`] |
//! | permutations | [`permutation`] |
//! | `P A Pᵀ` of one triangle | [`permute`] |
//! | choice of ordering | [`ordering`] |
//! | fill-reducing ordering (AMD) | [`amd`] |
//! | the pattern of `P A Pᵀ`, for the analysis | [`pattern`] |
//! | elimination tree | [`etree`] |
//! | postorder | [`postorder`] |
//! | column counts | [`column_counts`] |
//! | pattern of a row of `L` | [`row_pattern`] |
//! | supernodes | [`supernodes`] |
//! | rows of each supernode | [`supernode_rows`] |
//! | relaxed supernodes (amalgamation) | [`amalgamation`] |
//! | symbolic analysis | [`symbolic`] |
//! | numeric factorization, row by row | [`up_looking`] |
//! | where `A`'s entries go in `L` | [`factor_loading`] |
//! | numeric factorization, supernodal | [`supernodal`] |
//! | the elimination tree cut among threads | [`subtrees`] |
//! | the same factorization on several threads | [`supernodal_parallel`] |
//! | forward and back substitution | [`triangular_solve`] |
//! | the same, by supernodes | [`supernodal_solve`] |
//! | the same, on several threads | [`supernodal_solve_parallel`] |
//! | all of it together | [`cholesky`] |

pub mod add;
pub mod amalgamation;
pub mod amd;
pub mod cholesky;
pub mod column_counts;
pub mod csc;
pub mod etree;
pub mod factor_loading;
pub mod multiply;
pub mod ordering;
pub mod pattern;
pub mod permutation;
pub mod permute;
pub mod postorder;
pub mod product;
pub mod row_pattern;
pub mod subtrees;
pub mod supernodal;
pub mod supernodal_parallel;
pub mod supernodal_solve;
pub mod supernodal_solve_parallel;
pub mod supernode_rows;
pub mod supernodes;
pub mod symbolic;
pub mod transpose;
pub mod triangular_solve;
pub mod triplets;
pub mod up_looking;

pub use amalgamation::{Relaxation, SupernodeMerging};
pub use cholesky::{Method, SparseCholesky};
pub use csc::{CscMatrix, Triangle};
pub use ordering::Ordering;
pub use permutation::Permutation;
pub use permute::PermutedTriangle;
pub use symbolic::SymbolicCholesky;
pub use triplets::TripletMatrix;
