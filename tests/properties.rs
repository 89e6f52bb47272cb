//! Property tests of the invariants that matter: every reader reads back what its writer
//! writes (to the written precision), FootSLAM emits only finite values for any valid step
//! trace, and its results do not depend on the thread count.

use footslam::dataset::{
    TimedPoint, read_steps, read_trajectory, read_wifi, steps_csv::write_steps, write_trajectory,
    write_wifi,
};
use footslam::filter::{FootSlam, FootSlamConfig};
use footslam::sensor::{Step, StepTrace, WifiReading, WifiScan};
use proptest::prelude::*;

/// Valid steps: times strictly increasing (at least 10 ms apart, as a written millisecond
/// keeps them), strides up to 2 m, any heading change, height changes of stairs.
fn steps(max: usize) -> impl Strategy<Value = Vec<Step>> {
    prop::collection::vec(
        (
            0.01f64..2.0,
            0.0f64..2.0,
            -3.1f64..3.1,
            -0.3f64..0.3,
            prop::option::of(-3.1f64..3.1),
        ),
        1..max,
    )
    .prop_flat_map(|rows| (Just(rows), 0.0f64..2e9))
    .prop_map(|(rows, t0)| {
        let mut t = t0;
        let with_heading = rows.first().is_some_and(|r| r.4.is_some());
        rows.into_iter()
            .map(|(dt, length, dheading, dz, heading)| {
                t += dt;
                Step {
                    t,
                    length,
                    dheading,
                    dz,
                    heading: heading
                        .filter(|_| with_heading)
                        .or(with_heading.then_some(0.0)),
                }
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn step_traces_round_trip(steps in steps(40)) {
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("steps.csv");
        let trace = StepTrace::new(steps).expect("valid");
        write_steps(&path, &trace).expect("write");
        let back = read_steps(&path).expect("read back");
        prop_assert_eq!(back.len(), trace.len());
        for (a, b) in trace.steps().iter().zip(back.steps()) {
            prop_assert!((a.t - b.t).abs() <= 5e-4 * (1.0 + a.t.abs() * 1e-12), "{} {}", a.t, b.t);
            prop_assert!((a.length - b.length).abs() <= 5e-5);
            prop_assert!((a.dheading - b.dheading).abs() <= 5e-7);
            prop_assert!((a.dz - b.dz).abs() <= 5e-5);
            prop_assert_eq!(a.heading.is_some(), b.heading.is_some());
        }
    }

    #[test]
    fn trajectories_round_trip(
        points in prop::collection::vec((0.01f64..5.0, -1e4f64..1e4, -1e4f64..1e4), 1..50),
        t0 in 0.0f64..2e9,
    ) {
        let mut t = t0;
        let points: Vec<TimedPoint> = points
            .into_iter()
            .map(|(dt, x, y)| {
                t += dt;
                TimedPoint { t, x, y }
            })
            .collect();
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("track.csv");
        write_trajectory(&path, points.iter().copied()).expect("write");
        let back = read_trajectory(&path).expect("read back");
        prop_assert_eq!(back.len(), points.len());
        for (a, b) in points.iter().zip(&back) {
            prop_assert!((a.x - b.x).abs() <= 5e-4 && (a.y - b.y).abs() <= 5e-4);
        }
    }

    #[test]
    fn wifi_logs_round_trip(
        scans in prop::collection::vec(
            (0.01f64..10.0, prop::collection::btree_map(0u8..40, -110.0f64..-20.0, 1..8)),
            1..20,
        ),
    ) {
        let mut t = 1.7e9;
        let scans: Vec<WifiScan> = scans
            .into_iter()
            .map(|(dt, aps)| {
                t += dt;
                WifiScan {
                    t,
                    readings: aps
                        .into_iter()
                        .map(|(ap, rssi)| WifiReading {
                            bssid: format!("02:00:00:00:00:{ap:02x}"),
                            rssi,
                            ssid: Some("net".into()),
                            freq: Some(2437.0),
                        })
                        .collect(),
                }
            })
            .collect();
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("wifi.csv");
        write_wifi(&path, &scans).expect("write");
        let back = read_wifi(&path).expect("read back");
        prop_assert_eq!(back.len(), scans.len());
        for (a, b) in scans.iter().zip(&back) {
            prop_assert_eq!(a.readings.len(), b.readings.len());
            for r in &a.readings {
                let rssi = b.rssi(&r.bssid);
                prop_assert!(rssi.is_some_and(|v| (v - r.rssi).abs() <= 0.05 + 1e-9));
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    #[test]
    fn footslam_is_finite_and_independent_of_threads(steps in steps(60), seed in 0u64..1000) {
        let config = FootSlamConfig { particles: 200, seed, ..FootSlamConfig::default() };
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("pool");
            pool.install(|| {
                let mut filter = FootSlam::new(config.clone()).expect("filter");
                for s in &steps {
                    filter.update(s);
                }
                let e = filter.estimate();
                (e.path, filter.ess_history().to_vec())
            })
        };
        let (one, ess1) = run(1);
        let (two, ess2) = run(2);
        prop_assert!(one.iter().all(|p| p.x.is_finite() && p.y.is_finite() && p.heading.is_finite()));
        prop_assert!(ess1.iter().all(|e| e.is_finite() && *e > 0.0));
        prop_assert_eq!(one, two);
        prop_assert_eq!(ess1, ess2);
    }
}
