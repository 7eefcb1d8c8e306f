//! Fuzz target: a student's file as `trace --compare` reads it (the
//! binary's `src/app/trace/compare/{entries,springs,factor}.rs`, included
//! as they are, driven by `tests/common/student_file.rs`): read as each
//! quantity's shape, as an `A` whose springs are matched to ours, as a `P`
//! and as an `L`. Any file must be compared or refused with a reason; never
//! a panic, an abort or an allocation past the memory limit.
#![no_main]

use libfuzzer_sys::fuzz_target;
use masssprings::matrix_market::parse;

#[allow(dead_code)]
#[path = "../../src/app/trace/compare/entries.rs"]
mod entries;
#[allow(dead_code)]
#[path = "../../src/app/trace/compare/factor.rs"]
mod factor;
#[allow(dead_code)]
#[path = "../../src/app/trace/compare/springs.rs"]
mod springs;
#[path = "../../tests/common/student_file.rs"]
mod student_file;

fuzz_target!(|data: &[u8]| {
    // Keep the memory limit small: a size line may claim anything.
    std::env::set_var(masssprings::memory::LIMIT_VARIABLE, "0.1");
    if let Ok(file) = parse(&String::from_utf8_lossy(data)) {
        student_file::compare_everything(&file);
    }
});
