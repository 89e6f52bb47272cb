//! A run's output folder, written completely or not at all.
//!
//! Files are written into a hidden staging folder beside the destination; [`RunFolder::commit`]
//! moves them into place. Dropping an uncommitted folder removes the staging folder, so a
//! failed run leaves no half-written outputs.

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// A staging folder that becomes the run's output folder on [`RunFolder::commit`].
#[derive(Debug)]
pub struct RunFolder {
    destination: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl RunFolder {
    /// Starts a run whose outputs will land in `destination` (created if missing; files of
    /// the same names already there are replaced).
    pub fn create(destination: &Path) -> Result<Self> {
        let parent = destination
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        let name = destination
            .file_name()
            .map_or_else(|| "run".into(), |n| n.to_string_lossy().into_owned());
        let staging = parent.join(format!(".{name}.staging.{}", std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
        }
        std::fs::create_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
        Ok(Self {
            destination: destination.to_path_buf(),
            staging,
            committed: false,
        })
    }

    /// Where a file named `name` is to be written before commit.
    pub fn path(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// The final folder.
    pub fn destination(&self) -> &Path {
        &self.destination
    }

    /// Writes `bytes` as `name`.
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.path(name);
        std::fs::write(&p, bytes).map_err(|e| Error::io(p, e))
    }

    /// Creates the sub-folder `name` (for runs with several parts).
    pub fn create_dir(&self, name: &str) -> Result<()> {
        let p = self.path(name);
        std::fs::create_dir_all(&p).map_err(|e| Error::io(p, e))
    }

    /// Writes `value` as pretty JSON into `name`.
    pub fn write_json<T: serde::Serialize>(&self, name: &str, value: &T) -> Result<()> {
        let text = serde_json::to_string_pretty(value)
            .map_err(|e| Error::Input(format!("cannot serialise {name}: {e}")))?;
        self.write(name, text.as_bytes())
    }

    /// Moves every staged file and folder into the destination folder; a staged folder
    /// replaces a folder of the same name there (a re-run's `walk-N/`).
    pub fn commit(mut self) -> Result<PathBuf> {
        std::fs::create_dir_all(&self.destination).map_err(|e| Error::io(&self.destination, e))?;
        let entries = std::fs::read_dir(&self.staging).map_err(|e| Error::io(&self.staging, e))?;
        for entry in entries {
            let entry = entry.map_err(|e| Error::io(&self.staging, e))?;
            let to = self.destination.join(entry.file_name());
            if entry.path().is_dir() && to.is_dir() {
                std::fs::remove_dir_all(&to).map_err(|e| Error::io(&to, e))?;
            }
            std::fs::rename(entry.path(), &to).map_err(|e| Error::io(&to, e))?;
        }
        let _ = std::fs::remove_dir_all(&self.staging);
        self.committed = true;
        Ok(self.destination.clone())
    }
}

impl Drop for RunFolder {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rerun_replaces_files_and_folders_of_the_same_names() {
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("run");
        for (text, stale) in [("first", true), ("second", false)] {
            let folder = RunFolder::create(&out).expect("create");
            folder.create_dir("walk-1").expect("dir");
            folder
                .write("walk-1/track.csv", text.as_bytes())
                .expect("write");
            if stale {
                folder.write("walk-1/old.csv", b"x").expect("write");
            }
            folder
                .write("summary.json", text.as_bytes())
                .expect("write");
            folder.commit().expect("commit");
        }
        let read = |name: &str| std::fs::read_to_string(out.join(name)).expect("read");
        assert_eq!(read("summary.json"), "second");
        assert_eq!(read("walk-1/track.csv"), "second");
        assert!(!out.join("walk-1/old.csv").exists());
    }
}
