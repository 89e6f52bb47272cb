//! What `footslam.learn` and `footslam.learn_one` read from their arguments, as `footslam
//! learn` reads its flags and files: the configuration with its overrides, the walks (steps,
//! GPS fixes and WiFi scans, each checked against the steps' time span), the prior map, the
//! frame and the outline.

use crate::checks::{check_same_grid, read_fixes, read_scans};
use crate::inputs::{self, Document};
use crate::tables::{self, GPS, STEPS, Table, WIFI};
use crate::{detached, fail, py_error};
use footslam::filter::{FootSlamConfig, StartPose};
use footslam::geometry::LocalFrame;
use footslam::io::map_geojson::StoredMap;
use footslam::map::CellConfig;
use footslam::pipeline::{
    LearnInput, LearnWalk, default_frame, fixes_far_from_origin, outline_off_walks,
};
use pyo3::prelude::*;

/// What `learn` and `learn_one` read from their arguments, as `footslam learn` reads its
/// flags and files.
pub(crate) struct Inputs {
    pub(crate) config: FootSlamConfig,
    pub(crate) walks: Vec<LearnWalk>,
    /// Each walk's steps, as messages name them.
    pub(crate) labels: Vec<String>,
    pub(crate) prior_map: Option<StoredMap>,
    pub(crate) frame: LocalFrame,
    pub(crate) outline: Option<geo::Polygon<f64>>,
    pub(crate) cells: CellConfig,
    /// Warnings of the input checks (logs partly off the walk's clock).
    pub(crate) warnings: Vec<String>,
}

/// The arguments `learn` and `learn_one` share.
pub(crate) struct Args<'a, 'py> {
    pub(crate) steps: &'a Bound<'py, PyAny>,
    pub(crate) gps: Option<&'a Bound<'py, PyAny>>,
    pub(crate) wifi: Option<&'a Bound<'py, PyAny>>,
    pub(crate) start: Option<&'a Bound<'py, PyAny>>,
    pub(crate) prior_map: Option<&'a Bound<'py, PyAny>>,
    pub(crate) outline: Option<&'a Bound<'py, PyAny>>,
    pub(crate) origin: Option<(f64, f64)>,
    pub(crate) config: Option<&'a Bound<'py, PyAny>>,
    pub(crate) seed: Option<u64>,
    pub(crate) particles: Option<usize>,
    pub(crate) hex_radius: Option<f64>,
    pub(crate) prior_weight: Option<f64>,
    pub(crate) ignore_heading: bool,
    pub(crate) cell: Option<f64>,
    pub(crate) gps_t0: Option<f64>,
}

/// The tables of the walks and their start poses, converted while the GIL is held.
struct WalkTables {
    steps: Vec<Table>,
    gps: Vec<Option<Table>>,
    wifi: Vec<Option<Table>>,
    starts: Vec<Option<StartPose>>,
}

impl Args<'_, '_> {
    /// The configuration: `config`'s (or the defaults) with the keyword overrides, checked.
    fn learn_config(&self) -> PyResult<FootSlamConfig> {
        let mut config: FootSlamConfig = inputs::config(self.config)?;
        if let Some(n) = self.particles {
            config.particles = n;
        }
        if let Some(s) = self.seed {
            config.seed = s;
        }
        if let Some(r) = self.hex_radius {
            config.hex_radius = r;
        }
        if let Some(w) = self.prior_weight {
            config.prior_weight = w;
        }
        if self.ignore_heading {
            config.heading.enabled = false;
        }
        config.validate().map_err(py_error)?;
        Ok(config)
    }

    /// The walks' tables: `steps` one walk's or a list of walks', with `gps`, `wifi` and
    /// `start` one per walk.
    fn tables(&self, one_walk_only: bool) -> PyResult<WalkTables> {
        let list = if one_walk_only {
            None
        } else {
            inputs::as_list(self.steps)?
        };
        let batch = list.is_some();
        let steps_objects = list.unwrap_or_else(|| vec![self.steps.clone()]);
        if steps_objects.is_empty() {
            return Err(crate::fail("steps: an empty list of walks"));
        }
        let n = steps_objects.len();
        let name = |what: &str, i: usize| {
            if batch {
                format!("{what}[{i}]")
            } else {
                what.to_owned()
            }
        };
        let steps = steps_objects
            .iter()
            .enumerate()
            .map(|(i, o)| tables::table(o, &STEPS, &name("steps", i)))
            .collect::<PyResult<Vec<_>>>()?;
        let optional_tables = |obj, what: &str, kind| -> PyResult<Vec<Option<Table>>> {
            inputs::per_walk(obj, n, batch, what)?
                .iter()
                .enumerate()
                .map(|(i, o)| {
                    o.as_ref()
                        .map(|o| tables::table(o, kind, &name(what, i)))
                        .transpose()
                })
                .collect()
        };
        let gps = optional_tables(self.gps, "gps", &GPS)?;
        let wifi = optional_tables(self.wifi, "wifi", &WIFI)?;
        let starts = inputs::per_walk(self.start, n, batch, "start")?
            .iter()
            .enumerate()
            .map(|(i, o)| inputs::start(o.as_ref(), &name("start", i)))
            .collect::<PyResult<Vec<_>>>()?;
        Ok(WalkTables {
            steps,
            gps,
            wifi,
            starts,
        })
    }
}

