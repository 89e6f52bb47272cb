//! The arguments of `footslam learn`, with `--shard`'s `I/N`.

use super::common::parse_origin;
use footslam::filter::StartPose;
use footslam::geometry::LocalFrame;
use footslam::io::parse_utc_time;
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `footslam learn`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Step trace CSV (`t,length,dheading[,dz][,heading]`; an absolute `heading` column sets
    /// the start heading and weights the particles, see `--ignore-heading`), or a folder holding `steps.csv`
    /// or sub-folders that do (one walk each, with `gps.csv` or `gps.gpx` beside it when
    /// there is one). Repeat for a batch of walks, learned in parallel (walk i has seed
    /// `seed + i`). Default: the bundled sample walk.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) steps: Vec<PathBuf>,
    /// GPS fixes: CSV `t,lat,lon[,accuracy]` on the steps' clock, or GPX 1.1 (by the `.gpx`
    /// extension). Repeat once per walk, in the order of the walks.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) gps: Vec<PathBuf>,
    /// UTC time of the steps' `t = 0` for GPX files (RFC 3339, e.g. 2024-05-01T10:00:00Z,
    /// or Unix seconds). Default: the steps' `t` are Unix seconds.
    #[arg(long, value_parser = parse_utc_time, value_name = "UTC_TIME", help_heading = "Inputs")]
    pub(super) gps_t0: Option<f64>,
    /// WiFi log CSV (`t,bssid,rssi[,ssid,freq]`) of a walk, on the steps' clock: its scans
    /// weigh the particles (each against the walker's earlier scans, `[wifi]` in the
    /// config), then are placed on the learned path and make a radio map on the plan
    /// learned from the run's map (`radiomap.geojson`, `radiomap.csv`, heatmaps and ε, as
    /// `footslam survey` writes them). Repeat once per walk, in the order of the walks; a walk folder's
    /// `wifi.csv` is found without it.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) wifi: Vec<PathBuf>,
    /// Radio-map cell granularity with WiFi, metres (default 3).
    #[arg(long, value_name = "METRES", help_heading = "Filter")]
    pub(super) cell: Option<f64>,
    /// Building outline (GeoJSON Polygon, Feature or `FeatureCollection` of one), known to a
    /// few metres: crossing it becomes improbable (low Dirichlet prior `outline_alpha`).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) outline: Option<PathBuf>,
    /// A map learned earlier (map.geojson, a `footslam merge` of several, or the
    /// merged.geojson of a walk learned with a prior map): its counts become prior
    /// pseudo-counts. Its origin becomes the default origin. The run then also writes
    /// merged.geojson: the prior and this walk's map in this walk's frame (the next walk's
    /// prior; with GPS the frame averages the walks' GPS biases).
    #[arg(
        long = "map",
        alias = "prior-map",
        value_name = "FILE",
        help_heading = "Inputs"
    )]
    pub(super) prior_map: Option<PathBuf>,
    /// Weight of the prior map's counts (overrides the config file; default 1).
    #[arg(
        long = "map-weight",
        alias = "prior-weight",
        value_name = "WEIGHT",
        help_heading = "Filter"
    )]
    pub(super) prior_weight: Option<f64>,
    /// Number of particles (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    pub(super) particles: Option<usize>,
    /// Random seed (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    pub(super) seed: Option<u64>,
    /// Hexagon circumradius in metres (overrides the config file; default 0.5).
    #[arg(long, value_name = "METRES", help_heading = "Filter")]
    pub(super) hex_radius: Option<f64>,
    /// WGS84 origin of the local frame, `LAT,LON` in degrees. Default: the prior map's
    /// origin, else the first GPS fix, else 0,0.
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true, value_name = "LAT,LON", help_heading = "Inputs")]
    pub(super) origin: Option<LocalFrame>,
    /// FootSLAM configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    pub(super) out: Option<PathBuf>,
    /// The part of the frame the pictures show (maps, radio map, heatmaps), `X0,Y0,X1,Y1`
    /// local metres (default: the map and the path, and the building outline within 10 m of
    /// them).
    #[arg(long, value_parser = super::common::parse_extent, allow_hyphen_values = true, value_name = "X0,Y0,X1,Y1", help_heading = "Outputs")]
    pub(super) picture_extent: Option<[f64; 4]>,
    /// With `--wifi`: heatmaps for the N access points heard in the most cells, or `all`
    /// [default: 24].
    #[arg(long, value_parser = super::radio_outputs::parse_heatmaps, value_name = "N|all", help_heading = "Outputs")]
    pub(super) heatmaps: Option<super::radio_outputs::Heatmaps>,
    /// Worker threads (default: all cores; at most 4 per core). Results do not depend on it.
    #[arg(long, value_name = "N", help_heading = "Filter")]
    pub(super) threads: Option<usize>,
    /// The walk's known start, `X,Y[,HEADING[,LEVEL]]` (metres in the local frame, radians
    /// counter-clockwise from east, the floor level; `X,Y,,LEVEL` for a level without a
    /// heading). Without HEADING the start heading is unknown (the step headings set it
    /// where the trace has them). Repeat once per walk, in the order of the walks: walks
    /// with known starts are learned into one frame. A given start wins over the first GPS
    /// fix.
    #[arg(long, value_parser = super::track::parse_start, allow_hyphen_values = true, value_name = "X,Y[,HEADING[,LEVEL]]", help_heading = "Inputs")]
    pub(super) start: Vec<StartPose>,
    /// Walk manifest CSV instead of `--steps`/`--gps`/`--wifi`/`--start`: a header naming
    /// `steps` and optionally `gps`, `wifi` and `start` (as `--start`, quoted), one walk a
    /// row, paths relative to the manifest.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) walks: Option<PathBuf>,
    /// Learn only shard `K` of `N` (counted from 1, as walks are) of the `--walks`
    /// manifest: walks `K`, `K + N`, `K + 2N`, … (the manifest's rows, from 1), each exactly
    /// as in the whole batch (walk `w` with seed `seed + w − 1`), into `walk-<w>/`. For batch
    /// schedulers (Slurm arrays, Kubernetes jobs): run the shards of a pass in any order or
    /// place, then `footslam merge` their `walk-*/map.geojson`.
    #[arg(long, value_parser = parse_shard, requires = "walks", value_name = "K/N", help_heading = "Filter")]
    pub(super) shard: Option<Shard>,
    /// With `--shard`: the shard folders of the previous pass (repeat, or one folder per
    /// shard): this shard runs a FeetSLAM pass, each walk against the merged map of the
    /// other walks' `walk-<k>/map.geojson` there. Without it: the first pass, each walk
    /// alone.
    #[arg(long, requires = "shard", value_name = "DIR", help_heading = "Inputs")]
    pub(super) previous: Vec<PathBuf>,
    /// Ignore the step traces' absolute `heading` column (same as `heading.enabled = false`
    /// in the config): the walk then starts at `start.heading` (default 0, east).
    #[arg(long, help_heading = "Inputs")]
    pub(super) ignore_heading: bool,
}

