//! Pieces shared by the subcommands: origins, output folders, progress bars, config files.

use anyhow::{Context, Result, bail};
use footslam::geometry::LocalFrame;
use std::path::{Path, PathBuf};

/// Parses `LAT,LON` (degrees).
pub fn parse_origin(s: &str) -> Result<LocalFrame, String> {
    let (lat, lon) = s
        .split_once(',')
        .ok_or_else(|| format!("expected LAT,LON in degrees, got `{s}`"))?;
    let lat: f64 = lat
        .trim()
        .parse()
        .map_err(|_| format!("latitude `{lat}` is not a number"))?;
    let lon: f64 = lon
        .trim()
        .parse()
        .map_err(|_| format!("longitude `{lon}` is not a number"))?;
    LocalFrame::new(lat, lon).ok_or_else(|| {
        format!(
            "`{s}` is not the latitude,longitude of a building (latitude within ±{} °, \
             longitude within ±180 °)",
            footslam::geometry::local_frame::MAX_ORIGIN_LATITUDE
        )
    })
}

/// Parses `--picture-extent`: `X0,Y0,X1,Y1` local metres, `X0 < X1` and `Y0 < Y1`.
pub fn parse_extent(s: &str) -> Result<[f64; 4], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("expected X0,Y0,X1,Y1 in metres, got `{s}`"))?;
    let [x0, y0, x1, y1] = v[..] else {
        return Err(format!("expected four numbers X0,Y0,X1,Y1, got `{s}`"));
    };
    let config = footslam::render::plan_png::PlanPictureConfig {
        extent: Some([x0, y0, x1, y1]),
        ..Default::default()
    };
    config.validate().map_err(|e| e.to_string())?;
    Ok([x0, y0, x1, y1])
}

/// Starts a run into `out` ([`footslam::io::RunFolder::create`]), with a notice when it will replace an
/// earlier run there (never files of two runs in one folder).
pub fn create_run_folder(out: &Path) -> footslam::Result<footslam::io::RunFolder> {
    let folder = footslam::io::RunFolder::create(out)?;
    if folder.replacing() > 0 && !super::verbosity::quiet() {
        #[allow(clippy::print_stderr)]
        {
            eprintln!(
                "note: {} holds an earlier run: its {} files and folders are replaced whole \
                 when this run ends",
                out.display(),
                folder.replacing()
            );
        }
    }
    Ok(folder)
}

/// `--out` or a fresh folder `outputs/<command>-<UTC time>`.
pub fn output_dir(out: Option<PathBuf>, command: &str) -> PathBuf {
    out.unwrap_or_else(|| {
        let secs = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        let (days, rem) = (secs / 86_400, secs % 86_400);
        let (y, m, d) = civil_from_days(days.cast_signed());
        PathBuf::from("outputs").join(format!(
            "{command}-{y:04}{m:02}{d:02}-{:02}{:02}{:02}",
            rem / 3600,
            rem % 3600 / 60,
            rem % 60
        ))
    })
}

/// Gregorian date of a day count since 1970-01-01 (H. Hinnant's algorithm).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

/// Reads a component config from TOML (or JSON, by extension) into `T`.
pub fn read_config<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T> {
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    let text = text.trim_start_matches('\u{feff}');
    let is_json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    if is_json {
        serde_json::from_str(text)
            .with_context(|| format!("{}: invalid configuration", path.display()))
    } else {
        toml::from_str(text).with_context(|| format!("{}: invalid configuration", path.display()))
    }
}

/// A bundled dataset file: `relative` under the working directory when it is there (a
/// checkout), else under the source tree the binary was built from.
pub fn bundled(relative: &str) -> PathBuf {
    let local = PathBuf::from(relative);
    if local.is_file() {
        local
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
    }
}

/// Fails with a clear message when `path` does not exist.
pub fn require_file(path: &Path, what: &str) -> Result<()> {
    if !path.is_file() {
        bail!(
            "{what} `{}` does not exist or is not a file",
            path.display()
        );
    }
    Ok(())
}

/// Where walk `i` of a run writes: its own `walk-<i+1>/` folder (created) when the run has
/// several, else the run folder itself; the prefix for its file names.
pub fn walk_prefix(folder: &footslam::io::RunFolder, i: usize, several: bool) -> Result<String> {
    if !several {
        return Ok(String::new());
    }
    let name = format!("walk-{}", i + 1);
    folder.create_dir(&name)?;
    Ok(format!("{name}/"))
}

/// `truth.png`: a simulated walk's true path over its floor plan.
pub fn write_truth_png(
    path: &Path,
    plan: &footslam::map::FloorPlan,
    truth: &[(f64, f64)],
) -> Result<()> {
    use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};
    let empty = footslam::map::HexMapSnapshot {
        radius: 0.5,
        alpha: 0.8,
        cells: Vec::new(),
        levels: Vec::new(),
    };
    let picture = MapPicture {
        map: &empty,
        path: truth,
        path_breaks: &[],
        truth: None,
        plan: Some(plan),
        outline: None,
        path_label: "true path",
        truth_label: "",
        north_up: true,
    };
    write_map_png(path, &picture, &PictureConfig::default())?;
    Ok(())
}

/// The most worker threads `--threads` may ask for, per core of the machine: more only adds
/// scheduling overhead (2,000 threads on 2 cores took 435 s instead of 0.1 s).
pub const THREADS_PER_CORE: usize = 4;

/// The worker pool of `--threads` (`None` or 0: one thread per core), capped at
/// [`THREADS_PER_CORE`] × the machine's cores with a warning.
pub fn worker_pool(threads: Option<usize>) -> Result<rayon::ThreadPool> {
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let cap = THREADS_PER_CORE * cores;
    let wanted = threads.unwrap_or(0);
    let n = if wanted > cap {
        warn_capped(wanted, cap, cores);
        cap
    } else {
        wanted
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(n)
        .build()
        .context("cannot start worker threads")
}

/// The warning of [`worker_pool`].
fn warn_capped(wanted: usize, cap: usize, cores: usize) {
    warn(&format!(
        "--threads {wanted} capped at {cap} ({THREADS_PER_CORE} per core on {cores} cores); \
         results do not depend on the thread count"
    ));
}

/// A warning for the user on stderr: the run goes on (the CLI layer may print).
#[allow(clippy::print_stderr)]
pub fn warn(message: &str) {
    eprintln!("warning: {message}");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn civil_dates() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(20_000), (2024, 10, 4));
    }

    #[test]
    fn origins_parse_or_explain() {
        assert!(parse_origin("48.1,11.5").is_ok());
        assert!(parse_origin("48.1").is_err());
        assert!(parse_origin("x,1").is_err());
        assert!(parse_origin("95,1").is_err());
    }
}
