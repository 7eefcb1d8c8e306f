//! Fuzz target: the PNG texture decoder of `render` (the binary's
//! `src/app/render/texture.rs`, included as it is). Any input must give a
//! texture or an error; a header claiming a huge image is refused before
//! anything is allocated for it.
#![no_main]

use libfuzzer_sys::fuzz_target;

/// What `texture.rs` takes from its sibling `look.rs`.
mod look {
    pub type Rgb = [f32; 3];
}

#[allow(dead_code)]
#[path = "../../src/app/render/texture.rs"]
mod texture;

const LIMIT: masssprings::memory::Limit = masssprings::memory::Limit {
    bytes: 256 << 20,
    source: "the fuzzer's limit",
};

fuzz_target!(|data: &[u8]| {
    let _ = texture::Texture::decode_png(std::io::Cursor::new(data), LIMIT);
});
