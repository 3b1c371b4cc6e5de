"""
Buildings
=========

A scene of boxes on flat ground (:func:`uavcov.terrain.buildings_scene`, the paper's Figs. 7-8):
walls hide what stands behind them, so the team must spread around the blocks. Four UAVs,
d_max = 8 m, 60 CAO iterations from a CVT start on the approximation S' from 60 known points,
seen from above (:func:`uavcov.plotting.plot_coverage_map`, ``view="top"``).
"""

import uavcov
from uavcov import plotting, terrain

scene = terrain.buildings_scene(size=24.0, n_buildings=4, footprint=(2.0, 5.0), heights=(3.0, 8.0), rng=0)
settings = uavcov.MissionSettings(
    n_uavs=4,
    d_max=8.0,
    n_prior=60,
    start=uavcov.StartSettings(altitude=2.0, altitude_reference="ground", climb=0.5),
    constraints=uavcov.Constraints(h_min=1.0, h_max=6.0, z_max=20.0, d_safe=1.0, check_moves=True),
    iterations=60,
)
result = uavcov.run_mission(scene, settings, rng=0)
print(f"coverage {result.initial_coverage:.3f} at the CVT start, {result.best_coverage:.3f} after CAO")
fig = plotting.plot_coverage_map(result, view="top")
