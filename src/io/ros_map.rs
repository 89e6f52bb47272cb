//! An occupancy grid as a ROS map: `map.pgm` (8-bit binary PGM, written with the `image`
//! crate) and `map.yaml` in the `map_server` / Nav2 convention that `map_saver` writes.
//!
//! Pixels: free 254, occupied 0, unknown 205, the first row the grid's northern edge. With
//! `negate: 0` a reader turns a pixel `p` into the occupancy `(255 − p) / 255` — 0.004 free,
//! 1 occupied, 0.196 unknown — and classes it against `occupied_thresh: 0.65` and
//! `free_thresh: 0.196` (`mode: trinary`). `origin` is the pose of the south-west corner of
//! the first (bottom-left) pixel in the plan's local frame: metres east and north of the
//! plan's `origin`, yaw 0.

use super::write_atomically;
use crate::error::{Error, Result};
use crate::map::{Occupancy, OccupancyGrid};
use image::ExtendedColorType;
use image::codecs::pnm::{PnmEncoder, PnmSubtype, SampleEncoding};
use std::path::Path;

/// Pixel value of a free square.
pub const FREE: u8 = 254;
/// Pixel value of an occupied square.
pub const OCCUPIED: u8 = 0;
/// Pixel value of an unknown square.
pub const UNKNOWN: u8 = 205;

/// The PGM bytes of `grid`.
///
/// # Errors
///
/// [`Error::TooLarge`] when the grid is wider or taller than `u32::MAX` squares. (The
/// encoder's [`Error::Encode`] cannot occur: the pixels always match the dimensions.)
///
/// # Panics
///
/// When `grid.cells` holds fewer than `width × height` squares.
pub fn encode_pgm(grid: &OccupancyGrid) -> Result<Vec<u8>> {
    let mut pixels = Vec::with_capacity(grid.width * grid.height);
    for row in (0..grid.height).rev() {
        pixels.extend(
            grid.cells[row * grid.width..][..grid.width]
                .iter()
                .map(|c| match c {
                    Occupancy::Free => FREE,
                    Occupancy::Occupied => OCCUPIED,
                    Occupancy::Unknown => UNKNOWN,
                }),
        );
    }
    let mut bytes = Vec::new();
    let (w, h) = (
        u32::try_from(grid.width)
            .map_err(|_| Error::too_large("an occupancy grid", grid.width, u32::MAX, ""))?,
        u32::try_from(grid.height)
            .map_err(|_| Error::too_large("an occupancy grid", grid.height, u32::MAX, ""))?,
    );
    PnmEncoder::new(&mut bytes)
        .with_subtype(PnmSubtype::Graymap(SampleEncoding::Binary))
        .encode(pixels.as_slice(), w, h, ExtendedColorType::L8)
        .map_err(|e| Error::encode("encode the occupancy grid as PGM", e))?;
    Ok(bytes)
}

/// The `map.yaml` text for `grid` stored in the image file `image` (a name relative to the
/// YAML file).
#[must_use]
pub fn ros_map_yaml(grid: &OccupancyGrid, image: &str) -> String {
    format!(
        "image: {image}\nmode: trinary\nresolution: {}\norigin: [{}, {}, 0.0]\nnegate: 0\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
        grid.resolution, grid.origin.0, grid.origin.1
    )
}

/// Writes `grid` as `pgm` and `yaml` (each completely or not at all); the YAML names the
/// image by its file name, so keep the two side by side.
///
/// # Errors
///
/// [`Error::Output`] when `pgm` has no file name or one that is not UTF-8; as [`encode_pgm`];
/// [`Error::Io`] when either file cannot be written. The PGM is written first and stays when
/// the YAML then fails.
///
/// # Panics
///
/// As [`encode_pgm`]: when `grid.cells` holds fewer than `width × height` squares.
pub fn write_ros_map(pgm: &Path, yaml: &Path, grid: &OccupancyGrid) -> Result<()> {
    let name = pgm
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| Error::output(pgm, "not a file name"))?;
    write_atomically(pgm, &encode_pgm(grid)?)?;
    write_atomically(yaml, ros_map_yaml(grid, name).as_bytes())
}
