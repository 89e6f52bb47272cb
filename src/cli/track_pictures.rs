//! `footslam track`'s pictures: the particle cloud at chosen steps (`particles.png`) and
//! the filtered and smoothed tracks (`track.png`).

use footslam::io::{RunFolder, TrackPoint};
use footslam::map::FloorPlan;
use footslam::pipeline::{CloudSnapshot, TrackRun};
use footslam::render::plan_png::{PlanPath, PlanPicture, PlanPictureConfig, PlanPoints};
use std::path::Path;

/// The smoothed track's certain steps and its uncertain estimates `(x, y, level)`.
type Smoothed<'a> = (&'a [TrackPoint], &'a [(f32, f32, i32)]);

/// Colours of the pictures.
const PARTICLE_COLOUR: [u8; 3] = [200, 30, 30];
const TRACK_COLOUR: [u8; 3] = [20, 60, 200];
const FILTERED_COLOUR: [u8; 3] = [230, 150, 30];

/// A snapshot's title: `prior: N particles`, `step K: N particles`, `localised K: …`.
fn title(s: &CloudSnapshot) -> String {
    if s.step == 0 {
        format!("prior: {} particles", s.points.len())
    } else {
        format!("{} {}: {} particles", s.what, s.step, s.points.len())
    }
}

/// `particles.png` and, with smoothing (`smoothed`: the certain steps and the uncertain
/// estimates), `track.png`, over a walk of `steps` steps; both show `extent` (local metres)
/// when given, else what they draw.
pub(super) fn write_track_pictures(
    folder: &RunFolder,
    plan: &FloorPlan,
    run: &TrackRun,
    smoothed: Option<Smoothed<'_>>,
    steps: usize,
    extent: Option<[f64; 4]>,
) -> footslam::Result<()> {
    let points: Vec<(f64, f64, i32)> = run.filtered.iter().map(|p| (p.x, p.y, p.level)).collect();
    let config = PlanPictureConfig {
        extent,
        ..Default::default()
    };
    let particles = folder.path("particles.png");
    write_particles_png(&particles, plan, &run.snapshots, &points, &config)?;
    if let Some(smoothed) = smoothed {
        let path = folder.path("track.png");
        write_track_png(&path, plan, &points, smoothed, steps, &config)?;
    }
    Ok(())
}

/// `particles.png`: one picture per snapshot, with the filtered track (`track_points`, as
/// `(x, y, level)`) up to the snapshot's step; nothing without snapshots.
fn write_particles_png(
    path: &Path,
    plan: &FloorPlan,
    snapshots: &[CloudSnapshot],
    track_points: &[(f64, f64, i32)],
    config: &PlanPictureConfig,
) -> footslam::Result<()> {
    let pictures: Vec<PlanPicture> = snapshots
        .iter()
        .map(|s| PlanPicture {
            plan,
            title: Some(title(s)),
            paths: vec![PlanPath {
                points: &track_points[..s.track_len],
                colour: TRACK_COLOUR,
                label: "track",
            }],
            points: vec![PlanPoints {
                points: &s.points,
                colour: PARTICLE_COLOUR,
                label: "particles",
            }],
            cells: Vec::new(),
            markers: Vec::new(),
            north_up: true,
            colour_bar: None,
        })
        .collect();
    if !pictures.is_empty() {
        footslam::render::plan_png::write_plan_png(path, &pictures, config)?;
    }
    Ok(())
}

/// `track.png`: the filtered track (`track_points`), the smoothed track's certain steps
/// (`answer`) and its uncertain estimates, over a walk of `steps_total` steps; both pictures
/// show the part of the plan `config` says.
fn write_track_png(
    path: &Path,
    plan: &FloorPlan,
    track_points: &[(f64, f64, i32)],
    (answer, uncertain): Smoothed<'_>,
    steps_total: usize,
    config: &PlanPictureConfig,
) -> footslam::Result<()> {
    let certain: Vec<(f64, f64, i32)> = answer.iter().map(|p| (p.x, p.y, p.level)).collect();
    footslam::render::plan_png::write_plan_png(
        path,
        &[PlanPicture {
            plan,
            title: Some(format!(
                "smoothed: {} of {} steps certain",
                certain.len(),
                steps_total
            )),
            paths: vec![
                PlanPath {
                    points: track_points,
                    colour: FILTERED_COLOUR,
                    label: "filtered",
                },
                PlanPath {
                    points: &certain,
                    colour: TRACK_COLOUR,
                    label: "smoothed (certain)",
                },
            ],
            points: vec![PlanPoints {
                points: uncertain,
                colour: PARTICLE_COLOUR,
                label: "smoothed (uncertain)",
            }],
            cells: Vec::new(),
            markers: Vec::new(),
            north_up: true,
            colour_bar: None,
        }],
        config,
    )
}
