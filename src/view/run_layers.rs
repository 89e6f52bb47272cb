//! A run folder read into the page's layers: the files `learn`, `track`, `survey`,
//! `simulate`, `plan`, `fingerprint` and `import` write ([`VIEWABLE_FILES`]), in the folder,
//! in its `walk-N/` folders (a batch's walks) and in other sub-folders holding such files (an
//! importer's traces), each placed on the globe at the run's origin.
//!
//! The origin of a folder's local metres is the `origin` its `summary.json` records, else
//! the `origin` member of its GeoJSON files, else that of the folder above (a batch's walk),
//! else (0°, 0°) — where every run puts it when given none.

use super::layer::{Layer, LayerData, LayerKind, PathPoint, ViewRun};
use super::path_csv::{LevelsByTime, read_gps_path, read_path_csv, read_waypoints_path, time_key};
use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::geojson_file::{read_feature_collection, read_json_text, read_origin};
use geojson::{FeatureCollection, GeometryValue};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The files of a run folder the page draws, bottom to top: file name, kind, layer name.
pub const VIEWABLE_FILES: [(&str, LayerKind, &str); 14] = [
    ("floor.geojson", LayerKind::Plan, "floor plan"),
    ("outline.geojson", LayerKind::Outline, "outline"),
    ("plan.geojson", LayerKind::Plan, "learned plan"),
    ("merged_plan.geojson", LayerKind::Plan, "merged plan"),
    ("radiomap.geojson", LayerKind::RadioMap, "radio map"),
    ("fieldmap.geojson", LayerKind::FieldMap, "magnetic field"),
    ("map.geojson", LayerKind::HexMap, "learned map"),
    ("merged.geojson", LayerKind::HexMap, "merged map"),
    (
        "dead_reckoning.csv",
        LayerKind::DeadReckoning,
        "dead reckoning",
    ),
    ("truth.csv", LayerKind::Truth, "truth"),
    ("waypoints.csv", LayerKind::Waypoints, "waypoints"),
    ("gps.csv", LayerKind::GpsFixes, "GPS fixes"),
    (
        "track_filtered.csv",
        LayerKind::FilteredTrack,
        "filtered track",
    ),
    ("track.csv", LayerKind::Track, "track"),
];

/// A track as GeoJSON (`track.geojson`): read for its steps' levels, or as the track when
/// the folder has no `track.csv`.
const TRACK_GEOJSON: &str = "track.geojson";

/// Reads the run folder `folder` and its parts' folders (`walk-N/`, an importer's traces)
/// into layers.
///
/// # Errors
///
/// - [`Error::Io`] when `folder` does not exist, is not a folder, or a file or sub-folder in it
///   cannot be read.
/// - [`Error::NotEnough`] when it holds nothing to view (the message lists what was looked for).
/// - [`Error::Parse`] naming the file and line of a malformed file (a summary, GeoJSON or CSV file,
///   or an unreadable origin).
pub fn read_run(folder: &Path) -> Result<ViewRun> {
    check_folder(folder)?;
    let origin = folder_origin(folder, None)?;
    let name = folder
        .canonicalize()
        .ok()
        .and_then(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
        .unwrap_or_else(|| folder.display().to_string());
    let mut run = ViewRun::new(name, folder.to_path_buf(), origin);
    read_folder(&mut run, folder, "", "", &origin)?;
    if !run.layers.iter().any(|l| l.kind == LayerKind::Plan)
        && let Some(plan) = summary_plan(folder)?
    {
        let layer = geojson_layer(&plan, LayerKind::Plan)?;
        run.layers.insert(
            0,
            Layer {
                name: "floor plan".into(),
                file: plan.display().to_string(),
                ..layer
            },
        );
        run.inputs.push(plan);
    }
    for (label, name, part) in part_folders(folder)? {
        let part_origin = folder_origin(&part, Some(origin))?;
        let (file_prefix, name_prefix) = (format!("{name}/"), format!("{label} · "));
        read_folder(&mut run, &part, &file_prefix, &name_prefix, &part_origin)?;
    }
    let summary = folder.join("summary.json");
    if summary.is_file() {
        run.inputs.push(summary);
    }
    if run.layers.is_empty() {
        let names: Vec<&str> = VIEWABLE_FILES.iter().map(|(f, _, _)| *f).collect();
        return Err(Error::not_enough(
            format!(
                "{}: nothing to view: none of {}, {TRACK_GEOJSON} is there, nor a \
                 sub-folder (walk-N/) holding one",
                folder.display(),
                names.join(", ")
            ),
            "give a folder that footslam learn, track, survey, simulate, plan or import wrote",
        ));
    }
    Ok(run)
}

/// Fails unless `folder` is an existing folder.
fn check_folder(folder: &Path) -> Result<()> {
    if folder.is_dir() {
        return Ok(());
    }
    let (kind, message) = if folder.exists() {
        (
            std::io::ErrorKind::InvalidInput,
            "not a folder: give the run's folder, not one of its files",
        )
    } else {
        (
            std::io::ErrorKind::NotFound,
            "no such run folder: give a folder a footslam command wrote",
        )
    };
    Err(Error::io(folder, std::io::Error::new(kind, message)))
}

/// The folders of a run's parts, as (label, folder name, path): a batch's `walk-N/` by N
/// (labelled `walk N`), then any other sub-folder holding a file the page draws, by name (an
/// importer's folder per trace).
fn part_folders(folder: &Path) -> Result<Vec<(String, String, PathBuf)>> {
    let entries = std::fs::read_dir(folder).map_err(|e| Error::io(folder, e))?;
    let mut walks = Vec::new();
    let mut others = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| Error::io(folder, e))?;
        let path = entry.path();
        let Some(name) = entry.file_name().to_str().map(str::to_owned) else {
            continue;
        };
        if !path.is_dir() || name.starts_with('.') {
            continue;
        }
        match name
            .strip_prefix("walk-")
            .and_then(|n| n.parse::<usize>().ok())
        {
            Some(n) => walks.push((n, name, path)),
            None if holds_viewable(&path) => others.push((name.clone(), name, path)),
            None => {}
        }
    }
    walks.sort();
    others.sort();
    Ok(walks
        .into_iter()
        .map(|(n, name, path)| (format!("walk {n}"), name, path))
        .chain(others)
        .collect())
}