impl WalkTables {
    /// Reads the walks, each file and its time span checked as `footslam learn` checks them.
    fn read(self, gps_t0: Option<f64>) -> PyResult<(Vec<LearnWalk>, Vec<String>, Vec<String>)> {
        if gps_t0.is_some() && !self.gps.iter().flatten().any(Table::is_gpx) {
            return Err(fail(
                "gps_t0 places GPX files' UTC times on the steps' clock, and no walk has a GPX \
                 file (CSV fixes and tables are on the steps' clock already): leave gps_t0 out",
            ));
        }
        let mut warnings = Vec::new();
        let mut walks = Vec::with_capacity(self.steps.len());
        let mut labels = Vec::with_capacity(self.steps.len());
        for (((steps, gps), wifi), start) in self
            .steps
            .iter()
            .zip(&self.gps)
            .zip(&self.wifi)
            .zip(self.starts)
        {
            let (trace, field) = steps.steps_with_field().map_err(py_error)?;
            let (fixes, fixes_warning) = match gps {
                Some(t) => read_fixes(t, gps_t0, &trace)?,
                None => (Vec::new(), None),
            };
            let (scans, scans_warning) = match wifi {
                Some(t) => read_scans(t, &trace)?,
                None => (Vec::new(), None),
            };
            warnings.extend(fixes_warning.into_iter().chain(scans_warning));
            labels.push(steps.label());
            walks.push(LearnWalk {
                trace,
                fixes,
                scans,
                start,
                field,
            });
        }
        Ok((walks, labels, warnings))
    }
}

/// Reads everything `learn` needs, in the command line's order: the configuration, the
/// walks, the cells, the prior map, the frame and the outline.
pub(crate) fn read_inputs(
    py: Python<'_>,
    args: &Args<'_, '_>,
    one_walk_only: bool,
) -> PyResult<Inputs> {
    let config = args.learn_config()?;
    let tables = args.tables(one_walk_only)?;
    let prior_doc = args
        .prior_map
        .filter(|o| !o.is_none())
        .map(|o| inputs::document(o, "prior map", "prior_map"))
        .transpose()?;
    let outline_doc = args
        .outline
        .filter(|o| !o.is_none())
        .map(|o| inputs::document(o, "outline", "outline"))
        .transpose()?;
    let origin = inputs::origin(args.origin)?;
    let gps_t0 = args.gps_t0;
    let cells = CellConfig {
        granularity: args.cell.unwrap_or(CellConfig::default().granularity),
        ..CellConfig::default()
    };
    detached(py, None, move || {
        let (walks, labels, warnings) = tables.read(gps_t0)?;
        cells.validate().map_err(py_error)?;
        let prior_map = prior_doc
            .as_ref()
            .map(Document::stored_map)
            .transpose()
            .map_err(py_error)?;
        let frame = origin.unwrap_or_else(|| default_frame(prior_map.as_ref(), &walks));
        let outline = outline_doc
            .as_ref()
            .map(|d| d.outline(&frame))
            .transpose()
            .map_err(py_error)?;
        for (walk, label) in walks.iter().zip(&labels) {
            if let Some(problem) = fixes_far_from_origin(&walk.fixes, &frame) {
                return Err(fail(format!("{label}: its GPS fixes: {problem}")));
            }
        }
        if let (Some(outline), Some(doc)) = (&outline, &outline_doc) {
            let default_start = (config.start.x, config.start.y);
            if let Some(problem) = outline_off_walks(outline, &walks, default_start) {
                return Err(fail(format!("{}: {problem}", doc.label())));
            }
        }
        if let (Some(stored), Some(doc)) = (&prior_map, &prior_doc) {
            let radius = stored.map.radius;
            check_same_grid(
                &doc.label(),
                radius,
                &stored.frame,
                config.hex_radius,
                &frame,
            )?;
        }
        Ok(Inputs {
            config,
            walks,
            labels,
            prior_map,
            frame,
            outline,
            cells,
            warnings,
        })
    })
}

impl Inputs {
    pub(crate) fn input(&self) -> LearnInput<'_> {
        LearnInput {
            walks: &self.walks,
            frame: self.frame,
            outline: self.outline.as_ref(),
            prior_map: self.prior_map.as_ref(),
            cells: self.cells,
        }
    }
}
