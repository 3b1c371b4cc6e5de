"""Hostile input at the Rust core (issue 14: items 1-4, and no panic reaching Python).

Each case runs in a process of its own, under a 4 GiB address-space limit and a timeout, so a
panic (``pyo3_runtime.PanicException``, a ``BaseException`` the child does not catch), an abort
(a signal), a hang (the timeout) or a raw traceback fails the test; the child prints one JSON
line with what each call gave: a value, or the name of the ``uavcov.errors`` class it raised.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

# Seconds a case may take; the slowest takes a few on the project's 2-core machine.
TIMEOUT = 120

PRELUDE = """
import json, resource, sys, time
resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
import numpy as np
import uavcov
from uavcov import Terrain, Visibility, errors
from uavcov import _core

def outcome(f):
    # A value, or the uavcov error class; anything else (a PanicException included) escapes.
    try:
        value = f()
    except errors.UavcovError as e:
        return ["error", type(e).__name__, str(e)[:200]]
    if isinstance(value, np.ndarray):
        value = value.tolist()
    return ["ok", value]

def done(result):
    print(json.dumps(result))
"""


def run(code: str, timeout: float = TIMEOUT) -> object:
    """Runs `code` after PRELUDE in a fresh interpreter; the JSON its last line holds."""
    proc = subprocess.run(
        [sys.executable, "-c", PRELUDE + textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )
    assert proc.returncode == 0, f"exit {proc.returncode}\n{proc.stderr[-3000:]}"
    assert "PanicException" not in proc.stderr, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def is_error(result: list, *classes: str) -> bool:
    return result[0] == "error" and (not classes or result[1] in classes)


# Item 1: d_max >= 1e19 on the grid method panicked (a range start of usize::MAX).


def test_a_huge_sensing_range_is_an_unlimited_one_on_both_methods() -> None:
    out = run(
        """
        t = Terrain.from_grid(np.zeros((11, 11)), 1.0)
        uav = [[5, 5, 3]]
        reference = Visibility(t, 100.0).coverage(uav)
        rows = []
        for d_max in [6e18, 1e19, 1e300, sys.float_info.max]:
            for method in ["grid", "mesh"]:
                vis = Visibility(t, d_max, method=method)
                rows.append([outcome(lambda: vis.coverage(uav)), outcome(lambda: vis.per_uav(uav).coverage),
                             outcome(lambda: int(vis.seen(uav).sum()))])
        done([reference, rows])
        """
    )
    reference, rows = out
    assert reference == 1.0
    for coverage, per_uav, seen in rows:
        assert coverage == ["ok", reference] and per_uav == ["ok", reference] and seen == ["ok", 121]


# Item 2: a grid at 1e10 m or more made the grid method spin (the walk's margins, 1e-9 of the
# coordinates, spanned more cells than its bisection could ever shrink below).


@pytest.mark.parametrize("origin", [1e9, 1e10, 1e13, 1e14])
def test_a_grid_far_from_the_origin_answers_like_the_mesh_method(origin: float) -> None:
    out = run(
        f"""
        o = {origin!r}
        rng = np.random.default_rng(0)
        t = Terrain.from_grid(rng.uniform(0, 5, (41, 41)), 1.0, origin=(o, o))
        uavs = [[o + 20, o + 20, 10], [o + 5, o + 33, 8]]
        start = time.perf_counter()
        grid = Visibility(t, 25.0, method="grid")
        seen_grid = grid.seen(uavs)
        counts = grid.per_uav(uavs)
        seconds = time.perf_counter() - start
        mesh = Visibility(t, 25.0, method="mesh")
        done([bool((seen_grid == mesh.seen(uavs)).all()), counts.coverage == mesh.coverage(uavs),
              counts.seen.tolist() == mesh.per_uav(uavs).seen.tolist(), float(seen_grid.mean()), seconds])
        """
    )
    same_mask, same_coverage, same_counts, share, seconds = out
    assert same_mask and same_coverage and same_counts
    assert 0.0 < share < 1.0
    assert seconds < 30.0


# Item 3: sizes that depend on the input aborted the process ("memory allocation failed").


def test_a_huge_cvt_is_a_clean_error_under_4_gib() -> None:
    out = run(
        """
        t = Terrain.from_grid(np.zeros((11, 11)), 1.0)
        s = t.core
        run = lambda n, q, window=5, iterations=1: _core.CVT.run(s, n, q, (0.5, 0.5), (0.5, 0.5), 0.1, window, iterations, 0,
                                                                 n_threads=1)
        done([
            # 200 million generators: 4.8 GB of generators alone, refused by the system.
            outcome(lambda: run(200_000_000, 200_000_000)[5]),
            # A window past any iteration count: no overflow, no history beyond the iterations.
            outcome(lambda: run(3, 2000, window=2**63, iterations=2)[5]),
            # A target density whose count overflowed usize before its limit was checked.
            outcome(lambda: len(s.area_targets(1e300)[0])),
        ])
        """
    )
    huge, window, density = out
    assert is_error(huge, "SurfaceTooLargeError"), huge
    assert window == ["ok", 2]
    assert is_error(density, "InvalidInputError"), density


@pytest.mark.parametrize("n", [30_000, 10**6])
def test_the_issues_cvt_team_sizes_end_cleanly(n: int) -> None:
    # The documented limits of the Python wrapper refuse these before Rust runs; the core would
    # now run them within its memory budget (but for hours).
    out = run(
        f"""
        t = Terrain.from_grid(np.random.default_rng(0).uniform(0, 5, (21, 21)), 1.0)
        done(outcome(lambda: len(uavcov.placement.cvt(t, {n}, rng=0).generators)))
        """
    )
    assert is_error(out) or out == ["ok", n], out


# Item 4: silent wrong answers near the limits of f64.


def test_coordinates_beyond_1e15_are_refused_not_answered_wrongly() -> None:
    out = run(
        """
        t = Terrain.from_grid(np.zeros((11, 11)), 1.0)
        big = 1e300
        done([
            outcome(lambda: Visibility(t, 1e300, method="mesh").coverage([[5, 5, 3e300]])),
            outcome(lambda: Visibility(t, 1e300, method="grid").coverage([[5, 5, 3e300]])),
            outcome(lambda: t.closest_point([[big] * 3])),
            outcome(lambda: t.clearance([[big, 0, 0]])),
            outcome(lambda: t.segments_clear([[0, 0, big]], [[1, 1, 1]])),
            outcome(lambda: t.ground_height([[big, 0]])),
            outcome(lambda: Terrain.from_grid(np.zeros((11, 11)), 1.0, origin=(1e300, 1e300)).area),
            outcome(lambda: Terrain.from_grid(np.zeros((3, 3)), 0.01, origin=(9e14, 0.0)).area),
            outcome(lambda: Terrain.from_grid(np.zeros((3, 3)), 1e-300).area),
            outcome(lambda: Terrain(np.array([[0, 0, 0], [big, 0, 0], [0, big, 0]]), np.array([[0, 1, 2]])).area),
            outcome(lambda: Visibility(t, 5.0, targets=uavcov.Targets.from_points(np.array([[big, 0.0, 0.0]]))).coverage([[5, 5, 3]])),
            # At the bound, answers are exact: the closest point of a far query is a corner.
            outcome(lambda: t.closest_point([[-1e15, -1e15, -1e15]])),
        ])
        """
    )
    *refused, at_bound = out
    for result in refused:
        assert is_error(result, "InvalidInputError", "MeshError", "InvalidTypeError"), result
    assert at_bound == ["ok", [[0.0, 0.0, 0.0]]]


# No input reaches a panic: the public API driven with extreme finite floats.


def test_extreme_finite_floats_never_panic_hang_or_abort() -> None:
    out = run(
        """
        values = [0.0, 5e-324, 1e-300, 1e-100, 1e-9, 1.0, 1e9, 1e15, 1e16, 1e100, 1e300, sys.float_info.max]
        values += [-v for v in values if v]
        rng = np.random.default_rng(14)
        pick = lambda: float(rng.choice(values))
        counts = {"ok": 0, "error": 0}
        for _ in range(150):
            spacing, ox, oy, scale = abs(pick()) or 1.0, pick(), pick(), pick()
            z = rng.uniform(-1, 1, (9, 9)) * scale
            made = outcome(lambda: Terrain.from_grid(z, spacing, origin=(ox, oy)))
            counts[made[0]] += 1
            if made[0] != "ok":
                continue
            t = Terrain.from_grid(z, spacing, origin=(ox, oy))
            uavs = np.array([[pick(), pick(), pick()], [ox + 4 * spacing, oy + 4 * spacing, abs(pick())]])
            for method in ["grid", "mesh"]:
                vis = outcome(lambda: Visibility(t, abs(pick()) or 1.0, method=method))
                counts[vis[0]] += 1
                if vis[0] == "ok":
                    v = Visibility(t, abs(pick()) or 1.0, method=method)
                    for call in (v.coverage, v.seen, v.per_uav):
                        counts[outcome(lambda: (call(uavs), 0)[1])[0]] += 1
            for call in (t.closest_point, t.clearance, lambda p: t.segments_clear(p, p[::-1]), lambda p: t.ground_height(p[:, :2])):
                counts[outcome(lambda: (call(uavs), 0)[1])[0]] += 1
        for _ in range(60):
            scale = pick()
            v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1]]) * scale + pick()
            made = outcome(lambda: Terrain(v, np.array([[0, 1, 2], [1, 3, 2]])))
            counts[made[0]] += 1
            if made[0] == "ok":
                t = Terrain(v, np.array([[0, 1, 2], [1, 3, 2]]))
                uavs = np.array([[pick(), pick(), pick()]])
                counts[outcome(lambda: Visibility(t, abs(pick()) or 1.0, targets=uavcov.Targets.from_points(v[:3])).coverage(uavs))[0]] += 1
                counts[outcome(lambda: (t.closest_point(uavs), 0)[1])[0]] += 1
        done(counts)
        """,
        timeout=300,
    )
    assert out["ok"] > 50 and out["error"] > 50, out


def test_the_mesh_tables_of_a_large_grid_are_a_clean_error_under_4_gib() -> None:
    # 81 million nodes fit (about 2 GB with numpy's copy); their 162 million triangles' face
    # table and its numpy copy (1.9 + 3.9 GB) do not, and are refused instead of aborting.
    out = run(
        """
        s = _core.Surface.from_grid(np.zeros((9000, 9000)), 1.0, 1.0, 0.0, 0.0)
        done([s.n_faces, outcome(lambda: s.faces().shape), outcome(lambda: s.vertices().shape)])
        """
    )
    n_faces, faces, vertices = out
    assert n_faces == 2 * 8999 * 8999
    assert is_error(faces, "SurfaceTooLargeError"), faces
    assert is_error(vertices, "SurfaceTooLargeError") or vertices == ["ok", [81_000_000, 3]], vertices
