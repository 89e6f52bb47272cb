//! `eval --picture`: the scored track over its reference (the truth, or the waypoints
//! joined in time order), after the alignment `eval` measured with, on the floor plan when
//! `--plan` is given (one panel per floor) or on white.

use anyhow::Result;
use footslam::eval::ErrorReport;
use footslam::io::floor_plan_geojson::read_floor_plan;
use footslam::io::{TimedPoint, TrackPoint};
use footslam::map::HexMapSnapshot;
use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};
use footslam::render::plan_png::{PlanPath, PlanPicture, PlanPictureConfig, write_plan_png};
use std::path::Path;

/// The track's colour (as on the learned-map pictures).
const TRACK_RED: [u8; 3] = [178, 24, 43];
/// The reference's colour.
const TRUTH_BLUE: [u8; 3] = [33, 102, 172];

/// What the picture shows.
pub(super) struct EvalPicture<'a> {
    /// The scored track rows, in the track's frame.
    pub(super) track: &'a [TimedPoint],
    /// What the track is drawn over.
    pub(super) reference: Reference<'a>,
    /// The errors, whose transform (rigid alignment) moves the track into the truth's frame.
    pub(super) report: &'a ErrorReport,
    /// The floor plan (`--plan`) and the origin that overrides its own.
    pub(super) plan: Option<&'a Path>,
    /// `--origin`.
    pub(super) origin: Option<footslam::geometry::LocalFrame>,
    /// A learned plan (`--learned-plan`), in the track's frame: drawn, aligned as the
    /// track is, over the true plan.
    pub(super) learned_plan: Option<&'a Path>,
}

/// The reference of an `eval` picture, and the track's rows with levels.
pub(super) struct Reference<'a> {
    /// `(x, y, level)` in time order (level 0 when unknown).
    pub(super) points: &'a [(f64, f64, i32)],
    /// What it is ("true path", "waypoints").
    pub(super) label: &'a str,
    /// The track file's rows when it has `z` and `level` columns (the track's levels).
    pub(super) track_rows: Option<&'a [TrackPoint]>,
}

/// `p` moved into the truth's frame by `report`'s alignment (as it is, without one).
fn aligned(report: &ErrorReport, p: (f64, f64)) -> (f64, f64) {
    report.transform.as_ref().map_or(p, |t| t.apply(p))
}

/// The learned plan's outlines.
const LEARNED_BROWN: [u8; 3] = [166, 97, 26];

impl EvalPicture<'_> {
    /// Writes the picture to `out` (PNG).
    pub(super) fn write(&self, out: &Path) -> Result<()> {
        let levels = track_levels(self.reference.track_rows, self.track);
        let track: Vec<(f64, f64, i32)> = self
            .track
            .iter()
            .zip(levels)
            .map(|(p, level)| {
                let (x, y) = aligned(self.report, (p.x, p.y));
                (x, y, level)
            })
            .collect();
        let (reference, label) = (self.reference.points, self.reference.label);
        let title = format!(
            "error median {:.2} m, p90 {:.2} m, {} points",
            self.report.p50, self.report.p90, self.report.n
        );
        match self.plan {
            Some(plan) => {
                let (plan, _) = read_floor_plan(plan, self.origin)?;
                let outlines = self.learned_outlines()?;
                let mut paths: Vec<PlanPath> = outlines
                    .iter()
                    .map(|ring| PlanPath {
                        points: ring,
                        colour: LEARNED_BROWN,
                        label: "learned plan",
                    })
                    .collect();
                paths.extend([
                    PlanPath {
                        points: reference,
                        colour: TRUTH_BLUE,
                        label,
                    },
                    PlanPath {
                        points: &track,
                        colour: TRACK_RED,
                        label: "track",
                    },
                ]);
                let picture = PlanPicture {
                    plan: &plan,
                    title: Some(title),
                    paths,
                    points: Vec::new(),
                    cells: Vec::new(),
                    markers: Vec::new(),
                    north_up: true,
                    colour_bar: None,
                };
                write_plan_png(out, &[picture], &PlanPictureConfig::default())?;
            }
            None => {
                let empty = HexMapSnapshot {
                    radius: 0.5,
                    alpha: 0.8,
                    cells: Vec::new(),
                    levels: Vec::new(),
                };
                let track: Vec<(f64, f64)> = track.iter().map(|&(x, y, _)| (x, y)).collect();
                let truth: Vec<(f64, f64)> = reference.iter().map(|&(x, y, _)| (x, y)).collect();
                let picture = MapPicture {
                    truth: Some(&truth),
                    truth_label: label,
                    path_label: "track",
                    // The truth's frame: east and north.
                    north_up: true,
                    ..MapPicture::new(&empty, &track)
                };
                write_map_png(out, &picture, &PictureConfig::default())?;
            }
        }
        Ok(())
    }
}

impl EvalPicture<'_> {
    /// The rings of `--learned-plan`'s polygons as closed `(x, y, level)` lines, moved into
    /// the truth's frame by the track's alignment.
    fn learned_outlines(&self) -> Result<Vec<Vec<(f64, f64, i32)>>> {
        let Some(path) = self.learned_plan else {
            return Ok(Vec::new());
        };
        let (learned, _) = read_floor_plan(path, self.origin)?;
        Ok(learned
            .polygons
            .iter()
            .flat_map(|f| {
                std::iter::once(f.polygon.exterior())
                    .chain(f.polygon.interiors())
                    .map(move |ring| {
                        ring.coords()
                            .map(|c| {
                                let (x, y) = aligned(self.report, (c.x, c.y));
                                (x, y, f.level)
                            })
                            .collect()
                    })
            })
            .collect())
    }
}

/// The level of each of `rows` from the track file's rows `all` (the row at the same time),
/// 0 where it has none.
fn track_levels(all: Option<&[TrackPoint]>, rows: &[TimedPoint]) -> Vec<i32> {
    let Some(all) = all else {
        return vec![0; rows.len()];
    };
    rows.iter()
        .map(|p| {
            let i = all.partition_point(|r| r.t < p.t);
            all.get(i).filter(|r| r.t == p.t).map_or(0, |r| r.level)
        })
        .collect()
}
