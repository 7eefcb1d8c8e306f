//! The memory estimates of the commands, checked before the work starts
//! (`masssprings::memory` holds the limit and the message): the dense path,
//! the frames `render` keeps, the `generate grid N` mesh. And the one way
//! the commands precompute a simulation, so that a failure (a `Q` that is
//! not positive definite, say) names the scene file.

use super::error::AppError;
use masssprings::files::shown;
use masssprings::memory::{self, bytes_for, thousands};
use masssprings::mesh::Scene;
use masssprings::sim::precomputation;
use masssprings::sim::simulation::SimulationOptions;
use masssprings::sim::{Dense, LinearAlgebra, Simulation, SimulationError};
use std::path::Path;

/// Precomputes the simulation of `scene` (read from `scene_path`): refuses
/// a dense system that would not fit in memory first, and names the scene
/// file when the precomputation fails (a `Q` that would overflow `f64`
/// is named as such, with its bound, by the library).
///
/// # Errors
/// The memory refusal, or the precomputation's error after the scene's path.
pub fn precompute<B: LinearAlgebra>(
    scene: &Scene,
    scene_path: &Path,
    options: SimulationOptions,
) -> Result<Simulation<B>, AppError> {
    check_precomputation::<B>(scene, scene_path, options)?;
    Simulation::<B>::from_scene(scene, options)
        .map_err(|error| precomputation_failed(scene_path, &error))
}

/// What [`precompute`] checks before it starts: the dense path's memory,
/// `Q`'s overflow.
///
/// # Errors
/// The refusal.
pub fn check_precomputation<B: LinearAlgebra>(
    scene: &Scene,
    scene_path: &Path,
    options: SimulationOptions,
) -> Result<(), AppError> {
    if B::NAME == Dense::NAME {
        check_dense(scene)?;
    }
    // the library refuses it too; here before any allocation, with the path
    precomputation::check_q_fits(&scene.springs, &scene.masses, scene.k, options.delta_t)
        .map_err(|error| precomputation_failed(scene_path, &error))
}

/// The precomputation of the scene at `scene_path` failed with `error`: a
/// `Q` that would overflow is named as the library names it (the quantity,
/// its vertex, the largest value that fits), anything else as a failed
/// precomputation.
pub fn precomputation_failed(scene_path: &Path, error: &SimulationError) -> AppError {
    let path = shown(scene_path);
    AppError::Failed(match error {
        SimulationError::QOverflow(why) => format!("{path}: {why}"),
        error => format!("{path}: the precomputation failed: {error}"),
    })
}

/// The bytes of the dense path: `A` (springs × n), `C` (pins × n) and five
/// `n × n` matrices (`Q`, its factor, and the terms `AᵀA`, `M`, `CᵀC` while
/// `Q` is assembled), 8 bytes an entry.
pub fn dense_bytes(n: usize, springs: usize, pins: usize) -> u64 {
    let n = n as u64;
    let rows = (springs as u64).saturating_add(pins as u64);
    let entries = rows
        .saturating_mul(n)
        .saturating_add(5u64.saturating_mul(n.saturating_mul(n)));
    bytes_for(entries, 8)
}

/// Refuses `--dense` for a scene whose dense matrices would not fit.
///
/// # Errors
/// A failure with the estimate, the limit and the advice to use the sparse
/// path.
pub fn check_dense(scene: &Scene) -> Result<(), AppError> {
    let (bytes, what) = dense_need(scene);
    memory::check(bytes, || what, "use the sparse path (without --dense)")?;
    Ok(())
}

/// What the dense path of `scene` takes: its bytes ([`dense_bytes`]) and
/// what they are for, as [`check_dense`] says it.
pub fn dense_need(scene: &Scene) -> (u64, String) {
    let n = scene.vertices.len();
    let what = format!(
        "the dense path for n = {} ({} springs; five n × n matrices of f64)",
        thousands(n as u64),
        thousands(scene.springs.len() as u64)
    );
    (
        dense_bytes(n, scene.springs.len(), scene.pinned.len()),
        what,
    )
}

