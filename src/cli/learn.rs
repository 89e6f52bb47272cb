//! `footslam learn`: FootSLAM on one walk or a batch of walks, optionally anchored to the
//! world by GPS fixes, a rough building outline and a map learned on earlier walks.
//!
//! [`run`] reads the walks and the anchors ([`super::learn_inputs`]), learns them
//! ([`footslam::pipeline::learn`]), writes each walk's outputs ([`super::learn_outputs`]),
//! the merged maps and the radio map of their WiFi logs ([`super::learn_radio`]), and the
//! run's summary.

use super::batch_table::walks_table;
use super::common::{bundled, output_dir, read_config, walk_prefix, warn};
use super::learn_args::Args;
use super::learn_inputs::{WalkArgs, WalkFiles, check_anchors, read_anchors, read_walks};
use super::learn_outputs::{MapFrame, MapPictures, Summary, write_learned_plan, write_walk};
use super::learn_radio::{RadioSummary, write_learned_radio_map};
use super::progress_bars::Bars;
use anyhow::Result;
use footslam::filter::FootSlamConfig;
use footslam::filter::departure::Trust;
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::map_geojson::{StoredMap, write_walks_map_geojson};
use footslam::map::CellConfig;
use footslam::model::{FieldUnused, ScanPairsUnused};
use footslam::pipeline::{FieldReport, LearnInput, Learned, Quality, default_frame, learn};
use serde::Serialize;
use std::time::Instant;

/// The bundled sample walk, used when `--steps` is not given.
const DEFAULT_STEPS: &str = "datasets/office/steps.csv";

/// `summary.json`: one walk's figures at the top level, or a batch's under `walks`.
#[derive(Debug, Serialize)]
struct RunSummary {
    /// A batch's verdict: its walks' reasons, each named (one walk's is in its summary).
    #[serde(skip_serializing_if = "Option::is_none")]
    quality: Option<Quality>,
    #[serde(flatten)]
    single: Option<Summary>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    walks: Vec<Summary>,
    runtime_s: f64,
    threads: usize,
    outline_edges: usize,
    prior_map_hexagons: usize,
    prior_map_walks: u32,
    /// FeetSLAM iterations run over the batch (`iterations` in the configuration; 0 for
    /// one walk, or for walks in frames of their own).
    iterations: u32,
    peak_memory_bytes: Option<u64>,
    origin: LocalFrame,
    /// The radio map made from the walks' WiFi logs (`--wifi`).
    #[serde(skip_serializing_if = "Option::is_none")]
    radio: Option<RadioSummary>,
    version: &'static str,
}

/// Runs `footslam learn`.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    let config = learn_config(&args)?;
    if let (Some(shard), Some(manifest)) = (args.shard, &args.walks) {
        return super::learn_shard::run(&args, manifest, shard, &config);
    }
    let walk_args = WalkArgs {
        steps: &args.steps,
        gps: &args.gps,
        wifi: &args.wifi,
        starts: &args.start,
        manifest: args.walks.as_deref(),
        gps_t0: args.gps_t0,
    };
    let (files, walks) = read_walks(&walk_args, &bundled(DEFAULT_STEPS))?;
    let cells = CellConfig {
        granularity: args.cell.unwrap_or(CellConfig::default().granularity),
        ..CellConfig::default()
    };
    cells.validate()?;
    let default = |prior: Option<&StoredMap>| Ok(default_frame(prior, &walks));
    let (prior_map, frame, outline) = read_anchors(&args, &config, default)?;
    let anchors = (&frame, outline.as_ref(), args.outline.as_deref());
    check_anchors(&files, &walks, anchors, &config)?;
    let input = LearnInput {
        walks: &walks,
        frame,
        outline: outline.as_ref(),
        prior_map: prior_map.as_ref(),
        cells,
    };
    let pool = super::common::worker_pool(args.threads)?;
    let threads = pool.current_num_threads();
    let learned = pool.install(|| learn(&input, &config, &Bars::default()))?;

    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "learn"))?;
    protect_inputs(&mut folder, &args, &files);
    let mut summary = write_outputs(&folder, &files, &input, &learned, args.picture_extent)?;
    summary.runtime_s = started.elapsed().as_secs_f64();
    summary.threads = threads;
    // One walk: the configuration it ran with (start from its fixes included); a batch: the
    // shared one (each walk's own is in its folder).
    match (walks.len() > 1, learned.walks.first()) {
        (false, Some(run)) => folder.write_json("config.json", &run.config)?,
        _ => folder.write_json("config.json", &config)?,
    }
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    summary.print(&out);
    Ok(())
}

