//! The source tree stays one a newcomer can hold in their head (issue 15): no source file
//! over `MAX_LINES` lines, and no import cycle between files or between top-level modules
//! (`scripts/import_cycles.py`, which CI's Python runs). The integration tests are two
//! binaries (`tests/it/`, `tests/accuracy/`, docs/testing.md) and every test file is a
//! module of one of them.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The longest source file allowed, in lines ("about 600").
const MAX_LINES: usize = 650;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("read src") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn no_source_file_is_over_the_limit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    assert!(files.len() > 50, "found only {} source files", files.len());
    let long: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).expect("read").lines().count();
            (lines > MAX_LINES).then(|| format!("{} ({lines} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "over {MAX_LINES} lines: {long:?}");
}

#[test]
fn no_import_cycles() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Command::new("python3")
        .arg("scripts/import_cycles.py")
        .current_dir(root)
        .output()
        .expect("python3 runs scripts/import_cycles.py");
    assert!(
        out.status.success(),
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The command line's commands only read, call the library and write: each `run` (and
/// `run_*`) function of `src/cli/` is at most this many lines.
const MAX_RUN_LINES: usize = 60;

#[test]
fn cli_run_functions_are_short() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src/cli"), &mut files);
    let mut long = Vec::new();
    let mut found = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).expect("read");
        let mut start: Option<(usize, &str)> = None;
        for (i, line) in text.lines().enumerate() {
            let is_run = ["pub fn run", "fn run_", "pub fn run_", "pub(super) fn run"]
                .iter()
                .any(|p| line.starts_with(p));
            if start.is_none() && is_run {
                start = Some((i, line));
            } else if let Some((first, head)) = start
                && line == "}"
            {
                found += 1;
                let lines = i - first + 1;
                if lines > MAX_RUN_LINES {
                    long.push(format!("{}: `{head}` ({lines} lines)", file.display()));
                }
                start = None;
            }
        }
    }
    assert!(found >= 10, "found only {found} run functions");
    assert!(long.is_empty(), "over {MAX_RUN_LINES} lines: {long:?}");
}

/// The longest function of a face (`src/cli/`, `python/src/`), in lines: a screen or
/// less, since the faces only translate arguments into a job's request and its answer into
/// outputs (issue 36).
const MAX_FACE_FUNCTION_LINES: usize = 80;

/// The functions of `text` (at any indentation) and their lengths in lines, from the line
/// that names them to their closing brace at the same indentation.
fn function_lengths(text: &str) -> Vec<(String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        let trimmed = line.trim_start();
        let indent = &line[..line.len() - trimmed.len()];
        let head = ["fn ", "pub fn ", "pub(crate) fn ", "pub(super) fn "]
            .iter()
            .find_map(|p| trimmed.strip_prefix(p));
        let Some(head) = head else {
            i += 1;
            continue;
        };
        let name: String = head
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // The signature ends at `{` (a body) or `;` (a declaration).
        let mut j = i;
        while j < lines.len() && !lines[j].ends_with('{') && !lines[j].ends_with(';') {
            j += 1;
        }
        if j == lines.len() || lines[j].ends_with(';') {
            i = j + 1;
            continue;
        }
        let close = format!("{indent}}}");
        let end = (j..lines.len()).find(|&k| lines[k] == close).unwrap_or(j);
        found.push((name, end - i + 1));
        i = end + 1;
    }
    found
}

#[test]
fn face_functions_fit_a_screen() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    rust_files(&root.join("src/cli"), &mut files);
    rust_files(&root.join("python/src"), &mut files);
    let mut long = Vec::new();
    let mut counted = 0;
    for file in &files {
        let text = std::fs::read_to_string(file).expect("read");
        for (name, lines) in function_lengths(&text) {
            counted += 1;
            if lines > MAX_FACE_FUNCTION_LINES {
                long.push(format!("{}: `{name}` ({lines} lines)", file.display()));
            }
        }
    }
    assert!(counted > 100, "found only {counted} functions");
    assert!(
        long.is_empty(),
        "over {MAX_FACE_FUNCTION_LINES} lines: {long:?}"
    );
}

#[test]
fn function_lengths_count_from_the_name_to_the_closing_brace() {
    let text = "fn a() {\n    x;\n}\n\nimpl A {\n    pub fn b(\n        y: u8,\n    ) -> u8 {\n        y\n    }\n    fn c();\n}\n";
    assert_eq!(
        function_lengths(text),
        vec![("a".to_string(), 3), ("b".to_string(), 5)]
    );
}

/// `Cargo.toml` turns off the discovery of test files (`autotests = false`): a file in
/// `tests/` that is not a module of the two test binaries would never run.
#[test]
fn every_test_file_is_a_module_of_a_tier() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let stray: Vec<PathBuf> = std::fs::read_dir(&root)
        .expect("read tests")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .collect();
    assert!(
        stray.is_empty(),
        "make these modules of tests/it/ (fast) or tests/accuracy/ (slow, statistical): {stray:?}"
    );
    let mut modules = 0;
    for tier in ["it", "accuracy"] {
        let dir = root.join(tier);
        let main = std::fs::read_to_string(dir.join("main.rs")).expect("read main.rs");
        let mut files = Vec::new();
        rust_files(&dir, &mut files);
        for file in files {
            let name = file
                .file_stem()
                .expect("stem")
                .to_string_lossy()
                .into_owned();
            if name == "main" {
                continue;
            }
            modules += 1;
            assert!(
                main.lines().any(|l| l == format!("mod {name};")),
                "{}: no `mod {name};` in tests/{tier}/main.rs, so it never runs",
                file.display()
            );
        }
    }
    assert!(modules >= 30, "found only {modules} test modules");
}
