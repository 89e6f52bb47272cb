//! `footslam steps`: one hour of 100 Hz IMU data (360,000 samples) through each front end —
//! the foot-mounted zero-velocity-aided INS and the phone's step-and-heading system — and
//! the IMU CSV reader on the same hour. The hour is a real excerpt (tests/data: a
//! foot-mounted walk of the PyShoe/gait-driven dataset, a phone walk of the Indoor Location
//! Competition 2.0) taken at 100 Hz and repeated end to end with times running on, so the
//! detectors see real strides, turns and stances throughout.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use footslam::inertial::{FootConfig, PhoneConfig, detect_steps, detect_strides};
use footslam::io::{read_imu, write_imu};
use footslam::sensor::{ImuRecording, ImuSample};
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

/// Samples in one hour at 100 Hz.
const HOUR_AT_100_HZ: usize = 360_000;

/// The excerpt in `tests/data/<name>` at 100 Hz (every sample nearest a 10 ms tick), repeated
/// to one hour.
fn hour_of(name: &str) -> ImuRecording {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let excerpt = read_imu(&path).expect("excerpt");
    let s = excerpt.samples();
    let (t0, t1) = (s[0].t, s[s.len() - 1].t);
    let mut at_100: Vec<ImuSample> = Vec::new();
    let mut tick = t0;
    for w in s.windows(2) {
        while tick <= w[1].t {
            let nearest = if tick - w[0].t <= w[1].t - tick {
                w[0]
            } else {
                w[1]
            };
            at_100.push(ImuSample { t: tick, ..nearest });
            tick += 0.01;
        }
    }
    let period = t1 - t0 + 0.01;
    let samples: Vec<ImuSample> = (0..HOUR_AT_100_HZ)
        .map(|i| {
            let k = i / at_100.len();
            let s = at_100[i % at_100.len()];
            ImuSample {
                t: 1.7e9 + s.t - t0 + k as f64 * period,
                ..s
            }
        })
        .collect();
    ImuRecording::new(samples, 0).expect("hour")
}

fn front_ends(c: &mut Criterion) {
    let foot = hour_of("foot_excerpt.csv");
    let phone = hour_of("phone_excerpt.csv");
    let mut g = c.benchmark_group("steps_one_hour_100hz");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    g.throughput(Throughput::Elements(HOUR_AT_100_HZ as u64));
    g.bench_with_input(
        BenchmarkId::new("foot_ins", HOUR_AT_100_HZ),
        &foot,
        |b, r| b.iter(|| detect_strides(black_box(r), &FootConfig::default()).expect("strides")),
    );
    g.bench_with_input(
        BenchmarkId::new("phone_pdr", HOUR_AT_100_HZ),
        &phone,
        |b, r| b.iter(|| detect_steps(black_box(r), &PhoneConfig::default()).expect("steps")),
    );
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("imu.csv");
    write_imu(&csv, &phone).expect("write");
    g.bench_with_input(
        BenchmarkId::new("read_imu_csv", HOUR_AT_100_HZ),
        &csv,
        |b, p| b.iter(|| read_imu(black_box(p)).expect("read")),
    );
    g.finish();
}

criterion_group!(benches, front_ends);
criterion_main!(benches);
