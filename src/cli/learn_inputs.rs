//! The inputs of `footslam learn`, read into the job's request
//! ([`footslam::pipeline::LearnRequest`]): walks from files, folders and manifests, their
//! GPS fixes and WiFi logs, the prior map, the outline and the configuration.

use super::common::{read_config, require_file};
use super::learn_args::Args;
use anyhow::{Context, Result, bail};
use footslam::filter::StartPose;
use footslam::io::map_geojson::{StoredMap, read_stored_map};
use footslam::io::{
    ManifestWalk, read_gps_csv, read_gpx, read_steps_with_field, read_walk_manifest, read_wifi_log,
    read_world_outline,
};
use footslam::pipeline::{LearnConfig, LearnOverrides, LearnRequest, LearnWalkRequest, Named};
use std::path::{Path, PathBuf};

/// One walk found from the flags, a manifest or a folder (the manifest's own record).
pub(super) type Found = ManifestWalk;

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
}

/// The walks named by `--steps` (files or folders) with their GPS fixes (`--gps`, one per
/// walk in order, or none), WiFi logs and starts likewise; or those of a manifest: their
/// files, in the order of the walks.
pub(super) fn find_walks(args: &WalkArgs, default: &Path) -> Result<Vec<Found>> {
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
            name: None,
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
                name: None,
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
    Ok(found)
}

/// Reads the files of `found`, GPX times placed by `gps_t0`: each walk's request.
pub(super) fn read_found(found: &[Found], gps_t0: Option<f64>) -> Result<Vec<LearnWalkRequest>> {
    let label = |p: &Path| p.display().to_string();
    found
        .iter()
        .map(|f| {
            let (trace, field) = read_steps_with_field(&f.steps)?;
            let gps = match &f.gps {
                Some(p) if is_gpx(p) => {
                    let fixes = read_gpx(p, gps_t0.unwrap_or(0.0))?;
                    Some((Named::new(fixes, label(p)), true))
                }
                Some(p) => Some((Named::new(read_gps_csv(p)?, label(p)), false)),
                None => None,
            };
            let wifi = match &f.wifi {
                Some(p) => {
                    let log = read_wifi_log(p)?;
                    Some((Named::new(log.scans, label(p)), log.duplicate_readings))
                }
                None => None,
            };
            Ok(LearnWalkRequest {
                steps: Named::new(trace, label(&f.steps)),
                field,
                gps,
                wifi,
                start: f.start,
            })
        })
        .collect()
}

/// The request of `learn` on the walks `found`: their files read, with the prior map, the
/// outline (in WGS84), the origin, the configuration file's and the flags over it.
pub(super) fn read_request(args: &Args, found: &[Found]) -> Result<LearnRequest> {
    let config: LearnConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => LearnConfig::default(),
    };
    let outline = match &args.outline {
        Some(path) => {
            require_file(path, "outline")?;
            let label = path.display().to_string();
            Some(Named::new(read_world_outline(path)?, label))
        }
        None => None,
    };
    Ok(LearnRequest {
        walks: read_found(found, args.gps_t0)?,
        gps_t0: args.gps_t0,
        prior_map: read_prior_map(args)?,
        outline,
        origin: args.origin,
        config,
        overrides: LearnOverrides {
            seed: args.seed,
            particles: args.particles,
            hex_radius: args.hex_radius,
            prior_weight: args.prior_weight,
            ignore_heading: args.ignore_heading,
            cell: args.cell,
        },
    })
}

/// `--prior-map`, read.
pub(super) fn read_prior_map(args: &Args) -> Result<Option<Named<StoredMap>>> {
    match &args.prior_map {
        Some(p) => {
            require_file(p, "prior map")?;
            let label = p.display().to_string();
            Ok(Some(Named::new(read_stored_map(p)?, label)))
        }
        None => Ok(None),
    }
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
                name: None,
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
