//! Checks that a run's inputs belong together — one clock, one hexagon grid, one building,
//! floors the steps can change — made by every face (the command line, the Python package)
//! before it calls a pipeline, since each input alone is valid and its reader cannot tell.
//!
//! Each check says what is wrong in words; the face puts the file's name before it and the
//! way out after it, in its own spelling of the option (`--hex-radius 0.5` on the command
//! line, `hex_radius=0.5` in Python).

use crate::geometry::LocalFrame;
use crate::map::{FloorPlan, RadioMap};
use crate::sensor::{GpsFix, WifiScan};
use geo::Polygon;
use std::fmt;

/// Two local frames whose origins are closer than this are the same, metres.
pub const SAME_ORIGIN_M: f64 = 1e-3;

/// A GPS fix up to this long before a walk's first step still belongs to the walk, seconds
/// (a receiver's first fix often comes while the walker waits to start).
pub const GPS_LEAD_S: f64 = 60.0;

/// Below this share of a WiFi log's scans hearing an access point of the radio map, a run
/// warns: the log is mostly of somewhere the map does not cover.
pub const MIN_MATCHED_SHARE: f64 = 0.5;

/// Why `scans` cannot belong to a walk spanning `[start, end]` seconds: no scan falls in
/// the span (a log on another clock would place no scan, or every scan at one end of the
/// walk); `None` when one does.
#[must_use]
pub fn scans_off_clock(scans: &[WifiScan], start: f64, end: f64) -> Option<String> {
    (!scans.iter().any(|s| s.t >= start && s.t <= end)).then(|| {
        format!(
            "no scan falls within the walk's time span [{start}, {end}] s (scans run from {} \
             to {} s): the WiFi log and the step trace must share one clock",
            scans.first().map_or(f64::NAN, |s| s.t),
            scans.last().map_or(f64::NAN, |s| s.t)
        )
    })
}

/// Why `fixes` cannot belong to a walk spanning `[start, end]` seconds: no fix falls in the
/// span (or up to [`GPS_LEAD_S`] before it), as with a log on another clock or a GPX track
/// whose UTC times were not put on the steps' clock; `None` when one does (or there are no
/// fixes).
#[must_use]
pub fn fixes_off_clock(fixes: &[GpsFix], start: f64, end: f64) -> Option<String> {
    let (first, last) = (fixes.first()?, fixes.last()?);
    let within = fixes
        .iter()
        .any(|f| f.t >= start - GPS_LEAD_S && f.t <= end);
    (!within).then(|| {
        format!(
            "no fix falls within the walk's time span [{start}, {end}] s (fixes run from {} to \
             {} s)",
            first.t, last.t
        )
    })
}

/// Scans or fixes more than this far outside a walk's time span are off its clock, seconds
/// (a WiFi log or receiver may run a little before and after the walk).
pub const CLOCK_SLACK_S: f64 = 10.0;

/// Above this share of a log's records lying off the walk's clock (and at least 3 of them),
/// a run warns: the log is probably on another clock or offset from the steps'.
pub const MAX_OFF_CLOCK_SHARE: f64 = 0.2;

/// GPS fixes farther than this from the run's origin cannot be of the walk, metres.
pub const MAX_FIX_DISTANCE_M: f64 = 50_000.0;

/// An outline farther than this from every walk's start cannot be the walk's building,
/// metres.
pub const MAX_OUTLINE_DISTANCE_M: f64 = 500.0;

/// An outline smaller than this cannot hold a walk, square metres.
pub const MIN_OUTLINE_AREA_M2: f64 = 10.0;

/// The warning for a log whose records' times (`times`) lie partly off the walk's time span
/// `[start, end]` (`what` names the records, e.g. "scans"): more than
/// [`MAX_OFF_CLOCK_SHARE`] of them, and at least 3, more than [`CLOCK_SLACK_S`] (before
/// the start, `lead` more) outside; `None` otherwise. A log offset by tens of seconds
/// still overlaps the walk, so [`scans_off_clock`] cannot see it, but its records then
/// weigh the wrong steps.
#[must_use]
pub fn partly_off_clock(
    times: &[f64],
    what: &str,
    start: f64,
    end: f64,
    lead: f64,
) -> Option<String> {
    let off = times
        .iter()
        .filter(|&&t| t < start - lead - CLOCK_SLACK_S || t > end + CLOCK_SLACK_S)
        .count();
    let n = times.len();
    (off >= 3 && off as f64 > MAX_OFF_CLOCK_SHARE * n as f64).then(|| {
        format!(
            "{off} of its {n} {what} lie more than {CLOCK_SLACK_S} s outside the walk's time \
             span [{start}, {end}] s ({what} run from {} to {} s): is it on the steps' clock, \
             or offset? Those {what} are left out, and the rest may weigh the wrong steps",
            times.first().copied().unwrap_or(f64::NAN),
            times.last().copied().unwrap_or(f64::NAN)
        )
    })
}

