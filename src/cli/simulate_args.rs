//! The flags of `footslam simulate` ([`Args`]): the building, its walk and its sensor, read
//! by the office and tower runs ([`super::simulate`]) and the campus run
//! ([`super::simulate_campus`]).

use super::common::parse_origin;
use footslam::geometry::LocalFrame;
use footslam::sim::StepNoiseConfig;
use std::path::PathBuf;

/// Which building to simulate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum Building {
    /// One office floor: a corridor loop with rooms (the FootSLAM walks).
    Office,
    /// A multi-floor building with two stairwells of treads (known-map tracking).
    Tower,
    /// The office in a yard with a front door: outdoor–indoor–outdoor walks with GPS fixes
    /// outdoors, and the building's rough outline.
    Campus,
}

/// Which tour the tower's walker takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum Tour {
    /// Room after random room from a random start.
    Random,
    /// A radio survey: every room swept lane by lane, both stairwells between every pair of
    /// floors (ends where the tour ends — about 23 minutes on the default building — or
    /// after `--minutes` when given).
    Survey,
}

/// Arguments of `footslam simulate`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The building.
    #[arg(
        long,
        value_enum,
        default_value = "office",
        help_heading = "Simulation"
    )]
    pub(super) building: Building,
    /// Tower: number of floors (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Simulation")]
    pub(super) floors: Option<usize>,
    /// Tower: every floor with the same layout (overrides the config file).
    #[arg(long, help_heading = "Simulation")]
    pub(super) identical_floors: bool,
    /// Tower: length of the walk in minutes (overrides the config file).
    #[arg(long, value_name = "MINUTES", help_heading = "Simulation")]
    pub(super) minutes: Option<f64>,
    /// Tower: the kind of tour (overrides the config file; default random).
    #[arg(long, value_enum, help_heading = "Simulation")]
    pub(super) tour: Option<Tour>,
    /// Random seed (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Filter")]
    pub(super) seed: Option<u64>,
    /// Office, campus: laps of the corridor loop (overrides the config file).
    #[arg(long, value_name = "N", help_heading = "Simulation")]
    pub(super) laps: Option<usize>,
    /// Campus: number of walks of the building, written to walk-1/ … walk-N/ when more
    /// than one (overrides the config file).
    #[arg(
        long = "walk-count",
        alias = "walks",
        value_name = "N",
        help_heading = "Simulation"
    )]
    pub(super) walks: Option<usize>,
    /// Campus: the walks end indoors after the tour, so GPS sees only the way in
    /// (overrides the config file's `walk_out`).
    #[arg(long, help_heading = "Simulation")]
    pub(super) entrance_only: bool,
    /// Office, tower: the steps carry a magnetometer's reading of the building's field
    /// (`field`, `field_up`; overrides the config file's `field.enabled`).
    #[arg(long, help_heading = "Simulation")]
    pub(super) magnetometer: bool,
    /// Campus: the steps carry a compass's absolute `heading` (overrides the config file's
    /// `compass.enabled`).
    #[arg(long, help_heading = "Simulation")]
    pub(super) compass: bool,
    /// Step-sensor errors: `foot` (a foot-mounted IMU, the default) or `phone` (a hand-held
    /// phone's PDR; on the campus also its compass), both measured on real recordings
    /// (docs/error-models.md). Overrides the config file's `noise` (and `compass`).
    #[arg(long, value_enum, help_heading = "Simulation")]
    pub(super) sensor: Option<Sensor>,
    /// Simulation configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    pub(super) config: Option<PathBuf>,
    /// WGS84 origin of the local frame for the floor plan GeoJSON, `LAT,LON` (default 0,0).
    #[arg(long, value_parser = parse_origin, allow_hyphen_values = true, value_name = "LAT,LON", help_heading = "Inputs")]
    pub(super) origin: Option<LocalFrame>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    pub(super) out: Option<PathBuf>,
}

impl Args {
    /// An error naming a flag given for a building it does not apply to (it would be
    /// ignored, and the user would take the output for what they asked).
    pub(super) fn check_flags_apply(&self) -> anyhow::Result<()> {
        use Building::{Campus, Office, Tower};
        let given: [(&str, bool, &[Building]); 9] = [
            ("--floors", self.floors.is_some(), &[Tower]),
            ("--identical-floors", self.identical_floors, &[Tower]),
            ("--minutes", self.minutes.is_some(), &[Tower]),
            ("--tour", self.tour.is_some(), &[Tower]),
            ("--laps", self.laps.is_some(), &[Office, Campus]),
            ("--walks", self.walks.is_some(), &[Campus]),
            ("--entrance-only", self.entrance_only, &[Campus]),
            ("--magnetometer", self.magnetometer, &[Office, Tower]),
            ("--compass", self.compass, &[Campus]),
        ];
        for (flag, is_given, buildings) in given {
            if is_given && !buildings.contains(&self.building) {
                let names: Vec<&str> = buildings.iter().map(|b| b.name()).collect();
                anyhow::bail!(
                    "{flag} applies to --building {}, not to {}: leave it out, or simulate \
                     --building {}",
                    names.join(" or "),
                    self.building.name(),
                    names[0]
                );
            }
        }
        Ok(())
    }
}

impl Building {
    /// The name `--building` takes.
    fn name(self) -> &'static str {
        match self {
            Building::Office => "office",
            Building::Tower => "tower",
            Building::Campus => "campus",
        }
    }
}

/// Step-sensor error presets of `--sensor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum Sensor {
    /// A foot-mounted IMU's strides.
    Foot,
    /// A hand-held phone's steps.
    Phone,
}

impl Sensor {
    /// The preset's step errors.
    pub(super) fn noise(self) -> StepNoiseConfig {
        match self {
            Self::Foot => StepNoiseConfig::foot(),
            Self::Phone => StepNoiseConfig::phone(),
        }
    }
}
