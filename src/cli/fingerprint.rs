//! `footslam fingerprint`: each WiFi scan placed by the radio map alone (weighted k-nearest
//! fingerprints) — the baseline that tracking with the radio map should beat.

use super::common::{check_scans_match, output_dir, read_config, read_wifi_warned, require_file};
use anyhow::{Result, bail};
use footslam::filter::{FingerprintConfig, NearestFingerprint};
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::{TrackPoint, write_track};
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
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    wifi: PathBuf,
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

#[derive(Debug, Serialize)]
struct Summary {
    radiomap_file: String,
    wifi_file: String,
    scans: usize,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    duplicate_readings: usize,
    placed: usize,
    /// Scans that share no access point with the map.
    unplaced: usize,
    version: &'static str,
}

/// The configuration file's (or the defaults) with `--k`.
fn fingerprint_config(args: &Args) -> Result<FingerprintConfig> {
    let mut config: FingerprintConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => FingerprintConfig::default(),
    };
    if let Some(k) = args.k {
        config.k = k;
    }
    Ok(config)
}

/// Runs `footslam fingerprint`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.radiomap, "radio map")?;
    require_file(&args.wifi, "WiFi log")?;
    let config = fingerprint_config(&args)?;
    let (map, _) = read_radio_map_geojson(&args.radiomap, None)?;
    let localiser = NearestFingerprint::new(&map, &config)?;
    let log = read_wifi_warned(&args.wifi)?;
    let scans = log.scans;
    check_scans_match(&map, &scans, &args.radiomap, &args.wifi)?;
    let fixes: Vec<_> = scans.iter().filter_map(|s| localiser.locate(s)).collect();
    if fixes.is_empty() {
        bail!(
            "none of the {} scans of {} shares an access point with the radio map {}: is it \
             the same building?",
            scans.len(),
            args.wifi.display(),
            args.radiomap.display()
        );
    }
    let out = output_dir(args.out, "fingerprint");
    let folder = super::common::create_run_folder(&out)?;
    let track: Vec<TrackPoint> = fixes
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
    folder.write_json("config.json", &config)?;
    folder.write_json(
        "summary.json",
        &Summary {
            radiomap_file: args.radiomap.display().to_string(),
            wifi_file: args.wifi.display().to_string(),
            scans: scans.len(),
            duplicate_readings: log.duplicate_readings,
            placed: fixes.len(),
            unplaced: scans.len() - fixes.len(),
            version: env!("CARGO_PKG_VERSION"),
        },
    )?;
    let out = folder.commit()?;
    info!(
        "placed {} of {} scans by the radio map alone: {}",
        fixes.len(),
        scans.len(),
        out.join("track.csv").display()
    );
    super::verbosity::done(&out, None);
    Ok(())
}
