//! Property tests of the invariants that matter: every reader reads back what its writer
//! writes (to the written precision), FootSLAM emits only finite values for any valid step
//! trace, and its results do not depend on the thread count.

use footslam::filter::{FootSlam, FootSlamConfig};
use footslam::io::{
    TimedPoint, read_steps, read_trajectory, read_wifi, steps_csv::write_steps, write_trajectory,
    write_wifi,
};
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

/// What `write` wrote to a fresh file `name`, as `read` reads it back.
fn round_trip<R>(
    name: &str,
    write: impl FnOnce(&std::path::Path) -> footslam::Result<()>,
    read: impl FnOnce(&std::path::Path) -> footslam::Result<R>,
) -> R {
    let dir = tempfile::tempdir().expect("tmp");
    let path = dir.path().join(name);
    write(&path).expect("write");
    read(&path).expect("read back")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn step_traces_round_trip(steps in steps(40)) {
        let trace = StepTrace::new(steps).expect("valid");
        let back = round_trip("steps.csv", |p| write_steps(p, &trace), read_steps);
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
        let back = round_trip(
            "track.csv",
            |p| write_trajectory(p, points.iter().copied()),
            read_trajectory,
        );
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
        let back = round_trip("wifi.csv", |p| write_wifi(p, &scans), read_wifi);
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

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn gps_fixes_round_trip(
        fixes in prop::collection::vec((0.1f64..30.0, -80.0f64..80.0, -179.0f64..179.0, 0.5f64..200.0), 1..30),
    ) {
        use footslam::io::{read_gps_csv, write_gps_csv};
        let mut t = 1.7e9;
        let fixes: Vec<footslam::sensor::GpsFix> = fixes
            .into_iter()
            .map(|(dt, lat, lon, accuracy)| {
                t += dt;
                footslam::sensor::GpsFix { t, lat, lon, accuracy }
            })
            .collect();
        let back = round_trip("gps.csv", |p| write_gps_csv(p, &fixes), read_gps_csv);
        prop_assert_eq!(back.len(), fixes.len());
        for (a, b) in fixes.iter().zip(&back) {
            prop_assert!((a.lat - b.lat).abs() <= 5e-9 && (a.lon - b.lon).abs() <= 5e-9);
            prop_assert!((a.accuracy - b.accuracy).abs() <= 5e-3 && (a.t - b.t).abs() <= 5e-4);
        }
    }

    #[test]
    fn tracks_round_trip(
        points in prop::collection::vec((0.01f64..5.0, -1e4f64..1e4, -1e4f64..1e4, -50.0f64..50.0, -3i32..10), 1..40),
    ) {
        use footslam::io::{TrackPoint, read_track, write_track};
        let mut t = 1.7e9;
        let points: Vec<TrackPoint> = points
            .into_iter()
            .map(|(dt, x, y, z, level)| {
                t += dt;
                TrackPoint { t, x, y, z, level }
            })
            .collect();
        let back = round_trip("track.csv", |p| write_track(p, &points), read_track);
        prop_assert_eq!(back.len(), points.len());
        for (a, b) in points.iter().zip(&back) {
            prop_assert!((a.x - b.x).abs() <= 5e-4 && (a.y - b.y).abs() <= 5e-4);
            prop_assert!((a.z - b.z).abs() <= 5e-4 && a.level == b.level);
        }
    }

    /// A plan of axis-aligned rooms on several levels, written as GeoJSON in WGS84 and read
    /// back: the same surfaces, levels and heights, corners within a millimetre.
    #[test]
    fn floor_plans_round_trip(
        rooms in prop::collection::vec((-500.0f64..500.0, -500.0f64..500.0, 1.0f64..40.0, 1.0f64..40.0, 0i32..4), 1..12),
        lat in -60.0f64..60.0,
        lon in -170.0f64..170.0,
    ) {
        use footslam::io::floor_plan_geojson::{read_floor_plan, write_floor_plan};
        use footslam::geometry::LocalFrame;
        use footslam::map::{FloorPlan, FloorPolygon};
        let polygons: Vec<FloorPolygon> = rooms
            .iter()
            .enumerate()
            .map(|(i, &(x, y, w, h, level))| FloorPolygon {
                polygon: geo::Rect::new((x, y), (x + w, y + h)).to_polygon(),
                level,
                z: 3.0 * f64::from(level),
                name: Some(format!("room {i}")),
                room: None,
            })
            .collect();
        let plan = FloorPlan { polygons, barriers: Vec::new() };
        let frame = LocalFrame::new(lat, lon).expect("frame");
        let (back, back_frame) = round_trip(
            "plan.geojson",
            |p| write_floor_plan(p, &plan, &frame),
            |p| read_floor_plan(p, None),
        );
        prop_assert!(frame.distance_to(&back_frame) < 1e-3);
        prop_assert_eq!(back.polygons.len(), plan.polygons.len());
        for (a, b) in plan.polygons.iter().zip(&back.polygons) {
            prop_assert_eq!(a.level, b.level);
            prop_assert!((a.z - b.z).abs() < 1e-6);
            prop_assert_eq!(&a.name, &b.name);
            for (p, q) in a.polygon.exterior().points().zip(b.polygon.exterior().points()) {
                prop_assert!((p.x() - q.x()).abs() < 1e-3 && (p.y() - q.y()).abs() < 1e-3, "{:?} {:?}", p, q);
            }
        }
    }

    /// A learned hexagon map written as GeoJSON and read back: the same hexagons, levels and
    /// edge counts.
    #[test]
    fn hexagon_maps_round_trip(
        cells in prop::collection::btree_map((-200i32..200, -200i32..200, 0i32..3), prop::array::uniform6(0u32..50), 1..60),
        radius in 0.2f64..3.0,
    ) {
        use footslam::io::map_geojson::{read_map_geojson, write_map_geojson};
        use footslam::geometry::{Hex, LocalFrame};
        use footslam::map::hex_transitions::{HexCell, HexMapSnapshot};
        let mut cells: Vec<HexCell> = cells
            .into_iter()
            .filter(|(_, counts)| counts.iter().any(|&c| c > 0))
            .map(|((q, r, level), counts)| HexCell { hex: Hex::new(q, r), level, counts })
            .collect();
        prop_assume!(!cells.is_empty());
        cells.sort_by_key(|c| (c.level, c.hex.x, c.hex.y));
        let map = HexMapSnapshot { radius, alpha: 0.8, cells, levels: Vec::new() };
        let frame = LocalFrame::new(52.2, 0.1).expect("frame");
        let (back, _) = round_trip(
            "map.geojson",
            |p| write_map_geojson(p, &map, &frame),
            read_map_geojson,
        );
        prop_assert!((back.radius - map.radius).abs() < 1e-9);
        let key = |c: &HexCell| (c.level, c.hex.x, c.hex.y, c.counts);
        let mut a: Vec<_> = map.cells.iter().map(key).collect();
        let mut b: Vec<_> = back.cells.iter().map(key).collect();
        a.sort();
        b.sort();
        prop_assert_eq!(a, b);
    }

    /// An IMU recording with every optional channel, written and read back.
    #[test]
    fn imu_recordings_round_trip(
        samples in prop::collection::vec((0.001f64..0.05, prop::array::uniform3(-5.0f64..5.0), prop::array::uniform3(-8.0f64..8.0), prop::array::uniform3(-60.0f64..60.0), 950.0f64..1050.0), 2..60),
    ) {
        use footslam::io::{read_imu, write_imu};
        use footslam::sensor::{ImuRecording, ImuSample};
        let mut t = 1.7e9;
        let samples: Vec<ImuSample> = samples
            .into_iter()
            .map(|(dt, a, gyro, mag, pressure)| {
                t += dt;
                ImuSample {
                    t,
                    accel: [a[0], a[1], 9.8 + a[2]],
                    gyro,
                    mag: Some(mag),
                    orientation: Some([0.0, 0.0, 0.6, 0.8]),
                    pressure: Some(pressure),
                }
            })
            .collect();
        let recording = ImuRecording::new(samples, 0).expect("valid");
        let back = round_trip("imu.csv", |p| write_imu(p, &recording), read_imu);
        prop_assert_eq!(back.samples().len(), recording.samples().len());
        prop_assert!(back.has_magnetometer() && back.has_orientation() && back.has_pressure());
        for (a, b) in recording.samples().iter().zip(back.samples()) {
            prop_assert!((a.t - b.t).abs() <= 5e-5 + 1e-6, "{} {}", a.t, b.t);
            for (x, y) in a.accel.iter().chain(&a.gyro).zip(b.accel.iter().chain(&b.gyro)) {
                prop_assert!((x - y).abs() <= 5e-7);
            }
        }
    }
}
