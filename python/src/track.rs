//! `footslam.track`: one walk located and tracked on a known floor plan, as `footslam
//! track` runs it.

use crate::checks::{check_height_changes, check_scans_match, read_scans};
use crate::inputs;
use crate::outputs::{Column, columns, json_object};
use crate::tables::{self, STEPS, WIFI};
use crate::{Reporter, detached, fail, py_error, with_context};
use footslam::filter::{RfLocaliser, RfMode, TrackerConfig};
use footslam::io::TrackPoint;
use footslam::map::{FloorTopology, grow_plan};
use footslam::model::TransitionPrior;
use footslam::model::wifi_distance::Normalisation;
use footslam::pipeline::{RadioInput, SAME_ORIGIN_M, SnapshotSteps, TrackInput};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::json;

/// One smoothed row of the answer: the point, certain, hypotheses, spread, share.
type SmoothedRow = (TrackPoint, bool, usize, f64, f64);

/// What a tracking run gives, ready for Python.
struct TrackOut {
    /// The smoothed answer (`None` online).
    smoothed: Option<Vec<SmoothedRow>>,
    filtered: Vec<TrackPoint>,
    /// Per step: particles, clusters (-1: not clustered), localised.
    records: Vec<(i64, i64, bool)>,
    summary: serde_json::Value,
}

/// `obj` unless it is Python's `None`.
fn present<'a, 'py>(obj: Option<&'a Bound<'py, PyAny>>) -> Option<&'a Bound<'py, PyAny>> {
    obj.filter(|o| !o.is_none())
}

