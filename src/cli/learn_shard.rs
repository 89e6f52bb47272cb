//! `learn --walks M --shard I/N`: one shard of a batch, for batch schedulers without Python
//! (Slurm arrays, Kubernetes indexed jobs). Walk `k` of the manifest (0-based) belongs to
//! shard `k mod N` and is learned exactly as in the unsharded batch — seed `seed + k`, the
//! batch's frame, outline and prior map — into `walk-<k+1>/`. With `--previous`, the shard
//! runs a FeetSLAM pass: each walk's prior is the merged map of the other walks' maps in the
//! previous pass's shard folders. Outputs depend only on the arguments, so a shard run again
//! rewrites the same files; `footslam merge` of the last pass's `walk-*/map.geojson` (in walk
//! order) gives the batch's `merged.geojson`.

use super::common::{output_dir, walk_prefix};
use super::learn_args::{Args, Shard};
use super::learn_inputs::{read_found, read_manifest, read_prior_map, read_request};
use super::learn_outputs::{MapFrame, write_walk};
use super::progress_bars::Bars;
use anyhow::{Context, Result, bail};
use footslam::geometry::LocalFrame;
use footslam::io::map_geojson::{StoredMap, read_stored_map};
use footslam::io::{ManifestWalk, RunFolder};
use footslam::map::HexMapSnapshot;
use footslam::pipeline::{
    ItemProgress, PreparedLearn, Progress, WalkReport, WalkRun, default_frame, others_map,
    prepare_learn,
};
use rayon::prelude::*;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `summary.json` of a shard.
#[derive(Debug, Serialize)]
struct ShardSummary {
    shard: Shard,
    /// The manifest's walks in all, and this shard's (1-based, as the `walk-<k>` folders).
    manifest_walks: usize,
    shard_walks: Vec<usize>,
    /// The previous pass's shard folders (empty: the first pass, each walk alone).
    previous: Vec<String>,
    walks: Vec<WalkReport>,
    runtime_s: f64,
    peak_memory_bytes: Option<u64>,
    origin: LocalFrame,
    version: &'static str,
}

/// Learns the prepared shard's walks (their manifest rows `mine`, and in a FeetSLAM pass
/// the other walks' maps `others`) in parallel, a bar for the walks and one per walk.
fn learn_shard_walks(
    args: &Args,
    prepared: &PreparedLearn,
    mine: &[usize],
    others: &[Option<HexMapSnapshot>],
) -> Result<Vec<WalkRun>> {
    let pool = super::common::worker_pool(args.threads)?;
    let bars = Bars::default();
    bars.start("learning the shard's walks", mine.len() as u64);
    let runs = pool.install(|| {
        (0..mine.len())
            .into_par_iter()
            .map(|i| {
                let item = ItemProgress {
                    inner: &bars,
                    item: i,
                    label: format!("walk {}", mine[i] + 1),
                };
                let run = prepared.run_one(i, mine[i], others[i].as_ref(), Some(&item));
                bars.advance(1);
                run
            })
            .collect::<footslam::Result<Vec<_>>>()
    })?;
    bars.finish();
    Ok(runs)
}

/// Runs one shard of `learn --walks`.
pub fn run(args: &Args, manifest: &Path, shard: Shard) -> Result<()> {
    let started = Instant::now();
    let all = read_manifest(manifest)?;
    let mine: Vec<usize> = (shard.index..all.len()).step_by(shard.count).collect();
    let found: Vec<ManifestWalk> = mine.iter().map(|&k| all[k].clone()).collect();
    let mut request = read_request(args, &found)?;
    if request.origin.is_none() {
        let prior = read_prior_map(args)?;
        request.origin = Some(batch_frame(args, &all, prior.as_ref().map(|m| &m.value))?);
    }
    let prepared = prepare_learn(request, &Bars::default())?;
    let others = previous_priors(&args.previous, &all, &mine)?;
    let runs = learn_shard_walks(args, &prepared, &mine, &others)?;
    let folder = shard_folder(args, manifest, &all)?;
    let mut summaries = Vec::with_capacity(runs.len());
    let map_frame = MapFrame::of(&prepared, args.picture_extent);
    for (i, run) in runs.iter().enumerate() {
        let prefix = walk_prefix(&folder, mine[i], true)?;
        let (labels, walk) = (&prepared.labels[i], &prepared.walks[i]);
        summaries.push(write_walk(&folder, &prefix, labels, walk, run, &map_frame)?);
    }
    folder.write_json("config.json", &prepared.config)?;
    let summary = ShardSummary {
        shard,
        manifest_walks: all.len(),
        shard_walks: mine.iter().map(|k| k + 1).collect(),
        previous: args
            .previous
            .iter()
            .map(|p| p.display().to_string())
            .collect(),
        walks: summaries,
        runtime_s: started.elapsed().as_secs_f64(),
        peak_memory_bytes: footslam::memory::peak_bytes(),
        origin: prepared.frame,
        version: env!("CARGO_PKG_VERSION"),
    };
    folder.write_json("summary.json", &summary)?;
    let out = folder.commit()?;
    let (walks, n) = (&summary.shard_walks, all.len());
    info!(
        "shard {}/{}: learned walks {walks:?} of {n}",
        shard.number, shard.count
    );
    super::verbosity::done(&out, None);
    Ok(())
}

