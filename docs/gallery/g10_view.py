"""
The 3D view
===========

:func:`uavcov.plotting.view` turns a mission around in the browser (plotly): the surface
coloured by what the team sees at the shown iteration (or, a button, by how many UAVs see each
point), the UAVs, their paths, starts and best positions, and a slider over iterations. Drag to
turn it, scroll to zoom. ``uavcov view RUN --out view.html`` writes the same figure as one HTML
file that opens with no network. Here 9 UAVs on a Gaussian-hill terrain (100 m x 100 m),
60 CAO iterations, the surface drawn on a 51 x 51 grid.
"""

import uavcov
from uavcov import plotting

terrain = uavcov.gaussian_hills(size=100.0, spacing=2.0, n_hills=5, heights=(10.0, 30.0), sigma=12.0, rng=0)
result = uavcov.run_mission(terrain, uavcov.MissionSettings(n_uavs=9, d_max=35.0, iterations=60), rng=0)
view = plotting.view(result, max_frames=12)
# sphinx_gallery_thumbnail_path = 'figures/example_coverage_map.png'
