use super::*;

/// The default configuration with the prior switched on.
fn on() -> AxesConfig {
    AxesConfig {
        enabled: true,
        ..Default::default()
    }
}

/// A walk of straight legs of `leg` steps (0.7 m, 0.6 s apart), turning by each of `turns`
/// in one step between legs.
fn walk(turns: &[f64], leg: usize) -> Vec<Step> {
    let mut steps = Vec::new();
    let mut t = 1.7e9;
    let mut push = |dheading: f64, steps: &mut Vec<Step>| {
        t += 0.6;
        steps.push(Step {
            t,
            length: 0.7,
            dheading,
            dz: 0.0,
            heading: None,
        });
    };
    for _ in 0..leg {
        push(0.0, &mut steps);
    }
    for &turn in turns {
        push(turn.to_radians(), &mut steps);
        for _ in 0..leg {
            push(0.0, &mut steps);
        }
    }
    steps
}

#[test]
fn right_angled_walk_shows_axes() {
    let turns = [90.0, 90.0, -90.0, 180.0, 90.0, -90.0, 90.0, 90.0];
    let e = AxisEvidence::new(&walk(&turns, 12), &on());
    assert_eq!(e.turns, 8);
    assert!(e.alignment > 0.99, "{}", e.alignment);
    assert!(e.active);
    assert!(e.is_straight(5) && !e.is_straight(12) && !e.is_straight(10_000));
}

#[test]
fn turns_at_any_angle_show_none() {
    let turns = [
        37.0, 113.0, -71.0, 52.0, -128.0, 66.0, -23.0, 101.0, -49.0, 144.0,
    ];
    let e = AxisEvidence::new(&walk(&turns, 12), &on());
    assert_eq!(e.turns, 10);
    assert!(
        !e.active,
        "alignment {} {}",
        e.alignment, e.diagonal_alignment
    );
    assert_eq!(e.directions, 0);
}

#[test]
fn turns_by_multiples_of_45_degrees_show_eight_directions() {
    let turns = [45.0, 90.0, -135.0, 45.0, -45.0, 135.0, 90.0, -45.0, 45.0];
    let e = AxisEvidence::new(&walk(&turns, 12), &on());
    assert!(e.active && e.directions == 8, "{e:?}");
    let right = AxisEvidence::new(&walk(&[90.0, -90.0, 90.0, 180.0], 12), &on());
    assert_eq!(right.directions, 4);
    let no_diagonals = AxesConfig {
        diagonals: false,
        ..on()
    };
    assert!(!AxisEvidence::new(&walk(&turns, 12), &no_diagonals).active);
}

#[test]
fn eight_directions_fold_at_45_degrees() {
    let model = AxisLikelihood::new(AxesConfig::default(), 8);
    let mut state = AxisState::default();
    for _ in 0..8 {
        state.weigh_and_learn(&model, 0.7, 0.0);
    }
    let at = |deg: f64| {
        let mut s = state;
        let a = deg.to_radians();
        s.weigh_and_learn(&model, 0.7 * a.cos(), 0.7 * a.sin())
    };
    assert!((at(0.0) - at(45.0)).abs() < 1e-6 && at(45.0) > at(22.0));
}

#[test]
fn there_and_back_along_one_corridor_is_one_axis() {
    let e = AxisEvidence::new(&walk(&[180.0, -180.0, 180.0, -180.0], 14), &on());
    assert_eq!(e.turns, 4);
    assert!(e.active, "alignment {}", e.alignment);
}

#[test]
fn a_few_right_angles_are_not_enough() {
    // Two turns cannot tell a rectangular building from chance.
    let e = AxisEvidence::new(&walk(&[90.0, -90.0], 12), &on());
    assert_eq!(e.turns, 2);
    assert!(!e.active);
}

#[test]
fn a_round_walk_has_no_straight_stretches() {
    let steps: Vec<Step> = (0..200)
        .map(|k| Step {
            t: 10.0 + 0.6 * f64::from(k),
            length: 0.7,
            dheading: 6.0_f64.to_radians(),
            dz: 0.0,
            heading: None,
        })
        .collect();
    let e = AxisEvidence::new(&steps, &on());
    assert_eq!(e.straight_m, 0.0);
    assert!(!e.active);
}

#[test]
fn disabled_prior_never_acts() {
    let e = AxisEvidence::new(&walk(&[90.0; 8], 12), &AxesConfig::default());
    assert!(e.alignment > 0.99 && e.shows_axes() && !e.active);
}

#[test]
fn steps_near_an_axis_outweigh_steps_off_it() {
    let model = AxisLikelihood::new(AxesConfig::default(), 4);
    let mut state = AxisState::default();
    // Nothing weighs before the axes exist (5 m of straight walking at 10°).
    for _ in 0..8 {
        let (dx, dy) = (
            0.7 * 10f64.to_radians().cos(),
            0.7 * 10f64.to_radians().sin(),
        );
        assert_eq!(state.weigh_and_learn(&model, dx, dy), 0.0);
    }
    let axis = state.axis(5.0, 4.0).expect("axes after 5.6 m");
    assert!((axis - 10f64.to_radians()).abs() < 1e-4);
    let at = |deg: f64| {
        let mut s = state;
        let a = deg.to_radians();
        s.weigh_and_learn(&model, 0.7 * a.cos(), 0.7 * a.sin())
    };
    // Every axis direction counts alike (eq. 1 folds them together).
    assert!((at(10.0) - at(100.0)).abs() < 1e-6 && (at(10.0) - at(-170.0)).abs() < 1e-6);
    assert!(at(10.0) > at(14.0) && at(14.0) > at(25.0));
    // Far from every axis the uniform floor bounds the cost: ln ε, tempered by ℓ / L.
    let floor = 0.7 / 5.0 * 0.3f64.ln();
    assert!((at(55.0) - floor).abs() < 1e-3, "{}", at(55.0));
    // A step off the axes does not turn them.
    let mut s = state;
    let off = 40f64.to_radians();
    s.weigh_and_learn(&model, 5.0 * off.cos(), 5.0 * off.sin());
    assert_eq!(s, state);
}

#[test]
fn fold_wraps_into_half_open_band() {
    for (x, want) in [
        (0.0, 0.0),
        (100.0, 10.0),
        (-100.0, -10.0),
        (44.0, 44.0),
        (46.0, -44.0),
    ] {
        let got = fold(f64::to_radians(x), FRAC_PI_2).to_degrees();
        assert!((got - want).abs() < 1e-9, "{x} → {got}");
    }
}

#[test]
fn validate_names_bad_fields() {
    let bad = AxesConfig {
        sigma: f64::NAN,
        ..Default::default()
    };
    assert!(
        bad.validate()
            .unwrap_err()
            .to_string()
            .contains("axes.sigma")
    );
    assert!(AxesConfig::default().validate().is_ok());
}
