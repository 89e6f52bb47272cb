"""Type stubs of footslam's native module (``footslam._footslam``).

Units and frames: seconds; metres in the local frame (x east, y north, placed on the globe
by a WGS84 ``origin``); headings in radians counter-clockwise from east. Tables are dicts
of 1-D numpy arrays, one per column; maps and plans are GeoJSON dicts.
"""

import os
from typing import Any, Callable, Mapping, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

class FootslamError(ValueError):
    """Bad data, a bad configuration or inputs that do not belong together; the message is
    the one the command line prints."""

class FootslamWarning(UserWarning):
    """Something a run found that may make its result wrong (the CLI's ``warning:`` lines)."""

PathLike = Union[str, os.PathLike[str]]
"""A file's path."""
Table = Union[PathLike, Mapping[str, Any], Any]
"""A CSV path, a pandas DataFrame, a dict of 1-D arrays or a numpy structured array."""
GeoJson = Union[PathLike, Mapping[str, Any], Any]
"""A GeoJSON path, a GeoJSON dict, GeoJSON text or an object with ``__geo_interface__``."""
Config = Union[Mapping[str, Any], PathLike, None]
"""A dict with the keys of the command line's config file, or a TOML or JSON file."""
Start = Union[
    str,
    Tuple[float, float],
    Tuple[float, float, Optional[float]],
    Tuple[float, float, Optional[float], Optional[int]],
    Mapping[str, Any],
    None,
]
"""A known start: ``"X,Y[,HEADING[,LEVEL]]"``, ``(x, y[, heading[, level]])`` or a dict."""
FeatureCollection = dict[str, Any]
"""A GeoJSON FeatureCollection (``geopandas.GeoDataFrame.from_features`` reads it)."""
Floats = npt.NDArray[np.float64]
Ints = npt.NDArray[np.int64]
Bools = npt.NDArray[np.bool_]

class StepColumns(TypedDict):
    t: Floats
    """Time of the step, s."""
    length: Floats
    """Step (phone) or stride (foot) length, m."""
    dheading: Floats
    """Heading change since the previous step, rad counter-clockwise."""
    dz: Floats
    """Height change, m."""
    heading: Floats
    """Absolute heading, rad from east (NaN where none)."""

class StepsResult(TypedDict):
    steps: StepColumns
    path: Floats
    """The dead-reckoned ``(n + 1, 3)`` array of ``x, y, z``, m, from the start."""
    summary: dict[str, Any]
    config: dict[str, Any]

class PathColumns(TypedDict):
    t: Floats
    x: Floats
    y: Floats
    z: Floats
    level: Ints

class SmoothedColumns(PathColumns, total=False):
    certain: Bools
    """One hypothesis, no wider than the localisation spread, remains at this step."""
    hypotheses: Ints
    spread: Floats
    """RMS distance of the answer's hypothesis' particles from its position, metres."""
    share: Floats
    """The answer's hypothesis' share of the belief, 0 to 1."""

class LearnedColumns(PathColumns):
    spread_m: Floats
    """How far the averaged final paths spread about the answer at this step, metres."""

class LearnedWalk(TypedDict, total=False):
    track: LearnedColumns
    """The whole-walk answer (the mean of the final paths near the most probable one), one
    row per step."""
    map: FeatureCollection
    """The learned hexagon map, as ``map.geojson``."""
    plan: Optional[FeatureCollection]
    """Its walkable plan, as ``plan.geojson`` (None when too little was walked)."""
    merged_with_prior: FeatureCollection
    """With a prior map: the prior moved into this walk's frame merged with its map."""
    summary: dict[str, Any]
    config: dict[str, Any]

class LearnResult(TypedDict):
    walks: list[LearnedWalk]
    merged: Optional[FeatureCollection]
    """A batch's maps merged (without a prior map)."""
    radio_map: Optional[FeatureCollection]
    """With WiFi: the radio map, as ``radiomap.geojson``."""
    radio_plan: Optional[FeatureCollection]
    """With WiFi: the learned plan the radio map's cells lie on."""
    summary: dict[str, Any]
    """As ``summary.json``."""
    config: dict[str, Any]
    """As ``config.json``."""

