//! Walk manifests: a CSV naming many walks (`learn --walks`, `survey --walks`), one walk a
//! row, paths relative to the manifest's folder.
//!
//! | column  | content                                                          |
//! |---------|------------------------------------------------------------------|
//! | `steps` | the walk's step trace (required)                                 |
//! | `gps`   | its GPS fixes, CSV or GPX (optional; `learn`)                    |
//! | `wifi`  | its WiFi log (optional for `learn`, required for `survey`)       |
//! | `start` | `X,Y[,HEADING[,LEVEL]]`, quoted (optional; empty: unknown)       |
//! | `name`  | the walk's name (optional; `track --walks` names its folder so)  |

use super::csv_table::CsvTable;
use crate::error::{Error, Result};
use crate::filter::StartPose;
use std::path::{Path, PathBuf};

/// One walk of a manifest: its files (joined to the manifest's folder) and, when given,
/// its start.
#[derive(Debug, Clone, PartialEq)]
pub struct ManifestWalk {
    /// The step trace.
    pub steps: PathBuf,
    /// GPS fixes (CSV or GPX), when the row names one.
    pub gps: Option<PathBuf>,
    /// The WiFi log, when the row names one.
    pub wifi: Option<PathBuf>,
    /// The walk's start, when the row gives one.
    pub start: Option<StartPose>,
    /// The walk's name, when the row gives one.
    pub name: Option<String>,
}

/// Reads a walk manifest; with `wifi_required` (a survey) every row must name a WiFi log.
/// Errors name the file and line. The files it names are not opened here.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be opened, else [`Error::Parse`] naming the line: no `steps`
/// column (nor `wifi` with `wifi_required`), a row without a step trace (or WiFi log), a
/// `start` that is not `X,Y[,HEADING[,LEVEL]]` of finite numbers and an integer level, or no
/// rows.
pub fn read_walk_manifest(path: &Path, wifi_required: bool) -> Result<Vec<ManifestWalk>> {
    let base = path.parent().unwrap_or(Path::new("."));
    let mut table = CsvTable::open(path)?;
    let steps = table.column("steps")?;
    let wifi = match wifi_required {
        true => Some(table.column("wifi")?),
        false => table.optional_column("wifi"),
    };
    let (gps, start) = (table.optional_column("gps"), table.optional_column("start"));
    let name = table.optional_column("name");
    let mut walks = Vec::new();
    table.for_each_row(|row| {
        let file = |c: Option<usize>| {
            c.map(|c| row.text(c))
                .filter(|t| !t.is_empty())
                .map(|t| base.join(t))
        };
        let (steps, wifi) = (file(Some(steps)), file(wifi));
        let steps = match (steps, &wifi, wifi_required) {
            (Some(s), Some(_), true) | (Some(s), _, false) => s,
            (_, _, true) => return Err(row.error("expected a step trace and a WiFi log")),
            (None, _, false) => {
                return Err(row.error("expected a step trace in column `steps`"));
            }
        };
        let start = start
            .map(|c| row.text(c))
            .filter(|t| !t.is_empty())
            .map(|text| {
                text.parse::<StartPose>()
                    .map_err(|e| row.error(format!("start: {e}")))
            })
            .transpose()?;
        walks.push(ManifestWalk {
            steps,
            gps: file(gps),
            wifi,
            start,
            name: name
                .map(|c| row.text(c).trim().to_owned())
                .filter(|t| !t.is_empty()),
        });
        Ok(())
    })?;
    if walks.is_empty() {
        return Err(Error::parse(path, 0, "the walk manifest lists no walk"));
    }
    Ok(walks)
}

/// Writes a walk manifest that [`read_walk_manifest`] reads back: the paths as given
/// (relative to the manifest's folder, `/` between parts), a column only where some walk
/// has it, each start as `X,Y[,HEADING[,LEVEL]]` (metres to the millimetre).
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_walk_manifest(path: &Path, walks: &[ManifestWalk]) -> Result<()> {
    let has_gps = walks.iter().any(|w| w.gps.is_some());
    let has_wifi = walks.iter().any(|w| w.wifi.is_some());
    let has_start = walks.iter().any(|w| w.start.is_some());
    let has_name = walks.iter().any(|w| w.name.is_some());
    let text = |p: &Option<PathBuf>| {
        p.as_ref()
            .map(|p| p.to_string_lossy().replace('\\', "/"))
            .unwrap_or_default()
    };
    let mut out = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["steps"];
    header.extend(has_gps.then_some("gps"));
    header.extend(has_wifi.then_some("wifi"));
    header.extend(has_start.then_some("start"));
    header.extend(has_name.then_some("name"));
    let wrote = |e: csv::Error| Error::io(path, std::io::Error::other(e));
    out.write_record(&header).map_err(wrote)?;
    for w in walks {
        let mut row = vec![text(&Some(w.steps.clone()))];
        if has_gps {
            row.push(text(&w.gps));
        }
        if has_wifi {
            row.push(text(&w.wifi));
        }
        if has_start {
            row.push(w.start.map(start_text).unwrap_or_default());
        }
        if has_name {
            row.push(w.name.clone().unwrap_or_default());
        }
        out.write_record(&row).map_err(wrote)?;
    }
    let bytes = out
        .into_inner()
        .map_err(|e| Error::io(path, std::io::Error::other(e.to_string())))?;
    crate::io::write_atomically(path, &bytes)
}

