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
    write_atomically_with(path, |w| w.write_all(bytes))
}

/// Writes `path` atomically from `write`, which streams the content into a buffered
/// temporary file in the same folder; the file is synced and renamed over `path` only when
/// `write` has finished. Long outputs are never held in memory whole.
pub fn write_atomically_with(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let (tmp, file) = tempfile_in(dir, path)?;
    let mut out = std::io::BufWriter::with_capacity(1 << 16, file);
    let written = write(&mut out)
        .and_then(|()| out.flush())
        .and_then(|()| out.get_ref().sync_all());
    drop(out);
    let result = written
        .map_err(|e| Error::io(path, e))
        .and_then(|()| std::fs::rename(&tmp, path).map_err(|e| Error::io(path, e)));
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Writes a GeoJSON feature collection to `path` atomically.
pub fn write_geojson(path: &Path, collection: &geojson::FeatureCollection) -> Result<()> {
    let text = serde_json::to_string(collection).map_err(|e| Error::io(path, e.into()))?;
    write_atomically(path, text.as_bytes())
}

/// `text` split around the first `marker`, the marker's last character (`]`) kept in the
/// tail; panics when there is none (a serialisation of our own types).
pub(crate) fn split_once_at<'a>(text: &'a str, marker: &str) -> (&'a str, &'a str) {
    let at = text
        .find(marker)
        .expect("the serialised shell holds its empty array");
    let cut = at + marker.len() - 1;
    (&text[..cut], &text[cut..])
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
