//! The outputs of one learned walk: its track (CSV and GeoJSON), map (GeoJSON and one picture
//! per floor), walkable plan and configuration, and its report for `summary.json`.

use super::field_outputs::write_field_map_png;
use anyhow::Result;
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::field_map_geojson::write_field_map_geojson;
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::map_geojson::write_map_geojson;
use footslam::io::track_geojson::write_track_geojson;
use footslam::io::{TimedPoint, TrackPoint, write_trajectory, write_trajectory_with};
use footslam::map::{HexMapSnapshot, PlanConfig, walkable_plan};
use footslam::pipeline::{LearnWalk, PreparedLearn, WalkLabels, WalkReport, WalkRun};
use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};

/// The frame of a run's maps, what placed it on the globe, and the part of it the pictures
/// show.
#[derive(Debug, Clone, Copy)]
pub(super) struct MapFrame<'a> {
    /// The local frame.
    pub(super) frame: &'a LocalFrame,
    /// The building outline, local metres, when given.
    pub(super) outline: Option<&'a geo::Polygon<f64>>,
    /// An outline or a prior map holds the frame to the globe (north up).
    pub(super) anchored: bool,
    /// `--picture-extent`: the part of the frame the map pictures show.
    pub(super) picture_extent: Option<[f64; 4]>,
}

impl<'a> MapFrame<'a> {
    /// The frame of a prepared run: anchored by its outline or prior map; the pictures
    /// show `picture_extent`, else what they draw.
    pub(super) fn of(prepared: &'a PreparedLearn, picture_extent: Option<[f64; 4]>) -> Self {
        Self {
            frame: &prepared.frame,
            outline: prepared.outline.as_ref(),
            anchored: prepared.outline.is_some() || prepared.prior_map.is_some(),
            picture_extent,
        }
    }
}

/// The pictures of a learned map: one per floor, `NAME.png` the first (level 0) and
/// `NAME-level+N.png` the others, each with the path's part on that floor.
pub(super) struct MapPictures<'a> {
    /// The path `(x, y, level)`, empty for a map of several walks.
    pub(super) path: &'a [(f64, f64, i32)],
    /// What the path is, for the key.
    pub(super) path_label: &'a str,
    /// The frame's y axis points north.
    pub(super) north_up: bool,
    /// The building outline, drawn over the map.
    pub(super) outline: Option<&'a geo::Polygon<f64>>,
    /// The part of the frame shown (`--picture-extent`); `None`: what is drawn.
    pub(super) extent: Option<[f64; 4]>,
}

impl MapPictures<'_> {
    /// Writes the pictures of `map` to `at(NAME…)`.
    pub(super) fn write(
        &self,
        at: &dyn Fn(&str) -> std::path::PathBuf,
        name: &str,
        map: &HexMapSnapshot,
    ) -> Result<()> {
        let mut levels = map.cell_levels();
        if !levels.contains(&0) {
            levels.insert(0, 0);
        }
        for level in levels {
            let on_level = HexMapSnapshot {
                cells: map
                    .cells
                    .iter()
                    .filter(|c| c.level == level)
                    .cloned()
                    .collect(),
                levels: Vec::new(),
                ..*map
            };
            // The path on this floor, broken where the walk left it.
            let (mut walked, mut breaks) = (Vec::new(), Vec::new());
            let mut previous = None;
            for (i, &(x, y, l)) in self.path.iter().enumerate() {
                if l == level {
                    if previous.is_some_and(|j| j + 1 != i) {
                        breaks.push(walked.len());
                    }
                    walked.push((x, y));
                    previous = Some(i);
                }
            }
            let picture = MapPicture {
                path_breaks: &breaks,
                outline: self.outline,
                path_label: self.path_label,
                north_up: self.north_up,
                ..MapPicture::new(&on_level, &walked)
            };
            let file = match level {
                0 => format!("{name}.png"),
                l => format!("{name}-level{l:+}.png"),
            };
            let config = PictureConfig {
                extent: self.extent,
                ..PictureConfig::default()
            };
            write_map_png(&at(&file), &picture, &config)?;
        }
        Ok(())
    }
}

