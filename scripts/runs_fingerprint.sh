#!/usr/bin/env bash
# The runs that a refactor must not move: a fixed subset of Table 1 and of the pyramid, a
# structure mission, a DEM plan and a structure plan, written to OUT for
# `python scripts/compare_fingerprints.py BEFORE AFTER` (every number, timings excepted).
# Usage: bash scripts/runs_fingerprint.sh OUT   (with uavcov installed in the active Python)
set -euo pipefail
out="${1:?usage: runs_fingerprint.sh OUT}"
rm -rf "$out" && mkdir -p "$out"
uavcov reproduce table1 --seeds 0-4 --out "$out/table1" --workers 2 --threads 1 --no-plots --no-progress >/dev/null
uavcov reproduce pyramid --seeds 0-4 --out "$out/pyramid" --workers 2 --threads 1 --no-plots --no-progress >/dev/null
uavcov plan --sample --window 140,200,140,200 --uavs 10 --d-max 800 --h-min 30 --h-max 120 \
    --separation 20 --takeoff=-84.2725,36.5883 --iterations 300 --seed 0 --threads 1 --out "$out/plan-sample" >/dev/null
uavcov plan --structure girder_bridge --anchor 5.0,45.0,200.0 --uavs 6 --d-max 15 --iterations 60 \
    --seed 1 --threads 1 --out "$out/plan-structure" >/dev/null
python - "$out/structure_mission.json" <<'PY'
import json, sys
import uavcov
from uavcov.limits import Constraints
from uavcov.placement import StartSettings
from uavcov.structures import girder_bridge

bridge = girder_bridge(rng=0)
settings = uavcov.MissionSettings(
    n_uavs=8, d_max=15.0, n_prior=100, iterations=100,
    start=StartSettings(kind="cvt", altitude=6.0, altitude_reference="normal", climb=0.5),
    constraints=Constraints(clearance="standoff", h_min=2.0, d_safe=1.0, z_max=22.0, check_moves=True),
)
r = uavcov.run_mission(bridge, settings, targets=bridge.targets(spacing=1.0), rng=0)
json.dump({
    "initial": repr(r.initial_coverage), "best": repr(r.best_coverage),
    "best_positions": [repr(float(v)) for v in r.best_positions.ravel()],
    "coverage": [repr(float(v)) for v in r.coverage],
    "distance_flown": [repr(float(v)) for v in r.distance_flown],
    "by_part": {k: repr(v) for k, v in r.coverage_by_part.items()},
}, open(sys.argv[1], "w"), indent=0)
PY
echo "fingerprint written to $out"
