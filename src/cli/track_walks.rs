//! `footslam track --walks`: many walks tracked on one plan (and radio
//! map), prepared once — the plan's topology, the learned map and the radio map's fitted
//! model and calibration are the same for every walk of a floor.
//!
//! The run folder holds one folder per walk (what `track` writes for one walk), `walks.csv`
//! (one row per walk: its `summary.json` flattened), `config.json` and a `summary.json`
//! listing the walks.

use super::batch_table::{NamedRow, walks_table};
use super::common::{create_run_folder, output_dir, require_file, worker_pool};
use super::progress_bars::Bars;
use super::track::{Args, read_request, track_into};
use anyhow::{Context, Result, bail};
use footslam::io::steps_csv::has_dz_column;
use footslam::io::{ManifestWalk, RunFolder, read_steps, read_walk_manifest, read_wifi_log};
use footslam::pipeline::{
    ItemProgress, Named, PreparedTrack, Progress, TrackReport, TrackWalkRequest, prepare,
};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashSet;
use std::path::PathBuf;
use std::time::Instant;

/// Most walks tracked at once (their particles all in memory: about 0.6 GB each for an
/// unknown start on a 10,000 m² floor).
const MAX_LANES: usize = 4;

/// `summary.json` of a batch.
#[derive(Debug, Serialize)]
struct BatchReport {
    /// The manifest.
    walks_file: String,
    /// The radio map, when one placed the walks.
    radiomap_file: Option<String>,
    /// Per walk: its folder and the headline of its `summary.json`.
    walks: Vec<BatchWalk>,
    /// Wall-clock time of the whole batch, seconds.
    runtime_s: f64,
    /// Worker threads.
    threads: usize,
}

/// One walk of [`BatchReport`].
#[derive(Debug, Serialize)]
struct BatchWalk {
    name: String,
    steps_file: String,
    steps: usize,
    steps_to_localise: Option<usize>,
    runtime_s: f64,
}

/// Runs `footslam track --walks`.
pub(super) fn run(args: &Args) -> Result<()> {
    let started = Instant::now();
    let manifest = args.walks.as_ref().context("--walks")?;
    require_file(manifest, "walk manifest")?;
    let walks = read_walk_manifest(manifest, args.radiomap.is_some())?;
    let names = walk_names(manifest, &walks)?;
    let pool = worker_pool(args.threads)?;
    let bars = Bars::default();
    let mut folder = create_run_folder(&output_dir(args.out.clone(), "track"))?;
    let (first, inputs) = read_request(args, Some(&walks[0]))?;
    folder.protect(inputs.iter().chain(args.config.iter()).chain([manifest]));
    let batch = Batch {
        args,
        walks: &walks,
        names: &names,
        folder: &folder,
        bars: &bars,
    };
    let shared = pool.install(|| prepare(first, &batch.item(0)))?;
    let reports = pool.install(|| batch.track_all(&shared, started))?;
    let rows: Vec<NamedRow<TrackReport>> = names
        .iter()
        .zip(&reports)
        .map(|(name, row)| NamedRow { name, row })
        .collect();
    folder.write("walks.csv", &walks_table(&rows)?)?;
    folder.write_json("config.json", &shared.config)?;
    let report = batch_report(
        args,
        manifest,
        &names,
        &reports,
        started,
        pool.current_num_threads(),
    );
    folder.write_json("summary.json", &report)?;
    let out = folder.commit()?;
    let localised = reports
        .iter()
        .filter(|r| r.steps_to_localise.is_some())
        .count();
    info!(
        "{} walks tracked in {:.1} s, {localised} localised; one folder each, walks.csv and summary.json in {}",
        reports.len(),
        report.runtime_s,
        out.display()
    );
    super::verbosity::done(&out, None);
    Ok(())
}

/// A batch's walks and where their outputs and progress go.
struct Batch<'a> {
    args: &'a Args,
    walks: &'a [ManifestWalk],
    names: &'a [String],
    folder: &'a RunFolder,
    bars: &'a Bars,
}

