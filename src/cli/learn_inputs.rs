//! The inputs of `footslam learn`: walks from files and folders, their GPS fixes and WiFi
//! logs, and the check that a prior map lies on the run's grid.

use super::common::{SAME_ORIGIN, require_file};
use anyhow::{Context, Result, bail};
use footslam::dataset::{read_gps_csv, read_gpx, read_steps, read_wifi};
use footslam::geometry::LocalFrame;
use footslam::sensor::{GpsFix, StepTrace, WifiScan};
use std::path::{Path, PathBuf};

/// One walk to learn.
#[derive(Debug)]
pub(super) struct Walk {
    pub(super) steps_path: PathBuf,
    pub(super) gps_path: Option<PathBuf>,
    pub(super) trace: StepTrace,
    pub(super) fixes: Vec<GpsFix>,
    pub(super) wifi_path: Option<PathBuf>,
    /// The walk's WiFi scans, in time order (empty without a log).
    pub(super) scans: Vec<WifiScan>,
}

/// A walk found in the arguments: its step trace, GPS file and WiFi log.
struct Found {
    steps: PathBuf,
    gps: Option<PathBuf>,
    wifi: Option<PathBuf>,
}

/// The walks named by `--steps` (files or folders) with their GPS fixes (`gps`, one per
/// walk in order, or none) and WiFi logs (`wifi`, likewise).
pub(super) fn read_walks(
    steps: &[PathBuf],
    gps: &[PathBuf],
    wifi: &[PathBuf],
    gps_t0: Option<f64>,
    default: &Path,
) -> Result<Vec<Walk>> {
    let mut found: Vec<Found> = Vec::new();
    if steps.is_empty() {
        found.push(Found {
            steps: default.to_path_buf(),
            gps: None,
            wifi: None,
        });
    }
    for path in steps {
        if path.is_dir() {
            found.extend(walks_in_folder(path)?);
        } else {
            require_file(path, "step trace")?;
            found.push(Found {
                steps: path.clone(),
                gps: None,
                wifi: None,
            });
        }
    }
    let one_per_walk = |files: &[PathBuf], flag: &str| -> Result<()> {
        if !files.is_empty() && files.len() != found.len() {
            bail!(
                "{} {flag} files for {} walks: give one per walk, in the order of the walks",
                files.len(),
                found.len()
            );
        }
        Ok(())
    };
    one_per_walk(gps, "--gps")?;
    one_per_walk(wifi, "--wifi")?;
    for (walk, gps) in found.iter_mut().zip(gps) {
        require_file(gps, "GPS file")?;
        walk.gps = Some(gps.clone());
    }
    for (walk, wifi) in found.iter_mut().zip(wifi) {
        require_file(wifi, "WiFi log")?;
        walk.wifi = Some(wifi.clone());
    }
    found
        .into_iter()
        .map(|f| {
            let trace = read_steps(&f.steps)?;
            let fixes = match &f.gps {
                Some(p) => read_fixes(p, gps_t0, &trace)?,
                None => Vec::new(),
            };
            let scans = match &f.wifi {
                Some(p) => read_scans(p, &trace)?,
                None => Vec::new(),
            };
            Ok(Walk {
                steps_path: f.steps,
                gps_path: f.gps,
                trace,
                fixes,
                wifi_path: f.wifi,
                scans,
            })
        })
        .collect()
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
            Found { steps, gps, wifi }
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

/// Fixes from CSV or GPX, checked to overlap the walk in time.
fn read_fixes(path: &Path, t0: Option<f64>, trace: &StepTrace) -> Result<Vec<GpsFix>> {
    let is_gpx = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gpx"));
    let fixes = if is_gpx {
        read_gpx(path, t0.unwrap_or(0.0))?
    } else {
        read_gps_csv(path)?
    };
    let steps = trace.steps();
    let (a, b) = (steps[0].t, steps[steps.len() - 1].t);
    if !fixes.iter().any(|f| f.t >= a - 60.0 && f.t <= b) {
        let hint = if is_gpx {
            "; pass --gps-t0 with the UTC time of the steps' t = 0"
        } else {
            ""
        };
        bail!(
            "{}: no fix falls within the walk's time span [{a}, {b}] s (fixes run from {} to {} s){hint}",
            path.display(),
            fixes[0].t,
            fixes[fixes.len() - 1].t
        );
    }
    Ok(fixes)
}

/// WiFi scans, checked to overlap the walk in time: a log on another clock would place no
/// scan (or every scan at one end of the walk).
fn read_scans(path: &Path, trace: &StepTrace) -> Result<Vec<WifiScan>> {
    let scans = read_wifi(path)?;
    let steps = trace.steps();
    let (a, b) = (steps[0].t, steps[steps.len() - 1].t);
    if !scans.iter().any(|s| s.t >= a && s.t <= b) {
        bail!(
            "{}: no scan falls within the walk's time span [{a}, {b}] s (scans run from {} to \
             {} s): the WiFi log and the step trace must share one clock",
            path.display(),
            scans[0].t,
            scans[scans.len() - 1].t
        );
    }
    Ok(scans)
}

/// The prior map must lie on the run's hexagon grid.
pub(super) fn check_same_grid(
    path: &Path,
    radius: f64,
    map_frame: &LocalFrame,
    run_radius: f64,
    frame: &LocalFrame,
) -> Result<()> {
    if (radius - run_radius).abs() > 1e-9 {
        bail!(
            "{}: hexagons of radius {radius} m, but this run uses {run_radius} m: pass --hex-radius {radius}",
            path.display()
        );
    }
    let off = frame.distance_to(map_frame);
    if off > SAME_ORIGIN {
        bail!(
            "{}: its origin ({}, {}) lies {off:.3} m from this run's ({}, {}); hexagons of \
             different origins do not line up: pass --origin {},{} (or leave --origin out)",
            path.display(),
            map_frame.lat,
            map_frame.lon,
            frame.lat,
            frame.lon,
            map_frame.lat,
            map_frame.lon
        );
    }
    Ok(())
}
