use super::*;
use crate::map::{FloorPolygon, HexCell};
use crate::render::canvas::{INK, PATH_RED, START_GREEN};
use geo::{LineString, Polygon};
use hexx::Hex;
use std::collections::BTreeMap;

fn empty_map() -> HexMapSnapshot {
    HexMapSnapshot {
        radius: 0.5,
        alpha: 0.8,
        cells: Vec::new(),
        levels: Vec::new(),
    }
}

/// Counts the edge crossings of `path` as FootSLAM does (both hexagons of each crossing).
fn map_of(path: &[(f64, f64)], radius: f64) -> HexMapSnapshot {
    let grid = HexGrid::new(radius);
    let mut counts: BTreeMap<(i32, i32), [u32; 6]> = BTreeMap::new();
    for w in path.windows(2) {
        grid.for_each_crossing(w[0], w[1], |c| {
            counts.entry((c.from.x, c.from.y)).or_default()[usize::from(c.edge)] += 1;
            counts.entry((c.to.x, c.to.y)).or_default()[usize::from((c.edge + 3) % 6)] += 1;
        });
    }
    let cells = counts
        .into_iter()
        .map(|((x, y), counts)| HexCell {
            hex: Hex { x, y },
            counts,
            level: 0,
        })
        .collect();
    HexMapSnapshot {
        radius,
        alpha: 0.8,
        cells,
        levels: Vec::new(),
    }
}

fn decode(png: &[u8]) -> image::RgbaImage {
    image::load_from_memory_with_format(png, image::ImageFormat::Png)
        .expect("valid PNG")
        .to_rgba8()
}

fn near(p: &image::Rgba<u8>, c: ColorU8, tol: i32) -> bool {
    [c.red(), c.green(), c.blue()]
        .iter()
        .zip(p.0)
        .all(|(&a, b)| (i32::from(a) - i32::from(b)).abs() <= tol)
}

#[test]
fn picture_has_the_expected_size() {
    let path = [(0.0, 0.0), (40.0, 0.0), (40.0, 10.0)];
    let map = empty_map();
    let config = PictureConfig::default();
    let png = render_map_png(&MapPicture::new(&map, &path), &config).expect("render");
    let img = decode(&png);
    // 40 m × 10 m at 20 px/m, 40 px margins; the legend strip below the map, and one row
    // of key (path, start, end: 14 px of text and 10 px of spacing).
    assert_eq!(img.width(), 800 + 80);
    let expect_h = (40.0 + 200.0 + 20.0 + legend_height(2) + 24.0 + 20.0) as u32;
    assert_eq!(img.height(), expect_h);
}

#[test]
fn path_pixels_have_the_path_colour() {
    let path: Vec<(f64, f64)> = vec![(0.0, 0.0), (12.0, 0.0), (12.0, 6.0), (3.0, 9.0)];
    let map = map_of(&path, 0.5);
    let picture = MapPicture::new(&map, &path);
    let config = PictureConfig::default();
    let img = decode(&render_map_png(&picture, &config).expect("render"));
    let layout = Layout::new(&picture, &config, &picture.key());
    for w in path.windows(2) {
        for f in [0.3, 0.5, 0.7] {
            let p = (
                w[0].0 + f * (w[1].0 - w[0].0),
                w[0].1 + f * (w[1].1 - w[0].1),
            );
            let (x, y) = layout.pixel(p);
            let pixel = img.get_pixel(x as u32, y as u32);
            assert!(near(pixel, PATH_RED, 8), "{p:?} at ({x}, {y}) is {pixel:?}");
        }
    }
    // Hexagons away from the path are coloured (not white) inside the map.
    assert!(map.cells.len() > 20);
}

#[test]
fn a_broken_path_draws_no_line_across_the_break() {
    // Two runs on one floor, (0,0)–(12,0) and (12,6)–(3,9): the walk left the floor
    // between them, so nothing is drawn from (12,0) to (12,6).
    let path: Vec<(f64, f64)> = vec![(0.0, 0.0), (12.0, 0.0), (12.0, 6.0), (3.0, 9.0)];
    let map = empty_map();
    let picture = MapPicture {
        path_breaks: &[2],
        ..MapPicture::new(&map, &path)
    };
    let config = PictureConfig::default();
    let img = decode(&render_map_png(&picture, &config).expect("render"));
    let layout = Layout::new(&picture, &config, &picture.key());
    let at = |p: (f64, f64)| {
        let (x, y) = layout.pixel(p);
        *img.get_pixel(x as u32, y as u32)
    };
    assert!(near(&at((6.0, 0.0)), PATH_RED, 8));
    assert!(near(&at((7.5, 7.5)), PATH_RED, 8));
    assert!(
        !near(&at((12.0, 3.0)), PATH_RED, 60),
        "{:?}",
        at((12.0, 3.0))
    );
}

