//! WiFi scans: the access points a receiver heard at one time and how strongly (RSSI, dBm).

use serde::{Deserialize, Serialize};

/// Weakest RSSI accepted, dBm (below any receiver's sensitivity).
pub const MIN_RSSI: f64 = -120.0;
/// Strongest RSSI accepted, dBm (a receiver touching the access point).
pub const MAX_RSSI: f64 = 0.0;

/// An access point and where it is: the radio world's truth (the simulator places them; a
/// survey of real access points may know them too).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AccessPoint {
    /// Its BSSID (the simulator's are locally administered MAC addresses).
    pub bssid: String,
    /// East, metres.
    pub x: f64,
    /// North, metres.
    pub y: f64,
    /// Floor level.
    pub level: i32,
}

/// One access point heard in a scan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WifiReading {
    /// The access point's BSSID (MAC addresses normalised to lower case).
    pub bssid: String,
    /// Received signal strength, dBm, in [`MIN_RSSI`, `MAX_RSSI`].
    pub rssi: f64,
    /// Network name, when logged.
    pub ssid: Option<String>,
    /// Channel frequency, MHz, when logged.
    pub freq: Option<f64>,
}

/// The readings of one scan, at one time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WifiScan {
    /// Time of the scan, seconds, on the step trace's clock.
    pub t: f64,
    /// The access points heard, each at most once.
    pub readings: Vec<WifiReading>,
}

impl WifiScan {
    /// A scan at `t` of `(bssid, rssi)` readings without SSID or frequency (BSSIDs as given:
    /// no normalisation, no checks — for data already validated, and for tests).
    #[must_use]
    pub fn from_readings(t: f64, readings: &[(&str, f64)]) -> Self {
        Self {
            t,
            readings: readings
                .iter()
                .map(|&(bssid, rssi)| WifiReading {
                    bssid: bssid.into(),
                    rssi,
                    ssid: None,
                    freq: None,
                })
                .collect(),
        }
    }

    /// The RSSI of `bssid` in this scan, if it was heard.
    #[must_use]
    pub fn rssi(&self, bssid: &str) -> Option<f64> {
        self.readings
            .iter()
            .find(|r| r.bssid == bssid)
            .map(|r| r.rssi)
    }
}

/// A BSSID as stored: trimmed, and lower case when it is a MAC address (`aa:bb:..`), so that
/// logs from different tools agree. `None` when empty or holding a comma or quote.
#[must_use]
pub fn normalise_bssid(raw: &str) -> Option<String> {
    let b = raw.trim();
    if b.is_empty() || b.contains([',', '"']) {
        return None;
    }
    let is_mac = b.len() == 17
        && b.split([':', '-'])
            .all(|part| part.len() == 2 && part.chars().all(|c| c.is_ascii_hexdigit()));
    Some(if is_mac {
        b.to_ascii_lowercase().replace('-', ":")
    } else {
        b.to_string()
    })
}

/// Why a reading is implausible, if it is.
///
/// # Errors
///
/// A message naming the value and the rule when the RSSI is not within [[`MIN_RSSI`],
/// [`MAX_RSSI`]] dBm, or a frequency is given outside 100–100 000 MHz.
pub fn check_reading(reading: &WifiReading) -> Result<(), String> {
    if !(reading.rssi.is_finite() && (MIN_RSSI..=MAX_RSSI).contains(&reading.rssi)) {
        return Err(format!(
            "rssi {} dBm is outside [{MIN_RSSI}, {MAX_RSSI}] dBm",
            crate::error::short_number(reading.rssi)
        ));
    }
    if let Some(f) = reading.freq
        && !(f.is_finite() && (100.0..=100_000.0).contains(&f))
    {
        return Err(format!("freq {f} MHz is not a WiFi channel frequency"));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bssids_normalise_and_readings_validate() {
        assert_eq!(
            normalise_bssid(" AA-bb-CC-dd-EE-ff ").as_deref(),
            Some("aa:bb:cc:dd:ee:ff")
        );
        assert_eq!(normalise_bssid("ap-7").as_deref(), Some("ap-7"));
        assert_eq!(normalise_bssid("  "), None);
        let mut r = WifiReading {
            bssid: "ap".into(),
            rssi: -70.0,
            ssid: None,
            freq: Some(2412.0),
        };
        assert!(check_reading(&r).is_ok());
        r.rssi = 5.0;
        assert!(check_reading(&r).is_err());
        r.rssi = f64::NAN;
        assert!(check_reading(&r).is_err());
        r.rssi = -60.0;
        r.freq = Some(-1.0);
        assert!(check_reading(&r).is_err());
        let scan = WifiScan {
            t: 1.0,
            readings: vec![WifiReading { freq: None, ..r }],
        };
        assert_eq!(scan.rssi("ap"), Some(-60.0));
        assert_eq!(scan.rssi("other"), None);
    }
}
