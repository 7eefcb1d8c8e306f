//! Fuzz target: a scene, JSON and OBJ, read from files as `load_scene`
//! reads them. The input is split at its first NUL byte: the JSON before,
//! the OBJ after (the JSON's "obj" key is replaced to point at that OBJ).
//! Any input must give a scene or an error naming a file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use masssprings::mesh::load_scene;

fuzz_target!(|data: &[u8]| {
    std::env::set_var(masssprings::memory::LIMIT_VARIABLE, "0.1");
    let (json, obj) = match data.iter().position(|&b| b == 0) {
        Some(at) => (&data[..at], &data[at + 1..]),
        None => (data, &b"v 0 0 0\nv 1 0 0\nf 1 2\n"[..]),
    };
    let folder = std::env::temp_dir().join(format!("masssprings-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&folder).unwrap();
    let json_path = folder.join("scene.json");
    std::fs::write(&json_path, json).unwrap();
    std::fs::write(folder.join("mesh.obj"), obj).unwrap();
    if let Err(error) = load_scene(&json_path) {
        assert!(error.path().is_some(), "{error}");
    }
});
