//! The inputs of `footslam learn`: walks from files and folders, their GPS fixes and WiFi
//! logs, the prior map and outline, and the check that a prior map lies on the run's grid.

use super::common::{read_scans, require_file, warn};
use super::learn_args::Args;
use anyhow::{Context, Result, bail};
use footslam::filter::{FootSlamConfig, StartPose};
use footslam::geometry::LocalFrame;
use footslam::io::map_geojson::{StoredMap, read_stored_map};
use footslam::io::{
    ManifestWalk, read_gps_csv, read_gpx, read_outline, read_steps_with_field, read_walk_manifest,
};
use footslam::pipeline::{
    GPS_LEAD_S, GridMismatch, LearnWalk, fixes_far_from_origin, fixes_off_clock, grid_mismatch,
    outline_off_walks, partly_off_clock,
};
use footslam::sensor::{GpsFix, StepTrace};
use geo::Polygon;
use std::path::{Path, PathBuf};

/// The files of one walk to learn.
#[derive(Debug)]
pub(super) struct WalkFiles {
    pub(super) steps_path: PathBuf,
    pub(super) gps_path: Option<PathBuf>,
    pub(super) wifi_path: Option<PathBuf>,
    /// Rows of the WiFi log that repeated an access point within a scan (left out).
    pub(super) wifi_duplicate_readings: usize,
}

/// One walk found from the flags, a manifest or a folder (the manifest's own record).
type Found = ManifestWalk;

/// Where `learn` finds its walks: the flags, one entry per walk in order.
pub(super) struct WalkArgs<'a> {
    /// `--steps`: files or folders.
    pub(super) steps: &'a [PathBuf],
    /// `--gps`, `--wifi`, `--start`: none, or one per walk.
    pub(super) gps: &'a [PathBuf],
    pub(super) wifi: &'a [PathBuf],
    pub(super) starts: &'a [StartPose],
    /// `--walks`: a manifest instead of the flags above.
    pub(super) manifest: Option<&'a Path>,
    /// `--gps-t0`.
    pub(super) gps_t0: Option<f64>,
}

/// The walks named by `--steps` (files or folders) with their GPS fixes (`--gps`, one per
/// walk in order, or none), WiFi logs and starts likewise; or those of a manifest: their
/// files and what they hold, in the order of the walks.
pub(super) fn read_walks(
    args: &WalkArgs,
    default: &Path,
) -> Result<(Vec<WalkFiles>, Vec<LearnWalk>)> {
    let mut found: Vec<Found> = Vec::new();
    if let Some(manifest) = args.manifest {
        if !(args.steps.is_empty()
            && args.gps.is_empty()
            && args.wifi.is_empty()
            && args.starts.is_empty())
        {
            bail!(
                "--walks {} names the walks and their files: give --steps, --gps, --wifi and \
                 --start in it, not as flags",
                manifest.display()
            );
        }
        found = read_manifest(manifest)?;
    } else if args.steps.is_empty() {
        found.push(Found {
            steps: default.to_path_buf(),
            gps: None,
            wifi: None,
            start: None,
        });
    }
    for path in args.steps {
        if path.is_dir() {
            found.extend(walks_in_folder(path)?);
        } else {
            require_file(path, "step trace")?;
            found.push(Found {
                steps: path.clone(),
                gps: None,
                wifi: None,
                start: None,
            });
        }
    }
    let one_per_walk = |given: usize, flag: &str| -> Result<()> {
        if given != 0 && given != found.len() {
            bail!(
                "{given} {flag} for {} walks: give one per walk, in the order of the walks",
                found.len()
            );
        }
        Ok(())
    };
    one_per_walk(args.gps.len(), "--gps files")?;
    one_per_walk(args.wifi.len(), "--wifi files")?;
    one_per_walk(args.starts.len(), "--start poses")?;
    for (walk, gps) in found.iter_mut().zip(args.gps) {
        require_file(gps, "GPS file")?;
        walk.gps = Some(gps.clone());
    }
    for (walk, wifi) in found.iter_mut().zip(args.wifi) {
        require_file(wifi, "WiFi log")?;
        walk.wifi = Some(wifi.clone());
    }
    for (walk, start) in found.iter_mut().zip(args.starts) {
        walk.start = Some(*start);
    }
    let gps_t0 = args.gps_t0;
    if gps_t0.is_some() && !found.iter().any(|f| f.gps.as_deref().is_some_and(is_gpx)) {
        bail!(
            "--gps-t0 places GPX files' UTC times on the steps' clock, and no walk has a GPX \
             file (CSV fixes are on the steps' clock already): leave --gps-t0 out"
        );
    }
    read_found(found, gps_t0)
}

/// Reads the files of `found`: each walk's files and what they hold, in order.
pub(super) fn read_found(
    found: Vec<Found>,
    gps_t0: Option<f64>,
) -> Result<(Vec<WalkFiles>, Vec<LearnWalk>)> {
    found
        .into_iter()
        .map(|f| {
            let (trace, field) = read_steps_with_field(&f.steps)?;
            let fixes = match &f.gps {
                Some(p) => read_fixes(p, gps_t0, &trace)?,
                None => Vec::new(),
            };
            let (scans, wifi_duplicate_readings) = match &f.wifi {
                Some(p) => read_scans(p, &trace)?,
                None => (Vec::new(), 0),
            };
            let files = WalkFiles {
                steps_path: f.steps,
                gps_path: f.gps,
                wifi_path: f.wifi,
                wifi_duplicate_readings,
            };
            let walk = LearnWalk {
                trace,
                fixes,
                scans,
                start: f.start,
                field,
            };
            Ok((files, walk))
        })
        .collect::<Result<Vec<_>>>()
        .map(|pairs| pairs.into_iter().unzip())
}

