//! The command line: the only place for clap, anyhow, progress bars and printing.

/// Prints a line on stdout, ignoring a closed pipe (`footslam ... | head`).
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($arg)*);
    }};
}

/// Prints a line of a run's report on stdout, unless `--quiet`.
macro_rules! info {
    ($($arg:tt)*) => {{
        if !$crate::cli::verbosity::quiet() {
            outln!($($arg)*);
        }
    }};
}

mod batch_table;
mod common;
mod eval;
mod eval_picture;
mod field_outputs;
mod fingerprint;
mod import;
mod learn;
mod learn_args;
mod learn_inputs;
mod learn_outputs;
mod learn_shard;
mod merge;
mod plan;
mod progress_bars;
mod radio_outputs;
mod shell;
mod simulate;
mod simulate_args;
mod simulate_campus;
mod steps;
mod survey;
mod track;
mod track_pictures;
mod track_summary;
mod track_walks;
mod verbosity;
mod view;

use clap::{Parser, Subcommand};

/// footslam: learn building maps from pedestrians' walks.
#[derive(Debug, Parser)]
#[command(name = "footslam", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Say nothing but errors and warnings: no progress bars, no report.
    #[arg(short, long, global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Also list every file written, and show progress bars from the start.
    #[arg(short, long, global = true)]
    verbose: bool,
}

/// Every subcommand takes negative numbers as values (`--flag -3`, not only `--flag=-3`).
#[derive(Debug, Subcommand)]
enum Command {
    /// Learn a hexagon transition map and the walker's path from a step trace (FootSLAM).
    #[command(allow_negative_numbers = true)]
    Learn(learn_args::Args),
    /// Combine maps learned on several walks of one building (same frame).
    #[command(allow_negative_numbers = true)]
    Merge(merge::Args),
    /// Turn a learned map into a walkable floor plan and a ROS occupancy grid.
    #[command(allow_negative_numbers = true)]
    Plan(plan::Args),
    /// Turn a raw IMU recording (foot-mounted or phone) into step events.
    #[command(allow_negative_numbers = true)]
    Steps(steps::Args),
    /// Locate and track a walker on a known 2.5D floor plan from step events.
    #[command(allow_negative_numbers = true)]
    Track(track::Args),
    /// Build a WiFi radio map from walks tracked on a known floor plan.
    #[command(allow_negative_numbers = true)]
    Survey(survey::Args),
    /// Simulate a building (office floor or multi-floor tower), a walk and its sensors.
    #[command(allow_negative_numbers = true)]
    Simulate(simulate_args::Args),
    /// Place each WiFi scan by a radio map alone (weighted k-nearest fingerprints).
    #[command(allow_negative_numbers = true)]
    Fingerprint(fingerprint::Args),
    /// Position error of a track against the truth.
    #[command(allow_negative_numbers = true)]
    Eval(eval::Args),
    /// Convert public dataset recordings (Indoor Location Competition, IPIN) into footslam's CSV and GeoJSON.
    #[command(allow_negative_numbers = true)]
    Import(import::Args),
    /// Write an interactive map page of run folders (open index.html in a browser; no server).
    #[command(allow_negative_numbers = true)]
    View(view::Args),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(shell::CompletionArgs),
    /// Write the manual pages (man footslam, man footslam-learn, ...).
    Man(shell::ManArgs),
}

/// Runs the command line and maps errors to an exit code.
pub fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    verbosity::set(cli.quiet, cli.verbose);
    // Ctrl-C or SIGTERM: the run's staged outputs go with it (exit status 130, as a shell's
    // for an interrupt). Without a handler (none could be set) the next run removes them.
    let _ = ctrlc::set_handler(|| {
        footslam::io::run_folder::remove_staging_folders();
        std::process::exit(130);
    });
    let result = match cli.command {
        Command::Learn(a) => learn::run(a),
        Command::Merge(a) => merge::run(a),
        Command::Plan(a) => plan::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Steps(a) => steps::run(a),
        Command::Track(a) if a.walks.is_some() => track_walks::run(&a),
        Command::Track(a) => track::run(a),
        Command::Survey(a) => survey::run(a),
        Command::Eval(a) => eval::run(a),
        Command::Fingerprint(a) => fingerprint::run(a),
        Command::Import(a) => import::run(a),
        Command::View(a) => view::run(a),
        Command::Completions(a) => shell::completions(&a),
        Command::Man(a) => shell::man(&a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            #[allow(clippy::print_stderr)]
            {
                eprintln!("error: {}", spelled(&e));
            }
            std::process::ExitCode::FAILURE
        }
    }
}

/// An error as `{:#}` shows it (each cause after the one before), with a library
/// [`Remedy`](footslam::error::Remedy) spelled as this command line's option.
fn spelled(e: &anyhow::Error) -> String {
    use footslam::error::{Remedy, RemedyValue};
    let option = |r: &Remedy| {
        let flag = format!("--{}", r.option.replace('_', "-"));
        match r.value {
            RemedyValue::Flag => flag,
            RemedyValue::Number(v) => format!("{flag} {v}"),
            RemedyValue::LatLon(lat, lon) => format!("{flag} {lat},{lon}"),
            RemedyValue::Described(what) => format!("{flag} <{what}>"),
        }
    };
    e.chain()
        .map(|cause| match cause.downcast_ref::<footslam::Error>() {
            Some(footslam::Error::Remedied { problem, remedy }) => {
                format!("{problem}, or pass {}", option(remedy))
            }
            Some(footslam::Error::BadOption { option, problem }) => {
                format!("--{}: {problem}", option.replace('_', "-"))
            }
            _ => cause.to_string(),
        })
        .collect::<Vec<_>>()
        .join(": ")
}
