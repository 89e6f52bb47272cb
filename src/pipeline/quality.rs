//! A run's quality verdict — `ok`, `doubtful` or `poor`, with the reasons — the one place
//! where every command's `summary.json` (key `quality`) and its last terminal line say
//! whether the answer can be trusted. A bad answer otherwise looks exactly like a good one:
//! a walk tracked on another building's plan still gets a track, and a walk FootSLAM folded
//! onto itself still gets a map.
//!
//! What feeds it, per command (docs/robustness.md lists it for users):
//!
//! * **track** and each walk of **survey** — how the steps fitted the plan
//!   ([`PlanFit`]): height changes the plan's surfaces do not explain (a walk that climbs a
//!   storey on a one-level plan), steps at which every particle hit a wall, restarts from
//!   the last good belief (history fitting), a walk never settled on one place, a prior cut
//!   at the particle cap;
//! * **learn** — the answer against dead reckoning ([`Departure`]: a path folded by the
//!   map term alone) and how far the final particles' paths disagree;
//! * **steps** — the detector's own warnings (the recording does not look like the mount,
//!   axes that disagree).
//!
//! Every threshold is in [`QualityConfig`], each default measured: the bundled walks and
//! the shared real recordings on their own plans come out `ok` (with the few real walks
//! that leave their plan for long `doubtful`), walks on another building's plan `poor`.

use super::track_records::{PlanFit, RecoveryEvent};
use crate::filter::Recovery;
use crate::filter::departure::{Departure, Trust};
use serde::{Deserialize, Serialize};

/// How far a run's answer can be trusted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Nothing speaks against the answer.
    Ok,
    /// Some evidence speaks against it: use it with care.
    Doubtful,
    /// The evidence says the answer is wrong (e.g. the walk does not fit the plan).
    Poor,
}

impl Verdict {
    /// The verdict's name in `summary.json`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Ok => "ok",
            Self::Doubtful => "doubtful",
            Self::Poor => "poor",
        }
    }
}

/// One piece of evidence against a run's answer.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reason {
    /// A stable identifier (e.g. `unexplained_climb`), for scripts.
    pub code: &'static str,
    /// What this reason alone makes of the answer.
    pub verdict: Verdict,
    /// What was found, in words.
    pub message: String,
}

/// A run's verdict and the reasons for it (none when `ok`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Quality {
    /// The worst verdict of the reasons (`ok` without any).
    pub verdict: Verdict,
    /// The evidence, worst first.
    pub reasons: Vec<Reason>,
}

impl Default for Quality {
    fn default() -> Self {
        Self::of(Vec::new())
    }
}

impl Quality {
    /// The verdict of `reasons`: the worst of theirs.
    #[must_use]
    pub fn of(mut reasons: Vec<Reason>) -> Self {
        reasons.sort_by_key(|r| std::cmp::Reverse(r.verdict));
        Self {
            verdict: reasons.first().map_or(Verdict::Ok, |r| r.verdict),
            reasons,
        }
    }

    /// The verdict of several parts (e.g. the walks of a batch), each part's reasons
    /// prefixed with its name.
    pub fn combined<'q>(parts: impl IntoIterator<Item = (String, &'q Quality)>) -> Self {
        Self::of(
            parts
                .into_iter()
                .flat_map(|(name, q)| {
                    q.reasons.iter().map(move |r| Reason {
                        message: format!("{name}: {}", r.message),
                        ..r.clone()
                    })
                })
                .collect(),
        )
    }

    /// The verdict in one line: `ok`, or `doubtful: reason; reason`.
    #[must_use]
    pub fn line(&self) -> String {
        if self.reasons.is_empty() {
            return self.verdict.name().into();
        }
        let reasons: Vec<&str> = self.reasons.iter().map(|r| r.message.as_str()).collect();
        format!("{}: {}", self.verdict.name(), reasons.join("; "))
    }
}