/// Why `fixes` cannot be of a walk in `frame`: the nearest lies more than
/// [`MAX_FIX_DISTANCE_M`] from the frame's origin (another city than `--origin`, or
/// latitude and longitude swapped); `None` when one is near (or there are none).
pub fn fixes_far_from_origin(fixes: &[GpsFix], frame: &LocalFrame) -> Option<String> {
    let nearest = fixes
        .iter()
        .map(|f| {
            let (x, y) = frame.to_local(f.lon, f.lat);
            x.hypot(y)
        })
        .min_by(f64::total_cmp)?;
    (nearest > MAX_FIX_DISTANCE_M).then(|| {
        format!(
            "its nearest fix lies {:.0} km from the run's origin ({}, {}): the fixes and the \
             origin must be of one place (latitude and longitude swapped?)",
            nearest / 1000.0,
            frame.lat,
            frame.lon
        )
    })
}

/// Why `outline` (in the frame's metres) cannot be the building of `walks` (each starting
/// at its own start, else at `default_start`): smaller than [`MIN_OUTLINE_AREA_M2`], or
/// farther than [`MAX_OUTLINE_DISTANCE_M`] from every start; `None` otherwise.
pub fn outline_off_walks(
    outline: &Polygon<f64>,
    walks: &[super::LearnWalk],
    default_start: (f64, f64),
) -> Option<String> {
    use geo::{Area, Distance, Euclidean, Point};
    let starts: Vec<(f64, f64)> = walks
        .iter()
        .map(|w| w.start.map_or(default_start, |s| (s.x, s.y)))
        .collect();
    let area = outline.unsigned_area();
    if area < MIN_OUTLINE_AREA_M2 {
        return Some(format!(
            "the outline covers {area:.3e} m², less than the {MIN_OUTLINE_AREA_M2} m² a walk \
             needs: is it in degrees of the right place, and the building's?"
        ));
    }
    let nearest = starts
        .iter()
        .map(|&(x, y)| Euclidean.distance(&Point::new(x, y), outline))
        .min_by(f64::total_cmp)?;
    (nearest > MAX_OUTLINE_DISTANCE_M).then(|| {
        format!(
            "the outline lies {nearest:.0} m from the walk's start: it is not this walk's \
             building (or the origin or start is wrong)"
        )
    })
}

/// How a map's hexagon grid differs from a run's: hexagons of another size, or a frame of
/// another origin (hexagons of different origins do not line up).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridMismatch {
    /// The hexagons' circumradii differ, metres.
    Radius {
        /// The map's.
        map: f64,
        /// The run's.
        run: f64,
    },
    /// The frames' origins lie `off` metres apart.
    Origin {
        /// The distance between the origins, metres.
        off: f64,
        /// The map's frame.
        map: LocalFrame,
        /// The run's frame.
        run: LocalFrame,
    },
}

impl fmt::Display for GridMismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Radius { map, run } => {
                write!(f, "hexagons of radius {map} m, but this run uses {run} m")
            }
            Self::Origin { off, map, run } => write!(
                f,
                "its origin ({}, {}) lies {off:.3} m from this run's ({}, {}); hexagons of \
                 different origins do not line up",
                map.lat, map.lon, run.lat, run.lon
            ),
        }
    }
}

/// How a map on hexagons of `map_radius` in `map_frame` fails to lie on a run's grid
/// (`run_radius`, `run_frame`); `None` when it lies on it.
#[must_use]
pub fn grid_mismatch(
    map_radius: f64,
    map_frame: &LocalFrame,
    run_radius: f64,
    run_frame: &LocalFrame,
) -> Option<GridMismatch> {
    if (map_radius - run_radius).abs() > 1e-9 {
        return Some(GridMismatch::Radius {
            map: map_radius,
            run: run_radius,
        });
    }
    let off = run_frame.distance_to(map_frame);
    (off > SAME_ORIGIN_M).then_some(GridMismatch::Origin {
        off,
        map: *map_frame,
        run: *run_frame,
    })
}

