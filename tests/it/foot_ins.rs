//! The foot-mounted INS on a real excerpt (see `tests/data/README.md`): stride count, lengths
//! and turns against the Vicon truth.

use footslam::inertial::{FootConfig, HeadingSource, detect_strides};
use footslam::io::read_imu;
use std::path::Path;

/// Truth of the excerpt: end time (s) and length (m) of each complete stride, and the change of
/// walking direction from the previous stride (radians; the first has none).
const TRUTH: [(f64, f64, Option<f64>); 3] = [
    (4.32016, 1.1108, None),
    (5.07004, 1.1577, Some(-1.3282)),
    (5.76998, 1.2552, Some(-1.3264)),
];

#[test]
fn strides_of_a_real_excerpt_match_the_vicon_truth() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/foot_excerpt.csv");
    let recording = read_imu(&path).expect("excerpt readable");
    let events = detect_strides(&recording, &FootConfig::default()).expect("strides");
    let steps = events.trace.steps();
    assert_eq!(steps.len(), TRUTH.len(), "{steps:?}");
    assert_eq!(events.path.len(), steps.len() + 1);
    assert_eq!(events.heading_source, HeadingSource::Gyroscope);
    for (s, &(t, length, turn)) in steps.iter().zip(&TRUTH) {
        assert!((s.t - t).abs() < 0.1, "stride at {} s, truth {t} s", s.t);
        assert!(
            (s.length - length).abs() < 0.08,
            "stride at {t} s: {} m, truth {length} m",
            s.length
        );
        assert!(s.heading.is_none() && s.dz.abs() < 0.05);
        match turn {
            // The change of walking direction, measured on the INS displacement (the foot's
            // yaw alone would be off by about half the turn: it looks ahead).
            Some(turn) => assert!(
                (s.dheading - turn).abs() < 0.08,
                "stride at {t} s turns {} rad, truth {turn} rad",
                s.dheading
            ),
            // The first stride sets the walk's direction.
            None => assert_eq!(s.dheading, 0.0),
        }
    }
    let f = &events.figures;
    assert_eq!(f.strides, 3);
    assert!(f.stationary_s > 3.0, "{f:?}"); // the stand before the walk
    assert!(f.max_zupt_residual < 0.5, "{f:?}");
}
