//! The picture's colours and drawing primitives on a `tiny_skia` pixmap.

use tiny_skia::{
    ColorU8, FillRule, LineCap, LineJoin, Paint, Path, PathBuilder, Pixmap, Rect, Stroke,
    StrokeDash, Transform,
};

/// The estimated path.
pub const PATH_RED: ColorU8 = rgb(178, 24, 43);
/// The true path.
pub const TRUTH_BLUE: ColorU8 = rgb(33, 102, 172);
/// The start marker.
pub const START_GREEN: ColorU8 = rgb(26, 152, 80);
/// Text, the end marker, legend outlines.
pub const INK: ColorU8 = rgb(30, 30, 30);
/// Walkable floor.
pub const PLAN_FILL: ColorU8 = rgb(232, 232, 232);
/// Walls (outlines of floor polygons).
pub const PLAN_WALL: ColorU8 = rgb(70, 70, 70);
/// Halos and the light half of the scale bar.
pub const WHITE: ColorU8 = rgb(255, 255, 255);

/// An opaque colour.
pub const fn rgb(r: u8, g: u8, b: u8) -> ColorU8 {
    ColorU8::from_rgba(r, g, b, 255)
}

/// Viridis (van der Walt & Smith 2015) sampled at nine evenly spaced stops.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 45, 123],
    [59, 82, 139],
    [44, 114, 142],
    [33, 145, 140],
    [40, 174, 128],
    [94, 201, 98],
    [173, 220, 48],
    [253, 231, 37],
];

/// Viridis at `t` in [0, 1] (clamped), linearly interpolated between stops.
pub fn viridis(t: f64) -> ColorU8 {
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + f * (f64::from(b) - f64::from(a))).round() as u8;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    rgb(mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2]))
}

fn paint(color: ColorU8) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color_rgba8(color.red(), color.green(), color.blue(), color.alpha());
    paint.anti_alias = true;
    paint
}

/// Fills `path` with `color` (anti-aliased).
pub fn fill(pixmap: &mut Pixmap, path: &Path, color: ColorU8, rule: FillRule) {
    pixmap.fill_path(path, &paint(color), rule, Transform::identity(), None);
}

/// Strokes `path` with round caps and joins, `width` pixels wide.
pub fn stroke(
    pixmap: &mut Pixmap,
    path: &Path,
    color: ColorU8,
    width: f32,
    dash: Option<StrokeDash>,
) {
    let stroke = Stroke {
        width,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        dash,
        ..Stroke::default()
    };
    pixmap.stroke_path(path, &paint(color), &stroke, Transform::identity(), None);
}

/// Appends a closed polygon through `points` (pixels) to `pb`.
pub fn push_ring(pb: &mut PathBuilder, points: impl IntoIterator<Item = (f32, f32)>) {
    let mut points = points.into_iter();
    if let Some((x, y)) = points.next() {
        pb.move_to(x, y);
        points.for_each(|(x, y)| pb.line_to(x, y));
        pb.close();
    }
}

/// An open polyline through `points` (pixels); `None` for fewer than two points.
pub fn polyline(points: impl IntoIterator<Item = (f32, f32)>) -> Option<Path> {
    let mut pb = PathBuilder::new();
    let mut points = points.into_iter();
    let (x, y) = points.next()?;
    pb.move_to(x, y);
    points.for_each(|(x, y)| pb.line_to(x, y));
    pb.finish()
}

/// Longest polyline stroked at once: tiny-skia's stroker holds a few hundred bytes a
/// point, so a day-long walk is stroked in pieces that share their end points.
pub const MAX_STROKE_POINTS: usize = 8192;

/// The open polylines through `points` (pixels), in pieces of at most
/// [`MAX_STROKE_POINTS`] that share their ends (one piece when shorter).
pub fn polyline_pieces(points: &[(f32, f32)]) -> impl Iterator<Item = Path> + '_ {
    let step = MAX_STROKE_POINTS - 1;
    (0..points.len().saturating_sub(1))
        .step_by(step)
        .filter_map(move |start| {
            let end = (start + MAX_STROKE_POINTS).min(points.len());
            polyline(points[start..end].iter().copied())
        })
}

/// The rectangle `x, y, w, h` (pixels) as a path; `None` when empty or not finite.
pub fn rect(x: f32, y: f32, w: f32, h: f32) -> Option<Path> {
    Rect::from_xywh(x, y, w, h).map(PathBuilder::from_rect)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_polylines_come_in_pieces_sharing_their_ends() {
        assert_eq!(polyline_pieces(&[]).count(), 0);
        assert_eq!(polyline_pieces(&[(1.0, 1.0)]).count(), 0);
        let short: Vec<(f32, f32)> = (0..100).map(|i| (i as f32, 0.0)).collect();
        assert_eq!(polyline_pieces(&short).count(), 1);
        let n = 2 * MAX_STROKE_POINTS + 5;
        let long: Vec<(f32, f32)> = (0..n).map(|i| (i as f32 * 0.01, 1.0)).collect();
        let pieces: Vec<Path> = polyline_pieces(&long).collect();
        assert_eq!(pieces.len(), 3);
        let points: usize = pieces.iter().map(Path::len).sum();
        assert_eq!(points, n + pieces.len() - 1, "neighbours share one point");
    }

    #[test]
    fn viridis_ends_and_clamps() {
        assert_eq!(viridis(0.0), rgb(68, 1, 84));
        assert_eq!(viridis(1.0), rgb(253, 231, 37));
        assert_eq!(viridis(0.5), rgb(33, 145, 140));
        assert_eq!(viridis(-3.0), viridis(0.0));
        assert_eq!(viridis(7.0), viridis(1.0));
    }
}
