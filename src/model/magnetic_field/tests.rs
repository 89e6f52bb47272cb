use super::*;
use crate::sensor::StepField;

/// A corridor walked back and forth `laps` times: 0.7 m steps along x, turning round at
/// either end, each step reading the field `f(x)` plus a little noise.
fn corridor(laps: usize, field: impl Fn(f64) -> (f64, f64)) -> (Vec<Step>, StepFields) {
    let (mut steps, mut fields) = (Vec::new(), Vec::new());
    let (mut x, mut dir, mut t) = (0.0, 1.0, 1.7e9);
    for lap in 0..2 * laps {
        for i in 0..30 {
            t += 0.6;
            x += 0.7 * dir;
            let turn = if i == 0 && lap > 0 {
                std::f64::consts::PI
            } else {
                0.0
            };
            steps.push(Step {
                t,
                length: 0.7,
                dheading: turn,
                dz: 0.0,
                heading: None,
            });
            let noise = 0.2 * ((steps.len() as f64) * 2.3).sin();
            let (m, v) = field(x);
            fields.push(Some(StepField {
                magnitude: m + noise,
                vertical: Some(v - noise),
            }));
        }
        dir = -dir;
    }
    (steps, StepFields::new(fields).expect("valid"))
}

fn steel(x: f64) -> (f64, f64) {
    (50.0 + 6.0 * (x / 1.7).sin(), -30.0 + 5.0 * (x / 2.3).cos())
}

#[test]
fn a_varied_field_calibrates_and_weighs_revisits() {
    let (steps, fields) = corridor(3, steel);
    let e = FieldEvidence::new(&FieldConfig::default(), &steps, &fields);
    let c = e.calibration.clone().expect("calibrated");
    assert!(e.active(), "{c:?}");
    assert_eq!(c.components, 2);
    assert!(c.passing_sd_ut[0] < c.far_sd_ut[0] / 2.0, "{c:?}");
    assert_eq!(c.near_sd_ut, c.passing_sd_ut, "revisit_factor = 1");
    let (model, y) = e.reading(40).expect("a reading");
    // The same place agrees, another place does not, an empty hexagon says nothing.
    assert!(model.log_ratio(y, 3, y) > 0.3);
    assert!(model.log_ratio(y, 3, [y[0] + 12.0, y[1] - 10.0]) < -0.3);
    let mut map = FieldMap::new();
    let here = Pose2::new(3.0, 0.0, 0.0);
    assert_eq!(model.weigh_and_learn(&mut map, &here, 0, 100, y), 0.0);
    // Its own reading of a moment ago is no revisit.
    assert_eq!(model.weigh_and_learn(&mut map, &here, 0, 101, y), 0.0);
    let away = Pose2::new(20.0, 0.0, 0.0);
    assert_eq!(model.weigh_and_learn(&mut map, &away, 0, 150, y), 0.0);
    let revisit = model.weigh_and_learn(&mut map, &here, 0, 200, y);
    assert!(revisit > 0.3, "{revisit}");
    model.weigh_and_learn(&mut map, &away, 0, 250, y);
    let elsewhere = model.weigh_and_learn(&mut map, &here, 0, 300, [y[0] + 12.0, y[1]]);
    assert!(elsewhere < -0.3, "{elsewhere}");
    // Another level is another map.
    assert_eq!(model.weigh_and_learn(&mut map, &here, 1, 400, y), 0.0);
}

#[test]
fn more_readings_make_a_place_surer() {
    let (steps, fields) = corridor(3, steel);
    let e = FieldEvidence::new(&FieldConfig::default(), &steps, &fields);
    let (model, y) = e.reading(10).unwrap();
    let off = [y[0] + 1.5, y[1] - 1.0];
    assert!(model.log_ratio(y, 10, y) > model.log_ratio(y, 1, y));
    let far = [y[0] + 15.0, y[1] + 15.0];
    assert!(model.log_ratio(y, 10, far) < model.log_ratio(y, 10, off));
    // The outlier share bounds a single reading's penalty.
    let floor = FieldConfig::default().tempering * FieldConfig::default().outlier_share.ln();
    assert!(model.log_ratio(y, 10, [y[0] + 200.0, y[1]]) >= floor - 1e-9);
}

#[test]
fn a_flat_field_or_too_few_readings_weigh_nothing() {
    let (steps, fields) = corridor(3, |_| (45.0, -38.0));
    let e = FieldEvidence::new(&FieldConfig::default(), &steps, &fields);
    assert_eq!(e.model.as_ref().err(), Some(&FieldUnused::NoContrast));
    assert!(e.reading(5).is_none());
    let (steps, fields) = corridor(3, steel);
    let few = StepFields::new(
        (0..steps.len())
            .map(|i| if i < 10 { fields.get(i) } else { None })
            .collect(),
    )
    .unwrap();
    let e = FieldEvidence::new(&FieldConfig::default(), &steps, &few);
    assert_eq!(e.model.as_ref().err(), Some(&FieldUnused::TooFewReadings));
    let off = FieldConfig {
        enabled: false,
        ..Default::default()
    };
    let e = FieldEvidence::new(&off, &steps, &fields);
    assert_eq!(e.model.as_ref().err(), Some(&FieldUnused::Disabled));
    assert_eq!(e.observed, steps.len());
}

#[test]
fn magnitude_alone_when_the_vertical_part_is_mostly_missing() {
    let (steps, fields) = corridor(3, steel);
    let no_up = StepFields::new(
        fields
            .fields()
            .iter()
            .enumerate()
            .map(|(i, f)| {
                f.map(|f| StepField {
                    vertical: (i % 3 == 0).then_some(f.vertical).flatten(),
                    ..f
                })
            })
            .collect(),
    )
    .unwrap();
    let e = FieldEvidence::new(&FieldConfig::default(), &steps, &no_up);
    assert_eq!(e.calibration.as_ref().unwrap().components, 1);
    assert!(e.active());
    assert!(
        FieldConfig {
            tempering: 2.0,
            ..Default::default()
        }
        .validate()
        .is_err()
    );
}
