//! `footslam learn`: FootSLAM on one walk or a batch of walks, optionally anchored to the
//! world by GPS fixes, a rough building outline and a map learned on earlier walks.
//!
//! [`run`] reads the walks and the anchors into the job's request
//! ([`super::learn_inputs`]), prepares and learns them ([`footslam::pipeline::learn_job`]),
//! writes each walk's outputs ([`super::learn_outputs`]), the merged maps and the radio map
//! of their WiFi logs, and the job's report ([`LearnReport`]) as `summary.json`.

use super::batch_table::walks_table;
use super::common::{bundled, output_dir, walk_prefix, warn};
use super::learn_args::Args;
use super::learn_inputs::{Found, WalkArgs, find_walks, read_request};
use super::learn_outputs::{MapFrame, MapPictures, write_learned_plan, write_walk};
use super::progress_bars::Bars;
use super::radio_outputs::{Heatmaps, print_heatmaps, write_radio_map_files};
use anyhow::Result;
use footslam::filter::departure::Trust;
use footslam::io::RunFolder;
use footslam::io::map_geojson::write_walks_map_geojson;
use footslam::model::{FieldUnused, ScanPairsUnused};
use footslam::pipeline::{
    FieldReport, LearnReport, Learned, PreparedLearn, WalkReport, prepare_learn,
};
use std::time::Instant;

/// The bundled sample walk, used when `--steps` is not given.
const DEFAULT_STEPS: &str = "datasets/office/steps.csv";

/// Runs `footslam learn`.
pub fn run(args: Args) -> Result<()> {
    let started = Instant::now();
    if let (Some(shard), Some(manifest)) = (args.shard, &args.walks) {
        return super::learn_shard::run(&args, manifest, shard);
    }
    let walk_args = WalkArgs {
        steps: &args.steps,
        gps: &args.gps,
        wifi: &args.wifi,
        starts: &args.start,
        manifest: args.walks.as_deref(),
    };
    let found = find_walks(&walk_args, &bundled(DEFAULT_STEPS))?;
    let bars = Bars::default();
    let prepared = prepare_learn(read_request(&args, &found)?, &bars)?;
    let pool = super::common::worker_pool(args.threads)?;
    let learned = pool.install(|| prepared.run(&bars))?;

    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "learn"))?;
    protect_inputs(&mut folder, &args, &found);
    let heatmaps = args.heatmaps.unwrap_or(Heatmaps::DEFAULT);
    let pictures = (args.picture_extent, heatmaps);
    let walks = pool.install(|| write_outputs(&folder, &prepared, &learned, pictures))?;
    let threads = pool.current_num_threads();
    let report = LearnReport::new(&prepared, &learned, walks, started, threads);
    folder.write_json("config.json", &prepared.config_run(&learned))?;
    folder.write_json("summary.json", &report)?;
    let out = folder.commit()?;
    print_report(&report, &out);
    Ok(())
}

/// Marks every input file of the run as one its outputs must not replace.
fn protect_inputs(folder: &mut RunFolder, args: &Args, found: &[Found]) {
    folder.protect(
        found
            .iter()
            .flat_map(|w| [Some(&w.steps), w.gps.as_ref(), w.wifi.as_ref()])
            .flatten()
            .chain(args.prior_map.iter())
            .chain(args.outline.iter())
            .chain(args.config.iter())
            .chain(args.walks.iter()),
    );
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

/// Writes every walk's outputs, the merged maps and the radio map; returns the walks'
/// reports.
fn write_outputs(
    folder: &RunFolder,
    prepared: &PreparedLearn,
    learned: &Learned,
    (picture_extent, heatmaps): (Option<[f64; 4]>, Heatmaps),
) -> Result<Vec<WalkReport>> {
    let frame = &prepared.frame;
    let map_frame = MapFrame::of(prepared, picture_extent);
    let batch = prepared.walks.len() > 1;
    let mut reports = Vec::with_capacity(learned.walks.len());
    for (i, (walk, run)) in prepared.walks.iter().zip(&learned.walks).enumerate() {
        let prefix = walk_prefix(folder, i, batch)?;
        let labels = &prepared.labels[i];
        reports.push(write_walk(folder, &prefix, labels, walk, run, &map_frame)?);
        warn_walk(&labels.steps, run);
        if let (Some(stored), Some(merged)) = (
            &prepared.prior_map,
            learned.combined.merged_with_prior.get(i),
        ) {
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
    if let Some(radio) = &learned.combined.radio {
        let pictures = (frame, map_frame.anchored, picture_extent, heatmaps);
        let drawn =
            write_radio_map_files(folder, "", &radio.plan.plan, &radio.survey.map, pictures)?;
        print_heatmaps(drawn, &radio.survey.map);
    }
    if batch {
        folder.write("walks.csv", &walks_table(&reports)?)?;
    }
    Ok(reports)
}

/// Warns of a walk (its steps `name`) whose scans did not weigh, or whose answer is no
/// better supported than dead reckoning.
fn warn_walk(name: &str, run: &footslam::pipeline::WalkRun) {
    if let Some(Err(why)) = &run.wifi
        && *why != ScanPairsUnused::Disabled
    {
        warn(&format!(
            "{name}: its WiFi scans did not weigh inside the filter: {why}"
        ));
    }
    let d = &run.departure;
    if d.trust == Trust::DeadReckoning {
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

/// Prints each walk's figures and the output folder.
fn print_report(report: &LearnReport, out: &std::path::Path) {
    let batch = !report.walks.is_empty();
    for (i, s) in report.walk_reports().enumerate() {
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
    let quality = report
        .quality
        .as_ref()
        .or(report.single.as_ref().map(|s| &s.quality));
    super::verbosity::done(out, quality.map(|q| q.line()).as_deref());
}