#[test]
fn north_is_up() {
    let path = [(0.0, 0.0), (0.0, 10.0)];
    let map = empty_map();
    let picture = MapPicture::new(&map, &path);
    let config = PictureConfig::default();
    let img = decode(&render_map_png(&picture, &config).expect("render"));
    let layout = Layout::new(&picture, &config, &picture.key());
    let (sx, sy) = layout.pixel(path[0]);
    let (ex, ey) = layout.pixel(path[1]);
    assert!(sy > ey, "the start (south) must be below the end (north)");
    assert!(near(img.get_pixel(sx as u32, sy as u32), START_GREEN, 8));
    assert!(near(img.get_pixel(ex as u32, ey as u32), INK, 8));
}

#[test]
fn empty_map_gives_a_small_valid_picture() {
    let map = empty_map();
    let config = PictureConfig {
        shading: Shading::Probability,
        ..PictureConfig::default()
    };
    let img = decode(&render_map_png(&MapPicture::new(&map, &[]), &config).expect("render"));
    assert!(img.width() <= 1000 && img.height() <= 1000 && img.height() > 100);
}

#[test]
fn huge_extent_is_capped() {
    let path = [(0.0, 0.0), (10_000.0, 5_000.0)];
    let map = empty_map();
    let img = decode(
        &render_map_png(&MapPicture::new(&map, &path), &PictureConfig::default()).expect("render"),
    );
    assert_eq!(img.width(), 4000);
    assert!(img.height() <= 4000);
}

#[test]
fn bad_input_is_refused() {
    let map = empty_map();
    let config = PictureConfig {
        pixels_per_metre: 0.0,
        ..PictureConfig::default()
    };
    let err = render_map_png(&MapPicture::new(&map, &[]), &config).expect_err("must fail");
    assert!(err.to_string().contains("pixels_per_metre"), "{err}");
    let path = [(0.0, 0.0), (f64::NAN, 1.0)];
    let err = render_map_png(&MapPicture::new(&map, &path), &PictureConfig::default())
        .expect_err("must fail");
    assert!(err.to_string().contains("path point 1"), "{err}");
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> LineString<f64> {
    LineString::from(vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)])
}

/// Renders a full picture (plan, truth, drifting estimate) in both shadings and writes it
/// atomically; set `FOOTSLAM_SAMPLE_PNG_DIR` to keep the files for looking at.
#[test]
fn writes_sample_pictures() {
    let dir = tempfile::tempdir().expect("tempdir");
    let keep = std::env::var_os("FOOTSLAM_SAMPLE_PNG_DIR").map(std::path::PathBuf::from);
    let out = keep.as_deref().unwrap_or(dir.path());
    let corners: [(f64, f64); 7] = [
        (0.0, 0.0),
        (20.0, 0.0),
        (20.0, 10.0),
        (8.0, 10.0),
        (8.0, 14.0),
        (8.0, 10.0),
        (0.0, 10.0),
    ];
    let mut truth = Vec::new();
    for lap in 0..3 {
        for i in 0..corners.len() {
            let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
            let n = (b.0 - a.0).hypot(b.1 - a.1).div_euclid(0.7).max(1.0) as usize;
            for k in 0..n {
                let f = k as f64 / n as f64;
                let wobble = 0.15 * (f64::from(lap) + 0.3 * truth.len() as f64).sin();
                truth.push((
                    a.0 + f * (b.0 - a.0) + wobble,
                    a.1 + f * (b.1 - a.1) - wobble,
                ));
            }
        }
    }
    // The estimate drifts: a slow rotation and offset growing along the walk.
    let estimate: Vec<(f64, f64)> = truth
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| {
            let a = 0.0004 * i as f64;
            (
                x * a.cos() - y * a.sin() + 0.003 * i as f64,
                x * a.sin() + y * a.cos(),
            )
        })
        .collect();
    let map = map_of(&estimate, 0.5);
    let corridor = Polygon::new(
        rect(-1.5, -1.5, 21.5, 11.5),
        vec![rect(1.5, 1.5, 18.5, 8.5)],
    );
    let room = Polygon::new(rect(6.0, 11.5, 10.0, 15.5), vec![]);
    let plan = FloorPlan {
        barriers: Vec::new(),
        polygons: [corridor, room]
            .into_iter()
            .map(|polygon| FloorPolygon {
                polygon,
                level: 0,
                z: 0.0,
                name: None,
                room: None,
            })
            .collect(),
    };
    let picture = MapPicture {
        truth: Some(&truth),
        plan: Some(&plan),
        ..MapPicture::new(&map, &estimate)
    };
    write_map_png(
        &out.join("footslam_sample_map.png"),
        &picture,
        &PictureConfig::default(),
    )
    .expect("write");
    let config = PictureConfig {
        shading: Shading::Probability,
        ..PictureConfig::default()
    };
    write_map_png(&out.join("footslam_sample_map_p.png"), &picture, &config).expect("write");
    for name in ["footslam_sample_map.png", "footslam_sample_map_p.png"] {
        let img = image::open(out.join(name)).expect("decodes");
        assert!(img.width() > 300 && img.height() > 200);
    }
}