/// Refuses to keep `frames` frames of `bytes_per_frame` each (positions or
/// pictures kept for the whole run).
///
/// # Errors
/// A failure with the estimate, the limit and `advice`.
pub fn check_frames(frames: u64, bytes_per_frame: u64, advice: &str) -> Result<(), AppError> {
    check_kept(frames, "frames", bytes_per_frame, advice)
}

/// Refuses to keep `count` `items` (a plural: "iterates") of `each` bytes
/// for the whole run: the one rule for every record whose number a flag
/// sets (`--iterations`, `--steps`, `--repeats`).
///
/// # Errors
/// A failure with the estimate, the limit and `advice`.
pub fn check_kept(count: u64, items: &str, each: u64, advice: &str) -> Result<(), AppError> {
    memory::check(
        bytes_for(count, each),
        || {
            format!(
                "keeping {} {items} of {} bytes each",
                thousands(count),
                thousands(each)
            )
        },
        advice,
    )?;
    Ok(())
}

/// Pixels left below a picture for its caption (two lines of text at
/// twice its size, and their gaps, take less).
pub const CAPTION_PIXELS: u64 = 64;

/// The bytes of a `width × height` picture (its caption below) drawn with
/// `supersampling` samples a side: each sample its colour and depth (16
/// bytes), each pixel 3 bytes for the picture and as many again for the
/// PNG encoder; saturating.
pub fn picture_bytes(width: usize, height: usize, supersampling: usize) -> u64 {
    let pixels = (width as u64).saturating_mul((height as u64).saturating_add(CAPTION_PIXELS));
    let samples = pixels.saturating_mul((supersampling as u64).saturating_pow(2));
    bytes_for(samples, 16).saturating_add(bytes_for(pixels, 6))
}

/// Refuses to draw a picture of `bytes` ([`picture_bytes`], and what else
/// it keeps), `what` saying which.
///
/// # Errors
/// A failure with the estimate and the limit.
pub fn check_picture(bytes: u64, what: impl FnOnce() -> String) -> Result<(), AppError> {
    memory::check(bytes, what, "choose a smaller --size")?;
    Ok(())
}

/// The bytes of the `grid N` mesh: `N²` vertices (24 bytes) and `(N−1)²`
/// quads (4 indices of 8 bytes), saturating.
pub fn grid_bytes(n: usize) -> u64 {
    let n = n as u64;
    let cells = n.saturating_sub(1).saturating_mul(n.saturating_sub(1));
    bytes_for(n.saturating_mul(n), 24).saturating_add(bytes_for(cells, 32))
}

/// Refuses `generate grid N` when its mesh would not fit.
///
/// # Errors
/// A failure with the estimate and the limit.
pub fn check_grid(n: usize) -> Result<(), AppError> {
    memory::check(
        grid_bytes(n),
        || format!("grid {n} ({} vertices)", squared(n)),
        "choose a smaller N",
    )?;
    Ok(())
}

/// `n²`, exactly (a `u64` would overflow from `n = 2³²`), with thousands
/// separated: the vertex count of `grid n`.
fn squared(n: usize) -> String {
    thousands((n as u128) * (n as u128))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn estimates_grow_as_the_structures_and_saturate() {
        assert_eq!(dense_bytes(300_000, 0, 0), 5 * 300_000 * 300_000 * 8);
        assert_eq!(dense_bytes(2, 1, 1), (2 * 2 + 5 * 4) * 8);
        assert_eq!(dense_bytes(usize::MAX, usize::MAX, usize::MAX), u64::MAX);
        assert_eq!(grid_bytes(2), 4 * 24 + 32);
        assert_eq!(grid_bytes(usize::MAX), u64::MAX);
        assert_eq!(squared(4_294_967_296), "18,446,744,073,709,551,616");
        assert_eq!(squared(300), "90,000");
        assert_eq!(
            picture_bytes(10, 6, 3),
            (10 * 70 * 9 * 16 + 10 * 70 * 6) as u64
        );
        assert_eq!(picture_bytes(usize::MAX, 2, 3), u64::MAX);
    }
}