/// Whether `folder` holds a file the page draws.
fn holds_viewable(folder: &Path) -> bool {
    VIEWABLE_FILES
        .iter()
        .map(|(file, _, _)| *file)
        .chain([TRACK_GEOJSON])
        .any(|file| folder.join(file).is_file())
}

/// The floor plan a run was given, as its `summary.json` records it (`plan_file`: `track`,
/// `fingerprint`), when that file is still there (as given, or relative to the run folder).
fn summary_plan(folder: &Path) -> Result<Option<PathBuf>> {
    let path = folder.join("summary.json");
    if !path.is_file() {
        return Ok(None);
    }
    let Some(Value::String(plan)) = read_summary(&path)?.get("plan_file").cloned() else {
        return Ok(None);
    };
    let plan = PathBuf::from(plan);
    Ok([plan.clone(), folder.join(&plan)]
        .into_iter()
        .find(|p| p.is_file()))
}

/// A run's `summary.json`, read as JSON.
fn read_summary(path: &Path) -> Result<Value> {
    let text = read_json_text(path)?;
    serde_json::from_str(&text).map_err(|e| Error::parse(path, e.line(), format!("not JSON: {e}")))
}

/// The origin of `folder`'s local metres (see the module's documentation).
fn folder_origin(folder: &Path, above: Option<LocalFrame>) -> Result<LocalFrame> {
    let summary = folder.join("summary.json");
    if summary.is_file()
        && let Some(member) = read_summary(&summary)?.get("origin")
    {
        return read_origin(member).map_err(|m| Error::parse(&summary, 0, m));
    }
    for (file, _, _) in VIEWABLE_FILES
        .iter()
        .chain([&(TRACK_GEOJSON, LayerKind::Track, "")])
    {
        let path = folder.join(file);
        if file.ends_with(".geojson") && path.is_file() {
            let collection = read_feature_collection(&path)?;
            if let Some(member) = collection
                .foreign_members
                .as_ref()
                .and_then(|m| m.get("origin"))
            {
                return read_origin(member).map_err(|m| Error::parse(&path, 0, m));
            }
        }
    }
    Ok(above.unwrap_or_default())
}

/// Adds the layers of the files in `folder` (`file_prefix`: its path in the run folder,
/// `name_prefix`: before each layer's name).
fn read_folder(
    run: &mut ViewRun,
    folder: &Path,
    file_prefix: &str,
    name_prefix: &str,
    frame: &LocalFrame,
) -> Result<()> {
    let track_geojson = folder.join(TRACK_GEOJSON);
    let track_steps = if track_geojson.is_file() {
        run.inputs.push(track_geojson.clone());
        Some(step_points(&track_geojson)?)
    } else {
        None
    };
    let levels: Option<LevelsByTime> = track_steps.as_ref().map(|points| {
        points
            .iter()
            .filter_map(|p| Some((time_key(p.t), p.level?)))
            .collect()
    });
    for (file, kind, name) in VIEWABLE_FILES {
        let path = folder.join(file);
        let layer = if path.is_file() {
            read_layer(&path, kind, frame, levels.as_ref())?
        } else if kind == LayerKind::Track
            && let Some(points) = &track_steps
        {
            path_layer(LayerKind::Track, points.clone())
        } else {
            continue;
        };
        let file = if path.is_file() { file } else { TRACK_GEOJSON };
        run.inputs.push(folder.join(file));
        run.layers.push(Layer {
            name: format!("{name_prefix}{name}"),
            file: format!("{file_prefix}{file}"),
            ..layer
        });
    }
    Ok(())
}

