"""
Coverage map
============

The true surface coloured by what the team sees at its best configuration, with the paths (:func:`uavcov.plotting.plot_coverage_map`).
"""

import uavcov
from uavcov import plotting
from uavcov.paper import EXAMPLE

terrain = EXAMPLE.terrain.make(0)  # the paper's example terrain: 100 m x 100 m, 1 m grid
result = uavcov.run_mission(terrain, EXAMPLE.mission.with_changes(n_uavs=9, iterations=60), rng=0)
fig = plotting.plot_coverage_map(result)
