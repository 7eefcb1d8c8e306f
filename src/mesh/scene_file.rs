//! The scene file: a JSON object naming the mesh and the physical settings.
//!
//! ```text
//! {
//!   "obj": "horizontal-chain.obj",   required: the OBJ, relative to this file's folder
//!   "k": 5e2,                        required: the stiffness of every spring, > 0
//!   "b": [1, 10],                    required: pinned vertices, 1-based (may be empty)
//!   "m": 1,                          optional: a uniform mass, > 0 (else Voronoi masses)
//!   "png": "flag.png"                optional: a texture for display, relative to this folder
//! }
//! ```
//!
//! Any other key is an error, and so is `bc`: the assignment's reader
//! refuses boundary conditions ("not supported"), and so do we, saying so.
//! Pins are integers ≥ 1 here; that they name an existing vertex is checked
//! once the OBJ is read. A pin listed twice is kept twice (the assignment
//! does the same; `C` gets two rows for it).
//!
//! Cost: one pass over the text (serde_json), which reports the line of
//! every problem.
//!
//! Source: the assignment's `read_json`; the scene format in `data/README.md`.

use std::fmt;
use std::path::Path;

use serde::de::{self, Deserializer, MapAccess, Unexpected, Visitor};
use serde::Deserialize;

use super::SceneError;
use crate::files::Source;

/// The keys of a scene file, checked one by one as they are parsed.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    #[serde(deserialize_with = "mesh_file")]
    pub obj: String,
    #[serde(deserialize_with = "stiffness")]
    pub k: f64,
    #[serde(deserialize_with = "pins")]
    pub b: Vec<u64>,
    #[serde(default, deserialize_with = "uniform_mass")]
    pub m: Option<f64>,
    #[serde(default, deserialize_with = "texture_file")]
    pub png: Option<String>,
    /// Never set: any value of `bc` is refused while it is parsed.
    #[serde(
        default,
        rename = "bc",
        deserialize_with = "refuse_boundary_conditions"
    )]
    _boundary_conditions: Option<()>,
}

/// Reads and checks the scene file at `path` of `files`.
///
/// # Errors
/// A [`SceneError`] naming `path` (with serde_json's line) for a file that
/// cannot be read, invalid JSON, a missing, repeated, mistyped or unknown
/// key, `bc`, `k` or `m` not a finite number > 0, or a pin < 1.
pub(crate) fn read_scene_file(files: &dyn Source, path: &Path) -> Result<SceneFile, SceneError> {
    let text = files.text(path)?;
    serde_json::from_str(&text)
        .map(|SceneObject(scene)| scene)
        .map_err(|error| json_error(error).in_file(path))
}

/// A [`SceneFile`] written as a JSON object, and only so: serde's derived
/// structs would also accept an array of the values in field order.
struct SceneObject(SceneFile);

impl<'de> Deserialize<'de> for SceneObject {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<SceneObject, D::Error> {
        deserializer.deserialize_map(SceneObjectVisitor)
    }
}

struct SceneObjectVisitor;

impl<'de> Visitor<'de> for SceneObjectVisitor {
    type Value = SceneObject;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(
            "a scene: an object with keys \"obj\", \"k\", \"b\" (and optionally \"m\", \"png\")",
        )
    }

    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<SceneObject, A::Error> {
        SceneFile::deserialize(de::value::MapAccessDeserializer::new(map)).map(SceneObject)
    }
}

/// serde_json's message without its " at line L column C" tail, placed on
/// line L.
fn json_error(error: serde_json::Error) -> SceneError {
    let message = error.to_string();
    let position = format!(" at line {} column {}", error.line(), error.column());
    let problem = message.strip_suffix(&position).unwrap_or(&message);
    let scene_error = SceneError::invalid(problem);
    if error.line() > 0 {
        scene_error.at_line(error.line())
    } else {
        scene_error
    }
}

fn mesh_file<'de, D: Deserializer<'de>>(deserializer: D) -> Result<String, D::Error> {
    deserializer.deserialize_any(FileName { key: "obj" })
}

