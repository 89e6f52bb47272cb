//! Time and peak memory of one FootSLAM run on a simulated office walk, for BENCHMARKS.md.
//!
//! `cargo run --release --example scaling -- PARTICLES STEPS [SEED]` prints one CSV row:
//! `particles,steps,seconds,particle_steps_per_s,peak_rss_bytes,bytes_per_particle`.
//! Peak memory is the process's high-water mark (Linux `VmHWM`), so run one size per process
//! (`scripts/scaling.sh` does).

use footslam::filter::{FootSlam, FootSlamConfig};
use footslam::sim::office_walk_steps;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn peak_rss() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| {
                l.split_whitespace()
                    .nth(1)
                    .and_then(|v| v.parse::<u64>().ok())
            })
        })
        .map_or(0, |kb| kb * 1024)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let particles: usize = args.next().map_or(Ok(100_000), |s| s.parse())?;
    let steps: usize = args.next().map_or(Ok(700), |s| s.parse())?;
    let seed: u64 = args.next().map_or(Ok(1), |s| s.parse())?;
    let trace = office_walk_steps(steps, seed)?;
    let baseline = peak_rss();
    let started = std::time::Instant::now();
    let mut filter = FootSlam::new(FootSlamConfig {
        particles,
        seed,
        ..Default::default()
    })?;
    for step in &trace {
        filter.update(step);
    }
    let estimate = filter.estimate();
    let seconds = started.elapsed().as_secs_f64();
    let peak = peak_rss();
    std::hint::black_box(estimate);
    #[allow(clippy::print_stdout)]
    {
        println!(
            "{particles},{steps},{seconds:.3},{:.0},{peak},{:.0}",
            (particles * steps) as f64 / seconds,
            peak.saturating_sub(baseline) as f64 / particles as f64
        );
    }
    Ok(())
}