impl Batch<'_> {
    /// Walk `i`'s progress, under its name.
    fn item(&self, i: usize) -> ItemProgress<'_> {
        ItemProgress {
            inner: self.bars,
            item: i,
            label: self.names[i].clone(),
        }
    }

    /// Tracks every walk (the first prepared as `shared`, the others from it) into its
    /// folder, in lanes side by side (each lane's walks one after another, each walk's
    /// filter also on the pool): at most [`MAX_LANES`] walks' particles in memory. The
    /// reports in the manifest's order.
    fn track_all(&self, shared: &PreparedTrack, started: Instant) -> Result<Vec<TrackReport>> {
        self.bars.start("walks", self.walks.len() as u64);
        let lanes = rayon::current_num_threads().clamp(1, MAX_LANES);
        let mut done: Vec<(usize, Result<TrackReport>)> = (0..lanes)
            .into_par_iter()
            .flat_map_iter(|lane| {
                (lane..self.walks.len())
                    .step_by(lanes)
                    .map(|i| (i, self.track_one(shared, i, started)))
                    .collect::<Vec<_>>()
            })
            .collect();
        self.bars.finish();
        done.sort_by_key(|(i, _)| *i);
        done.into_iter().map(|(_, r)| r).collect()
    }

    /// Tracks walk `i` into its folder.
    fn track_one(&self, shared: &PreparedTrack, i: usize, started: Instant) -> Result<TrackReport> {
        let walk_started = if i == 0 { started } else { Instant::now() };
        let progress = self.item(i);
        let other = match i {
            0 => None,
            _ => {
                let walk = walk_request(self.args, shared, &self.walks[i])?;
                Some(shared.for_walk(walk, &progress)?)
            }
        };
        let prepared: &PreparedTrack = other.as_ref().unwrap_or(shared);
        let child = RunFolder::create(&self.folder.path(&self.names[i]))?;
        let extent = self.args.picture_extent;
        let report =
            track_into(&child, prepared, &progress, extent, walk_started).with_context(|| {
                format!("walk {} ({})", self.names[i], self.walks[i].steps.display())
            })?;
        child.commit()?;
        self.bars.advance(1);
        Ok(report)
    }
}

/// A manifest row after the first, read: its steps, WiFi log and start.
fn walk_request(
    args: &Args,
    shared: &PreparedTrack,
    walk: &ManifestWalk,
) -> footslam::Result<TrackWalkRequest> {
    // Only a plan of several levels needs the steps' header read again (as `track`).
    let one_level = shared.plan.levels().len() <= 1 || shared.one_floor;
    let label = |p: &PathBuf| p.display().to_string();
    let scans = match (&args.radiomap, &walk.wifi) {
        (Some(_), Some(wifi)) => {
            let log = read_wifi_log(wifi)?;
            Some((Named::new(log.scans, label(wifi)), log.duplicate_readings))
        }
        _ => None,
    };
    Ok(TrackWalkRequest {
        steps: Named::new(read_steps(&walk.steps)?, label(&walk.steps)),
        steps_have_dz: one_level || has_dz_column(&walk.steps)?,
        scans,
        start: walk.start,
    })
}

/// Each walk's folder name: the manifest's `name` column where given, else `walk-1`,
/// `walk-2`, … (as `learn` names its walks); names must be unique plain folder names.
pub(super) fn walk_names(
    manifest: &std::path::Path,
    walks: &[ManifestWalk],
) -> Result<Vec<String>> {
    let names: Vec<String> = walks
        .iter()
        .enumerate()
        .map(|(i, w)| w.name.clone().unwrap_or_else(|| format!("walk-{}", i + 1)))
        .collect();
    let mut seen = HashSet::new();
    for (i, name) in names.iter().enumerate() {
        let plain = !name.is_empty()
            && !name.starts_with('.')
            && !name.contains(['/', '\\', ':'])
            && name != "summary.json";
        if !plain {
            bail!(
                "{}: walk {} is named `{name}`: a name must be a plain folder name (no `/`, `\\`, `:` or leading `.`)",
                manifest.display(),
                i + 1
            );
        }
        if !seen.insert(name.as_str()) {
            bail!(
                "{}: walk {} is named `{name}` like an earlier walk: names must be unique",
                manifest.display(),
                i + 1
            );
        }
    }
    Ok(names)
}

/// The batch's `summary.json`.
fn batch_report(
    args: &Args,
    manifest: &std::path::Path,
    names: &[String],
    reports: &[TrackReport],
    started: Instant,
    threads: usize,
) -> BatchReport {
    BatchReport {
        walks_file: manifest.display().to_string(),
        radiomap_file: args.radiomap.as_ref().map(|p| p.display().to_string()),
        walks: names
            .iter()
            .zip(reports)
            .map(|(name, r)| BatchWalk {
                name: name.clone(),
                steps_file: r.steps_file.clone(),
                steps: r.steps,
                steps_to_localise: r.steps_to_localise,
                runtime_s: r.runtime_s,
            })
            .collect(),
        runtime_s: started.elapsed().as_secs_f64(),
        threads,
    }
}
