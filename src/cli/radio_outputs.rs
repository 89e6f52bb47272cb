//! The files of a radio map, written alike by `survey` (on a drawn plan) and `learn --wifi`
//! (on the plan learned from the walks): `radiomap.geojson`, `radiomap.csv` and one heatmap
//! per access point.

use anyhow::Result;
use footslam::geometry::LocalFrame;
use footslam::io::RunFolder;
use footslam::io::radio_map_geojson::{write_radio_map_csv, write_radio_map_geojson};
use footslam::map::{FloorPlan, RadioMap};
use footslam::render::plan_png::{
    ColourBar, PlanCell, PlanMarker, PlanPicture, PlanPictureConfig, viridis_rgb, write_plan_png,
};
use geo::Centroid;

/// Heatmap colours run from this RSSI (dark) to [`HEATMAP_TOP`] (bright), dBm.
const HEATMAP_FLOOR: f64 = -96.0;
/// The brightest heatmap colour, dBm.
const HEATMAP_TOP: f64 = -30.0;

/// Writes `{prefix}radiomap.geojson`, `{prefix}radiomap.csv` and `{prefix}heatmap-NNN.png`
/// (mean RSSI per cell of access point `NNN`, in the order of
/// [`RadioMap::access_points`], over `plan`).
pub(super) fn write_radio_map_files(
    folder: &RunFolder,
    prefix: &str,
    plan: &FloorPlan,
    map: &RadioMap,
    frame: &LocalFrame,
) -> Result<()> {
    let at = |name: &str| folder.path(&format!("{prefix}{name}"));
    write_radio_map_geojson(&at("radiomap.geojson"), map, frame)?;
    write_radio_map_csv(&at("radiomap.csv"), map)?;
    for (i, &bssid) in map.access_points().iter().enumerate() {
        let heat: Vec<PlanCell> = map
            .cells
            .iter()
            .filter_map(|c| {
                let mean = c.radio.aps.get(bssid)?.mean()?;
                let t = ((mean - HEATMAP_FLOOR) / (HEATMAP_TOP - HEATMAP_FLOOR)).clamp(0.0, 1.0);
                Some(PlanCell {
                    area: &c.area,
                    level: c.level,
                    colour: viridis_rgb(t),
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
        let picture = PlanPicture {
            plan,
            title: Some(format!("{bssid}: mean RSSI per cell")),
            paths: Vec::new(),
            points: Vec::new(),
            cells: heat,
            markers,
            colour_bar: Some(ColourBar {
                low: format!("{HEATMAP_FLOOR} dBm"),
                high: format!("{HEATMAP_TOP} dBm"),
                colour: viridis_rgb,
            }),
        };
        write_plan_png(
            &at(&format!("heatmap-{i:03}.png")),
            &[picture],
            &PlanPictureConfig::default(),
        )?;
    }
    Ok(())
}
