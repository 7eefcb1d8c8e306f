//! Fuzz target: the viewer's HTTP request parser (the binary's
//! `src/app/view/http.rs`, included as it is). Any head must parse or be
//! refused with a 4xx or 5xx.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[allow(dead_code)]
#[path = "../../src/app/view/http.rs"]
mod http;

fuzz_target!(|data: &[u8]| {
    let Some(end) = http::find_head_end(data) else {
        return;
    };
    match http::parse_head(&data[..end]) {
        Ok(_) => {}
        Err(response) => assert!((400..=505).contains(&response.status)),
    }
});
