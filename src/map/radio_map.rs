//! Cell-based WiFi radio maps (Woodman & Harle 2009, sec. 4): for every cell, how many scans
//! were taken there and, per access point, an RSSI histogram in 1 dB bins with its count,
//! mean and spread; the scans of the cell that did not hear an access point are its misses.
//! Maps built from several walks merge by adding their counts.

use crate::error::{Error, Result};
use crate::sensor::WifiScan;
use geo::MultiPolygon;
use rustc_hash::FxHashMap;
use std::collections::BTreeMap;

/// One access point's readings in one cell.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ApStats {
    /// Readings.
    pub n: u32,
    /// Sum of the readings, dBm.
    pub sum: f64,
    /// Sum of their squares, dBm².
    pub sum_sq: f64,
    /// Readings per whole dBm (1 dB bins, keyed by the rounded RSSI).
    pub hist: BTreeMap<i32, u32>,
}

impl ApStats {
    /// Counts one reading.
    pub fn add(&mut self, rssi: f64) {
        self.n += 1;
        self.sum += rssi;
        self.sum_sq += rssi * rssi;
        *self.hist.entry(rssi.round() as i32).or_default() += 1;
    }

    /// Mean RSSI, dBm (`None` without readings).
    #[must_use]
    pub fn mean(&self) -> Option<f64> {
        (self.n > 0).then(|| self.sum / f64::from(self.n))
    }

    /// Standard deviation of the readings, dB (`None` without readings).
    #[must_use]
    pub fn std(&self) -> Option<f64> {
        let mean = self.mean()?;
        Some(
            (self.sum_sq / f64::from(self.n) - mean * mean)
                .max(0.0)
                .sqrt(),
        )
    }

    /// Adds `other`'s readings.
    pub fn merge(&mut self, other: &ApStats) {
        self.n += other.n;
        self.sum += other.sum;
        self.sum_sq += other.sum_sq;
        for (&bin, &count) in &other.hist {
            *self.hist.entry(bin).or_default() += count;
        }
    }
}

/// What a cell heard.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CellRadio {
    /// Scans taken in the cell.
    pub scans: u32,
    /// Per access point (by BSSID), its readings.
    pub aps: BTreeMap<String, ApStats>,
}

impl CellRadio {
    /// Counts one scan taken in the cell.
    pub fn add_scan(&mut self, scan: &WifiScan) {
        self.scans += 1;
        for r in &scan.readings {
            self.aps.entry(r.bssid.clone()).or_default().add(r.rssi);
        }
    }

    /// Scans of the cell that did not hear `bssid`.
    #[must_use]
    pub fn misses(&self, bssid: &str) -> u32 {
        self.scans - self.aps.get(bssid).map_or(0, |a| a.n)
    }

    /// Adds `other`'s scans.
    pub fn merge(&mut self, other: &CellRadio) {
        self.scans += other.scans;
        for (bssid, stats) in &other.aps {
            self.aps.entry(bssid.clone()).or_default().merge(stats);
        }
    }
}

/// One cell of a radio map: its id, level, floor area (local metres) and what it heard.
#[derive(Debug, Clone, PartialEq)]
pub struct RadioMapCell {
    /// Cell id (unique in the map).
    pub id: String,
    /// Floor level.
    pub level: i32,
    /// The cell's floor, local metres.
    pub area: MultiPolygon<f64>,
    /// What it heard.
    pub radio: CellRadio,
}

/// Cells of two maps whose centres lie this close are the same cell, metres (the files
/// round coordinates to centimetres).
const SAME_CELL_M: f64 = 0.5;

/// The distance between the centres of two cells' floors, metres (infinite when either has
/// no area).
fn cell_offset(a: &RadioMapCell, b: &RadioMapCell) -> f64 {
    use geo::Centroid;
    match (a.area.centroid(), b.area.centroid()) {
        (Some(p), Some(q)) => (p.x() - q.x()).hypot(p.y() - q.y()),
        _ => f64::INFINITY,
    }
}