/// `--shard K/N`: shard `K` of `N`, counted from 1 as walks (`walk-1/`) are.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Shard {
    /// This shard, 0-based (`K − 1`): `0 ≤ index < count`. Not in `summary.json`, which
    /// gives `number`.
    #[serde(skip)]
    pub index: usize,
    /// This shard as the user numbers it, `1 ≤ number ≤ count`.
    pub number: usize,
    /// Shards in all.
    pub count: usize,
}

/// Parses `K/N` with `1 ≤ K ≤ N`.
pub fn parse_shard(s: &str) -> Result<Shard, String> {
    let (k, n) = s
        .split_once('/')
        .ok_or_else(|| format!("expected K/N (shard K of N, 1 ≤ K ≤ N), got `{s}`"))?;
    let number = |v: &str, what: &str| {
        v.trim()
            .parse::<usize>()
            .map_err(|_| format!("{what} `{v}` is not a whole number ≥ 1"))
    };
    let (number, count) = (number(k, "shard")?, number(n, "shard count")?);
    if number == 0 && count > 0 {
        return Err(format!(
            "shard 0 of {count}: shards count from 1, as walks do (`walk-1/`): `--shard 1/{count}` \
             is the first (earlier releases counted from 0; add 1 to the shard, e.g. \
             `$((SLURM_ARRAY_TASK_ID + 1))` for a 0-based array)"
        ));
    }
    if count == 0 || number > count {
        return Err(format!("shard {number} of {count}: need 1 ≤ K ≤ N"));
    }
    Ok(Shard {
        index: number - 1,
        number,
        count,
    })
}
