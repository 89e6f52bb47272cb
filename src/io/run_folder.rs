//! A run's output folder, written completely or not at all, and replaced whole.
//!
//! The contract of `--out`: it is one run's folder. A new or empty folder is created; a
//! folder an earlier run wrote (it holds a `summary.json`) is **replaced whole** when the
//! new run commits, so no file of the old run is left beside the new ones (an old
//! `walk-3/` beside a 2-walk batch, an old `track.png` after `--online`); any other
//! non-empty folder (`--out .`, `--out /`, a folder of data) is refused before the run
//! starts, and a run whose `--out` holds one of its inputs is refused before anything is
//! moved.
//!
//! Files are written into a hidden staging folder and moved into place by
//! [`RunFolder::commit`]: beside the destination (`.NAME.staging.PID`) when it does not
//! exist yet, inside it (`.footslam.staging.PID`) when it does — so the moves are renames
//! within one file system even when `--out` is a mount point. Dropping an uncommitted folder
//! removes the staging folder, so a failed run leaves no half-written outputs.
//!
//! The staging folder is also the run's lock: a run whose destination another live process
//! is writing stops with an error naming that process, and staging folders of processes
//! that no longer run (a run killed with `kill -9` or Ctrl-C, a power cut) are removed when
//! the next run into the same destination starts. (Which processes run is read from
//! `/proc` on Linux; elsewhere nothing is removed or refused.)

use crate::error::{Error, Result};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The staging folders of this process's uncommitted runs, for [`remove_staging_folders`].
static STAGING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes the staging folders of this process's uncommitted runs: for an interrupt
/// handler (Ctrl-C, SIGTERM) to call before the process exits, so that an interrupted run
/// leaves nothing behind (the next run into the folder would remove it otherwise).
pub fn remove_staging_folders() {
    if let Ok(mut list) = STAGING.lock() {
        for path in list.drain(..) {
            let _ = std::fs::remove_dir_all(path);
        }
    }
}

fn registered(staging: &Path, add: bool) {
    if let Ok(mut list) = STAGING.lock() {
        if add {
            list.push(staging.to_path_buf());
        } else {
            list.retain(|p| p != staging);
        }
    }
}

/// A staging folder that becomes the run's output folder on [`RunFolder::commit`].
#[derive(Debug)]
pub struct RunFolder {
    destination: PathBuf,
    staging: PathBuf,
    committed: bool,
    /// The run's inputs (canonical paths), which [`RunFolder::commit`] must not replace.
    inputs: Vec<PathBuf>,
    /// The files and folders of an earlier run in the destination, which the commit
    /// replaces (0: a new or empty folder).
    replacing: usize,
}