/// The layer of the file `path` of kind `kind` (name and file left for the caller).
fn read_layer(
    path: &Path,
    kind: LayerKind,
    frame: &LocalFrame,
    levels: Option<&LevelsByTime>,
) -> Result<Layer> {
    match kind {
        LayerKind::Waypoints => Ok(path_layer(kind, read_waypoints_path(path, frame)?)),
        LayerKind::GpsFixes => Ok(path_layer(kind, read_gps_path(path)?)),
        k if k.is_path() => Ok(path_layer(kind, read_path_csv(path, frame, levels)?)),
        _ => geojson_layer(path, kind),
    }
}

/// A path layer of `points`.
fn path_layer(kind: LayerKind, points: Vec<PathPoint>) -> Layer {
    let mut levels: Vec<i32> = points.iter().filter_map(|p| p.level).collect();
    levels.sort_unstable();
    levels.dedup();
    Layer {
        name: String::new(),
        kind,
        file: String::new(),
        levels,
        features: points.len(),
        data: LayerData::Path(points),
    }
}

/// A GeoJSON layer: the collection carried through (a radio map's histograms dropped).
fn geojson_layer(path: &Path, kind: LayerKind) -> Result<Layer> {
    let collection = read_feature_collection(path)?;
    let mut levels: Vec<i32> = collection
        .features
        .iter()
        .filter_map(|f| f.property("level")?.as_i64())
        .filter_map(|l| i32::try_from(l).ok())
        .collect();
    levels.sort_unstable();
    levels.dedup();
    let features = collection.features.len();
    let mut value = serde_json::to_value(&collection)
        .map_err(|e| Error::encode(format!("the page's copy of {}", path.display()), e))?;
    if kind == LayerKind::RadioMap {
        drop_histograms(&mut value);
    }
    Ok(Layer {
        name: String::new(),
        kind,
        file: String::new(),
        levels,
        features,
        data: LayerData::Geojson(value),
    })
}

/// Removes the `hist` of every access point of every cell of a radio map: the page shows
/// the means, and the histograms are most of the file.
fn drop_histograms(collection: &mut Value) {
    let Some(features) = collection.get_mut("features").and_then(Value::as_array_mut) else {
        return;
    };
    for feature in features {
        let aps = feature
            .get_mut("properties")
            .and_then(|p| p.get_mut("aps"))
            .and_then(Value::as_object_mut);
        for ap in aps.into_iter().flat_map(|a| a.values_mut()) {
            if let Some(ap) = ap.as_object_mut() {
                ap.remove("hist");
            }
        }
    }
}

/// The step points of a `track.geojson` (`Point` features with `t` and `level`), in time
/// order.
fn step_points(path: &Path) -> Result<Vec<PathPoint>> {
    let collection: FeatureCollection = read_feature_collection(path)?;
    let mut points: Vec<PathPoint> = collection
        .features
        .iter()
        .filter_map(|f| {
            let GeometryValue::Point { coordinates } = &f.geometry.as_ref()?.value else {
                return None;
            };
            let t = f.property("t")?.as_f64()?;
            Some(PathPoint {
                t,
                lon: *coordinates.as_slice().first()?,
                lat: *coordinates.as_slice().get(1)?,
                level: f
                    .property("level")
                    .and_then(Value::as_i64)
                    .and_then(|l| i32::try_from(l).ok()),
                spread: None,
                certain: None,
            })
        })
        .collect();
    points.sort_by(|a, b| a.t.total_cmp(&b.t));
    Ok(points)
}

/// A `--truth` file (`t,x,y[,level]`, local metres of `frame`) as a layer.
///
/// # Errors
///
/// As [`read_path_csv`]: the file cannot be read, or a line is malformed or out of time order.
pub fn read_truth_layer(path: &Path, frame: &LocalFrame) -> Result<Layer> {
    Ok(given_layer(
        path,
        path_layer(LayerKind::Truth, read_path_csv(path, frame, None)?),
        "truth",
    ))
}

/// A `--waypoints` file (`t,x,y[,level]`, local metres of `frame`) as a layer.
///
/// # Errors
///
/// As [`read_waypoints_path`]: the file cannot be read, or a line is malformed or out of time
/// order.
pub fn read_waypoints_layer(path: &Path, frame: &LocalFrame) -> Result<Layer> {
    Ok(given_layer(
        path,
        path_layer(LayerKind::Waypoints, read_waypoints_path(path, frame)?),
        "waypoints",
    ))
}

/// `layer` named after the file given for it.
fn given_layer(path: &Path, layer: Layer, what: &str) -> Layer {
    let file = path.display().to_string();
    // The file's name and its folder's: importers write one `waypoints.csv` per walk folder.
    let short: Vec<String> = path
        .components()
        .rev()
        .take(2)
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .filter(|c| c != "." && c != "/")
        .collect();
    let short = short.into_iter().rev().collect::<Vec<_>>().join("/");
    Layer {
        name: format!("{what} ({short})"),
        file,
        ..layer
    }
}
