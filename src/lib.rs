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
pub mod sensor;
pub mod sim;

pub use error::{Error, Result};