/// `X,Y[,HEADING[,LEVEL]]`, as `--start` and the manifest's `start` column take it.
fn start_text(s: StartPose) -> String {
    let mut text = format!("{:.3},{:.3}", s.x, s.y);
    match (s.heading, s.level) {
        (Some(h), Some(l)) => text.push_str(&format!(",{h},{l}")),
        (Some(h), None) => text.push_str(&format!(",{h}")),
        (None, Some(l)) => text.push_str(&format!(",,{l}")),
        (None, None) => {}
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_written_manifest_reads_back() {
        let dir = std::env::temp_dir().join(format!("footslam-manifest-w-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let start = |x, heading, level| StartPose {
            x,
            y: -2.5,
            heading,
            level,
        };
        let walks = vec![
            ManifestWalk {
                steps: "a, odd/steps.csv".into(),
                gps: None,
                wifi: Some("a, odd/wifi.csv".into()),
                start: Some(start(1.25, None, None)),
                name: Some("first, odd".into()),
            },
            ManifestWalk {
                steps: "b/steps.csv".into(),
                gps: None,
                wifi: None,
                start: Some(start(3.0, Some(0.5), Some(-1))),
                name: None,
            },
            ManifestWalk {
                steps: "c/steps.csv".into(),
                gps: None,
                wifi: None,
                start: Some(start(4.0, None, Some(2))),
                name: None,
            },
        ];
        let path = dir.join("walks.csv");
        write_walk_manifest(&path, &walks).expect("write");
        let back = read_walk_manifest(&path, false).expect("read back");
        let _ = std::fs::remove_dir_all(&dir);
        assert_eq!(back.len(), 3);
        for (w, b) in walks.iter().zip(&back) {
            assert_eq!(b.steps, dir.join(&w.steps));
            assert_eq!(b.wifi, w.wifi.as_ref().map(|f| dir.join(f)));
            assert_eq!(b.gps, None);
            assert_eq!(b.start, w.start);
            assert_eq!(b.name, w.name);
        }
    }

    fn read(text: &str, wifi_required: bool) -> Result<Vec<ManifestWalk>> {
        let dir = std::env::temp_dir().join(format!("footslam-manifest-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("dir");
        let path = dir.join(format!("walks-{wifi_required}-{}.csv", text.len()));
        std::fs::write(&path, text).expect("write");
        let out = read_walk_manifest(&path, wifi_required);
        let _ = std::fs::remove_file(&path);
        out
    }

    #[test]
    fn paths_are_relative_to_the_manifest_and_starts_parse() {
        let walks = read(
            "steps,gps,start\na/steps.csv,,\"1,2,,3\"\nb.csv,b.gpx,\n",
            false,
        )
        .expect("manifest");
        assert_eq!(walks.len(), 2);
        assert!(walks[0].steps.ends_with("a/steps.csv"));
        assert_eq!(walks[0].gps, None);
        assert_eq!(walks[0].start.and_then(|s| s.level), Some(3));
        assert!(walks[1].gps.as_ref().is_some_and(|g| g.ends_with("b.gpx")));
        assert_eq!(walks[1].start, None);
    }

    #[test]
    fn errors_name_the_line_and_problem() {
        let err = read("steps,wifi\na.csv,\n", true).expect_err("no wifi");
        assert!(
            err.to_string().contains(":2") && err.to_string().contains("WiFi log"),
            "{err}"
        );
        let err = read("steps\n\n", false).expect_err("no walk");
        assert!(err.to_string().contains("lists no walk"), "{err}");
        let err = read("steps,start\na.csv,\"1\"\n", false).expect_err("bad start");
        assert!(err.to_string().contains("start: expected X,Y"), "{err}");
        assert!(read("wifi\nw.csv\n", false).is_err());
    }
}
