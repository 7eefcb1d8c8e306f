//! Fuzz target: the frame reader of `simulate --resume` (the binary's
//! `src/app/resume/frames.rs`, included as it is). Any text must give a frame or
//! an error on a line of it (or about the whole file: no vertices); the
//! record of a frame read back must be written again to the same record.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[allow(dead_code)]
#[path = "../../src/app/resume/frames.rs"]
mod frames;

fuzz_target!(|data: &[u8]| {
    std::env::set_var(masssprings::memory::LIMIT_VARIABLE, "0.1");
    let Ok(text) = std::str::from_utf8(data) else {
        return; // the reader gets text only (files::read_text)
    };
    match frames::parse_frame(text) {
        Ok(frame) => {
            if let Some(record) = frame.record {
                let again = frames::parse_frame(&format!(
                    "{}\n{}\nv 0 0 0\n",
                    frames::header(&frame.scene, frame.step, frame.precision),
                    record.line()
                ))
                .expect("a frame written from a frame reads back");
                assert_eq!(again.record, Some(record));
            }
        }
        Err(error) => {
            let whole_file = error.to_string().contains("no vertices");
            assert!(error.line().is_some() || whole_file, "{error}");
        }
    }
});
