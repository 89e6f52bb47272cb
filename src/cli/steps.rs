//! `footslam steps`: a raw IMU recording → step events (`steps.csv`), with the detector's
//! figures and a picture of the dead-reckoned path.

use super::common::{output_dir, read_config, require_file};
use anyhow::{Context, Result};
use footslam::inertial::frame_check::axes_flag;
use footslam::inertial::{HeadingSource, Mount, StepsConfig};
use footslam::io::RunFolder;
use footslam::io::{ImuUnits, read_imu_in, steps_csv::write_steps_with_field};
use footslam::map::hex_transitions::HexMapSnapshot;
use footslam::pipeline::{DetectorFigures, FrameVerdict, Quality, StepsRun, steps, steps_quality};
use footslam::render::map_png::{MapPicture, PictureConfig, write_map_png};
use footslam::sensor::{ImuRecording, SamplingReport};
use serde::Serialize;
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

#[derive(Debug, Serialize)]
struct Summary<'r> {
    /// The steps' verdict and its reasons (docs/robustness.md).
    quality: Quality,
    imu_file: String,
    mount: Mount,
    steps: usize,
    mean_stride_m: f64,
    total_length_m: f64,
    net_height_change_m: f64,
    heading_source: HeadingSource,
    steps_with_heading: usize,
    /// Steps with a magnetic field reading (`field` column), and of them with its vertical
    /// part (`field_up`).
    steps_with_field: usize,
    steps_with_field_up: usize,
    /// Why the output may be wrong (e.g. the recording does not look like the mount).
    warnings: Vec<String>,
    sampling: SamplingReport,
    detector: &'r DetectorFigures,
    runtime_s: f64,
    version: &'static str,
}

/// Runs `footslam steps`.
pub fn run(args: Args) -> Result<()> {
    require_file(&args.imu, "IMU recording")?;
    let config: StepsConfig = match &args.config {
        Some(p) => read_config(p)?,
        None => StepsConfig::default(),
    };
    config.validate()?;
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
    let mut recording = read_imu_in(&args.imu, units)?;
    if let Some(flip) = args.gyro_flip {
        recording = recording.with_gyro_flipped(flip);
    }
    let out = output_dir(args.out.clone(), "steps");
    let mut folder = super::common::create_run_folder(&out)?;
    folder.protect(std::iter::once(&args.imu).chain(args.config.iter()));
    let mount = match args.mount {
        MountArg::Foot => Mount::Foot,
        MountArg::Phone => Mount::Phone,
    };
    let run = steps(&recording, mount, &config)
        .with_context(|| format!("{}: cannot detect steps", args.imu.display()))?;
    let warnings = run
        .recording_warnings()
        .into_iter()
        .chain(frame_warnings(&args, run.frame_verdict())?)
        .collect();
    let trace_len = run.trace.len();
    let quality = write_outputs(&folder, &args, &recording, warnings, run, started)?;
    folder.write_json("config.json", &config)?;
    let out = folder.commit()?;
    let what = match mount {
        Mount::Foot => "strides",
        Mount::Phone => "steps",
    };
    info!("{trace_len} {what}: {}", out.join("steps.csv").display());
    super::verbosity::done(&out, Some(&quality.line()));
    Ok(())
}

/// The frame check's verdict as an error, or as warnings where the output does not depend
/// on the finding.
fn frame_warnings(args: &Args, verdict: FrameVerdict) -> Result<Vec<String>> {
    let flipped = match args.gyro_flip {
        Some(flip) => format!(" (after --gyro-flip {})", axes_flag(flip)),
        None => String::new(),
    };
    verdict
        .messages(&flipped)
        .map_err(|problem| anyhow::anyhow!("{}: {problem}", args.imu.display()))
}

fn write_outputs(
    folder: &RunFolder,
    args: &Args,
    recording: &ImuRecording,
    warnings: Vec<String>,
    run: StepsRun,
    started: Instant,
) -> Result<Quality> {
    let mount = run.mount;
    let sampling = recording.report().clone();
    let steps = run.trace.steps();
    if steps.is_empty() {
        anyhow::bail!(
            "{}: no {} detected in {:.1} s of data (is --mount right? is the walker moving?)",
            args.imu.display(),
            match mount {
                Mount::Foot => "strides",
                Mount::Phone => "steps",
            },
            sampling.duration_s
        );
    }
    write_steps_with_field(&folder.path("steps.csv"), &run.trace, run.field.as_ref())?;
    for w in &warnings {
        #[allow(clippy::print_stderr)]
        {
            eprintln!("warning: {}: {w}", args.imu.display());
        }
    }
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
    let total_length_m: f64 = steps.iter().map(|s| s.length).sum();
    let summary = Summary {
        quality: steps_quality(&warnings),
        imu_file: args.imu.display().to_string(),
        mount,
        steps: steps.len(),
        mean_stride_m: total_length_m / steps.len() as f64,
        total_length_m,
        net_height_change_m: steps.iter().map(|s| s.dz).sum(),
        heading_source: run.heading_source,
        steps_with_heading: run.trace.with_heading(),
        steps_with_field: run.field.as_ref().map_or(0, |f| f.observed()),
        steps_with_field_up: run.field.as_ref().map_or(0, |f| f.with_vertical()),
        warnings,
        sampling,
        detector: &run.figures,
        runtime_s: started.elapsed().as_secs_f64(),
        version: env!("CARGO_PKG_VERSION"),
    };
    folder.write_json("summary.json", &summary)?;
    Ok(summary.quality)
}
