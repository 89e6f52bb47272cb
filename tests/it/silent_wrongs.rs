//! Cases that once exited 0 with a wrong answer (issue 34 items 5, 6 and 11): each must now
//! fail with a message naming the cause and the way out, or warn, end to end through the
//! CLI. The IMU cases rewrite the test excerpts (`tests/data/`, see its README).

use crate::cli_cases::{Case, bundled, footslam, rewrite, run_case, with_field};
use std::path::{Path, PathBuf};

fn excerpt(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The phone excerpt with each row's fields rewritten by `f` (`t,ax,…,qx,qy,qz,qw`).
fn phone(to: &Path, f: impl Fn(&mut Vec<String>)) {
    rewrite(&excerpt("phone_excerpt.csv"), to, |l| {
        let mut fields: Vec<String> = l.split(',').map(str::to_owned).collect();
        f(&mut fields);
        fields.join(",")
    });
}

fn number(s: &str) -> f64 {
    s.parse().expect("number")
}

#[test]
fn recordings_in_the_wrong_scale_or_order_are_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let foot = excerpt("foot_excerpt.csv");
    rewrite(&foot, &d.join("foot_ms.csv"), |l| {
        with_field(l, 0, |t| format!("{}", number(t) * 1000.0))
    });
    // Accelerometer and gyroscope columns swapped (the header kept).
    rewrite(&foot, &d.join("swapped.csv"), |l| {
        let f: Vec<&str> = l.split(',').collect();
        [f[0], f[4], f[5], f[6], f[1], f[2], f[3]].join(",")
    });
    let t0 = 1_574_563_619.0;
    phone(&d.join("phone_x2.csv"), |f| {
        f[0] = format!("{}", t0 + (number(&f[0]) - t0) * 2.0)
    });
    phone(&d.join("conjugated.csv"), |f| {
        for q in &mut f[10..13] {
            *q = format!("{}", -number(q));
        }
    });
    phone(&d.join("wxyz.csv"), |f| f[10..14].rotate_right(1));

    let p = |name: &str| d.join(name).display().to_string();
    let s = |x: &str| x.to_owned();
    let steps = |imu: &str, mount: &str, extra: &[&str]| {
        let mut a = vec![
            s("steps"),
            s("--imu"),
            imu.to_owned(),
            s("--mount"),
            s(mount),
        ];
        a.extend(extra.iter().map(|x| s(x)));
        a
    };
    let cases = [
        Case {
            name: "IMU times in milliseconds",
            args: steps(&p("foot_ms.csv"), "foot", &[]),
            fails: true,
            says: &["foot_ms.csv", "0.2 Hz", "milliseconds"],
        },
        Case {
            name: "accelerometer and gyroscope columns swapped",
            args: steps(&p("swapped.csv"), "foot", &[]),
            fails: true,
            says: &["swapped.csv", "swapped"],
        },
        Case {
            name: "--accel-unit g on a file in m/s²",
            args: steps(&foot.display().to_string(), "foot", &["--accel-unit", "g"]),
            fails: true,
            says: &["leave out --accel-unit g"],
        },
        Case {
            name: "phone timestamps doubled",
            args: steps(&p("phone_x2.csv"), "phone", &[]),
            fails: true,
            says: &["phone_x2.csv", "2.1", "timestamps are not in seconds"],
        },
        Case {
            name: "the quaternion conjugated",
            args: steps(&p("conjugated.csv"), "phone", &[]),
            fails: true,
            says: &["conjugated.csv", "negate the qx, qy, qz columns"],
        },
        Case {
            name: "the quaternion written w, x, y, z",
            args: steps(&p("wxyz.csv"), "phone", &[]),
            fails: true,
            says: &["wxyz.csv", "w, x, y, z", "reorder the columns"],
        },
    ];
    for (i, case) in cases.iter().enumerate() {
        run_case(case, &d.join(format!("out-{i}")));
    }
    // As logged, the excerpt reads with no warning on the frame.
    let out = d.join("as-logged");
    let run = footslam()
        .args(["steps", "--mount", "phone", "--imu"])
        .arg(excerpt("phone_excerpt.csv"))
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run");
    assert!(run.status.success());
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(!stderr.contains("quaternion"), "{stderr}");
}

