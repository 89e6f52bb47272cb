//! Simulated WiFi: access points on every floor and the scans a walker's receiver records.
//!
//! The expected received signal strength of access point `a` at a point `p` is
//!
//! ```text
//! RSSI(a, p) = P₁ − 10 n log₁₀(max(d, 1 m)) − L_w · walls(a, p) − L_f · |Δlevel| + S_a(p)
//! ```
//!
//! (log-distance path loss with exponent `n` and the RSSI `P₁` at 1 m, a loss per wall segment
//! crossed on the receiver's level, a loss per floor between them, and a fixed spatial
//! shadowing field `S_a`: a stationary Gaussian field per access point and level with a
//! squared-exponential correlation of length `shadowing_length`, drawn once as a sum of random
//! cosines). A scan adds temporal noise and body shadowing (up to `body_loss_max` when the
//! walker's body is between the receiver and the access point), rounds to whole dBm and
//! drops readings below the detection floor. The expected field ([`RadioWorld::expected_rssi`],
//! `wifi_field.csv`) is the mean reading: with half the largest body loss. Scans come every `scan_interval` seconds (with
//! jitter) at the walker's interpolated position.

use crate::error::{Error, Result};
use crate::map::{FloorTopology, SegmentKind};
use crate::random::gauss;
use crate::sensor::truth::{TruePath, TruePose};
use crate::sensor::{AccessPoint, WifiReading, WifiScan};
use rand::{RngExt, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Random cosines per shadowing field.
const FEATURES: usize = 48;

/// The radio environment's parameters; every default in one place.
///
/// | field                | default  | meaning                                                |
/// |----------------------|----------|--------------------------------------------------------|
/// | `aps_per_floor`      | 8        | access points on each floor, spread over its area (24 in the tower; the paper's building showed 33) |
/// | `rssi_at_1m`         | −38 dBm  | `P₁`                                                   |
/// | `path_loss_exponent` | 2.2      | `n`                                                    |
/// | `wall_loss`          | 2.5 dB   | per wall segment crossed (a wall between two rooms is two segments) |
/// | `max_wall_loss`      | 25 dB    | cap on the total wall loss                             |
/// | `floor_loss`         | 15 dB    | per floor between access point and receiver            |
/// | `shadowing_sigma`    | 4 dB     | spread of the fixed spatial shadowing                  |
/// | `shadowing_length`   | 3 m      | its correlation length                                 |
/// | `temporal_sigma`     | 2 dB     | noise of each reading                                  |
/// | `body_loss_max`      | 9 dB     | body shadowing with the access point straight behind   |
/// | `detection_floor`    | −96 dBm  | weaker readings are not reported                       |
/// | `scan_interval`      | 2 s      | time between scans                                     |
/// | `scan_jitter`        | 0.1      | relative jitter (1σ) of that interval                  |
/// | `radio_seed`         | 1        | seed of the access points' places and the shadowing    |
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WifiSimConfig {
    /// Access points per floor.
    pub aps_per_floor: usize,
    /// RSSI at 1 m, dBm.
    pub rssi_at_1m: f64,
    /// Path-loss exponent.
    pub path_loss_exponent: f64,
    /// Loss per wall segment crossed, dB.
    pub wall_loss: f64,
    /// Cap on the total wall loss, dB.
    pub max_wall_loss: f64,
    /// Loss per floor between access point and receiver, dB.
    pub floor_loss: f64,
    /// Spread (1σ) of the fixed spatial shadowing, dB.
    pub shadowing_sigma: f64,
    /// Correlation length of the shadowing, metres.
    pub shadowing_length: f64,
    /// Noise (1σ) of each reading, dB.
    pub temporal_sigma: f64,
    /// Body shadowing with the access point straight behind the walker, dB.
    pub body_loss_max: f64,
    /// Weakest reported RSSI, dBm.
    pub detection_floor: f64,
    /// Time between scans, seconds.
    pub scan_interval: f64,
    /// Relative jitter (1σ) of the scan interval.
    pub scan_jitter: f64,
    /// Seed of the access points' places and the shadowing fields: walks simulated with
    /// equal radio seeds (and buildings) share one radio environment, so a radio map
    /// surveyed on one serves the others.
    pub radio_seed: u64,
}

impl Default for WifiSimConfig {
    fn default() -> Self {
        Self {
            aps_per_floor: 8,
            rssi_at_1m: -38.0,
            path_loss_exponent: 2.2,
            wall_loss: 2.5,
            max_wall_loss: 25.0,
            floor_loss: 15.0,
            shadowing_sigma: 4.0,
            shadowing_length: 3.0,
            temporal_sigma: 2.0,
            body_loss_max: 9.0,
            detection_floor: -96.0,
            scan_interval: 2.0,
            scan_jitter: 0.1,
            radio_seed: 1,
        }
    }
}

impl WifiSimConfig {
    /// Checks every field against its documented range.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] naming the first field out of its range (e.g. `aps_per_floor` outside
    /// [1, 1000], `rssi_at_1m` outside [−80, 0] dBm, `detection_floor` outside [−120, −30] dBm,
    /// `scan_interval` outside [0.1, 600] s).
    pub fn validate(&self) -> Result<()> {
        crate::error::check_range(
            "wifi.aps_per_floor",
            self.aps_per_floor as f64,
            1.0..=1000.0,
            "",
        )?;
        crate::error::check_range("wifi.rssi_at_1m", self.rssi_at_1m, -80.0..=0.0, "dBm")?;
        crate::error::check_range(
            "wifi.path_loss_exponent",
            self.path_loss_exponent,
            1.0..=6.0,
            "",
        )?;
        crate::error::check_range("wifi.wall_loss", self.wall_loss, 0.0..=30.0, "dB")?;
        crate::error::check_range("wifi.max_wall_loss", self.max_wall_loss, 0.0..=100.0, "dB")?;
        crate::error::check_range("wifi.floor_loss", self.floor_loss, 0.0..=60.0, "dB")?;
        crate::error::check_range(
            "wifi.shadowing_sigma",
            self.shadowing_sigma,
            0.0..=20.0,
            "dB",
        )?;
        crate::error::check_range(
            "wifi.shadowing_length",
            self.shadowing_length,
            0.1..=100.0,
            "m",
        )?;
        crate::error::check_range("wifi.temporal_sigma", self.temporal_sigma, 0.0..=20.0, "dB")?;
        crate::error::check_range("wifi.body_loss_max", self.body_loss_max, 0.0..=30.0, "dB")?;
        crate::error::check_range(
            "wifi.detection_floor",
            self.detection_floor,
            -120.0..=-30.0,
            "dBm",
        )?;
        crate::error::check_range("wifi.scan_interval", self.scan_interval, 0.1..=600.0, "s")?;
        crate::error::check_range("wifi.scan_jitter", self.scan_jitter, 0.0..=0.5, "")?;
        Ok(())
    }
}

/// One cosine of a shadowing field: `cos(wx·x + wy·y + phase)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Feature {
    wx: f64,
    wy: f64,
    phase: f64,
}

