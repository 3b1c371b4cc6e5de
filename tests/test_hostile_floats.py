"""Extreme finite floats (1e-300 .. 1e300, both signs) through the public API (issue 14).

Every call must return a finite, sensible answer or raise an error from :mod:`uavcov.errors`;
never another exception type, never a Rust panic (``pyo3_runtime.PanicException``, a
``BaseException``), never a hang, never an abort. The calls run in a worker process, one probe per
line, each with a timeout, so that a hang or an abort fails one probe and the worker is started
again.

The inputs of the issue that reached the Rust core's failures (a panic for a huge range, a walk
that did not end far from the origin, wrong answers near the limits of f64, an overflowing
target count) are the deterministic cases at the end.
"""

from __future__ import annotations

import json
import math
import os
import select
import subprocess
import sys
import tempfile
from typing import Any

import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, Phase, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

TIMEOUT_S = 5.0

# One probe per line of JSON; one answer per line: {"status": "ok" | "uavcov" | "other", ...}.
WORKER = r"""
import json, math, sys
import numpy as np
from uavcov.limits._constraints import Constraints, closest_admissible
from uavcov.placement._cvt import cvt
from uavcov.errors import UavcovError
from uavcov.settings import MissionSettings
from uavcov.placement._starts import StartSettings
from uavcov.engine._surface import Terrain
from uavcov.engine._targets import Targets
from uavcov.engine._visibility import Visibility

def terrain(case):
    if case["surface"] == "grid":
        return Terrain.from_grid(np.array(case["z"], dtype=float), case["spacing"], origin=case["origin"])
    return Terrain(np.array(case["vertices"], dtype=float), np.array(case["faces"]))

def probe(case):
    out = {}
    t = terrain(case)
    out["area"] = float(t.area)
    out["bounds"] = np.asarray(t.bounds, dtype=float).tolist()
    kind = case["probe"]
    if kind == "surface":
        return out
    p = np.array([case.get("point", [0.0, 0.0, 0.0])], dtype=float)
    if kind == "queries":
        out["ground"] = float(t.ground_height(p[:, :2])[0])
        out["clearance"] = float(t.clearance(p)[0])
        out["closest"] = t.closest_point(p)[0].tolist()
    elif kind == "coverage":
        for method in case["methods"]:
            out[method] = float(Visibility(t, case["d_max"], method=method).coverage(p))
    elif kind == "cvt":
        out["generators"] = cvt(t, case["n"], rng=0, max_iterations=5).generators.tolist()
    elif kind == "constraints":
        c = Constraints(**case["constraints"]).resolve(t)
        c.check_team(case["n"], t)
        out["flight_box"] = [float(v) for v in c.flight_box]
        out["admissible"] = closest_admissible(c, t, np.repeat(p, case["n"], axis=0)).tolist()
    elif kind == "spec":
        spec = MissionSettings(n_uavs=2, d_max=case["d_max"], start=StartSettings(**case["start"]))
        out["d_max"] = spec.d_max
        out["targets"] = Targets(p, [case["d_max"]]).weights.tolist()
    return out

for line in sys.stdin:
    case = json.loads(line)
    try:
        answer = {"status": "ok", "value": probe(case)}
    except UavcovError as exc:
        answer = {"status": "uavcov", "type": type(exc).__name__, "message": str(exc)[:500]}
    except BaseException as exc:  # a PanicException is a BaseException
        answer = {"status": "other", "type": f"{type(exc).__module__}.{type(exc).__name__}", "message": str(exc)[:500]}
    sys.stdout.write(json.dumps(answer) + "\n")
    sys.stdout.flush()
"""


