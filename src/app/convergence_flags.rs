//! The flags that choose how each step is solved, shared by `simulate`,
//! `render`, `view` and `converge`: `--method`, `--tolerance`,
//! `--iterations`, `--rho`, `--window`, `--pins`.

use super::args::Args;
use super::AppError;
use masssprings::sim::simulation::SimulationOptions;

/// The option names (each takes a value).
pub const OPTIONS: &[&str] = &["method", "tolerance", "iterations", "rho", "window", "pins"];

/// Sets `options` from the flags that were given.
///
/// # Errors
/// A usage error for an unknown method or a value out of range.
pub fn apply(args: &Args, options: &mut SimulationOptions) -> Result<(), AppError> {
    options.method = args.value_or("method", options.method)?;
    options.pins = args.value_or("pins", options.pins)?;
    options.iterations = args.value_or("iterations", options.iterations)?;
    let tolerance: f64 = args.value_or("tolerance", f64::NAN)?;
    if !tolerance.is_nan() {
        if !(tolerance > 0.0 && tolerance < 1.0) {
            return Err(AppError::Usage(format!(
                "--tolerance expects a number between 0 and 1 (a relative gradient), got {tolerance}"
            )));
        }
        options.tolerance = Some(tolerance);
    }
    let rho: f64 = args.value_or("rho", f64::NAN)?;
    if !rho.is_nan() {
        if !(rho > 0.0 && rho < 1.0) {
            return Err(AppError::Usage(format!(
                "--rho expects a spectral radius between 0 and 1, got {rho}"
            )));
        }
        options.rho = Some(rho);
    }
    options.window = args.value_or("window", options.window)?;
    if options.window == 0 || options.window > 100 {
        return Err(AppError::Usage(format!(
            "--window expects a history length from 1 to 100, got {}",
            options.window
        )));
    }
    Ok(())
}
