//! `footslam merge`: combine maps learned on several walks of one building.

use super::common::{output_dir, require_file, warn};
use super::learn_outputs::{MapPictures, write_learned_plan};
use anyhow::{Result, bail};
use footslam::io::map_geojson::{StoredMap, read_stored_map, write_walks_map_geojson};
use footslam::pipeline::{SAME_ORIGIN_M, merge};
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

/// `summary.json` of a merge.
#[derive(Debug, serde::Serialize)]
struct Summary<'a> {
    maps: Vec<String>,
    weights: &'a [f64],
    walks: u32,
    hexagons: usize,
    /// Walkable area of `merged_plan.geojson`, m² (`None`: too little to make a plan of).
    walkable_plan_m2: Option<f64>,
    version: &'static str,
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
    check_weights(&args.weights, args.maps.len())?;
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
    let maps = read_maps(&args.maps)?;
    let weighted: Vec<_> = maps
        .iter()
        .enumerate()
        .map(|(i, m)| (m, args.weights.get(i).copied().unwrap_or(1.0)))
        .collect();
    let merged = merge(&weighted)?;
    info!(
        "merged {} maps ({} walks) into {} hexagons",
        maps.len(),
        merged.walks,
        merged.map.cells.len(),
    );
    if let Some(out) = one_file {
        write_walks_map_geojson(out, &merged.map, &merged.frame, merged.walks)?;
        info!("wrote {}", out.display());
        return Ok(());
    }
    write_merged_folder(&args, &merged)
}

/// The merge's run folder: the merged map, its plan and pictures, configuration and summary.
fn write_merged_folder(args: &Args, merged: &StoredMap) -> Result<()> {
    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "merge"))?;
    folder.protect(args.maps.iter());
    let (map, frame) = (&merged.map, &merged.frame);
    write_walks_map_geojson(&folder.path("merged.geojson"), map, frame, merged.walks)?;
    let walkable_plan_m2 = write_learned_plan(&folder.path("merged_plan.geojson"), map, frame)?;
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
    folder.write_json(
        "summary.json",
        &Summary {
            maps: args.maps.iter().map(|p| p.display().to_string()).collect(),
            weights: &args.weights,
            walks: merged.walks,
            hexagons: map.cells.len(),
            walkable_plan_m2,
            version: env!("CARGO_PKG_VERSION"),
        },
    )?;
    let out = folder.commit()?;
    super::verbosity::done(&out, None);
    Ok(())
}

/// `--weights`: none, or one finite weight ≥ 0 per map, not all 0.
fn check_weights(weights: &[f64], maps: usize) -> Result<()> {
    if !weights.is_empty() && weights.len() != maps {
        bail!(
            "{} weights for {maps} maps: give one weight per map",
            weights.len()
        );
    }
    if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        bail!("--weights: {w} is not a finite weight ≥ 0");
    }
    if !weights.is_empty() && weights.iter().all(|&w| w == 0.0) {
        bail!(
            "--weights are all 0: the merged map would be empty; give at least one map weight > 0"
        );
    }
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

/// Reads the maps, which must share the first one's frame.
fn read_maps(paths: &[PathBuf]) -> Result<Vec<StoredMap>> {
    let mut maps = Vec::with_capacity(paths.len());
    for path in paths {
        require_file(path, "map")?;
        maps.push(read_stored_map(path)?);
    }
    let frame = maps[0].frame;
    for (path, f) in paths.iter().zip(maps.iter().map(|m| &m.frame)).skip(1) {
        let off = frame.distance_to(f);
        if off > SAME_ORIGIN_M {
            bail!(
                "{}: its origin ({}, {}) lies {off:.3} m from the first map's ({}, {}); \
                 only maps in one frame merge (learn the walks with one --origin)",
                path.display(),
                f.lat,
                f.lon,
                frame.lat,
                frame.lon
            );
        }
    }
    Ok(maps)
}
