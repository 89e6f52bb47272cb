//! The local frame (x east, y north, metres) placed on the WGS84 globe at an origin.
//!
//! Uses the local tangent-plane approximation with the ellipsoid's meridional and
//! prime-vertical radii of curvature at the origin: errors stay below a millimetre within
//! 100 m of the origin and a few centimetres within a kilometre, far below hexagon sizes.

use serde::{Deserialize, Serialize};

const WGS84_A: f64 = 6_378_137.0;
const WGS84_E2: f64 = 6.694_379_990_14e-3;

/// A local east-north frame anchored at a WGS84 latitude/longitude (degrees).
///
/// Local metres to WGS84 degrees and back:
///
/// ```
/// use footslam::geometry::LocalFrame;
///
/// let frame = LocalFrame::new(48.15, 11.57).expect("a valid origin");
/// // 100 m east and 50 m south of the origin, to (lon, lat) and back.
/// let (lon, lat) = frame.to_lon_lat(100.0, -50.0);
/// assert!(lon > 11.57 && lat < 48.15);
/// let (x, y) = frame.to_local(lon, lat);
/// assert!((x - 100.0).abs() < 1e-6 && (y + 50.0).abs() < 1e-6);
/// // A degree of latitude is about 111 km.
/// let (_, north) = frame.to_local(11.57, 49.15);
/// assert!((north - 111_200.0).abs() < 300.0);
/// // At a pole east and north are undefined.
/// assert!(LocalFrame::new(90.0, 0.0).is_none());
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LocalFrame {
    /// Latitude of the origin, degrees.
    pub lat: f64,
    /// Longitude of the origin, degrees.
    pub lon: f64,
}

impl Default for LocalFrame {
    /// The default origin (0°, 0°): maps still export as valid GeoJSON; pass `--origin` to
    /// place them on the building.
    fn default() -> Self {
        Self { lat: 0.0, lon: 0.0 }
    }
}

/// The farthest an origin may lie from the equator, degrees: at the poles east and north
/// are undefined, and within a degree of them a local frame's maps would reach over the
/// pole.
pub const MAX_ORIGIN_LATITUDE: f64 = 89.0;

/// `lon` degrees wrapped into [-180, 180] (unchanged, to the bit, when already there).
fn wrap_longitude(lon: f64) -> f64 {
    if (-180.0..=180.0).contains(&lon) {
        lon
    } else {
        (lon + 180.0).rem_euclid(360.0) - 180.0
    }
}

impl LocalFrame {
    /// A frame at `lat`, `lon` (degrees); `None` unless both are finite, the latitude within
    /// ±[`MAX_ORIGIN_LATITUDE`] and the longitude within ±180.
    #[must_use]
    pub fn new(lat: f64, lon: f64) -> Option<Self> {
        (lat.is_finite()
            && lon.is_finite()
            && lat.abs() <= MAX_ORIGIN_LATITUDE
            && lon.abs() <= 180.0)
            .then_some(Self { lat, lon })
    }

    /// Metres per radian of latitude and of longitude at the origin.
    fn radii(&self) -> (f64, f64) {
        let phi = self.lat.to_radians();
        let s2 = phi.sin().powi(2);
        let w = (1.0 - WGS84_E2 * s2).sqrt();
        let meridional = WGS84_A * (1.0 - WGS84_E2) / (w * w * w);
        let prime_vertical = WGS84_A / w;
        (meridional, prime_vertical * phi.cos())
    }

    /// Local (x east, y north) metres to (lon, lat) degrees.
    #[must_use]
    pub fn to_lon_lat(&self, x: f64, y: f64) -> (f64, f64) {
        let (m, n) = self.radii();
        let lat = self.lat + (y / m).to_degrees();
        let lon = if n > 0.0 {
            self.lon + (x / n).to_degrees()
        } else {
            self.lon
        };
        // Across the antimeridian the longitude wraps, so every output is a WGS84 position
        // the readers accept (and read back to the same local point).
        (wrap_longitude(lon), lat.clamp(-90.0, 90.0))
    }

    /// Distance in metres between this origin and `other`'s, measured in this frame.
    #[must_use]
    pub fn distance_to(&self, other: &LocalFrame) -> f64 {
        let (x, y) = self.to_local(other.lon, other.lat);
        x.hypot(y)
    }

    /// (lon, lat) degrees to local (x east, y north) metres.
    #[must_use]
    pub fn to_local(&self, lon: f64, lat: f64) -> (f64, f64) {
        let (m, n) = self.radii();
        (
            wrap_longitude(lon - self.lon).to_radians() * n,
            (lat - self.lat).to_radians() * m,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_scales() {
        let f = LocalFrame::new(48.0, 11.0).expect("valid");
        let (lon, lat) = f.to_lon_lat(100.0, -50.0);
        let (x, y) = f.to_local(lon, lat);
        assert!((x - 100.0).abs() < 1e-9 && (y + 50.0).abs() < 1e-9);
        // One degree of latitude is about 111.2 km at 48°.
        let (_, y1) = f.to_local(11.0, 49.0);
        assert!((y1 - 111_200.0).abs() < 200.0, "{y1}");
        assert!(LocalFrame::new(f64::NAN, 0.0).is_none());
        assert!(LocalFrame::new(91.0, 0.0).is_none());
        assert!(LocalFrame::new(89.5, 0.0).is_none());
        // Near the antimeridian, outputs stay in range and read back.
        let east = LocalFrame::new(-16.5, 179.9995).expect("Fiji");
        let (lon, lat) = east.to_lon_lat(200.0, 0.0);
        assert!((-180.0..=180.0).contains(&lon) && lon < -179.99, "{lon}");
        let (x, y) = east.to_local(lon, lat);
        assert!((x - 200.0).abs() < 1e-6 && y.abs() < 1e-6, "{x} {y}");
    }
}
