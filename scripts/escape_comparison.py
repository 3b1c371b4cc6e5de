"""Plain CAO against CAO with escapes (``optimizer="escape"``) on the paper's Table 1 scenario.

Each terrain seed runs both optimisers from the same CVT start (the same prior, the same start:
only the optimiser's stream differs in use), so the comparison is paired per terrain. Printed and
written as Markdown: mean best coverage of each, the mean paired difference with its 95 % t
interval, the distance a UAV flies (mean over the team, then over terrains), the mission time
at a cruise speed (:func:`uavcov.mission_time`), and the escapes made.

The certified gap (upper bound on the coverage minus the best coverage reached) is a column
as soon as a bound is given: :func:`compare` takes ``bound(seed, n_uavs) -> float``, an upper
bound on the coverage any team of that size can reach on that terrain; :func:`oracle_bound` is
the oracle's (:func:`uavcov.paper.oracle`: no N candidates of the 5 m admissible lattice on
the true surface see more; positions off the lattice may see a little more, so a gap can be
slightly negative). ``--no-bound`` leaves the columns "n/a".

Usage (the figures in docs/escape.md)::

    python scripts/escape_comparison.py --seeds 0-19 --team-sizes 8,12 --out docs/escape.md

Development seeds for tuning are 1000-1019 (``--seeds 1000-1019``).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields

import numpy as np
from scipy import stats

from uavcov import mission_time
from uavcov.experiments import experiment_specs, parse_seeds
from uavcov.optim import EscapeSettings
from uavcov.paper import TABLE1, oracle

Bound = Callable[[int, int], float]
OPTIMIZERS = ("cao", "escape")


@dataclass(frozen=True)
class Row:
    """One team size: both optimisers over the same terrains."""

    n_uavs: int
    pairs: int
    best: dict[str, float]
    difference: float
    difference_ci: tuple[float, float]
    wins: int
    losses: int
    distance: dict[str, float]
    time_s: dict[str, float]
    relocations: float
    relocation_distance: float
    gap: dict[str, float] | None


def _t_interval(d: np.ndarray) -> tuple[float, float]:
    if d.size < 2:
        return (math.nan, math.nan)
    half = float(stats.t.ppf(0.975, d.size - 1) * np.std(d, ddof=1) / math.sqrt(d.size))
    return (float(d.mean()) - half, float(d.mean()) + half)


def compare(
    team_sizes: Sequence[int],
    seeds: Sequence[int],
    *,
    escape: EscapeSettings | None = None,
    speed: float = 5.0,
    bound: Bound | None = None,
    progress: bool = False,
) -> list[Row]:
    """Run both optimisers on Table 1's scenario (CVT start) for every team size and seed."""
    escape = EscapeSettings() if escape is None else escape
    rows = []
    for n in team_sizes:
        best: dict[str, list[float]] = {o: [] for o in OPTIMIZERS}
        distance: dict[str, list[float]] = {o: [] for o in OPTIMIZERS}
        seconds: dict[str, list[float]] = {o: [] for o in OPTIMIZERS}
        gaps: dict[str, list[float]] = {o: [] for o in OPTIMIZERS}
        relocations: list[int] = []
        relocated_m: list[float] = []
        for seed in seeds:
            for optimizer in OPTIMIZERS:
                experiment = TABLE1.with_changes(**{"mission.optimizer": optimizer, "mission.escape": escape})
                (spec,) = experiment_specs(experiment, seeds=[seed], team_sizes=[n], starts=["cvt"])
                result = spec.run(n_threads=1)
                best[optimizer].append(result.best_coverage)
                distance[optimizer].append(float(result.distance_flown.mean()))
                seconds[optimizer].append(mission_time(result, speed))
                if bound is not None:
                    gaps[optimizer].append(bound(seed, n) - result.best_coverage)
                if optimizer == "escape":
                    relocations.append(len(result.relocations))
                    relocated_m.append(result.relocation_distance)
            if progress:
                print(f"N={n} seed {seed}: cao {best['cao'][-1]:.4f}, escape {best['escape'][-1]:.4f}", file=sys.stderr, flush=True)
        d = np.array(best["escape"]) - np.array(best["cao"])
        rows.append(
            Row(
                n_uavs=n,
                pairs=len(seeds),
                best={o: float(np.mean(v)) for o, v in best.items()},
                difference=float(d.mean()),
                difference_ci=_t_interval(d),
                wins=int((d > 0).sum()),
                losses=int((d < 0).sum()),
                distance={o: float(np.mean(v)) for o, v in distance.items()},
                time_s={o: float(np.mean(v)) for o, v in seconds.items()},
                relocations=float(np.mean(relocations)),
                relocation_distance=float(np.mean(relocated_m)),
                gap={o: float(np.mean(v)) for o, v in gaps.items()} if bound is not None else None,
            )
        )
    return rows