/// The features of a map file, parsed.
fn features(path: &Path) -> Vec<serde_json::Value> {
    let map: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("map")).expect("json");
    map["features"].as_array().expect("features").clone()
}

#[test]
fn merge_weights_are_relative() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    footslam()
        .args(["learn", "--particles", "300", "--steps"])
        .arg(bundled("../office/steps.csv"))
        .arg("--out")
        .arg(d.join("learn"))
        .assert()
        .success();
    let map = d.join("learn/map.geojson");
    let merge = |weights: &str, out: &str| {
        footslam()
            .arg("merge")
            .arg(&map)
            .arg(&map)
            .args(["--weights", weights, "--out"])
            .arg(d.join(out))
            .assert()
            .success();
        features(&d.join(out))
    };
    let unit = merge("1,1", "unit.geojson");
    let small = merge("0.3,0.3", "small.geojson");
    assert_eq!(small.len(), unit.len(), "0.3,0.3 keeps every hexagon");
    assert_eq!(small, unit);
    let heavy = merge("1e12,1", "heavy.geojson");
    assert_eq!(heavy.len(), unit.len());
    let largest = heavy
        .iter()
        .flat_map(|f| {
            f["properties"]["counts"]
                .as_array()
                .expect("counts")
                .clone()
        })
        .map(|c| c.as_u64().expect("count"))
        .max()
        .expect("counts");
    assert!(largest < 1000, "no count saturates: {largest}");
}

