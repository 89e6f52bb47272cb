//! `footslam merge`: combine maps learned on several walks of one building.

use super::common::{output_dir, require_file, warn};
use super::learn_outputs::MapPictures;
use anyhow::{Result, bail};
use footslam::io::floor_plan_geojson::write_floor_plan;
use footslam::io::map_geojson::{read_stored_map, write_walks_map_geojson};
use footslam::pipeline::{MergeJob, MergeRequest, Named, run_merge};
use std::path::PathBuf;

/// Arguments of `footslam merge`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Learned maps (map.geojson) sharing one frame (origin and hexagon radius), as
    /// GPS-anchored walks learned with one `--origin` (or one prior map) do.
    #[arg(required = true, num_args = 1..)]
    maps: Vec<PathBuf>,
    /// Relative weight of each map's counts, comma-separated, one per map (default all 1):
    /// the largest counts each crossing once, the others in proportion; 0 leaves a map out.
    #[arg(
        long,
        value_delimiter = ',',
        value_name = "W1,W2,...",
        help_heading = "Filter"
    )]
    weights: Vec<f64>,
    /// Output folder (default: a new folder under `outputs/`): `merged.geojson` (the format
    /// of map.geojson), its walkable plan `merged_plan.geojson`, the picture `merged.png`,
    /// `config.json` and `summary.json`. A path ending in `.geojson` writes that one file
    /// instead (the older form; deprecated).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
}

/// An error when `out` is one of the input maps (the same file, by any path): the merge
/// would replace an input it has not finished reading from the user's point of view, and a
/// failed merge would leave neither.
fn refuse_overwriting_an_input(out: &std::path::Path, maps: &[PathBuf]) -> Result<()> {
    let Ok(out_real) = std::fs::canonicalize(out) else {
        return Ok(()); // A new file: not an input.
    };
    for m in maps {
        if std::fs::canonicalize(m).is_ok_and(|p| p == out_real) {
            bail!(
                "--out {} is the input map {}: write the merged map to another file",
                out.display(),
                m.display()
            );
        }
    }
    Ok(())
}

/// Runs `footslam merge`.
pub fn run(args: Args) -> Result<()> {
    let one_file = args.out.as_ref().filter(|o| {
        o.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("geojson"))
            || o.is_file()
    });
    if let Some(out) = one_file {
        refuse_overwriting_an_input(out, &args.maps)?;
        warn(&format!(
            "--out {}: merge now writes a folder like every command (merged.geojson, \
             merged_plan.geojson, merged.png); writing the one file, as before, for this release",
            out.display()
        ));
    }
    warn_repeated(&args.maps);
    let maps = args
        .maps
        .iter()
        .map(|path| {
            require_file(path, "map")?;
            Ok(Named::new(
                read_stored_map(path)?,
                path.display().to_string(),
            ))
        })
        .collect::<Result<Vec<_>>>()?;
    let job = run_merge(MergeRequest {
        maps,
        weights: args.weights.clone(),
    })?;
    let merged = &job.merged;
    info!(
        "merged {} maps ({} walks) into {} hexagons",
        args.maps.len(),
        merged.walks,
        merged.map.cells.len(),
    );
    if let Some(out) = one_file {
        write_walks_map_geojson(out, &merged.map, &merged.frame, merged.walks)?;
        info!("wrote {}", out.display());
        return Ok(());
    }
    write_merged_folder(&args, &job)
}

/// The merge's run folder: the merged map, its plan and pictures, configuration and summary.
fn write_merged_folder(args: &Args, job: &MergeJob) -> Result<()> {
    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "merge"))?;
    folder.protect(args.maps.iter());
    let (map, frame) = (&job.merged.map, &job.merged.frame);
    write_walks_map_geojson(&folder.path("merged.geojson"), map, frame, job.merged.walks)?;
    if let Some(plan) = &job.plan {
        write_floor_plan(&folder.path("merged_plan.geojson"), &plan.plan, frame)?;
    }
    let pictures = MapPictures {
        path: &[],
        path_label: "",
        // Maps are merged only in one frame; whether it points north is not recorded.
        north_up: false,
        outline: None,
        extent: None,
    };
    pictures.write(&|name| folder.path(name), "merged", map)?;
    folder.write_json(
        "config.json",
        &serde_json::json!({ "maps": &args.maps, "weights": &args.weights }),
    )?;
    folder.write_json("summary.json", &job.report)?;
    let out = folder.commit()?;
    super::verbosity::done(&out, None);
    Ok(())
}

/// One map given twice counts its walks twice: says so (a user may mean it as a weight).
fn warn_repeated(paths: &[PathBuf]) {
    let mut seen: Vec<PathBuf> = Vec::new();
    for path in paths {
        let key = path.canonicalize().unwrap_or_else(|_| path.clone());
        if seen.contains(&key) {
            warn(&format!(
                "{} is given twice: its counts are added twice (use --weights to weigh a map)",
                path.display()
            ));
        }
        seen.push(key);
    }
}
