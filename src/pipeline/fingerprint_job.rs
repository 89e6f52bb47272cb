//! The `fingerprint` job, request in, report out: each WiFi scan placed by the radio map
//! alone (weighted k-nearest fingerprints), the baseline that tracking with the radio map
//! should beat.

use super::Progress;
use super::job_checks::{check_scans_match, warn_duplicate_readings};
use super::named::Named;
use crate::error::{Error, Result};
use crate::filter::{FingerprintConfig, FingerprintFix, NearestFingerprint};
use crate::map::RadioMap;
use crate::sensor::WifiScan;
use serde::Serialize;

/// Everything `fingerprint` runs on, read and parsed by a face.
#[derive(Debug, Clone)]
pub struct FingerprintRequest {
    /// The radio map.
    pub map: Named<RadioMap>,
    /// The WiFi log's scans, in time order.
    pub wifi: Named<Vec<WifiScan>>,
    /// Rows of the log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
    /// The configuration file's (or the defaults).
    pub config: FingerprintConfig,
    /// `k`, the nearest cells averaged, over the configuration's.
    pub k: Option<usize>,
}

/// `summary.json` of `fingerprint`.
#[derive(Debug, Clone, Serialize)]
pub struct FingerprintReport {
    /// The radio map's name.
    pub radiomap_file: String,
    /// The WiFi log's name.
    pub wifi_file: String,
    /// Scans in the log.
    pub scans: usize,
    /// Rows of the WiFi log that repeated an access point within a scan (the later kept).
    pub duplicate_readings: usize,
    /// Scans placed.
    pub placed: usize,
    /// Scans that share no access point with the map.
    pub unplaced: usize,
    /// The method used (`auto` resolved).
    pub method: crate::filter::FingerprintMethod,
    /// The interpolated map's kernel, fitted on the map's survey (method `interpolated`).
    pub interpolation: Option<crate::model::VariogramFit>,
    /// The path-loss model's fit on the map's survey (method `pathloss`).
    pub pathloss: Option<crate::model::PathLossSummary>,
    /// The toolkit's version.
    pub version: &'static str,
}

/// What [`run_fingerprint`] gives.
#[derive(Debug, Clone)]
pub struct FingerprintJob {
    /// The configuration run, `k` applied.
    pub config: FingerprintConfig,
    /// One place per scan placed, in time order.
    pub fixes: Vec<FingerprintFix>,
    /// Its report.
    pub report: FingerprintReport,
}

/// A radio map made ready to place scans ([`NearestFingerprint`]): for one log
/// ([`run_fingerprint`]) or, prepared once, for the logs of many walks.
#[derive(Debug)]
pub struct PreparedFingerprint {
    map: Named<RadioMap>,
    localiser: NearestFingerprint,
    config: FingerprintConfig,
}

impl PreparedFingerprint {
    /// Prepares `map` with `config` (`k` over the configuration's).
    ///
    /// # Errors
    ///
    /// [`Error::Config`] when the configuration (with its `k`) is out of range;
    /// [`Error::NotEnough`] when no cell of the map holds scans.
    pub fn new(map: Named<RadioMap>, config: FingerprintConfig, k: Option<usize>) -> Result<Self> {
        let mut config = config;
        if let Some(k) = k {
            config.k = k;
        }
        let localiser = NearestFingerprint::new(&map.value, &config)?;
        Ok(Self {
            map,
            localiser,
            config,
        })
    }

    /// The configuration in use (`k` applied).
    #[must_use]
    pub fn config(&self) -> &FingerprintConfig {
        &self.config
    }

    /// Places each scan of `wifi` by the radio map alone, with a warning to `progress` when
    /// most scans hear none of the map's access points (and when `duplicate_readings` rows
    /// repeated an access point within a scan).
    ///
    /// # Errors
    ///
    /// [`Error::Mismatch`] when no scan of the log hears an access point of the map, or none
    /// shares enough of them to be placed (another building?).
    pub fn place(
        &self,
        wifi: &Named<Vec<WifiScan>>,
        duplicate_readings: usize,
        progress: &dyn Progress,
    ) -> Result<FingerprintJob> {
        let (map, localiser) = (&self.map, &self.localiser);
        warn_duplicate_readings(&wifi.label, duplicate_readings, progress);
        check_scans_match(
            &Named::new(&map.value, map.label.as_str()),
            &Named::new(wifi.value.as_slice(), wifi.label.as_str()),
            progress,
        )?;
        let fixes: Vec<FingerprintFix> = wifi
            .value
            .iter()
            .filter_map(|s| localiser.locate(s))
            .collect();
        if fixes.is_empty() {
            return Err(Error::mismatch(
                format!(
                    "none of the {} scans of {} shares enough access points with the radio map {}",
                    wifi.value.len(),
                    wifi.label,
                    map.label
                ),
                "is it the same building?",
            ));
        }
        let report = FingerprintReport {
            radiomap_file: map.label.clone(),
            wifi_file: wifi.label.clone(),
            scans: wifi.value.len(),
            duplicate_readings,
            placed: fixes.len(),
            unplaced: wifi.value.len() - fixes.len(),
            method: localiser.method(),
            interpolation: localiser.interpolation_fit(),
            pathloss: localiser.pathloss_summary(),
            version: env!("CARGO_PKG_VERSION"),
        };
        Ok(FingerprintJob {
            config: self.config.clone(),
            fixes,
            report,
        })
    }
}

/// Places each scan of the request by the radio map alone ([`PreparedFingerprint`]).
///
/// # Errors
///
/// As [`PreparedFingerprint::new`] and [`PreparedFingerprint::place`].
pub fn run_fingerprint(
    request: FingerprintRequest,
    progress: &dyn Progress,
) -> Result<FingerprintJob> {
    PreparedFingerprint::new(request.map, request.config, request.k)?.place(
        &request.wifi,
        request.duplicate_readings,
        progress,
    )
}
