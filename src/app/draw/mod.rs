//! The software renderer: a rasterizer in a few hundred lines, with the
//! viewer's look (`look.rs`), and what else draws pixels: plots
//! (`plot.rs`), sparsity patterns and elimination trees (`sparsity.rs`),
//! and the PNG and GIF encoders (`palette.rs`, `encode.rs`). `render`
//! draws a simulation with it (`render --mistake`: two, side by side,
//! `panels.rs`); `spy`, `etree`, `converge`, `bench` and
//! `generate` draw their pictures with it.
//!
//! A frame, one file per step: one camera frames the scene (`camera.rs`);
//! each frame is drawn (`frame.rs`): background (`canvas.rs`), surfaces
//! (`triangle.rs`, `lighting.rs`, `texture.rs`), springs (`lines.rs`),
//! point masses (`discs.rs`), at 2× and filtered down; then encoded
//! (`palette.rs`, `encode.rs`).
//!
//! This is teaching code, written for reading, not a production renderer
//! (no clipping against the near plane: the camera keeps the whole scene in
//! front of it; no mipmaps; no shadows).

pub(super) mod camera;
mod canvas;
mod discs;
pub(super) mod encode;
pub(super) mod frame;
mod lighting;
mod lines;
pub(super) mod look;
mod palette;
pub(super) mod panels;
pub(super) mod plot;
pub(super) mod sparsity;
mod text;
pub(super) mod texture;
mod triangle;
mod vector;

#[cfg(test)]
#[path = "../../../tests/common/mod.rs"]
mod tests_common;
