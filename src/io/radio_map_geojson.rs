//! Radio maps as RFC 7946 GeoJSON (`radiomap.geojson`) and long-format CSV (`radiomap.csv`),
//! and back from GeoJSON — written by this crate or by another tool with the same properties
//! and any cell polygons.
//!
//! One `Polygon` or `MultiPolygon` feature per cell, in WGS84 (exterior rings
//! counter-clockwise, no `crs` member), with properties `cell` (id), `level`, `scans` and
//! `aps`: `{bssid: {"n": readings, "mean": dBm, "hist": {"<dBm>": count}}}`. The collection's
//! foreign member `origin` (`{"lat", "lon"}`) names the local frame; `epsilon` and
//! `epsilon_sqrt`, where known, are the region thresholds calibrated on the survey for the
//! paper's distance and for the one divided by `√k` ([`crate::model::wifi_distance`]).
//!
//! The CSV has one row per cell and access point: `cell,level,bssid,n,mean,std,misses`
//! (`misses` = scans of the cell that did not hear the access point).

use crate::error::{Error, Result};
use crate::geometry::LocalFrame;
use crate::io::floor_plan_geojson::{polygon_positions, read_polygon};
use crate::io::geojson_file::{collection_frame, origin_member};
use crate::map::{ApStats, CellRadio, RadioMap, RadioMapCell};
use geo::MultiPolygon;
use geojson::{Feature, FeatureCollection, Geometry, GeometryValue, JsonObject, JsonValue};
use serde_json::json;
use std::collections::BTreeMap;

/// Largest region threshold a radio map may carry, dBm (as `rf.epsilon`).
const MAX_EPSILON: f64 = 200.0;
use std::path::Path;

/// The map as a feature collection placed on the globe by `frame`.
#[must_use]
pub fn radio_map_to_geojson(map: &RadioMap, frame: &LocalFrame) -> FeatureCollection {
    let features = map
        .cells
        .iter()
        .map(|cell| {
            let polygons: Vec<_> = cell
                .area
                .0
                .iter()
                .map(|p| polygon_positions(p, frame))
                .collect();
            let geometry = if polygons.len() == 1 {
                GeometryValue::new_polygon(polygons.into_iter().next().unwrap_or_default())
            } else {
                GeometryValue::new_multi_polygon(polygons)
            };
            let aps: serde_json::Map<String, JsonValue> = cell
                .radio
                .aps
                .iter()
                .map(|(bssid, s)| {
                    let hist: serde_json::Map<String, JsonValue> = s
                        .hist
                        .iter()
                        .map(|(bin, count)| (bin.to_string(), json!(count)))
                        .collect();
                    let mean = s.mean().map(|m| (m * 100.0).round() / 100.0);
                    (
                        bssid.clone(),
                        json!({ "n": s.n, "mean": mean, "hist": hist }),
                    )
                })
                .collect();
            let mut properties = JsonObject::new();
            properties.insert("cell".into(), json!(cell.id));
            properties.insert("level".into(), json!(cell.level));
            properties.insert("scans".into(), json!(cell.radio.scans));
            properties.insert("aps".into(), JsonValue::Object(aps));
            Feature {
                bbox: None,
                geometry: Some(Geometry::new(geometry)),
                id: None,
                properties: Some(properties),
                foreign_members: None,
            }
        })
        .collect();
    let mut members = origin_member(frame);
    for (name, e) in [("epsilon", map.epsilon), ("epsilon_sqrt", map.epsilon_sqrt)] {
        if let Some(e) = e {
            members.insert(name.into(), json!((e * 1000.0).round() / 1000.0));
        }
    }
    FeatureCollection {
        bbox: None,
        features,
        foreign_members: Some(members),
    }
}

/// Writes [`radio_map_to_geojson`] to `path` atomically.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as [`write_geojson`](crate::io::write_geojson);
/// an existing file is then left as it was.
pub fn write_radio_map_geojson(path: &Path, map: &RadioMap, frame: &LocalFrame) -> Result<()> {
    super::write_geojson(path, &radio_map_to_geojson(map, frame))
}

/// Writes the long-format CSV: `cell,level,bssid,n,mean,std,misses`.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be written, as
/// [`write_atomically`](crate::io::write_atomically); an existing file is then left as it was.
pub fn write_radio_map_csv(path: &Path, map: &RadioMap) -> Result<()> {
    let mut text = String::from("cell,level,bssid,n,mean,std,misses\n");
    for cell in &map.cells {
        for (bssid, s) in &cell.radio.aps {
            let (Some(mean), Some(std)) = (s.mean(), s.std()) else {
                continue;
            };
            text.push_str(&format!(
                "{},{},{},{},{:.2},{:.2},{}\n",
                cell.id,
                cell.level,
                bssid,
                s.n,
                mean,
                std,
                cell.radio.misses(bssid)
            ));
        }
    }
    super::write_atomically(path, text.as_bytes())
}