class Grid(TypedDict):
    level: int
    resolution: float
    """Side of a square, m."""
    origin: Tuple[float, float]
    """South-west corner of the first square, local metres."""
    occupancy: npt.NDArray[np.int8]
    """``(height, width)``, row 0 the southernmost: 0 free, 100 occupied, -1 unknown."""

class PlanResult(TypedDict):
    plan: FeatureCollection
    grids: list[Grid]
    summary: dict[str, Any]
    config: dict[str, Any]

class StepRecords(TypedDict):
    particles: Ints
    clusters: Ints
    """-1: the step was not clustered."""
    localised: Bools

class TrackResult(TypedDict):
    track: SmoothedColumns
    """The answer: smoothed, one row per step with an estimate (online: the filtered one)."""
    filtered: PathColumns
    """Each step's estimate as the filter saw it, from localisation on."""
    steps: StepRecords
    summary: dict[str, Any]
    config: dict[str, Any]

class CoverageColumns(TypedDict):
    granularity_m: Floats
    cells: Ints
    coverage: Floats
    """Share of the plan's area in cells with a scan."""
    mean_scans: Floats

class SurveyResult(TypedDict):
    radio_map: FeatureCollection
    coverage: CoverageColumns
    walks: list[dict[str, Any]]
    summary: dict[str, Any]
    config: dict[str, Any]

#: ``progress(stage, done, total)``: told of a run's progress (learn, track, survey).
ProgressCallback = Callable[[str, int, int], object]


def steps(
    imu: Table,
    mount: str,
    *,
    config: Config = None,
    accel_unit: str = "m/s2",
    gyro_unit: str = "rad/s",
    gyro_flip: Optional[str] = None,
) -> StepsResult:
    """Detects the steps of a raw IMU recording (``footslam steps``).

    ``imu`` has columns ``t,ax,ay,az,gx,gy,gz`` (s, m/s² with gravity, rad/s) and
    optionally ``mx,my,mz`` (µT), ``qx,qy,qz,qw`` and ``pressure`` (hPa); ``mount`` is
    ``"foot"`` (one event per stride) or ``"phone"`` (one per step).
    """

def learn(
    steps: Union[Table, Sequence[Table]],
    *,
    gps: Union[Table, Sequence[Optional[Table]], None] = None,
    wifi: Union[Table, Sequence[Optional[Table]], None] = None,
    start: Union[Start, Sequence[Start]] = None,
    prior_map: Optional[GeoJson] = None,
    outline: Optional[GeoJson] = None,
    origin: Optional[Tuple[float, float]] = None,
    config: Config = None,
    seed: Optional[int] = None,
    particles: Optional[int] = None,
    hex_radius: Optional[float] = None,
    prior_weight: Optional[float] = None,
    ignore_heading: bool = False,
    cell: Optional[float] = None,
    gps_t0: Optional[float] = None,
    threads: Optional[int] = None,
    progress: Optional[ProgressCallback] = None,
) -> LearnResult:
    """Learns the map of one walk, or of a list of walks (FootSLAM; ``footslam learn``).

    ``steps`` has columns ``t,length,dheading[,dz][,heading]`` (s, m, rad, m, rad); walk
    ``i`` of a batch has seed ``seed + i``. ``gps``, ``wifi`` and ``start`` are one per walk.
    """