class Worker:
    """The worker process; restarted after a hang (killed at the timeout) or a crash."""

    def __init__(self) -> None:
        self.stderr = tempfile.TemporaryFile()  # noqa: SIM115 (closed by close(): the worker writes to it across calls)
        self.process: subprocess.Popen[bytes] | None = None
        self.fresh = True

    def _start(self) -> subprocess.Popen[bytes]:
        env = {**os.environ, "RUST_BACKTRACE": "0", "RAYON_NUM_THREADS": "2"}
        return subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.stderr, env=env)

    def ask(self, case: dict[str, Any], timeout: float = TIMEOUT_S) -> dict[str, Any]:
        if self.process is None or self.process.poll() is not None:
            self.process = self._start()
            self.fresh = True
        process = self.process
        assert process.stdin is not None and process.stdout is not None
        process.stdin.write((json.dumps(case) + "\n").encode())
        process.stdin.flush()
        ready, _, _ = select.select([process.stdout], [], [], timeout + (30.0 if self.fresh else 0.0))  # a fresh one imports first
        self.fresh = False
        if not ready:
            process.kill()
            process.wait()
            self.process = None
            return {"status": "timeout", "message": f"no answer within {timeout} s"}
        line = process.stdout.readline()
        if not line:
            process.wait()
            self.process = None
            return {"status": "died", "message": f"the worker died with exit code {process.returncode}"}
        answer: dict[str, Any] = json.loads(line)
        return answer

    def close(self) -> None:
        if self.process is not None:
            self.process.kill()
            self.process.wait()
        self.stderr.close()


@pytest.fixture(scope="module")
def worker():
    w = Worker()
    yield w
    w.close()


# ---------------------------------------------------------------------------------------------
# Strategies: extreme finite floats, both signs, mixed with ordinary ones


def _scaled(mantissa: float, exponent: int, sign: int) -> float:
    return sign * mantissa * 10.0**exponent


extreme = st.one_of(
    st.just(0.0),
    st.builds(_scaled, st.floats(1.0, 9.99), st.integers(-300, 299), st.sampled_from([-1, 1])),
    st.floats(-100.0, 100.0),
)
positive_extreme = st.one_of(
    st.builds(_scaled, st.floats(1.0, 9.99), st.integers(-300, 299), st.just(1)),
    st.floats(0.01, 100.0),
)
ordinary_or_extreme = st.one_of(st.floats(-20.0, 20.0), extreme)


@st.composite
def grid_surfaces(draw: Any, extreme_geometry: bool = True) -> dict[str, Any]:
    scale = draw(st.one_of(st.just(1.0), positive_extreme)) if extreme_geometry else 1.0
    z = [[draw(st.floats(0.0, 5.0)) * scale for _ in range(4)] for _ in range(4)]
    spacing = draw(st.one_of(st.just(1.0), positive_extreme)) if extreme_geometry else 1.0
    origin = [draw(st.one_of(st.just(0.0), extreme)) if extreme_geometry else 0.0 for _ in range(2)]
    return {"surface": "grid", "z": z, "spacing": spacing, "origin": origin}


@st.composite
def mesh_surfaces(draw: Any, extreme_geometry: bool = True) -> dict[str, Any]:
    s = draw(st.one_of(st.just(3.0), extreme)) if extreme_geometry else 3.0
    shift = [draw(st.one_of(st.just(0.0), extreme)) if extreme_geometry else 0.0 for _ in range(3)]
    base = [[0, 0, 0], [s, 0, 0], [0, s, 0], [s, s, 0.5 * s]]
    vertices = [[c + d for c, d in zip(v, shift, strict=True)] for v in base]
    return {"surface": "mesh", "vertices": vertices, "faces": [[0, 1, 2], [1, 3, 2]]}


points = st.lists(ordinary_or_extreme, min_size=3, max_size=3)

PROPERTY = settings(
    max_examples=int(os.environ.get("UAVCOV_HOSTILE_EXAMPLES", "100")),
    deadline=None,
    database=None,
    derandomize=True,  # the same examples every run
    phases=[Phase.explicit, Phase.generate],  # no shrinking: each shrink step of a hang costs a timeout
    suppress_health_check=list(HealthCheck),
)


# ---------------------------------------------------------------------------------------------
# What a sensible answer is


def _finite(values: Any) -> bool:
    return all(math.isfinite(v) for v in (values if isinstance(values, list) else [values]))


def _tolerance(bounds: list[list[float]]) -> float:
    extent = max(abs(v) for row in bounds for v in row)
    return 1e-9 * max(extent, 1e-300) + 1e-300


def _inside(point: list[float], bounds: list[list[float]]) -> bool:
    tol = _tolerance(bounds)
    return all(bounds[0][k] - tol <= point[k] <= bounds[1][k] + tol for k in range(3))