/// Reads a radio map and its frame: `origin` when given (it overrides the file's), else the
/// file's `origin` member, else an error. Errors name the file and feature.
///
/// # Errors
///
/// [`Error::Io`] when `path` cannot be read; [`Error::Parse`] naming the line when it is not a
/// GeoJSON `FeatureCollection`, else naming the file (and the feature):
/// * no frame: no `origin` given and no valid `origin` member;
/// * a geometry that is not a Polygon or `MultiPolygon` of closed rings of at least 4 finite
///   positions in range, or a `cell`, `level` or `scans` property missing or malformed;
/// * an access point whose `n` exceeds the cell's `scans`, whose `mean` is not in
///   [-120, 0] dBm, or whose `hist` has a bin that is not such an RSSI or counts that do not
///   add up to `n`;
/// * a cell id given twice, or an `epsilon` or `epsilon_sqrt` outside (0, 200] dBm.
pub fn read_radio_map_geojson(
    path: &Path,
    origin: Option<LocalFrame>,
) -> Result<(RadioMap, LocalFrame)> {
    let collection = crate::io::geojson_file::read_feature_collection(path)?;
    radio_map_from_collection(&collection, path, origin)
}

/// Reads a radio map from GeoJSON `text` (the format of `radiomap.geojson`), as
/// [`read_radio_map_geojson`] reads a file; errors name `name`.
///
/// # Errors
///
/// As [`read_radio_map_geojson`], naming `name`, except that there is no file to read.
pub fn radio_map_from_str(
    text: &str,
    name: &str,
    origin: Option<LocalFrame>,
) -> Result<(RadioMap, LocalFrame)> {
    let path = Path::new(name);
    let collection = crate::io::geojson_file::feature_collection_from_str(text, path)?;
    radio_map_from_collection(&collection, path, origin)
}

/// A radio map from a parsed collection; errors name `path`.
fn radio_map_from_collection(
    collection: &FeatureCollection,
    path: &Path,
    origin: Option<LocalFrame>,
) -> Result<(RadioMap, LocalFrame)> {
    let whole = |message: String| Error::parse(path, 0, message);
    let frame = collection_frame(path, collection, origin)?;
    let mut cells = Vec::with_capacity(collection.features.len());
    for (i, feature) in collection.features.iter().enumerate() {
        cells.push(read_cell(feature, &frame).map_err(|m| whole(format!("feature {i}: {m}")))?);
    }
    let mut ids: Vec<&str> = cells.iter().map(|c: &RadioMapCell| c.id.as_str()).collect();
    ids.sort_unstable();
    if let Some(w) = ids.windows(2).find(|w| w[0] == w[1]) {
        return Err(whole(format!("cell `{}` appears twice", w[0])));
    }
    let threshold = |name: &str| match collection
        .foreign_members
        .as_ref()
        .and_then(|m| m.get(name))
    {
        None | Some(JsonValue::Null) => Ok(None),
        Some(v) => v
            .as_f64()
            .filter(|e| e.is_finite() && *e > 0.0 && *e <= MAX_EPSILON)
            .map(Some)
            .ok_or_else(|| {
                whole(format!(
                    "member `{name}` = {v} is not a threshold in (0, {MAX_EPSILON}] dBm"
                ))
            }),
    };
    Ok((
        RadioMap {
            cells,
            epsilon: threshold("epsilon")?,
            epsilon_sqrt: threshold("epsilon_sqrt")?,
        },
        frame,
    ))
}