fn texture_file<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<String>, D::Error> {
    deserializer
        .deserialize_any(FileName { key: "png" })
        .map(Some)
}

fn stiffness<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
    deserializer.deserialize_any(PositiveNumber { key: "k" })
}

fn uniform_mass<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Option<f64>, D::Error> {
    deserializer
        .deserialize_any(PositiveNumber { key: "m" })
        .map(Some)
}

fn pins<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<u64>, D::Error> {
    let pins = Vec::<Pin>::deserialize(deserializer)?;
    Ok(pins.into_iter().map(|Pin(index)| index).collect())
}

fn refuse_boundary_conditions<'de, D: Deserializer<'de>>(
    _deserializer: D,
) -> Result<Option<()>, D::Error> {
    Err(de::Error::custom(
        "boundary conditions \"bc\" are not supported (as in the assignment): pin vertices \
         with \"b\" instead",
    ))
}

/// A string value, named `key` in messages.
struct FileName {
    key: &'static str,
}

impl Visitor<'_> for FileName {
    type Value = String;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a file name (a non-empty string) for \"{}\"", self.key)
    }

    fn visit_str<E: de::Error>(self, value: &str) -> Result<String, E> {
        if value.is_empty() {
            return Err(E::invalid_value(Unexpected::Str(value), &self));
        }
        Ok(value.to_string())
    }
}

/// A finite number > 0, named `key` in messages.
struct PositiveNumber {
    key: &'static str,
}

impl Visitor<'_> for PositiveNumber {
    type Value = f64;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a finite number > 0 for \"{}\"", self.key)
    }

    fn visit_f64<E: de::Error>(self, value: f64) -> Result<f64, E> {
        self.check(value, Unexpected::Float(value))
    }

    fn visit_u64<E: de::Error>(self, value: u64) -> Result<f64, E> {
        self.check(value as f64, Unexpected::Unsigned(value))
    }

    fn visit_i64<E: de::Error>(self, value: i64) -> Result<f64, E> {
        self.check(value as f64, Unexpected::Signed(value))
    }
}

impl PositiveNumber {
    /// `value` if it is finite and > 0; else an error quoting it as written.
    fn check<E: de::Error>(self, value: f64, as_written: Unexpected) -> Result<f64, E> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(E::invalid_value(as_written, &self))
        }
    }
}

/// One entry of `b`: a 1-based vertex index, an integer ≥ 1 (that it
/// names a vertex of the OBJ is checked once the OBJ is read, which then
/// names a pin of 2⁶⁴ − 1 as what it is: no vertex).
struct Pin(u64);

impl<'de> Deserialize<'de> for Pin {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Pin, D::Error> {
        deserializer.deserialize_any(PinVisitor).map(Pin)
    }
}

struct PinVisitor;

impl Visitor<'_> for PinVisitor {
    type Value = u64;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a pin in \"b\": a 1-based vertex index (an integer ≥ 1)")
    }

    fn visit_u64<E: de::Error>(self, value: u64) -> Result<u64, E> {
        if value >= 1 {
            Ok(value)
        } else {
            Err(E::invalid_value(Unexpected::Unsigned(value), &self))
        }
    }

    fn visit_i64<E: de::Error>(self, value: i64) -> Result<u64, E> {
        match u64::try_from(value) {
            Ok(index) if index >= 1 => Ok(index),
            _ => Err(E::invalid_value(Unexpected::Signed(value), &self)),
        }
    }

    fn visit_f64<E: de::Error>(self, value: f64) -> Result<u64, E> {
        if value.fract() == 0.0 && value >= 1.0 {
            // an integer past 2⁶⁴, which JSON reads as a float
            return Err(E::custom(format!(
                "the pin {value:e} in \"b\" is larger than any vertex index (pins are 1-based \
                 vertex indices)"
            )));
        }
        Err(E::invalid_type(Unexpected::Float(value), &self))
    }
}
