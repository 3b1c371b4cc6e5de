"""
Seen points
===========

Every surface point seen by the team at its best configuration, as a point cloud
(:func:`uavcov.plotting.plot_point_cloud`; ``ply=`` also writes it as a PLY file).
"""

import uavcov
from uavcov import plotting
from uavcov.paper import EXAMPLE

terrain = EXAMPLE.terrain.make(0)  # the paper's example terrain: 100 m x 100 m, 1 m grid
result = uavcov.run_mission(terrain, EXAMPLE.mission.with_changes(n_uavs=9, iterations=60), rng=0)
fig = plotting.plot_point_cloud(result)
