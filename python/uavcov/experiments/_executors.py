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
import ctypes
import ctypes.util
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

from .._validate import MAX_THREADS, MAX_WORKERS, as_count, as_positive_float, is_int
from ..errors import ConfigError, MissingExtraError, SchedulerTimeoutError

MAX_SCHEDULER_TIMEOUT_S = 86_400.0
"""The longest wait for a Dask scheduler, seconds (a day): a longer one is a typo, and Dask's
clock overflows far beyond it (a timeout of 1e300 s waited forever)."""

SCHEDULER_SCHEMES = ("tcp", "tls", "ws", "wss")
"""The protocols a scheduler in another process is reached by (``inproc`` is within one process,
and ``ucx`` needs a transport distributed no longer ships: either left a Client whose clean-up
printed a traceback at exit)."""


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

    def __post_init__(self) -> None:
        # also built from a caller's own executor (run_specs): checked here, not only in plan_execution
        object.__setattr__(self, "workers", as_count(self.workers, "workers", MAX_WORKERS))
        object.__setattr__(self, "n_threads", as_count(self.n_threads, "n_threads", MAX_THREADS))


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
    if not is_int(cores) or cores < 1:
        raise ConfigError(f"cores must be an integer >= 1, got {cores!r}")
    for name, value in (("workers", workers), ("n_threads", n_threads)):
        if value is not None and (not is_int(value) or value < 1):
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


_PR_SET_PDEATHSIG = 1  # linux/prctl.h


def _die_with(parent: int, kernel_signal: bool) -> None:
    """End this process when ``parent`` dies, even by ``kill -9`` (which runs no clean-up there).

    A daemon thread checks ``os.getppid()`` twice a second and exits when the parent is gone
    (the process is then re-parented). With ``kernel_signal``, on Linux, the kernel also sends
    SIGKILL at once (``prctl(PR_SET_PDEATHSIG)``); the kernel ties that signal to the *thread*
    that started the process, so it is asked for only when the pool is made and used by the
    parent's main thread (what :func:`uavcov.experiments.run_specs` does).
    """
    if kernel_signal and sys.platform.startswith("linux"):
        with contextlib.suppress(Exception):  # no libc to load: the thread below still watches
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(0.5)
        os._exit(1)  # orphaned: nothing of ours is left to report to

    if os.getppid() != parent:
        os._exit(1)
    threading.Thread(target=watch, name="uavcov-parent-watch", daemon=True).start()


def _worker_start(parent: int, kernel_signal: bool) -> None:
    """The pool workers' initializer: die with the parent, and leave Ctrl-C to it."""
    _die_with(parent, kernel_signal)
    # Ctrl-C is the parent's to handle: it stops the sweep, then ends the workers itself.
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def local_executor(workers: int) -> cf.ProcessPoolExecutor:
    """A process pool of ``workers`` processes started with the spawn context.

    Spawn, not fork: a forked child would inherit the parent's Rust thread pools in a state it
    cannot use, and spawn behaves the same on every platform. The workers die with this process,
    even when it is killed with SIGKILL: no orphan keeps computing (and holding the
    multiprocessing resource tracker alive) after its sweep is gone.

    Each worker imports the main script: in a script, everything that runs goes under
    ``if __name__ == "__main__":`` (else the workers run it again and the pool breaks with
    ``BrokenProcessPool``); a notebook needs no guard. Give each mission ``n_threads=1`` so that
    the workers do not compete for the cores.

    Parameters
    ----------
    workers : int
        Processes, 1 to 4096.

    Returns
    -------
    concurrent.futures.ProcessPoolExecutor
        Use it in a ``with`` block (it is shut down at its end), or pass it to
        :func:`run_specs` as ``executor``.

    Raises
    ------
    ConfigError
        ``workers`` not an integer in [1, 4096].

    Examples
    --------
    Two seeds of a mission on your own terrain, one per process (``run_mission`` and its inputs
    pickle):

    >>> import uavcov
    >>> from uavcov.experiments import local_executor
    >>> hills = uavcov.gaussian_hills(size=40.0, spacing=2.0, n_hills=3, rng=1)
    >>> settings = uavcov.MissionSettings(n_uavs=3, d_max=15.0, iterations=5)
    >>> with local_executor(2) as pool:
    ...     futures = [pool.submit(uavcov.run_mission, hills, settings, rng=seed, n_threads=1) for seed in (0, 1)]
    ...     results = [future.result() for future in futures]
    >>> [run.seed for run in results], results[0].best_coverage == uavcov.run_mission(hills, settings, rng=0).best_coverage
    ([0, 1], True)
    """
    if not is_int(workers) or not 1 <= workers <= MAX_WORKERS:
        raise ConfigError(f"workers must be an integer in [1, {MAX_WORKERS}], got {workers!r}")
    main_thread = threading.current_thread() is threading.main_thread()
    return cf.ProcessPoolExecutor(
        max_workers=int(workers),
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_worker_start,
        initargs=(os.getpid(), main_thread),
    )


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