/// The access points of a building and everything that shapes their signals.
#[derive(Debug, Clone, PartialEq)]
pub struct RadioWorld {
    config: WifiSimConfig,
    aps: Vec<AccessPoint>,
    levels: (i32, i32),
    /// Shadowing features per (access point, level index).
    fields: Vec<Vec<Feature>>,
    /// Walls (and barriers) per level index, as segments.
    walls: Vec<Vec<[f64; 4]>>,
}

impl RadioWorld {
    /// Places `aps_per_floor` access points on every level of the plan (uniformly over each
    /// floor's walkable area, at least 5 m apart where possible) and draws their shadowing,
    /// all from `seed`.
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when `config` fails [`WifiSimConfig::validate`]; [`Error::NotEnough`] when
    /// the plan has no walkable surface.
    pub fn new(topology: &FloorTopology, config: &WifiSimConfig, seed: u64) -> Result<Self> {
        config.validate()?;
        if topology.is_empty() {
            return Err(Error::not_enough(
                "the floor plan has no walkable surface",
                "",
            ));
        }
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let levels = topology.levels();
        let n_levels = (levels.1 - levels.0 + 1) as usize;
        let mut aps: Vec<AccessPoint> = Vec::new();
        for level in levels.0..=levels.1 {
            let mut placed = 0;
            let mut tries = 0;
            while placed < config.aps_per_floor && tries < 100_000 {
                tries += 1;
                let (s, [x, y]) = topology.sample_uniform(&mut rng);
                if topology.level(s) != level {
                    continue;
                }
                let crowded = aps
                    .iter()
                    .any(|a| a.level == level && (a.x - x).hypot(a.y - y) < 5.0);
                if crowded && tries < 10_000 {
                    continue;
                }
                aps.push(AccessPoint {
                    bssid: format!(
                        "02:00:00:00:{:02x}:{:02x}",
                        aps.len() / 256,
                        aps.len() % 256
                    ),
                    x,
                    y,
                    level,
                });
                placed += 1;
            }
        }
        let length = config.shadowing_length;
        let fields = (0..aps.len() * n_levels)
            .map(|_| {
                (0..FEATURES)
                    .map(|_| Feature {
                        wx: gauss(&mut rng) / length,
                        wy: gauss(&mut rng) / length,
                        phase: rng.random_range(0.0..std::f64::consts::TAU),
                    })
                    .collect()
            })
            .collect();
        let mut walls = vec![Vec::new(); n_levels];
        for s in topology.segments() {
            let level = match s.kind {
                SegmentKind::Wall { surface } => topology.level(surface),
                SegmentKind::Barrier { level } => level,
                SegmentKind::Connection { .. } => continue,
            };
            walls[(level - levels.0) as usize].push([s.a[0], s.a[1], s.b[0], s.b[1]]);
        }
        Ok(Self {
            config: *config,
            aps,
            levels,
            fields,
            walls,
        })
    }

