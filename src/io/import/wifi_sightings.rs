//! One scan's sightings as phone logs give them: Android hands out cached results, so a
//! scan may hold readings last seen long before it (stale) and an access point twice. The
//! importers keep each BSSID's most recently seen reading and drop the stale ones.

use crate::sensor::WifiReading;

/// What [`fresh_readings`] dropped, summed over scans.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DroppedSightings {
    /// Readings last seen more than the allowed age before the reference time.
    pub stale: usize,
    /// Second sightings of a BSSID within one scan.
    pub duplicates: usize,
}

/// The readings of one scan, each BSSID once (its most recently seen reading), without those
/// last seen more than `max_age` before `reference` (`seen` and `reference` on one clock and
/// in `max_age`'s unit; a reading without a last-seen time is never stale).
pub fn fresh_readings(
    sightings: Vec<(WifiReading, Option<f64>)>,
    reference: f64,
    max_age: f64,
    dropped: &mut DroppedSightings,
) -> Vec<WifiReading> {
    let mut kept: Vec<(WifiReading, Option<f64>)> = Vec::with_capacity(sightings.len());
    for (reading, seen) in sightings {
        if seen.is_some_and(|s| reference - s > max_age) {
            dropped.stale += 1;
            continue;
        }
        match kept.iter_mut().find(|(r, _)| r.bssid == reading.bssid) {
            Some(slot) => {
                dropped.duplicates += 1;
                if seen > slot.1 {
                    *slot = (reading, seen);
                }
            }
            None => kept.push((reading, seen)),
        }
    }
    kept.into_iter().map(|(r, _)| r).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(bssid: &str, rssi: f64) -> WifiReading {
        WifiReading {
            bssid: bssid.into(),
            rssi,
            ssid: None,
            freq: None,
        }
    }

    #[test]
    fn keeps_the_freshest_sighting_and_drops_stale_ones() {
        let mut dropped = DroppedSightings::default();
        let kept = fresh_readings(
            vec![
                (reading("a", -60.0), Some(9.0)),
                (reading("a", -50.0), Some(9.5)),
                (reading("b", -70.0), Some(5.0)),
                (reading("c", -80.0), None),
            ],
            10.0,
            2.5,
            &mut dropped,
        );
        assert_eq!(kept, vec![reading("a", -50.0), reading("c", -80.0)]);
        assert_eq!(
            dropped,
            DroppedSightings {
                stale: 1,
                duplicates: 1
            }
        );
    }
}
