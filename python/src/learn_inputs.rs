//! What `footslam.learn` and `footslam.learn_one` read from their arguments, as `footslam
//! learn` reads its flags and files, into the job's request
//! ([`footslam::pipeline::LearnRequest`]): the configuration and its overrides, the walks
//! (steps, GPS fixes and WiFi scans), the prior map, the origin and the outline.

use crate::inputs;
use crate::tables::{self, GPS, STEPS, Table, WIFI};
use crate::{detached, py_error};
use footslam::filter::StartPose;
use footslam::pipeline::{LearnConfig, LearnOverrides, LearnRequest, LearnWalkRequest, Named};
use pyo3::prelude::*;

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
    /// The options over the configuration.
    fn overrides(&self) -> LearnOverrides {
        LearnOverrides {
            seed: self.seed,
            particles: self.particles,
            hex_radius: self.hex_radius,
            prior_weight: self.prior_weight,
            ignore_heading: self.ignore_heading,
            cell: self.cell,
        }
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
    /// Parses the walks' tables, GPX times placed by `gps_t0`.
    fn read(self, gps_t0: Option<f64>) -> footslam::Result<Vec<LearnWalkRequest>> {
        let mut walks = Vec::with_capacity(self.steps.len());
        for (((steps, gps), wifi), start) in self
            .steps
            .iter()
            .zip(&self.gps)
            .zip(&self.wifi)
            .zip(self.starts)
        {
            let (trace, field) = steps.steps_with_field()?;
            let gps = match gps {
                Some(t) => Some((Named::new(t.gps(gps_t0)?, t.label()), t.is_gpx())),
                None => None,
            };
            let wifi = match wifi {
                Some(t) => {
                    let log = t.wifi_log()?;
                    Some((Named::new(log.scans, t.label()), log.duplicate_readings))
                }
                None => None,
            };
            walks.push(LearnWalkRequest {
                steps: Named::new(trace, steps.label()),
                field,
                gps,
                wifi,
                start,
            });
        }
        Ok(walks)
    }
}

/// The request of `learn` (`one_walk_only`: of `learn_one`) from its arguments, as `footslam
/// learn` reads its flags and files.
pub(crate) fn read_request(
    py: Python<'_>,
    args: &Args<'_, '_>,
    one_walk_only: bool,
) -> PyResult<LearnRequest> {
    let config: LearnConfig = inputs::config(args.config)?;
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
    let (gps_t0, overrides) = (args.gps_t0, args.overrides());
    detached(py, None, move || {
        let read = || -> footslam::Result<LearnRequest> {
            Ok(LearnRequest {
                walks: tables.read(gps_t0)?,
                gps_t0,
                prior_map: match &prior_doc {
                    Some(d) => Some(Named::new(d.stored_map()?, d.label())),
                    None => None,
                },
                outline: match &outline_doc {
                    Some(d) => Some(Named::new(d.world_outline()?, d.label())),
                    None => None,
                },
                origin,
                config,
                overrides,
            })
        };
        read().map_err(py_error)
    })
}