/// A radio map: cells with their readings.
///
/// A plan's cells, scans counted where they were taken, coverage and a merge:
///
/// ```
/// use footslam::map::{CellConfig, CellMap, FloorPlan, FloorPolygon, FloorTopology, RadioMap};
/// use footslam::map::TopologyConfig;
/// use footslam::sensor::WifiScan;
///
/// let room = |x0: f64| FloorPolygon {
///     polygon: geo::Rect::new((x0, 0.0), (x0 + 6.0, 3.0)).to_polygon(),
///     level: 0,
///     z: 0.0,
///     name: None,
///     room: None,
/// };
/// // Two 6 m × 3 m rooms, each cut into two 3 m cells.
/// let plan = FloorPlan { polygons: vec![room(0.0), room(10.0)], barriers: Vec::new() };
/// let topology = FloorTopology::build(&plan, &TopologyConfig::default())?;
/// let cells = CellMap::build(&plan, &topology, &CellConfig::default())?;
/// assert_eq!((cells.rooms().len(), cells.cells().len()), (2, 4));
///
/// let mut map = RadioMap::empty(&cells);
/// for (x, scan) in [
///     (1.0, WifiScan::from_readings(0.0, &[("ap-west", -40.0), ("ap-east", -85.0)])),
///     (1.5, WifiScan::from_readings(1.0, &[("ap-west", -42.0)])),
///     (4.0, WifiScan::from_readings(2.0, &[("ap-west", -50.0), ("ap-east", -80.0)])),
///     (13.0, WifiScan::from_readings(3.0, &[("ap-east", -45.0)])),
/// ] {
///     let surface = topology.locate(x, 1.5, None, None).expect("on the floor");
///     let cell = cells.cell_at(surface, x, 1.5).expect("a cell");
///     map.cells[cell].radio.add_scan(&scan);
/// }
/// assert_eq!(map.access_points(), ["ap-east", "ap-west"]);
/// let first = &map.cells[0].radio;
/// assert_eq!((first.scans, first.misses("ap-east")), (2, 1));
/// assert_eq!(first.aps["ap-west"].mean(), Some(-41.0));
/// // Three of the four equal cells hold scans, 4/3 scans each.
/// let (share, scans_per_cell) = map.coverage();
/// assert!((share - 0.75).abs() < 1e-12 && (scans_per_cell - 4.0 / 3.0).abs() < 1e-12);
///
/// // Maps of one plan surveyed apart merge by adding their counts.
/// let mut both = map.clone();
/// both.merge(&map)?;
/// assert_eq!(both.cells[0].radio.scans, 4);
/// # Ok::<(), footslam::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RadioMap {
    /// The cells.
    pub cells: Vec<RadioMapCell>,
    /// The region threshold `ε` calibrated on the survey for the paper's distance (dBm, see
    /// [`crate::model::wifi_distance::calibrate_epsilon`]), if known.
    pub epsilon: Option<f64>,
    /// The same for the distance divided by `√k` (`Normalisation::Sqrt` of
    /// [`crate::model::wifi_distance`]), if known.
    pub epsilon_sqrt: Option<f64>,
}

impl RadioMap {
    /// An empty map over the cells of `cells` (ids `"<room>-<column>-<row>"`).
    #[must_use]
    pub fn empty(cells: &super::CellMap) -> Self {
        Self {
            cells: cells
                .cells()
                .iter()
                .map(|c| RadioMapCell {
                    id: format!("{}-{}-{}", c.room, c.box_index.0, c.box_index.1),
                    level: c.level,
                    area: c.area.clone(),
                    radio: CellRadio::default(),
                })
                .collect(),
            ..Default::default()
        }
    }

    /// Centre (local metres) and level of each cell, in order; a cell without area has a NaN
    /// centre.
    #[must_use]
    pub fn cell_centres(&self) -> Vec<(f64, f64, i32)> {
        use geo::Centroid;
        self.cells
            .iter()
            .map(|c| {
                c.area
                    .centroid()
                    .map_or((f64::NAN, f64::NAN, c.level), |p| (p.x(), p.y(), c.level))
            })
            .collect()
    }

