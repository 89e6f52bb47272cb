//! `footslam steps` on bad recordings: a clear error naming the file, line and problem, no
//! output folder, never a panic.

use assert_cmd::Command;
use predicates::prelude::*;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

const HEAD: &str = "t,ax,ay,az,gx,gy,gz";

/// Runs `steps` on `text` as imu.csv with both mounts; asserts failure with every `expected`
/// piece in the message and no output folder.
fn refuses(dir: &Path, name: &str, text: &str, expected: &[&str]) {
    let imu = dir.join(format!("{name}.csv"));
    std::fs::write(&imu, text).expect("write");
    for mount in ["foot", "phone"] {
        let out = dir.join(format!("{name}-{mount}"));
        let mut assert = footslam()
            .args(["steps", "--mount", mount, "--imu"])
            .arg(&imu)
            .arg("--out")
            .arg(&out)
            .assert()
            .failure()
            .stderr(predicate::str::contains(format!("{name}.csv")))
            .stderr(predicate::str::contains("panicked").not());
        for e in expected {
            assert = assert.stderr(predicate::str::contains(*e));
        }
        drop(assert);
        assert!(!out.exists(), "{name}: no output on failure");
    }
}

#[test]
fn bad_recordings_are_refused_with_file_line_and_reason() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let row = |t: f64| format!("{t},0.1,0.2,9.8,0.01,0.0,0.0\n");
    refuses(d, "empty", "", &["empty"]);
    refuses(d, "header_only", &format!("{HEAD}\n"), &["no samples"]);
    refuses(
        d,
        "unsorted",
        &format!("{HEAD}\n{}{}{}", row(1.0), row(2.0), row(1.5)),
        &[":4", "sorted"],
    );
    refuses(
        d,
        "nan",
        &format!("{HEAD}\n{}2,0.1,NaN,9.8,0,0,0\n", row(1.0)),
        &[":3", "ay"],
    );
    refuses(d, "no_gyro", "t,ax,ay,az\n0,0,0,9.8\n", &["gx"]);
    refuses(
        d,
        "truncated",
        &format!("{HEAD}\n{}{}2.0,0.1,0.2", row(1.0), row(1.5)),
        &[":4"],
    );
    let in_g: String = (0..20)
        .map(|i| format!("{i},0.01,0.02,1.0,0.01,0,0\n"))
        .collect();
    refuses(
        d,
        "in_g",
        &format!("{HEAD}\n{in_g}"),
        &["in g?", "--accel-unit g"],
    );
    refuses(
        d,
        "absurd",
        &format!("{HEAD}\n{}2,0.1,0.2,9.8,500,0,0\n", row(1.0)),
        &[":3", "angular rate"],
    );
}

#[test]
fn a_missing_file_or_mount_is_a_usage_error() {
    footslam()
        .args(["steps", "--mount", "foot", "--imu", "/nonexistent/imu.csv"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("does not exist"));
    footslam()
        .args(["steps", "--mount", "wrist", "--imu", "imu.csv"])
        .assert()
        .failure()
        .stderr(predicate::str::contains("foot"));
}

#[test]
fn a_phone_excerpt_gives_steps_with_absolute_heading_a_summary_and_a_picture() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    let imu = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/phone_excerpt.csv");
    footslam()
        .args(["steps", "--mount", "phone", "--imu"])
        .arg(&imu)
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("steps"));
    for name in ["steps.csv", "summary.json", "steps.png", "config.json"] {
        assert!(out.join(name).is_file(), "{name}");
    }
    let steps = footslam::io::read_steps(&out.join("steps.csv")).expect("steps.csv");
    // 28 steps by hand count (tests/data/README.md).
    assert!((25..=31).contains(&steps.len()), "{}", steps.len());
    assert!(steps.steps().iter().all(|s| s.heading.is_some()));
    // The magnetometer gives each step's field: an Earth-like magnitude, dipping down in the
    // northern hemisphere (the excerpt is from Europe).
    let (_, field) =
        footslam::io::read_steps_with_field(&out.join("steps.csv")).expect("steps.csv");
    let field = field.expect("a field column");
    assert_eq!(field.observed(), steps.len());
    assert_eq!(field.with_vertical(), steps.len());
    for f in field.fields().iter().flatten() {
        assert!((20.0..80.0).contains(&f.magnitude), "{f:?}");
        assert!(f.vertical.is_some_and(|v| v < 0.0), "{f:?}");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("read"))
            .expect("json");
    assert_eq!(summary["heading_source"], "rotation_vector");
    assert_eq!(summary["mount"], "phone");
    assert_eq!(summary["steps"], steps.len());
    assert_eq!(summary["steps_with_field"], steps.len());
    assert!(summary["sampling"]["rate_hz"].as_f64().expect("rate") > 40.0);
    // The config written beside the outputs repeats the run.
    let again = dir.path().join("again");
    footslam()
        .args(["steps", "--mount", "phone", "--imu"])
        .arg(&imu)
        .arg("--config")
        .arg(out.join("config.json"))
        .arg("--out")
        .arg(&again)
        .assert()
        .success();
    assert_eq!(
        std::fs::read(out.join("steps.csv")).expect("a"),
        std::fs::read(again.join("steps.csv")).expect("b")
    );
}