def learn_one(
    steps: Table,
    index: int,
    *,
    others: Optional[GeoJson] = None,
    gps: Optional[Table] = None,
    wifi: Optional[Table] = None,
    start: Start = None,
    prior_map: Optional[GeoJson] = None,
    outline: Optional[GeoJson] = None,
    origin: Optional[Tuple[float, float]] = None,
    config: Config = None,
    seed: Optional[int] = None,
    particles: Optional[int] = None,
    hex_radius: Optional[float] = None,
    prior_weight: Optional[float] = None,
    ignore_heading: bool = False,
    gps_t0: Optional[float] = None,
    threads: Optional[int] = None,
) -> LearnedWalk:
    """Learns walk ``index`` of a batch alone, as :func:`learn` learns it (one task of a
    batch fanned out; ``others``: the other walks' merged map in a FeetSLAM pass)."""

def feetslam_passes(walks: int, *, known_starts: bool, config: Config = None) -> int:
    """FeetSLAM passes after the first for a batch of ``walks`` walks."""

def others_map(maps: Sequence[GeoJson], i: int) -> FeatureCollection:
    """The merged map of every map but the ``i``-th (walk ``i``'s ``others``)."""

def merge(maps: Sequence[GeoJson], weights: Optional[Sequence[float]] = None) -> FeatureCollection:
    """Merges maps of one frame, their counts summed with weights (``footslam merge``)."""

def plan(
    map: GeoJson,
    *,
    config: Config = None,
    min_visits: Optional[int] = None,
    resolution: Optional[float] = None,
) -> PlanResult:
    """A learned map as a walkable floor plan and occupancy grids (``footslam plan``)."""

def track(
    plan: GeoJson,
    steps: Table,
    *,
    start: Start = None,
    wifi: Optional[Table] = None,
    radio_map: Optional[GeoJson] = None,
    hexmap: Optional[GeoJson] = None,
    hexmap_weight: Optional[float] = None,
    origin: Optional[Tuple[float, float]] = None,
    plan_margin: Optional[float] = None,
    one_floor: bool = False,
    config: Config = None,
    seed: Optional[int] = None,
    ignore_heading: bool = False,
    online: bool = False,
    rf_mode: Optional[str] = None,
    rf_distance: Optional[str] = None,
    rf_epsilon: Optional[float] = None,
    rf_every_step: bool = False,
    threads: Optional[int] = None,
    progress: Optional[ProgressCallback] = None,
) -> TrackResult:
    """Tracks one walk on a known floor plan (``footslam track``); with ``wifi`` and
    ``radio_map``, RF-assisted."""

def survey(
    plan: GeoJson,
    walks: Sequence[Union[Tuple[Table, Table], Mapping[str, Any]]],
    *,
    start: Start = None,
    cell: Optional[float] = None,
    config: Config = None,
    seed: Optional[int] = None,
    origin: Optional[Tuple[float, float]] = None,
    one_floor: bool = False,
    merge: Optional[Sequence[GeoJson]] = None,
    threads: Optional[int] = None,
    progress: Optional[ProgressCallback] = None,
) -> SurveyResult:
    """A WiFi radio map from walks tracked on a known plan (``footslam survey``)."""

class RadioMapResult(TypedDict):
    radio_map: FeatureCollection
    plan: FeatureCollection
    summary: dict[str, Any]

def radio_map(
    map: GeoJson,
    tracks: Sequence[Mapping[str, Any]],
    wifi: Sequence[Table],
    *,
    cell: Optional[float] = None,
) -> RadioMapResult:
    """The radio map of walks learned apart, on the plan of their merged map (``learn``'s
    radio stage): with the merged map and ``learn_one``'s tracks, ``learn``'s
    ``radio_map``."""

class FingerprintColumns(TypedDict):
    t: Floats
    x: Floats
    y: Floats
    level: Ints
    ndist: Floats
    """Distance to the nearest cell, dBm."""

class FingerprintResult(TypedDict):
    track: FingerprintColumns
    summary: dict[str, Any]
    config: dict[str, Any]

def fingerprint(
    radiomap: GeoJson,
    wifi: Table,
    *,
    k: Optional[int] = None,
    config: Optional[Config] = None,
) -> FingerprintResult:
    """Each WiFi scan placed by the radio map alone (``footslam fingerprint``)."""