/// The shard's output folder, every input of the batch protected.
fn shard_folder(args: &Args, manifest: &Path, all: &[ManifestWalk]) -> Result<RunFolder> {
    let mut folder = super::common::create_run_folder(&output_dir(args.out.clone(), "learn"))?;
    folder.protect(
        all.iter()
            .flat_map(|w| [Some(&w.steps), w.gps.as_ref(), w.wifi.as_ref()])
            .flatten()
            .chain([manifest.to_path_buf()].iter())
            .chain(args.prior_map.iter())
            .chain(args.outline.iter())
            .chain(args.config.iter()),
    );
    Ok(folder)
}

/// The batch's frame without `--origin`, the same in every shard: the prior map's, else
/// the first GPS fix of the manifest's walks in order (not only this shard's), else (0, 0).
fn batch_frame(
    args: &Args,
    all: &[ManifestWalk],
    prior_map: Option<&StoredMap>,
) -> Result<LocalFrame> {
    let first_with_gps: Vec<ManifestWalk> = all
        .iter()
        .filter(|w| w.gps.is_some())
        .take(1)
        .cloned()
        .collect();
    let walks: Vec<_> = read_found(&first_with_gps, args.gps_t0)?
        .into_iter()
        .map(|w| footslam::pipeline::LearnWalk {
            fixes: w.gps.map(|g| g.0.value).unwrap_or_default(),
            ..Default::default()
        })
        .collect();
    Ok(default_frame(prior_map, &walks))
}

/// Per walk of this shard (`mine`, 0-based manifest indices): in a FeetSLAM pass, the
/// merged map of the other walks' maps of the previous pass, found as `walk-<k>/map.geojson`
/// in the `previous` folders (each walk of the manifest exactly once); `None` in the first.
fn previous_priors(
    previous: &[PathBuf],
    all: &[ManifestWalk],
    mine: &[usize],
) -> Result<Vec<Option<HexMapSnapshot>>> {
    if previous.is_empty() {
        return Ok(vec![None; mine.len()]);
    }
    if all.len() < 2 || all.iter().any(|w| w.start.is_none()) {
        bail!(
            "--previous: FeetSLAM passes need a batch of walks that each start at a known place \
             (a manifest `start` for every walk); these walks do not share a frame"
        );
    }
    let maps = (1..=all.len())
        .map(|k| {
            let found: Vec<PathBuf> = previous
                .iter()
                .map(|d| d.join(format!("walk-{k}/map.geojson")))
                .filter(|p| p.is_file())
                .collect();
            match found.as_slice() {
                [one] => read_stored_map(one).map(|m| m.map).map_err(Into::into),
                [] => bail!(
                    "--previous: no folder holds walk-{k}/map.geojson (walk {k} of {}): give \
                     every shard folder of the previous pass",
                    all.len()
                ),
                _ => bail!("--previous: walk-{k}/map.geojson is in several folders: {found:?}"),
            }
        })
        .collect::<Result<Vec<_>>>()?;
    let refs: Vec<&HexMapSnapshot> = maps.iter().collect();
    mine.iter()
        .map(|&k| {
            others_map(&refs, k)
                .map(Some)
                .with_context(|| format!("--previous: the maps of the walks other than {}", k + 1))
        })
        .collect()
}
