"""Which MIP solver proves the lattice optimum on more instances: scipy's HiGHS against highspy, CP-SAT and SCIP.

Each instance is the integer program :func:`uavcov.cover.exact_placement` would hand its solver
(Table 1's terrain ``seed``, team size ``N``: greedy, the LP dual bound, the swaps, the candidates
the dual point excludes and the dominated ones already out), captured once by ``--build`` into
``--cache`` with the swaps' placement (the start) and the bound proved before the solver (the
smaller of greedy's online bound and the LP dual bound). Then every solver gets the same program,
the same time limit and one thread, in a child process killed 30 s past its limit, one at a time,
instances interleaved (for each instance every solver in turn) so that the machine's load falls on
all alike. A row per (instance, solver) is appended to ``--rows`` (rerunning skips those there):

* ``scipy``: ``scipy.optimize.milp`` as ``exact_placement`` calls it (presolve off; no start);
* ``scipy-cutoff``: as ``scipy``, with the row "objective >= the start's" (a cutoff without a start);
* ``highspy``: the same HiGHS through its own API (its newer release), given the swaps' placement;
* ``highspy-presolve``: as ``highspy``, presolve on;
* ``highspy-nostart``: as ``highspy``, without the start (what the newer HiGHS alone does);
* ``cpsat``: OR-Tools CP-SAT, one worker, hinted with the swaps' placement; integer weights
  ``ceil(W_g S)`` with ``S = 2**40``, so ``best_objective_bound / S`` bounds the true objective;
* ``scip``: SCIP through ``pyscipopt``, given the swaps' placement.

What counts for a placement is its true objective (the float shares of the groups it sees) and
for the bound ``min(pre-solver bound, solver's bound)``: as ``exact_placement`` would report.
Proved means ``bound - best <= 1e-4 bound``. highspy, ortools and pyscipopt are no dependency of uavcov (they
proved no more: benches/README.md, "Which MIP solver"); to rerun, install all three from wheels:
``pip install --only-binary=:all: highspy ortools pyscipopt``.

Run as::

    OPENBLAS_NUM_THREADS=1 nice .venv/bin/python benches/exact_solvers.py --build --seeds 0-4 --sizes 8 12
    OPENBLAS_NUM_THREADS=1 nice .venv/bin/python benches/exact_solvers.py --seeds 0-4 --sizes 8 12 \
        --solvers scipy highspy cpsat scip --rows /tmp/exact_solvers.jsonl
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

_SCALE = float(2**40)
_GAP = 1e-4


def _build(seeds: list[int], sizes: list[int], cache: Path) -> None:
    """Capture the program ``exact_placement`` would solve (its ``_round`` replaced by a recorder)."""
    from scipy.sparse import csr_matrix

    import uavcov
    from uavcov.cover import CoverageProblem, GreedySettings, _exact, exact_placement, viewpoint_lattice
    from uavcov.paper import TABLE1

    cache.mkdir(parents=True, exist_ok=True)
    captured: dict[str, Any] = {}

    def record(problem: Any, search: Any, survivors: np.ndarray, model: Any, k: int, limits: Any) -> None:
        captured.update(search=search, survivors=survivors, model=model)

    original = _exact._round
    _exact._round = record
    try:
        for seed in seeds:
            terrain = TABLE1.terrain.make(seed)
            limits = TABLE1.mission.constraints.resolve(terrain)
            lattice = viewpoint_lattice(terrain, limits, GreedySettings(spacing=5.0, n_heights=3), n_threads=1)
            problem = CoverageProblem(uavcov.Visibility(terrain, TABLE1.d_max, n_threads=1), lattice, n_threads=1)
            for k in sizes:
                captured.clear()
                started = time.perf_counter()
                result = exact_placement(problem, k, limits.d_safe, time_limit=600.0)
                if not captured:
                    print(f"seed {seed} N={k}: {result.status} before the solver", flush=True)
                    continue
                model, survivors, search = captured["model"], captured["survivors"], captured["search"]
                start = np.isin(survivors, search.picks).astype(np.float64)
                matrix = csr_matrix(model.constraints.A)
                instance = {
                    "seed": seed,
                    "k": k,
                    "cost": model.cost,
                    "integrality": model.integrality,
                    "matrix": matrix,
                    "lower": np.asarray(model.constraints.lb, dtype=np.float64),
                    "upper": np.asarray(model.constraints.ub, dtype=np.float64),
                    "n_x": int(survivors.size),
                    "start_x": start,
                    "start_value": float(search.coverage),
                    "pre_bound": float(search.bound),
                    "greedy": float(result.greedy_coverage),
                    "prepare_s": time.perf_counter() - started,
                }
                (cache / f"{seed}_{k}.pkl").write_bytes(pickle.dumps(instance, protocol=pickle.HIGHEST_PROTOCOL))
                print(
                    f"seed {seed} N={k}: {survivors.size} candidates, {model.n_rows} groups, {matrix.nnz} non-zeros, "
                    f"start {search.coverage:.5f}, bound {search.bound:.5f}, {time.perf_counter() - started:.1f} s",
                    flush=True,
                )
    finally:
        _exact._round = original


def _value(instance: dict[str, Any], x: np.ndarray) -> float:
    """The true objective of a 0/1 choice of candidates: the shares of the groups it sees."""
    n_x = instance["n_x"]
    shares = -instance["cost"][n_x:]
    coverage = instance["matrix"][: shares.size, :n_x]  # -1 where a candidate sees a group
    seen = np.asarray(-(coverage @ (x[:n_x] > 0.5).astype(np.float64))).ravel() >= 1.0
    return float(shares[seen].sum())


def _start_vector(instance: dict[str, Any]) -> np.ndarray:
    """The swaps' placement as a full column vector (its groups' ``z`` set to what it sees)."""
    n_x = instance["n_x"]
    groups = instance["cost"].size - n_x
    coverage = instance["matrix"][:groups, :n_x]
    z = (np.asarray(-(coverage @ instance["start_x"])).ravel() >= 1.0).astype(np.float64)
    return np.concatenate([instance["start_x"], z])


def _scipy(instance: dict[str, Any], time_limit: float, cutoff: bool = False) -> dict[str, Any]:
    from scipy.optimize import Bounds, LinearConstraint, milp
    from scipy.sparse import csr_matrix, vstack

    n = instance["cost"].size
    matrix, lower, upper = instance["matrix"], instance["lower"], instance["upper"]
    if cutoff:  # objective >= the start's: what it excludes is no better than the start, so max(bound, start) holds
        matrix = vstack([matrix, csr_matrix(-instance["cost"][None, :])], format="csr")
        lower = np.append(lower, instance["start_value"] * (1.0 - 1e-9))
        upper = np.append(upper, np.inf)
    result = milp(
        c=instance["cost"],
        integrality=instance["integrality"],
        bounds=Bounds(np.zeros(n), np.ones(n)),
        constraints=LinearConstraint(matrix, lower, upper),
        options={"presolve": False, "mip_rel_gap": _GAP, "time_limit": time_limit},
    )
    bound = getattr(result, "mip_dual_bound", None)
    return {
        "x": None if result.x is None else np.asarray(result.x),
        "bound": float("inf") if bound is None else -float(bound),
        "status": str(result.status),
        "nodes": int(getattr(result, "mip_node_count", 0) or 0),
    }


def _highspy(instance: dict[str, Any], time_limit: float, presolve: bool, start: bool = True) -> dict[str, Any]:
    import highspy

    matrix = instance["matrix"].tocsc()
    n = instance["cost"].size
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = n, matrix.shape[0]
    lp.col_cost_ = instance["cost"]
    lp.col_lower_, lp.col_upper_ = np.zeros(n), np.ones(n)
    lp.row_lower_ = np.where(np.isfinite(instance["lower"]), instance["lower"], -highspy.kHighsInf)
    lp.row_upper_ = np.where(np.isfinite(instance["upper"]), instance["upper"], highspy.kHighsInf)
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.start_, lp.a_matrix_.index_, lp.a_matrix_.value_ = matrix.indptr, matrix.indices, matrix.data
    lp.a_matrix_.num_col_, lp.a_matrix_.num_row_ = n, matrix.shape[0]
    lp.integrality_ = [highspy.HighsVarType.kInteger if v else highspy.HighsVarType.kContinuous for v in instance["integrality"]]
    h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    for key, value in {"threads": 1, "presolve": "on" if presolve else "off", "mip_rel_gap": _GAP, "time_limit": time_limit}.items():
        h.setOptionValue(key, value)
    h.passModel(lp)
    if start:
        solution = highspy.HighsSolution()
        solution.col_value = list(_start_vector(instance))
        solution.value_valid = True
        h.setSolution(solution)
    h.run()
    info = h.getInfo()
    x = np.asarray(h.getSolution().col_value) if info.primal_solution_status == 2 else None
    status = h.modelStatusToString(h.getModelStatus())
    return {"x": x, "bound": -float(info.mip_dual_bound), "status": status, "nodes": int(info.mip_node_count)}


def _cpsat(instance: dict[str, Any], time_limit: float) -> dict[str, Any]:
    from ortools.sat.python import cp_model

    n_x, n = instance["n_x"], instance["cost"].size
    model = cp_model.CpModel()
    variables = [model.new_bool_var(f"v{j}") for j in range(n)]
    matrix = instance["matrix"]
    for i in range(matrix.shape[0]):
        lo, hi = matrix.indptr[i], matrix.indptr[i + 1]
        terms = [round(a) * variables[j] for j, a in zip(matrix.indices[lo:hi], matrix.data[lo:hi], strict=True)]
        lower, upper = instance["lower"][i], instance["upper"][i]
        model.add_linear_constraint(sum(terms), int(lower) if np.isfinite(lower) else -(2**40), int(upper) if np.isfinite(upper) else 2**40)
    shares = -instance["cost"][n_x:]
    integer = np.ceil(shares * _SCALE).astype(np.int64)  # ceil: the integer objective over S bounds the true one
    model.maximize(sum(int(w) * variables[n_x + g] for g, w in enumerate(integer)))
    for variable, value in zip(variables, _start_vector(instance), strict=True):
        model.add_hint(variable, int(value > 0.5))
    solver = cp_model.CpSolver()
    solver.parameters.num_workers = 1
    solver.parameters.max_time_in_seconds = time_limit
    solver.parameters.relative_gap_limit = _GAP
    status = solver.solve(model)
    x = None
    if status in (cp_model.OPTIMAL, cp_model.FEASIBLE):
        x = np.array([solver.value(v) for v in variables[:n_x]], dtype=np.float64)
    # float rounding of B / S: far below the 1e-4 gap target
    bound = float(solver.best_objective_bound) / _SCALE * (1.0 + 1e-12)
    return {"x": x, "bound": bound, "status": solver.status_name(status), "nodes": int(solver.num_branches)}


def _scip(instance: dict[str, Any], time_limit: float) -> dict[str, Any]:
    from pyscipopt import Model, quicksum

    n_x, n = instance["n_x"], instance["cost"].size
    model = Model()
    model.hideOutput()
    variables = [model.addVar(vtype="B" if instance["integrality"][j] else "C", lb=0.0, ub=1.0) for j in range(n)]
    matrix = instance["matrix"]
    for i in range(matrix.shape[0]):
        lo, hi = matrix.indptr[i], matrix.indptr[i + 1]
        expression = quicksum(float(a) * variables[j] for j, a in zip(matrix.indices[lo:hi], matrix.data[lo:hi], strict=True))
        lower, upper = instance["lower"][i], instance["upper"][i]
        if np.isfinite(lower) and lower == upper:
            model.addCons(expression == float(upper))
        else:
            if np.isfinite(upper):
                model.addCons(expression <= float(upper))
            if np.isfinite(lower):
                model.addCons(expression >= float(lower))
    model.setObjective(quicksum(float(-instance["cost"][j]) * variables[j] for j in range(n_x, n)), "maximize")
    model.setParam("limits/time", time_limit)
    model.setParam("limits/gap", _GAP)
    model.setParam("lp/threads", 1)
    start = model.createSol()
    for variable, value in zip(variables, _start_vector(instance), strict=True):
        model.setSolVal(start, variable, float(value))
    model.addSol(start)
    model.optimize()
    x = None
    if model.getNSols() > 0:
        best = model.getBestSol()
        x = np.array([model.getSolVal(best, v) for v in variables[:n_x]], dtype=np.float64)
    return {"x": x, "bound": float(model.getDualbound()), "status": model.getStatus(), "nodes": int(model.getNNodes())}


def _solve(solver: str, path: Path, time_limit: float) -> dict[str, Any]:
    instance = pickle.loads(path.read_bytes())
    started = time.perf_counter()
    if solver in ("scipy", "scipy-cutoff"):
        outcome = _scipy(instance, time_limit, cutoff=solver == "scipy-cutoff")
    elif solver in ("highspy", "highspy-presolve", "highspy-nostart"):
        outcome = _highspy(instance, time_limit, presolve=solver == "highspy-presolve", start=solver != "highspy-nostart")
    elif solver == "cpsat":
        outcome = _cpsat(instance, time_limit)
    elif solver == "scip":
        outcome = _scip(instance, time_limit)
    else:
        raise SystemExit(f"unknown solver {solver}")
    wall = time.perf_counter() - started
    found = _value(instance, outcome["x"]) if outcome["x"] is not None else 0.0
    best = max(found, instance["start_value"])
    bound = max(min(instance["pre_bound"], outcome["bound"]), best)
    return {
        "seed": instance["seed"],
        "k": instance["k"],
        "solver": solver,
        "status": outcome["status"],
        "found": found,
        "best": best,
        "bound": bound,
        "solver_bound": outcome["bound"],
        "start": instance["start_value"],
        "pre_bound": instance["pre_bound"],
        "proved": bool(bound - best <= _GAP * bound),
        "nodes": outcome["nodes"],
        "wall_s": wall,
    }


def _run(seeds: list[int], sizes: list[int], solvers: list[str], cache: Path, rows: Path, time_limit: float) -> None:
    done = set()
    if rows.exists():
        done = {(r["seed"], r["k"], r["solver"]) for r in map(json.loads, rows.read_text().splitlines())}
    turn = 0
    for k in sizes:
        for seed in seeds:
            path = cache / f"{seed}_{k}.pkl"
            if not path.exists():
                continue
            turn += 1
            order = solvers[turn % len(solvers) :] + solvers[: turn % len(solvers)]  # each solver first in turn
            for solver in order:
                if (seed, k, solver) in done:
                    continue
                command = [sys.executable, __file__, "--child", solver, str(path), "--time-limit", str(time_limit)]
                started = time.perf_counter()
                try:
                    out = subprocess.run(command, capture_output=True, timeout=time_limit + 30.0, check=True).stdout
                    row = json.loads(out.decode().strip().splitlines()[-1])
                except (subprocess.TimeoutExpired, subprocess.CalledProcessError) as error:
                    row = {"seed": seed, "k": k, "solver": solver, "status": f"failed: {type(error).__name__}", "proved": False}
                row["child_s"] = time.perf_counter() - started
                row["load"] = os.getloadavg()[0]
                with rows.open("a") as handle:
                    handle.write(json.dumps(row) + "\n")
                print(json.dumps(row), flush=True)


def _table(rows: Path, solvers: list[str]) -> None:
    every = [json.loads(line) for line in rows.read_text().splitlines()]
    print("\n| N | solver | instances | proved | mean gap left | largest gap left | mean best | mean time to proof (proved) s | load |")
    print("|---|---|---|---|---|---|---|---|---|")
    for k in sorted({r["k"] for r in every}):
        for solver in solvers:
            mine = [r for r in every if r["k"] == k and r["solver"] == solver and "best" in r]
            if not mine:
                continue
            gaps = [r["bound"] - r["best"] for r in mine]
            proved = [r for r in mine if r["proved"]]
            time_to_proof = f"{np.mean([r['wall_s'] for r in proved]):.1f}" if proved else "-"
            print(
                f"| {k} | {solver} | {len(mine)} | {len(proved)} | {np.mean(gaps):.5f} | {max(gaps):.5f} | "
                f"{np.mean([r['best'] for r in mine]):.5f} | {time_to_proof} | {np.mean([r['load'] for r in mine]):.1f} |"
            )


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", action="store_true", help="capture the programs into --cache")
    parser.add_argument("--child", nargs=2, metavar=("SOLVER", "INSTANCE"), help=argparse.SUPPRESS)
    parser.add_argument("--seeds", default="0-4")
    parser.add_argument("--sizes", type=int, nargs="+", default=[8, 12])
    parser.add_argument("--solvers", nargs="+", default=["scipy", "highspy", "cpsat", "scip"])
    parser.add_argument("--cache", type=Path, default=Path("/tmp/exact_solvers_cache"))
    parser.add_argument("--rows", type=Path, default=Path("/tmp/exact_solvers.jsonl"))
    parser.add_argument("--time-limit", type=float, default=60.0)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(_solve(args.child[0], Path(args.child[1]), args.time_limit)))
        return
    from uavcov.experiments import parse_seeds

    seeds = list(parse_seeds(args.seeds))
    if args.build:
        _build(seeds, args.sizes, args.cache)
    else:
        _run(seeds, args.sizes, args.solvers, args.cache, args.rows, args.time_limit)
        _table(args.rows, args.solvers)


if __name__ == "__main__":
    main()
