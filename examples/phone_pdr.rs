//! The phone step-and-heading system ([`footslam::inertial::detect_steps`]) against
//! ground-truth waypoints: pure dead reckoning started at each walk's first waypoint
//! (position given, heading from the recording), error at every later waypoint.
//!
//! DIR holds pairs `NAME.imu.csv` (the `footslam::io::read_imu` format) and
//! `NAME.waypoints.csv` (header `t,x,y`: seconds on the IMU's clock, metres east and north).
//! A missing DIR is skipped with a message. Also times one hour of synthetic 100 Hz data.
//!
//! ```sh
//! cargo run --release --example phone_pdr -- DIR
//! K=0.5 cargo run --release --example phone_pdr -- DIR      # another stride constant
//! HEADING=mag cargo run --release --example phone_pdr -- DIR # ignore the rotation vector
//! FOLD=even cargo run --release --example phone_pdr -- DIR  # only even (odd) traces
//! ```

#![allow(clippy::print_stdout)] // an example reports on stdout

use footslam::inertial::{PhoneConfig, detect_steps};
use footslam::io::read_imu;
use footslam::sensor::{ImuRecording, ImuSample};
use std::path::{Path, PathBuf};
use std::time::Instant;

type Res<T> = Result<T, Box<dyn std::error::Error>>;

fn read_waypoints(path: &Path) -> Res<Vec<(f64, f64, f64)>> {
    let text = std::fs::read_to_string(path)?;
    let mut out = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let v: Vec<f64> = line
            .split(',')
            .map(|c| c.trim().parse::<f64>())
            .collect::<Result<_, _>>()?;
        if v.len() < 3 {
            return Err(format!("{}: short line {line:?}", path.display()).into());
        }
        out.push((v[0], v[1], v[2]));
    }
    Ok(out)
}

/// Position on the piecewise-linear track `(t, x, y)` at time `t` (clamped to its ends).
fn at(track: &[(f64, f64, f64)], t: f64) -> (f64, f64) {
    let i = track.partition_point(|p| p.0 <= t);
    if i == 0 {
        return (track[0].1, track[0].2);
    }
    if i == track.len() {
        let p = track[track.len() - 1];
        return (p.1, p.2);
    }
    let (a, b) = (track[i - 1], track[i]);
    let u = (t - a.0) / (b.0 - a.0);
    (a.1 + u * (b.1 - a.1), a.2 + u * (b.2 - a.2))
}

fn percentile(v: &mut [f64], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * q).round() as usize]
}

#[derive(Default)]
struct Totals {
    errors: Vec<f64>,
    final_errors: Vec<f64>,
    heading_offsets: Vec<f64>,
    pdr_length: f64,
    truth_length: f64,
    steps: usize,
    ratios: Vec<f64>,
    seconds: f64,
}

fn evaluate(imu: &Path, wp: &Path, config: &PhoneConfig, totals: &mut Totals) -> Res<()> {
    let recording = read_imu(imu)?;
    let waypoints = read_waypoints(wp)?;
    if waypoints.len() < 2 {
        return Err("fewer than two waypoints".into());
    }
    let started = Instant::now();
    let events = detect_steps(&recording, config)?;
    totals.seconds += started.elapsed().as_secs_f64();
    let t0 = recording.samples()[0].t;
    // The track: the start at the first sample, then one point per step.
    let track: Vec<(f64, f64, f64)> = std::iter::once(t0)
        .chain(events.trace.steps().iter().map(|s| s.t))
        .zip(&events.path)
        .map(|(t, p)| (t, p[0], p[1]))
        .collect();
    let (w0, wn) = (waypoints[0], waypoints[waypoints.len() - 1]);
    let start = at(&track, w0.0);
    let offset = (w0.1 - start.0, w0.2 - start.1);
    let mut errors = Vec::new();
    for w in &waypoints[1..] {
        let p = at(&track, w.0);
        errors.push((p.0 + offset.0 - w.1).hypot(p.1 + offset.1 - w.2));
    }
    // Lengths between the first and the last waypoint's times.
    let inside = events
        .trace
        .steps()
        .iter()
        .filter(|s| s.t >= w0.0 && s.t <= wn.0);
    let pdr: f64 = inside.clone().map(|s| s.length).sum();
    let n_inside = inside.count();
    let truth: f64 = waypoints
        .windows(2)
        .map(|w| (w[1].1 - w[0].1).hypot(w[1].2 - w[0].2))
        .sum();
    // Heading check: legs of 3 m or more, mean step heading against the bearing.
    for w in waypoints.windows(2) {
        let (dx, dy) = (w[1].1 - w[0].1, w[1].2 - w[0].2);
        if dx.hypot(dy) < 3.0 {
            continue;
        }
        let (mut c, mut s) = (0.0, 0.0);
        for step in events.trace.steps() {
            if let Some(h) = step.heading
                && step.t > w[0].0
                && step.t <= w[1].0
            {
                c += step.length * h.cos();
                s += step.length * h.sin();
            }
        }
        if c != 0.0 || s != 0.0 {
            totals
                .heading_offsets
                .push(footslam::geometry::wrap_turn(s.atan2(c) - dy.atan2(dx)).to_degrees());
        }
    }
    let f = &events.figures;
    let name = imu
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    println!(
        "{:<28} {:>5.1}s {:>3} steps {:>5.1}/min stride {:.2} m | length pdr {:>5.1} truth {:>5.1} ({:>4.2}) | err median {:>4.1} max {:>4.1} end {:>4.1} m | gaps {}",
        name.trim_end_matches(".imu.csv"),
        f.duration_s,
        f.steps,
        f.cadence_spm,
        f.mean_stride_m,
        pdr,
        truth,
        pdr / truth,
        percentile(&mut errors.clone(), 0.5),
        errors.iter().copied().fold(0.0, f64::max),
        errors[errors.len() - 1],
        f.gaps,
    );
    totals.final_errors.push(errors[errors.len() - 1]);
    totals.errors.extend(errors);
    totals.pdr_length += pdr;
    totals.truth_length += truth;
    totals.steps += n_inside;
    totals.ratios.push(pdr / truth);
    Ok(())
}