/// The thresholds of the verdicts; every default in one place.
///
/// | field | default | meaning |
/// |---|---|---|
/// | `max_unexplained_climb_m` | 1.5 m | height change the plan's surfaces may leave unexplained (half a storey) before the walk is `poor` on the plan |
/// | `deaths_share` | 0.08 | share of steps at which every particle may hit a wall before `doubtful` (real phone walks on their own plan: ≤ 0.06, but for walks that leave it) |
/// | `deaths_min` | 5 | … and at least this many such steps |
/// | `restarts_per_100_steps` | 1.0 | restarts from the last good belief (history fitting) per 100 steps before `poor` (real walks on their own plan: at most one a walk; walks on another building's plan 3–6 per 100 steps) |
/// | `restarts_min` | 3 | … and at least this many |
/// | `max_path_spread_m` | 2.0 m | median disagreement of FootSLAM's final paths before `doubtful` |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct QualityConfig {
    /// See the table.
    pub max_unexplained_climb_m: f64,
    /// See the table.
    pub deaths_share: f64,
    /// See the table.
    pub deaths_min: usize,
    /// See the table.
    pub restarts_per_100_steps: f64,
    /// See the table.
    pub restarts_min: usize,
    /// See the table.
    pub max_path_spread_m: f64,
}

impl Default for QualityConfig {
    fn default() -> Self {
        Self {
            max_unexplained_climb_m: 1.5,
            deaths_share: 0.08,
            deaths_min: 5,
            restarts_per_100_steps: 1.0,
            restarts_min: 3,
            max_path_spread_m: 2.0,
        }
    }
}

/// What a tracked walk shows of its fit to the plan ([`track_quality`]).
#[derive(Debug, Clone, Copy)]
pub struct TrackEvidence<'a> {
    /// The steps' fit ([`super::StepRecords::fit`]).
    pub fit: &'a PlanFit,
    /// The steps at which every particle died.
    pub recoveries: &'a [RecoveryEvent],
    /// Steps of the walk.
    pub steps: usize,
    /// Whether the filter ever settled on one place, or the whole-walk answer made any
    /// step certain.
    pub settled: bool,
    /// Prior draws cut at the particle cap before the KLD bound was met.
    pub capped_draws: usize,
    /// The step at which the ancestry outgrew `smoothing_max_nodes` and the whole-walk
    /// answer was given up.
    pub smoothing_dropped_at: Option<usize>,
}

/// The verdict of a tracked walk.
#[must_use]
pub fn track_quality(e: &TrackEvidence, config: &QualityConfig) -> Quality {
    let mut reasons = Vec::new();
    let climb = e.fit.unexplained_climb_m;
    if climb >= config.max_unexplained_climb_m {
        reasons.push(Reason {
            code: "unexplained_climb",
            verdict: Verdict::Poor,
            message: format!(
                "the walk climbs or descends {climb:.1} m that the plan's floors and stairs do \
                 not explain (another building's plan, or one without these floors?)"
            ),
        });
    }
    let restarts = e
        .recoveries
        .iter()
        .filter(|r| matches!(r.recovery, Recovery::History { .. }))
        .count();
    let per_100 = |n: usize| 100.0 * n as f64 / e.steps.max(1) as f64;
    if restarts >= config.restarts_min && per_100(restarts) >= config.restarts_per_100_steps {
        reasons.push(Reason {
            code: "repeated_restarts",
            verdict: Verdict::Poor,
            message: format!(
                "the filter restarted from its last good belief {restarts} times in {} steps: \
                 the walk keeps running into the plan's walls (another building's plan, or \
                 the wrong origin or level?)",
                e.steps
            ),
        });
    }
    let deaths = e.recoveries.len();
    if deaths >= config.deaths_min && deaths as f64 >= config.deaths_share * e.steps as f64 {
        reasons.push(Reason {
            code: "walls_refuse_steps",
            verdict: Verdict::Doubtful,
            message: format!(
                "every particle hit a wall at {deaths} of {} steps ({:.0} %): the walk often \
                 leaves the plan's walkable space",
                e.steps,
                per_100(deaths)
            ),
        });
    }
    if !e.settled && e.steps > 0 {
        reasons.push(Reason {
            code: "not_settled",
            verdict: Verdict::Doubtful,
            message: "the walk never settled on one place: several places of the plan fit it \
                      (track.csv's `certain` is 0 throughout); a known start would settle it"
                .into(),
        });
    }
    if let Some(step) = e.smoothing_dropped_at {
        reasons.push(Reason {
            code: "smoothing_dropped",
            verdict: Verdict::Doubtful,
            message: format!(
                "the belief had not narrowed by step {step} and its ancestry outgrew \
                 smoothing_max_nodes: the whole-walk answer was given up, track.csv holds the \
                 filter's causal estimates"
            ),
        });
    }
    if e.capped_draws > 0 {
        reasons.push(Reason {
            code: "thin_prior",
            verdict: Verdict::Doubtful,
            message: "the prior over the plan stopped at the particle cap before its bound was \
                      met: the start may have been missed"
                .into(),
        });
    }
    Quality::of(reasons)
}

