//! The `masssprings` command line: see `masssprings help`.

mod app;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    std::process::exit(app::run(&args));
}