/// Marks every input file of the run as one its outputs must not replace.
fn protect_inputs(folder: &mut RunFolder, args: &Args, files: &[WalkFiles]) {
    folder.protect(
        files
            .iter()
            .flat_map(|w| {
                [
                    Some(&w.steps_path),
                    w.gps_path.as_ref(),
                    w.wifi_path.as_ref(),
                ]
            })
            .flatten()
            .chain(args.prior_map.iter())
            .chain(args.outline.iter())
            .chain(args.config.iter())
            .chain(args.walks.iter()),
    );
}

/// The FootSLAM configuration: the config file's (or the defaults) with the flags'
/// overrides, validated.
fn learn_config(args: &Args) -> Result<FootSlamConfig> {
    let mut config: FootSlamConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => FootSlamConfig::default(),
    };
    if let Some(n) = args.particles {
        config.particles = n;
    }
    if let Some(s) = args.seed {
        config.seed = s;
    }
    if let Some(r) = args.hex_radius {
        config.hex_radius = r;
    }
    if let Some(w) = args.prior_weight {
        config.prior_weight = w;
    }
    if args.ignore_heading {
        config.heading.enabled = false;
    }
    config.validate()?;
    Ok(config)
}

/// The pictures of a map merged from several walks (no one path to draw).
fn merged_pictures<'a>(frame: &MapFrame<'a>) -> MapPictures<'a> {
    MapPictures {
        path: &[],
        path_label: "",
        north_up: frame.anchored,
        outline: frame.outline,
        extent: frame.picture_extent,
    }
}

/// Writes every walk's outputs, the merged maps and the radio map; returns the summary
/// (its runtime and threads left for the caller).
fn write_outputs(
    folder: &RunFolder,
    files: &[WalkFiles],
    input: &LearnInput,
    learned: &Learned,
    picture_extent: Option<[f64; 4]>,
) -> Result<RunSummary> {
    let frame = &input.frame;
    let map_frame = MapFrame::of(input, picture_extent);
    let batch = input.walks.len() > 1;
    let mut summaries = Vec::with_capacity(learned.walks.len());
    for (i, (walk, run)) in input.walks.iter().zip(&learned.walks).enumerate() {
        let prefix = walk_prefix(folder, i, batch)?;
        summaries.push(write_walk(
            folder, &prefix, &files[i], walk, run, &map_frame,
        )?);
        if let Some(Err(why)) = &run.wifi
            && *why != ScanPairsUnused::Disabled
        {
            let name = files[i].steps_path.display();
            warn(&format!(
                "{name}: its WiFi scans did not weigh inside the filter: {why}"
            ));
        }
        let d = &run.departure;
        if d.trust == Trust::DeadReckoning {
            let name = files[i].steps_path.display();
            let answer = if d.answer == Trust::DeadReckoning {
                "track.csv and map.geojson hold the dead-reckoned steps"
            } else {
                "trust dead_reckoning.csv over track.csv"
            };
            warn(&format!(
                "{name}: the learned path departs {:.1} m (p95) from dead reckoning, and {:.0} % \
                 of its revisits are further apart in dead reckoning than it drifts, with no \
                 other evidence: folded by the map alone; {answer}",
                d.p95_m,
                100.0 * d.implausible_share
            ));
        }
        if let (Some(stored), Some(merged)) =
            (input.prior_map, learned.combined.merged_with_prior.get(i))
        {
            let path = folder.path(&format!("{prefix}merged.geojson"));
            write_walks_map_geojson(&path, merged, frame, stored.walks + 1)?;
            let plan = folder.path(&format!("{prefix}merged_plan.geojson"));
            write_learned_plan(&plan, merged, frame)?;
            let at = |name: &str| folder.path(&format!("{prefix}{name}"));
            merged_pictures(&map_frame).write(&at, "merged", merged)?;
        }
    }
    if let Some(merged) = &learned.combined.merged {
        let walks = learned.walks.len() as u32;
        write_walks_map_geojson(&folder.path("merged.geojson"), merged, frame, walks)?;
        write_learned_plan(&folder.path("merged_plan.geojson"), merged, frame)?;
        merged_pictures(&map_frame).write(&|name| folder.path(name), "merged", merged)?;
    }
    let radio = match &learned.combined.radio {
        Some(radio) => Some(write_learned_radio_map(
            folder,
            input.walks,
            radio,
            &input.cells,
            &map_frame,
        )?),
        None => None,
    };
    let (single, walks) = if batch {
        folder.write("walks.csv", &walks_table(&summaries)?)?;
        (None, summaries)
    } else {
        (summaries.pop(), Vec::new())
    };
    let quality = batch.then(|| {
        Quality::combined(
            walks
                .iter()
                .enumerate()
                .map(|(i, s)| (format!("walk {}", i + 1), &s.quality)),
        )
    });
    Ok(RunSummary {
        quality,
        single,
        walks,
        runtime_s: 0.0,
        threads: 0,
        outline_edges: learned.outline_edges,
        prior_map_hexagons: learned.prior_map_hexagons,
        prior_map_walks: learned.prior_map_walks,
        iterations: learned.iterations,
        peak_memory_bytes: footslam::memory::peak_bytes(),
        origin: *frame,
        radio,
        version: env!("CARGO_PKG_VERSION"),
    })
}

