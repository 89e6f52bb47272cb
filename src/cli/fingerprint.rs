//! `footslam fingerprint`: each WiFi scan placed by the radio map alone (weighted k-nearest
//! fingerprints) — the baseline that tracking with the radio map should beat.

use super::common::{output_dir, read_config, require_file};
use super::progress_bars::Bars;
use anyhow::Result;
use footslam::filter::FingerprintConfig;
use footslam::io::radio_map_geojson::read_radio_map_geojson;
use footslam::io::{TrackPoint, read_wifi_log, write_track};
use footslam::pipeline::{FingerprintRequest, Named, run_fingerprint};
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

/// Runs `footslam fingerprint`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.radiomap, "radio map")?;
    require_file(&args.wifi, "WiFi log")?;
    let config: FingerprintConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => FingerprintConfig::default(),
    };
    let (map, _) = read_radio_map_geojson(&args.radiomap, None)?;
    let log = read_wifi_log(&args.wifi)?;
    let request = FingerprintRequest {
        map: Named::new(map, args.radiomap.display().to_string()),
        wifi: Named::new(log.scans, args.wifi.display().to_string()),
        duplicate_readings: log.duplicate_readings,
        config,
        k: args.k,
    };
    let job = run_fingerprint(request, &Bars::default())?;
    let folder = super::common::create_run_folder(&output_dir(args.out, "fingerprint"))?;
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
    let out = folder.commit()?;
    let report = &job.report;
    info!(
        "placed {} of {} scans by the radio map alone: {}",
        report.placed,
        report.scans,
        out.join("track.csv").display()
    );
    super::verbosity::done(&out, None);
    Ok(())
}
