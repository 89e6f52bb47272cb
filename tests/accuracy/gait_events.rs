//! What FootSLAM tolerates in a real step trace: pauses (zero-length steps while standing),
//! turns on the spot, U-turns, missed steps (two strides measured as one) and double steps
//! (one stride measured as two). Each is injected into a simulated office walk; the learned
//! track must stay about as good as on the clean trace (no corrupted map), the particle
//! cloud must not collapse, and no value may be non-finite.

use footslam::eval::{Alignment, position_errors};
use footslam::filter::{FootSlam, FootSlamConfig};
use footslam::io::TimedPoint;
use footslam::sensor::Step;
use footslam::sim::{SimConfig, simulate};
use std::f64::consts::PI;

/// One gait event, applied at a step index of the clean trace.
#[derive(Debug, Clone, Copy)]
enum Event {
    /// The walker stands still: `n` zero-length steps (a detector's false steps).
    Pause(usize),
    /// Turns on the spot by `angle` in `n` zero-length steps before going on as before.
    TurnOnSpot(f64, usize),
    /// Walks back two steps the way it came, then turns again and goes on.
    UTurn,
    /// Two strides measured as one (lengths summed, heading changes summed).
    Missed,
    /// One stride measured as two halves.
    Doubled,
}

/// The trace with `events` applied (sorted by index), and for each output step the index
/// of the clean step whose truth it ends at (`None` inside an inserted detour).
fn inject(steps: &[Step], events: &[(usize, Event)]) -> (Vec<Step>, Vec<Option<usize>>) {
    let (mut out, mut at) = (Vec::new(), Vec::new());
    let mut i = 0;
    let mut next = events.iter().peekable();
    while i < steps.len() {
        let s = steps[i];
        let t_prev = out.last().map_or(s.t - 1.0, |p: &Step| p.t);
        let dt = (s.t - t_prev).max(0.01);
        let inserted = |k: usize, n: usize| t_prev + dt * (k as f64 + 1.0) / (n as f64 + 2.0);
        match next.next_if(|(k, _)| *k == i).map(|&(_, e)| e) {
            Some(Event::Pause(n)) => {
                for k in 0..n {
                    out.push(Step {
                        t: inserted(k, n),
                        length: 0.0,
                        dheading: 0.0,
                        ..s
                    });
                    at.push(None);
                }
                out.push(Step { t: s.t, ..s });
                at.push(Some(i));
            }
            Some(Event::TurnOnSpot(angle, n)) => {
                for k in 0..n {
                    out.push(Step {
                        t: inserted(k, n),
                        length: 0.0,
                        dheading: angle / n as f64,
                        ..s
                    });
                    at.push(None);
                }
                // Turn back within the step that follows: the path goes on unchanged.
                out.push(Step {
                    dheading: s.dheading - angle,
                    ..s
                });
                at.push(Some(i));
            }
            Some(Event::UTurn) => {
                // Back two strides of 0.7 m and forward again, then the step itself.
                let back = [(PI, 0.7), (0.0, 0.7), (PI, 0.7), (0.0, 0.7)];
                for (k, (dh, len)) in back.iter().enumerate() {
                    out.push(Step {
                        t: inserted(k, back.len()),
                        length: *len,
                        dheading: *dh,
                        ..s
                    });
                    at.push(None);
                }
                out.push(s);
                at.push(Some(i));
            }
            Some(Event::Missed) if i + 1 < steps.len() => {
                let n = steps[i + 1];
                out.push(Step {
                    t: n.t,
                    length: s.length + n.length,
                    dheading: s.dheading + n.dheading,
                    dz: s.dz + n.dz,
                    heading: n.heading,
                });
                at.push(Some(i + 1));
                i += 1;
            }
            Some(Event::Doubled) => {
                out.push(Step {
                    t: inserted(0, 1),
                    length: s.length / 2.0,
                    dheading: s.dheading / 2.0,
                    dz: s.dz / 2.0,
                    heading: s.heading,
                });
                at.push(None);
                out.push(Step {
                    length: s.length / 2.0,
                    dheading: s.dheading / 2.0,
                    dz: s.dz / 2.0,
                    ..s
                });
                at.push(Some(i));
            }
            _ => {
                out.push(s);
                at.push(Some(i));
            }
        }
        i += 1;
    }
    (out, at)
}

/// Learns `steps`; returns the rigidly aligned p95 error at the steps that end on the
/// truth, and the smallest effective sample size as a share of the particles.
fn learn(steps: &[Step], at: &[Option<usize>], truth: &[TimedPoint]) -> (f64, f64) {
    let config = FootSlamConfig {
        particles: 3000,
        seed: 7,
        ..FootSlamConfig::default()
    };
    let mut filter = FootSlam::new(config).expect("filter");
    for s in steps {
        filter.update(s);
    }
    let estimate = filter.estimate();
    assert!(
        estimate
            .path
            .iter()
            .all(|p| p.x.is_finite() && p.y.is_finite()),
        "non-finite path"
    );
    let (mut t, mut k) = (Vec::new(), Vec::new());
    for (p, a) in estimate.path.iter().zip(at) {
        if let Some(i) = a {
            t.push(truth[*i]);
            k.push(TimedPoint {
                t: truth[*i].t,
                x: p.x,
                y: p.y,
            });
        }
    }
    let errors = position_errors(&t, &k, Alignment::Rigid).expect("errors");
    let min_ess = filter
        .ess_history()
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    (errors.p95, min_ess / 3000.0)
}

#[test]
fn pauses_turns_u_turns_missed_and_double_steps_leave_the_map_intact() {
    let sim = simulate(&SimConfig {
        seed: 5,
        ..SimConfig::default()
    })
    .expect("simulation");
    let steps = sim.steps.steps();
    let truth: Vec<TimedPoint> = sim
        .truth
        .poses
        .iter()
        .map(|p| TimedPoint {
            t: p.t,
            x: p.x,
            y: p.y,
        })
        .collect();
    let clean_at: Vec<Option<usize>> = (0..steps.len()).map(Some).collect();
    let (clean, clean_ess) = learn(steps, &clean_at, &truth);
    assert!(clean < 2.0, "clean walk p95 {clean:.2} m");
    let n = steps.len();
    let every = |e: Event| -> Vec<(usize, Event)> { (1..8).map(|k| (k * n / 8, e)).collect() };
    let cases = [
        ("pauses", every(Event::Pause(8))),
        ("turns on the spot", every(Event::TurnOnSpot(PI / 2.0, 3))),
        ("U-turns", every(Event::UTurn)),
        ("missed steps", every(Event::Missed)),
        ("double steps", every(Event::Doubled)),
    ];
    for (name, events) in cases {
        let (trace, at) = inject(steps, &events);
        let (p95, ess) = learn(&trace, &at, &truth);
        eprintln!(
            "{name}: p95 {p95:.2} m (clean {clean:.2} m), min ESS {ess:.3} (clean {clean_ess:.3})"
        );
        assert!(
            p95 <= 1.5 * clean + 0.3,
            "{name}: p95 {p95:.2} m against {clean:.2} m on the clean walk"
        );
        assert!(
            ess > 0.01,
            "{name}: the particle cloud collapsed (min ESS {ess:.4})"
        );
    }
}
