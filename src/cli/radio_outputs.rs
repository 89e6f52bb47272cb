//! The files of a radio map, written alike by `survey` (on a drawn plan) and `learn --wifi`
//! (on the plan learned from the walks): `radiomap.geojson`, `radiomap.csv` and a heatmap for
//! each of the access points heard in the most cells (`--heatmaps`).

use anyhow::Result;
use footslam::filter::FingerprintConfig;
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::radio_map_geojson::{write_radio_map_csv, write_radio_map_geojson};
use footslam::map::{ApStats, FloorPlan, RadioMap};
use footslam::model::RadioInterpolation;
use footslam::render::plan_png::{
    ColourBar, PlanCell, PlanMarker, PlanPicture, PlanPictureConfig, viridis_rgb, write_plan_png,
};
use geo::Centroid;
use rayon::prelude::*;

/// Heatmap colours run from this RSSI (dark) to [`HEATMAP_TOP`] (bright), dBm.
const HEATMAP_FLOOR: f64 = -96.0;
/// The brightest heatmap colour, dBm.
const HEATMAP_TOP: f64 = -30.0;

/// How many access points get a heatmap (`--heatmaps N|all`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Heatmaps {
    /// The `N` heard in the most cells.
    Most(usize),
    /// Every access point of the map.
    All,
}

impl Heatmaps {
    /// The default: a real floor's survey hears hundreds to thousands of access points
    /// (1,987 on a mall floor), and one picture each would be most of the run's time and
    /// disk; the 24 heard most widely show the floor's radio field.
    pub(super) const DEFAULT: Self = Self::Most(24);
}

/// Parses `--heatmaps`: a count or `all`.
pub(super) fn parse_heatmaps(s: &str) -> Result<Heatmaps, String> {
    if s.eq_ignore_ascii_case("all") {
        return Ok(Heatmaps::All);
    }
    s.parse::<usize>()
        .map(Heatmaps::Most)
        .map_err(|_| format!("expected a number of access points or `all`, got `{s}`"))
}

/// The access points given a heatmap: by cells that heard them (most first), then readings,
/// then BSSID; all of them for [`Heatmaps::All`].
fn heatmap_access_points(map: &RadioMap, which: Heatmaps) -> Vec<&str> {
    let mut heard: rustc_hash::FxHashMap<&str, (u32, u32)> = rustc_hash::FxHashMap::default();
    for c in &map.cells {
        for (bssid, stats) in &c.radio.aps {
            let e = heard.entry(bssid.as_str()).or_default();
            e.0 += 1;
            e.1 += stats.n;
        }
    }
    let mut bssids: Vec<(&str, (u32, u32))> = heard.into_iter().collect();
    bssids.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    let keep = match which {
        Heatmaps::All => bssids.len(),
        Heatmaps::Most(n) => n.min(bssids.len()),
    };
    bssids.into_iter().take(keep).map(|(b, _)| b).collect()
}

/// Writes `{prefix}radiomap.geojson`, `{prefix}radiomap.csv`, `{prefix}radiomap.png` (scans
/// per cell over `plan`) and `{prefix}heatmap-BSSID.png` (mean RSSI per cell of one access
/// point, named by [`heatmap_name`]) for the access points `heatmaps` selects, drawn in
/// parallel. Returns how many heatmaps it wrote.
pub(super) fn write_radio_map_files(
    folder: &RunFolder,
    prefix: &str,
    plan: &FloorPlan,
    map: &RadioMap,
    (frame, north_up, extent, heatmaps): (&LocalFrame, bool, Option<[f64; 4]>, Heatmaps),
) -> Result<usize> {
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    // The part of the plan the pictures show: `--picture-extent`, else what they draw.
    let pictures = PlanPictureConfig {
        extent,
        ..PlanPictureConfig::default()
    };
    write_radio_map_geojson(&at("radiomap.geojson"), map, frame)?;
    write_radio_map_csv(&at("radiomap.csv"), map)?;
    write_coverage_png(&at("radiomap.png"), plan, map, (north_up, &pictures))?;
    // File names first (in order: two BSSIDs may differ only in characters a file name
    // cannot hold), then the pictures in parallel.
    let mut names = std::collections::BTreeSet::new();
    let chosen: Vec<(&str, String)> = heatmap_access_points(map, heatmaps)
        .into_iter()
        .map(|bssid| {
            let mut name = heatmap_name(bssid);
            while !names.insert(name.clone()) {
                name = name.replace(".png", "_.png");
            }
            (bssid, name)
        })
        .collect();
    // Between surveyed cells, the interpolated map `fingerprint` uses (its defaults).
    let fingerprint = FingerprintConfig::default();
    let (missing, min_scans) = (fingerprint.missing_rssi, fingerprint.min_scans);
    let interpolation =
        RadioInterpolation::new(map, missing, min_scans, &fingerprint.interpolation).ok();
    chosen.par_iter().try_for_each(|(bssid, name)| {
        let picture = heatmap_picture(plan, map, interpolation.as_ref(), bssid, north_up);
        write_plan_png(&at(name), &[picture], &pictures)
    })?;
    Ok(chosen.len())
}

