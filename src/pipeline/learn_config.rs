//! The configuration of the `learn` job: the filter's ([`FootSlamConfig`], what each walk's
//! particle filter reads) and the pipeline's own knobs (FeetSLAM passes over a batch, the
//! weight of a prior map, the radio map's cells), every default in one place, and the
//! options of the faces that override it ([`LearnOverrides`]).
//!
//! A configuration file (and `config.json`) holds the filter's keys and the pipeline's side
//! by side, as one table:
//!
//! ```
//! use footslam::pipeline::LearnConfig;
//! let config: LearnConfig = toml::from_str("particles = 500\niterations = 0\n").unwrap();
//! assert_eq!((config.footslam.particles, config.iterations), (500, 0));
//! assert!(toml::from_str::<LearnConfig>("iterashuns = 0\n").is_err());
//! ```

use crate::error::{Error, Result};
use crate::filter::FootSlamConfig;
use crate::map::CellConfig;
use serde::{Deserialize, Deserializer, Serialize};

/// The most FeetSLAM iterations a configuration may ask for.
const MAX_ITERATIONS: u32 = 20;

/// Everything `learn` runs with; every default in one place.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LearnConfig {
    /// The filter's configuration, each walk's before its start is set from its own anchors
    /// (known start, GPS fixes, compass).
    #[serde(flatten)]
    pub footslam: FootSlamConfig,
    /// Weight `w` of a prior map's counts as pseudo-counts on top of `α`. Default 1.
    pub prior_weight: f64,
    /// FeetSLAM iterations for a batch of walks learned into one frame (every walk with a
    /// known start): after the walks are learned alone, each is learned again
    /// `iterations` times with the merged map of the others (from the pass before) as its
    /// prior, weighted by `prior_weight`. Default 2: the first pass shares what the others
    /// saw; the second lets walks that were wrong alone correct the others in turn, and more
    /// passes change little (docs/footslam.md) while each costs a full run.
    pub iterations: u32,
    /// The cells of the radio map made of the walks' WiFi. Default: see [`CellConfig`].
    pub cells: CellConfig,
}

impl Default for LearnConfig {
    fn default() -> Self {
        Self {
            footslam: FootSlamConfig::default(),
            prior_weight: 1.0,
            iterations: 2,
            cells: CellConfig::default(),
        }
    }
}

/// The filter's configuration with the pipeline's defaults.
impl From<FootSlamConfig> for LearnConfig {
    fn from(footslam: FootSlamConfig) -> Self {
        Self {
            footslam,
            ..Self::default()
        }
    }
}

impl LearnConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `footslam` fails
    /// [`FootSlamConfig::validate`](crate::filter::FootSlamConfig::validate), `prior_weight` is
    /// outside [0, 1000], `iterations` exceeds 20, or `cells` fails
    /// [`CellConfig::validate`](crate::map::CellConfig::validate).
    pub fn validate(&self) -> Result<()> {
        self.footslam.validate()?;
        if !(self.prior_weight.is_finite() && (0.0..=1000.0).contains(&self.prior_weight)) {
            return Err(Error::config(
                "prior_weight",
                self.prior_weight.to_string(),
                "must be a finite number ≥ 0 (and not absurd)",
            ));
        }
        if self.iterations > MAX_ITERATIONS {
            return Err(Error::config(
                "iterations",
                self.iterations.to_string(),
                "must be at most 20 (each is a full pass over the walks)",
            ));
        }
        self.cells.validate()
    }
}

/// The pipeline's keys of a configuration table.
#[derive(Deserialize)]
#[serde(default, deny_unknown_fields)]
struct Knobs {
    prior_weight: f64,
    iterations: u32,
    cells: CellConfig,
}

impl Default for Knobs {
    fn default() -> Self {
        let LearnConfig {
            prior_weight,
            iterations,
            cells,
            ..
        } = LearnConfig::default();
        Self {
            prior_weight,
            iterations,
            cells,
        }
    }
}