/// Writes one walk's outputs under `prefix` and returns its report.
pub(super) fn write_walk(
    folder: &RunFolder,
    prefix: &str,
    labels: &WalkLabels,
    walk: &LearnWalk,
    run: &WalkRun,
    frame: &MapFrame,
) -> Result<WalkReport> {
    let (config, estimate) = (&run.config, &run.estimate);
    let (anchors, frame) = (frame, frame.frame);
    let north_up = anchors.anchored || run.heading_is_absolute();
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    // Built one at a time from the trace and the path (a long walk's per-step outputs are
    // the largest things a run holds).
    let steps_and_path = || walk.trace.steps().iter().zip(&estimate.path);
    write_trajectory_with(
        &at("track.csv"),
        "spread_m",
        steps_and_path()
            .zip(&estimate.spread_m)
            .map(|((s, p), &spread)| {
                let point = TimedPoint {
                    t: s.t,
                    x: p.x,
                    y: p.y,
                };
                (point, spread)
            }),
    )?;
    let points: Vec<TrackPoint> = steps_and_path()
        .zip(&estimate.levels)
        .map(|((s, p), &level)| TrackPoint {
            t: s.t,
            x: p.x,
            y: p.y,
            z: estimate.map.level_height(level),
            level,
        })
        .collect();
    write_track_geojson(&at("track.geojson"), &points, frame)?;
    drop(points);
    write_map_geojson(&at("map.geojson"), &estimate.map, frame)?;
    // The path `(x, y, level)`, for the pictures.
    let path: Vec<(f64, f64, i32)> = estimate
        .path
        .iter()
        .zip(&estimate.levels)
        .map(|(p, &l)| (p.x, p.y, l))
        .collect();
    if let Some(field) = estimate.field_map.as_ref().filter(|f| !f.cells.is_empty()) {
        write_field_map_geojson(&at("fieldmap.geojson"), field, frame)?;
        write_field_map_png(&at("fieldmap.png"), field, &path, north_up)?;
    }
    let plan = walkable_plan(&estimate.map, &PlanConfig::default()).ok();
    if let Some(plan) = &plan {
        write_floor_plan(&at("plan.geojson"), &plan.plan, frame)?;
    }
    let pictures = MapPictures {
        path: &path,
        path_label: "most probable path",
        north_up,
        outline: anchors.outline,
        extent: anchors.picture_extent,
    };
    pictures.write(&at, "map", &estimate.map)?;
    if !prefix.is_empty() {
        folder.write_json(&format!("{prefix}config.json"), config)?;
    }
    write_dead_reckoning(&at("dead_reckoning.csv"), walk, run)?;
    Ok(WalkReport::new(walk, run, labels, plan.as_ref()))
}

/// Writes the walk's steps dead-reckoned from its start (`dead_reckoning.csv`).
fn write_dead_reckoning(path: &std::path::Path, walk: &LearnWalk, run: &WalkRun) -> Result<()> {
    let steps = walk.trace.steps().iter().zip(&run.dead_reckoned);
    let points = steps.map(|(s, p)| TimedPoint {
        t: s.t,
        x: p.x,
        y: p.y,
    });
    Ok(write_trajectory(path, points)?)
}

/// Writes the walkable plan of `map` ([`walkable_plan`], default settings) to `path` and
/// returns its area; writes nothing and returns `None` when the map is too small to make
/// one (`footslam plan` gives the reason and the settings to change).
pub(super) fn write_learned_plan(
    path: &std::path::Path,
    map: &HexMapSnapshot,
    frame: &LocalFrame,
) -> Result<Option<f64>> {
    match walkable_plan(map, &PlanConfig::default()) {
        Ok(learned) => {
            write_floor_plan(path, &learned.plan, frame)?;
            Ok(Some(learned.area_m2))
        }
        Err(_) => Ok(None),
    }
}
