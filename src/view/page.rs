//! The page written: `index.html`, its data as a script (`data.js`: a page opened from disk
//! may not fetch files), the viewer's script and style, and Leaflet 1.9.4 with its licence
//! (BSD-2-Clause), all embedded in the binary and written beside the page, so the folder
//! opens in any browser with no server and no network.

use super::layer::ViewRun;
use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::RunFolder;
use serde::Serialize;
use serde_json::json;
use std::path::Path;

/// The page's files that never change, by their path in the output folder.
const ASSETS: [(&str, &[u8]); 8] = [
    ("viewer.js", include_bytes!("../../assets/viewer/viewer.js")),
    (
        "viewer.css",
        include_bytes!("../../assets/viewer/viewer.css"),
    ),
    (
        "leaflet/leaflet.js",
        include_bytes!("../../assets/viewer/leaflet/leaflet.js"),
    ),
    (
        "leaflet/leaflet.css",
        include_bytes!("../../assets/viewer/leaflet/leaflet.css"),
    ),
    (
        "leaflet/LICENSE",
        include_bytes!("../../assets/viewer/leaflet/LICENSE"),
    ),
    (
        "leaflet/README.md",
        include_bytes!("../../assets/viewer/leaflet/README.md"),
    ),
    (
        "leaflet/images/layers.png",
        include_bytes!("../../assets/viewer/leaflet/images/layers.png"),
    ),
    (
        "leaflet/images/layers-2x.png",
        include_bytes!("../../assets/viewer/leaflet/images/layers-2x.png"),
    ),
];

/// The page, `{{TITLE}}` standing for its title.
const INDEX_HTML: &str = include_str!("../../assets/viewer/index.html");

/// What the page shows under its layers.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Basemap {
    /// Web map tiles: a URL template with `{z}`, `{x}`, `{y}` (and optionally `{s}`).
    Tiles {
        /// The template, e.g. `https://tile.openstreetmap.org/{z}/{x}/{y}.png`.
        url: String,
        /// The attribution the tiles' licence asks for.
        attribution: String,
    },
    /// An image (a floor plan) stretched over a rectangle, copied beside the page.
    Image {
        /// Its file name beside the page (`basemap.png`, `basemap.jpg`, …).
        file: String,
        /// South-west and north-east corners, `[lat, lon]` degrees.
        bounds: [[f64; 2]; 2],
        /// The image's bytes.
        #[serde(skip)]
        bytes: Vec<u8>,
    },
}

impl Basemap {
    /// Tiles from `url`, which must hold `{z}`, `{x}` and `{y}`.
    ///
    /// # Errors
    ///
    /// [`Error::InvalidData`] when `url` lacks one of `{z}`, `{x}`, `{y}`.
    pub fn tiles(url: &str, attribution: &str) -> Result<Self> {
        if !["{z}", "{x}", "{y}"].iter().all(|p| url.contains(p)) {
            return Err(Error::invalid(
                format!("basemap URL `{url}`"),
                "a tile URL template holds {z}, {x} and {y}, e.g. \
                 https://tile.openstreetmap.org/{z}/{x}/{y}.png",
            ));
        }
        Ok(Self::Tiles {
            url: url.to_owned(),
            attribution: attribution.to_owned(),
        })
    }

    /// The image file `path` (PNG, JPEG, GIF, WebP or SVG) over `extent` (`X0,Y0,X1,Y1`:
    /// west, south, east, north in local metres of `frame`).
    ///
    /// # Errors
    ///
    /// [`Error::InvalidData`] when `path` has another extension or `extent` is not west < east and
    /// south < north; [`Error::Io`] when `path` cannot be read.
    pub fn image(path: &Path, extent: [f64; 4], frame: &LocalFrame) -> Result<Self> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        if !["png", "jpg", "jpeg", "gif", "webp", "svg"].contains(&extension.as_str()) {
            return Err(Error::invalid(
                path.display().to_string(),
                "a basemap image is a .png, .jpg, .gif, .webp or .svg file",
            ));
        }
        let [x0, y0, x1, y1] = extent;
        if !(x0 < x1 && y0 < y1) {
            return Err(Error::invalid(
                format!("basemap extent {x0},{y0},{x1},{y1}"),
                "X0,Y0,X1,Y1 must have X0 < X1 and Y0 < Y1 (west, south, east, north)",
            ));
        }
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
        let (west, south) = frame.to_lon_lat(x0, y0);
        let (east, north) = frame.to_lon_lat(x1, y1);
        Ok(Self::Image {
            file: format!("basemap.{extension}"),
            bounds: [[south, west], [north, east]],
            bytes,
        })
    }
}