/// The verdict of a learned walk from its answer against dead reckoning and the spread of
/// its final paths (median over the steps, metres).
#[must_use]
pub fn learn_quality(
    departure: &Departure,
    spread_median_m: f64,
    config: &QualityConfig,
) -> Quality {
    let mut reasons = Vec::new();
    if departure.trust == Trust::DeadReckoning {
        let (verdict, answer) = if departure.answer == Trust::DeadReckoning {
            (
                Verdict::Doubtful,
                "the answer is the dead-reckoned path and the map adds nothing to it",
            )
        } else {
            (Verdict::Poor, "trust dead_reckoning.csv over track.csv")
        };
        reasons.push(Reason {
            code: "folded_by_map",
            verdict,
            message: format!(
                "the learned path departs {:.1} m (p95) from dead reckoning where only the map \
                 term supports it ({:.0} % of its revisits implausible for dead reckoning): {answer}",
                departure.p95_m,
                100.0 * departure.implausible_share
            ),
        });
    }
    if spread_median_m > config.max_path_spread_m {
        reasons.push(Reason {
            code: "paths_disagree",
            verdict: Verdict::Doubtful,
            message: format!(
                "the final particles' paths disagree by {spread_median_m:.1} m (median over the \
                 steps): the walk's shape is not pinned"
            ),
        });
    }
    Quality::of(reasons)
}