def _check_address(scheduler: Any) -> None:
    """Refuse what is not a scheduler address before a Dask ``Client`` is made: a Client that fails
    to start leaves an object whose clean-up, at exit, waits 20 s and prints a traceback."""
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise ConfigError(f"a Dask scheduler address is a string like tcp://host:8786, got {scheduler!r}")
    try:
        from distributed.comm.addressing import parse_address, parse_host_port

        scheme, location = parse_address(scheduler)
        if scheme not in SCHEDULER_SCHEMES:
            raise ValueError(f"the protocol {scheme!r} is none of {', '.join(SCHEDULER_SCHEMES)}")
        host, port = parse_host_port(location)
        if not host or not 0 < int(port) < 65536:
            raise ValueError("a host and a port from 1 to 65535 are needed")
    except (ValueError, TypeError) as exc:
        raise ConfigError(f"{scheduler!r} is not the address of a Dask scheduler (like tcp://host:8786): {exc}") from None


@contextlib.contextmanager
def dask_executor(
    scheduler: str | None = None, n_workers: int | None = None, *, timeout: float = 10.0
) -> Iterator[tuple[cf.Executor, int]]:
    """A ``concurrent.futures`` executor on a Dask cluster (the ``uavcov[distributed]`` extra).

    Parameters
    ----------
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``).
    n_workers : int, optional
        Without ``scheduler``: start a local cluster of this many worker processes, one thread
        each (every core by default).
    timeout : float
        Seconds to wait for the scheduler before giving up, in (0, 86400] (a day).

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
        ``scheduler`` is not the address of a Dask scheduler (over tcp, tls, ws or wss), a bad
        ``n_workers`` (an integer in [1, 4096]) or ``timeout``.
    """
    timeout = as_positive_float(timeout, "timeout")
    if timeout > MAX_SCHEDULER_TIMEOUT_S:
        raise ConfigError(f"timeout must be at most {MAX_SCHEDULER_TIMEOUT_S:g} s (a day) to wait for a Dask scheduler, got {timeout:g} s")
    if n_workers is not None and (not is_int(n_workers) or not 1 <= n_workers <= MAX_WORKERS):
        raise ConfigError(f"the number of Dask workers must be an integer in [1, {MAX_WORKERS}], got {n_workers!r}")
    try:
        import logging

        from distributed import Client, LocalCluster
    except ImportError as exc:
        raise MissingExtraError(f"Dask is not installed: pip install 'uavcov[distributed]' ({exc})") from exc
    cluster = None
    try:
        if scheduler is not None:
            _check_address(scheduler)
            try:
                client = Client(scheduler, timeout=f"{timeout}s", set_as_default=False)
            except (OSError, TimeoutError) as exc:
                raise SchedulerTimeoutError(f"the Dask scheduler at {scheduler} did not answer within {timeout:g} s: {exc}") from exc
            except Exception as exc:  # a bad address, or something that is not a Dask scheduler answered
                raise ConfigError(f"cannot use {scheduler!r} as a Dask scheduler: {type(exc).__name__}: {exc}") from exc
        else:
            workers = available_cores() if n_workers is None else n_workers
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