#[test]
fn a_foot_excerpt_gives_strides_without_absolute_heading() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("run");
    let imu = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/foot_excerpt.csv");
    footslam()
        .args(["steps", "--mount", "foot", "--imu"])
        .arg(&imu)
        .arg("--out")
        .arg(&out)
        .assert()
        .success()
        .stdout(predicate::str::contains("strides").and(predicate::str::contains("quality: ok")));
    let steps = footslam::io::read_steps(&out.join("steps.csv")).expect("steps.csv");
    // The excerpt's truth (tests/data/README.md): three strides of 1.11–1.26 m after a stand.
    assert!((3..=4).contains(&steps.len()), "{}", steps.len());
    assert!(steps.steps().iter().all(|s| s.heading.is_none()));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("read"))
            .expect("json");
    assert_eq!(summary["heading_source"], "gyroscope");
    assert_eq!(summary["mount"], "foot");
    assert!(out.join("steps.png").is_file());
}

#[test]
fn the_wrong_mount_is_said_not_swallowed() {
    let dir = tempfile::tempdir().expect("tempdir");
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    for (file, mount, hint) in [
        ("foot_excerpt.csv", "phone", "--mount foot"),
        ("phone_excerpt.csv", "foot", "--mount phone"),
    ] {
        let out = dir.path().join(mount);
        footslam()
            .args(["steps", "--mount", mount, "--imu"])
            .arg(data.join(file))
            .arg("--out")
            .arg(&out)
            .assert()
            .success()
            .stderr(predicate::str::contains("warning").and(predicate::str::contains(hint)));
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("read"))
                .expect("json");
        assert_eq!(summary["warnings"].as_array().expect("warnings").len(), 1);
        // The warning makes the steps' verdict doubtful, in summary.json and on the terminal.
        assert_eq!(summary["quality"]["verdict"], "doubtful");
        assert_eq!(summary["quality"]["reasons"][0]["code"], "detector_warning");
    }
}

/// `text` of a CSV with the columns `negate` multiplied by -1 and `t` by `time_scale`.
fn altered(path: &Path, negate: &[&str], time_scale: f64) -> String {
    let text = std::fs::read_to_string(path).expect("excerpt");
    let mut lines = text.lines();
    let head: Vec<&str> = lines.next().expect("header").split(',').collect();
    let mut out = head.join(",") + "\n";
    for line in lines {
        let row: Vec<String> = line
            .split(',')
            .zip(&head)
            .map(|(v, h)| {
                let x: f64 = v.parse().expect("number");
                match *h {
                    "t" => format!("{:.5}", x * time_scale),
                    h if negate.contains(&h) => format!("{}", -x),
                    _ => v.to_string(),
                }
            })
            .collect();
        out += &(row.join(",") + "\n");
    }
    out
}

/// `footslam steps --mount MOUNT [extra…] --imu IMU --out OUT`, asserted on.
fn steps(mount: &str, extra: &[&str], imu: &Path, out: &Path) -> assert_cmd::assert::Assert {
    footslam()
        .args(["steps", "--mount", mount])
        .args(extra)
        .arg("--imu")
        .arg(imu)
        .arg("--out")
        .arg(out)
        .assert()
}

#[test]
fn a_mirrored_gyroscope_or_a_wrong_time_base_is_detected_with_the_way_out() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (d, data) = (
        dir.path(),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data"),
    );
    let write = |name: &str, excerpt: &str, negate: &[&str], time_scale: f64| {
        let path = d.join(name);
        std::fs::write(&path, altered(&data.join(excerpt), negate, time_scale)).expect("w");
        path
    };
    // A foot IMU whose gyroscope y axis is inverted: refused, naming the flag.
    let foot = write("foot_flipped.csv", "foot_excerpt.csv", &["gy"], 1.0);
    let out = d.join("foot-out");
    steps("foot", &[], &foot, &out)
        .failure()
        .stderr(predicate::str::contains("foot_flipped.csv"))
        .stderr(predicate::str::contains("--gyro-flip y"));
    assert!(!out.exists());
    // With the flag it gives the same strides as the recording as logged.
    let (fixed, plain) = (d.join("fixed"), d.join("plain"));
    steps("foot", &["--gyro-flip", "y"], &foot, &fixed).success();
    steps("foot", &[], &data.join("foot_excerpt.csv"), &plain).success();
    let read = |d: &Path| std::fs::read_to_string(d.join("steps.csv")).expect("steps");
    assert_eq!(read(&fixed), read(&plain));
    // A phone whose timestamps run three times too slow: the gyroscope turns 3× as far as
    // its orientation quaternion.
    let phone = write("phone_slow.csv", "phone_excerpt.csv", &[], 3.0);
    steps("phone", &[], &phone, &d.join("phone-out"))
        .failure()
        .stderr(predicate::str::contains("timestamps are not in seconds"));
    // A phone whose gyroscope x axis is inverted: its heading comes from the quaternion, so
    // a warning, not an error.
    let mirrored = write("phone_mirrored.csv", "phone_excerpt.csv", &["gx"], 1.0);
    steps("phone", &[], &mirrored, &d.join("mirrored-out"))
        .success()
        .stderr(predicate::str::contains("x axis looks mirrored"));
}