#[test]
fn a_north_arrow_only_where_the_frame_is_absolute() {
    let path = [(0.0, 0.0), (20.0, 0.0), (20.0, 10.0)];
    let map = map_of(&path, 0.5);
    let config = PictureConfig::default();
    let relative = decode(&render_map_png(&MapPicture::new(&map, &path), &config).expect("render"));
    let picture = MapPicture {
        north_up: true,
        ..MapPicture::new(&map, &path)
    };
    let absolute = decode(&render_map_png(&picture, &config).expect("render"));
    assert_eq!(relative.dimensions(), absolute.dimensions());
    // They differ only at the arrow: right of the colour bar, in the legend strip.
    let layout = Layout::new(&picture, &config, &picture.key());
    let arrow_left = relative.width() - config.margin_px - 25;
    let mut differ = 0;
    for (x, y, p) in relative.enumerate_pixels() {
        if *p != *absolute.get_pixel(x, y) {
            assert!(
                x >= arrow_left,
                "pixel ({x}, {y}) differs left of the arrow"
            );
            assert!(
                f64::from(y) >= layout.legend_top,
                "pixel ({x}, {y}) above the legend"
            );
            differ += 1;
        }
    }
    assert!(differ > 50, "the arrow drew {differ} pixels");
}

#[test]
fn one_visit_everywhere_gives_no_degenerate_colour_bar() {
    let map = map_of(&[(0.0, 0.0), (3.0, 0.0)], 0.5);
    let (_, _, scale) = shading_values(&map, Shading::Visits);
    assert_eq!(scale, ColourScale::Uniform("1 visit each".into()));
}

#[test]
fn a_given_extent_crops_the_picture_and_nothing_is_drawn_outside_it() {
    let path = [(0.0, 0.0), (40.0, 0.0), (40.0, 30.0)];
    let map = map_of(&path, 0.5);
    let picture = MapPicture::new(&map, &path);
    let config = PictureConfig {
        extent: Some([30.0, -5.0, 50.0, 5.0]),
        ..PictureConfig::default()
    };
    let layout = Layout::new(&picture, &config, &picture.key());
    assert!(layout.cropped);
    assert!((layout.map_width - 20.0 * layout.scale).abs() < 1e-9);
    assert!((layout.map_height - 10.0 * layout.scale).abs() < 1e-9);
    let img = decode(&render_map_png(&picture, &config).expect("render"));
    // Above the map and left of it, only white and the thin frame: no path, no hexagons.
    let (left, top) = (layout.left as u32, layout.top as u32);
    for (x, y, p) in img.enumerate_pixels() {
        if y + 2 < top || (x + 2 < left && f64::from(y) < layout.legend_top) {
            assert!(
                near(p, WHITE, 0),
                "pixel ({x}, {y}) outside the map is {p:?}"
            );
        }
    }
    // The part shown holds the path (the corner at 40, 0).
    let (cx, cy) = layout.pixel((40.0, 0.0));
    let red = (-3..=3)
        .flat_map(|dx| (-3..=3).map(move |dy| (dx, dy)))
        .any(|(dx, dy)| {
            let p = img.get_pixel((cx as i32 + dx) as u32, (cy as i32 + dy) as u32);
            near(p, PATH_RED, 40)
        });
    assert!(red, "the path's corner is in the picture");
}

#[test]
fn an_outline_is_cut_to_the_walk_and_the_default_picture_is_not_cropped() {
    let path = [(0.0, 0.0), (10.0, 0.0)];
    let map = map_of(&path, 0.5);
    let plain = MapPicture::new(&map, &path);
    let config = PictureConfig::default();
    assert!(!Layout::new(&plain, &config, &plain.key()).cropped);
    let mall = Polygon::new(
        LineString::from(vec![
            (-100.0, -100.0),
            (140.0, -100.0),
            (140.0, 100.0),
            (-100.0, 100.0),
        ]),
        Vec::new(),
    );
    let picture = MapPicture {
        outline: Some(&mall),
        ..MapPicture::new(&map, &path)
    };
    let (x0, y0, x1, y1) = extent(&picture, 10.0).expect("something drawn");
    assert!(
        (-11.0..=-10.0).contains(&x0) && (20.0..=21.0).contains(&x1),
        "{x0} {x1}"
    );
    assert!(
        (-11.0..=-10.0).contains(&y0) && (10.0..=11.0).contains(&y1),
        "{y0} {y1}"
    );
    assert!(Layout::new(&picture, &config, &picture.key()).cropped);
    let everything = extent(&picture, f64::INFINITY).expect("something drawn");
    assert_eq!(everything, (-100.0, -100.0, 140.0, 100.0));
}

#[test]
fn a_bad_extent_is_refused_by_name() {
    for extent in [
        [5.0, 0.0, 1.0, 1.0],
        [0.0, 0.0, f64::NAN, 1.0],
        [0.0, 3.0, 1.0, 3.0],
    ] {
        let config = PictureConfig {
            extent: Some(extent),
            ..PictureConfig::default()
        };
        let err = config.validate().expect_err("refused").to_string();
        assert!(err.contains("picture.extent"), "{err}");
    }
}