fn read_cell(feature: &Feature, frame: &LocalFrame) -> Result<RadioMapCell, String> {
    let polygons = match feature.geometry.as_ref().map(|g| &g.value) {
        Some(GeometryValue::Polygon { coordinates }) => vec![coordinates],
        Some(GeometryValue::MultiPolygon { coordinates }) => coordinates.iter().collect(),
        _ => return Err("geometry must be a Polygon or MultiPolygon".into()),
    };
    let area = MultiPolygon::new(
        polygons
            .into_iter()
            .map(|rings| read_polygon(rings, frame))
            .collect::<Result<_, _>>()?,
    );
    let id = match feature.property("cell") {
        Some(JsonValue::String(s)) => s.clone(),
        Some(JsonValue::Number(n)) => n.to_string(),
        _ => return Err("property `cell` (the cell id) is missing".into()),
    };
    let level = match feature.property("level") {
        None | Some(JsonValue::Null) => {
            return Err(
                "property `level` (the cell's floor) is missing: add `\"level\": 0` on a \
                 one-floor plan, else the cell's floor as the plan numbers it"
                    .into(),
            );
        }
        Some(v) => v
            .as_i64()
            .and_then(|l| i32::try_from(l).ok())
            .ok_or_else(|| format!("property `level` = {v} is not an integer"))?,
    };
    let scans = feature
        .property("scans")
        .and_then(JsonValue::as_u64)
        .and_then(|s| u32::try_from(s).ok())
        .ok_or("property `scans` must be a whole number")?;
    let mut aps = BTreeMap::new();
    if let Some(v) = feature.property("aps") {
        let object = v.as_object().ok_or("property `aps` must be an object")?;
        for (bssid, stats) in object {
            let s = read_ap(stats).map_err(|m| format!("aps.{bssid}: {m}"))?;
            if s.n > scans {
                return Err(format!(
                    "aps.{bssid}: n = {} exceeds the cell's {scans} scans",
                    s.n
                ));
            }
            aps.insert(bssid.clone(), s);
        }
    }
    Ok(RadioMapCell {
        id,
        level,
        area,
        radio: CellRadio { scans, aps },
    })
}

