//! `footslam steps`: a raw IMU recording → step events (`steps.csv`), with the detector's
//! figures and a picture of the dead-reckoned path.

use super::common::{output_dir, read_config, require_file};
use anyhow::Result;
use footslam::inertial::{HeadingSource, Mount, StepsConfig};
use footslam::io::RunFolder;
use footslam::io::{ImuUnits, read_imu_in, steps_csv::write_steps_with_field};
use footslam::map::hex_transitions::HexMapSnapshot;
use footslam::pipeline::{Named, StepsJob, StepsRequest, run_steps};
use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `footslam steps`.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// IMU recording CSV: `t,ax,ay,az,gx,gy,gz` (s, m/s² with gravity, rad/s, sensor frame),
    /// optionally `mx,my,mz` (µT), `qx,qy,qz,qw` (orientation sensor → ENU) and `pressure`
    /// (hPa); extra columns are ignored.
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    imu: PathBuf,
    /// Where the IMU was worn: `foot` (zero-velocity-aided INS, one event per stride) or
    /// `phone` (held in the hand: step-and-heading system, one event per step).
    #[arg(long, value_enum, help_heading = "Inputs")]
    mount: MountArg,
    /// Unit of the acceleration columns: `m/s2` (the format's) or `g`.
    #[arg(
        long,
        value_enum,
        default_value = "m/s2",
        value_name = "UNIT",
        help_heading = "Inputs"
    )]
    accel_unit: AccelUnit,
    /// Unit of the angular-rate columns: `rad/s` (the format's) or `deg/s`.
    #[arg(
        long,
        value_enum,
        default_value = "rad/s",
        value_name = "UNIT",
        help_heading = "Inputs"
    )]
    gyro_unit: GyroUnit,
    /// Gyroscope axes to negate (any of `x`, `y`, `z`, e.g. `y` or `xyz`): for recordings
    /// whose gyroscope is mirrored against the accelerometer (a left-handed frame, or an
    /// inverted axis). Such recordings are detected and refused with the axes to give here.
    #[arg(long, value_parser = footslam::inertial::frame_check::parse_axes, value_name = "AXES", help_heading = "Inputs")]
    gyro_flip: Option<[bool; 3]>,
    /// Detector configuration (TOML, or JSON such as a previous run's config.json).
    #[arg(long, value_name = "FILE", help_heading = "Inputs")]
    config: Option<PathBuf>,
    /// Output folder (default: a new folder under `outputs/`).
    #[arg(short = 'o', long, value_name = "DIR", help_heading = "Outputs")]
    out: Option<PathBuf>,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum AccelUnit {
    #[value(name = "m/s2")]
    MetresPerSecondSquared,
    #[value(name = "g")]
    G,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum GyroUnit {
    #[value(name = "rad/s")]
    RadiansPerSecond,
    #[value(name = "deg/s")]
    DegreesPerSecond,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum MountArg {
    Foot,
    Phone,
}

/// Runs `footslam steps`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.imu, "IMU recording")?;
    let config: StepsConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => StepsConfig::default(),
    };
    let started = Instant::now();
    let units = ImuUnits {
        accel: match args.accel_unit {
            AccelUnit::MetresPerSecondSquared => 1.0,
            AccelUnit::G => ImuUnits::G,
        },
        gyro: match args.gyro_unit {
            GyroUnit::RadiansPerSecond => 1.0,
            GyroUnit::DegreesPerSecond => std::f64::consts::PI / 180.0,
        },
    };
    let request = StepsRequest {
        recording: Named::new(
            read_imu_in(&args.imu, units)?,
            args.imu.display().to_string(),
        ),
        mount: match args.mount {
            MountArg::Foot => Mount::Foot,
            MountArg::Phone => Mount::Phone,
        },
        gyro_flip: args.gyro_flip,
        config,
    };
    let out = output_dir(args.out.clone(), "steps");
    let mut folder = super::common::create_run_folder(&out)?;
    folder.protect(std::iter::once(&args.imu).chain(args.config.iter()));
    let config = request.config.clone();
    let job = run_steps(request, started)?;
    for w in &job.report.warnings {
        super::common::warn(&format!("{}: {w}", job.report.imu_file));
    }
    write_outputs(&folder, &job)?;
    folder.write_json("config.json", &config)?;
    let out = folder.commit()?;
    let what = match job.run.mount {
        Mount::Foot => "strides",
        Mount::Phone => "steps",
    };
    info!(
        "{} {what}: {}",
        job.run.trace.len(),
        out.join("steps.csv").display()
    );
    super::verbosity::done(&out, Some(&job.report.quality.line()));
    Ok(())
}

/// `steps.csv`, `steps.png` and `summary.json`.
fn write_outputs(folder: &RunFolder, job: &StepsJob) -> Result<()> {
    let run = &job.run;
    write_steps_with_field(&folder.path("steps.csv"), &run.trace, run.field.as_ref())?;
    let path: Vec<(f64, f64)> = run.path.iter().map(|p| (p[0], p[1])).collect();
    let empty = HexMapSnapshot {
        radius: 0.5,
        alpha: 0.8,
        cells: Vec::new(),
        levels: Vec::new(),
    };
    // The front end's frame is east-north only where its heading is absolute.
    let picture = MapPicture {
        path_label: "dead-reckoned steps",
        north_up: run.heading_source != HeadingSource::Gyroscope,
        ..MapPicture::new(&empty, &path)
    };
    write_map_png(
        &folder.path("steps.png"),
        &picture,
        &PictureConfig::default(),
    )?;
    folder.write_json("summary.json", &job.report)?;
    Ok(())
}
