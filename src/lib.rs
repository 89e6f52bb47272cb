//! # footslam
//!
//! An open toolkit that turns pedestrians' walks into building maps.
//!
//! * **FootSLAM** (Robertson et al. 2009): a Rao-Blackwellised particle filter that reads
//!   step traces and learns, per particle, a hexagon transition map — Dirichlet-multinomial
//!   counts of crossings of each hexagon edge. See [`filter::FootSlam`] and
//!   [`map::HexTransitionMap`]. Anchored to the world ([`filter::Anchors`]): GPS fixes
//!   ([`model::GpsLikelihood`]), a rough building outline and maps of earlier walks as
//!   per-edge Dirichlet priors ([`map::EdgePrior`]), maps merged across walks
//!   ([`map::merge_maps`], [`map::register_maps`]).
//! * **Tracking on known floor plans** (Woodman & Harle 2008): a particle filter on 2.5D
//!   floor polygons — walls kill particles, stairs are weighed by height change, unknown
//!   start, KLD-sampling, mean-shift clusters, recovery when every particle dies. See
//!   [`filter::Tracker`] and [`map::FloorTopology`].
//! * **Raw IMU recordings to step events** ([`inertial`]): a foot-mounted zero-velocity-aided
//!   INS ([`inertial::detect_strides`]) and a phone's step-and-heading system
//!   ([`inertial::detect_steps`]), over [`sensor::ImuRecording`].
//! * **Pipelines** ([`pipeline`]): the toolkit's work as functions over typed inputs —
//!   [`pipeline::steps()`], [`pipeline::learn()`] (and [`pipeline::learn_one`] /
//!   [`pipeline::combine`] for a batch spread over machines), [`pipeline::merge()`],
//!   [`pipeline::plan()`], [`pipeline::track()`], [`pipeline::survey()`] — each a list of named
//!   stages, reporting through [`pipeline::Progress`]. The command line and the Python
//!   package are faces over them.
//! * One module per file format, reading and writing it: step traces, IMU recordings, WiFi
//!   and GPS logs, floor plans and learned maps as RFC 7946 GeoJSON, and importers of public
//!   datasets (the Indoor Location Competition 2.0, IPIN logfiles) ([`io`]); pictures of
//!   maps, plans, paths and particle clouds ([`render`]); interactive map pages of run
//!   folders, opened from disk in a browser ([`view`]); a simulator of office and
//!   multi-floor walks with a foot-mounted-grade error model ([`sim`]) and evaluation
//!   ([`eval`]).
//!
//! ```
//! use footslam::filter::{FootSlam, FootSlamConfig};
//! use footslam::sim::{SimConfig, simulate};
//!
//! // A simulated one-lap office walk with foot-mounted-grade step errors.
//! let mut sim_config = SimConfig { seed: 3, ..Default::default() };
//! sim_config.walk.laps = 1;
//! let sim = simulate(&sim_config)?;
//!
//! let mut slam = FootSlam::new(FootSlamConfig { particles: 500, ..Default::default() })?;
//! for step in sim.steps.steps() {
//!     slam.update(step);
//! }
//! let best = slam.estimate();
//! assert_eq!(best.path.len(), sim.steps.len());
//! assert!(!best.map.cells.is_empty());
//! # Ok::<(), footslam::Error>(())
//! ```
//!
//! Tracking a walk on a known three-floor building from an unknown start:
//!
//! ```
//! use footslam::filter::{Tracker, TrackerConfig};
//! use footslam::map::{FloorTopology, TopologyConfig};
//! use footslam::sim::{TowerSimConfig, simulate_tower};
//!
//! let mut sim_config = TowerSimConfig { seed: 2, ..Default::default() };
//! sim_config.walk.minutes = 1.0;
//! let sim = simulate_tower(&sim_config)?;
//! let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default())?;
//! let mut tracker = Tracker::new(&topology, &TrackerConfig::default())?;
//! assert!(tracker.initial_particles() > 100_000); // the uniform prior over three floors
//! for step in sim.steps.steps() {
//!     let report = tracker.update(step)?;
//!     if let Some(cluster) = report.estimate.filter(|_| report.localised) {
//!         assert!(cluster.x.is_finite() && cluster.level >= 0);
//!     }
//! }
//! # Ok::<(), footslam::Error>(())
//! ```
//!
//! The same work as the command line's `learn`, through its pipeline (no files):
//!
//! ```
//! use footslam::filter::FootSlamConfig;
//! use footslam::geometry::LocalFrame;
//! use footslam::pipeline::{LearnConfig, LearnInput, LearnWalk, Silent, learn};
//! use footslam::sim::{SimConfig, simulate};
//!
//! let mut sim_config = SimConfig { seed: 4, ..Default::default() };
//! sim_config.walk.laps = 1;
//! let walks = [LearnWalk { trace: simulate(&sim_config)?.steps, ..Default::default() }];
//! let input = LearnInput {
//!     walks: &walks,
//!     frame: LocalFrame::default(),
//!     outline: None,
//!     prior_map: None,
//! };
//! let config = LearnConfig::from(FootSlamConfig { particles: 300, ..Default::default() });
//! let learned = learn(&input, &config, &Silent)?;
//! assert_eq!(learned.walks[0].estimate.path.len(), walks[0].trace.len());
//! # Ok::<(), footslam::Error>(())
//! ```
//!
//! Layers point down only, each using only those before it: [`geometry`] → [`sensor`] →
//! [`inertial`], [`map`] → [`model`] → [`filter`] → [`io`] (files) → [`pipeline`] (the
//! work, reading no files), [`render`] (pictures) and [`view`] (map pages of run folders),
//! with [`sim`] and [`eval`] beside them. The library never prints.

pub mod error;
pub mod eval;
pub mod filter;
pub mod geometry;
pub mod inertial;
pub mod io;
pub mod map;
pub mod memory;
pub mod model;
pub mod pipeline;
pub mod random;
pub mod render;
pub mod sensor;
pub mod sim;
pub mod view;

pub use error::{Error, Result};

#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

#[cfg(doctest)]
#[doc = include_str!("../docs/library.md")]
pub struct LibraryDocDoctests;
