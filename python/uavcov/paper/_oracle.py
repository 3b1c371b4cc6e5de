"""The full-knowledge oracle: greedy and its certified bound on the TRUE surface of each scenario.

For one scenario (an experiment's terrain seed) the oracle knows the true surface: it builds the
admissible lattice of viewpoints over the true flight band (the experiment's constraints
resolved against the true surface), the seen-matrix of those candidates on the targets a
mission measures coverage on (the true surface's default targets, range ``d_max``), then for
each team size the lazy greedy (picks kept ``d_safe`` apart) and its certified bound: the
smaller of greedy's online bound (Leskovec et al. 2007) and the LP relaxation's dual bound
(:meth:`uavcov.cover.CoverageProblem.dual_bound`), which stays informative where the online
bound reaches 1 (N >= 8 on Table 1's terrains). One matrix serves every team size of a scenario.

With ``exact=True`` each row also holds the lattice optimum itself
(:func:`uavcov.cover.exact_placement`: integer programming, greedy as the fallback, the
solver's proven bound), so each start's coverage can be set against the optimum, not a bound on it.

What its numbers are: ``coverage`` is a placement any team could fly (an admissible, separated
configuration of candidates); ``bound`` is certified for the best ``N`` candidates of the lattice
(no ``N`` of them see more), not for positions off the lattice, which can see a little more (see
benches/README.md for how the bound moves as the lattice is refined).
"""

from __future__ import annotations

import functools
import time
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from ..cover import CoverageProblem, ExactResult, GreedySettings, exact_placement, viewpoint_lattice
from ..engine import Visibility
from ..errors import InvalidTypeError
from ..experiments import Experiment, local_executor


@dataclass(frozen=True)
class OracleRow:
    """The oracle on one scenario and team size.

    Attributes
    ----------
    seed, n_uavs : int
        The scenario and the team size.
    coverage : float
        Greedy's coverage on the true surface (an admissible placement).
    bound : float
        Certified: no ``n_uavs`` candidates of the lattice see more (with or without the
        separation); the smaller of ``online_bound`` and ``dual_bound``.
    ceiling : float
        The share of the targets any candidate sees.
    n_candidates : int
    matrix_time_s, greedy_time_s : float
        Seconds for the scenario's lattice and seen-matrix (shared by its team sizes), and for
        this team's greedy and bound.
    holds_for : str
        What the bound bounds, in words.
    online_bound, dual_bound : float
        Greedy's online bound and the LP relaxation's dual bound, each certified on its own.
    dual_time_s : float
        Seconds for the LP and the evaluation of its dual certificate.
    optimum, optimum_bound : float or None
        With ``exact=True``: the best coverage of ``n_uavs`` separated candidates the integer
        program found, and its proven bound (equal within the gap target when
        ``optimum_status == "optimal"``); None without.
    optimum_status : str
        ``ExactResult.status``, or ``""`` without ``exact``.
    optimum_time_s : float or None
        Wall time of the whole exact_placement call (greedy, LP, swaps, program, solver), seconds.
    """

    seed: int
    n_uavs: int
    coverage: float
    bound: float
    ceiling: float
    n_candidates: int
    matrix_time_s: float
    greedy_time_s: float
    holds_for: str
    online_bound: float
    dual_bound: float
    dual_time_s: float
    optimum: float | None = None
    optimum_bound: float | None = None
    optimum_status: str = ""
    optimum_time_s: float | None = None


