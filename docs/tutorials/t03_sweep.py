"""
A sweep of settings
===================

A sweep runs every combination of the settings listed under ``[sweep]`` for every seed, team
size and start (``uavcov sweep CONFIG.toml``; ``examples/sweep.toml`` is a full example). Here
CAO's initial step size ``alpha0`` against two sensing ranges, on two development seeds and 30
iterations, read from a TOML text by :func:`uavcov.experiments.parse_sweep_config`.
"""

# %%
import tempfile
import tomllib
from pathlib import Path

from uavcov import experiments, load_mission, paper, plotting

config = experiments.parse_sweep_config(
    tomllib.loads(
        """
name = "step-size"
base = "table1"
seeds = [1000, 1001]
team_sizes = [5]
starts = ["cvt"]
iterations = 30

[terrain]
kind = "hills"
size = 60.0
spacing = 2.0
n_hills = 4
heights = [5.0, 20.0]
sigma = 8.0

[sweep]
"cao.alpha0" = [2.0, 8.0]
d_max = [15.0, 25.0]
"""
    ),
    bases=paper.EXPERIMENTS,
)
out = Path(tempfile.mkdtemp()) / "sweep"
rows = experiments.run_sweep(config, out, workers=1, progress=False)
print(len(rows), "runs")

# %%
# ``summary.md``: the mean (and spread) per combination
print((out / "summary.md").read_text())

# %%
# The coverage curves of the runs, grouped by setting
# ---------------------------------------------------
# Every run is stored as ``runs/<run_id>.npz`` (:func:`uavcov.load_mission`); ``runs.csv`` has a
# column per swept setting.
groups: dict[str, list] = {}
for row in rows:
    label = f"alpha0 = {float(row['cao.alpha0']):g}, d_max = {float(row['d_max']):g} m"
    groups.setdefault(label, []).append(load_mission(out / "runs" / f"{row['run_id']}.npz"))
curves = plotting.plot_coverage_curves(groups, title="CAO's initial step size against the sensing range")