/// The verdict of a step detection from its warnings (each makes the steps doubtful).
#[must_use]
pub fn steps_quality(warnings: &[String]) -> Quality {
    Quality::of(
        warnings
            .iter()
            .map(|w| Reason {
                code: "detector_warning",
                verdict: Verdict::Doubtful,
                message: w.clone(),
            })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::StepFit;

    fn fit(survival: f32, dz: &[f32]) -> PlanFit {
        let mut f = PlanFit::default();
        for &d in dz {
            f.add(&StepFit {
                survival,
                unexplained_dz: d,
            });
        }
        f
    }

    fn deaths(steps: &[usize], history: bool) -> Vec<RecoveryEvent> {
        steps
            .iter()
            .map(|&step| RecoveryEvent {
                step,
                t: step as f64,
                recovery: if history {
                    Recovery::History {
                        radius_m: 1.0,
                        steps: 1,
                    }
                } else {
                    Recovery::HeadingSearch {
                        correction_deg: 10.0,
                    }
                },
            })
            .collect()
    }

    fn evidence<'a>(fit: &'a PlanFit, recoveries: &'a [RecoveryEvent]) -> TrackEvidence<'a> {
        TrackEvidence {
            fit,
            recoveries,
            steps: fit.steps,
            settled: true,
            capped_draws: 0,
            smoothing_dropped_at: None,
        }
    }

    #[test]
    fn a_walk_that_fits_is_ok() {
        let f = fit(0.95, &[0.05, -0.05, 0.02, -0.02]);
        let q = track_quality(&evidence(&f, &[]), &QualityConfig::default());
        assert_eq!(q.verdict, Verdict::Ok);
        assert!(q.reasons.is_empty());
        assert_eq!(q.line(), "ok");
    }

    #[test]
    fn a_storey_the_plan_does_not_have_is_poor() {
        // 20 steps climbing 0.15 m each that no surface explains: 3 m.
        let f = fit(0.95, &[0.15; 20]);
        let q = track_quality(&evidence(&f, &[]), &QualityConfig::default());
        assert_eq!(q.verdict, Verdict::Poor);
        assert_eq!(q.reasons[0].code, "unexplained_climb");
        assert!(
            q.line()
                .starts_with("poor: the walk climbs or descends 3.0 m")
        );
    }

    #[test]
    fn noise_about_zero_does_not_add_up() {
        // Height noise that averages out: the running sum never strays far.
        let dz: Vec<f32> = (0..1000)
            .map(|i| if i % 2 == 0 { 0.1 } else { -0.1 })
            .collect();
        let f = fit(0.95, &dz);
        assert!(f.unexplained_climb_m < 0.2);
    }

    #[test]
    fn deaths_and_restarts_grade_by_their_rate() {
        let f = fit(0.6, &[0.0; 100]);
        let config = QualityConfig::default();
        // 4 deaths in 100 steps: within what real walks show.
        let few = deaths(&[10, 20, 30, 40], false);
        assert_eq!(
            track_quality(&evidence(&f, &few), &config).verdict,
            Verdict::Ok
        );
        // 10 deaths: doubtful.
        let many = deaths(&(1..=10).map(|i| i * 9).collect::<Vec<_>>(), false);
        let q = track_quality(&evidence(&f, &many), &config);
        assert_eq!(q.verdict, Verdict::Doubtful);
        assert_eq!(q.reasons[0].code, "walls_refuse_steps");
        // 3 restarts in 100 steps: poor.
        let restarts = deaths(&[20, 50, 80], true);
        let q = track_quality(&evidence(&f, &restarts), &config);
        assert_eq!(q.verdict, Verdict::Poor);
        assert_eq!(q.reasons[0].code, "repeated_restarts");
        // The same 3 in 1,000 steps: a long walk's occasional restart.
        let long = fit(0.9, &[0.0; 1000]);
        assert_eq!(
            track_quality(&evidence(&long, &restarts), &config).verdict,
            Verdict::Ok
        );
    }

    #[test]
    fn an_unsettled_walk_is_doubtful() {
        let f = fit(0.9, &[0.0; 10]);
        let mut e = evidence(&f, &[]);
        e.settled = false;
        let q = track_quality(&e, &QualityConfig::default());
        assert_eq!(q.verdict, Verdict::Doubtful);
        assert_eq!(q.reasons[0].code, "not_settled");
    }

    fn departure(trust: Trust, answer: Trust) -> Departure {
        Departure {
            p95_m: 5.2,
            share_of_length: 0.05,
            revisits: 40,
            plausible_revisits: 0,
            other_evidence: Vec::new(),
            implausible_share: 1.0,
            trust,
            answer,
        }
    }

    #[test]
    fn a_path_folded_by_the_map_is_said() {
        let config = QualityConfig::default();
        let fine = departure(Trust::Learned, Trust::Learned);
        assert_eq!(learn_quality(&fine, 0.3, &config).verdict, Verdict::Ok);
        // Folded and answered with dead reckoning: the map adds nothing.
        let q = learn_quality(
            &departure(Trust::DeadReckoning, Trust::DeadReckoning),
            0.3,
            &config,
        );
        assert_eq!(q.verdict, Verdict::Doubtful);
        assert_eq!(q.reasons[0].code, "folded_by_map");
        // Folded, but the fall-back is off: the answer itself is the folded path.
        let q = learn_quality(
            &departure(Trust::DeadReckoning, Trust::Learned),
            0.3,
            &config,
        );
        assert_eq!(q.verdict, Verdict::Poor);
        assert!(q.line().contains("trust dead_reckoning.csv"));
        // Final paths that disagree by metres.
        let q = learn_quality(&fine, 3.5, &config);
        assert_eq!(q.verdict, Verdict::Doubtful);
        assert_eq!(q.reasons[0].code, "paths_disagree");
    }

    #[test]
    fn combined_takes_the_worst_and_names_the_parts() {
        let ok = Quality::default();
        let bad = steps_quality(&["axes disagree".into()]);
        let q = Quality::combined([("walk 1".to_string(), &ok), ("walk 2".to_string(), &bad)]);
        assert_eq!(q.verdict, Verdict::Doubtful);
        assert_eq!(q.reasons[0].message, "walk 2: axes disagree");
    }
}
