"""footslam: building maps from pedestrians' walks.

FootSLAM (maps and paths learned from step events alone), tracking on known floor
plans, and WiFi radio surveys — the pipelines of the ``footslam`` command line over
numpy arrays, pandas DataFrames or files.

* :func:`steps` — raw IMU recording (foot or phone) → step events
* :func:`learn` — FootSLAM on one walk or a batch (GPS, outline, prior map, WiFi)
* :func:`learn_one`, :func:`others_map`, :func:`feetslam_passes` — a batch fanned out
  walk by walk (the same maps and paths as :func:`learn`)
* :func:`merge` — maps of several walks combined
* :func:`plan` — a learned map as a floor plan and occupancy grids
* :func:`radio_map` — the radio map of walks learned apart, on their merged map's plan
* :mod:`footslam.batch` — buildings × walks on a Dask cluster
* :func:`track` — one walk on a known floor plan
* :func:`survey` — a WiFi radio map from walks on a known plan
* :func:`fingerprint` — each WiFi scan placed by a radio map alone

Tables are returned as dicts of 1-D numpy arrays (``pandas.DataFrame(result["track"])``),
maps and plans as GeoJSON dicts (``geopandas.GeoDataFrame.from_features(result["map"])``).
Local frame: metres, x east, y north; headings in radians counter-clockwise from east.
The same inputs and seed give the command line's results. Errors raise
:class:`FootslamError` (a ``ValueError``) with the command line's message.
"""

from ._footslam import (
    FootslamError,
    FootslamWarning,
    __version__,
    feetslam_passes,
    fingerprint,
    learn,
    learn_one,
    merge,
    others_map,
    plan,
    radio_map,
    steps,
    survey,
    track,
)

__all__ = [
    "FootslamError",
    "FootslamWarning",
    "__version__",
    "feetslam_passes",
    "fingerprint",
    "learn",
    "learn_one",
    "merge",
    "others_map",
    "plan",
    "radio_map",
    "steps",
    "survey",
    "track",
]
