"""Missions on structures no one on the project designed, judged by independent references.

Every kind of ``tests/shape_zoo.py`` (a dome, tori, a stadium, L/U/courtyard buildings, a thin
wall, a sign on a pole, a chimney, overlapping boxes, a guyed mast, a long low bridge, a building
at UTM coordinates, a 1 m box, a model wound inside out, an open shed, duplicated faces, a
non-manifold edge, a file in millimetres, a building below its datum, a hollow block, zero-area
faces), several seeds each, built with numpy alone, is flown
with the README's structure settings (8 UAVs, d_max 15 m, 100 known points, 2 m standoff, every
move checked, 100 iterations; the CVT start 6 m out and the greedy start 4 m out along S''s
normals), handed over as a ``Structure`` and as a mesh file read by ``load_structure`` (STL,
OBJ, PLY, ASCII and binary in turn), and once per kind through ``uavcov plan --structure FILE``.
Every configuration is judged by the references of the zoo (numpy point-triangle distance,
winding number, Moller-Trumbore): standoff, separation, ceiling, ground, inside a solid, moves
through the mesh, and the reported coverage against a recount on the mission's few hundred
targets. Prints one row per kind::

    nice python scripts/unseen_shapes.py --seeds 0-2 --iterations 100

``--round 2`` flies ``tests/shape_zoo2.py``'s kinds instead (tilted, on a hillside or over a
valley, 200 m apart, 1.5 km long, a cooling tower, a turbine, 0.1 m cables, a wall with windows,
stairs, a cantilever, 200k faces, slivers, zero-area slivers, no ground, a ground short of the
structure): each as a
``Structure``, as a file (the site's terrain in it where the ground is not flat: read as a user
would, with ``closed=False`` when refused as closed) and through ``uavcov plan``, and a second
table flies the Structure routes again from priors of another nature (``PRIORS``: noise 0.1 and
1 m, no normals, coarse boxes, a decimated mesh; one per kind and seed in turn)::

    nice python scripts/unseen_shapes.py --round 2 --seeds 0-2 --iterations 100
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from collections import defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import shape_checks as checks
import shape_zoo as zoo
import shape_zoo2 as zoo2


def seeds_of(text: str) -> list[int]:
    if "-" in text:
        lo, hi = (int(x) for x in text.split("-"))
        return list(range(lo, hi + 1))
    return [int(x) for x in text.split(",")]


def file_structure(shape: zoo.Shape, directory: Path, form: str, notes: set[str]):
    """The shape read from a file as a user would: ``closed`` as the shape is, then, if the
    reader refuses and says so, again with ``closed=False``."""
    from uavcov.errors import MeshError

    try:
        return zoo.through_file(shape, directory, form)[0]
    except MeshError as exc:
        if "closed=False" not in str(exc):
            raise
        notes.add("file refused as closed (" + str(exc).split(": ", 1)[1].split(";")[0] + "), read with closed=False")
        return zoo.through_file(shape, directory, form, closed=False)[0]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-2")
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--targets", type=int, default=400, help="about how many targets each mission has (and is recounted on)")
    parser.add_argument("--kinds", default=None, help="comma-separated kinds (default: every kind of the round)")
    parser.add_argument("--no-cli", action="store_true", help="skip uavcov plan --structure")
    parser.add_argument("--round", type=int, choices=(1, 2), default=1, help="the zoo of round 1 (shape_zoo) or 2 (shape_zoo2)")
    args = parser.parse_args()
    if args.round == 2:
        second_round(args)
        return
    args.kinds = args.kinds or ",".join(zoo.KINDS)
    seeds = seeds_of(args.seeds)
    began = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for kind in args.kinds.split(","):
            count: dict[str, float] = defaultdict(float)
            best: dict[str, list[float]] = defaultdict(list)
            notes: set[str] = set()
            for seed in seeds:
                shape = zoo.make(kind, seed)
                form = zoo.FILE_FORMATS[seed % len(zoo.FILE_FORMATS)]
                routes = {}
                try:
                    routes["Structure"] = zoo.as_structure(shape)
                except Exception as exc:  # noqa: BLE001 -- counted as a crash or a clear refusal
                    count["refused" if _ours(exc) else "crashes"] += 2
                    notes.add(f"Structure: {type(exc).__name__}: {str(exc)[:90]}")
                try:
                    routes[form] = file_structure(shape, Path(scratch), form, notes)
                except Exception as exc:  # noqa: BLE001 -- counted as a crash or a clear refusal
                    count["refused" if _ours(exc) else "crashes"] += 2
                    notes.add(f"{form}: {type(exc).__name__}: {str(exc)[:90]}")
                if "Structure" in routes and shape.closed:
                    missed, false_alarms = checks.inside_disagreements(routes["Structure"], shape)
                    count["inside_missed"] += missed
                    count["inside_false"] += false_alarms
                for route, structure in routes.items():
                    for start in ("cvt", "greedy"):
                        outcome = checks.run_judged(structure, start, args.iterations, seed, shape.closed, targets_count=args.targets)
                        _tally(outcome, route, count, best, notes)
                if not args.no_cli and seed == seeds[0]:
                    path = zoo.write_mesh(
                        Path(scratch), f"cli_{kind}_{seed}", shape.vertices * (1000.0 if shape.millimetres else 1.0), shape.faces, form
                    )
                    scale = 0.001 if shape.millimetres else 1.0
                    _plan_tally(path, Path(scratch), f"{kind}_{seed}", seed, args.iterations, count, notes, scale=scale)
            rows.append((kind, seeds, count, best, notes))
            print(f"  {kind} done ({time.perf_counter() - began:.0f} s)", file=sys.stderr, flush=True)
    print_table(rows, args)
    print(f"\n{time.perf_counter() - began:.0f} s in all")


# No second table's runs on these: their S' are a dome's and a drum's, their Structure is refused.
_NO_PRIOR_RUNS = ("dense_dome", "slivers", "no_ground", "small_ground", "hairline_slivers")


def second_round(args) -> None:
    """The kinds of ``tests/shape_zoo2.py``, their files, the plan command, and the priors."""
    seeds = seeds_of(args.seeds)
    began = time.perf_counter()
    rows, prior_rows = [], {name: (defaultdict(float), defaultdict(list), set()) for name in zoo2.PRIORS}
    kinds = (args.kinds or ",".join(zoo2.KINDS2)).split(",")
    with tempfile.TemporaryDirectory() as scratch:
        for index, kind in enumerate(kinds):
            count: dict[str, float] = defaultdict(float)
            best: dict[str, list[float]] = defaultdict(list)
            notes: set[str] = set()
            for seed in seeds:
                shape = zoo2.make2(kind, seed)
                form = zoo.FILE_FORMATS[(seed + index) % len(zoo.FILE_FORMATS)]
                routes = _second_routes(shape, Path(scratch), form, count, notes)
                for route, (structure, solid) in routes.items():
                    for start in ("cvt", "greedy"):
                        outcome = checks.run_judged(structure, start, args.iterations, seed, True, targets_count=args.targets, solid=solid)
                        _tally(outcome, route, count, best, notes)
                if "Structure" in routes and kind not in _NO_PRIOR_RUNS:
                    name = list(zoo2.PRIORS)[(seed + index) % len(zoo2.PRIORS)]
                    p_count, p_best, p_notes = prior_rows[name]
                    for start in ("cvt", "greedy"):
                        outcome = checks.run_judged(
                            routes["Structure"][0], start, args.iterations, seed, True, targets_count=args.targets, prior=zoo2.PRIORS[name]
                        )
                        _tally(outcome, kind, p_count, p_best, p_notes)
                if not args.no_cli and seed == seeds[0]:
                    _second_cli(shape, Path(scratch), form, seed, args.iterations, count, notes)
            rows.append((kind, seeds, count, best, notes))
            print(f"  {kind} done ({time.perf_counter() - began:.0f} s)", file=sys.stderr, flush=True)
    print_table(rows, args)
    print(f"\nThe Structure routes again from other priors (one per kind and seed in turn), seeds {args.seeds}")
    columns = ["prior", "runs", "crashes", "clear refusals", "safety violations", "raw starts inside", "coverage - recount"]
    print("| " + " | ".join(columns + ["mean best cvt", "mean best greedy"]) + " |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, (count, best, _) in prior_rows.items():
        mean = {s: (f"{np.mean(best[s]):.3f}" if best[s] else "-") for s in ("cvt", "greedy")}
        cells = [name, int(count["runs"]), int(count["crashes"]), int(count["refused"]), int(count["safety"]), int(count["raw_inside"])]
        print("| " + " | ".join(str(c) for c in cells + [f"{count['coverage_off']:.1g}", mean["cvt"], mean["greedy"]]) + " |")
    for name, (_, _, notes) in prior_rows.items():
        for note in sorted(notes):
            print(f"- {name}: {note}")
    print(f"\n{time.perf_counter() - began:.0f} s in all")


def _second_routes(shape: zoo.Shape, scratch: Path, form: str, count: dict, notes: set) -> dict:
    """``{route: (structure, solid triangles or None)}``: the shape as a ``Structure`` and read
    from its file; a refusal counts (twice: both starts) and is noted."""
    from uavcov.errors import MeshError

    routes = {}
    try:
        structure = zoo.as_structure(shape)
        routes["Structure"] = (structure, None)
        missed, false_alarms = checks.inside_disagreements(structure, shape)
        count["inside_missed"] += missed
        count["inside_false"] += false_alarms
    except Exception as exc:  # noqa: BLE001 -- counted as a crash or a clear refusal
        count["refused" if _ours(exc) else "crashes"] += 2
        notes.add(f"Structure: {type(exc).__name__}: {str(exc)[:90]}")
    try:
        try:
            structure, _, solid = zoo2.through_file2(shape, scratch, form)
        except MeshError as exc:
            if "closed=False" not in str(exc):
                raise
            notes.add("file refused as closed (" + str(exc).split(": ", 1)[1].split(";")[0] + "), read with closed=False")
            structure, _, solid = zoo2.through_file2(shape, scratch, form, closed=False)
        routes[form] = (structure, solid)
    except Exception as exc:  # noqa: BLE001 -- counted as a crash or a clear refusal
        count["refused" if _ours(exc) else "crashes"] += 2
        notes.add(f"{form}: {type(exc).__name__}: {str(exc)[:90]}")
    return routes


def _tally(outcome: checks.Outcome, route: str, count: dict, best: dict, notes: set) -> None:
    count["runs"] += 1
    if outcome.error is not None:
        count["refused" if outcome.clear_refusal else "crashes"] += 1
        notes.add(f"{route} {outcome.start}: {outcome.error[:160]}")
        return
    verdict = outcome.verdict
    count["safety"] += verdict.safety
    count["raw_inside"] += verdict.raw_start_inside
    count["coverage_off"] = max(count["coverage_off"], verdict.coverage_off)
    best[outcome.start].append(outcome.best)


def _second_cli(shape: zoo.Shape, scratch: Path, form: str, seed: int, iterations: int, count: dict, notes: set) -> None:
    """``uavcov plan --structure FILE`` on the shape's file, as the message tells a user."""
    v, f = zoo2.file_mesh(shape)
    path = zoo.write_mesh(scratch, f"cli_{shape.kind}_{seed}", v, f, form)
    solid = shape.vertices[shape.faces] - v[np.unique(f)].min(axis=0)  # the terrain in a site's file is no solid
    _plan_tally(path, scratch, f"{shape.kind}_{seed}", seed, iterations, count, notes, solid=solid)


