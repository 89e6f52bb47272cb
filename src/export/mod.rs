//! Layer 4 (out): GeoJSON, pictures and run folders. Every file is written completely or
//! not at all (written beside its destination, then renamed).

mod glyphs;
pub mod map_geojson;
pub mod map_png;
pub mod plan_marks;
pub mod plan_png;
pub mod radio_map_geojson;
pub mod ros_map;
pub mod run_folder;
pub mod track_geojson;

pub use ros_map::write_ros_map;
pub use run_folder::RunFolder;

use crate::error::{Error, Result};
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, synced, then
/// renamed over `path`.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let mut tmp = tempfile_in(dir, path)?;
    tmp.1.write_all(bytes).map_err(|e| Error::io(&tmp.0, e))?;
    tmp.1.sync_all().map_err(|e| Error::io(&tmp.0, e))?;
    drop(tmp.1);
    std::fs::rename(&tmp.0, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp.0);
        Error::io(path, e)
    })
}

/// Writes a GeoJSON feature collection to `path` atomically.
pub fn write_geojson(path: &Path, collection: &geojson::FeatureCollection) -> Result<()> {
    let text = serde_json::to_string(collection).map_err(|e| Error::io(path, e.into()))?;
    write_atomically(path, text.as_bytes())
}

fn tempfile_in(dir: &Path, path: &Path) -> Result<(std::path::PathBuf, std::fs::File)> {
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    for attempt in 0..100u32 {
        let candidate = dir.join(format!(".{name}.{}.{attempt}.tmp", std::process::id()));
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&candidate)
        {
            Ok(f) => return Ok((candidate, f)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(Error::io(candidate, e)),
        }
    }
    Err(Error::io(
        dir,
        std::io::Error::other("cannot create a temporary file"),
    ))
}