#[test]
fn flags_and_values_that_would_be_ignored_or_misread_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let office = bundled("../office/steps.csv");
    let truth = bundled("../office/truth.csv");
    // A track 1e300 m east; a truth that never moves.
    rewrite(&truth, &d.join("far.csv"), |l| {
        with_field(l, 1, |x| format!("{}", number(x) + 1e300))
    });
    rewrite(&truth, &d.join("still.csv"), |l| {
        with_field(&with_field(l, 1, |_| "1.0".into()), 2, |_| "2.0".into())
    });
    // Headings in degrees.
    let text = std::fs::read_to_string(&office).expect("steps");
    let mut degrees = String::from("t,length,dheading,dz,heading\n");
    for (i, l) in text.lines().skip(1).enumerate() {
        degrees.push_str(&format!("{l},{}\n", (i * 7) % 360));
    }
    std::fs::write(d.join("degrees.csv"), degrees).expect("degrees");
    std::fs::write(d.join("gps.csv"), "t,lat,lon,accuracy\n1.0,48.1,11.5,5\n").expect("gps");
    std::fs::write(
        d.join("wide.csv"),
        format!("t,lat,lon,accuracy\n1.0,48.1,11.5,1{}\n", "0".repeat(308)),
    )
    .expect("gps");

    let p = |name: &str| d.join(name).display().to_string();
    let s = |x: &str| x.to_owned();
    let (office, truth) = (office.display().to_string(), truth.display().to_string());
    let cases = [
        Case {
            name: "eval: coordinates of 1e300 m",
            args: vec![
                s("eval"),
                s("--truth"),
                truth.clone(),
                s("--track"),
                p("far.csv"),
            ],
            fails: true,
            says: &["far.csv:2", "1e300", "at most 1000 km"],
        },
        Case {
            name: "eval: a rigid alignment on a truth that stays in one place",
            args: vec![
                s("eval"),
                s("--truth"),
                p("still.csv"),
                s("--track"),
                truth.clone(),
                s("--align"),
                s("rigid"),
            ],
            fails: true,
            says: &["within 0.00 m", "any track would fit it"],
        },
        Case {
            name: "eval: no reference",
            args: vec![s("eval"), s("--track"), truth],
            fails: true,
            says: &["--truth", "--waypoints"],
        },
        Case {
            name: "simulate: --laps on the tower",
            args: vec![
                s("simulate"),
                s("--building"),
                s("tower"),
                s("--laps"),
                s("3"),
            ],
            fails: true,
            says: &["--laps applies to --building office or campus, not to tower"],
        },
        Case {
            name: "simulate: --floors on the office",
            args: vec![s("simulate"), s("--floors"), s("3")],
            fails: true,
            says: &["--floors applies to --building tower"],
        },
        Case {
            name: "simulate: --tour on the office",
            args: vec![s("simulate"), s("--tour"), s("survey")],
            fails: true,
            says: &["--tour applies to --building tower"],
        },
        Case {
            name: "learn: --gps-t0 with CSV fixes",
            args: vec![
                s("learn"),
                s("--steps"),
                office.clone(),
                s("--gps"),
                p("gps.csv"),
                s("--gps-t0"),
                s("1700000000"),
            ],
            fails: true,
            says: &["--gps-t0", "no walk has a GPX file"],
        },
        Case {
            name: "learn: a heading column in degrees",
            args: vec![s("learn"), s("--steps"), p("degrees.csv")],
            fails: true,
            says: &["degrees.csv:", "absolute heading", "degrees?"],
        },
        Case {
            name: "a GPS accuracy of 1e308 m, printed short",
            args: vec![
                s("learn"),
                s("--steps"),
                office.clone(),
                s("--gps"),
                p("wide.csv"),
            ],
            fails: true,
            says: &["wide.csv:2", "accuracy 1e308 m"],
        },
        Case {
            name: "a GeoJSON plan given as steps",
            args: vec![
                s("learn"),
                s("--steps"),
                bundled("floor.geojson").display().to_string(),
            ],
            fails: true,
            says: &["floor.geojson:1", "this is JSON", "not a CSV table"],
        },
        Case {
            name: "an origin at the pole",
            args: vec![s("simulate"), s("--origin"), s("89.5,0")],
            fails: true,
            says: &["latitude within ±89"],
        },
    ];
    for (i, case) in cases.iter().enumerate() {
        run_case(case, &d.join(format!("out-{i}")));
    }
}

#[test]
fn maps_across_the_antimeridian_read_back() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    footslam()
        .args(["simulate", "--origin", "-16.5,179.99995", "--out"])
        .arg(d.join("sim"))
        .assert()
        .success();
    // Every position written is a WGS84 one, and the toolkit reads its own plan back.
    let text = std::fs::read_to_string(d.join("sim/floor.geojson")).expect("plan");
    assert!(text.contains("-179.99"), "the plan wraps the antimeridian");
    footslam()
        .args(["track", "--online", "--plan"])
        .arg(d.join("sim/floor.geojson"))
        .arg("--steps")
        .arg(d.join("sim/steps.csv"))
        .arg("--out")
        .arg(d.join("track"))
        .assert()
        .success();
}

#[test]
fn importers_drop_a_byte_order_mark_and_never_use_a_cut_last_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let text = std::fs::read_to_string(excerpt("ilc_excerpt.txt")).expect("excerpt");
    // Cut inside the last sensor row: its number still parses.
    let body: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    let last = body.last().expect("rows");
    let cut_at = text.rfind(last).expect("last row") + last.len() - 2;
    std::fs::write(d.join("cut.txt"), format!("\u{feff}{}", &text[..cut_at])).expect("cut");
    let out = footslam()
        .args(["import", "ilc", "--trace"])
        .arg(d.join("cut.txt"))
        .arg("--out")
        .arg(d.join("ilc"))
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("is unterminated (the log was cut off) and was skipped"),
        "{stdout}"
    );
}