def oracle_bound(team_sizes: Sequence[int]) -> Bound:
    """``bound(seed, n)``: the oracle's certified bound on Table 1's terrain ``seed`` (every team size at once, cached)."""
    cache: dict[tuple[int, int], float] = {}

    def bound(seed: int, n: int) -> float:
        if (seed, n) not in cache:
            for row in oracle(TABLE1, seeds=[seed], team_sizes=team_sizes):
                cache[(row.seed, row.n_uavs)] = row.bound
        return cache[(seed, n)]

    return bound


def markdown(rows: Sequence[Row], escape: EscapeSettings, seeds: str, speed: float) -> str:
    """The comparison as a Markdown table with its settings."""
    knobs = ", ".join(f"{f.name}={getattr(escape, f.name)!r}" for f in fields(escape))
    lines = [
        f"Terrain seeds {seeds}, Table 1's scenario and CAO constants, CVT start, 500 iterations; escape settings: {knobs}.",
        "",
        (
            "| N | terrains | CAO best | escape best | escape - CAO (95 % t interval) | better / worse | "
            "distance per UAV, CAO (m) | distance per UAV, escape (m) | "
            f"time at {speed:g} m/s, CAO (s) | time, escape (s) | escapes per run | escape flights (m) | "
            "certified gap, CAO | certified gap, escape |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lo, hi = r.difference_ci
        gap = ("n/a", "n/a") if r.gap is None else (f"{r.gap['cao']:.4f}", f"{r.gap['escape']:.4f}")
        lines.append(
            f"| {r.n_uavs} | {r.pairs} | {r.best['cao']:.4f} | {r.best['escape']:.4f} | "
            f"{r.difference:+.4f} ({lo:+.4f}, {hi:+.4f}) | {r.wins} / {r.losses} | "
            f"{r.distance['cao']:.1f} | {r.distance['escape']:.1f} | {r.time_s['cao']:.0f} | {r.time_s['escape']:.0f} | "
            f"{r.relocations:.1f} | {r.relocation_distance:.1f} | {gap[0]} | {gap[1]} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="0-19", help="terrain seeds, e.g. 0-19 (held out) or 1000-1019 (development)")
    parser.add_argument("--team-sizes", default="8,12")
    parser.add_argument("--speed", type=float, default=5.0, help="cruise speed for the mission time, m/s")
    parser.add_argument("--patience", type=int, default=EscapeSettings.patience)
    parser.add_argument("--out", help="write the table into this Markdown page, between its markers")
    parser.add_argument("--no-bound", action="store_true", help="leave the certified gap columns n/a (no oracle)")
    args = parser.parse_args(argv)
    seeds = parse_seeds(args.seeds)
    escape = EscapeSettings(patience=args.patience)
    started = time.perf_counter()
    sizes = [int(n) for n in args.team_sizes.split(",")]
    bound = None if args.no_bound else oracle_bound(sizes)
    rows = compare(sizes, seeds, escape=escape, speed=args.speed, bound=bound, progress=True)
    table = markdown(rows, escape, args.seeds, args.speed)
    print(table)
    print(f"({time.perf_counter() - started:.0f} s)", file=sys.stderr)
    if args.out:
        _write_between_markers(args.out, table)
    return 0


BEGIN, END = "<!-- escape-comparison:begin -->", "<!-- escape-comparison:end -->"


def _write_between_markers(path: str, table: str) -> None:
    with open(path, encoding="utf-8") as handle:
        text = handle.read()
    if BEGIN not in text or END not in text:
        raise SystemExit(f"{path} has no {BEGIN} ... {END} markers")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(path, "w", encoding="utf-8") as handle:
        handle.write(f"{head}{BEGIN}\n{table}{END}{tail}")


if __name__ == "__main__":
    sys.exit(main())
