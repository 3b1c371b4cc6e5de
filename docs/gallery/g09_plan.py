"""
A flight plan on a DEM
======================

:func:`uavcov.plan` on the bundled DEM (matplotlib's Jacksboro sample, WGS 84), ten UAVs
30-120 m above the ground, 60 CAO iterations (``uavcov plan --sample`` on the command line;
the README's plan runs 300). The map is the report's (:func:`uavcov.write_plan` writes it as
``report.png``): the DEM's heights, each UAV and its footprint, the take-off, the cells no UAV
sees in purple, and the coverage at each iteration.
"""

import tempfile
from pathlib import Path

from matplotlib.figure import Figure
from PIL import Image

import uavcov

dem = uavcov.sample_dem((140, 200, 140, 200))
settings = uavcov.PlanSettings(n_uavs=10, d_max=800.0, h_min=30.0, h_max=120.0, d_safe=20.0, takeoff=(-84.2725, 36.5883), iterations=60)
flight_plan = uavcov.plan(dem, settings, rng=0)
out = Path(tempfile.mkdtemp()) / "plan"
uavcov.write_plan(flight_plan, out)
print(f"coverage {flight_plan.coverage:.3f} of the area; files: {', '.join(sorted(p.name for p in out.iterdir()))}")

fig = Figure(figsize=(11, 5))
ax = fig.add_axes((0, 0, 1, 1))
ax.imshow(Image.open(out / "report.png"))
ax.set_axis_off()
