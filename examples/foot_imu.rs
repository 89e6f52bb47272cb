//! The foot-mounted INS ([`footslam::inertial::detect_strides`]) on every walk found under a
//! folder (each sub-folder with an `imu.csv` and a `strides.csv` of truth stances), scored
//! against the truth: stride count, stride-length RMS error, total-distance error and the
//! shape error (the dead-reckoned strides rigidly aligned to the footprints, p95). Then the
//! speed on one hour of 100 Hz data (the first walk, decimated and repeated).
//!
//! ```sh
//! cargo run --release --example foot_imu -- /work/shared/data/foot-imu
//! FOOT='{"adaptive_fraction":0.3}' cargo run --release --example foot_imu -- DIR   # other settings
//! DECIMATE=2 cargo run --release --example foot_imu -- DIR   # every 2nd sample (100 Hz)
//! ```
//!
//! Matching: a stride's end (its `t`) and start (the previous stride's `t`, or the first
//! stance) are matched to the truth stance nearest in time within 0.3 s; a stride whose ends
//! both match is compared with the truth's straight-line distance between those stances.

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::geometry::RigidTransform;
use footslam::inertial::{FootConfig, detect_strides};
use footslam::io::read_imu;
use footslam::sensor::{ImuRecording, ImuSample};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Largest time difference between a detected and a truth stance that still matches, s.
const MATCH_S: f64 = 0.3;

struct Score {
    name: String,
    truth_strides: usize,
    strides: usize,
    length_errors: Vec<f64>,
    truth_distance: f64,
    distance: f64,
    p95_shape: f64,
    seconds: f64,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "/work/shared/data/foot-imu".into()),
    );
    let config: FootConfig = match std::env::var("FOOT") {
        Ok(v) => serde_json::from_str(&v)?,
        Err(_) => FootConfig::default(),
    };
    let walks = find_walks(&root);
    if walks.is_empty() {
        println!(
            "no walks (imu.csv + strides.csv) under {}: skipped",
            root.display()
        );
        return Ok(());
    }
    println!(
        "{:<34} {:>5} {:>5} {:>7} {:>7} {:>7} {:>7} {:>6} {:>7}",
        "walk", "truth", "found", "count%", "lenRMS", "dist_m", "dist%", "p95_m", "ms"
    );
    let mut scores = Vec::new();
    for dir in &walks {
        let s = score(dir, &root, &config)?;
        println!(
            "{:<34} {:>5} {:>5} {:>+7.1} {:>7.3} {:>7.1} {:>+7.2} {:>6.2} {:>7.1}",
            s.name,
            s.truth_strides,
            s.strides,
            100.0 * (s.strides as f64 - s.truth_strides as f64) / s.truth_strides as f64,
            rms(&s.length_errors),
            s.truth_distance,
            100.0 * (s.distance - s.truth_distance) / s.truth_distance,
            s.p95_shape,
            1e3 * s.seconds
        );
        scores.push(s);
    }
    aggregate(&scores);
    timing(&walks[0], &config)?;
    Ok(())
}

fn find_walks(root: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        if dir.join("imu.csv").is_file() && dir.join("strides.csv").is_file() {
            found.push(dir.clone());
        }
        if let Ok(entries) = std::fs::read_dir(&dir) {
            stack.extend(entries.flatten().map(|e| e.path()).filter(|p| p.is_dir()));
        }
    }
    found.sort();
    found
}

fn read_truth(path: &Path) -> Result<Vec<[f64; 4]>, Box<dyn std::error::Error>> {
    let mut rows = Vec::new();
    for line in std::fs::read_to_string(path)?.lines().skip(1) {
        let v: Vec<f64> = line
            .split(',')
            .map(|c| c.trim().parse())
            .collect::<Result<_, _>>()?;
        if v.len() >= 4 {
            rows.push([v[0], v[1], v[2], v[3]]);
        }
    }
    Ok(rows)
}

fn nearest(truth: &[[f64; 4]], t: f64) -> Option<usize> {
    let (i, d) = truth
        .iter()
        .enumerate()
        .map(|(i, r)| (i, (r[0] - t).abs()))
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    (d <= MATCH_S).then_some(i)
}

