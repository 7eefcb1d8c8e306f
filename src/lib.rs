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
//!   (simplicial and supernodal), triangular solves, Matrix Market I/O. It
//!   knows nothing about springs.

pub mod linalg;
