//! A track moved from its run's local frame into another (the truth's), through WGS84: runs
//! anchored to the world (`learn --gps`) put their origin at the first fix, not where the
//! simulator put the truth's.

use crate::geometry::LocalFrame;
use crate::io::TimedPoint;

/// Moves `points` (local metres of `from`) into the local metres of `to`, in place.
pub fn reproject(points: &mut [TimedPoint], from: &LocalFrame, to: &LocalFrame) {
    for p in points {
        let (lon, lat) = from.to_lon_lat(p.x, p.y);
        (p.x, p.y) = to.to_local(lon, lat);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_keeps_its_place_on_the_globe() {
        let from = LocalFrame::new(48.1, 11.5).expect("frame");
        let to = LocalFrame::new(48.1001, 11.5).expect("frame");
        let mut points = [TimedPoint {
            t: 1.0,
            x: 3.0,
            y: 4.0,
        }];
        reproject(&mut points, &from, &to);
        // `to` lies about 11.1 m north of `from`.
        assert!((points[0].x - 3.0).abs() < 1e-3, "{points:?}");
        assert!((points[0].y - (4.0 - 11.12)).abs() < 0.05, "{points:?}");
        assert_eq!(points[0].t, 1.0);
    }
}
