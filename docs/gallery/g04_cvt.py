"""
The CVT start
=============

The constrained centroidal Voronoi tessellation on S' that places the team's start (:func:`uavcov.plotting.plot_cvt`).
"""

import uavcov
from uavcov import plotting
from uavcov.paper import EXAMPLE

terrain = EXAMPLE.terrain.make(0)  # the paper's example terrain: 100 m x 100 m, 1 m grid
result = uavcov.run_mission(terrain, EXAMPLE.mission.with_changes(n_uavs=9, iterations=1), rng=0)
fig = plotting.plot_cvt(result)
