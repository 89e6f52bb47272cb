//! Layer 5: pictures (PNG, drawn with `tiny-skia`), each written atomically through
//! [`crate::io::write_atomically`].
//!
//! * [`map_png`] — a learned hexagon map with paths, plan and legend
//! * [`plan_picture`] — what a plan picture holds, and its settings
//! * [`plan_png`] — multi-floor plans with paths, particle clouds, cells and heatmaps
//! * [`plan_marks`] — labelled markers and colour bars on plan pictures
//! * `plan_layout` — which part of the floor a plan picture shows, and its panels
//! * `key` — the legend strip's parts: key of lines and marks, scale bar, north arrow
//! * `canvas` — colours and drawing primitives shared by the pictures
//! * `glyphs` — a tiny bitmap font for labels

mod canvas;
mod glyphs;
mod key;
pub mod map_png;
mod plan_layout;
pub mod plan_marks;
pub mod plan_picture;
pub mod plan_png;
