//! Inputs that are each well-formed but wrong together: every case must fail (or warn) with
//! a message naming the files and the way out, and write nothing — never a confident answer
//! with exit 0. One table, run end to end through the CLI on the bundled tower walk.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn bundled(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("datasets/tower")
        .join(name)
}

/// Rewrites each data row of a CSV file with `f` (the header kept).
fn rewrite(from: &Path, to: &Path, f: impl Fn(&str) -> String) {
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
fn with_field(line: &str, i: usize, value: impl Fn(&str) -> String) -> String {
    let mut fields: Vec<String> = line.split(',').map(str::to_owned).collect();
    fields[i] = value(&fields[i]);
    fields.join(",")
}

/// One case: arguments (`{dir}` is replaced by the scratch folder), whether the command
/// must fail, and words its stderr must hold.
struct Case {
    name: &'static str,
    args: Vec<String>,
    fails: bool,
    says: &'static [&'static str],
}

#[test]
fn inputs_wrong_together_fail_or_warn_clearly() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let (plan, steps, wifi) = (
        bundled("floor.geojson"),
        bundled("steps.csv"),
        bundled("wifi.csv"),
    );
    // A radio map of the walk's own building.
    footslam()
        .args(["survey", "--plan"])
        .arg(&plan)
        .arg("--steps")
        .arg(&steps)
        .arg("--wifi")
        .arg(&wifi)
        .arg("--out")
        .arg(d.join("survey"))
        .assert()
        .success();
    // The same walk's log with every BSSID renamed: another building's access points.
    rewrite(&wifi, &d.join("renamed.csv"), |l| {
        with_field(l, 1, |b| b.replace("02:00", "0a:ff"))
    });
    // A quarter of the scans renamed: mostly another building.
    rewrite(&wifi, &d.join("mostly_renamed.csv"), |l| {
        let t: f64 = l.split(',').next().and_then(|t| t.parse().ok()).expect("t");
        if (t as u64).is_multiple_of(4) {
            l.to_owned()
        } else {
            with_field(l, 1, |b| b.replace("02:00", "0a:ff"))
        }
    });
    // The log on another clock.
    rewrite(&wifi, &d.join("late.csv"), |l| {
        with_field(l, 0, |t| format!("{}", t.parse::<f64>().expect("t") + 1e5))
    });
    // The steps without their height changes.
    rewrite(&steps, &d.join("flat.csv"), |l| {
        let f: Vec<&str> = l.split(',').collect();
        f[..3].join(",")
    });
    let text = std::fs::read_to_string(d.join("flat.csv")).expect("flat");
    std::fs::write(
        d.join("flat.csv"),
        text.replacen("t,length,dheading,dz", "t,length,dheading", 1),
    )
    .expect("header");

    let p = |p: &Path| p.display().to_string();
    let s = |x: &str| x.to_owned();
    let radiomap = p(&d.join("survey/radiomap.geojson"));
    let track = |steps: &str, wifi: &str| {
        vec![
            s("track"),
            s("--plan"),
            p(&plan),
            s("--steps"),
            s(steps),
            s("--radiomap"),
            radiomap.clone(),
            s("--wifi"),
            s(wifi),
        ]
    };
    let survey = |steps: &str, wifi: &str| {
        vec![
            s("survey"),
            s("--plan"),
            p(&plan),
            s("--steps"),
            s(steps),
            s("--wifi"),
            s(wifi),
        ]
    };
    let (steps_s, flat) = (p(&steps), p(&d.join("flat.csv")));
    let cases = [
        Case {
            name: "radio map and WiFi log share no access point",
            args: track(&steps_s, &p(&d.join("renamed.csv"))),
            fails: true,
            says: &["renamed.csv", "radiomap.geojson", "none of the log's"],
        },
        Case {
            name: "most scans hear no access point of the map",
            args: track(&steps_s, &p(&d.join("mostly_renamed.csv"))),
            fails: false,
            says: &["warning", "mostly_renamed.csv", "hear an access point"],
        },
        Case {
            name: "track: WiFi log on another clock",
            args: track(&steps_s, &p(&d.join("late.csv"))),
            fails: true,
            says: &["late.csv", "no scan falls within the walk's time span"],
        },
        Case {
            name: "survey: WiFi log on another clock",
            args: survey(&steps_s, &p(&d.join("late.csv"))),
            fails: true,
            says: &["late.csv", "one clock"],
        },
        Case {
            name: "fingerprint: radio map of another building",
            args: vec![
                s("fingerprint"),
                s("--radiomap"),
                radiomap.clone(),
                s("--wifi"),
                p(&d.join("renamed.csv")),
            ],
            fails: true,
            says: &["renamed.csv", "access point"],
        },
        Case {
            name: "track: steps without dz on a plan of three floors",
            args: vec![
                s("track"),
                s("--plan"),
                p(&plan),
                s("--steps"),
                flat.clone(),
            ],
            fails: true,
            says: &["flat.csv", "dz", "3 levels", "--one-floor"],
        },
        Case {
            name: "survey: steps without dz on a plan of three floors",
            args: survey(&flat, &p(&wifi)),
            fails: true,
            says: &["flat.csv", "dz", "--one-floor"],
        },
        Case {
            name: "track: steps without dz, the walk said to stay on one floor",
            args: vec![
                s("track"),
                s("--plan"),
                p(&plan),
                s("--steps"),
                flat,
                s("--one-floor"),
            ],
            fails: false,
            says: &[],
        },
    ];
    for (i, case) in cases.iter().enumerate() {
        let out = d.join(format!("out-{i}"));
        let assert = footslam().args(&case.args).arg("--out").arg(&out).assert();
        let output = assert.get_output();
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
        assert_eq!(out.exists(), !case.fails, "{}: outputs", case.name);
    }
}