/// The magnetic field's part in one line: what it weighed, or why nothing.
fn field_line(f: &FieldReport) -> String {
    let spreads = f.calibration.as_ref().map_or(String::new(), |c| {
        format!(
            " (readings one cell apart differ by {:.1} µT, unrelated places by {:.1} µT)",
            c.near_sd_ut[0], c.far_sd_ut[0]
        )
    });
    match f.unused {
        None => format!("{} steps weighed{spreads}", f.steps_weighed),
        Some(FieldUnused::Disabled) => "not used ([field] enabled = false)".into(),
        Some(FieldUnused::TooFewReadings) => format!(
            "not used: {} readings are too few to calibrate",
            f.steps_with_field
        ),
        Some(FieldUnused::NoContrast) => {
            format!("not used: it hardly varies between places{spreads}")
        }
    }
}

impl RunSummary {
    /// Prints each walk's figures and the output folder.
    fn print(&self, out: &std::path::Path) {
        let batch = !self.walks.is_empty();
        for (i, s) in self.single.iter().chain(&self.walks).enumerate() {
            let walk = if batch {
                format!("walk {}: ", i + 1)
            } else {
                String::new()
            };
            let gps = if s.gps_fixes > 0 {
                format!(" and {} GPS fixes", s.gps_fixes_used)
            } else {
                String::new()
            };
            info!(
                "{walk}learned {} hexagons from {} steps{gps} with {} particles in {:.2} s ({:.2e} particle-steps/s); final ESS {:.0}",
                s.hexagons,
                s.steps,
                s.particles,
                s.filter_runtime_s,
                s.particle_steps_per_s,
                s.final_effective_sample_size
            );
            let m = &s.smoothing;
            if m.averaged_paths > 1 {
                info!(
                    "{walk}track.csv: the mean of {} final paths; they spread {:.2} m about it (median over the steps), {:.2} m at most",
                    m.averaged_paths, m.spread_median_m, m.spread_max_m
                );
            }
            if let Some(f) = &s.magnetic_field {
                info!("{walk}magnetic field: {}", field_line(f));
            }
        }
        let quality = self
            .quality
            .as_ref()
            .or(self.single.as_ref().map(|s| &s.quality));
        super::verbosity::done(out, quality.map(|q| q.line()).as_deref());
    }
}
