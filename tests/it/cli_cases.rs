//! The harness of the CLI's bad-input tables (`tests/it/bad_input.rs`,
//! `tests/it/silent_wrongs.rs`): a case is a command line that must fail (or warn) with words
//! its stderr must hold, never panic, and write nothing when it fails.
//!
//! A module of the fast tests' binary (`tests/it/main.rs`): each table uses some of it.
#![allow(dead_code)]

use assert_cmd::Command;
use std::path::{Path, PathBuf};

pub fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

pub fn bundled(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("datasets/tower")
        .join(name)
}

/// Rewrites each data row of a CSV file with `f` (the header kept).
pub fn rewrite(from: &Path, to: &Path, f: impl Fn(&str) -> String) {
    let text = std::fs::read_to_string(from).expect("read");
    let mut lines = text.lines();
    let mut out = format!("{}\n", lines.next().expect("header"));
    for line in lines {
        out.push_str(&f(line));
        out.push('\n');
    }
    std::fs::write(to, out).expect("write");
}

/// Replaces field `i` of a CSV row.
pub fn with_field(line: &str, i: usize, value: impl Fn(&str) -> String) -> String {
    let mut fields: Vec<String> = line.split(',').map(str::to_owned).collect();
    fields[i] = value(&fields[i]);
    fields.join(",")
}

/// One case: arguments (`{dir}` is replaced by the scratch folder), whether the command
/// must fail, and words its stderr must hold.
pub struct Case {
    pub name: &'static str,
    pub args: Vec<String>,
    pub fails: bool,
    pub says: &'static [&'static str],
}

/// Runs `case` (with `--out out` unless it is `eval` or gives its own) and checks its exit
/// status, that it did not panic, its message's key words, and no outputs on failure.
pub fn run_case(case: &Case, out: &Path) {
    let mut cmd = footslam();
    cmd.args(&case.args);
    if case.args[0] != "eval" && !case.args.iter().any(|a| a == "--out") {
        cmd.arg("--out").arg(out);
    }
    let output = cmd.output().expect("run");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(
        output.status.success(),
        !case.fails,
        "{}: exit {:?}, stderr: {stderr}",
        case.name,
        output.status.code()
    );
    assert!(!stderr.contains("panicked"), "{}: {stderr}", case.name);
    for word in case.says {
        assert!(
            stderr.contains(word),
            "{}: expected `{word}` in: {stderr}",
            case.name
        );
    }
    if case.fails {
        assert!(!out.exists(), "{}: no outputs on failure", case.name);
    }
}
