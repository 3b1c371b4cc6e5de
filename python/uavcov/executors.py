"""Where runs go: a local process pool, a Dask cluster, and how many threads each run gets.

:func:`plan_execution` resolves ``workers`` and ``n_threads`` for the cores this process may use
(``workers * n_threads`` never beyond them: oversubscribed threads only slow every run down);
:func:`local_executor` is a spawn process pool whose workers ignore Ctrl-C (the parent stops the
sweep, then ends them); :func:`dask_executor` a ``concurrent.futures`` executor on a Dask cluster
(the ``uavcov[distributed]`` extra).
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import multiprocessing
import os
import signal
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import ConfigError, MissingExtraError, SchedulerTimeoutError

__all__ = ["ExecutionPlan", "available_cores", "plan_execution", "local_executor", "stop_pool", "dask_executor"]


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def available_cores() -> int:
    """Cores this process may run on (the affinity mask, not the machine's count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # not on Linux
        return max(1, os.cpu_count() or 1)


@dataclass(frozen=True)
class ExecutionPlan:
    """How many runs go at once and how many Rust threads each gets.

    ``workers * n_threads`` never exceeds the cores of the machine for local execution.
    """

    workers: int
    n_threads: int


def plan_execution(workers: int | None = None, n_threads: int | None = None, cores: int | None = None) -> ExecutionPlan:
    """Resolve ``workers`` and ``n_threads`` for ``cores`` cores (this machine's by default).

    ``workers`` defaults to every core (capped at 1 when ``n_threads`` fills the machine);
    ``n_threads`` to ``max(1, cores // workers)``.

    Raises
    ------
    ConfigError
        Not positive integers, or ``workers * n_threads`` above the cores.
    """
    cores = available_cores() if cores is None else cores
    for name, value in (("workers", workers), ("n_threads", n_threads)):
        if value is not None and (not _is_int(value) or value < 1):
            raise ConfigError(f"{name} must be an integer >= 1, got {value!r}")
    if workers is None:
        workers = max(1, cores // (n_threads or 1))
    if n_threads is None:
        n_threads = max(1, cores // workers)
    if workers * n_threads > cores:
        raise ConfigError(
            f"{workers} workers x {n_threads} threads = {workers * n_threads} exceeds the {cores} cores: "
            "oversubscribed threads slow every run down; use fewer workers or threads"
        )
    return ExecutionPlan(int(workers), int(n_threads))


def _ignore_sigint() -> None:
    # Ctrl-C is the parent's to handle: it stops the sweep, then ends the workers itself.
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def local_executor(workers: int) -> cf.ProcessPoolExecutor:
    """A process pool of ``workers`` processes started with the spawn context.

    Spawn, not fork: a forked child would inherit the parent's Rust thread pools in a state it
    cannot use, and spawn behaves the same on every platform.
    """
    return cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"), initializer=_ignore_sigint)


def stop_pool(executor: cf.Executor) -> None:
    """Shut a pool down now: cancel what has not started and end our own worker processes."""
    executor.shutdown(wait=False, cancel_futures=True)
    processes = getattr(executor, "_processes", None) or {}
    for process in list(processes.values()):
        with contextlib.suppress(Exception):
            process.terminate()
    for process in list(processes.values()):
        with contextlib.suppress(Exception):
            process.join(timeout=5)


@contextlib.contextmanager
def dask_executor(scheduler: str | None = None, n_workers: int | None = None, *, timeout: float = 10.0) -> Iterator[tuple[cf.Executor, int]]:
    """A ``concurrent.futures`` executor on a Dask cluster (the ``uavcov[distributed]`` extra).

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``).
    n_workers : int, optional
        Without ``scheduler``: start a local cluster of this many worker processes, one thread
        each (every core by default).
    timeout : float
        Seconds to wait for the scheduler before giving up.

    Yields
    ------
    (executor, slots)
        The executor, and how many runs the cluster runs at once (its worker threads).

    Raises
    ------
    MissingExtraError
        Dask is not installed.
    SchedulerTimeoutError
        The scheduler does not answer within ``timeout``.
    ConfigError
        ``scheduler`` is not the address of a Dask scheduler, or a bad ``n_workers``.
    """
    try:
        import logging

        from distributed import Client, LocalCluster
    except ImportError as exc:
        raise MissingExtraError(f"Dask is not installed: pip install 'uavcov[distributed]' ({exc})") from exc
    cluster = None
    try:
        if scheduler is not None:
            try:
                client = Client(scheduler, timeout=f"{timeout}s", set_as_default=False)
            except (OSError, TimeoutError) as exc:
                raise SchedulerTimeoutError(f"the Dask scheduler at {scheduler} did not answer within {timeout:g} s: {exc}") from exc
            except Exception as exc:  # a bad address, or something that is not a Dask scheduler answered
                raise ConfigError(f"cannot use {scheduler!r} as a Dask scheduler: {type(exc).__name__}: {exc}") from exc
        else:
            workers = available_cores() if n_workers is None else n_workers
            if not _is_int(workers) or workers < 1:
                raise ConfigError(f"the number of Dask workers must be an integer >= 1, got {workers!r}")
            cluster = LocalCluster(
                n_workers=int(workers), threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=logging.ERROR
            )
            client = Client(cluster, set_as_default=False)
        try:
            slots = max(1, sum(client.nthreads().values()))
            yield client.get_executor(), slots
        finally:
            client.close()
    finally:
        if cluster is not None:
            cluster.close()