    /// The access points.
    #[must_use]
    pub fn access_points(&self) -> &[AccessPoint] {
        &self.aps
    }

    /// The expected RSSI of access point `ap` at `(x, y)` on `level`, dBm: the mean of what a
    /// receiver there reads over temporal noise and over the walker's headings (so with the
    /// mean body loss, half of `body_loss_max`); not clipped at the detection floor.
    #[must_use]
    pub fn expected_rssi(&self, ap: usize, x: f64, y: f64, level: i32) -> f64 {
        self.unobstructed_rssi(ap, x, y, level) - self.config.body_loss_max / 2.0
    }

    /// The RSSI without the walker's body and without noise.
    fn unobstructed_rssi(&self, ap: usize, x: f64, y: f64, level: i32) -> f64 {
        let c = &self.config;
        let a = &self.aps[ap];
        let d = (a.x - x).hypot(a.y - y).max(1.0);
        let li = (level.clamp(self.levels.0, self.levels.1) - self.levels.0) as usize;
        let walls = self.walls[li]
            .iter()
            .filter(|w| segments_cross([a.x, a.y, x, y], **w))
            .count() as f64;
        let n_levels = (self.levels.1 - self.levels.0 + 1) as usize;
        let field = &self.fields[ap * n_levels + li];
        let shadow = c.shadowing_sigma
            * (2.0 / FEATURES as f64).sqrt()
            * field
                .iter()
                .map(|f| (f.wx * x + f.wy * y + f.phase).cos())
                .sum::<f64>();
        c.rssi_at_1m
            - 10.0 * c.path_loss_exponent * d.log10()
            - (c.wall_loss * walls).min(c.max_wall_loss)
            - c.floor_loss * f64::from((a.level - level).abs())
            + shadow
    }