def _plan_tally(path: Path, scratch: Path, name: str, seed: int, iterations: int, count: dict, notes: set, **judged) -> None:
    """``uavcov plan --structure FILE``, again with ``--open-mesh`` if refused as the message
    tells a user, judged (``scale``, ``solid`` as ``checks.plan_judged``) and counted."""
    planned = checks.plan_judged(path, scratch / f"plan_{name}", seed, iterations, **judged)
    if planned.returncode == 2 and "--open-mesh" in planned.stderr:
        notes.add("CLI refused the file as closed solids, planned with --open-mesh")
        planned = checks.plan_judged(path, scratch / f"plan_{name}b", seed, iterations, open_mesh=True, **judged)
    count["cli_runs"] += 1
    count["cli_ok"] += planned.returncode == 0
    count["cli_violations"] += planned.violations
    if planned.returncode != 0:
        lines = planned.stderr.splitlines()
        notes.add(f"CLI exit {planned.returncode} ({len(lines)} line): {lines[-1][:110] if lines else ''}")


def _ours(exc: Exception) -> bool:
    from uavcov.errors import UavcovError

    return isinstance(exc, UavcovError)


def print_table(rows, args) -> None:
    print(f"README structure settings, {args.iterations} iterations, about {args.targets} targets per mission, seeds {args.seeds}")
    print(
        "| kind | seeds | runs | crashes | clear refusals | safety violations | raw starts inside | inside test: missed / false | "
        "coverage - recount | mean best cvt | mean best greedy | CLI ok | CLI violations |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for kind, seeds, count, best, _ in rows:
        mean = {s: (f"{np.mean(best[s]):.3f}" if best[s] else "-") for s in ("cvt", "greedy")}
        cells = [kind, len(seeds), int(count["runs"]), int(count["crashes"]), int(count["refused"]), int(count["safety"])]
        cells += [int(count["raw_inside"]), f"{int(count['inside_missed'])} / {int(count['inside_false'])}", f"{count['coverage_off']:.1g}"]
        cells += [mean["cvt"], mean["greedy"], f"{int(count['cli_ok'])}/{int(count['cli_runs'])}", int(count["cli_violations"])]
        print("| " + " | ".join(str(c) for c in cells) + " |")
    print("\nNotes:")
    for kind, _, _, _, notes in rows:
        for note in sorted(notes):
            print(f"- {kind}: {note}")


if __name__ == "__main__":
    main()
