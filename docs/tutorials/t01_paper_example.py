"""
The paper's illustrative example
================================

The method of Renzaglia et al. (arXiv:1901.10272) end to end on a small grid: a true surface
of Gaussian hills, 30 known points from which the approximation S' is built, a constrained CVT
on S' as the start, then CAO on the true surface. The paper's example (Fig. 5) flies 9 UAVs
with ``d_max = 35`` m over a 100 m x 100 m terrain at 1 m for 500 iterations
(``uavcov reproduce example``); here the grid is 2 m and CAO runs 60 iterations so the page
builds in seconds.
"""

# %%
# The true surface and the mission's settings
# -------------------------------------------
# :class:`uavcov.paper.EXAMPLE` holds the paper's settings; we keep them and change only
# the resolution of the terrain and the number of iterations.
import dataclasses

import uavcov
from uavcov.paper import EXAMPLE

terrain = dataclasses.replace(EXAMPLE.terrain, spacing=2.0).make(0)
settings = EXAMPLE.mission.with_changes(n_uavs=9, iterations=60)
print(f"{terrain.grid.shape} grid nodes, {terrain.area:.0f} m^2")
print(settings.d_max, settings.n_prior, settings.start.kind)

# %%
# One mission
# -----------
# :func:`uavcov.run_mission` samples the prior, builds S', places the CVT start on it and runs
# CAO against the true surface. ``rng`` makes it reproducible.
result = uavcov.run_mission(terrain, settings, rng=0)
print(f"coverage at the start {result.initial_coverage:.3f}, best {result.best_coverage:.3f} (iteration {result.best_iteration})")

# %%
# The figures of the run
# ----------------------
# The true surface S beside its approximation S', the CVT on S' and the coverage reached.
from uavcov import plotting

approximation = plotting.plot_approximation(result)
cvt = plotting.plot_cvt(result)
coverage_map = plotting.plot_coverage_map(result)