    /// One scan at `pose` (the walker heading `pose.heading`) at time `t`.
    pub fn scan(&self, t: f64, pose: &TruePose, rng: &mut Pcg64Mcg) -> WifiScan {
        let c = &self.config;
        let mut readings = Vec::new();
        for (i, a) in self.aps.iter().enumerate() {
            let bearing = (a.y - pose.y).atan2(a.x - pose.x);
            let body = c.body_loss_max * (1.0 - (bearing - pose.heading).cos()) / 2.0;
            let noise = c.temporal_sigma * gauss(rng);
            let rssi =
                (self.unobstructed_rssi(i, pose.x, pose.y, pose.level) - body + noise).round();
            if rssi >= c.detection_floor {
                readings.push(WifiReading {
                    bssid: a.bssid.clone(),
                    rssi: rssi.min(0.0),
                    ssid: Some("footslam-sim".into()),
                    freq: Some(if i % 2 == 0 { 2437.0 } else { 5180.0 }),
                });
            }
        }
        WifiScan { t, readings }
    }

    /// Scans along a walk, every `scan_interval` seconds (with jitter) from the start, at the
    /// walker's position interpolated between steps; drawn from `seed`.
    #[must_use]
    pub fn scans_along(&self, start: &TruePose, truth: &TruePath, seed: u64) -> Vec<WifiScan> {
        let c = &self.config;
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        let Some(end) = truth.poses.last().map(|p| p.t) else {
            return Vec::new();
        };
        let mut scans = Vec::new();
        let mut t = start.t + rng.random_range(0.0..c.scan_interval);
        while t <= end {
            let pose = truth.pose_at(start, t);
            scans.push(self.scan((t * 1000.0).round() / 1000.0, &pose, &mut rng));
            let step = c.scan_interval * (1.0 + c.scan_jitter * gauss(&mut rng));
            t += step.max(0.2 * c.scan_interval);
        }
        scans
    }
}

/// A point of the expected RSSI field: `(level, x, y, [dBm per access point])`.
pub type FieldPoint = (i32, f64, f64, Vec<f64>);

/// The expected RSSI of every access point on a grid of `spacing` metres over the walkable
/// area of every level, in level, y, x order.
#[must_use]
pub fn expected_field(
    world: &RadioWorld,
    topology: &FloorTopology,
    spacing: f64,
) -> Vec<FieldPoint> {
    let b = topology.bounds();
    let spacing = spacing.max(0.1);
    let (nx, ny) = (
        ((b[2] - b[0]) / spacing).floor() as usize + 1,
        ((b[3] - b[1]) / spacing).floor() as usize + 1,
    );
    let (lo, hi) = topology.levels();
    let mut rows = Vec::new();
    for level in lo..=hi {
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = (b[0] + i as f64 * spacing, b[1] + j as f64 * spacing);
                if topology.locate(x, y, Some(level), None).is_some() {
                    let rssi = (0..world.aps.len())
                        .map(|a| world.expected_rssi(a, x, y, level))
                        .collect();
                    rows.push((level, x, y, rssi));
                }
            }
        }
    }
    rows
}