    /// Every access point heard in any cell, sorted (a stable column order).
    #[must_use]
    pub fn access_points(&self) -> Vec<&str> {
        let mut bssids: Vec<&str> = self
            .cells
            .iter()
            .flat_map(|c| c.radio.aps.keys().map(String::as_str))
            .collect();
        bssids.sort_unstable();
        bssids.dedup();
        bssids
    }

    /// The column of each access point in [`Self::access_points`]' order (a model's
    /// per-access-point vectors).
    #[must_use]
    pub fn access_point_columns(&self) -> FxHashMap<String, usize> {
        self.access_points()
            .into_iter()
            .enumerate()
            .map(|(i, b)| (b.to_owned(), i))
            .collect()
    }

    /// How many of `scans` hear at least one access point the map knows: a scan that hears
    /// none cannot be placed by the map, and a log where none does belongs to another
    /// building (or had its BSSIDs renamed).
    #[must_use]
    pub fn scans_matched(&self, scans: &[WifiScan]) -> usize {
        let known = self.access_points();
        scans
            .iter()
            .filter(|s| {
                s.readings
                    .iter()
                    .any(|r| known.binary_search(&r.bssid.as_str()).is_ok())
            })
            .count()
    }

    /// Adds `other`'s readings cell by cell; both maps must have the same cell ids in the
    /// same order (maps of one plan at one granularity).
    ///
    /// # Errors
    ///
    /// [`Error::Mismatch`], leaving `self` unchanged, when the maps' cells differ in number or ids,
    /// or a cell of `other` lies on another level or more than 0.5 m from its namesake (a map of
    /// another plan or frame).
    pub fn merge(&mut self, other: &RadioMap) -> Result<()> {
        if self.cells.len() != other.cells.len()
            || self
                .cells
                .iter()
                .zip(&other.cells)
                .any(|(a, b)| a.id != b.id)
        {
            return Err(Error::mismatch(
                "radio maps with different cells cannot be merged",
                "survey them on the same plan at the same granularity",
            ));
        }
        // Ids are per plan ("room-column-row"): another building's map can share them.
        // Its cells must also lie where these do, on the same level.
        if let Some((a, b, off)) = self
            .cells
            .iter()
            .zip(&other.cells)
            .map(|(a, b)| (a, b, cell_offset(a, b)))
            .find(|&(a, b, off)| a.level != b.level || off > SAME_CELL_M)
        {
            return Err(Error::mismatch(
                format!(
                    "cell {} lies {off:.1} m from this map's cell {} (levels {} and {}): \
                     a map of another plan or frame",
                    b.id, a.id, b.level, a.level
                ),
                "merge radio maps surveyed on the same plan, in the same frame (origin)",
            ));
        }
        for (a, b) in self.cells.iter_mut().zip(&other.cells) {
            a.radio.merge(&b.radio);
        }
        // The larger of two calibrations is the safer threshold for the merged map.
        let safer = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
        self.epsilon = safer(self.epsilon, other.epsilon);
        self.epsilon_sqrt = safer(self.epsilon_sqrt, other.epsilon_sqrt);
        Ok(())
    }

