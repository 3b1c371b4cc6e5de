"""Fuzz every public callable of uavcov, and the command line, with hostile input.

Each public function, class and method of ``uavcov.__all__`` and of every subpackage's
``__all__`` is called with valid arguments (a small fixture per callable), except for ONE
argument replaced by a hostile value (None, a string, True, -0.0, 1e300, NaN, inf, a huge
integer, empty, ragged, complex, string, object and boolean arrays, ...). A call passes when it
returns or raises an exception of :mod:`uavcov.errors`; the harness reports every other
outcome: another exception type (with its message and where it was raised), a crash of the
process (a Rust abort, a signal) or a hang (no answer within ``--timeout`` seconds). A call
that *accepts* NaN, inf, 1e300, complex or string arrays is listed apart, for review: some are
legitimate (a title, a free-form label), others are silent wrong answers. Those reviewed and
found right are in ``REVIEWED``, with the reason, and counted apart ("reviewed").

The calls run one at a time in a worker process (restarted after a crash or a hang) whose
working directory is a fresh temporary directory, with a 4 GB address-space limit (a huge
allocation becomes a MemoryError, not a swapping machine) and one Rust thread. The command line
is fuzzed too: every subcommand of ``uavcov --help`` with bad option values and corrupt input
files must exit with code 2 and one line on stderr, no traceback.

Run it from anywhere but the repository, in a fresh directory (calls write files there)::

    cd "$(mktemp -d)" && nice /work/wt/hostile3/.venv/bin/python \\
        /work/wt/hostile3/scripts/fuzz_public_api.py --out report.txt

``--only SUBSTRING`` restricts the run to the callables whose name contains it; ``--cli-only``
and ``--no-cli`` choose the parts; ``--list`` prints the cases without running them;
``--every-accepted`` lists every accepted case (a string, True or -1 taken), not only the
suspicious ones; ``--values "10**400;masked(3,3)"`` fuzzes with those hostile values only.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import json
import os
import pkgutil
import resource
import select
import subprocess
import sys
import tempfile
import time
import traceback
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

import uavcov

# Every public subpackage but the command line (fuzzed through its subcommands below).
SUBPACKAGES = tuple(m.name for m in pkgutil.iter_modules(uavcov.__path__) if m.ispkg and not m.name.startswith("_") and m.name != "cli")

# ---------------------------------------------------------------------------------------------
# Hostile values: made fresh for each call (a call may keep or change what it is given)

HOSTILE: dict[str, Callable[[], Any]] = {
    "None": lambda: None,
    "str": lambda: "abc",
    "True": lambda: True,
    "-0.0": lambda: -0.0,
    "0": lambda: 0,
    "-1": lambda: -1,
    "1e15": lambda: 1e15,
    "10**12": lambda: 10**12,
    "2**64": lambda: 2**64,
    "1e300": lambda: 1e300,
    "-1e300": lambda: -1e300,
    "nan": lambda: float("nan"),
    "inf": lambda: float("inf"),
    "-inf": lambda: float("-inf"),
    "[]": list,
    "{}": dict,
    "zeros(0,3)": lambda: np.zeros((0, 3)),
    "ragged": lambda: [[1.0, 2.0], [3.0]],
    "nan(3,3)": lambda: np.full((3, 3), np.nan),
    "1e300(3,3)": lambda: np.full((3, 3), 1e300),
    "ones(2,5)": lambda: np.ones((2, 5)),
    "complex(3,3)": lambda: np.ones((3, 3), complex),
    "strarr(1,3)": lambda: np.array([["a", "b", "c"]]),
    "objarr(1,3)": lambda: np.array([[1.0, None, 2.0]], dtype=object),
    "bool(3,3)": lambda: np.ones((3, 3), bool),
    # round 6: numbers numpy or Python hold that float() and int() do not take as they look
    "10**400": lambda: 10**400,
    "Fraction(10**400)": lambda: Fraction(10**400),
    "timedelta64": lambda: np.timedelta64(5, "s"),
    "emptystr": lambda: "",
    "masked(3,3)": lambda: np.ma.masked_array(np.ones((3, 3)), mask=np.eye(3, dtype=bool)),
    "timedelta(3,3)": lambda: np.ones((3, 3), "m8[s]"),
    "uint64max(3,3)": lambda: np.full((3, 3), 2**64 - 1, np.uint64),
    "5e-324": lambda: 5e-324,  # the smallest subnormal: a size, step or range whose derived values underflow
    "-5e-324": lambda: -5e-324,
    # round 7: numpy scalars and 0-d arrays, array layouts numpy keeps as views, dtypes that cast
    # silently, generators of other kinds, values whose arithmetic (a difference, a square) overflows
    "0d(2.0)": lambda: np.array(2.0),
    "0d(nan)": lambda: np.array(np.nan),
    "np.True_": lambda: np.True_,
    "np.int64(10**12)": lambda: np.int64(10**12),
    "2.5": lambda: 2.5,
    "longdouble(1e4000)": lambda: np.longdouble("1e4000"),
    "float16(3,3)": lambda: np.full((3, 3), 2.0, np.float16),
    "negstride(3,3)": lambda: np.arange(9.0)[::-1].reshape(3, 3) + 1.0,
    "noncontig(3,3)": lambda: (np.arange(18.0).reshape(3, 6) + 1.0)[:, ::2],
    "fortran(3,3)": lambda: np.asfortranarray(np.arange(9.0).reshape(3, 3) + 1.0),
    "readonly(3,3)": lambda: _read_only(np.arange(9.0).reshape(3, 3) + 1.0),
    "structured(3,)": lambda: np.zeros(3, dtype=[("x", "f8"), ("y", "f8"), ("z", "f8")]),
    "pm1e308(3,3)": lambda: np.array([[1e308, -1e308, 1e308], [-1e308, 1e308, -1e308], [1e308, 1e308, -1e308]]),
    "5e-324(3,3)": lambda: np.full((3, 3), 5e-324),
    "RandomState": lambda: np.random.RandomState(0),
    "SeedSequence": lambda: np.random.SeedSequence(0),
    "object()": object,
    "bytes": lambda: b"abc",
    "ctrlstr": lambda: "a\nb\x1b[31m\t",
}


def _read_only(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


# values no argument should take silently (a title or a label aside): accepted ones are listed
SUSPICIOUS = {
    "nan",
    "inf",
    "-inf",
    "nan(3,3)",
    "complex(3,3)",
    "objarr(1,3)",
    "1e300(3,3)",
    "timedelta64",
    "masked(3,3)",
    "timedelta(3,3)",
    "0d(nan)",
    "longdouble(1e4000)",
    "structured(3,)",
    "pm1e308(3,3)",
    "RandomState",
    "object()",
}

# Accepted suspicious values that were reviewed and are right answers: (callable, argument,
# hostile values) and why. They are counted as "reviewed", not listed for review again.
REVIEWED: dict[tuple[str, str], tuple[frozenset[str], str]] = {
    ("CAOSettings#step_size", "k"): (
        frozenset({"1e300(3,3)"}),
        "the step of iteration k is a formula of any finite k >= 0: at k = 1e300 it is the vanishing step the formula gives",
    ),
    ("facing_attitudes", "directions"): (
        frozenset({"1e300(3,3)", "pm1e308(3,3)"}),
        (
            "a direction's yaw and pitch do not depend on its length: 1e300 * (1, 1, 1) faces as (1, 1, 1) does, "
            "and (1e308, -1e308, 1e308) as (1, -1, 1)"
        ),
    ),
    ("observed_targets", "points"): (
        frozenset({"1e300(3,3)", "pm1e308(3,3)"}),
        "sensed points 1e300 m away are within no radius of a target: nothing observed is the right answer",
    ),
    ("sensed_coverage", "points"): (
        frozenset({"1e300(3,3)", "pm1e308(3,3)"}),
        "sensed points 1e300 m away are within no radius of a target: no coverage is the right answer",
    ),
    ("wrap_longitude", "lon"): (
        frozenset({"nan", "nan(3,3)", "1e300(3,3)", "masked(3,3)", "0d(nan)", "pm1e308(3,3)"}),
        (
            "documented: NaN (no data) passes through as NaN, and fmod reduces 1e300 exactly (a longitude within [-180, 180]); "
            "a masked longitude is no data, NaN"
        ),
    ),
    ("Terrain.from_grid", "z"): (
        frozenset({"masked(3,3)"}),
        "a masked height is no data, read as NaN (a hole in the grid), as the docstring says of NaN heights",
    ),
}

# ---------------------------------------------------------------------------------------------
# Fixtures: small valid objects, built once per worker (lazily) and copied where calls mutate


class Fixtures:
    """Small valid inputs of every kind, built on first use."""

    def __init__(self) -> None:
        self._cache: dict[str, Any] = {}

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_"):
            raise AttributeError(name)
        if name not in self._cache:
            self._cache[name] = getattr(self, "_make_" + name)()
        return self._cache[name]

    def _make_terrain(self) -> Any:
        import uavcov

        return uavcov.gaussian_hills(size=30, spacing=1, n_hills=2, rng=0)

    def _make_structure(self) -> Any:
        from uavcov.structures import girder_bridge

        return girder_bridge(rng=0)

    def _make_visibility(self) -> Any:
        import uavcov

        return uavcov.Visibility(self.terrain, 10.0, n_threads=1)

    def _make_uavs(self) -> np.ndarray:
        return np.array([[10.0, 10.0, 30.0], [20.0, 20.0, 30.0]])

    def _make_settings(self) -> Any:
        import uavcov

        return uavcov.MissionSettings(n_uavs=2, d_max=10.0, n_prior=10, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))

    def _make_mission(self) -> Any:
        import uavcov

        return uavcov.run_mission(self.terrain, self.settings, n_threads=1, rng=0)

    def _make_saved_mission(self) -> str:
        import uavcov

        return str(uavcov.save_mission(self.mission, Path(tempfile.mkdtemp(dir=".")) / "m.npz"))

    def _make_dem(self) -> Any:
        import uavcov

        return uavcov.sample_dem(window=(0, 10, 0, 10))

    def _make_plan_settings(self) -> Any:
        import uavcov

        return uavcov.PlanSettings(n_uavs=2, d_max=200.0, iterations=2, cao=uavcov.CAOSettings(n_candidates=10))

    def _make_flight_plan(self) -> Any:
        import uavcov

        return uavcov.plan(self.dem, self.plan_settings, rng=0, n_threads=1)

    def _make_problem(self) -> Any:
        from uavcov.cover import CoverageProblem

        return CoverageProblem(self.visibility, self.candidates, n_threads=1)

    def _make_candidates(self) -> np.ndarray:
        x, y = np.meshgrid(np.arange(3.0, 30, 8), np.arange(3.0, 30, 8))
        return np.column_stack([x.ravel(), y.ravel(), np.full(x.size, 32.0)])

    def _make_cvt_result(self) -> Any:
        from uavcov.placement import cvt

        return cvt(self.terrain, 3, rng=0, n_threads=1)

    def _make_structure_targets(self) -> Any:
        return self.structure.targets(2.0)

    def _make_structure_prior(self) -> Any:
        from uavcov.structures import sample_structure_prior

        return sample_structure_prior(self.structure, 200, rng=0)

    def _make_structure_plan(self) -> Any:
        import uavcov
        from uavcov.field import GeoAnchor, plan_structure

        settings = uavcov.MissionSettings(
            n_uavs=2,
            d_max=10.0,
            n_prior=50,
            iterations=2,
            cao=uavcov.CAOSettings(n_candidates=10),
            constraints=uavcov.Constraints(h_min=1.0, z_max=20.0, clearance="standoff"),
        )
        return plan_structure(self.structure, settings, GeoAnchor(-84.2, 36.5), rng=0, n_threads=1)

    def _make_flown(self) -> Any:
        from uavcov.sim import FlightSettings, SimSettings, fly_mission

        sim = SimSettings(flight=FlightSettings(dt=0.05, max_leg_s=2.0), render=False)
        return fly_mission(self.terrain, self.settings.with_changes(iterations=1), sim, rng=0)

    def _make_results_dir(self) -> str:
        from uavcov.experiments import experiment_specs, run_specs
        from uavcov.paper import TABLE1

        tiny = TABLE1.with_changes(
            **{"terrain.size": 40.0, "terrain.spacing": 4.0, "n_prior": 8, "iterations": 2, "cao.n_candidates": 20, "cvt.max_iterations": 5}
        )
        out = Path(tempfile.mkdtemp(dir=".")) / "runs"
        run_specs(experiment_specs(tiny, seeds=[0], team_sizes=[2], starts=["cvt"]), out=out, workers=1, n_threads=1, progress=False)
        return str(out)

    def _make_realistic_dir(self) -> str:
        from uavcov.paper._realistic import CONFIG, ROWS, _config
        from uavcov.sim import SimSettings

        # a realistic run started and not yet through its first flight: its config, no row yet
        out = Path(tempfile.mkdtemp(dir=".")) / "realistic"
        out.mkdir()
        (out / CONFIG).write_text(json.dumps(_config("realistic", 4, (0,), ("cvt",), ("exact",), 1, SimSettings())))
        (out / ROWS).write_text("")
        return str(out)

    def _make_geojson(self) -> str:
        path = Path(tempfile.mkdtemp(dir=".")) / "area.geojson"
        ring = [[-84.4, 36.45], [-84.38, 36.45], [-84.38, 36.47], [-84.4, 36.45]]
        path.write_text(json.dumps({"type": "Polygon", "coordinates": [ring]}))
        return str(path)

    def _make_obj(self) -> str:
        path = Path(tempfile.mkdtemp(dir=".")) / "tetra.obj"
        path.write_text("v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n")
        return str(path)

    def _make_tif(self) -> str:
        import rasterio
        from rasterio.transform import Affine

        path = Path(tempfile.mkdtemp(dir=".")) / "dem.tif"
        z = np.random.default_rng(0).random((12, 12)).astype("float32") * 10
        profile = {
            "driver": "GTiff",
            "height": 12,
            "width": 12,
            "count": 1,
            "dtype": "float32",
            "transform": Affine(30, 0, 500000, 0, -30, 4000000),
            "crs": "EPSG:32617",
        }
        with rasterio.open(path, "w", **profile) as dataset:
            dataset.write(z, 1)
        return str(path)

    def _make_sweep_toml(self) -> str:
        path = Path(tempfile.mkdtemp(dir=".")) / "sweep.toml"
        path.write_text(
            'name = "s"\nbase = "table1"\nseeds = [0]\nteam_sizes = [2]\nstarts = ["cvt"]\niterations = 1\nn_prior = 8\n'
            "[terrain]\nsize = 40.0\nspacing = 4.0\n[cao]\nn_candidates = 10\n"
        )
        return str(path)


def out_path(name: str) -> str:
    return str(Path(tempfile.mkdtemp(dir=".")) / name)


# ---------------------------------------------------------------------------------------------
# Targets: every public callable, with the valid arguments it is called with


def valid_arguments(f: Fixtures) -> dict[str, Callable[[], dict[str, Any]]]:
    """Valid keyword arguments of each target (its required ones, and a few small choices)."""
    import uavcov
    from uavcov import cover, experiments, paper, sim

    T = lambda: f.terrain  # noqa: E731
    pts = lambda: np.array([[5.0, 5.0, 30.0], [15.0, 12.0, 25.0]])  # noqa: E731
    xy = lambda: np.array([[5.0, 5.0], [15.0, 12.0]])  # noqa: E731
    sensor = lambda: uavcov.Sensor(10.0, camera=uavcov.Camera.from_fov(60, 45))  # noqa: E731
    return {
        # top level and engine
        "Terrain": lambda: {"vertices": np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), "faces": np.array([[0, 1, 2]])},
        "Terrain.from_mesh": lambda: {"mesh": f.terrain},
        "Terrain.from_grid": lambda: {"z": np.zeros((4, 5)), "spacing": 1.0},
        "Terrain#default_targets": dict,
        "Terrain#vertex_normals": dict,
        "Terrain#ground_height": lambda: {"xy": xy(), "n_threads": 1},
        "Terrain#clearance": lambda: {"points": pts(), "n_threads": 1},
        "Terrain#closest_point": lambda: {"points": pts(), "n_threads": 1},
        "Terrain#closest_face": lambda: {"points": pts(), "n_threads": 1},
        "Terrain#faces_at_closest": lambda: {"points": pts(), "n_threads": 1},
        "Terrain#distance": lambda: {"points": pts(), "n_threads": 1},
        "Terrain#inside": lambda: {"points": pts(), "n_threads": 1},
        "Terrain#segments_clear": lambda: {"a": pts(), "b": pts() + 1.0, "n_threads": 1},
        "Terrain#admissible_mask": lambda: {
            "current": pts(),
            "candidates": pts()[None] + 1.0,
            "bounds": (0.0, 0.0, 30.0, 30.0),
            "h_min": 2.0,
            "h_max": None,
            "z_max": 50.0,
            "d_safe": 1.0,
            "check_moves": True,
            "n_threads": 1,
        },
        "Terrain#admissible_check": lambda: {
            "bounds": (0.0, 0.0, 30.0, 30.0),
            "h_min": 2.0,
            "h_max": None,
            "z_max": 50.0,
            "d_safe": 1.0,
            "check_moves": True,
            "n_threads": 1,
        },
        "Targets": lambda: {"points": pts()},
        "Targets.from_points": lambda: {"points": pts()},
        "Visibility": lambda: {"terrain": T(), "d_max": 10.0, "n_threads": 1},
        "Visibility#coverage": lambda: {"uavs": f.uavs},
        "Visibility#seen": lambda: {"uavs": f.uavs},
        "Visibility#quality": lambda: {"uavs": f.uavs},
        "Visibility#quality_coverage": lambda: {"uavs": f.uavs},
        "Visibility#tracker": dict,
        "Visibility#per_uav": lambda: {"uavs": f.uavs},
        "Sensor": lambda: {"d_max": 10.0},
        "Camera": lambda: {
            "sensor_width_mm": 13.2,
            "sensor_height_mm": 8.8,
            "focal_length_mm": 8.8,
            "image_width_px": 4000,
            "image_height_px": 3000,
        },
        "Camera.from_fov": lambda: {"hfov_deg": 60.0, "vfov_deg": 45.0},
        "Camera#gsd_m": lambda: {"distance_m": 10.0},
        "Gimbal": dict,
        "Gimbal.preset": lambda: {"capability": "nadir"},
        "gaussian_hills": lambda: {"size": 30.0, "n_hills": 2, "rng": 0},
        "GeoDem#to_crs": lambda: {"local": pts()},
        "GeoDem#from_crs": lambda: {"points": f.dem.to_crs(pts())},
        "GeoDem#to_wgs84": lambda: {"local": pts()},
        "GeoDem#from_wgs84": lambda: {"lonlat": f.dem.to_wgs84(pts())},
        "GeoDem#crs_to_local_xy": lambda: {"xy": f.dem.to_crs(pts())[:, :2]},
        "read_dem": lambda: {"path": f.tif},
        "sample_dem": lambda: {"window": (0, 8, 0, 8)},
        "Constraints": dict,
        "Constraints.for_world": lambda: {"world": T()},
        "Constraints#resolve": lambda: {"world": T()},
        "Constraints#check_team": lambda: {"n_uavs": 2, "world": T()},
        "CVTSettings": dict,
        "CVTSettings#samples_for": lambda: {"n": 3},
        "CAOSettings": dict,
        "CAOSettings#regressors_for": lambda: {"n_uavs": 2},
        "CAOSettings#step_size": lambda: {"k": 3},
        "CAOSettings#resolved": lambda: {"n_uavs": 2},
        "EscapeSettings": dict,
        "StartSettings": dict,
        "StartSettings#height_above_reference": lambda: {"n": 2, "rng": np.random.default_rng(0)},
        "MissionSettings": lambda: {"n_uavs": 2, "d_max": 10.0, "iterations": 2},
        "MissionSettings#with_changes": lambda: {"iterations": 3},
        "MissionSettings.from_dict": lambda: {"data": f.settings.as_dict()},
        "run_mission": lambda: {"terrain": T(), "settings": f.settings, "n_threads": 1, "rng": 0},
        "mission_time": lambda: {"result": f.mission, "speed": 2.0},
        "save_mission": lambda: {"result": f.mission, "path": out_path("m.npz")},
        "load_mission": lambda: {"path": f.saved_mission},
        "PlanSettings": lambda: {"n_uavs": 2, "d_max": 200.0},
        "plan": lambda: {"dem": f.dem, "settings": f.plan_settings, "rng": 0, "n_threads": 1},
        "write_plan": lambda: {"flight_plan": f.flight_plan, "out": out_path("plan")},
        "camera_axes": lambda: {"yaw_deg": 10.0, "pitch_deg": -45.0},
        "gimbal_pitch_limits": lambda: {"capability": "nadir"},
        "pack_sensors": lambda: {
            "sensors": [sensor(), sensor()],
            "poses": np.array([[1.0, 2.0, 20.0, 0.0, -90.0], [5.0, 5.0, 20.0, 90.0, -45.0]]),
        },
        "as_mesh_surface": lambda: {"surface": T(), "purpose": "fuzz"},
        "degenerate_faces": lambda: {"vertices": np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), "faces": np.array([[0, 1, 2]])},
        "CoverageTracker": lambda: {"visibility": f.visibility},
        "CoverageTracker#coverage": lambda: {"uavs": f.uavs},
        "CoverageTracker#seen": lambda: {"uavs": f.uavs},
        "coverage": lambda: {"terrain": T(), "uavs": f.uavs, "d_max": 10.0, "n_threads": 1},
        # terrain
        "buildings_scene": lambda: {"size": 12.0, "n_buildings": 2, "rng": 0},
        "RasterGrid": lambda: {"transform": (1.0, 0.0, 0.0, 0.0, -1.0, 10.0), "shape": (10, 10)},
        "dem_from_array": lambda: {
            "z": np.arange(20.0).reshape(4, 5),
            "transform": (30.0, 0.0, 500000.0, 0.0, -30.0, 4000000.0),
            "crs": "EPSG:32617",
        },
        "read_mesh_dem": lambda: {"path": f.obj, "crs": "EPSG:32617"},
        "wrap_longitude": lambda: {"lon": np.array([10.0, 190.0])},
        "LocalFrame": lambda: {"origin": np.zeros(3), "factors": np.ones(3)},
        "LocalFrame#to_local": lambda: {"points": pts()},
        "LocalFrame#to_source": lambda: {"points": pts()},
        "metres_per_degree": lambda: {"latitude": 45.0},
        "HillsGenerator": lambda: {"size": 30.0},
        "HillsGenerator#make": lambda: {"seed": 0},
        "BuildingsGenerator": dict,
        "BuildingsGenerator#boxes": lambda: {"seed": 0},
        "BuildingsGenerator#make": lambda: {"seed": 0},
        "BuildingsGenerator#simplified_map": lambda: {"seed": 0},
        "load_mesh": lambda: {"path": f.obj},
        "MeshReport": dict,
        "Prior": lambda: {"points": np.array([[0.0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 3]])},
        "sample_prior": lambda: {"terrain": T(), "n": 10, "rng": 0},
        "sample_node_prior": lambda: {"nodes": T().vertices, "n": 10, "rng": 0},
        "approximate_surface": lambda: {"samples": np.array([[0.0, 0, 0], [10, 0, 1], [0, 10, 2], [10, 10, 3]])},
        "approximation_error": lambda: {"truth": T(), "approx": T()},
        # structures
        "Structure#part_index": lambda: {"name": f.structure.part_names[0]},
        "Structure#face_mask": dict,
        "Structure#targets": lambda: {"spacing": 2.0},
        "Structure#coverage_by_part": lambda: {"seen": np.ones(len(f.structure_targets.points), bool), "targets": f.structure_targets},
        "girder_bridge": lambda: {"rng": 0},
        "facade": lambda: {"rng": 0},
        "load_structure": lambda: {"path": f.obj},
        "height_field_violation": lambda: {"structure": f.structure},
        "StructurePrior": lambda: {"points": np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]), "normals": None, "kind": "points"},
        "StructurePrior#behind": lambda: {"points": pts()},
        "sample_structure_prior": lambda: {"structure": f.structure, "n": 50, "rng": 0},
        "coarse_structure_prior": lambda: {"structure": f.structure},
        "reconstruct_structure": lambda: {"prior": f.structure_prior, "rng": 0},
        "reconstruction_error": lambda: {"truth": f.structure, "approx": f.structure.surface, "n_samples": 500},
        # limits
        "feasibility": lambda: {"constraints": uavcov.Constraints(), "world": T(), "n_threads": 1},
        "closest_admissible": lambda: {"constraints": uavcov.Constraints(), "world": T(), "x": pts()},
        # cover
        "GreedySettings": dict,
        "viewpoint_lattice": lambda: {
            "world": T(),
            "constraints": uavcov.Constraints(),
            "settings": cover.GreedySettings(spacing=10.0),
            "n_threads": 1,
        },
        "viewpoint_offsets": lambda: {
            "world": f.structure.surface,
            "constraints": uavcov.Constraints(h_min=1.0, clearance="standoff"),
            "distances": (3.0,),
            "spacing": 4.0,
            "n_threads": 1,
        },
        "closest_faces": lambda: {"surface": T(), "points": pts()},
        "surface_normals": lambda: {"surface": T(), "points": pts()},
        "CoverageProblem": lambda: {"visibility": f.visibility, "candidates": f.candidates, "n_threads": 1},
        "CoverageProblem#seen": lambda: {"c": 0},
        "CoverageProblem#dual_bound": lambda: {"k": 2},
        "CoverageProblem#certified_bound": lambda: {"k": 2},
        "CoverageProblem#greedy": lambda: {"k": 2},
        "CoverageProblem#bound": lambda: {"positions": f.uavs},
        "greedy_placement": lambda: {"visibility": f.visibility, "candidates": f.candidates, "k": 2, "n_threads": 1},
        "coverage_bound": lambda: {"visibility": f.visibility, "positions": f.uavs, "candidates": f.candidates, "n_threads": 1},
        "exact_placement": lambda: {"problem": f.problem, "k": 2, "time_limit": 5.0},
        # placement
        "cvt": lambda: {"surface": T(), "n": 3, "rng": 0, "n_threads": 1},
        "CVTResult#regions": lambda: {"points": pts(), "n_threads": 1},
        "fit_footprints": lambda: {
            "surface": T(),
            "generators": f.cvt_result.generators,
            "sensor": sensor(),
            "attitudes": np.array([[0.0, -90.0]] * 3),
            "heights": (5.0, 20.0),
            "n_threads": 1,
        },
        "start_configuration": lambda: {
            "spec": uavcov.StartSettings(),
            "approximation": T(),
            "terrain": T(),
            "n": 2,
            "rng": 0,
            "n_threads": 1,
        },
        "standoff_start": lambda: {"surface": f.structure.surface, "n": 2, "standoff": 3.0, "rng": 0, "n_threads": 1},
        "facing_attitudes": lambda: {"directions": np.array([[1.0, 0, 0], [0, 0, -1]])},
        # optim
        "cao": lambda: {
            "measure": lambda x: -float(np.sum(x**2)),
            "x0": np.ones((2, 3)),
            "feasible": None,
            "iterations": 3,
            "settings": uavcov.CAOSettings(n_candidates=10),
            "rng": 0,
        },
        "per_robot_cao": lambda: {
            "measure": lambda x: (-float(np.sum(x**2)), -np.sum(x**2, axis=1)),
            "x0": np.ones((2, 3)),
            "feasible": None,
            "iterations": 3,
            "settings": uavcov.CAOSettings(n_candidates=10),
            "rng": 0,
        },
        "standard_normal": lambda: {"rng": np.random.default_rng(0), "shape": (2, 3)},
        "cao_preset": lambda: {"name": "paper"},
        # experiments
        "Experiment#mission_settings": lambda: {"n_uavs": 2, "start": "cvt"},
        "Experiment#known": lambda: {"seed": 0},
        "Experiment#with_changes": lambda: {"iterations": 3},
        "experiment_specs": lambda: {"experiment": paper.TABLE1, "seeds": [0], "team_sizes": [2], "starts": ["cvt"]},
        "experiments_hash": lambda: {"experiments": {"table1": paper.TABLE1}},
        "parse_seeds": lambda: {"text": "0-3,7"},
        "ExecutionPlan": lambda: {"workers": 1, "n_threads": 1},
        "plan_execution": lambda: {"workers": 1, "n_threads": 1, "cores": 2},
        "local_executor": lambda: {"workers": 1},
        "ResultsFolder": lambda: {"path": out_path("folder")},
        "read_runs": lambda: {"path": str(Path(f.results_dir) / "runs.csv")},
        "summarise": lambda: {"rows": experiments.read_runs(Path(f.results_dir) / "runs.csv")},
        "finished_rows": lambda: {"rows": experiments.read_runs(Path(f.results_dir) / "runs.csv")},
        "row_number": lambda: {"row": experiments.read_runs(Path(f.results_dir) / "runs.csv")[0], "column": "n_uavs", "kind": int},
        "check_run_options": lambda: {
            "resume": False,
            "save_runs": True,
            "exclusive": False,
            "progress": None,
            "command": "fuzz",
            "execution": {"workers": 1},
        },
        "load_sweep_config": lambda: {"path": f.sweep_toml, "bases": dict(paper.EXPERIMENTS)},
        "parse_sweep_config": lambda: {
            "data": {"base": "table1", "seeds": [0], "team_sizes": [2], "starts": ["cvt"]},
            "bases": dict(paper.EXPERIMENTS),
        },
        # field
        "AreaOfInterest#contains": lambda: {"xy": xy(), "dem": f.dem},
        "AreaOfInterest#local_rings": lambda: {"dem": f.dem},
        "bbox_area": lambda: {"xmin": -84.4, "ymin": 36.45, "xmax": -84.38, "ymax": 36.47},
        "read_area": lambda: {"path": f.geojson},
        "check_plan_folder": lambda: {"out": out_path("plan")},
        "GeoAnchor": lambda: {"longitude": -84.2, "latitude": 36.5},
        "plan_structure": lambda: {
            "structure": f.structure,
            "settings": f.structure_plan.result.settings,
            "anchor": __import__("uavcov.field", fromlist=["GeoAnchor"]).GeoAnchor(-84.2, 36.5),
            "rng": 0,
            "n_threads": 1,
        },
        "write_structure_plan": lambda: {"plan": f.structure_plan, "out": out_path("splan")},
        "write_seen_ply": lambda: {
            "path": out_path("seen.ply"),
            "targets": f.structure_targets,
            "seen_count": np.ones(len(f.structure_targets.points), int),
        },
        "StructureFlight#route_wgs84": lambda: {"uav": 0},
        # sim
        "fly_mission": lambda: {
            "terrain": T(),
            "settings": f.settings.with_changes(iterations=1),
            "sim": sim.SimSettings(flight=sim.FlightSettings(dt=0.05, max_leg_s=2.0), render=False),
            "rng": 0,
        },
        "FlownMission#time_to_fraction": lambda: {"fraction": 0.5},
        "SimSettings": dict,
        "SimSettings#camera_for": lambda: {"d_max": 10.0},
        "SimSettings#flight_limits": lambda: {"planned": uavcov.Constraints()},
        "FlightSettings": dict,
        "Team.hovering": lambda: {"positions": pts(), "settings": sim.FlightSettings(dt=0.05, max_leg_s=2.0), "terrain": T(), "rng": 0},
        "DrydenGusts": lambda: {"mean": (1.0, 0.0, 0.0), "sigma": (0.5, 0.5, 0.5), "dt": 0.01, "altitude": 10.0, "rng": 0},
        "dryden_scales": lambda: {"altitude": 10.0},
        "vehicle_parameters": lambda: {"name": "hummingbird"},
        "DepthCamera": lambda: {"width": 8, "height": 6, "fov_deg": (60.0, 45.0), "range_m": 10.0},
        "DepthCamera.omnidirectional": lambda: {"range_m": 10.0, "resolution": 8},
        "DepthCamera#render": lambda: {
            "terrain": T(),
            "position": np.array([10.0, 10.0, 30.0]),
            "rotation": np.eye(3),
            "rng": 0,
            "n_threads": 1,
        },
        "camera_rotation": lambda: {"quaternion": np.array([0.0, 0.0, 0.0, 1.0]), "camera": sim.DepthCamera(8, 6, (60.0, 45.0), 10.0)},
        "VoxelMap": lambda: {"size": 0.5},
        "VoxelMap#add": lambda: {"points": pts()},
        "observed_targets": lambda: {"targets": T().default_targets(), "points": pts(), "radius": 1.0},
        "sensed_coverage": lambda: {"targets": T().default_targets(), "points": pts(), "radius": 1.0},
        "save_flown": lambda: {"flown": f.flown, "path": out_path("f.npz"), "terrain": T()},
        "load_flown": lambda: {"path": str(sim.save_flown(f.flown, out_path("f.npz"), f.terrain))},
        "is_flown_file": lambda: {"path": f.saved_mission},
        # paper
        "reproduce": lambda: {
            "name": "example",
            "out": out_path("r"),
            "seeds": "0",
            "iterations": 1,
            "workers": 1,
            "n_threads": 1,
            "save_runs": False,
            "progress": False,
        },
        "speed": lambda: {"rows": experiments.read_runs(Path(f.results_dir) / "runs.csv")},
        "PublishedValue": lambda: {"mean": 0.5, "sigma": 0.1},
        "StructuresExperiment": dict,
        "write_realistic_report": lambda: {"folder": f.realistic_dir},
        # records a user may build
        "Structure": lambda: {
            "name": "s",
            "surface": T(),
            "face_parts": np.zeros(len(T().faces), np.int64),
            "part_names": ("ground",),
            "ground_part": 0,
        },
        "StructureTargets": lambda: {
            "points": pts(),
            "weights": np.ones(2),
            "normals": np.array([[0.0, 0, 1], [0, 0, 1]]),
            "parts": np.zeros(2, np.int64),
            "part_names": ("a",),
        },
        "RasterGrid#node_of_pixel": lambda: {"rows": np.array([0, 1]), "cols": np.array([2, 3])},
        "RasterGrid#pixel_of_node": lambda: {"i": np.array([0, 1]), "j": np.array([2, 3])},
        "check_flight": lambda: {
            "terrain": T(),
            "constraints": uavcov.Constraints().resolve(T()),
            "positions": np.array([[[10.0, 10, 30], [20, 20, 30]]] * 3),
            "leg_of_state": np.zeros(3, np.int64),
            "starts": np.array([[[10.0, 10, 30], [20, 20, 30]]]),
            "goals": np.array([[[10.0, 10, 30], [20, 20, 30]]]),
        },
        "Team#fly": lambda: {"waypoints": pts() + 0.5},
        "DrydenGusts#update": lambda: {"t": 0.1, "position": np.array([1.0, 2.0, 10.0])},
        "AreaOfInterest": lambda: {"polygons": ((np.array([[-84.4, 36.45], [-84.38, 36.45], [-84.38, 36.47]]),),)},
        "RunSpec": lambda: {"experiment": paper.TABLE1, "seed": 0, "n_uavs": 2, "start": "cvt"},
        "hover_rotor_speed": lambda: {"params": sim.vehicle_parameters("hummingbird")},
        "Experiment": lambda: {
            "name": "e",
            "terrain": paper.TABLE1.terrain,
            "mission": paper.TABLE1.mission,
            "team_sizes": (2,),
            "starts": ("cvt",),
        },
        "ResultsFolder#write_text": lambda: {"name": "a.txt", "text": "x"},
        "ResultsFolder#write_csv": lambda: {"name": "a.csv", "header": ["a"], "rows": [[1]]},
        "ResultsFolder#run_file": lambda: {"run_id": "abc"},
        # plotting
        "footprints": lambda: {"terrain": T(), "poses": np.array([[10.0, 10.0, 20.0, 0.0, -90.0]]), "sensors": [sensor()]},
        "plot_camera_views": lambda: {
            "terrain": T(),
            "poses": np.array([[10.0, 10.0, 20.0, 0.0, -90.0]]),
            "sensors": [sensor()],
            "out": out_path("v.png"),
        },
        "plot_approximation": lambda: {"source": f.mission, "out": out_path("a.png")},
        "plot_coverage_curves": lambda: {"results": [f.mission], "out": out_path("c.png")},
        "plot_coverage_map": lambda: {"source": f.mission, "view": "top", "out": out_path("m.png"), "raster": 40},
        "plot_cvt": lambda: {"source": f.mission, "out": out_path("cvt.png")},
        "plot_directory": lambda: {"directory": f.results_dir, "out": out_path("figs"), "animation": False, "max_runs": 1},
        "report_figures": lambda: {"folder": f.results_dir},
        "plot_point_cloud": lambda: {"source": f.mission, "out": out_path("p.png")},
        "plot_table1": lambda: {"rows": experiments.read_runs(Path(f.results_dir) / "runs.csv"), "out": out_path("t.png")},
        "plot_structure_seen": lambda: {
            "surface": f.structure.surface,
            "seen": np.ones(len(f.structure.surface.faces), bool),
            "out": out_path("s.png"),
        },
        "view": lambda: {"result": f.mission},
        "write_view": lambda: {"result": f.mission, "out": out_path("v.html")},
        "find_run": lambda: {"path": f.results_dir},
        "animate_mission": lambda: {"source": f.mission, "out": out_path("a.gif"), "max_frames": 2, "raster": 20, "dpi": 20.0},
    }


# instances the methods are called on
def instances(f: Fixtures) -> dict[str, Callable[[], Any]]:
    import uavcov
    from uavcov import paper, sim, terrain

    return {
        "Terrain": lambda: f.terrain,
        "Visibility": lambda: f.visibility,
        "Camera": lambda: uavcov.Camera.from_fov(60, 45),
        "GeoDem": lambda: f.dem,
        "Constraints": uavcov.Constraints,
        "CVTSettings": uavcov.CVTSettings,
        "CAOSettings": uavcov.CAOSettings,
        "StartSettings": uavcov.StartSettings,
        "MissionSettings": lambda: f.settings,
        "CoverageTracker": lambda: f.visibility.tracker(),  # noqa: PLW0108 - built on first use only
        "LocalFrame": terrain.LocalFrame.identity,
        "HillsGenerator": lambda: terrain.HillsGenerator(size=30.0, n_hills=2),
        "BuildingsGenerator": lambda: terrain.BuildingsGenerator(size=12.0, n_buildings=2),
        "Structure": lambda: f.structure,
        "StructurePrior": lambda: f.structure_prior,
        "CoverageProblem": lambda: f.problem,
        "CVTResult": lambda: f.cvt_result,
        "Experiment": lambda: paper.TABLE1,
        "AreaOfInterest": lambda: __import__("uavcov.field", fromlist=["bbox_area"]).bbox_area(-84.4, 36.45, -84.38, 36.47),
        "StructureFlight": lambda: f.structure_plan.flight,
        "RasterGrid": lambda: terrain.RasterGrid((1.0, 0.0, 0.0, 0.0, -1.0, 10.0), (10, 10)),
        "Team": lambda: sim.Team.hovering(
            np.array([[5.0, 5.0, 30.0], [15.0, 12.0, 25.0]]), sim.FlightSettings(dt=0.05, max_leg_s=2.0), f.terrain, rng=0
        ),
        "DrydenGusts": lambda: sim.DrydenGusts((1.0, 0.0, 0.0), (0.5, 0.5, 0.5), 0.01, 10.0, 0),
        "ResultsFolder": lambda: __import__("uavcov.experiments", fromlist=["ResultsFolder"]).ResultsFolder(out_path("folder")),
        "FlownMission": lambda: f.flown,
        "SimSettings": sim.SimSettings,
        "VoxelMap": lambda: sim.VoxelMap(0.5),
        "DepthCamera": lambda: sim.DepthCamera(8, 6, (60.0, 45.0), 10.0),
    }


# never called: they start pools, clusters or whole experiments, or take no user input
SKIPPED = {
    "reproduce_all": "runs every experiment (hours)",
    "ablate": "runs the ablation study (hours)",
    "reproduce_structures": "runs the structures experiment (hours)",
    "reproduce_realistic": "runs the realistic experiment (hours)",
    "reproduce_flown_table1": "runs the flown experiment (hours)",
    "oracle": "runs Table 1's oracle over an experiment (minutes per call)",
    "run_sweep": "fuzzed through the CLI's sweep command",
    "run_specs": "fuzzed through reproduce and the CLI",
    "dask_executor": "starts a Dask cluster",
    "available_cores": "takes no argument",
    "RunSpec#run": "runs one mission of an experiment (covered by run_mission)",
}


def targets() -> list[tuple[str, str, Callable[[Fixtures], Callable[..., Any]]]]:
    """``(id, module, getter)`` of every public callable; ids: ``name``, ``Class.static``, ``Class#method``."""
    found: dict[str, tuple[str, Callable[[Fixtures], Callable[..., Any]]]] = {}
    modules = ["uavcov"] + [f"uavcov.{name}" for name in SUBPACKAGES]
    for module_name in modules:
        try:
            module = importlib.import_module(module_name)
        except ImportError:
            continue  # an optional extra that is not installed
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.ismodule(obj) or not callable(obj) or name in found:
                continue
            found[name] = (module_name, lambda f, obj=obj: obj)
            if not inspect.isclass(obj):
                continue
            for attr, raw in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if isinstance(raw, (classmethod, staticmethod)):
                    found[f"{name}.{attr}"] = (module_name, lambda f, obj=obj, attr=attr: getattr(obj, attr))
                elif inspect.isfunction(raw):
                    found[f"{name}#{attr}"] = (module_name, lambda f, name=name, attr=attr: getattr(instances(f)[name](), attr))
    return [(key, module, getter) for key, (module, getter) in found.items()]