def problems(case: dict[str, Any], answer: dict[str, Any]) -> list[str]:
    """What is wrong with ``answer`` (empty when it is a uavcov error or a sensible result)."""
    status = answer["status"]
    if status == "uavcov":
        return []
    if status != "ok":
        return [f"{status}: {answer.get('type', '')} {answer.get('message', '')}"]
    value = answer["value"]
    found = []
    bounds = value["bounds"]
    if not _finite(value["area"]) or value["area"] <= 0.0:
        found.append(f"area {value['area']}")
    if not all(_finite(row) for row in bounds):
        found.append(f"bounds {bounds}")
    if "ground" in value:
        g = value["ground"]
        if not (math.isnan(g) or bounds[0][2] - _tolerance(bounds) <= g <= bounds[1][2] + _tolerance(bounds)):
            found.append(f"ground_height {g} outside the surface's heights {bounds[0][2]}..{bounds[1][2]}")
    if "clearance" in value and math.isnan(value["clearance"]):
        found.append("clearance is NaN")
    if "closest" in value and not (_finite(value["closest"]) and _inside(value["closest"], bounds)):
        found.append(f"closest_point {value['closest']} is not a point of the surface (bounds {bounds})")
    for method in ("grid", "mesh", "auto"):
        if method in value:
            c = value[method]
            if not (0.0 <= c <= 1.0):
                found.append(f"coverage ({method}) {c}")
            # Farther than d_max from the whole surface: nothing can be seen.
            p = case["point"]
            gap = math.hypot(*(max(bounds[0][k] - p[k], 0.0, p[k] - bounds[1][k]) for k in range(3)))  # no overflow
            if math.isfinite(gap) and gap > case["d_max"] * (1 + 1e-9) and c != 0.0:
                found.append(f"coverage ({method}) {c} from {gap:.3g} m away, beyond d_max = {case['d_max']:.3g} m")
    if "grid" in value and "mesh" in value and value["grid"] != value["mesh"]:
        found.append(f"grid method {value['grid']} != mesh method {value['mesh']}")
    if "generators" in value and not all(_finite(g) and _inside(g, bounds) for g in value["generators"]):
        found.append(f"CVT generators {value['generators']} off the surface")
    if "admissible" in value and not all(_finite(p) for p in value["admissible"]):
        found.append(f"closest_admissible {value['admissible']}")
    return found


def check(worker: Worker, case: dict[str, Any]) -> None:
    """Fail on the first problem; with ``UAVCOV_HOSTILE_LOG=<file>``, log every one there instead
    (one JSON line each: how to list all the failing inputs for the Rust side)."""
    found = problems(case, worker.ask(case))
    log = os.environ.get("UAVCOV_HOSTILE_LOG")
    if log and found:
        with open(log, "a", encoding="utf-8") as out:
            out.write(json.dumps({"case": case, "problems": found}) + "\n")
        return
    assert not found, f"{json.dumps(case)}: {'; '.join(found)}"


# ---------------------------------------------------------------------------------------------
# Property tests


@PROPERTY
@given(surface=st.one_of(grid_surfaces(), mesh_surfaces()))
def test_surfaces_with_extreme_coordinates(worker, surface):
    check(worker, {**surface, "probe": "surface"})


@PROPERTY
@given(surface=st.one_of(grid_surfaces(extreme_geometry=False), mesh_surfaces(extreme_geometry=False)), point=points)
def test_queries_at_extreme_points(worker, surface, point):
    check(worker, {**surface, "probe": "queries", "point": point})


@PROPERTY
@given(surface=st.one_of(grid_surfaces(), mesh_surfaces()), point=points)
def test_queries_on_extreme_surfaces(worker, surface, point):
    check(worker, {**surface, "probe": "queries", "point": point})


@PROPERTY
@given(surface=grid_surfaces(extreme_geometry=False), point=points, d_max=positive_extreme)
def test_grid_coverage_with_extreme_uavs_and_ranges(worker, surface, point, d_max):
    check(worker, {**surface, "probe": "coverage", "point": point, "d_max": d_max, "methods": ["grid", "mesh"]})


@PROPERTY
@given(surface=mesh_surfaces(extreme_geometry=False), point=points, d_max=positive_extreme)
def test_mesh_coverage_with_extreme_uavs_and_ranges(worker, surface, point, d_max):
    check(worker, {**surface, "probe": "coverage", "point": point, "d_max": d_max, "methods": ["mesh"]})


@PROPERTY
@given(surface=st.one_of(grid_surfaces(), mesh_surfaces()), n=st.integers(1, 4))
def test_cvt_on_extreme_surfaces(worker, surface, n):
    check(worker, {**surface, "probe": "cvt", "n": n})


