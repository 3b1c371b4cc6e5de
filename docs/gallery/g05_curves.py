"""
Coverage during the optimisation
================================

The coverage at every CAO iteration, from a CVT start and from a corner start (:func:`uavcov.plotting.plot_coverage_curves`).
"""

import uavcov
from uavcov import plotting
from uavcov.paper import EXAMPLE

terrain = EXAMPLE.terrain.make(0)  # the paper's example terrain: 100 m x 100 m, 1 m grid
result = uavcov.run_mission(terrain, EXAMPLE.mission.with_changes(n_uavs=9, iterations=150), rng=0)
corner = uavcov.run_mission(terrain, EXAMPLE.mission.with_changes(**{"n_uavs": 9, "iterations": 150, "start.kind": "corner"}), rng=0)
fig = plotting.plot_coverage_curves({"cvt": [result], "corner": [corner]}, title="9 UAVs, d_max = 35 m")