def parameters(getter_obj: Any, key: str) -> list[str]:
    """The names of the arguments one can fuzz (no ``self``, ``*args``, ``**kwargs``, callbacks)."""
    try:
        signature = inspect.signature(getter_obj)
    except (TypeError, ValueError):
        return []
    names = []
    for name, parameter in signature.parameters.items():
        if name in ("self", "cls") or parameter.kind in (parameter.VAR_POSITIONAL, parameter.VAR_KEYWORD) or name.startswith("_"):
            continue
        if name in ("ax", "progress", "executor", "on_result", "measure", "figures", "keep_out"):
            continue  # callables and matplotlib axes: a Python contract, not user data
        names.append(name)
    return names


# ---------------------------------------------------------------------------------------------
# The worker: runs one case at a time, answers one JSON line per case


def run_case(fixtures: Fixtures, key: str, getter: Callable[[Fixtures], Any], param: str | None, hostile: str | None) -> dict[str, Any]:
    from uavcov.errors import UavcovError

    try:
        arguments = valid_arguments(fixtures)[key]()
        call = getter(fixtures)
    except Exception as exc:  # noqa: BLE001 - the fixture itself failed: a harness problem, reported as such
        return {"outcome": "fixture", "type": type(exc).__name__, "message": str(exc)[:300]}
    if param is not None and hostile is not None:
        arguments = dict(arguments)
        arguments[param] = HOSTILE[hostile]()
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            call(**arguments)
    except UavcovError as exc:
        return {"outcome": "refused", "type": type(exc).__name__, "message": str(exc)[:300]}
    except BaseException as exc:  # noqa: BLE001 - the harness reports every other exception
        frames = traceback.extract_tb(exc.__traceback__)
        where = next((f"{Path(fr.filename).name}:{fr.lineno}" for fr in reversed(frames) if "uavcov" in fr.filename), "")
        return {"outcome": "other", "type": type(exc).__name__, "message": str(exc)[:300], "where": where}
    finally:
        import matplotlib as mpl

        if "matplotlib.pyplot" in sys.modules:
            mpl.pyplot.close("all")
    return {"outcome": "accepted"}