/// The heatmap of access point `bssid`: each cell that heard it coloured by its mean RSSI;
/// with `interpolation`, each cell nobody surveyed that the interpolated map knows by its
/// predicted mean, paler (cells it does not know stay blank); the strongest cell marked.
fn heatmap_picture<'a>(
    plan: &'a FloorPlan,
    map: &'a RadioMap,
    interpolation: Option<&RadioInterpolation>,
    bssid: &str,
    north_up: bool,
) -> PlanPicture<'a> {
    let colour = |mean: f64| {
        viridis_rgb(((mean - HEATMAP_FLOOR) / (HEATMAP_TOP - HEATMAP_FLOOR)).clamp(0.0, 1.0))
    };
    let heat: Vec<PlanCell> = map
        .cells
        .iter()
        .enumerate()
        .filter_map(|(i, c)| {
            let colour = match c.radio.aps.get(bssid).and_then(ApStats::mean) {
                Some(mean) => colour(mean),
                None if c.radio.scans == 0 => {
                    let interpolation = interpolation.filter(|m| m.is_known(i))?;
                    paler(colour(interpolation.predict(i, bssid)?.0))
                }
                None => return None,
            };
            Some(PlanCell {
                area: &c.area,
                level: c.level,
                colour,
            })
        })
        .collect();
    // The access point's place is unknown to the map: mark the cell that hears it
    // strongest (with at least two readings where possible).
    let strongest = map
        .cells
        .iter()
        .filter_map(|c| Some((c, c.radio.aps.get(bssid)?)))
        .filter_map(|(c, s)| Some((c, s.mean()?, s.n)))
        .max_by(|a, b| (a.2 >= 2).cmp(&(b.2 >= 2)).then(a.1.total_cmp(&b.1)));
    let markers = strongest
        .and_then(|(c, mean, _)| {
            let p = c.area.centroid()?;
            Some(PlanMarker {
                x: p.x(),
                y: p.y(),
                level: c.level,
                label: format!("strongest: {mean:.0} dBm"),
            })
        })
        .into_iter()
        .collect();
    PlanPicture {
        plan,
        title: Some(if interpolation.is_some() {
            format!("{bssid}: mean RSSI (paler: predicted)")
        } else {
            format!("{bssid}: mean RSSI per cell")
        }),
        paths: Vec::new(),
        points: Vec::new(),
        cells: heat,
        markers,
        north_up,
        colour_bar: Some(ColourBar {
            low: format!("{HEATMAP_FLOOR} dBm"),
            high: format!("{HEATMAP_TOP} dBm"),
            colour: viridis_rgb,
        }),
    }
}

/// `rgb` halfway to white: a predicted value beside measured ones.
fn paler(rgb: [u8; 3]) -> [u8; 3] {
    rgb.map(|v| v + (255 - v) / 2)
}

/// Says how many access points got a heatmap, when not all of them did.
pub(super) fn print_heatmaps(drawn: usize, map: &RadioMap) {
    let heard = map.access_points().len();
    if drawn < heard {
        info!(
            "heatmaps: {drawn} of the {heard} access points (those heard in the most cells; \
             --heatmaps all for every one)"
        );
    }
}

/// The heatmap file of access point `bssid`: `heatmap-` and the BSSID with every character
/// but letters, digits, `-` and `_` written as `-` (`02:00:00:00:00:03` →
/// `heatmap-02-00-00-00-00-03.png`), at most 64 of them.
pub(super) fn heatmap_name(bssid: &str) -> String {
    let safe: String = bssid
        .chars()
        .take(64)
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '-'
            }
        })
        .collect();
    format!("heatmap-{safe}.png")
}

