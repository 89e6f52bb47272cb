//! A batch learned in shards (`learn --walks M --shard I/N [--previous …]`, then `merge`),
//! as batch schedulers without Python run it, gives the unsharded batch's maps and tracks
//! byte for byte; a shard run again rewrites the same files; a pass that misses a walk of
//! the previous pass says which.

use assert_cmd::Command;
use std::path::Path;

fn footslam() -> Command {
    Command::cargo_bin("footslam").expect("binary")
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn shard(d: &Path, index: usize, out: &str, previous: &[&str]) -> assert_cmd::assert::Assert {
    let mut cmd = footslam();
    cmd.args(["learn", "--particles", "400", "--walks"])
        .arg(d.join("walks.csv"))
        .args(["--shard", &format!("{}/2", index + 1), "--out"])
        .arg(d.join(out));
    for p in previous {
        cmd.arg("--previous").arg(d.join(p));
    }
    cmd.assert()
}

#[test]
fn shards_and_merge_give_the_batch() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    for s in [31u64, 32, 33] {
        footslam()
            .args(["simulate", "--building", "office", "--laps", "1", "--seed"])
            .arg(s.to_string())
            .arg("--out")
            .arg(d.join(format!("sim-{s}")))
            .assert()
            .success();
    }
    let rows = [31, 32, 33].map(|s| format!("sim-{s}/steps.csv,\"0,0,0\"\n"));
    std::fs::write(
        d.join("walks.csv"),
        format!("steps,start\n{}", rows.concat()),
    )
    .expect("w");
    footslam()
        .args(["learn", "--particles", "400", "--walks"])
        .arg(d.join("walks.csv"))
        .arg("--out")
        .arg(d.join("batch"))
        .assert()
        .success();

    // The default configuration runs two FeetSLAM passes after the first.
    shard(d, 0, "p0-a", &[]).success();
    shard(d, 1, "p0-b", &[]).success();
    shard(d, 0, "p1-a", &["p0-a", "p0-b"]).success();
    shard(d, 1, "p1-b", &["p0-a", "p0-b"]).success();
    shard(d, 0, "p2-a", &["p1-a", "p1-b"]).success();
    shard(d, 1, "p2-b", &["p1-a", "p1-b"]).success();
    // Shard 0 holds walks 1 and 3, shard 1 walk 2.
    assert!(d.join("p2-a/walk-1/map.geojson").is_file());
    assert!(d.join("p2-a/walk-3/map.geojson").is_file());
    assert!(d.join("p2-b/walk-2/map.geojson").is_file());
    assert!(!d.join("p2-b/walk-1").exists());
    footslam()
        .arg("merge")
        .arg(d.join("p2-a/walk-1/map.geojson"))
        .arg(d.join("p2-b/walk-2/map.geojson"))
        .arg(d.join("p2-a/walk-3/map.geojson"))
        .arg("--out")
        .arg(d.join("merged.geojson"))
        .assert()
        .success();
    assert_eq!(
        read(&d.join("merged.geojson")),
        read(&d.join("batch/merged.geojson")),
        "merged map"
    );
    for (walk, folder) in [(1, "p2-a"), (2, "p2-b"), (3, "p2-a")] {
        for file in ["track.csv", "map.geojson"] {
            let name = format!("walk-{walk}/{file}");
            assert_eq!(
                read(&d.join(folder).join(&name)),
                read(&d.join("batch").join(&name)),
                "{name}"
            );
        }
    }

    // Idempotent: the same shard again rewrites the same files.
    let before = read(&d.join("p2-b/walk-2/track.csv"));
    shard(d, 1, "p2-b", &["p1-a", "p1-b"]).success();
    assert_eq!(read(&d.join("p2-b/walk-2/track.csv")), before);

    // A pass must see every walk of the previous one.
    shard(d, 0, "bad", &["p1-a"])
        .failure()
        .stderr(predicates::str::contains(
            "no folder holds walk-2/map.geojson",
        ));
    footslam()
        .args(["learn", "--walks"])
        .arg(d.join("walks.csv"))
        .args(["--shard", "3/2"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("need 1 ≤ K ≤ N"));
    // Shards count from 1, as walks do; 0 names the fix.
    footslam()
        .args(["learn", "--walks"])
        .arg(d.join("walks.csv"))
        .args(["--shard", "0/2"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("--shard 1/2"));
}
