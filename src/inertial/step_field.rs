//! The magnetic field over each step of a recording ([`StepField`]), for the field map of
//! FootSLAM ([`crate::model::magnetic_field`]).
//!
//! Per step, the magnetometer samples since the previous step event (for the first step,
//! one step period before it) are averaged: the magnitude sample by sample, which needs no
//! orientation; the vertical part as the field's upward component, from the rotation vector
//! sample by sample where the recording has one, else from the step's mean specific force,
//! which over a whole step is gravity's direction (the walking accelerations average out).
//! A step whose mean specific force is far from 1 g (a swinging or falling sensor) has no
//! vertical part.

use super::heading_fusion::dot;
use crate::sensor::{ImuRecording, StepField, StepFields, StepTrace};

/// Standard gravity, m/s².
const G: f64 = 9.806_65;
/// The mean specific force over a step must be within this share of 1 g for it to stand
/// for gravity's direction.
const GRAVITY_TOLERANCE: f64 = 0.15;

/// The upward (east-north-up z) component of sensor-frame vector `v` under orientation
/// `q = [x, y, z, w]` (sensor → ENU): the third row of the rotation matrix times `v`.
fn up_component(q: [f64; 4], v: [f64; 3]) -> f64 {
    let [x, y, z, w] = q;
    let row = [
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    ];
    dot(row, v)
}

/// The field over each step of `trace`, from `recording`'s magnetometer; `None` when the
/// recording has none. A step without a magnetometer sample has no reading.
#[must_use]
pub fn field_per_step(recording: &ImuRecording, trace: &StepTrace) -> Option<StepFields> {
    if !recording.has_magnetometer() || trace.is_empty() {
        return None;
    }
    let samples = recording.samples();
    let steps = trace.steps();
    let first_period = steps.get(1).map_or(0.6, |s| s.t - steps[0].t);
    let mut next = 0;
    let mut fields = Vec::with_capacity(steps.len());
    for (i, step) in steps.iter().enumerate() {
        let from = if i == 0 {
            step.t - first_period
        } else {
            steps[i - 1].t
        };
        while next < samples.len() && samples[next].t <= from {
            next += 1;
        }
        let (mut magnitude, mut up_q, mut n) = (0.0, 0.0, 0usize);
        let (mut force, mut field) = ([0.0; 3], [0.0; 3]);
        let mut oriented = true;
        while next < samples.len() && samples[next].t <= step.t {
            let s = &samples[next];
            next += 1;
            let Some(m) = s.mag else { continue };
            magnitude += dot(m, m).sqrt();
            match s.orientation {
                Some(q) => up_q += up_component(q, m),
                None => oriented = false,
            }
            for k in 0..3 {
                force[k] += s.accel[k];
                field[k] += m[k];
            }
            n += 1;
        }
        if n == 0 {
            fields.push(None);
            continue;
        }
        let n = n as f64;
        let magnitude = magnitude / n;
        let vertical = if oriented {
            Some(up_q / n)
        } else {
            let g = dot(force, force).sqrt() / n;
            ((g - G).abs() <= GRAVITY_TOLERANCE * G).then(|| dot(force, field) / (g * n * n))
        };
        // The mean of the projections can exceed the mean of the magnitudes by rounding only.
        let vertical = vertical.map(|v| v.clamp(-magnitude, magnitude));
        fields.push(Some(StepField {
            magnitude,
            vertical,
        }));
    }
    // Every value is a mean of checked samples, so the checks hold.
    StepFields::new(fields).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensor::{ImuSample, Step};

    fn recording(orientation: Option<[f64; 4]>) -> ImuRecording {
        let samples = (0..200)
            .map(|i| {
                let t = 1.7e9 + f64::from(i) * 0.02;
                // Lying flat, z up; the field 20 µT north and 40 µT down, changing with time.
                let extra = if t < 1.7e9 + 2.0 { 0.0 } else { 5.0 };
                ImuSample {
                    t,
                    accel: [0.3 * f64::from(i).sin(), 0.0, G],
                    gyro: [0.0; 3],
                    mag: Some([0.0, 20.0, -40.0 - extra]),
                    orientation,
                    pressure: None,
                }
            })
            .collect();
        ImuRecording::new(samples, 0).expect("valid")
    }

    fn trace() -> StepTrace {
        let steps = (1..7)
            .map(|k| Step {
                t: 1.7e9 + 0.6 * f64::from(k),
                length: 0.7,
                dheading: 0.0,
                dz: 0.0,
                heading: None,
            })
            .collect();
        StepTrace::new(steps).expect("valid")
    }

    #[test]
    fn magnitude_and_vertical_per_step() {
        for q in [None, Some([0.0, 0.0, 0.0, 1.0])] {
            let f = field_per_step(&recording(q), &trace()).expect("has a magnetometer");
            assert_eq!(f.len(), 6);
            let first = f.get(0).unwrap();
            assert!((first.magnitude - 20f64.hypot(40.0)).abs() < 1e-9);
            assert!((first.vertical.unwrap() + 40.0).abs() < 0.01, "{first:?}");
            let last = f.get(5).unwrap();
            assert!((last.vertical.unwrap() + 45.0).abs() < 0.01, "{last:?}");
        }
    }

    #[test]
    fn turned_sensor_reads_the_same_vertical() {
        // Rolled 90° about x: sensor y is up. Quaternion for +90° about x.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let q = [h, 0.0, 0.0, h];
        let samples = (0..100)
            .map(|i| ImuSample {
                t: f64::from(i) * 0.02,
                accel: [0.0, G, 0.0],
                gyro: [0.0; 3],
                // World field (0, 20, −40) in the sensor frame: sensor y = up, sensor z = south.
                mag: Some([0.0, -40.0, -20.0]),
                orientation: Some(q),
                pressure: None,
            })
            .collect();
        let rec = ImuRecording::new(samples, 0).unwrap();
        let steps = StepTrace::new(vec![Step {
            t: 1.0,
            length: 0.7,
            dheading: 0.0,
            dz: 0.0,
            heading: None,
        }])
        .unwrap();
        let f = field_per_step(&rec, &steps).unwrap().get(0).unwrap();
        assert!((f.vertical.unwrap() + 40.0).abs() < 1e-6, "{f:?}");
        let mut no_q = rec.samples().to_vec();
        no_q.iter_mut().for_each(|s| s.orientation = None);
        let rec = ImuRecording::new(no_q, 0).unwrap();
        let f = field_per_step(&rec, &steps).unwrap().get(0).unwrap();
        assert!((f.vertical.unwrap() + 40.0).abs() < 1e-6, "{f:?}");
    }

    #[test]
    fn no_magnetometer_no_field() {
        let mut samples = recording(None).samples().to_vec();
        samples.iter_mut().for_each(|s| s.mag = None);
        let rec = ImuRecording::new(samples, 0).unwrap();
        assert!(field_per_step(&rec, &trace()).is_none());
    }
}
