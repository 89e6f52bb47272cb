//! Reading a GeoJSON FeatureCollection file, with the file and line named in errors.

use crate::error::{Error, Result};
use geojson::FeatureCollection;
use std::path::Path;

/// Reads `path` as an RFC 7946 FeatureCollection.
pub fn read_feature_collection(path: &Path) -> Result<FeatureCollection> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text).map_err(|e| {
        Error::parse(
            path,
            e.line(),
            format!("not a GeoJSON FeatureCollection: {e}"),
        )
    })
}