# What holds today, everywhere: Python-side validation of settings with extreme values, on an
# ordinary surface. Not xfail.

constraint_values = st.fixed_dictionaries(
    {},
    optional={
        "h_min": st.one_of(positive_extreme, extreme),
        "z_max": extreme,
        "d_safe": st.one_of(positive_extreme, extreme),
        "bounds": st.lists(extreme, min_size=4, max_size=4),
    },
)


@PROPERTY
@given(
    surface=st.one_of(grid_surfaces(extreme_geometry=False), mesh_surfaces(extreme_geometry=False)),
    constraints=constraint_values,
    n=st.integers(1, 3),
    point=st.lists(st.floats(0.0, 3.0), min_size=3, max_size=3),
)
def test_constraints_with_extreme_values(worker, surface, constraints, n, point):
    check(worker, {**surface, "probe": "constraints", "constraints": constraints, "n": n, "point": point})


start_values = st.fixed_dictionaries(
    {},
    optional={
        "altitude": extreme,
        "climb": extreme,
        "corner_spacing": extreme,
        "corner_altitude": extreme,
        "random_altitude": st.lists(extreme, min_size=2, max_size=2),
    },
)


@PROPERTY
@given(surface=grid_surfaces(extreme_geometry=False), d_max=extreme, start=start_values, point=points)
def test_mission_settings_with_extreme_values(worker, surface, d_max, start, point):
    check(worker, {**surface, "probe": "spec", "d_max": d_max, "start": start, "point": point})


# ---------------------------------------------------------------------------------------------
# The inputs that reached the Rust core's failures, one each


FLAT = {"surface": "grid", "z": [[0.0] * 11 for _ in range(11)], "spacing": 1.0, "origin": [0.0, 0.0]}
SMALL = {"surface": "grid", "z": [[0.0] * 4 for _ in range(4)], "spacing": 1.0, "origin": [0.0, 0.0]}
RAMP = {**SMALL, "z": [[0.0, 1.0, 2.0, 3.0], [1.0, 2.0, 3.0, 4.0], [2.0, 3.0, 4.0, 0.0], [3.0, 4.0, 0.0, 1.0]]}
ROUGH = {**FLAT, "z": [[float((3 * i + 7 * j) % 5) * 0.6 for j in range(11)] for i in range(11)]}
SQUARE = {"surface": "mesh", "vertices": [[0, 0, 0], [3, 0, 0], [0, 3, 0], [3, 3, 1.5]], "faces": [[0, 1, 2], [1, 3, 2]]}

KNOWN = [
    pytest.param(
        {**FLAT, "probe": "coverage", "point": [5, 5, 3], "d_max": 1e19, "methods": ["grid"]},
        id="item1-grid-d_max-1e19",
    ),
    pytest.param(
        {**SMALL, "probe": "coverage", "point": [1, 1, 1], "d_max": 1e150, "methods": ["grid"]},
        id="item1-grid-d_max-1e150",
    ),
    pytest.param(
        {**ROUGH, "origin": [1e10, 1e10], "probe": "coverage", "point": [1e10 + 5, 1e10 + 5, 5], "d_max": 10.0, "methods": ["grid"]},
        id="item2-grid-origin-1e10",
    ),
    pytest.param(
        {**RAMP, "spacing": 1e-100, "probe": "coverage", "point": [1, 1, 1], "d_max": 10.0, "methods": ["grid"]},
        id="grid-spacing-1e-100-uav-1e100-cells-away",
    ),
    pytest.param(
        {**SMALL, "probe": "coverage", "point": [8.7e76, 0, 1], "d_max": 4.8e122, "methods": ["grid"]},
        id="grid-far-uav",
    ),
    pytest.param(
        {**SQUARE, "probe": "coverage", "point": [1, 1, 3e300], "d_max": 1e300, "methods": ["mesh"]},
        id="item4-mesh-3e300",
    ),
    pytest.param(
        {**SQUARE, "probe": "queries", "point": [1e300, 1e300, 1e300]},
        id="item4-closest-point-1e300",
    ),
    pytest.param(
        {**FLAT, "probe": "queries", "point": [-1e300, 1e-300, 0.0]},
        id="item4-grid-closest-point-1e300",
    ),
    pytest.param(
        {**SMALL, "origin": [1e300, 1e300], "probe": "surface"},
        id="item4-grid-origin-1e300",
    ),
    pytest.param(
        {
            **SQUARE,
            "probe": "constraints",
            "constraints": {"d_safe": 2.8e177, "bounds": [0.0, -1.0, 6.3e177, 0.0]},
            "n": 2,
            "point": [2.0, 1.5, 3.0],
        },
        id="check_team-r-cubed-overflows",
    ),
    pytest.param(
        {
            "surface": "mesh",
            "vertices": [[0, 0, 0], [1e20, 0, 0], [0, 1e20, 0], [1e20, 1e20, 5e19]],
            "faces": [[0, 1, 2], [1, 3, 2]],
            "probe": "coverage",
            "point": [1, 1, 1],
            "d_max": 10.0,
            "methods": ["mesh"],
        },
        id="mesh-targets-1e20",
    ),
]


