//! Fuzz target: the Matrix Market reader, both entry points (any matrix,
//! and the symmetric one `analyze` uses). Any input must give a matrix or
//! an error with a line; never a panic, an abort or a huge allocation.
#![no_main]

use libfuzzer_sys::fuzz_target;
use masssprings::matrix_market::{parse, parse_symmetric};

fuzz_target!(|data: &[u8]| {
    // Keep the memory limit small: a size line may claim anything.
    std::env::set_var(masssprings::memory::LIMIT_VARIABLE, "0.1");
    let text = String::from_utf8_lossy(data);
    if let Err(error) = parse(&text) {
        assert!(error.line().is_some(), "{error}");
    }
    if let Err(error) = parse_symmetric(&text) {
        assert!(error.line().is_some(), "{error}");
    }
});