/// The walks of a manifest CSV ([`read_walk_manifest`]), each of whose files must exist.
pub(super) fn read_manifest(path: &Path) -> Result<Vec<Found>> {
    require_file(path, "walk manifest")?;
    let walks = read_walk_manifest(path, false)?;
    for w in &walks {
        require_file(&w.steps, "step trace")?;
        for (f, what) in [(&w.gps, "GPS file"), (&w.wifi, "WiFi log")] {
            if let Some(f) = f {
                require_file(f, what)?;
            }
        }
    }
    Ok(walks)
}

/// `DIR/steps.csv`, or every `DIR/*/steps.csv` in name order, each with `gps.csv` or
/// `gps.gpx`, and `wifi.csv`, beside it when present.
fn walks_in_folder(dir: &Path) -> Result<Vec<Found>> {
    let walk = |d: &Path| {
        let steps = d.join("steps.csv");
        steps.is_file().then(|| {
            let gps = ["gps.csv", "gps.gpx"]
                .iter()
                .map(|n| d.join(n))
                .find(|p| p.is_file());
            let wifi = Some(d.join("wifi.csv")).filter(|p| p.is_file());
            Found {
                steps,
                gps,
                wifi,
                start: None,
            }
        })
    };
    if let Some(w) = walk(dir) {
        return Ok(vec![w]);
    }
    let mut subdirs: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("{}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    subdirs.sort();
    let walks: Vec<_> = subdirs.iter().filter_map(|d| walk(d)).collect();
    if walks.is_empty() {
        bail!(
            "folder `{}` holds no steps.csv, nor sub-folders that do",
            dir.display()
        );
    }
    Ok(walks)
}

/// A GPX file (by its extension).
fn is_gpx(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gpx"))
}

/// Fixes from CSV or GPX, checked to overlap the walk in time.
pub(super) fn read_fixes(path: &Path, t0: Option<f64>, trace: &StepTrace) -> Result<Vec<GpsFix>> {
    let is_gpx = is_gpx(path);
    let fixes = if is_gpx {
        read_gpx(path, t0.unwrap_or(0.0))?
    } else {
        read_gps_csv(path)?
    };
    let steps = trace.steps();
    let (Some(first), Some(last)) = (steps.first(), steps.last()) else {
        return Ok(fixes);
    };
    if let Some(problem) = fixes_off_clock(&fixes, first.t, last.t) {
        let hint = if is_gpx {
            "; pass --gps-t0 with the UTC time of the steps' t = 0"
        } else {
            ""
        };
        bail!("{}: {problem}{hint}", path.display());
    }
    let times: Vec<f64> = fixes.iter().map(|f| f.t).collect();
    if let Some(problem) = partly_off_clock(&times, "fixes", first.t, last.t, GPS_LEAD_S) {
        warn(&format!("{}: {problem}", path.display()));
    }
    Ok(fixes)
}

/// Refuses GPS fixes of another place than the run's origin, and an outline that cannot be
/// the walks' building ([`fixes_far_from_origin`], [`outline_off_walks`]).
pub(super) fn check_anchors(
    files: &[WalkFiles],
    walks: &[LearnWalk],
    input: (&LocalFrame, Option<&Polygon<f64>>, Option<&Path>),
    config: &FootSlamConfig,
) -> Result<()> {
    let (frame, outline, outline_path) = input;
    for (f, w) in files.iter().zip(walks) {
        if let (Some(path), Some(problem)) = (&f.gps_path, fixes_far_from_origin(&w.fixes, frame)) {
            bail!("{}: {problem}", path.display());
        }
    }
    if let (Some(outline), Some(path)) = (outline, outline_path) {
        let default_start = (config.start.x, config.start.y);
        if let Some(problem) = outline_off_walks(outline, walks, default_start) {
            bail!("{}: {problem}", path.display());
        }
    }
    Ok(())
}

/// The prior map must lie on the run's hexagon grid.
pub(super) fn check_same_grid(
    path: &Path,
    radius: f64,
    map_frame: &LocalFrame,
    run_radius: f64,
    frame: &LocalFrame,
) -> Result<()> {
    let Some(mismatch) = grid_mismatch(radius, map_frame, run_radius, frame) else {
        return Ok(());
    };
    let fix = match mismatch {
        GridMismatch::Radius { map, .. } => format!("pass --hex-radius {map}"),
        GridMismatch::Origin { map, .. } => format!(
            "pass --origin {},{} (or leave --origin out)",
            map.lat, map.lon
        ),
    };
    bail!("{}: {mismatch}: {fix}", path.display())
}

/// The prior map, the run's frame and the outline in it.
/// `frame` gives the frame when `--origin` does not, from the prior map.
pub(super) fn read_anchors(
    args: &Args,
    config: &FootSlamConfig,
    frame: impl FnOnce(Option<&StoredMap>) -> Result<LocalFrame>,
) -> Result<(Option<StoredMap>, LocalFrame, Option<Polygon<f64>>)> {
    let prior_map = match &args.prior_map {
        Some(p) => {
            require_file(p, "prior map")?;
            Some(read_stored_map(p)?)
        }
        None => None,
    };
    let frame = match args.origin {
        Some(origin) => origin,
        None => frame(prior_map.as_ref())?,
    };
    let outline = match &args.outline {
        Some(path) => {
            require_file(path, "outline")?;
            Some(read_outline(path, &frame)?)
        }
        None => None,
    };
    if let (Some(stored), Some(path)) = (&prior_map, &args.prior_map) {
        let radius = stored.map.radius;
        check_same_grid(path, radius, &stored.frame, config.hex_radius, &frame)?;
    }
    Ok((prior_map, frame, outline))
}
