//! `footslam eval --waypoints`: errors at sparse ground-truth points, with dead reckoning
//! started at the first waypoint for comparison.

use assert_cmd::Command;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write");
    p
}

#[test]
fn errors_at_waypoints_and_dead_reckoning_from_the_first() {
    let dir = tempfile::tempdir().expect("tempdir");
    let t0 = 1_574_000_000.0;
    // A walker goes north from (10, 5) at 1 m/s: steps of 1 m each second, heading π/2.
    let mut steps = String::from("t,length,dheading,dz,heading\n");
    let mut track = String::from("t,x,y\n");
    for k in 1..=10 {
        let t = t0 + f64::from(k);
        steps.push_str(&format!("{t},1.0,0.0,0.0,1.5707963\n"));
        // The track is off by 1 m east.
        track.push_str(&format!("{t},11.0,{}\n", 5.0 + f64::from(k)));
    }
    let steps = write(dir.path(), "steps.csv", &steps);
    let track = write(dir.path(), "track.csv", &track);
    let waypoints = write(
        dir.path(),
        "waypoints.csv",
        &format!(
            "t,x,y\n{t0},10,5\n{},10,10\n{},10,15\n",
            t0 + 5.0,
            t0 + 10.0
        ),
    );
    let out = footslam()
        .args(["eval", "--json", "--track"])
        .arg(&track)
        .arg("--waypoints")
        .arg(&waypoints)
        .arg("--steps")
        .arg(&steps)
        .assert()
        .success();
    let v: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).expect("json");
    // The first waypoint is the walk's start, one step (1 s) before the track's first row:
    // held at that row (1 m east, 1 m north: 1.41 m); the other two are 1 m off.
    assert_eq!(v["track"]["n"], 3);
    assert_eq!(v["track"]["skipped"], 0);
    assert_eq!(v["held"], 1, "{v}");
    assert!(
        (v["track"]["max"].as_f64().expect("max") - 2f64.sqrt()).abs() < 1e-6,
        "{v}"
    );
    assert!(
        (v["track"]["p50"].as_f64().expect("p50") - 1.0).abs() < 1e-6,
        "{v}"
    );
    // Dead reckoning from the first waypoint with the absolute heading is exact.
    assert_eq!(v["dead_reckoning"]["n"], 3);
    assert!(
        v["dead_reckoning"]["max"].as_f64().expect("max") < 1e-3,
        "{v}"
    );
    assert_eq!(v["dead_reckoning_heading"], "absolute");
    assert_eq!(v["waypoints"].as_array().expect("points").len(), 3);
}

#[test]
fn waypoints_on_another_clock_are_a_clear_error() {
    let dir = tempfile::tempdir().expect("tempdir");
    let track = write(dir.path(), "track.csv", "t,x,y\n1,0,0\n2,1,0\n");
    let waypoints = write(dir.path(), "waypoints.csv", "t,x,y\n1000,0,0\n");
    footslam()
        .args(["eval", "--track"])
        .arg(&track)
        .arg("--waypoints")
        .arg(&waypoints)
        .assert()
        .failure()
        .stderr(predicates::str::contains("same clock"));
    footslam()
        .args(["eval", "--track"])
        .arg(&track)
        .assert()
        .failure()
        .stderr(predicates::str::contains("--truth"));
}

/// Pixels of `png` within 40 of colour `rgb` in every channel (thin lines are anti-aliased).
fn pixels_of(png: &Path, rgb: [u8; 3]) -> usize {
    let img = image::open(png).expect("a PNG").to_rgba8();
    img.pixels()
        .filter(|p| (0..3).all(|i| p.0[i].abs_diff(rgb[i]) <= 40))
        .count()
}

#[test]
fn picture_draws_the_track_over_the_waypoints() {
    let dir = tempfile::tempdir().expect("tempdir");
    let t0 = 1_574_000_000.0;
    let mut track = String::from("t,x,y\n");
    for k in 0..=20 {
        track.push_str(&format!(
            "{},{},{}\n",
            t0 + f64::from(k),
            11.0,
            5.0 + f64::from(k)
        ));
    }
    let track = write(dir.path(), "track.csv", &track);
    let waypoints = write(
        dir.path(),
        "waypoints.csv",
        &format!(
            "t,x,y\n{t0},10,5\n{},10,15\n{},10,25\n",
            t0 + 10.0,
            t0 + 20.0
        ),
    );
    // `eval --track T --waypoints W [EXTRA…]`.
    let eval = |extra: &[&std::ffi::OsStr]| {
        footslam()
            .args(["eval", "--track"])
            .arg(&track)
            .arg("--waypoints")
            .arg(&waypoints)
            .args(extra)
            .assert()
    };
    let png = dir.path().join("eval.png");
    eval(&["--picture".as_ref(), png.as_os_str()]).success();
    // The track in red, the waypoints joined in blue (dashed), both in the key.
    assert!(pixels_of(&png, [178, 24, 43]) > 200, "no track");
    assert!(pixels_of(&png, [33, 102, 172]) > 20, "no waypoints");
    // With a plan: one panel, the plan under both.
    let plan = write(
        dir.path(),
        "plan.geojson",
        r#"{"type":"FeatureCollection","origin":{"lat":0.0,"lon":0.0},"features":[{"type":"Feature",
        "properties":{"level":0},"geometry":{"type":"Polygon","coordinates":[[[0.00008,0.0],
        [0.00013,0.0],[0.00013,0.00027],[0.00008,0.00027],[0.00008,0.0]]]}}]}"#,
    );
    let png = dir.path().join("eval-plan.png");
    eval(&[
        "--plan".as_ref(),
        plan.as_os_str(),
        "--picture".as_ref(),
        png.as_os_str(),
    ])
    .success();
    assert!(pixels_of(&png, [178, 24, 43]) > 200, "no track on the plan");
    // --plan without --picture says what it is for.
    eval(&["--plan".as_ref(), plan.as_os_str()])
        .failure()
        .stderr(predicates::str::contains("--picture"));
}
