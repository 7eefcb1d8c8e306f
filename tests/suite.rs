//! The integration tests, one crate with a module per layer, so that they
//! compile and link once (`tests/hostile.rs`, which sets a memory limit for
//! its whole process, is the other crate). The modules mirror `src/`:
//!
//! ```sh
//! cargo test --test suite linalg::        # one layer
//! cargo test --test suite sim::fidelity:: # one file
//! cargo test textbook                     # every test whose name has `textbook`
//! ```

mod app;
/// Running the binary as a user does (shared with `tests/hostile.rs`).
#[path = "common/cli.rs"]
mod cli;
mod common;
mod linalg;
mod mesh;
mod repository;
mod sim;
/// The crate's source files, for the checks of its layers and words.
#[path = "common/source.rs"]
mod source;
