//! GNSS position fixes (the absolute anchor of the outdoor–indoor–outdoor walks of Robertson
//! et al. 2009, sec. 4.1–4.2).

use serde::{Deserialize, Serialize};

/// Default horizontal accuracy of a fix that does not state one, metres (1σ).
pub const DEFAULT_ACCURACY: f64 = 5.0;
/// Largest accepted stated accuracy, metres: a fix worse than this carries no information.
pub const MAX_ACCURACY: f64 = 1000.0;

/// One position fix on the steps' clock.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GpsFix {
    /// Time of the fix, seconds on the steps' clock.
    pub t: f64,
    /// WGS84 latitude, degrees.
    pub lat: f64,
    /// WGS84 longitude, degrees.
    pub lon: f64,
    /// Horizontal accuracy, metres (1σ of each horizontal coordinate).
    pub accuracy: f64,
}

/// Why a fix is implausible, if it is.
///
/// # Errors
///
/// A message naming the value and the rule when a value is not finite, the latitude is beyond ±90°
/// or within 1° of a pole, the longitude beyond ±180°, the fix is the receiver's (0°, 0°) "no fix",
/// the accuracy outside (0, [`MAX_ACCURACY`]] m, or the time not after `previous_t`.
pub fn check_fix(fix: &GpsFix, previous_t: Option<f64>) -> Result<(), String> {
    if ![fix.t, fix.lat, fix.lon, fix.accuracy]
        .iter()
        .all(|v| v.is_finite())
    {
        return Err("values must be finite numbers (found NaN or infinity)".into());
    }
    if fix.lat.abs() > 90.0 {
        return Err(format!(
            "latitude {}° is outside [-90, 90]",
            crate::error::short_number(fix.lat)
        ));
    }
    let polar = crate::geometry::local_frame::MAX_ORIGIN_LATITUDE;
    if fix.lat.abs() > polar {
        return Err(format!(
            "latitude {}° is within {}° of a pole, where a local east-north frame is undefined",
            fix.lat,
            90.0 - polar
        ));
    }
    if fix.lon.abs() > 180.0 {
        return Err(format!(
            "longitude {}° is outside [-180, 180]",
            crate::error::short_number(fix.lon)
        ));
    }
    if fix.lat == 0.0 && fix.lon == 0.0 {
        return Err(
            "latitude 0°, longitude 0° is a receiver's \"no fix\" value, not a place: \
             remove such rows"
                .into(),
        );
    }
    if !(fix.accuracy > 0.0 && fix.accuracy <= MAX_ACCURACY) {
        return Err(format!(
            "accuracy {} m is outside (0, {MAX_ACCURACY}] m",
            crate::error::short_number(fix.accuracy)
        ));
    }
    if let Some(p) = previous_t
        && fix.t <= p
    {
        return Err(format!(
            "time {} s is not after the previous fix's {} s (times must be strictly increasing)",
            fix.t, p
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn implausible_fixes_are_explained() {
        let ok = GpsFix {
            t: 1.0,
            lat: 48.0,
            lon: 11.0,
            accuracy: 5.0,
        };
        assert!(check_fix(&ok, Some(0.5)).is_ok());
        assert!(check_fix(&ok, Some(1.0)).is_err_and(|m| m.contains("increasing")));
        assert!(
            check_fix(&GpsFix { lat: 91.0, ..ok }, None).is_err_and(|m| m.contains("latitude"))
        );
        assert!(check_fix(&GpsFix { lon: -181.0, ..ok }, None).is_err());
        assert!(
            check_fix(
                &GpsFix {
                    accuracy: 0.0,
                    ..ok
                },
                None
            )
            .is_err()
        );
        assert!(check_fix(&GpsFix { t: f64::NAN, ..ok }, None).is_err());
        let null_island = GpsFix {
            lat: 0.0,
            lon: 0.0,
            ..ok
        };
        assert!(check_fix(&null_island, None).is_err_and(|m| m.contains("no fix")));
    }
}
