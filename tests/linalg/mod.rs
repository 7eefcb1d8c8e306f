//! The linear-algebra layer: dense and sparse kernels against nalgebra.

mod amd;
mod dense;
mod kernels;
mod matrix_market;
mod sparse_cholesky;
mod sparse_ops;
mod threads;
mod triplets;
