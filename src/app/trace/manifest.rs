//! `trace.json`, the manifest of a trace folder: what the trace holds,
//! written last (a folder with a manifest holds a complete trace) and read
//! first by `--compare` and by a re-run that replaces the folder.

use crate::app::error::AppError;
use masssprings::files::shown;
use std::path::Path;

/// What `trace.json` records about a trace, for `--compare`.
#[derive(Debug, serde::Serialize, serde::Deserialize)]
pub struct Manifest {
    pub scene: String,
    pub step: usize,
    pub iterations: usize,
    pub ordering: String,
    pub vertices: usize,
    pub springs: usize,
    pub pins: usize,
    /// The stiffness `k`, which `--compare` needs for the size of `b`'s terms.
    pub k: f64,
    pub files: Vec<String>,
    /// The mistake made on purpose (`--mistake`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mistake: Option<String>,
    /// The trace's fingerprint (of the values and of the fields above),
    /// which each of its files carries in its first lines: a file without
    /// it is of another trace.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub trace: Option<String>,
}

/// The file `--compare` reads first.
pub(super) const MANIFEST: &str = "trace.json";

/// The manifest of the trace in `folder`.
pub fn read_manifest(folder: &Path) -> Result<Manifest, AppError> {
    let path = folder.join(MANIFEST);
    let text = masssprings::files::read_text(&path).map_err(|e| {
        AppError::Failed(format!(
            "{e} ({} is not a folder written by masssprings trace)",
            shown(folder)
        ))
    })?;
    serde_json::from_str(&text)
        .map_err(|e| AppError::Failed(format!("{}:{}: {e}", shown(&path), e.line())))
}
