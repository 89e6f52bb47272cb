//! Walk manifests: a CSV naming many walks (`learn --walks`, `survey --walks`), one walk a
//! row, paths relative to the manifest's folder.
//!
//! | column  | content                                                          |
//! |---------|------------------------------------------------------------------|
//! | `steps` | the walk's step trace (required)                                 |
//! | `gps`   | its GPS fixes, CSV or GPX (optional; `learn`)                    |
//! | `wifi`  | its WiFi log (optional for `learn`, required for `survey`)       |
//! | `start` | `X,Y[,HEADING[,LEVEL]]`, quoted (optional; empty: unknown)       |

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
}

/// Reads a walk manifest; with `wifi_required` (a survey) every row must name a WiFi log.
/// Errors name the file and line. The files it names are not opened here.
pub fn read_walk_manifest(path: &Path, wifi_required: bool) -> Result<Vec<ManifestWalk>> {
    let base = path.parent().unwrap_or(Path::new("."));
    let mut table = CsvTable::open(path)?;
    let steps = table.column("steps")?;
    let wifi = match wifi_required {
        true => Some(table.column("wifi")?),
        false => table.optional_column("wifi"),
    };
    let (gps, start) = (table.optional_column("gps"), table.optional_column("start"));
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
        });
        Ok(())
    })?;
    if walks.is_empty() {
        return Err(Error::parse(path, 0, "the walk manifest lists no walk"));
    }
    Ok(walks)
}

#[cfg(test)]
mod tests {
    use super::*;

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
