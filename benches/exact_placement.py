"""The exact placement (integer programming) on Table 1's terrains, beside greedy and the LP bound.

Three parts, each optional:

* ``--sweep``: the oracle with ``exact=True`` (:func:`uavcov.paper.oracle`) on ``--seeds``
  (Table 1's terrains, 5 m lattice x 3 heights, the true surface, d_max = 25 m, d_safe = 1 m),
  one terrain at a time, each row appended to ``--rows`` (a JSON line; rerunning skips the rows
  there); then per team size the instances, how many were proved optimal (relative gap <= 1e-4),
  and the median seconds of greedy, the LP dual bound and the integer program, all from the same
  run; with ``--runs runs.csv`` (a Table 1 folder's) each start's max coverage as a share of the
  optimum (the markdown of :func:`uavcov.paper._bounds.optimum_markdown`);
* ``--refine``: the optimum on lattices of 5, 2.5 and 1.25 m (each holds the coarser one) for
  ``--refine-seeds``;
* ``--cao``: CAO (Table 1's mission, 500 iterations) started from the optimum's positions, against
  the optimum: how much positions off the lattice add.

Run as::

    OPENBLAS_NUM_THREADS=1 nice .venv/bin/python benches/exact_placement.py --sweep --seeds 0-39 --rows /tmp/exact_rows.jsonl
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

import uavcov
from uavcov.cover import CoverageProblem, GreedySettings, exact_placement, viewpoint_lattice
from uavcov.experiments import finished_rows, parse_seeds
from uavcov.paper import TABLE1, OracleRow, oracle
from uavcov.paper._bounds import optimum_markdown


def _sweep(seeds: list[int], sizes: tuple[int, ...], rows_path: Path, time_limit: float, threads: int) -> list[OracleRow]:
    done: dict[tuple[int, int], OracleRow] = {}
    if rows_path.exists():
        for line in rows_path.read_text().splitlines():
            row = OracleRow(**json.loads(line))
            done[(row.seed, row.n_uavs)] = row
    for seed in seeds:
        missing = [n for n in sizes if (seed, n) not in done]
        if not missing:
            continue
        started = time.perf_counter()
        found = oracle(TABLE1, seeds=[seed], team_sizes=missing, n_threads=threads, exact=True, time_limit=time_limit)
        with rows_path.open("a") as handle:
            for row in found:
                handle.write(json.dumps(dataclasses.asdict(row)) + "\n")
                done[(row.seed, row.n_uavs)] = row
        load = os.getloadavg()[0]
        print(
            f"seed {seed}: {time.perf_counter() - started:.1f} s, load {load:.1f}, "
            + ", ".join(f"N={r.n_uavs} {r.optimum_status} {r.optimum:.4f} ({r.optimum_time_s:.1f} s)" for r in found),
            flush=True,
        )
    return [done[(s, n)] for s in seeds for n in sizes if (s, n) in done]


def _summary(rows: list[OracleRow], sizes: tuple[int, ...]) -> None:
    print(
        "\n| N | instances | proved (gap <= 1e-4) | greedy s | LP dual s | exact s (median) | exact s (max) "
        "| greedy | optimum | LP bound | largest gap left |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in sizes:
        of_n = [r for r in rows if r.n_uavs == n]
        if not of_n:
            continue
        proved = sum(r.optimum_status == "optimal" for r in of_n)
        print(
            f"| {n} | {len(of_n)} | {proved} | {np.median([r.greedy_time_s for r in of_n]):.3f} | "
            f"{np.median([r.dual_time_s for r in of_n]):.2f} | {np.median([r.optimum_time_s for r in of_n]):.2f} | "
            f"{max(r.optimum_time_s for r in of_n):.1f} | {np.mean([r.coverage for r in of_n]):.4f} | "
            f"{np.mean([r.optimum for r in of_n]):.4f} | {np.mean([r.dual_bound for r in of_n]):.4f} | "
            f"{max(r.optimum_bound - r.optimum for r in of_n):.5f} |"
        )
    for r in rows:
        if r.optimum_status != "optimal":
            print(f"  seed {r.seed} N={r.n_uavs}: {r.optimum_status}, {r.optimum:.4f} of at most {r.optimum_bound:.4f}")


def _problem(seed: int, spacing: float, threads: int) -> tuple[uavcov.Terrain, float, CoverageProblem]:
    terrain = TABLE1.terrain.make(seed)
    limits = TABLE1.mission.constraints.resolve(terrain)
    lattice = viewpoint_lattice(terrain, limits, GreedySettings(spacing=spacing, n_heights=3), n_threads=threads)
    return terrain, limits.d_safe, CoverageProblem(uavcov.Visibility(terrain, TABLE1.d_max, n_threads=threads), lattice, n_threads=threads)


def _refine(seeds: list[int], sizes: tuple[int, ...], spacings: list[float], time_limit: float, threads: int) -> None:
    print("\n| terrain, lattice | candidates | " + " | ".join(f"N={n} greedy / best / bound (status, s)" for n in sizes) + " |")
    print("|---|---|" + "---|" * len(sizes))
    for seed in seeds:
        for spacing in spacings:
            _, d_safe, problem = _problem(seed, spacing, threads)
            cells = []
            for n in sizes:
                started = time.perf_counter()
                r = exact_placement(problem, n, d_safe, time_limit=time_limit)
                wall = time.perf_counter() - started
                cells.append(f"{r.greedy_coverage:.4f} / {r.coverage:.4f} / {r.bound:.4f} ({r.status}, {wall:.0f})")
            load = os.getloadavg()[0]
            print(f"| {seed}, {spacing:g} m | {problem.viewpoints.n} | " + " | ".join(cells) + f" |  load {load:.1f}", flush=True)


def _cao(seeds: list[int], sizes: tuple[int, ...], time_limit: float, threads: int) -> None:
    print("\n| N | terrains | proved | best on the lattice | CAO from it, max | max / best on the lattice (min-max) |")
    print("|---|---|---|---|---|---|")
    for n in sizes:
        shares, optima, bests, proved = [], [], [], 0
        for seed in seeds:
            terrain, d_safe, problem = _problem(seed, 5.0, threads)
            best = exact_placement(problem, n, d_safe, time_limit=time_limit)
            run = uavcov.run_mission(
                terrain, replace(TABLE1.mission, n_uavs=n), start_positions=best.positions, n_threads=threads, rng=seed
            )
            proved += best.status == "optimal"
            optima.append(best.coverage)
            bests.append(run.best_coverage)
            shares.append(run.best_coverage / best.coverage)
        s = np.array(shares)
        print(
            f"| {n} | {len(seeds)} | {proved} | {np.mean(optima):.4f} | {np.mean(bests):.4f} | "
            f"{s.mean():.4f} ({s.min():.4f}-{s.max():.4f}) |  load {os.getloadavg()[0]:.1f}",
            flush=True,
        )


def _structures(families: list[str], seeds: list[int], time_limit: float, rows_path: Path) -> None:
    """The structures experiment's full-knowledge reference solved exactly, beside greedy and its missions' best."""
    from uavcov.cover import viewpoint_offsets
    from uavcov.paper._structures import STARTS, StructuresExperiment, _limits, _structure

    experiment = StructuresExperiment()
    # The report seeds' rows are at each start's offset chosen on the development seeds.
    missions: dict[tuple[str, int, str], float] = {}
    for line in rows_path.read_text().splitlines() if rows_path.is_file() else []:
        row = json.loads(line)
        if row.get("start") in STARTS and int(row["seed"]) in experiment.report_seeds and not row.get("error"):
            missions[(row["family"], int(row["seed"]), row["start"])] = float(row["best"])
    names = {"cvt3d": "CVT on S'", "cvt_hf": "height-field prior", "greedy3d": "greedy on S'"}
    columns = " | ".join(f"{names.get(s, s)} / best" for s in STARTS)
    print(f"\n| family, seed | candidates | greedy | best | bound | status | s | {columns} |")
    print("|---|---|---|---|---|---|---|" + "---|" * len(STARTS))
    for family in families:
        for seed in seeds:
            structure = _structure(experiment, family, seed)
            limits = _limits(experiment, structure)
            candidates = viewpoint_offsets(
                structure.surface, limits, experiment.reference_distances, spacing=experiment.reference_spacing, n_threads=1
            )
            targets = structure.targets(spacing=experiment.target_spacing)
            visibility = uavcov.Visibility(structure.surface, experiment.d_max, targets, n_threads=1)
            problem = CoverageProblem(visibility, candidates, n_threads=1)
            started = time.perf_counter()
            r = exact_placement(problem, experiment.n_uavs, experiment.d_safe, time_limit=time_limit)
            wall = time.perf_counter() - started
            shares = [f"{missions[(family, seed, s)] / r.coverage:.3f}" if (family, seed, s) in missions else "-" for s in STARTS]
            print(
                f"| {family}, {seed} | {candidates.n} | {r.greedy_coverage:.4f} | {r.coverage:.4f} | {r.bound:.4f} | "
                f"{r.status} | {wall:.0f} | " + " | ".join(shares) + f" |  load {os.getloadavg()[0]:.1f}",
                flush=True,
            )


def _direct(seeds: list[int], sizes: tuple[int, ...], time_limit: float, threads: int, highs: list[str]) -> None:
    """``exact_placement`` on each terrain and team size with HiGHS's options changed (``key=value``): what each step did."""
    from uavcov.cover import _exact

    for item in highs:
        key, value = item.split("=", 1)
        _exact._HIGHS_OPTIONS[key] = {"True": True, "False": False}.get(
            value, value if not value.replace(".", "").isdigit() else float(value)
        )
    print(f"HiGHS options {_exact._HIGHS_OPTIONS}, {time_limit:g} s")
    for seed in seeds:
        _, d_safe, problem = _problem(seed, 5.0, threads)
        for n in sizes:
            started = time.perf_counter()
            r = exact_placement(problem, n, d_safe, time_limit=time_limit)
            wall = time.perf_counter() - started
            print(
                f"terrain {seed} N {n}: wall {wall:.1f} s, {r.status}, solver {r.solver}, incumbent {r.incumbent}, "
                f"greedy {r.greedy_coverage:.4f}, best {r.coverage:.4f}, bound {r.bound:.4f}, gap {r.gap:.4f}, "
                f"kept {r.n_kept}/{r.n_candidates}, rows {r.n_rows}, nodes {r.n_nodes}, load {os.getloadavg()[0]:.2f}",
                flush=True,
            )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--sweep", action="store_true")
    parser.add_argument("--seeds", default="0-39")
    parser.add_argument("--sizes", type=int, nargs="+", default=list(TABLE1.team_sizes))
    parser.add_argument("--rows", type=Path, default=Path("exact_rows.jsonl"))
    parser.add_argument("--runs", type=Path, help="a Table 1 runs.csv: each start's max as a share of the optimum")
    parser.add_argument("--refine", action="store_true")
    parser.add_argument("--refine-seeds", default="0-1")
    parser.add_argument("--spacings", type=float, nargs="+", default=[5.0, 2.5, 1.25])
    parser.add_argument("--cao", action="store_true")
    parser.add_argument("--cao-seeds", default="0-4")
    parser.add_argument("--direct", action="store_true", help="exact_placement on --direct-seeds x --sizes, one line each")
    parser.add_argument("--direct-seeds", default="0-3")
    parser.add_argument("--highs", nargs="*", default=[], help="HiGHS options for --direct, key=value")
    parser.add_argument("--structures", action="store_true")
    parser.add_argument("--structure-seeds", default="0-1")
    parser.add_argument("--families", nargs="+", default=["building", "girder_bridge", "arch_bridge", "tower", "pylon"])
    parser.add_argument("--structure-rows", type=Path, default=Path("docs/structures_experiment/rows.jsonl"))
    parser.add_argument("--time-limit", type=float, default=60.0)
    parser.add_argument("--threads", type=int, default=2)
    args = parser.parse_args()
    sizes = tuple(args.sizes)
    if args.sweep:
        rows = _sweep(list(parse_seeds(args.seeds)), sizes, args.rows, args.time_limit, args.threads)
        _summary(rows, sizes)
        if args.runs is not None:
            import csv

            with args.runs.open() as handle:
                print("\n" + optimum_markdown(finished_rows(list(csv.DictReader(handle))), rows))
    if args.refine:
        _refine(list(parse_seeds(args.refine_seeds)), sizes, args.spacings, args.time_limit, args.threads)
    if args.cao:
        _cao(list(parse_seeds(args.cao_seeds)), sizes, args.time_limit, args.threads)
    if args.direct:
        _direct(list(parse_seeds(args.direct_seeds)), sizes, args.time_limit, args.threads, args.highs)
    if args.structures:
        _structures(args.families, list(parse_seeds(args.structure_seeds)), args.time_limit, args.structure_rows)


if __name__ == "__main__":
    main()
