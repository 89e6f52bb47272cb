//! How much the command line says: `--quiet` (errors and warnings only), the default (what a
//! run found and one closing line), `--verbose` (also every file written, and progress bars
//! from the start).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicU8, Ordering};
use std::time::Instant;

/// 0: quiet, 1: normal, 2: verbose.
static LEVEL: AtomicU8 = AtomicU8::new(1);
/// When the command started.
static STARTED: OnceLock<Instant> = OnceLock::new();

/// Sets the level from the global flags and starts the command's clock.
pub fn set(quiet: bool, verbose: bool) {
    let level = match (quiet, verbose) {
        (true, _) => 0,
        (false, true) => 2,
        (false, false) => 1,
    };
    LEVEL.store(level, Ordering::Relaxed);
    let _ = STARTED.set(Instant::now());
}

/// `--quiet`: no progress, no report on stdout.
pub fn quiet() -> bool {
    LEVEL.load(Ordering::Relaxed) == 0
}

/// `--verbose`.
pub fn verbose() -> bool {
    LEVEL.load(Ordering::Relaxed) >= 2
}

/// Seconds since the command started.
pub fn elapsed_s() -> f64 {
    STARTED.get().map_or(0.0, |t| t.elapsed().as_secs_f64())
}

/// The files under `dir`, sorted (hidden staging folders left out).
fn files_under(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let path = e.path();
            if e.file_name().to_string_lossy().starts_with('.') {
                continue;
            }
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The closing line of a run that wrote the folder `out`: what was written, the quality
/// verdict (`quality`: its line, when the run judges one) and the time; with `--verbose`
/// first every file written.
pub fn done(out: &Path, quality: Option<&str>) {
    let files = files_under(out);
    if verbose() {
        for f in &files {
            let size = std::fs::metadata(f).map_or(0, |m| m.len());
            info!("  {} ({})", f.display(), human_bytes(size));
        }
    }
    let quality = quality.map_or(String::new(), |q| format!(" · quality: {q}"));
    info!(
        "wrote {} ({} files){quality} · {:.1} s",
        out.display(),
        files.len(),
        elapsed_s()
    );
}

/// `1234567` → `1.2 MB`.
fn human_bytes(n: u64) -> String {
    match n {
        n if n >= 1_000_000_000 => format!("{:.1} GB", n as f64 / 1e9),
        n if n >= 1_000_000 => format!("{:.1} MB", n as f64 / 1e6),
        n if n >= 1_000 => format!("{:.1} kB", n as f64 / 1e3),
        n => format!("{n} B"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_read_as_people_write_them() {
        assert_eq!(human_bytes(12), "12 B");
        assert_eq!(human_bytes(12_345), "12.3 kB");
        assert_eq!(human_bytes(1_234_567), "1.2 MB");
    }

    #[test]
    fn files_under_a_folder_are_listed_recursively_without_hidden_ones() {
        let dir = tempfile::tempdir().expect("tempdir");
        std::fs::create_dir(dir.path().join("walk-1")).expect("mkdir");
        std::fs::write(dir.path().join("a.csv"), "x").expect("write");
        std::fs::write(dir.path().join("walk-1/b.csv"), "x").expect("write");
        std::fs::write(dir.path().join(".hidden"), "x").expect("write");
        let files = files_under(dir.path());
        assert_eq!(files.len(), 2, "{files:?}");
    }
}
