//! `footslam fingerprint`: each WiFi scan placed by the radio map alone (weighted k-nearest
//! fingerprints) — the baseline that tracking with the radio map should beat.

use super::batch_table::{NamedRow, walks_table};
use super::common::{output_dir, read_config, require_file};
use super::progress_bars::Bars;
use super::track_walks::walk_names;
use anyhow::{Context, Result, bail};
use footslam::filter::FingerprintConfig;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::{RunFolder, TrackPoint, read_walk_manifest, read_wifi_log, write_track};
use footslam::pipeline::{FingerprintJob, FingerprintReport, Named, PreparedFingerprint};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `footslam fingerprint`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Radio map (`radiomap.geojson` as `footslam survey` writes it, or another tool's with
    /// the same properties).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    radiomap: PathBuf,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`).
    #[arg(
        long,
        value_name = "FILE",
        required_unless_present = "walks",
        help_heading = "Inputs"
    )]
    wifi: Option<PathBuf>,
    /// Manifest of walks (as `track --walks` reads it: its `wifi` column, `name` naming each
    /// walk's folder, default `walk-1`, `walk-2`, … as in `learn`): every log placed with
    /// the radio map prepared once, one folder per walk with `walks.csv` beside them.
    #[arg(
        long,
        value_name = "FILE",
        conflicts_with = "wifi",
        help_heading = "Inputs"
    )]
    walks: Option<PathBuf>,
    /// Nearest cells averaged (overrides the config file).
    #[arg(long, value_name = "K", help_heading = "Filter")]
    k: Option<usize>,
    /// Configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
}

/// Runs `footslam fingerprint`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.radiomap, "radio map")?;
    let config: FingerprintConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => FingerprintConfig::default(),
    };
    let logs = logs_of(&args)?;
    let (map, _) = read_radio_map_geojson(&args.radiomap, None)?;
    let prepared = PreparedFingerprint::new(
        Named::new(map, args.radiomap.display().to_string()),
        config,
        args.k,
    )?;
    let bars = Bars::default();
    let folder = super::common::create_run_folder(&output_dir(args.out, "fingerprint"))?;
    let mut reports = Vec::with_capacity(logs.len());
    for (wifi, name) in &logs {
        require_file(wifi, "WiFi log")?;
        let log = read_wifi_log(wifi)?;
        let scans = Named::new(log.scans, wifi.display().to_string());
        let job = prepared.place(&scans, log.duplicate_readings, &bars);
        let job = match name {
            Some(name) => job.with_context(|| format!("walk {name}"))?,
            None => job?,
        };
        match name {
            Some(name) => {
                let child = RunFolder::create(&folder.path(name))?;
                write_job(&child, &job)?;
                child.commit()?;
            }
            None => write_job(&folder, &job)?,
        }
        reports.push(job.report);
    }
    if args.walks.is_some() {
        write_batch(&folder, &logs, &reports, prepared.config())?;
    }
    let out = folder.commit()?;
    let (placed, scans) = reports
        .iter()
        .fold((0, 0), |(p, s), r| (p + r.placed, s + r.scans));
    info!(
        "placed {placed} of {scans} scans{} by the radio map alone: {}",
        match logs.len() {
            1 => String::new(),
            n => format!(" of {n} walks"),
        },
        match args.walks {
            Some(_) => out.clone(),
            None => out.join("track.csv"),
        }
        .display()
    );
    super::verbosity::done(&out, None);
    Ok(())
}

/// The WiFi logs to place: `--wifi`, or the manifest's with each walk's name.
fn logs_of(args: &Args) -> Result<Vec<(PathBuf, Option<String>)>> {
    Ok(match (&args.walks, &args.wifi) {
        (Some(manifest), _) => {
            require_file(manifest, "walk manifest")?;
            let walks = read_walk_manifest(manifest, true)?;
            let names = walk_names(manifest, &walks)?;
            walks
                .into_iter()
                .zip(names)
                .map(|(w, n)| (w.wifi.unwrap_or_default(), Some(n)))
                .collect()
        }
        (None, Some(wifi)) => vec![(wifi.clone(), None)],
        (None, None) => bail!("give --wifi (a WiFi log) or --walks (a manifest of walks)"),
    })
}

/// A batch's `walks.csv`, `config.json` and `summary.json`.
fn write_batch(
    folder: &RunFolder,
    logs: &[(PathBuf, Option<String>)],
    reports: &[FingerprintReport],
    config: &FingerprintConfig,
) -> Result<()> {
    let rows: Vec<NamedRow<FingerprintReport>> = logs
        .iter()
        .zip(reports)
        .map(|((_, name), row)| NamedRow {
            name: name.as_deref().unwrap_or_default(),
            row,
        })
        .collect();
    folder.write("walks.csv", &walks_table(&rows)?)?;
    folder.write_json("config.json", config)?;
    folder.write_json("summary.json", &BatchReport { walks: reports })?;
    Ok(())
}

/// `summary.json` of `fingerprint --walks`: each walk's report.
#[derive(Debug, Serialize)]
struct BatchReport<'a> {
    walks: &'a [FingerprintReport],
}

/// Writes one log's `track.csv`, `config.json` and `summary.json` into `folder`.
fn write_job(folder: &RunFolder, job: &FingerprintJob) -> Result<()> {
    let track: Vec<TrackPoint> = job
        .fixes
        .iter()
        .map(|f| TrackPoint {
            t: f.t,
            x: f.x,
            y: f.y,
            z: 0.0,
            level: f.level,
        })
        .collect();
    write_track(&folder.path("track.csv"), &track)?;
    folder.write_json("config.json", &job.config)?;
    folder.write_json("summary.json", &job.report)?;
    Ok(())
}
