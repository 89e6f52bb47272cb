//! The phone step-and-heading system on 15 s of a real walk (`tests/data/phone_excerpt.csv`,
//! see `tests/data/README.md`): the step count against a hand count, and an absolute
//! heading that follows the walk's waypoints.

use footslam::inertial::{HeadingSource, PhoneConfig, detect_steps};
use footslam::io::read_imu;
use std::path::Path;

#[test]
fn real_excerpt_counts_steps_and_heads_north_north_east() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/phone_excerpt.csv");
    let recording = read_imu(&path).expect("the excerpt reads");
    let events = detect_steps(&recording, &PhoneConfig::default()).expect("runs");
    let f = &events.figures;
    // 28 steps counted by hand in a plot of |a|; ±2 for the ambiguous humps and the ends.
    assert!((26..=30).contains(&f.steps), "{} steps", f.steps);
    assert_eq!(events.heading_source, HeadingSource::RotationVector);
    assert!(events.trace.steps().iter().all(|s| s.heading.is_some()));
    assert_eq!(f.gaps, 0);

    // From the second waypoint (621.6 s) to the third (628.5 s) the walk bears
    // atan2(8.84, 1.38) = 81° (counter-clockwise from east); the steps agree within 20°.
    let t0 = 1_574_563_621.625;
    let (mut c, mut s) = (0.0, 0.0);
    for step in events.trace.steps() {
        if step.t > t0 && step.t <= 1_574_563_628.486 {
            let h = step.heading.expect("absolute");
            c += h.cos();
            s += h.sin();
        }
    }
    let mean = s.atan2(c).to_degrees();
    assert!((mean - 81.0).abs() < 20.0, "mean heading {mean:.1}°");

    // Over the 15 s the waypoints move about 19.8 m at 75°: the dead-reckoned path agrees
    // within 25 % in length and 20° in direction.
    let end = events.path[events.path.len() - 1];
    let (length, bearing) = (end[0].hypot(end[1]), end[1].atan2(end[0]).to_degrees());
    assert!((length - 19.8).abs() < 0.25 * 19.8, "{length:.1} m");
    assert!((bearing - 75.0).abs() < 20.0, "{bearing:.1}°");
}
