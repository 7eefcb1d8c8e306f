//! # masssprings
//!
//! Fast Simulation of Mass-Spring Systems (Liu et al. 2013), as Alec
//! Jacobson's computer-graphics assignment teaches it, on linear algebra
//! written out by hand.
//!
//! The crate is layered; each layer uses only the ones below it:
//!
//! * [`linalg`]: dense matrices and Cholesky; sparse triplets → CSC, the CSC
//!   operations, AMD ordering, symbolic analysis, numeric Cholesky
//!   (simplicial and supernodal), triangular solves. It imports nothing
//!   from the rest of the crate: it knows nothing about springs, files or
//!   limits, and could be lifted out.
//! * [`files`], [`memory`]: the rules every reader and writer follows (size
//!   caps, errors naming file and line, writing all or nothing, the memory
//!   limit); [`matrix_market`]: Matrix Market files read into and written
//!   from `linalg`'s matrices under those rules.
//! * [`mesh`]: scenes: the assignment's JSON + OBJ files read into rest
//!   positions, springs, masses and pins; procedural scenes. It knows
//!   nothing about solvers.
//! * [`sim`]: the assignment's mathematics: signed incidence matrix,
//!   precomputation (`r, M, A, C, Q` and the factorization of `Q`), the
//!   local/global time step, forces; dense and sparse from one code.

pub mod files;
pub mod linalg;
pub mod matrix_market;
pub mod memory;
pub mod mesh;
pub mod sim;