/// A page: runs to show, and what lies under them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Page {
    /// The page's title.
    pub title: String,
    /// The runs, each with its layers; the first run's origin is the one the page's
    /// coordinate read-out measures from.
    pub runs: Vec<ViewRun>,
    /// A basemap, if any (none by default).
    pub basemap: Option<Basemap>,
    /// The footslam version that wrote the page.
    pub version: &'static str,
}

impl Page {
    /// A page of `runs`, titled by their names; runs of one name are told apart by number.
    #[must_use]
    pub fn new(mut runs: Vec<ViewRun>, basemap: Option<Basemap>) -> Self {
        for i in 1..runs.len() {
            let base = runs[i].name.clone();
            let mut n = 2;
            while runs[..i].iter().any(|r| r.name == runs[i].name) {
                runs[i].name = format!("{base} ({n})");
                n += 1;
            }
        }
        let names: Vec<&str> = runs.iter().map(|r| r.name.as_str()).collect();
        Self {
            title: format!("footslam view: {}", names.join(", ")),
            runs,
            basemap,
            version: env!("CARGO_PKG_VERSION"),
        }
    }

    /// Every file read for the page (the output folder must not replace them).
    #[must_use]
    pub fn inputs(&self) -> Vec<&Path> {
        self.runs
            .iter()
            .flat_map(|r| r.inputs.iter().map(|p| p.as_path()))
            .collect()
    }

    /// What the page shows, for the output folder's `summary.json`: each run's origin and
    /// layers (name, kind, file, levels, features), and the basemap.
    #[must_use]
    pub fn summary(&self) -> serde_json::Value {
        let runs: Vec<serde_json::Value> = self
            .runs
            .iter()
            .map(|r| {
                let layers: Vec<serde_json::Value> = r
                    .layers
                    .iter()
                    .map(|l| {
                        json!({"name": l.name, "kind": l.kind, "file": l.file,
                               "levels": l.levels, "features": l.features})
                    })
                    .collect();
                json!({"name": r.name, "folder": r.folder, "origin": r.origin,
                       "levels": r.levels(), "layers": layers})
            })
            .collect();
        json!({"page": "index.html", "runs": runs, "basemap": self.basemap,
               "version": self.version})
    }
}

/// Writes the page into `folder`: `index.html`, `data.js`, `viewer.js`, `viewer.css`,
/// `leaflet/` and the basemap image if there is one.
///
/// # Errors
///
/// [`Error::Io`] naming the file or folder that cannot be written; [`Error::Encode`] when the
/// page's data cannot be serialised as JSON.
pub fn write_page(folder: &RunFolder, page: &Page) -> Result<()> {
    folder.create_dir("leaflet/images")?;
    for (name, bytes) in ASSETS {
        folder.write(name, bytes)?;
    }
    if let Some(Basemap::Image { file, bytes, .. }) = &page.basemap {
        folder.write(file, bytes)?;
    }
    let data = serde_json::to_string(page).map_err(|e| Error::encode("the page's data", e))?;
    folder.write(
        "data.js",
        format!("window.FOOTSLAM_VIEW = {data};\n").as_bytes(),
    )?;
    let html = INDEX_HTML.replace("{{TITLE}}", &escape_html(&page.title));
    folder.write("index.html", html.as_bytes())
}

/// `text` with HTML's special characters escaped.
fn escape_html(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_of_one_name_are_told_apart() {
        let run = |name: &str| ViewRun::new(name.into(), name.into(), LocalFrame::default());
        let page = Page::new(vec![run("out"), run("out"), run("out"), run("x")], None);
        let names: Vec<&str> = page.runs.iter().map(|r| r.name.as_str()).collect();
        assert_eq!(names, ["out", "out (2)", "out (3)", "x"]);
        assert_eq!(escape_html("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn a_tile_url_needs_its_placeholders() {
        assert!(Basemap::tiles("https://tile.openstreetmap.org/{z}/{x}/{y}.png", "").is_ok());
        assert!(Basemap::tiles("https://example.org/map.png", "").is_err());
    }
}
