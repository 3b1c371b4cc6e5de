"""What CAO's perturbation draw costs: numpy's ``standard_normal`` beside ``uavcov.optim``.

Both draw the same values from the same state (tests/test_draws.py holds them bit for bit), so
this compares only speed. Per round, each path makes ``--calls`` draws of ``--shape`` (CAO's
centralised draw for 12 UAVs: 200 candidates x 36 coordinates) from its own generator; the
paths alternate round by round, so drifts of the machine's speed fall on both alike.

Run: ``python benches/normal_draws.py [--rounds 15] [--calls 500] [--shape 200,36]``.
Prints the median over rounds of the time per call (microseconds) of each path, and the ratio.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from uavcov.optim import standard_normal


def per_call(draw, shape: tuple[int, ...], calls: int) -> float:
    rng = np.random.default_rng(1)
    start = time.perf_counter()
    for _ in range(calls):
        draw(rng, shape)
    return (time.perf_counter() - start) / calls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--calls", type=int, default=500)
    parser.add_argument("--shape", default="200,36", help="comma-separated dimensions")
    args = parser.parse_args()
    shape = tuple(int(d) for d in args.shape.split(","))
    paths = {"numpy": lambda rng, s: rng.standard_normal(s), "uavcov.optim": standard_normal}
    times: dict[str, list[float]] = {name: [] for name in paths}
    for draw in paths.values():  # warm-up: imports, first allocations
        per_call(draw, shape, 10)
    for _ in range(args.rounds):
        for name, draw in paths.items():
            times[name].append(per_call(draw, shape, args.calls))
    n = int(np.prod(shape))
    medians = {name: statistics.median(t) for name, t in times.items()}
    for name, t in medians.items():
        print(f"{name:>13}: {t * 1e6:8.2f} us per draw of {shape} ({t / n * 1e9:.2f} ns a value)")
    print(f"        ratio: {medians['numpy'] / medians['uavcov.optim']:.2f}x (numpy / uavcov.optim, medians of {args.rounds} rounds)")


if __name__ == "__main__":
    main()
