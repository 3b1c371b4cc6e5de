"""
A flight plan on the bundled DEM
================================

:func:`uavcov.plan` takes a DEM (here the bundled sample, matplotlib's Jacksboro DEM, WGS 84;
``uavcov plan --sample`` on the command line), a team and its flight limits, and returns the
configuration found by the paper's method (CVT start on S', then CAO with the DEM as the true
surface) with what a flight controller and a GIS need; :func:`uavcov.write_plan` writes its
files (QGroundControl ``.plan``, CSV, GeoJSON, KML, GeoTIFFs, a report). The README's plan runs
300 iterations on a 60 x 60 node window; here 80.
"""

# %%
import tempfile
from pathlib import Path

import uavcov

dem = uavcov.sample_dem((140, 200, 140, 200))
settings = uavcov.PlanSettings(n_uavs=10, d_max=800.0, h_min=30.0, h_max=120.0, d_safe=20.0, takeoff=(-84.2725, 36.5883), iterations=80)
flight_plan = uavcov.plan(dem, settings, rng=0)
print(
    f"coverage {flight_plan.coverage:.3f} of the area (CVT start {flight_plan.initial_coverage:.3f}), {flight_plan.area_m2 / 1e6:.2f} km^2"
)
for k, (lon, lat) in enumerate(flight_plan.positions_wgs84[:3]):
    print(f"UAV {k + 1}: {lon:.6f}, {lat:.6f}, {flight_plan.altitude_agl[k]:.1f} m above ground")

# %%
# The files
# ---------
out = Path(tempfile.mkdtemp()) / "plan-sample"
written = uavcov.write_plan(flight_plan, out)
print(sorted(p.name for p in out.iterdir()))

# %%
# The report's map: coverage on the DEM, each UAV and its take-off
# ----------------------------------------------------------------
from matplotlib.figure import Figure
from PIL import Image

report = Figure(figsize=(8, 8))
ax = report.add_axes((0, 0, 1, 1))
ax.imshow(Image.open(out / "report.png"))
ax.set_axis_off()

# %%
# The same mission in 3D
# ----------------------
# ``flight_plan.mission`` is the mission's :class:`uavcov.MissionResult`;
# :func:`uavcov.plotting.view` turns it around (in a notebook the figure shows itself;
# ``uavcov view`` writes it as one HTML file).
from uavcov import plotting

view = plotting.view(flight_plan.mission, max_frames=10)
print(len(view.frames), "iterations on the slider,", len(view.data[0].x), "vertices drawn")
