# %% [markdown]
# # footslam from Python: learn a map, make a plan, track a walk on it
#
# Notebook-style (cells marked `# %%`: run it as a script, or open it in VS Code / Jupytext).
# Install the package first, from the repository root: `pip install ./python`.
# pandas, geopandas and matplotlib are optional: the cells that use them are skipped
# without them.
#
# Frames and units: metres in a local frame (x east, y north), seconds, radians
# counter-clockwise from east.

# %%
from pathlib import Path

import numpy as np

import footslam

ROOT = Path(__file__).resolve().parents[1] if "__file__" in globals() else Path.cwd()
OFFICE = ROOT / "datasets" / "office"  # a simulated 3-lap office walk (484 steps)
TOWER = ROOT / "datasets" / "tower"  # a simulated walk through a 3-floor building, with WiFi

try:
    import pandas as pd
except ImportError:
    pd = None
try:
    import geopandas as gpd
except ImportError:
    gpd = None
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None

# %% [markdown]
# ## Load a walk
# Step events: `t,length,dheading[,dz][,heading]`. A path, a pandas DataFrame or a dict of
# numpy arrays all work; `footslam.steps(imu, "foot" | "phone")` makes them from raw IMU data.

# %%
if pd is not None:
    walk = pd.read_csv(OFFICE / "steps.csv")
else:
    table = np.genfromtxt(OFFICE / "steps.csv", delimiter=",", names=True)
    walk = {name: table[name] for name in table.dtype.names}
print(f"{len(walk['t'])} steps, {float(np.sum(walk['length'])):.0f} m")

# %% [markdown]
# ## Learn the map (FootSLAM)
# Each particle is one hypothesis of the whole path with its own hexagon map; the most
# probable one is the answer. The same seed gives the command line's result
# (`footslam learn --steps datasets/office/steps.csv --particles 2000 --seed 1`).

# %%
learned = footslam.learn(walk, particles=2000, seed=1)
result = learned["walks"][0]
print(
    f"{result['summary']['hexagons']} hexagons learned in "
    f"{result['summary']['filter_runtime_s']:.2f} s"
)
track = result["track"]  # columns t, x, y, z, level

# %% [markdown]
# ## Turn the map into a floor plan and occupancy grid

# %%
planned = footslam.plan(result["map"])
grid = planned["grids"][0]
print(
    f"walkable plan of {planned['summary']['walkable_area_m2']:.0f} m², occupancy grid "
    f"{grid['occupancy'].shape} at {grid['resolution']} m"
)

# %% [markdown]
# ## Track the walk on the learned plan
# The learned plan's edges are where the walk stopped, so grow it a little (`plan_margin`).
# Without `start` the tracker starts uniformly over the whole plan.

# %%
tracked = footslam.track(planned["plan"], walk, plan_margin=0.25, seed=2)
summary = tracked["summary"]
print(f"localised after {summary['steps_to_localise']} of {summary['steps']} steps")
answer = tracked["track"]  # smoothed: t, x, y, z, level, certain, hypotheses

# %% [markdown]
# ## Known floor plans and WiFi: a radio survey, then RF-assisted tracking

# %%
surveyed = footslam.survey(
    TOWER / "floor.geojson", [(TOWER / "steps.csv", TOWER / "wifi.csv")], seed=1
)
print(
    f"radio map of {surveyed['summary']['cells']} cells, "
    f"{100 * surveyed['summary']['coverage']:.0f} % covered"
)
rf = footslam.track(
    TOWER / "floor.geojson",
    TOWER / "steps.csv",
    wifi=TOWER / "wifi.csv",
    radio_map=surveyed["radio_map"],
    seed=1,
)
print(f"with WiFi: localised after {rf['summary']['steps_to_localise']} steps")

# %% [markdown]
# ## Look at the results (pandas, geopandas, matplotlib when installed)

# %%
if pd is not None:
    print(pd.DataFrame(answer).head())
if gpd is not None:
    hexagons = gpd.GeoDataFrame.from_features(result["map"])
    plan = gpd.GeoDataFrame.from_features(planned["plan"])
    print(hexagons[["q", "r", "visits"]].describe())
if plt is not None:
    fig, ax = plt.subplots(figsize=(8, 5))
    g = grid["occupancy"]
    x0, y0 = grid["origin"]
    extent = (x0, x0 + g.shape[1] * grid["resolution"], y0, y0 + g.shape[0] * grid["resolution"])
    ax.imshow(g == 0, origin="lower", extent=extent, cmap="Greys", alpha=0.4)
    ax.plot(track["x"], track["y"], lw=0.8, label="learned path")
    ax.plot(answer["x"], answer["y"], lw=0.8, label="tracked on the learned plan")
    ax.set_aspect("equal")
    ax.set_xlabel("x east, m")
    ax.set_ylabel("y north, m")
    ax.legend()
    out = ROOT / "outputs" / "python_quickstart.png"
    out.parent.mkdir(exist_ok=True)
    fig.savefig(out, dpi=120)
    print(f"picture: {out}")