    /// Coverage as the paper defines it (sec. 4): the share of the floor area in cells with
    /// at least one scan; and the mean number of scans per such cell.
    #[must_use]
    pub fn coverage(&self) -> (f64, f64) {
        use geo::Area;
        let total: f64 = self.cells.iter().map(|c| c.area.unsigned_area()).sum();
        let covered: Vec<&RadioMapCell> = self.cells.iter().filter(|c| c.radio.scans > 0).collect();
        let share = if total > 0.0 {
            covered.iter().map(|c| c.area.unsigned_area()).sum::<f64>() / total
        } else {
            0.0
        };
        let mean = if covered.is_empty() {
            0.0
        } else {
            covered
                .iter()
                .map(|c| f64::from(c.radio.scans))
                .sum::<f64>()
                / covered.len() as f64
        };
        (share, mean)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan(readings: &[(&str, f64)]) -> WifiScan {
        WifiScan::from_readings(0.0, readings)
    }

    #[test]
    fn histograms_means_spreads_and_misses() {
        let mut cell = CellRadio::default();
        cell.add_scan(&scan(&[("a", -60.0), ("b", -80.0)]));
        cell.add_scan(&scan(&[("a", -64.0)]));
        cell.add_scan(&scan(&[("a", -62.4)]));
        let a = &cell.aps["a"];
        assert_eq!(a.n, 3);
        assert!((a.mean().expect("mean") + 62.133_333).abs() < 1e-5);
        assert!((a.std().expect("std") - 1.6438).abs() < 1e-3);
        assert_eq!(a.hist.get(&-62), Some(&1));
        assert_eq!(cell.misses("a"), 0);
        assert_eq!(cell.misses("b"), 2);
        assert_eq!(cell.misses("never"), 3);
        let mut other = CellRadio::default();
        other.add_scan(&scan(&[("b", -78.0)]));
        cell.merge(&other);
        assert_eq!((cell.scans, cell.aps["b"].n), (4, 2));
        assert_eq!(cell.misses("b"), 2);
    }

    #[test]
    fn scans_match_when_they_hear_a_known_access_point() {
        let mut radio = CellRadio::default();
        radio.add_scan(&scan(&[("a", -60.0), ("b", -80.0)]));
        let map = RadioMap {
            cells: vec![RadioMapCell {
                id: "0-0-0".into(),
                level: 0,
                area: MultiPolygon(Vec::new()),
                radio,
            }],
            epsilon: None,
            epsilon_sqrt: None,
        };
        let scans = [
            scan(&[("b", -70.0), ("x", -50.0)]),
            scan(&[("x", -50.0)]),
            scan(&[]),
        ];
        assert_eq!(map.scans_matched(&scans), 1);
        assert_eq!(map.scans_matched(&[]), 0);
    }

    #[test]
    fn maps_merge_only_over_the_same_cells_and_report_coverage() {
        let tower = crate::sim::Tower::new(&Default::default()).expect("tower");
        let topology =
            crate::map::FloorTopology::build(&tower.plan, &Default::default()).expect("topology");
        let cells =
            crate::map::CellMap::build(&tower.plan, &topology, &Default::default()).expect("cells");
        let mut a = RadioMap::empty(&cells);
        let mut b = RadioMap::empty(&cells);
        a.cells[0].radio.add_scan(&scan(&[("x", -70.0)]));
        b.cells[0].radio.add_scan(&scan(&[("x", -72.0)]));
        b.cells[1].radio.add_scan(&scan(&[]));
        a.merge(&b).expect("merge");
        assert_eq!(a.cells[0].radio.aps["x"].n, 2);
        let (share, mean) = a.coverage();
        use geo::Area;
        let area = |i: usize| a.cells[i].area.unsigned_area();
        let total: f64 = (0..a.cells.len()).map(area).sum();
        assert!((share - (area(0) + area(1)) / total).abs() < 1e-12);
        assert!((mean - 1.5).abs() < 1e-12);
        let mut other = a.clone();
        other.cells.pop();
        assert!(a.merge(&other).is_err());
        // The same ids somewhere else (another building, another frame) do not merge.
        use geo::Translate;
        let mut moved = a.clone();
        for c in &mut moved.cells {
            c.area = c.area.translate(40.0, 0.0);
        }
        let err = a.merge(&moved).expect_err("moved cells");
        assert!(err.to_string().contains("40.0 m"), "{err}");
        let mut relevelled = a.clone();
        relevelled.cells[3].level += 1;
        assert!(a.merge(&relevelled).is_err());
    }
}
