//! The `masssprings` command line: see `masssprings help`.

mod app;

/// The seeded mutator of the hostile-input tests (used by the unit tests of
/// the texture reader and the HTTP request parser).
#[cfg(test)]
#[path = "../tests/common/mutate.rs"]
mod mutate;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    std::process::exit(app::run(&args));
}
