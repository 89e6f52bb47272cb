//! The measured per-mount parameter sets shipped in `datasets/configs/` (docs/error-models.md):
//! each is accepted by its command and every value it sets reaches the run's `config.json`
//! (a misspelt or misplaced field would be rejected or silently stay at its default).

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every `(path, value)` leaf of a TOML table, paths joined with `.`.
fn leaves(prefix: &str, table: &toml::Table, out: &mut Vec<(String, f64)>) {
    for (key, value) in table {
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value {
            toml::Value::Table(t) => leaves(&path, t, out),
            toml::Value::Float(v) => out.push((path, *v)),
            toml::Value::Integer(v) => out.push((path, *v as f64)),
            other => panic!("{path}: unexpected {other:?}"),
        }
    }
}

/// Runs `args --config FILE --out DIR` and checks `DIR/config.json` against every value of
/// `FILE`.
fn check(file: &str, args: &[&str]) {
    let config = root().join("datasets/configs").join(file);
    let text = std::fs::read_to_string(&config).expect("config file");
    let table: toml::Table = toml::from_str(&text).expect("TOML");
    let mut expected = Vec::new();
    leaves("", &table, &mut expected);
    assert!(expected.len() >= 3, "{file}: {expected:?}");

    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    Command::cargo_bin("footslam")
        .expect("binary")
        .current_dir(root())
        .args(args)
        .arg("--config")
        .arg(&config)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let written: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("config.json")).expect("json"))
            .expect("config.json");
    for (path, value) in expected {
        let got = path
            .split('.')
            .try_fold(&written, |v, key| v.get(key))
            .and_then(serde_json::Value::as_f64)
            .unwrap_or_else(|| panic!("{file}: {path} missing from config.json"));
        assert!(
            (got - value).abs() <= 1e-12 * value.abs().max(1.0),
            "{file}: {path} = {got}, the file sets {value}"
        );
    }
}

fn office(file: &str) -> String {
    Path::new("datasets/office")
        .join(file)
        .to_string_lossy()
        .into_owned()
}

#[test]
fn the_foot_and_phone_sets_configure_learn() {
    for file in ["learn-foot.toml", "learn-phone.toml"] {
        check(
            file,
            &[
                "learn",
                "--steps",
                &office("steps.csv"),
                "--particles",
                "300",
            ],
        );
    }
}

#[test]
fn the_phone_set_configures_track() {
    let (plan, steps) = (office("floor.geojson"), office("steps.csv"));
    check(
        "track-phone.toml",
        &[
            "track", "--plan", &plan, "--steps", &steps, "--start", "0,0,0",
        ],
    );
}
