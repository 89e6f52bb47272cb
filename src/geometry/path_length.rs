//! The length of a polyline.

/// Length of the polyline through `points`, metres (0 for fewer than two points).
pub fn path_length(points: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    let mut points = points.into_iter();
    let Some(mut last) = points.next() else {
        return 0.0;
    };
    points
        .map(|p| {
            let d = (p.0 - last.0).hypot(p.1 - last.1);
            last = p;
            d
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_add_up() {
        assert_eq!(path_length([]), 0.0);
        assert_eq!(path_length([(1.0, 1.0)]), 0.0);
        assert_eq!(path_length([(0.0, 0.0), (3.0, 4.0), (3.0, 5.0)]), 6.0);
    }
}