impl RunFolder {
    /// Starts a run whose outputs will land in `destination`: created if missing, replaced
    /// whole at commit if an earlier run wrote it, refused if it holds anything else.
    ///
    /// # Errors
    ///
    /// * [`Error::Io`] when `destination`'s parent cannot be created or `destination` cannot be
    ///   listed;
    /// * [`Error::Output`] when `destination` is a file, is a non-empty folder without a
    ///   `summary.json` (not an earlier run's), is being written by another live process, or its
    ///   staging folder cannot be made.
    pub fn create(destination: &Path) -> Result<Self> {
        let parent = destination
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
        let name = destination
            .file_name()
            .map_or_else(|| "run".into(), |n| n.to_string_lossy().into_owned());
        if destination.exists() && !destination.is_dir() {
            return Err(Error::output(
                destination,
                "--out is a file: the outputs go into a folder; choose a folder's path",
            ));
        }
        let exists = destination.is_dir();
        let replacing = if exists {
            std::fs::read_dir(destination)
                .map_err(|e| Error::io(destination, e))?
                .flatten()
                .filter(|e| !e.file_name().to_string_lossy().contains(".staging."))
                .count()
        } else {
            0
        };
        if exists && !is_run_folder(destination)? {
            return Err(Error::output(
                destination,
                "--out is a folder with other files in it, not an earlier run's (it has no \
                 summary.json); a run replaces its --out whole, so choose a new or empty folder",
            ));
        }
        // Other runs into the same destination: a live one holds it, a dead one's staging
        // folder is left over.
        let beside = format!(".{name}.staging.");
        hold(parent, &beside, destination)?;
        if exists {
            hold(destination, INSIDE, destination)?;
        }
        let own = std::process::id();
        let staging = if exists {
            destination.join(format!("{INSIDE}{own}"))
        } else {
            parent.join(format!("{beside}{own}"))
        };
        // Errors name the folder asked for, not the hidden staging folder.
        let unwritable = |e: std::io::Error| {
            Error::output(
                destination,
                format!(
                    "cannot write the outputs into {}: {e}",
                    staging.parent().unwrap_or(parent).display()
                ),
            )
        };
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(unwritable)?;
        }
        std::fs::create_dir_all(&staging).map_err(unwritable)?;
        registered(&staging, true);
        Ok(Self {
            destination: destination.to_path_buf(),
            staging,
            committed: false,
            inputs: Vec::new(),
            replacing,
        })
    }

    /// How many files and folders of an earlier run the commit will replace (0: the
    /// destination is new or empty), for a notice before the run starts.
    #[must_use]
    pub fn replacing(&self) -> usize {
        self.replacing
    }

    /// Where a file named `name` is to be written before commit.
    #[must_use]
    pub fn path(&self, name: &str) -> PathBuf {
        self.staging.join(name)
    }

    /// The final folder.
    #[must_use]
    pub fn destination(&self) -> &Path {
        &self.destination
    }

    /// Writes `bytes` as `name`.
    ///
    /// # Errors
    ///
    /// [`Error::Io`] naming the staged file when it cannot be written (e.g. `name` lies in a
    /// sub-folder not made with [`RunFolder::create_dir`]).
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.path(name);
        std::fs::write(&p, bytes).map_err(|e| Error::io(p, e))
    }

    /// Creates the sub-folder `name` (for runs with several parts).
    ///
    /// # Errors
    ///
    /// [`Error::Io`] naming the staged folder when it cannot be created.
    pub fn create_dir(&self, name: &str) -> Result<()> {
        let p = self.path(name);
        std::fs::create_dir_all(&p).map_err(|e| Error::io(p, e))
    }

    /// Writes `value` as pretty JSON into `name`.
    /// (Streamed: a long run's summary is never held as text.)
    ///
    /// # Errors
    ///
    /// [`Error::Io`] when the staged file cannot be created or its last bytes cannot be written;
    /// [`Error::Encode`] when `value` cannot be serialised (e.g. a map with non-string keys) and
    /// also when writing fails midway, since `serde_json` reports the write's error as its own.
    pub fn write_json<T: serde::Serialize>(&self, name: &str, value: &T) -> Result<()> {
        let p = self.path(name);
        let file = std::fs::File::create(&p).map_err(|e| Error::io(&p, e))?;
        let mut out = std::io::BufWriter::with_capacity(1 << 16, file);
        serde_json::to_writer_pretty(&mut out, value)
            .map_err(|e| Error::encode(format!("serialise {name}"), e))?;
        std::io::Write::flush(&mut out).map_err(|e| Error::io(p, e))
    }

    /// Names the run's input files: [`RunFolder::commit`] refuses, before moving anything,
    /// to replace one of them, a folder holding one, or any file of an input's own folder
    /// (`--out` pointed at the folder of its inputs would overwrite what came with them,
    /// e.g. the simulator's `summary.json` beside its `steps.csv`).
    pub fn protect<P: AsRef<Path>>(&mut self, inputs: impl IntoIterator<Item = P>) {
        self.inputs.extend(
            inputs
                .into_iter()
                .filter_map(|p| p.as_ref().canonicalize().ok()),
        );
    }

    /// The first staged entry that would replace a protected input or a file of an input's
    /// folder, as (input, entry name).
    fn replaced_input(&self) -> Result<Option<(PathBuf, String)>> {
        let entries = std::fs::read_dir(&self.staging).map_err(|e| Error::io(&self.staging, e))?;
        for entry in entries {
            let entry = entry.map_err(|e| Error::io(&self.staging, e))?;
            let Ok(to) = self.destination.join(entry.file_name()).canonicalize() else {
                continue;
            };
            let name = entry.file_name().to_string_lossy().into_owned();
            if let Some(input) = self.inputs.iter().find(|i| {
                **i == to || (to.is_dir() && i.starts_with(&to)) || i.parent() == to.parent()
            }) {
                return Ok(Some((input.clone(), name)));
            }
        }
        Ok(None)
    }

    /// Staged inside an earlier run's folder: sets the earlier run's entries aside (renames
    /// within the folder), moves the new ones up, then deletes the earlier ones. A failed
    /// rename puts every entry back where it was, so the folder holds one run or the other,
    /// never a mix.
    fn replace_inside(&self) -> Result<()> {
        let dest = &self.destination;
        let aside = dest.join(format!("{INSIDE}{}{PREVIOUS}", std::process::id()));
        std::fs::create_dir(&aside).map_err(|e| Error::io(&aside, e))?;
        let names = |dir: &Path| -> Result<Vec<std::ffi::OsString>> {
            let entries = std::fs::read_dir(dir).map_err(|e| Error::io(dir, e))?;
            entries
                .map(|e| e.map(|e| e.file_name()).map_err(|e| Error::io(dir, e)))
                .collect()
        };
        let earlier: Vec<_> = names(dest)?
            .into_iter()
            .filter(|n| dest.join(n) != self.staging && dest.join(n) != aside)
            .collect();
        let fresh = names(&self.staging)?;
        let moved = move_entries(&earlier, dest, &aside).and_then(|()| {
            move_entries(&fresh, &self.staging, dest).inspect_err(|_| {
                let _ = move_entries(&earlier, &aside, dest);
            })
        });
        if let Err(e) = moved {
            let _ = std::fs::remove_dir(&aside);
            return Err(e);
        }
        // The new run is in place; a leftover of the earlier one is removed by the next run
        // into this folder (`hold`).
        let _ = std::fs::remove_dir_all(&aside);
        Ok(())
    }

    /// Replaces the destination folder's contents with the staged files and folders.
    /// Nothing is moved when an output would replace a protected input, or the destination
    /// holds one ([`RunFolder::protect`]).
    ///
    /// # Errors
    ///
    /// * [`Error::Output`], with nothing moved, when an output would replace a protected input or
    ///   a file beside one, or the destination holds an input; also when a destination that did
    ///   not exist at [`RunFolder::create`] has appeared and is not empty.
    /// * [`Error::Io`] when a folder cannot be listed or an entry cannot be moved. An earlier
    ///   run's folder is then put back as it was: it holds the old run or the new one, never a
    ///   mix (short of the process being killed between two renames).
    pub fn commit(mut self) -> Result<PathBuf> {
        if let Some((input, name)) = self.replaced_input()? {
            return Err(Error::output(
                &self.destination,
                format!(
                    "this run's output `{name}` would replace the input {} or a file beside \
                     it; choose an --out apart from the inputs (nothing was written)",
                    input.display()
                ),
            ));
        }
        if let Ok(dest) = self.destination.canonicalize()
            && let Some(input) = self.inputs.iter().find(|i| i.starts_with(&dest))
        {
            return Err(Error::output(
                &self.destination,
                format!(
                    "it holds this run's input {}, and a run replaces its --out whole; choose \
                     an --out apart from the inputs (nothing was written)",
                    input.display()
                ),
            ));
        }
        if self.staging.parent() == Some(self.destination.as_path()) {
            self.replace_inside()?;
            let _ = std::fs::remove_dir_all(&self.staging);
        } else {
            // Staged beside a destination that did not exist (another process may have
            // made it empty since).
            if self.destination.is_dir() {
                std::fs::remove_dir(&self.destination).map_err(|e| {
                    Error::output(
                        &self.destination,
                        format!("appeared while the run was writing and is not empty: {e}"),
                    )
                })?;
            }
            std::fs::rename(&self.staging, &self.destination)
                .map_err(|e| Error::io(&self.destination, e))?;
        }
        self.committed = true;
        registered(&self.staging, false);
        Ok(self.destination.clone())
    }
}

