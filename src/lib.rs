//! # footslam
//!
//! An open toolkit that turns pedestrians' walks into building maps.
//!
//! * **FootSLAM** (Robertson et al. 2009): a Rao-Blackwellised particle filter that reads
//!   step traces and learns, per particle, a hexagon transition map — Dirichlet-multinomial
//!   counts of crossings of each hexagon edge. See [`filter::FootSlam`] and
//!   [`map::HexTransitionMap`].
//! * Readers for step traces ([`dataset`]), exporters to RFC 7946 GeoJSON and pictures
//!   ([`export`]), a simulator of office walks with a foot-mounted-grade error model
//!   ([`sim`]) and trajectory evaluation ([`eval`]).
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
//! Layers point down only: [`geometry`] → [`sensor`], [`map`] → [`model`] → [`filter`] →
//! [`dataset`], [`export`] (and [`sim`], [`eval`]). The library never prints.

pub mod dataset;
pub mod error;
pub mod eval;
pub mod export;
pub mod filter;
pub mod geometry;
pub mod map;
pub mod model;
pub mod random;
pub mod sensor;
pub mod sim;

pub use error::{Error, Result};
