"""What every command shares: exit codes, one-line messages, argument types, the execution
options (process pool or Dask) and the closing summary."""

from __future__ import annotations

import argparse
import contextlib
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

EXIT_OK = 0
EXIT_RUNS_FAILED = 1
EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130
EXIT_PIPE_CLOSED = 141
"""128 + SIGPIPE: what a shell reports for a program whose reader went away (``| head``)."""


def _one_line(exc: BaseException) -> str:
    """An exception's message on one line (the CLI prints exactly one line per error)."""
    return " | ".join(part.strip() for part in str(exc).splitlines() if part.strip()) or type(exc).__name__


def _say(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def _int_list(text: str) -> tuple[int, ...]:
    try:
        values = tuple(int(v) for v in text.split(",") if v.strip())
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected integers separated by commas, got {text!r}") from None
    if not values:
        raise argparse.ArgumentTypeError("expected at least one integer")
    return values


def _path_text(text: str) -> str:
    """An argparse type for a file or folder: any text but an empty one, which ``Path`` would read
    as the working directory (``--out "$UNSET"`` writing a run's files there)."""
    if not text:
        raise argparse.ArgumentTypeError("expected a file or folder name, got an empty one ('.' for the working directory)")
    return text


def _str_list(text: str) -> tuple[str, ...]:
    values = tuple(v.strip() for v in text.split(",") if v.strip())
    if not values:
        raise argparse.ArgumentTypeError("expected at least one name")
    return values


def _int_at_least(minimum: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``minimum``."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected an integer >= {minimum}, got {value}")
        return value

    return parse


_positive_int = _int_at_least(1)
_non_negative_int = _int_at_least(0)


def _positive_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"expected a number > 0, got {text}")
    return value


# ---------------------------------------------------------------------------------------------
# Execution options shared by reproduce and sweep


def _add_execution(parser: argparse.ArgumentParser) -> None:
    group = parser.add_argument_group("execution")
    group.add_argument("--workers", type=_positive_int, help="runs at once on a local process pool (default: every core)")
    group.add_argument("--threads", type=_positive_int, help="Rust threads per run (default: cores // workers)")
    where = group.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDRESS", help="run on the Dask cluster of this scheduler (uavcov[distributed])")
    where.add_argument("--dask-workers", type=_positive_int, metavar="N", help="run on a local Dask cluster of N worker processes")
    group.add_argument(
        "--scheduler-timeout",
        type=_positive_float,
        default=10.0,
        metavar="SECONDS",
        help="give up on an unreachable scheduler after this long (default 10)",
    )
    group.add_argument("--resume", action="store_true", help="continue the sweep in --out: skip finished runs")
    group.add_argument("--retry-failed", action="store_true", help="with --resume: run again the runs that failed")
    group.add_argument("--no-save-runs", action="store_true", help="write only runs.csv, not one .npz per run")
    bar = group.add_mutually_exclusive_group()
    bar.add_argument("--progress", dest="progress", action="store_true", default=None, help="always show the progress bar")
    bar.add_argument("--no-progress", dest="progress", action="store_false", help="never show the progress bar")


@contextlib.contextmanager
def _execution(args: argparse.Namespace) -> Iterator[dict[str, Any]]:
    """Keyword arguments for run_specs (executor, workers, threads, ...) and what to record."""
    from ..experiments import available_cores, dask_executor, plan_execution

    options: dict[str, Any] = {
        "resume": bool(args.resume or args.retry_failed),
        "rerun": "failed" if args.retry_failed else "none",
        "save_runs": not args.no_save_runs,
        "progress": args.progress,
    }
    cores = available_cores()
    if args.scheduler is None and args.dask_workers is None:
        plan = plan_execution(args.workers, args.threads)
        options.update(workers=plan.workers, n_threads=plan.n_threads)
        record = {
            "executor": "process pool (spawn)" if plan.workers > 1 else "this process",
            "workers": plan.workers,
            "threads_per_run": plan.n_threads,
            "cores": cores,
        }
        yield {**options, "execution": record}
        return
    if args.workers is not None:
        from ..errors import ConfigError

        raise ConfigError("--workers is for the local process pool; with Dask the cluster decides (use --dask-workers)")
    if args.dask_workers is not None:
        plan = plan_execution(args.dask_workers, args.threads)
        threads = plan.n_threads
    else:
        threads = args.threads or 1  # a remote worker's cores are unknown here: one thread per run
    with dask_executor(args.scheduler, args.dask_workers, timeout=args.scheduler_timeout) as (executor, slots):
        record = {
            "executor": f"dask ({args.scheduler or 'local cluster'})",
            "workers": slots,
            "threads_per_run": threads,
            "cores": cores,
        }
        yield {**options, "executor": executor, "workers": slots, "n_threads": threads, "execution": record}


def _finish(rows: list[dict[str, Any]], out: Path, started: float, wrote: Sequence[str]) -> int:
    failed = [r for r in rows if r.get("error")]
    seconds = time.perf_counter() - started
    _say(f"{len(rows)} run(s) in {seconds:.1f} s; results in {out}/: " + ", ".join(wrote))
    if failed:
        _say(f"{len(failed)} run(s) failed; their errors are in the error column of {out / 'runs.csv'}, e.g.")
        _say(f"  {failed[0]['run_id']}: {failed[0]['error']}")
        return EXIT_RUNS_FAILED
    return EXIT_OK


def _floats(count: int, what: str) -> Callable[[str], tuple[float, ...]]:
    """An argparse type: ``count`` numbers separated by commas."""

    def parse(text: str) -> tuple[float, ...]:
        try:
            values = tuple(float(v) for v in text.split(","))
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}") from None
        if len(values) != count or not all(abs(v) < float("inf") for v in values):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return values

    return parse


def _prior(text: str) -> str | int:
    if text == "full":
        return text
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected 'full' or a number of sparse points, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected 'full' or a number of sparse points >= 1, got {value}")
    return value