/// True when segment `p` (x0, y0, x1, y1) properly crosses segment `q`.
fn segments_cross(p: [f64; 4], q: [f64; 4]) -> bool {
    let orient = |ax: f64, ay: f64, bx: f64, by: f64, cx: f64, cy: f64| {
        (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    };
    let d1 = orient(q[0], q[1], q[2], q[3], p[0], p[1]);
    let d2 = orient(q[0], q[1], q[2], q[3], p[2], p[3]);
    let d3 = orient(p[0], p[1], p[2], p[3], q[0], q[1]);
    let d4 = orient(p[0], p[1], p[2], p[3], q[2], q[3]);
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::TopologyConfig;
    use crate::sim::{TowerSimConfig, simulate_tower};

    fn world() -> (crate::sim::TowerSimulation, FloorTopology, RadioWorld) {
        let mut config = TowerSimConfig {
            seed: 3,
            ..Default::default()
        };
        config.walk.minutes = 3.0;
        let sim = simulate_tower(&config).expect("sim");
        let topology = FloorTopology::build(&sim.plan, &TopologyConfig::default()).expect("topo");
        let world = RadioWorld::new(&topology, &WifiSimConfig::default(), 5).expect("world");
        (sim, topology, world)
    }

    #[test]
    fn access_points_on_every_floor_and_signals_fall_with_distance_walls_and_floors() {
        let (sim, _, world) = world();
        assert_eq!(world.access_points().len(), 24);
        for level in 0..3 {
            assert_eq!(
                world
                    .access_points()
                    .iter()
                    .filter(|a| a.level == level)
                    .count(),
                8
            );
        }
        let a = &world.access_points()[0];
        assert!(sim.plan.is_walkable(a.x, a.y, Some(a.level)));
        let near = world.expected_rssi(0, a.x + 1.0, a.y, a.level);
        assert!((-60.0..-20.0).contains(&near), "{near}");
        // Averaged over the shadowing, 20 m away is much weaker, and a floor away weaker still.
        let mean = |dx: f64, dl: i32| {
            (0..36)
                .map(|k| {
                    let phi = f64::from(k) * 10f64.to_radians();
                    world.expected_rssi(0, a.x + dx * phi.cos(), a.y + dx * phi.sin(), a.level + dl)
                })
                .sum::<f64>()
                / 36.0
        };
        let other = if a.level == 0 { 1 } else { -1 };
        assert!(mean(20.0, 0) < mean(2.0, 0) - 15.0);
        assert!(mean(2.0, other) < mean(2.0, 0) - 10.0);
    }

    #[test]
    fn scans_every_two_seconds_above_the_floor_and_deterministic() {
        let (sim, _, world) = world();
        let scans = world.scans_along(&sim.start, &sim.truth, 9);
        let duration = sim.truth.poses.last().expect("poses").t;
        let expected = duration / 2.0;
        assert!(
            (scans.len() as f64 - expected).abs() < 0.15 * expected,
            "{} scans",
            scans.len()
        );
        assert!(scans.windows(2).all(|w| w[1].t > w[0].t));
        assert!(
            scans
                .iter()
                .all(|s| s.readings.iter().all(|r| r.rssi >= -96.0 && r.rssi <= 0.0))
        );
        let heard: usize = scans.iter().map(|s| s.readings.len()).sum();
        assert!(heard as f64 / scans.len() as f64 >= 3.0);
        assert_eq!(scans, world.scans_along(&sim.start, &sim.truth, 9));
        assert_ne!(scans, world.scans_along(&sim.start, &sim.truth, 10));
    }

    #[test]
    fn the_expected_field_covers_every_floor() {
        let (_, topology, world) = world();
        let field = expected_field(&world, &topology, 2.0);
        for level in 0..3 {
            let n = field.iter().filter(|r| r.0 == level).count() as f64;
            let area = 4.0 * n;
            assert!(area > 400.0 && area < 1200.0, "level {level}: {area} m²");
        }
        let (level, x, y, rssi) = &field[10];
        assert_eq!(rssi.len(), 24);
        assert_eq!(rssi[3], world.expected_rssi(3, *x, *y, *level));
    }

    #[test]
    fn walls_are_counted_where_crossed() {
        assert!(segments_cross([0.0, 0.0, 2.0, 0.0], [1.0, -1.0, 1.0, 1.0]));
        assert!(!segments_cross([0.0, 0.0, 0.5, 0.0], [1.0, -1.0, 1.0, 1.0]));
        assert!(!segments_cross([0.0, 0.0, 2.0, 0.0], [0.0, 1.0, 2.0, 1.0]));
    }
}