fn score(
    dir: &Path,
    root: &Path,
    config: &FootConfig,
) -> Result<Score, Box<dyn std::error::Error>> {
    let mut recording = read_imu(&dir.join("imu.csv"))?;
    if let Some(n) = std::env::var("DECIMATE")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        // Every n-th sample only: the same walk at a lower rate (no anti-alias filter).
        let kept = recording
            .samples()
            .iter()
            .step_by(n.max(1))
            .copied()
            .collect();
        recording = ImuRecording::new(kept, 0).map_err(|(i, m)| format!("sample {i}: {m}"))?;
    }
    let truth = read_truth(&dir.join("strides.csv"))?;
    let start = Instant::now();
    let events = detect_strides(&recording, config)?;
    let seconds = start.elapsed().as_secs_f64();
    let steps = events.trace.steps();
    if std::env::var("DUMP").is_ok_and(|d| dir.ends_with(d)) {
        println!("  {}", serde_json::to_string(&events.figures)?);
        for s in steps {
            println!("  stride {:.2} {:.3}", s.t, s.length);
        }
    }
    let hdist = |a: &[f64; 4], b: &[f64; 4]| (a[1] - b[1]).hypot(a[2] - b[2]);
    let truth_distance: f64 = truth.windows(2).map(|w| hdist(&w[0], &w[1])).sum();
    // The path's points: the first stance (its time is not in the trace; it is matched to
    // the truth's first stance), then each stride's end.
    let mut matches: Vec<Option<usize>> = vec![Some(0)];
    matches.extend(steps.iter().map(|s| nearest(&truth, s.t)));
    let mut length_errors = Vec::new();
    for (i, s) in steps.iter().enumerate() {
        if let (Some(a), Some(b)) = (matches[i], matches[i + 1])
            && b > a
        {
            length_errors.push(s.length - hdist(&truth[a], &truth[b]));
            if std::env::var("DUMP").is_ok_and(|d| dir.ends_with(d)) {
                println!(
                    "  {:.2} {:.3} truth {:.3} ({}→{})",
                    s.t,
                    s.length,
                    hdist(&truth[a], &truth[b]),
                    a,
                    b
                );
            }
        }
    }
    // The shape users get: `events.path` is what `steps.csv` dead-reckons to from the first
    // stance (`dheading` is the change of stride direction; unit-tested in `inertial::foot`).
    let (mut from, mut to) = (Vec::new(), Vec::new());
    for (p, m) in events.path.iter().zip(&matches) {
        if let Some(j) = m {
            from.push((p[0], p[1]));
            to.push((truth[*j][1], truth[*j][2]));
        }
    }
    let p95_shape = RigidTransform::fit(&from, &to).map_or(f64::NAN, |tf| {
        let mut e: Vec<f64> = from
            .iter()
            .zip(&to)
            .map(|(&a, &b)| {
                let (x, y) = tf.apply(a);
                (x - b.0).hypot(y - b.1)
            })
            .collect();
        percentile(&mut e, 0.95)
    });
    Ok(Score {
        name: dir.strip_prefix(root).unwrap_or(dir).display().to_string(),
        truth_strides: truth.len().saturating_sub(1),
        strides: steps.len(),
        length_errors,
        truth_distance,
        distance: events.figures.distance_m,
        p95_shape,
        seconds,
    })
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|e| e * e).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

fn percentile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn aggregate(scores: &[Score]) {
    let truth: usize = scores.iter().map(|s| s.truth_strides).sum();
    let found: usize = scores.iter().map(|s| s.strides).sum();
    let worst_count = scores
        .iter()
        .map(|s| (s.strides as f64 - s.truth_strides as f64).abs() / s.truth_strides as f64)
        .fold(0.0, f64::max);
    let exact = scores
        .iter()
        .filter(|s| s.strides == s.truth_strides)
        .count();
    let errors: Vec<f64> = scores
        .iter()
        .flat_map(|s| s.length_errors.clone())
        .collect();
    let mut dist: Vec<f64> = scores
        .iter()
        .map(|s| (s.distance - s.truth_distance).abs() / s.truth_distance)
        .collect();
    let mut p95: Vec<f64> = scores.iter().map(|s| s.p95_shape).collect();
    let matched = errors.len();
    println!();
    println!(
        "stride count      {found} of {truth} ({:+.2} %; {exact} of {} walks exact, worst walk {:.1} %)   target within 2 %",
        100.0 * (found as f64 - truth as f64) / truth as f64,
        scores.len(),
        100.0 * worst_count
    );
    println!(
        "stride length     RMS error {:.3} m over {matched} matched strides   target ≤ 0.10 m",
        rms(&errors)
    );
    println!(
        "total distance    median |error| {:.2} %   target ≤ 3 %",
        100.0 * percentile(&mut dist, 0.5)
    );
    println!(
        "shape             median of per-walk p95 {:.2} m   target ≤ 1 m",
        percentile(&mut p95, 0.5)
    );
}

/// One hour of 100 Hz data: the walk decimated to 100 Hz and repeated, times continued.
fn timing(dir: &Path, config: &FootConfig) -> Result<(), Box<dyn std::error::Error>> {
    let recording = read_imu(&dir.join("imu.csv"))?;
    let src: Vec<ImuSample> = recording.samples().iter().step_by(2).copied().collect();
    let samples: Vec<ImuSample> = (0..360_000)
        .map(|k| ImuSample {
            t: 0.01 * k as f64,
            ..src[k % src.len()]
        })
        .collect();
    let hour = ImuRecording::new(samples, 0).map_err(|(i, m)| format!("sample {i}: {m}"))?;
    let start = Instant::now();
    let events = detect_strides(&hour, config)?;
    println!(
        "\nspeed             1 h of 100 Hz data (360 000 samples, {} strides) in {:.3} s",
        events.trace.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}