def worker() -> None:
    """Read ``key param hostile`` lines, answer one JSON line each."""
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    fixtures = Fixtures()
    table = {key: getter for key, _, getter in targets()}
    for line in sys.stdin:
        key, param, hostile = json.loads(line)
        answer = run_case(fixtures, key, table[key], param, hostile)
        sys.stdout.write(json.dumps(answer) + "\n")
        sys.stdout.flush()


class Worker:
    """A worker process, restarted after a crash or a hang."""

    def __init__(self, timeout: float) -> None:
        self.timeout = timeout
        self.process: subprocess.Popen[str] | None = None

    def start(self) -> subprocess.Popen[str]:
        if self.process is None or self.process.poll() is not None:
            env = dict(os.environ, RAYON_NUM_THREADS="1", MPLBACKEND="Agg", OMP_NUM_THREADS="1")
            self.process = subprocess.Popen(
                [sys.executable, __file__, "--worker"],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.DEVNULL,
                text=True,
                env=env,
            )
        return self.process

    def ask(self, case: tuple[str, str | None, str | None], timeout: float) -> dict[str, Any]:
        process = self.start()
        assert process.stdin is not None
        assert process.stdout is not None
        process.stdin.write(json.dumps(case) + "\n")
        process.stdin.flush()
        ready, _, _ = select.select([process.stdout], [], [], timeout)
        if not ready:
            process.kill()
            process.wait()
            return {"outcome": "hang", "message": f"no answer in {timeout:.0f} s"}
        line = process.stdout.readline()
        if not line:
            code = process.wait()
            return {"outcome": "crash", "message": f"worker exited with code {code}"}
        return json.loads(line)

    def close(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()


def fuzz_api(
    only: str | None, timeout: float, listing: bool, report: list[str], every_accepted: bool = False, values: tuple[str, ...] = ()
) -> dict[str, int]:
    fixtures = Fixtures()
    args_table = valid_arguments(fixtures)
    counts = {"callables": 0, "cases": 0, "refused": 0, "accepted": 0, "defects": 0, "review": 0, "reviewed": 0}
    worker_process = Worker(timeout)
    no_fixture = []
    try:
        for key, module, _getter in targets():
            if only and only not in key:
                continue
            if key in SKIPPED or key.split("#")[0].split(".")[0] in SKIPPED:
                report.append(f"SKIP {key}: {SKIPPED.get(key, SKIPPED.get(key.split('#')[0], ''))}")
                continue
            if key not in args_table:
                no_fixture.append(key)
                continue
            owner = key.replace("#", ".").split(".")
            obj = importlib.import_module(module)
            for part in owner:
                obj = getattr(obj, part)
            names = parameters(obj, key)
            counts["callables"] += 1
            cases: list[tuple[str, str | None, str | None]] = [(key, None, None)]
            cases += [(key, name, hostile) for name in names for hostile in (values or tuple(HOSTILE))]
            if listing:
                print(key, names)
                continue
            baseline = worker_process.ask(cases[0], timeout * 3)
            if baseline["outcome"] != "accepted":
                report.append(f"FIXTURE {key}: valid call gives {baseline}")
                continue
            for case in cases[1:]:
                counts["cases"] += 1
                answer = worker_process.ask(case, timeout)
                outcome = answer["outcome"]
                label = f"{module}.{key}({case[1]}={case[2]})"
                if outcome == "refused":
                    counts["refused"] += 1
                elif outcome == "accepted":
                    counts["accepted"] += 1
                    reviewed = REVIEWED.get((key, case[1] or ""))
                    if case[2] in SUSPICIOUS and reviewed is not None and case[2] in reviewed[0]:
                        counts["reviewed"] += 1
                    elif case[2] in SUSPICIOUS:
                        counts["review"] += 1
                        report.append(f"ACCEPTED {label}")
                    elif every_accepted:
                        report.append(f"ACCEPTED (not suspicious) {label}")
                else:
                    counts["defects"] += 1
                    report.append(
                        f"{outcome.upper()} {label}: {answer.get('type', '')} {answer.get('message', '')!r} {answer.get('where', '')}"
                    )
            print(f"{key}: {len(cases) - 1} cases", file=sys.stderr, flush=True)
    finally:
        worker_process.close()
    if no_fixture:
        report.append("NO FIXTURE (not fuzzed): " + ", ".join(no_fixture))
    return counts


# ---------------------------------------------------------------------------------------------
# The command line


MESH_FILES = ("cut.ply", "huge.ply", "cut.stl", "nan.stl")
"""Corrupt mesh files of the formats trimesh reads besides OBJ (written by ``cli_cases``)."""


def cli_cases(workdir: Path) -> list[list[str]]:
    """Bad option values and corrupt files for every subcommand."""
    files = {
        "empty.toml": "",  # documented: the first base experiment, all defaults (a real run), so not run alone
        "bad.toml": "name = [\n",
        "wrong.toml": 'name = 3\nbase = "nope"\n',
        "huge.toml": 'base = "table1"\nseeds = [0]\nteam_sizes = [100000000]\nstarts = ["cvt"]\n',
        "nan.toml": 'base = "table1"\nseeds = [0]\nteam_sizes = [2]\nstarts = ["cvt"]\nd_max = nan\n',
        "neg.toml": 'base = "table1"\nseeds = [-1]\nteam_sizes = [2]\nstarts = ["cvt"]\n',
        "big.toml": 'base = "table1"\nseeds = [0]\nteam_sizes = [2]\nstarts = ["cvt"]\nd_max = 1e300\niterations = 1\n',
        "area.geojson": '{"type": "Polygon", "coordinates": [[[0, 0], [1e300, 0], [0, 1]]]}',
        "bad.geojson": "{not json",
        "nanarea.geojson": '{"type": "Polygon", "coordinates": [[[NaN, 0], [1, 0], [0, 1], [NaN, 0]]]}',
        "dem.tif": "II*\x00garbage",
        "mesh.obj": "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n",
        "empty.obj": "",
        "cut.ply": "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n",
        "huge.ply": "ply\nformat ascii 1.0\nelement vertex 3000000000\n" + "property float x\n" * 3 + "end_header\n0 0 0\n",
        "cut.stl": "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n",
        "nan.stl": "solid t\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
        "run.npz": "PK\x03\x04truncated",
        "run.json": "[]",
    }
    for name, text in files.items():
        (workdir / name).write_text(text)
    (workdir / "runs").mkdir(exist_ok=True)
    (workdir / "runs" / "runs.csv").write_text("run_id,experiment\nx,y\n")
    (workdir / "badruns").mkdir(exist_ok=True)
    (workdir / "badruns" / "runs.csv").write_bytes(b"\xff\xfe\x00garbage")
    # round 6: files that are no regular file (a read would block or never end), a PLY shorter
    # than its header, a folder whose config.json is a FIFO
    special = {"fifo.toml", "fifo.obj", "fifo.ply", "fifo.geojson", "fifo.tif"} if hasattr(os, "mkfifo") else set()
    for name in special:
        if not (workdir / name).exists():
            os.mkfifo(workdir / name)
    (workdir / "short.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
    )
    (workdir / "fifofolder").mkdir(exist_ok=True)
    if special and not (workdir / "fifofolder" / "config.json").exists():
        os.mkfifo(workdir / "fifofolder" / "config.json")
    sample = ["plan", "--sample", "--window", "0,10,0,10", "--iterations", "1", "--threads", "1", "--uavs", "2", "--d-max", "200"]
    cases: list[list[str]] = [
        [],
        ["nope"],
        ["demo", "--iterations", "-1"],
        ["demo", "--iterations", "1e300"],
        ["demo", "--seed", "nan"],
        ["demo", "--threads", "0"],
        ["demo", "--threads", "100000"],
        ["demo", "--iterations", "99999999999999999999"],
        ["demo", "--out", "/dev/null/x", "--iterations", "1", "--no-plots"],
        ["reproduce", "nope"],
        ["reproduce", "table1", "--seeds", "a-b"],
        ["reproduce", "table1", "--seeds", "5-1"],
        ["reproduce", "table1", "--seeds", "0-99999999999"],
        ["reproduce", "table1", "--team-sizes", "0"],
        ["reproduce", "table1", "--team-sizes", "99999999"],
        ["reproduce", "table1", "--starts", "nope"],
        ["reproduce", "table1", "--iterations", "-5"],
        ["reproduce", "table1", "--workers", "0"],
        ["reproduce", "table1", "--workers", "nan"],
        ["reproduce", "realistic", "--standoff", "nan"],
        ["reproduce", "realistic", "--standoff", "-1"],
        ["reproduce", "realistic", "--measurements", "nope"],
        ["reproduce", "table1", "--seeds", ""],
        ["reproduce", "table1", "--seeds", "-1"],
        ["reproduce", "table1", "--team-sizes", "2,,3", "--seeds", "0", "--iterations", "0", "--no-plots", "--workers", "1"],
        ["sweep", "missing.toml"],
        ["sweep", "bad.toml"],
        ["sweep", "wrong.toml"],
        ["sweep", "huge.toml"],
        ["sweep", "nan.toml"],
        ["sweep", "neg.toml"],
        ["sweep", "big.toml", "--out", "bigout", "--workers", "1", "--threads", "1", "--no-progress"],
        ["sweep", "dem.tif"],
        ["sweep", "runs"],
        ["sweep", "empty.toml", "--scheduler-timeout", "nan"],
        ["sweep", "empty.toml", "--dask-workers", "-1"],
        ["plot", "missing"],
        ["plot", "runs"],
        ["plot", "badruns"],
        ["plot", "empty.toml"],
        ["plot", "runs", "--max-runs", "-1"],
        ["plot", "runs", "--max-runs", "1e300"],
        ["view", "missing.npz"],
        ["view", "run.npz"],
        ["view", "run.json"],
        ["view", "runs"],
        ["view", "badruns"],
        ["view", "empty.toml"],
        ["view", "run.npz", "--max-vertices", "0"],
        ["view", "run.npz", "--max-frames", "-1"],
        ["plan"],
        ["plan", "missing.tif", "--uavs", "2", "--d-max", "10"],
        ["plan", "dem.tif", "--uavs", "2", "--d-max", "10"],
        ["plan", "mesh.obj", "--uavs", "2", "--d-max", "10", "--crs", "EPSG:32617"],
        ["plan", "empty.obj", "--uavs", "2", "--d-max", "10", "--crs", "EPSG:32617"],
        sample[:-4] + ["--uavs", "0", "--d-max", "10"],
        sample[:-4] + ["--uavs", "2", "--d-max", "nan"],
        sample[:-4] + ["--uavs", "2", "--d-max", "1e300"],
        sample[:-4] + ["--uavs", "2", "--d-max", "-0"],
        sample[:-4] + ["--uavs", "99999999", "--d-max", "100"],
        sample + ["--window", "0,0,0,0"],
        sample + ["--window", "a,b,c,d"],
        sample + ["--window", "0,99999999999,0,5"],
        sample + ["--stride", "0"],
        sample + ["--stride", "99999999999"],
        sample + ["--aoi", "area.geojson"],
        sample + ["--aoi", "bad.geojson"],
        sample + ["--aoi", "nanarea.geojson"],
        sample + ["--bbox", "nan,0,1,1"],
        sample + ["--bbox", "1,1,0,0"],
        sample + ["--bbox", "1e300,1e300,1e301,1e301"],
        sample + ["--takeoff", "1e300,0"],
        sample + ["--takeoff", "nan,nan"],
        sample + ["--camera", "0,0"],
        sample + ["--camera", "180,180"],
        sample + ["--camera", "nan,1"],
        sample + ["--attitude", "nan,-90"],
        sample + ["--attitude", "1e300,-90"],
        sample + ["--pitch-range", "10,-10"],
        sample + ["--pitch-range", "nan,0"],
        sample + ["--h-min", "-1"],
        sample + ["--h-min", "1e300"],
        sample + ["--h-max", "nan"],
        sample + ["--hold", "-1"],
        sample + ["--hold", "inf"],
        sample + ["--prior", "-3"],
        sample + ["--prior", "nope"],
        sample + ["--prior", "99999999999"],
        sample + ["--seed", "-1"],
        sample + ["--separation", "nan"],
        sample + ["--separation", "1e300"],
        sample + ["--out", "/dev/null/x"],
        sample + ["--crs", "EPSG:999999"],
        sample + ["--coords", "dem", "--bbox", "0,0,1e300,1e300"],
        ["plan", "--structure", "nope", "--uavs", "2", "--d-max", "10"],
        ["plan", "--structure", "girder_bridge", "--uavs", "2", "--d-max", "10", "--anchor", "nan,0,0"],
        ["plan", "--structure", "girder_bridge", "--uavs", "2", "--d-max", "10", "--anchor", "500,100,0"],
        ["plan", "--structure", "empty.obj", "--uavs", "2", "--d-max", "10", "--anchor", "0,0,0"],
        ["plan", "--structure", "mesh.obj", "--uavs", "2", "--d-max", "10", "--anchor", "0,0,0"],
        *(["plan", name, "--uavs", "2", "--d-max", "10", "--crs", "EPSG:32617"] for name in MESH_FILES),
        *(["plan", "--structure", name, "--uavs", "2", "--d-max", "10", "--anchor", "0,0,0"] for name in MESH_FILES),
        ["view", "runs", "--run", "../../etc"],
        *(["sweep", name] for name in sorted(special) if name.endswith(".toml")),
        ["sweep", "/dev/zero"],
        *(
            ["plan", name, "--uavs", "2", "--d-max", "10", "--crs", "EPSG:32617"]
            for name in ("fifo.obj", "fifo.ply", "fifo.tif", "short.ply")
            if name in special or name == "short.ply"
        ),
        *(
            ["plan", "--structure", name, "--uavs", "2", "--d-max", "10", "--anchor", "0,0,0"]
            for name in ("fifo.obj", "short.ply")
            if name in special or name == "short.ply"
        ),
        *([*sample, "--aoi", "fifo.geojson"] for _ in ("once",) if special),
        ["demo", "--out", "", "--iterations", "1", "--no-plots"],
        ["demo", "--out", "fifofolder", "--iterations", "1", "--no-plots", "--threads", "1"],
        ["sweep", ""],
        ["plot", ""],
        ["view", "", "--out", "v.html"],
        ["view", "run.npz", "--out", "/dev/null"],
        [*sample, "--out", ""],
        [*sample, "--hold", "1e308"],
        [*sample, "--d-max", "5e-324"],
        [*sample, "--camera", "5e-324,40"],
    ]
    return cases + round7_cli_cases(workdir)


def round7_cli_cases(workdir: Path) -> list[list[str]]:
    """Round 7: the Dask options (a timeout past the clock hung, two protocols printed a traceback
    at exit), a sweep file nested thousands deep, a .npy terrain of complex heights, a results
    folder whose config.json nests thousands deep."""
    head = 'base = "table1"\nseeds = [0]\nteam_sizes = [2]\nstarts = ["cvt"]\niterations = 0\n'
    (workdir / "r7.toml").write_text(head)
    (workdir / "r7deep.toml").write_text(head + "d_max = " + "[" * 5000 + "]" * 5000 + "\n")
    np.save(workdir / "r7complex.npy", np.zeros((20, 20), complex))
    (workdir / "r7complex.toml").write_text(head + '[terrain]\nkind = "file"\npath = "r7complex.npy"\nspacing = 1.0\n')
    (workdir / "r7deepcfg").mkdir(exist_ok=True)
    (workdir / "r7deepcfg" / "config.json").write_text("[" * 100_000 + "]" * 100_000)
    dask = ["sweep", "r7.toml", "--out", "r7out", "--scheduler"]
    return [
        [*dask, "inproc://x", "--scheduler-timeout", "1"],
        [*dask, "ucx://host:1", "--scheduler-timeout", "1"],
        [*dask, "tcp://127.0.0.1:1", "--scheduler-timeout", "1e300"],
        [*dask, "tcp://127.0.0.1:1", "--scheduler-timeout", "86401"],
        ["sweep", "r7.toml", "--out", "r7out", "--dask-workers", "1000000000"],
        ["sweep", "r7deep.toml"],
        ["sweep", "r7complex.toml", "--workers", "1", "--threads", "1"],
        ["sweep", "r7.toml", "--out", "r7deepcfg", "--resume", "--workers", "1", "--threads", "1"],
        ["reproduce", "structures", "--out", "r7deepcfg", "--resume", "--workers", "1"],
        ["reproduce", "realistic", "--out", "r7deepcfg", "--resume", "--workers", "1", "--seeds", "0"],
    ]


def fuzz_cli(timeout: float, report: list[str]) -> dict[str, int]:
    workdir = Path(tempfile.mkdtemp(dir="."))
    counts = {"cli_cases": 0, "cli_defects": 0}
    env = dict(os.environ, RAYON_NUM_THREADS="1", MPLBACKEND="Agg")
    for argv in cli_cases(workdir):
        counts["cli_cases"] += 1
        try:
            done = subprocess.run(
                [sys.executable, "-m", "uavcov", *argv], check=False, cwd=workdir, capture_output=True, text=True, timeout=timeout, env=env
            )
        except subprocess.TimeoutExpired:
            counts["cli_defects"] += 1
            report.append(f"CLI HANG uavcov {' '.join(argv)}")
            continue
        lines = done.stderr.strip().splitlines()
        if done.returncode == 0:
            report.append(f"CLI ACCEPTED uavcov {' '.join(argv)}")
        elif done.returncode != 2 or len(lines) != 1 or "Traceback" in done.stderr:
            counts["cli_defects"] += 1
            report.append(f"CLI BAD uavcov {' '.join(argv)}: exit {done.returncode}, stderr {done.stderr.strip()[-400:]!r}")
    return counts


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--only", help="fuzz only the callables whose name contains this")
    parser.add_argument("--timeout", type=float, default=20.0, help="seconds one call may take (default 20)")
    parser.add_argument("--out", default="fuzz_report.txt", help="the report file (default fuzz_report.txt)")
    parser.add_argument("--cli-only", action="store_true")
    parser.add_argument("--no-cli", action="store_true")
    parser.add_argument("--list", action="store_true", help="print the callables and their fuzzed arguments")
    parser.add_argument("--every-accepted", action="store_true", help="list every accepted case, the unsuspicious ones too")
    parser.add_argument("--values", help='only these hostile values, separated by semicolons (e.g. "10**400;masked(3,3)")')
    args = parser.parse_args()
    values = tuple(v for v in (args.values or "").split(";") if v)
    if any(v not in HOSTILE for v in values):
        print(f"--values: unknown hostile value(s); known: {', '.join(HOSTILE)}", file=sys.stderr)
        return 2
    if args.worker:
        worker()
        return 0
    repository = Path(__file__).resolve().parents[1]
    if Path.cwd().resolve().is_relative_to(repository):
        print("run the fuzzer in a fresh temporary directory, not in the repository (calls write files)", file=sys.stderr)
        return 2
    report: list[str] = []
    start = time.monotonic()
    counts: dict[str, int] = {}
    if not args.cli_only:
        counts.update(fuzz_api(args.only, args.timeout, args.list, report, args.every_accepted, values))
    if not args.no_cli and not args.list:
        counts.update(fuzz_cli(max(args.timeout, 60.0), report))
    summary = f"{counts} in {time.monotonic() - start:.0f} s"
    Path(args.out).write_text("\n".join(report + [summary]) + "\n")
    print("\n".join(report + [summary]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