/// One access point's statistics: `n` and `mean` (required), `hist` (optional; when present
/// its counts must add up to `n`, and it gives the spread).
fn read_ap(stats: &JsonValue) -> Result<ApStats, String> {
    let n = stats
        .get("n")
        .and_then(JsonValue::as_u64)
        .and_then(|n| u32::try_from(n).ok())
        .ok_or("`n` must be a whole number")?;
    let mean = stats.get("mean").and_then(JsonValue::as_f64);
    let mean = match (n, mean) {
        (0, _) => 0.0,
        (_, Some(m)) if m.is_finite() && (-120.0..=0.0).contains(&m) => m,
        _ => return Err("`mean` must be an RSSI in [-120, 0] dBm".into()),
    };
    let mut hist = BTreeMap::new();
    if let Some(h) = stats.get("hist") {
        let object = h.as_object().ok_or("`hist` must be an object")?;
        for (bin, count) in object {
            let bin: i32 = bin
                .trim()
                .parse()
                .map_err(|_| format!("`hist` bin `{bin}` is not a whole dBm"))?;
            if !(-120..=0).contains(&bin) {
                return Err(format!(
                    "`hist` bin {bin} dBm is not an RSSI in [-120, 0] dBm"
                ));
            }
            let count = count
                .as_u64()
                .and_then(|c| u32::try_from(c).ok())
                .ok_or_else(|| format!("`hist` count for {bin} dBm is not a whole number"))?;
            hist.insert(bin, count);
        }
        let total: u64 = hist.values().map(|&c| u64::from(c)).sum();
        if total != u64::from(n) {
            return Err(format!("`hist` counts add up to {total}, not n = {n}"));
        }
    }
    // Second moment from the histogram when there is one (1 dB bins), else no spread.
    let sum_sq = if hist.is_empty() {
        f64::from(n) * mean * mean
    } else {
        let binned_mean = hist
            .iter()
            .map(|(&b, &c)| f64::from(b) * f64::from(c))
            .sum::<f64>()
            / f64::from(n.max(1));
        let var: f64 = hist
            .iter()
            .map(|(&b, &c)| f64::from(c) * (f64::from(b) - binned_mean).powi(2))
            .sum::<f64>()
            / f64::from(n.max(1));
        f64::from(n) * (var + mean * mean)
    };
    Ok(ApStats {
        n,
        sum: mean * f64::from(n),
        sum_sq,
        hist,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::{CellMap, FloorTopology};
    use crate::sensor::{WifiReading, WifiScan};

    fn map() -> RadioMap {
        let tower = crate::sim::Tower::new(&Default::default()).expect("tower");
        let topology = FloorTopology::build(&tower.plan, &Default::default()).expect("topology");
        let cells = CellMap::build(&tower.plan, &topology, &Default::default()).expect("cells");
        let mut map = RadioMap::empty(&cells);
        for (i, rssi) in [-60.0, -62.0, -61.0].into_iter().enumerate() {
            map.cells[3].radio.add_scan(&WifiScan {
                t: i as f64,
                readings: vec![WifiReading {
                    bssid: "02:00:00:00:00:01".into(),
                    rssi,
                    ssid: None,
                    freq: None,
                }],
            });
        }
        map.cells[3].radio.add_scan(&WifiScan {
            t: 9.0,
            readings: Vec::new(),
        });
        map
    }

    #[test]
    fn round_trips_through_geojson_and_writes_csv() {
        let map = map();
        let frame = LocalFrame::new(52.2, 0.09).expect("frame");
        let dir = tempfile::tempdir().expect("tmp");
        let p = dir.path().join("radiomap.geojson");
        write_radio_map_geojson(&p, &map, &frame).expect("write");
        let text = std::fs::read_to_string(&p).expect("read");
        assert!(!text.contains("\"crs\""));
        assert!(text.contains(r#""hist":{"-60":1,"-61":1,"-62":1}"#));
        let (back, f) = read_radio_map_geojson(&p, None).expect("read back");
        assert_eq!(f, frame);
        assert_eq!(back.cells.len(), map.cells.len());
        let (a, b) = (&map.cells[3], &back.cells[3]);
        assert_eq!(
            (a.id.as_str(), a.level, a.radio.scans),
            (b.id.as_str(), b.level, b.radio.scans)
        );
        let (sa, sb) = (
            &a.radio.aps["02:00:00:00:00:01"],
            &b.radio.aps["02:00:00:00:00:01"],
        );
        assert_eq!((sa.n, &sa.hist), (sb.n, &sb.hist));
        assert!((sa.mean().expect("m") - sb.mean().expect("m")).abs() < 0.01);
        assert!((sa.std().expect("s") - sb.std().expect("s")).abs() < 0.01);
        let area = |c: &RadioMapCell| geo::Area::unsigned_area(&c.area);
        assert!((area(a) - area(b)).abs() < 1e-3 * area(a));
        let csv = dir.path().join("radiomap.csv");
        write_radio_map_csv(&csv, &map).expect("csv");
        let text = std::fs::read_to_string(&csv).expect("read");
        assert_eq!(text.lines().count(), 2);
        assert!(
            text.lines()
                .nth(1)
                .expect("row")
                .ends_with(",3,-61.00,0.82,1"),
            "{text}"
        );
    }

    #[test]
    fn maps_from_other_tools_are_checked() {
        let dir = tempfile::tempdir().expect("tmp");
        let p = dir.path().join("r.geojson");
        let square = "[[[0.09,52.2],[0.0901,52.2],[0.0901,52.2001],[0.09,52.2001],[0.09,52.2]]]";
        let feature = |props: &str| {
            format!(
                r#"{{"type":"FeatureCollection","origin":{{"lat":52.2,"lon":0.09}},"features":[{{"type":"Feature","properties":{props},"geometry":{{"type":"Polygon","coordinates":{square}}}}}]}}"#
            )
        };
        std::fs::write(
            &p,
            feature(r#"{"cell":"A","level":0,"scans":4,"aps":{"x":{"n":2,"mean":-70}}}"#),
        )
        .expect("write");
        let (map, _) = read_radio_map_geojson(&p, None).expect("no hist is fine");
        assert_eq!(map.cells[0].radio.misses("x"), 2);
        for (props, expected) in [
            (r#"{"scans":4,"level":0}"#, "`cell`"),
            (
                r#"{"cell":"A","scans":4,"aps":{"x":{"n":2,"mean":-70}}}"#,
                "`level`",
            ),
            (
                r#"{"cell":"A","level":0,"scans":4,"aps":{"x":{"n":1,"mean":-70,"hist":{"30":1}}}}"#,
                "bin 30 dBm",
            ),
            (
                r#"{"cell":"A","level":0,"scans":1,"aps":{"x":{"n":2,"mean":-70}}}"#,
                "exceeds",
            ),
            (
                r#"{"cell":"A","level":0,"scans":4,"aps":{"x":{"n":2,"mean":10}}}"#,
                "`mean`",
            ),
            (
                r#"{"cell":"A","level":0,"scans":4,"aps":{"x":{"n":2,"mean":-70,"hist":{"-70":1}}}}"#,
                "add up to 1",
            ),
        ] {
            std::fs::write(&p, feature(props)).expect("write");
            let e = read_radio_map_geojson(&p, None)
                .expect_err(props)
                .to_string();
            assert!(e.contains("r.geojson") && e.contains(expected), "{e}");
        }
    }
}
