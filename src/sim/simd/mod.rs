//! The fast path's kernels, several springs or vertices per instruction.
//!
//! Each file here is the twin of a file one level up, which holds the
//! formula one spring (or vertex) at a time: read that first. The twins do
//! the same arithmetic lane by lane on a CPU with AVX2 (checked at run time)
//! and fall back to the formula elsewhere, and wherever the portable
//! kernels are chosen ([`kernels`](crate::linalg::kernels)); the tests hold each to its
//! formula, bit for bit where the order of the sums is the same
//! (`tests/linalg/kernels.rs`).
//!
//! | here | the formula |
//! |---|---|
//! | [`local_step`] | [`sim::local_step`](super::local_step) |
//! | [`spring_blocks`] | [`sim::spring_blocks`](super::spring_blocks) |
//! | [`spring_pass`] | [`sim::spring_pass`](super::spring_pass) |
//! | [`energy`] | [`sim::energy`](super::energy) (the vertices' sums) |
//! | [`block_vector`] | [`sim::methods::block_vector`](super::methods::block_vector) |

pub mod block_vector;
pub mod energy;
pub mod local_step;
pub mod spring_blocks;
pub mod spring_pass;