/// One table holds both levels' keys. Serde's `flatten` cannot refuse unknown keys, so the
/// table is read whole, the pipeline's keys taken out, and the rest read as the filter's
/// configuration, which refuses any key it does not know; errors name the key's path.
impl<'de> Deserialize<'de> for LearnConfig {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error as _;
        let mut table = serde_json::Map::<String, serde_json::Value>::deserialize(deserializer)?;
        let knobs: serde_json::Map<String, serde_json::Value> =
            ["prior_weight", "iterations", "cells"]
                .into_iter()
                .filter_map(|key| table.remove(key).map(|v| (key.to_owned(), v)))
                .collect();
        let knobs: Knobs = serde_path_to_error::deserialize(serde_json::Value::Object(knobs))
            .map_err(|e| D::Error::custom(format!("{}: {}", e.path(), e.inner())))?;
        let footslam: FootSlamConfig = serde_path_to_error::deserialize(serde_json::Value::Object(
            table,
        ))
        .map_err(|e| match e.path().to_string().as_str() {
            "." => D::Error::custom(e.inner()),
            path => D::Error::custom(format!("{path}: {}", e.inner())),
        })?;
        Ok(Self {
            footslam,
            prior_weight: knobs.prior_weight,
            iterations: knobs.iterations,
            cells: knobs.cells,
        })
    }
}

/// The options of `learn` that change its configuration; `None` (or `false`) leaves the
/// configuration's value. Both faces fill it from their arguments.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LearnOverrides {
    /// `seed` (walk `i` of a batch has `seed + i`).
    pub seed: Option<u64>,
    /// `particles`.
    pub particles: Option<usize>,
    /// `hex_radius`, metres.
    pub hex_radius: Option<f64>,
    /// `prior_weight`.
    pub prior_weight: Option<f64>,
    /// `heading.enabled = false`: the steps' absolute heading is not read.
    pub ignore_heading: bool,
    /// `cells.granularity`, metres.
    pub cell: Option<f64>,
}

impl LearnOverrides {
    /// `config` with these overrides, validated.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when the result fails [`LearnConfig::validate`] (e.g. `particles: Some(0)`
    /// or a `hex_radius` outside [0.05, 10] m).
    ///
    /// # Examples
    ///
    /// ```
    /// use footslam::pipeline::{LearnConfig, LearnOverrides};
    /// let o = LearnOverrides { particles: Some(500), prior_weight: Some(0.5), ..Default::default() };
    /// let config = o.apply(LearnConfig::default())?;
    /// assert_eq!((config.footslam.particles, config.prior_weight), (500, 0.5));
    /// # Ok::<(), footslam::Error>(())
    /// ```
    pub fn apply(&self, mut config: LearnConfig) -> Result<LearnConfig> {
        let filter = &mut config.footslam;
        if let Some(n) = self.particles {
            filter.particles = n;
        }
        if let Some(s) = self.seed {
            filter.seed = s;
        }
        if let Some(r) = self.hex_radius {
            filter.hex_radius = r;
        }
        if self.ignore_heading {
            filter.heading.enabled = false;
        }
        if let Some(w) = self.prior_weight {
            config.prior_weight = w;
        }
        if let Some(g) = self.cell {
            config.cells.granularity = g;
        }
        config.validate()?;
        Ok(config)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_table_reads_both_levels_and_refuses_unknown_keys() {
        let text = "particles = 300\nprior_weight = 0.5\n[cells]\ngranularity = 4.0\n\
                    [motion]\nlength_sigma = 0.2\n";
        let config: LearnConfig = toml::from_str(text).expect("reads");
        assert_eq!(config.footslam.particles, 300);
        assert_eq!(config.prior_weight, 0.5);
        assert_eq!(config.cells.granularity, 4.0);
        assert_eq!(config.iterations, LearnConfig::default().iterations);
        for (bad, says) in [
            ("particle = 3\n", "particle"),
            ("[cells]\ngranularty = 3\n", "granularty"),
            ("[motion]\nlength_sigma = \"x\"\n", "motion.length_sigma"),
            ("iterations = -1\n", "iterations"),
        ] {
            let e = toml::from_str::<LearnConfig>(bad)
                .expect_err(bad)
                .to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn config_json_reads_back_to_the_same_configuration() {
        let config = LearnOverrides {
            seed: Some(7),
            cell: Some(5.0),
            prior_weight: Some(2.0),
            ..LearnOverrides::default()
        }
        .apply(LearnConfig::default())
        .expect("valid");
        let json = serde_json::to_string(&config).expect("serialises");
        let back: LearnConfig = serde_json::from_str(&json).expect("reads back");
        assert_eq!(back, config);
    }

    #[test]
    fn overrides_are_validated() {
        let bad = LearnOverrides {
            cell: Some(0.0),
            ..LearnOverrides::default()
        };
        assert!(bad.apply(LearnConfig::default()).is_err());
        let bad = LearnOverrides {
            prior_weight: Some(f64::NAN),
            ..LearnOverrides::default()
        };
        assert!(bad.apply(LearnConfig::default()).is_err());
    }
}
