//! The `masssprings` command line: see `masssprings help`.

mod app;

/// The seeded mutator of the hostile-input tests (used by the unit tests of
/// the texture reader and the HTTP request parser).
#[cfg(test)]
#[path = "../tests/common/mutate.rs"]
mod mutate;

fn main() {
    // as the system gives them: a name that is not UTF-8 is still a path
    let args: Vec<std::ffi::OsString> = std::env::args_os().skip(1).collect();
    std::process::exit(app::run(&args));
}