/// Prefix of the staging folder inside an existing destination.
const INSIDE: &str = ".footslam.staging.";

/// Moves each of `names` from folder `from` to folder `to`; on a failure, moves the ones
/// already moved back and returns the failure.
fn move_entries(names: &[std::ffi::OsString], from: &Path, to: &Path) -> Result<()> {
    for (k, name) in names.iter().enumerate() {
        if let Err(e) = std::fs::rename(from.join(name), to.join(name)) {
            for back in &names[..k] {
                let _ = std::fs::rename(to.join(back), from.join(back));
            }
            return Err(Error::io(to.join(name), e));
        }
    }
    Ok(())
}

/// Suffix of the folder inside the destination that holds an earlier run's entries while a
/// commit replaces them (`.footslam.staging.PID.previous`).
const PREVIOUS: &str = ".previous";

/// Whether `folder` is empty or an earlier run's (it holds a `summary.json`); staging
/// folders of other runs do not count.
fn is_run_folder(folder: &Path) -> Result<bool> {
    if folder.join("summary.json").is_file() {
        return Ok(true);
    }
    let entries = std::fs::read_dir(folder).map_err(|e| Error::io(folder, e))?;
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(folder, e))?;
        let name = entry.file_name();
        if !name.to_string_lossy().contains(".staging.") {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Staging folders `PREFIXpid` in `dir` of other processes: a live one's holds
/// `destination` (an error naming the process), a dead one's is removed.
fn hold(dir: &Path, prefix: &str, destination: &Path) -> Result<()> {
    let own = std::process::id();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let file = entry.file_name();
        let Some(pid) = file
            .to_str()
            .and_then(|f| f.strip_prefix(prefix))
            .and_then(|p| p.strip_suffix(PREVIOUS).unwrap_or(p).parse::<u32>().ok())
            .filter(|&p| p != own)
        else {
            continue;
        };
        match process_is_running(pid) {
            Some(true) => {
                return Err(Error::output(
                    destination,
                    format!(
                        "another run (process {pid}) is writing into it; wait for it to end or \
                         choose another --out"
                    ),
                ));
            }
            Some(false) => {
                let _ = std::fs::remove_dir_all(entry.path());
            }
            None => {}
        }
    }
    Ok(())
}

