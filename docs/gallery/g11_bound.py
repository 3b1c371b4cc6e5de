"""
How far from the best: the certified bound
==========================================

With a finite set of candidate viewpoints (a lattice over the flight band,
:func:`uavcov.cover.viewpoint_lattice`), coverage is a weighted maximum-coverage problem.
:class:`uavcov.cover.CoverageProblem` builds which candidate sees which target (bitsets, in
Rust), places ``k`` UAVs by lazy greedy, and certifies an upper bound on what ANY ``k`` of the
candidates can see together: the smaller of the online bound (greedy's coverage plus the ``k``
largest marginal gains) and the LP relaxation's dual bound. The true best lies in the band
between greedy and the bound; CAO from a CVT start is shown for comparison (its positions are
off the lattice, so it may even pass the bound).
"""

import numpy as np
from matplotlib.figure import Figure

import uavcov
from uavcov import cover

terrain = uavcov.gaussian_hills(size=100.0, spacing=2.0, n_hills=5, heights=(10.0, 30.0), sigma=12.0, rng=0)
limits = uavcov.Constraints(h_min=5.0, h_max=25.0)
candidates = cover.viewpoint_lattice(terrain, limits, cover.GreedySettings(spacing=8.0, n_heights=2))
vis = uavcov.Visibility(terrain, d_max=25.0)
problem = cover.CoverageProblem(vis, candidates)
teams = np.arange(1, 11)
greedy = [problem.greedy(int(k)).coverage for k in teams]
bound = [problem.certified_bound(int(k)) for k in teams]
cao_teams = teams[1::3]
missions = [uavcov.MissionSettings(n_uavs=int(k), d_max=25.0, constraints=limits, iterations=40) for k in cao_teams]
cao = [uavcov.run_mission(terrain, settings, rng=0) for settings in missions]
print(f"{candidates.n} candidates; greedy / bound at k = 10: {greedy[-1]:.3f} / {bound[-1]:.3f}")

fig = Figure(figsize=(6.4, 4.2), layout="constrained")
ax = fig.add_subplot()
ax.fill_between(teams, greedy, bound, color="tab:orange", alpha=0.2, label="where the best placement of the candidates lies")
ax.plot(teams, bound, "k--", marker="v", label="certified bound (no k candidates see more)")
ax.plot(teams, greedy, color="tab:orange", marker="o", label="greedy on the candidates")
ax.plot(cao_teams, [r.best_coverage for r in cao], "s", color="tab:green", label="CAO from a CVT start, 40 iterations")
ax.set_xlabel("team size k")
ax.set_ylabel("coverage (share of the surface seen)")
ax.set_title(f"Greedy against the bound: {candidates.n} candidates, d_max = 25 m", fontsize=10)
ax.grid(alpha=0.4)
ax.legend(fontsize=8, loc="lower right")
