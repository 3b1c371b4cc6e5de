"""
S and S'
========

The true surface S beside the approximation S' built from the 30 known points (:func:`uavcov.plotting.plot_approximation`).
"""

import uavcov
from uavcov import plotting
from uavcov.paper import EXAMPLE

terrain = EXAMPLE.terrain.make(0)  # the paper's example terrain: 100 m x 100 m, 1 m grid
result = uavcov.run_mission(terrain, EXAMPLE.mission.with_changes(n_uavs=9, iterations=1), rng=0)
fig = plotting.plot_approximation(result)