/// Whether process `pid` runs (`None`: cannot tell on this system).
fn process_is_running(pid: u32) -> Option<bool> {
    if cfg!(target_os = "linux") && Path::new("/proc/self").exists() {
        Some(Path::new("/proc").join(pid.to_string()).exists())
    } else {
        None
    }
}

impl Drop for RunFolder {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
            registered(&self.staging, false);
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
        // Nothing of the earlier run is left aside.
        let hidden = std::fs::read_dir(&out)
            .expect("list")
            .flatten()
            .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
            .count();
        assert_eq!(hidden, 0);
    }

    #[test]
    fn a_move_that_fails_halfway_puts_back_what_it_moved() {
        let dir = tempfile::tempdir().expect("tempdir");
        let (from, to) = (dir.path().join("from"), dir.path().join("to"));
        std::fs::create_dir_all(from.join("b")).expect("dir");
        std::fs::create_dir(&to).expect("dir");
        std::fs::write(from.join("a.csv"), "a").expect("write");
        // The second name does not exist: its rename fails after the first one's.
        let names = ["a.csv", "missing", "b"].map(std::ffi::OsString::from);
        let err = move_entries(&names, &from, &to).expect_err("a name is missing");
        assert!(err.to_string().contains("missing"), "{err}");
        assert!(from.join("a.csv").is_file() && from.join("b").is_dir());
        assert_eq!(std::fs::read_dir(&to).expect("list").count(), 0);
    }

    #[test]
    fn a_rerun_replaces_the_earlier_run_whole() {
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("run");
        let folder = RunFolder::create(&out).expect("create");
        for name in ["summary.json", "track.png"] {
            folder.write(name, b"first").expect("write");
        }
        folder.create_dir("walk-3").expect("dir");
        folder.commit().expect("commit");
        // The second run (into the existing folder: staged inside it) writes fewer files.
        let folder = RunFolder::create(&out).expect("create");
        assert!(
            folder.path("x").starts_with(&out),
            "staged inside the destination"
        );
        folder.write("summary.json", b"second").expect("write");
        folder.commit().expect("commit");
        let names: Vec<String> = std::fs::read_dir(&out)
            .expect("read")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(
            names,
            ["summary.json"],
            "no file of the earlier run is left"
        );
        // An empty folder is a fine --out; a folder of other files is refused before the run.
        let empty = dir.path().join("empty");
        std::fs::create_dir(&empty).expect("dir");
        RunFolder::create(&empty)
            .expect("empty")
            .commit()
            .expect("commit");
        let data = dir.path().join("data");
        std::fs::create_dir(&data).expect("dir");
        std::fs::write(data.join("notes.txt"), "mine").expect("write");
        let err = RunFolder::create(&data).expect_err("not a run's folder");
        assert!(err.to_string().contains("not an earlier run's"), "{err}");
        assert_eq!(
            std::fs::read_to_string(data.join("notes.txt")).expect("kept"),
            "mine"
        );
    }

    #[test]
    fn a_dead_runs_staging_folder_goes_and_a_live_one_holds_the_destination() {
        if process_is_running(std::process::id()) != Some(true) {
            return; // cannot tell which processes run here
        }
        let dir = tempfile::tempdir().expect("tempdir");
        let out = dir.path().join("run");
        // Process IDs are below 2²² on Linux: this one runs nowhere.
        let dead = dir.path().join(".run.staging.4294967");
        std::fs::create_dir_all(dead.join("walk-1")).expect("dir");
        let folder = RunFolder::create(&out).expect("create");
        assert!(!dead.exists(), "the dead run's staging folder is removed");
        folder.commit().expect("commit");
        // A live process (pid 1, init) writing into it: refused, naming the process.
        let live = dir.path().join(".run.staging.1");
        std::fs::create_dir_all(&live).expect("dir");
        let err = RunFolder::create(&out).expect_err("held by a live run");
        assert!(err.to_string().contains("process 1"), "{err}");
        assert!(live.exists(), "a live run's folder is left alone");
        // Another destination in the same parent is not held.
        RunFolder::create(&dir.path().join("other")).expect("create");
    }

    #[test]
    fn a_run_never_replaces_its_inputs() {
        let dir = tempfile::tempdir().expect("tempdir");
        let sim = dir.path().join("sim");
        std::fs::create_dir_all(&sim).expect("dir");
        std::fs::write(sim.join("steps.csv"), "t,length,dheading\n").expect("input");
        std::fs::write(sim.join("summary.json"), "simulator's").expect("input");
        let mut folder = RunFolder::create(&sim).expect("create");
        folder.protect([sim.join("steps.csv"), sim.join("summary.json")]);
        folder.write("summary.json", b"learn's").expect("write");
        folder.write("track.csv", b"t,x,y").expect("write");
        let err = folder.commit().expect_err("would replace an input");
        assert!(err.to_string().contains("summary.json"), "{err}");
        let read = |n: &str| std::fs::read_to_string(sim.join(n)).expect("read");
        assert_eq!(read("summary.json"), "simulator's");
        assert!(!sim.join("track.csv").exists(), "nothing was written");
        // A staged folder replacing a folder that holds an input is refused too.
        let out = dir.path().join("out");
        std::fs::create_dir_all(out.join("walk-1")).expect("dir");
        std::fs::write(out.join("walk-1/steps.csv"), "x").expect("input");
        assert!(RunFolder::create(&out).is_err(), "not a run's folder");
        std::fs::write(out.join("summary.json"), "{}").expect("an earlier run's");
        let mut folder = RunFolder::create(&out).expect("create");
        folder.protect([out.join("walk-1/steps.csv")]);
        folder.create_dir("walk-1").expect("dir");
        assert!(folder.commit().is_err());
        // A file of an input's folder (the simulator's config beside its steps) is kept too;
        // and since a run replaces its --out whole, a folder holding an input is refused
        // even for new file names.
        std::fs::write(sim.join("config.json"), "simulator's").expect("input");
        let mut folder = RunFolder::create(&sim).expect("create");
        folder.protect([sim.join("steps.csv")]);
        folder.write("config.json", b"learn's").expect("write");
        assert!(folder.commit().is_err());
        let mut folder = RunFolder::create(&sim).expect("create");
        folder.protect([sim.join("steps.csv")]);
        folder.write("track.csv", b"t,x,y").expect("write");
        let err = folder.commit().expect_err("holds an input");
        assert!(err.to_string().contains("holds this run's input"), "{err}");
        assert!(sim.join("steps.csv").exists() && !sim.join("track.csv").exists());
    }
}