def oracle(
    experiment: Experiment,
    *,
    seeds: Iterable[int] | None = None,
    team_sizes: Iterable[int] | None = None,
    settings: GreedySettings | None = None,
    n_threads: int | None = None,
    workers: int | None = None,
    exact: bool = False,
    time_limit: float = 60.0,
) -> list[OracleRow]:
    """The full-knowledge oracle of every scenario and team size of ``experiment``.

    Parameters
    ----------
    experiment : Experiment
        E.g. :data:`uavcov.paper.TABLE1`.
    seeds, team_sizes : iterable of int, optional
        Default: the experiment's own.
    settings : GreedySettings, optional
        The lattice (default ``GreedySettings()``: 5 m, 3 heights).
    n_threads : int, optional
        Threads for the Rust side.
    workers : int, optional
        Processes, one scenario each at a time (``None`` or 1: in this process); the rows do
        not depend on it.
    exact : bool, default False
        Also solve each row to the lattice optimum (:func:`uavcov.cover.exact_placement`).
    time_limit : float, default 60.0
        Seconds the integer program of one row may take (then its gap is stated).

    Returns
    -------
    list of OracleRow
        Seed-major, then team sizes in order.

    Examples
    --------
    >>> from uavcov.paper import TABLE1, oracle
    >>> from uavcov.cover import GreedySettings
    >>> rows = oracle(TABLE1, seeds=[0], team_sizes=[5], settings=GreedySettings(spacing=10.0))
    >>> rows[0].coverage <= rows[0].bound <= rows[0].ceiling
    True
    """
    if not isinstance(experiment, Experiment):
        raise InvalidTypeError(f"experiment must be an Experiment, got {type(experiment).__name__}")
    sizes = experiment.team_sizes if team_sizes is None else tuple(team_sizes)
    chosen = [int(s) for s in (experiment.seeds if seeds is None else tuple(seeds))]
    one = functools.partial(
        _scenario_rows,
        experiment,
        sizes=tuple(int(n) for n in sizes),
        settings=settings,
        n_threads=n_threads,
        exact=exact,
        time_limit=time_limit,
    )
    if workers is None or workers <= 1 or len(chosen) <= 1:
        parts = [one(seed) for seed in chosen]
    else:  # scenarios are independent: a process each, rows the same as in sequence
        with local_executor(min(int(workers), len(chosen))) as pool:
            parts = list(pool.map(one, chosen))
    return [row for part in parts for row in part]


def _scenario_rows(
    experiment: Experiment,
    seed: int,
    *,
    sizes: tuple[int, ...],
    settings: GreedySettings | None,
    n_threads: int | None,
    exact: bool = False,
    time_limit: float = 60.0,
) -> list[OracleRow]:
    """The oracle of one scenario: its lattice and matrix once, then every team size."""
    mission = experiment.mission
    terrain = experiment.scenario(seed)
    started = time.perf_counter()
    limits = mission.constraints.resolve(terrain)
    lattice = viewpoint_lattice(terrain, limits, settings, n_threads=n_threads)
    problem = CoverageProblem(Visibility(terrain, mission.d_max, n_threads=n_threads), lattice, n_threads=n_threads)
    matrix_time = time.perf_counter() - started
    use_separation = settings is None or settings.separation
    rows = []
    for n in sizes:
        d_safe = limits.d_safe if use_separation else 0.0
        result = problem.greedy(n, d_safe)
        certificate = problem.dual_bound(n)
        before = time.perf_counter()
        best = exact_placement(problem, n, d_safe, time_limit=time_limit) if exact else None
        exact_time = time.perf_counter() - before  # the whole call: greedy, LP, swaps, program, solver
        rows.append(
            OracleRow(
                seed=seed,
                n_uavs=n,
                coverage=result.coverage,
                bound=min(result.bound, certificate.bound),
                ceiling=result.ceiling,
                n_candidates=lattice.n,
                matrix_time_s=matrix_time,
                greedy_time_s=result.greedy_time_s,
                holds_for=result.holds_for,
                online_bound=result.bound,
                dual_bound=certificate.bound,
                dual_time_s=certificate.solve_time_s,
                **(_optimum_columns(best, exact_time) if best is not None else {}),
            )
        )
    return rows


def _optimum_columns(best: ExactResult, wall_s: float) -> dict[str, Any]:
    """The optimum's columns of an :class:`OracleRow`."""
    return {
        "optimum": best.coverage,
        "optimum_bound": best.bound,
        "optimum_status": best.status,
        "optimum_time_s": wall_s,
    }