/// Why a walk cannot be tracked on `plan` (named `plan_label`): the plan has several levels
/// but the steps carry no height changes (`has_dz` false), so every step reads `dz = 0` and
/// the walk could never change floor; `None` when the steps have them, the plan has one
/// level, or the caller says the walk stays on its floor (`one_floor`). The face adds how
/// to say so.
#[must_use]
pub fn missing_height_changes(
    plan: &FloorPlan,
    plan_label: &str,
    has_dz: bool,
    one_floor: bool,
) -> Option<String> {
    let levels = plan.levels().len();
    (levels > 1 && !one_floor && !has_dz).then(|| {
        format!(
            "no `dz` column, but {plan_label} has {levels} levels: the steps' height changes \
             are what moves the walk between floors; add `dz` (footslam steps writes it from \
             the barometer or the foot's height)"
        )
    })
}

/// How many of a WiFi log's scans hear an access point of a radio map: none means the log
/// and the map are of different buildings, fewer than [`MIN_MATCHED_SHARE`] that most of
/// the log is of places the map does not cover.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScanMatch {
    /// Scans hearing at least one access point of the map.
    pub matched: usize,
    /// Scans in the log.
    pub scans: usize,
}

impl ScanMatch {
    /// The match of `scans` against `map`.
    #[must_use]
    pub fn of(map: &RadioMap, scans: &[WifiScan]) -> Self {
        Self {
            matched: map.scans_matched(scans),
            scans: scans.len(),
        }
    }

    /// The share of the scans that match (0 for an empty log).
    #[must_use]
    pub fn share(&self) -> f64 {
        self.matched as f64 / self.scans.max(1) as f64
    }

    /// The error when no scan matches: the log and the map are of different buildings.
    #[must_use]
    pub fn unmatched(&self) -> Option<String> {
        (self.matched == 0).then(|| {
            format!(
                "none of the log's {} scans hears an access point of the radio map: they are \
                 of different buildings (or the BSSIDs were renamed)",
                self.scans
            )
        })
    }

    /// The warning when some but fewer than [`MIN_MATCHED_SHARE`] of the scans (of the log
    /// `wifi_label`) match the map (`map_label`).
    #[must_use]
    pub fn warning(&self, wifi_label: &str, map_label: &str) -> Option<String> {
        (self.matched > 0 && self.share() < MIN_MATCHED_SHARE).then(|| {
            format!(
                "only {} of {} scans of {wifi_label} ({:.0} %) hear an access point of \
                 {map_label}: the rest cannot be placed by the radio map",
                self.matched,
                self.scans,
                100.0 * self.share()
            )
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fix(t: f64) -> GpsFix {
        GpsFix {
            t,
            lat: 52.0,
            lon: 11.0,
            accuracy: 5.0,
        }
    }

    #[test]
    fn fixes_on_another_clock_are_named() {
        assert_eq!(fixes_off_clock(&[], 0.0, 10.0), None);
        // A fix a little before the walk counts; one after it or long before does not.
        assert_eq!(fixes_off_clock(&[fix(-30.0)], 0.0, 10.0), None);
        let off = fixes_off_clock(&[fix(-100.0), fix(1e9)], 0.0, 10.0).expect("off clock");
        assert!(
            off.contains("[0, 10] s") && off.contains("from -100 to 1000000000 s"),
            "{off}"
        );
    }

    #[test]
    fn grids_differ_by_radius_or_origin() {
        let here = LocalFrame::new(52.0, 11.0).expect("frame");
        let there = LocalFrame::new(52.001, 11.0).expect("frame");
        assert_eq!(grid_mismatch(0.5, &here, 0.5, &here), None);
        let radius = grid_mismatch(1.0, &here, 0.5, &here).expect("radius");
        assert_eq!(radius, GridMismatch::Radius { map: 1.0, run: 0.5 });
        assert_eq!(
            radius.to_string(),
            "hexagons of radius 1 m, but this run uses 0.5 m"
        );
        match grid_mismatch(0.5, &there, 0.5, &here) {
            Some(GridMismatch::Origin { off, .. }) => assert!((off - 111.2).abs() < 0.5, "{off}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn scan_matches_grade_the_log() {
        let none = ScanMatch {
            matched: 0,
            scans: 4,
        };
        assert!(
            none.unmatched()
                .expect("none")
                .contains("none of the log's 4 scans")
        );
        assert_eq!(none.warning("w", "m"), None);
        let few = ScanMatch {
            matched: 1,
            scans: 4,
        };
        assert_eq!(few.unmatched(), None);
        let warning = few.warning("wifi.csv", "radiomap.geojson").expect("few");
        assert!(
            warning.starts_with("only 1 of 4 scans of wifi.csv (25 %)"),
            "{warning}"
        );
        assert_eq!(
            ScanMatch {
                matched: 2,
                scans: 4
            }
            .warning("w", "m"),
            None
        );
    }
}