@pytest.mark.parametrize("case", KNOWN)
def test_known_rust_failures(worker, case):
    check(worker, case)


@pytest.mark.parametrize(
    "case",
    [
        {**FLAT, "probe": "coverage", "point": [5, 5, 3], "d_max": 1e18, "methods": ["grid", "mesh"]},
        {**FLAT, "origin": [1e9, 1e9], "probe": "coverage", "point": [1e9 + 5, 1e9 + 5, 3], "d_max": 10.0, "methods": ["grid", "mesh"]},
        {**SQUARE, "probe": "queries", "point": [1e15, -1e15, 1e15]},
        {**SQUARE, "probe": "coverage", "point": [1, 1, 1e30], "d_max": 1e20, "methods": ["mesh"]},
        {**FLAT, "probe": "constraints", "constraints": {"h_min": 1e300, "z_max": 1e300}, "n": 2, "point": [1, 1, 1]},
        {**FLAT, "probe": "constraints", "constraints": {"d_safe": 1e300}, "n": 3, "point": [1, 1, 1]},
        {**FLAT, "probe": "spec", "d_max": 1e300, "start": {"altitude": 1e300, "climb": 1e-300}, "point": [1, 1, 1]},
    ],
    ids=["grid-d_max-1e18", "grid-origin-1e9", "mesh-closest-1e15", "mesh-far-uav", "h_min-1e300", "d_safe-1e300", "spec-1e300"],
)
def test_cases_that_hold_today(worker, case):
    check(worker, case)


def test_more_public_helpers_refuse_hostile_input_with_uavcov_errors() -> None:
    """Found by calling every public callable with hostile values: each answered with a bare
    IndexError, OverflowError or numpy's ambiguity before."""
    import numpy as np

    from uavcov.engine import degenerate_faces
    from uavcov.errors import ConfigError, InvalidInputError, InvalidTypeError
    from uavcov.experiments import local_executor
    from uavcov.optim import standard_normal
    from uavcov.structures import StructurePrior
    from uavcov.terrain import wrap_longitude

    refused = (InvalidInputError, InvalidTypeError)
    triangle = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    for vertices, faces in ((1e300, [[0, 1, 2]]), (triangle, [[0, 1, 3]]), (triangle, [[-1, 1, 2]]), (triangle, [[0.5, 1, 2]])):
        with pytest.raises(refused):
            degenerate_faces(vertices, faces)  # type: ignore[arg-type]
    assert degenerate_faces(np.empty((0, 3)), np.empty((0, 3), dtype=np.int64)).shape == (0,)
    assert not degenerate_faces(triangle, np.array([[0, 1, 2]]))[0]
    for rng, shape in ((1e300, 3), (np.random.default_rng(0), "x"), (np.random.default_rng(0), 2.5)):
        with pytest.raises(refused):
            standard_normal(rng, shape)  # type: ignore[arg-type]
    for lon in ("x", [[1, 2], [3]], float("inf")):
        with pytest.raises(refused):
            wrap_longitude(lon)
    assert np.isnan(wrap_longitude(float("nan"))) and wrap_longitude(540.0) == 180.0
    for workers in (0, -1, 10**12, 2.5, "2"):
        with pytest.raises(ConfigError):
            local_executor(workers)  # type: ignore[arg-type]
    for kind in (np.zeros(3), None, 5):
        with pytest.raises(refused):
            StructurePrior(triangle, None, kind)  # type: ignore[arg-type]