/// One hour of 100 Hz synthetic walking and standing, for timing.
fn synthetic_hour() -> Res<ImuRecording> {
    let samples = (0..360_000)
        .map(|i| {
            let t = f64::from(i) * 0.01;
            let walking = (t / 60.0) as u64 % 4 != 3; // three minutes walking, one standing
            let up = if walking {
                3.0 * (2.0 * std::f64::consts::PI * 1.9 * t).sin()
            } else {
                0.0
            };
            let yaw = 0.3 * (t / 20.0).sin();
            ImuSample {
                t,
                accel: [0.3, 0.2, 9.81 + up],
                gyro: [0.0, 0.0, 0.015 * (t / 20.0).cos()],
                mag: Some([20.0 * yaw.sin(), 20.0 * yaw.cos(), -40.0]),
                orientation: Some([0.0, 0.0, (yaw / 2.0).sin(), (yaw / 2.0).cos()]),
                pressure: Some(1000.0 + 0.01 * (t / 100.0).sin()),
            }
        })
        .collect();
    ImuRecording::new(samples, 0).map_err(|(i, m)| format!("sample {i}: {m}").into())
}

fn main() -> Res<()> {
    let mut config = PhoneConfig::default();
    if let Ok(k) = std::env::var("K") {
        config.stride.weinberg_k = k.parse()?;
    }
    if std::env::var("HEADING").is_ok_and(|h| h == "mag") {
        config.use_rotation_vector = false;
    }
    let fold = std::env::var("FOLD").ok();

    let hour = synthetic_hour()?;
    for mag_only in [false, true] {
        let mut c = config.clone();
        c.use_rotation_vector = !mag_only;
        let started = Instant::now();
        let e = detect_steps(&hour, &c)?;
        println!(
            "1 h of 100 Hz ({} samples, {:?}): {} steps in {:.3} s",
            hour.samples().len(),
            e.heading_source,
            e.trace.len(),
            started.elapsed().as_secs_f64()
        );
    }

    let Some(dir) = std::env::args().nth(1).map(PathBuf::from) else {
        println!("usage: phone_pdr DIR (pairs NAME.imu.csv + NAME.waypoints.csv); skipped");
        return Ok(());
    };
    if !dir.is_dir() {
        println!("{}: no such folder; skipped", dir.display());
        return Ok(());
    }
    let mut imus: Vec<PathBuf> = std::fs::read_dir(&dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().ends_with(".imu.csv"))
        .collect();
    imus.sort();
    let mut totals = Totals::default();
    for (i, imu) in imus.iter().enumerate() {
        match fold.as_deref() {
            Some("even") if i % 2 == 1 => continue,
            Some("odd") if i % 2 == 0 => continue,
            _ => {}
        }
        let wp = PathBuf::from(imu.to_string_lossy().replace(".imu.csv", ".waypoints.csv"));
        if let Err(e) = evaluate(imu, &wp, &config, &mut totals) {
            println!("{}: {e}", imu.display());
        }
    }
    let n = totals.errors.len();
    let t = &mut totals;
    println!(
        "\n{} traces, {n} waypoints after the start; K = {}, heading {}",
        t.ratios.len(),
        config.stride.weinberg_k,
        if config.use_rotation_vector {
            "rotation vector"
        } else {
            "gyro + magnetometer"
        }
    );
    println!(
        "error at waypoints: median {:.2} m, p90 {:.2} m; at the walk's end: median {:.2} m, p90 {:.2} m",
        percentile(&mut t.errors, 0.5),
        percentile(&mut t.errors, 0.9),
        percentile(&mut t.final_errors, 0.5),
        percentile(&mut t.final_errors, 0.9),
    );
    println!(
        "length: pdr {:.1} m / waypoint polyline {:.1} m = {:.3} (per trace median {:.3}, p10 {:.3}, p90 {:.3}); {} steps = {:.3} m of polyline per step",
        t.pdr_length,
        t.truth_length,
        t.pdr_length / t.truth_length,
        percentile(&mut t.ratios, 0.5),
        percentile(&mut t.ratios, 0.1),
        percentile(&mut t.ratios, 0.9),
        t.steps,
        t.truth_length / t.steps as f64,
    );
    println!(
        "calibrated K over these traces: {:.3} (K · polyline / pdr)",
        config.stride.weinberg_k * t.truth_length / t.pdr_length
    );
    let mut abs: Vec<f64> = t.heading_offsets.iter().map(|h| h.abs()).collect();
    println!(
        "heading − bearing over {} legs ≥ 3 m: median {:.1}°, |median| {:.1}°, p90 |.| {:.1}°",
        t.heading_offsets.len(),
        percentile(&mut t.heading_offsets, 0.5),
        percentile(&mut abs, 0.5),
        percentile(&mut abs, 0.9),
    );
    println!("detect_steps time over all traces: {:.3} s", t.seconds);
    Ok(())
}