/// `radiomap.png`: the radio map's cells coloured by the scans taken in them (log scale),
/// over `plan`: where the map knows the radio field and how well.
fn write_coverage_png(
    path: &std::path::Path,
    plan: &FloorPlan,
    map: &RadioMap,
    (north_up, config): (bool, &PlanPictureConfig),
) -> Result<()> {
    let most = map.cells.iter().map(|c| c.radio.scans).max().unwrap_or(0);
    let cells: Vec<PlanCell> = map
        .cells
        .iter()
        .filter(|c| c.radio.scans > 0)
        .map(|c| {
            let t = if most > 1 {
                f64::from(c.radio.scans).ln() / f64::from(most).ln()
            } else {
                1.0
            };
            PlanCell {
                area: &c.area,
                level: c.level,
                colour: viridis_rgb(t),
            }
        })
        .collect();
    let covered = cells.len();
    let picture = PlanPicture {
        plan,
        title: Some(format!(
            "radio map: {covered} of {} cells with scans, {} access points",
            map.cells.len(),
            map.access_points().len()
        )),
        paths: Vec::new(),
        points: Vec::new(),
        cells,
        markers: Vec::new(),
        north_up,
        colour_bar: (most > 1).then(|| ColourBar {
            low: "1 scan".into(),
            high: format!("{most} scans"),
            colour: viridis_rgb,
        }),
    };
    write_plan_png(path, &[picture], config)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{heatmap_name, heatmap_picture, paler};
    use footslam::filter::FingerprintConfig;
    use footslam::map::{CellRadio, FloorPlan, RadioMap, RadioMapCell};
    use footslam::model::{InterpolationConfig, RadioInterpolation};
    use footslam::sensor::WifiScan;

    #[test]
    fn heatmaps_show_predicted_cells_paler_and_unknown_ones_blank() {
        // A corridor of 3 m cells along x, surveyed at both ends (cells 0–2 and 6–8) by one
        // access point that fades along it; cells 3–5 in the gap, cell 40 far away.
        let cells: Vec<RadioMapCell> = (0..9)
            .chain([40])
            .map(|i| {
                let x = 3.0 * f64::from(i) + 1.5;
                let mut radio = CellRadio::default();
                if !(3..=5).contains(&i) && i < 40 {
                    for k in 0..3 {
                        let rssi = -40.0 - 1.5 * x + f64::from(k);
                        radio.add_scan(&WifiScan::from_readings(0.0, &[("ap", rssi)]));
                    }
                }
                let area = geo::Rect::new((x - 1.5, 0.0), (x + 1.5, 3.0))
                    .to_polygon()
                    .into();
                RadioMapCell {
                    id: format!("0-{i}-0"),
                    level: 0,
                    area,
                    radio,
                }
            })
            .collect();
        let map = RadioMap {
            cells,
            ..Default::default()
        };
        let plan = FloorPlan::default();
        // Six cells are too few to fit a kernel: it is given.
        let fp = FingerprintConfig::default();
        let kernel = InterpolationConfig {
            length_scale: Some(20.0),
            noise_ratio: Some(0.1),
            ..fp.interpolation
        };
        let interpolation = RadioInterpolation::new(&map, fp.missing_rssi, fp.min_scans, &kernel)
            .expect("interpolation");
        let measured = heatmap_picture(&plan, &map, None, "ap", true);
        assert_eq!(measured.cells.len(), 6, "the surveyed cells only");
        let picture = heatmap_picture(&plan, &map, Some(&interpolation), "ap", true);
        // The gap's three cells are added, paler than any surveyed cell's colour would be
        // (each channel at least halfway to white); the far cell stays blank.
        assert_eq!(picture.cells.len(), 9);
        let gap: Vec<_> = picture
            .cells
            .iter()
            .filter(|c| {
                let x = geo::Centroid::centroid(c.area).expect("centre").x();
                (9.0..18.0).contains(&x)
            })
            .collect();
        assert_eq!(gap.len(), 3);
        assert!(
            gap.iter().all(|c| c.colour.iter().all(|&v| v >= 127)),
            "{:?}",
            gap[0].colour
        );
        assert_eq!(paler([0, 100, 255]), [127, 177, 255]);
    }

    #[test]
    fn heatmaps_are_named_by_bssid() {
        assert_eq!(
            heatmap_name("02:00:00:00:00:03"),
            "heatmap-02-00-00-00-00-03.png"
        );
        assert_eq!(heatmap_name("a/b\\c d"), "heatmap-a-b-c-d.png");
        assert_eq!(
            heatmap_name(&"x".repeat(100)).len(),
            "heatmap-.png".len() + 64
        );
    }
}