/// Tracks one walk on a known floor plan (``footslam track``): from an unknown start
/// (uniform over the plan) or a known one, with a radio map and the walk's WiFi when given.
///
/// Args:
///     plan: the floor plan: a path or GeoJSON dict (walkable polygons with ``level`` and
///         ``z``; e.g. :func:`plan`'s ``plan``).
///     steps: the walk's step trace: a CSV path, a pandas DataFrame or a dict of 1-D arrays
///         with columns ``t,length,dheading[,dz][,heading]``.
///     start: the known start ``"X,Y[,HEADING[,LEVEL]]"``, ``(x, y[, heading[, level]])``
///         or a dict (local metres, radians from east); default unknown.
///     wifi, radio_map: the walk's WiFi log (``t,bssid,rssi[,ssid,freq]``) and a radio map
///         (path or GeoJSON dict, as :func:`survey` makes): RF-assisted localisation.
///     hexmap: a map learned by :func:`learn` in the plan's frame: its transitions become a
///         motion prior; ``hexmap_weight`` its exponent (default 1).
///     origin: ``(lat, lon)`` of the local frame; overrides the plan's ``origin``.
///     plan_margin: grow the plan by this many metres first (for learned plans).
///     one_floor: allow steps without ``dz`` on a plan of several levels.
///     config: tracker configuration: a dict with the keys of ``config.json``, or a TOML
///         or JSON file.
///     seed: overrides the configuration's.
///     ignore_heading: ignore the steps' absolute ``heading`` column.
///     online: causal answers only (no smoothing): ``track`` is then the filtered track.
///     rf_mode: ``"auto"`` (the default), ``"evidence"``, ``"containment"``,
///         ``"probabilistic"`` or ``"prior-only"``.
///     rf_distance: ``"paper"`` or ``"sqrt"``; rf_epsilon: the region threshold, dBm;
///     rf_every_step: apply the latest scan at every step.
///     threads: worker threads (default: one per core); results do not depend on it.
///     progress: a callable ``progress(stage, done, total)`` told of the run's progress
///         from its start (``done`` 0) to its end (``done == total``), at most a few hundred
///         times a stage — a tqdm bar or a log line (default: none). An exception it
///         raises is raised when the run is over.
///
/// Returns:
///     dict: ``track`` — the answer, columns ``t`` (s), ``x``, ``y``, ``z`` (m, local
///     frame), ``level``, ``certain`` (bool), ``hypotheses``, ``spread`` (m), ``share``: one row per step with a
///     smoothed estimate, as ``track.csv``; ``filtered`` — each step's estimate as the
///     filter saw it, from localisation on (``t, x, y, z, level``, as
///     ``track_filtered.csv``); ``steps`` — per step ``particles``, ``clusters`` (-1: not
///     clustered), ``localised``; ``summary`` and ``config``.
///
/// Raises:
///     FootslamError: bad data or configuration, inputs that do not belong together.
///     FileNotFoundError: a path names no file.
///     TypeError: an input of the wrong type, or a column that is not numbers.
#[pyfunction]
#[pyo3(signature = (
    plan, steps, *, start=None, wifi=None, radio_map=None, hexmap=None, hexmap_weight=None,
    origin=None, plan_margin=None, one_floor=false, config=None, seed=None,
    ignore_heading=false, online=false, rf_mode=None, rf_distance=None, rf_epsilon=None,
    rf_every_step=false, threads=None, progress=None
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn track<'py>(
    py: Python<'py>,
    plan: &Bound<'py, PyAny>,
    steps: &Bound<'py, PyAny>,
    start: Option<&Bound<'py, PyAny>>,
    wifi: Option<&Bound<'py, PyAny>>,
    radio_map: Option<&Bound<'py, PyAny>>,
    hexmap: Option<&Bound<'py, PyAny>>,
    hexmap_weight: Option<f64>,
    origin: Option<(f64, f64)>,
    plan_margin: Option<f64>,
    one_floor: bool,
    config: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    ignore_heading: bool,
    online: bool,
    rf_mode: Option<&str>,
    rf_distance: Option<&str>,
    rf_epsilon: Option<f64>,
    rf_every_step: bool,
    threads: Option<&Bound<'py, PyAny>>,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let seed = crate::int_arg("seed", seed, u64::MAX)?;
    let threads = crate::int_arg("threads", threads, 1 << 20)?.map(|n| n as usize);
    // The configuration, with the keyword overrides (`footslam track`'s flags).
    let mut config: TrackerConfig = inputs::config(config)?;
    if let Some(s) = seed {
        config.seed = s;
    }
    if let Some(s) = inputs::start(start, "start")? {
        config.start = Some(s);
    }
    if ignore_heading {
        config.heading.enabled = false;
    }
    if let Some(m) = rf_mode {
        config.rf.mode = match m {
            "auto" => RfMode::Auto,
            "evidence" => RfMode::Evidence,
            "containment" => RfMode::Containment,
            "probabilistic" => RfMode::Probabilistic,
            "prior-only" | "prior_only" => RfMode::PriorOnly,
            other => {
                return Err(PyValueError::new_err(format!(
                    "rf_mode must be \"auto\", \"evidence\", \"containment\", \"probabilistic\" \
                     or \"prior-only\", got {other:?}"
                )));
            }
        };
    }
    if rf_epsilon.is_some() {
        config.rf.epsilon = rf_epsilon;
    }
    if let Some(d) = rf_distance {
        config.rf.distance = Some(match d {
            "paper" => Normalisation::Paper,
            "sqrt" => Normalisation::Sqrt,
            other => {
                return Err(PyValueError::new_err(format!(
                    "rf_distance must be \"paper\" or \"sqrt\", got {other:?}"
                )));
            }
        });
    }
    if rf_every_step {
        config.rf.every_step = true;
    }
    if online {
        config.smoothing = false;
    }
    if let Some(w) = hexmap_weight {
        config.transitions.weight = w;
    }
    config.validate().map_err(py_error)?;
    let (wifi, radio_map) = match (present(wifi), present(radio_map)) {
        (Some(w), Some(r)) => (Some(w), Some(r)),
        (None, None) => (None, None),
        _ => {
            return Err(fail(
                "radio_map and wifi go together: RF-assisted tracking needs the radio map and \
                 the walk's WiFi log",
            ));
        }
    };
    let plan_doc = inputs::document(plan, "floor plan", "plan")?;
    let steps_table = tables::table(steps, &STEPS, "steps")?;
    let hexmap_doc = present(hexmap)
        .map(|o| inputs::document(o, "learned map", "hexmap"))
        .transpose()?;
    let radio_doc = radio_map
        .map(|o| inputs::document(o, "radio map", "radio_map"))
        .transpose()?;
    let wifi_table = wifi.map(|o| tables::table(o, &WIFI, "wifi")).transpose()?;
    let origin = inputs::origin(origin)?;
    let report = Reporter::new(progress)?;
    let out = detached(py, threads, || {
        let plan_label = plan_doc.label();
        let (plan, frame) = plan_doc.floor_plan(origin).map_err(py_error)?;
        let plan = match plan_margin {
            Some(margin) => grow_plan(&plan, margin)
                .map_err(with_context(format!("{plan_label}: plan_margin {margin}")))?,
            None => plan,
        };
        let transitions = match &hexmap_doc {
            Some(doc) => {
                let stored = doc.stored_map().map_err(py_error)?;
                let off = frame.distance_to(&stored.frame);
                if off > SAME_ORIGIN_M {
                    return Err(fail(format!(
                        "{}: its origin lies {off:.3} m from the plan's ({plan_label}): the \
                         learned map must be in the plan's frame (the map and the plan.geojson \
                         of one learn run)",
                        doc.label()
                    )));
                }
                Some(TransitionPrior::new(&stored.map, config.transitions).map_err(py_error)?)
            }
            None => None,
        };
        let trace = steps_table.steps().map_err(py_error)?;
        check_height_changes(&steps_table, &plan_label, &plan, one_floor)?;
        let topology = FloorTopology::build(&plan, &config.topology).map_err(with_context(
            format!("{plan_label}: not a usable floor plan"),
        ))?;
        let radio = match (&radio_doc, &wifi_table) {
            (Some(doc), Some(table)) => {
                let (map, _) = doc.radio_map(Some(frame)).map_err(py_error)?;
                let (scans, warning) = read_scans(table, &trace)?;
                if let Some(w) = warning {
                    report.push(w);
                }
                let (matched, warning) =
                    check_scans_match(&map, &scans, &doc.label(), &table.label())?;
                if let Some(w) = warning {
                    report.push(w);
                }
                let localiser =
                    RfLocaliser::new(&map, &topology, &config.rf).map_err(with_context(
                        format!("{}: cannot localise with this radio map", doc.label()),
                    ))?;
                Some((localiser, scans, matched))
            }
            _ => None,
        };
        let input = TrackInput {
            topology: &topology,
            transitions: transitions.as_ref(),
            radio: radio
                .as_ref()
                .map(|(localiser, scans, _)| RadioInput { localiser, scans }),
        };
        let mut run =
            footslam::pipeline::track(&input, &trace, &config, &SnapshotSteps::Never, &report)
                .map_err(py_error)?;
        let times: Vec<f64> = trace.steps().iter().map(|s| s.t).collect();
        let smoothed = run.smoothed.take().map(|walk| {
            times
                .iter()
                .zip(walk.iter())
                .filter_map(|(&t, k)| {
                    let k = k?;
                    let c = k.estimate?;
                    let point = TrackPoint {
                        t,
                        x: c.x,
                        y: c.y,
                        z: c.z,
                        level: c.level,
                    };
                    Some((point, k.certain, k.hypotheses, c.spread, c.weight))
                })
                .collect::<Vec<SmoothedRow>>()
        });
        let records = &run.records;
        let first = records.first_localised();
        let initial = run.initial_particles;
        let rf = radio.as_ref().map(|(localiser, scans, matched)| {
            json!({
                "scans": scans.len(),
                "scans_matched": matched,
                "mode": localiser.config().mode,
                "distance": localiser.distance(),
                "epsilon_dbm": localiser.epsilon(),
                "epsilon_source": localiser.epsilon_source(),
                "started_at_step": records
                    .steps
                    .iter()
                    .position(|r| r.particles() > 0)
                    .map(|i| i + 1),
                "measurements_ignored": run.measurements_ignored,
                "evidence": localiser.evidence(),
                "evidence_fallback": localiser.fallback(),
            })
        });
        let quality = run.quality(
            smoothed
                .as_ref()
                .map_or(0, |s| s.iter().filter(|r| r.1).count()),
            &footslam::pipeline::QualityConfig::default(),
        );
        let summary = json!({
            "quality": quality,
            "rf": rf,
            "headings_used": run.headings_used > 0,
            "steps_with_heading": trace.with_heading(),
            "plan_file": plan_label,
            "hexmap_hexagons": transitions.as_ref().map(TransitionPrior::len),
            "steps_file": steps_table.label(),
            "steps": times.len(),
            "steps_to_localise": first.map(|i| i + 1),
            "localised_at_t": first.map(|i| times[i]),
            "track_rows": run.filtered.len(),
            "steps_estimated": smoothed.as_ref().map(Vec::len),
            "steps_certain": smoothed.as_ref().map(|s| s.iter().filter(|r| r.1).count()),
            "particles_initial": initial,
            "particles_max": records
                .steps
                .iter()
                .map(|r| r.particles())
                .max()
                .unwrap_or(initial)
                .max(initial),
            "particles_final": records.steps.last().map_or(initial, |r| r.particles()),
            "deaths": records.recoveries.len(),
            "recoveries": records.recoveries,
            "plan_fit": records.fit,
            "seed": run.seed,
            "filter_runtime_s": run.filter_runtime_s,
            "particle_steps_per_s": records.particle_steps() as f64
                / run.filter_runtime_s.max(1e-9),
            "bytes_per_particle": run.bytes_per_particle,
            "plan": {
                "surfaces": topology.len(),
                "walkable_area_m2": topology.total_area(),
                "levels": topology.levels(),
            },
            "origin": frame,
            "version": env!("CARGO_PKG_VERSION"),
        });
        let records = records
            .steps
            .iter()
            .map(|r| {
                let clusters = r.clusters().map_or(-1, |c| c as i64);
                (r.particles() as i64, clusters, r.localised())
            })
            .collect();
        Ok(TrackOut {
            smoothed,
            filtered: std::mem::take(&mut run.filtered),
            records,
            summary,
        })
    })?;
    let result = PyDict::new(py);
    let filtered = points(py, &out.filtered, None)?;
    match &out.smoothed {
        Some(rows) => {
            let p: Vec<TrackPoint> = rows.iter().map(|r| r.0).collect();
            result.set_item("track", points(py, &p, Some(rows))?)?;
        }
        None => result.set_item("track", points(py, &out.filtered, None)?)?,
    }
    result.set_item("filtered", filtered)?;
    let r = &out.records;
    result.set_item(
        "steps",
        columns(
            py,
            vec![
                ("particles", Column::I64(r.iter().map(|r| r.0).collect())),
                ("clusters", Column::I64(r.iter().map(|r| r.1).collect())),
                ("localised", Column::Bool(r.iter().map(|r| r.2).collect())),
            ],
        )?,
    )?;
    result.set_item("summary", json_object(py, &out.summary)?)?;
    result.set_item("config", json_object(py, &config)?)?;
    report.emit(py)?;
    Ok(result)
}

/// Columns `t, x, y, z, level` (and, for the smoothed answer, `certain, hypotheses,
/// spread, share`).
fn points<'py>(
    py: Python<'py>,
    p: &[TrackPoint],
    smoothed: Option<&[SmoothedRow]>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut cols = vec![
        ("t", Column::F64(p.iter().map(|q| q.t).collect())),
        ("x", Column::F64(p.iter().map(|q| q.x).collect())),
        ("y", Column::F64(p.iter().map(|q| q.y).collect())),
        ("z", Column::F64(p.iter().map(|q| q.z).collect())),
        (
            "level",
            Column::I64(p.iter().map(|q| i64::from(q.level)).collect()),
        ),
    ];
    if let Some(rows) = smoothed {
        cols.push(("certain", Column::Bool(rows.iter().map(|r| r.1).collect())));
        cols.push((
            "hypotheses",
            Column::I64(rows.iter().map(|r| r.2 as i64).collect()),
        ));
        cols.push(("spread", Column::F64(rows.iter().map(|r| r.3).collect())));
        cols.push(("share", Column::F64(rows.iter().map(|r| r.4).collect())));
    }
    columns(py, cols)
}
