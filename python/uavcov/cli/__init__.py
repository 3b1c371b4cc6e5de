"""The ``uavcov`` command line (also ``python -m uavcov``): parses arguments, calls the library.

Commands
--------
``uavcov demo``
    The paper's illustrative example end to end (9 UAVs, d_max = 35 m, 30 prior samples, CVT
    start, then CAO): prints a summary, writes runs.csv, the run and its figures to ``--out``.
``uavcov reproduce table1|pyramid|example|comparison|buildings|ablation|structures|realistic|flown-table1|all``
    One of the paper's experiments; writes runs.csv, the runs, config.json and ``<name>.md``.
``uavcov sweep CONFIG.toml``
    Any grid of settings (see ``examples/sweep.toml``); writes summary.md beside the runs.
``uavcov plot DIR``
    Redraws every figure from the runs stored in DIR (needs ``uavcov[plot]``).
``uavcov view RUN_OR_DIR --out view.html``
    One self-contained HTML file (opens offline) with an interactive 3D view of a run: the
    surface coloured by what the team sees, the UAVs, paths and footprints, a slider over
    iterations (needs ``uavcov[view]``).
``uavcov plan DEM.tif|--sample|--structure SCENE|MESH``
    A flight plan on a real DEM (needs ``uavcov[geo]``) or round a structure: the paper's CVT
    start and CAO, then QGroundControl ``.plan`` files, CSV, GeoJSON, KML, a coverage GeoTIFF and
    a report in ``--out``.

Exit codes: 0 done; 1 done, but some runs failed (their errors are in runs.csv); 2 bad input
(nothing already in ``--out`` was changed); 130 interrupted (every finished run is in runs.csv;
rerun with ``--resume``); 141 the reader of the output went away (``uavcov ... | head``: the
command stops without a word, as a program the closed pipe killed would).
"""

from __future__ import annotations

import os
import sys
import warnings
from collections.abc import Callable, Sequence
from typing import Any

from ._common import EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_OK, EXIT_PIPE_CLOSED, EXIT_RUNS_FAILED, _one_line, _say
from ._parser import _parser

__all__ = ["main", "EXIT_OK", "EXIT_RUNS_FAILED", "EXIT_BAD_INPUT", "EXIT_INTERRUPTED", "EXIT_PIPE_CLOSED"]


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit code (see the module docstring)."""
    args = _parser().parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)  # the report states the command that made it
    with warnings.catch_warnings():  # restored on return: main() called from Python leaves no trace
        warnings.showwarning = _warning_line(args.command)
        return _run(args)


def _warning_line(command: str) -> Callable[..., None]:
    """A warning as one line, ``uavcov <command>: warning: <message>``, like the errors: not Python's
    two lines that point into the installed package's source."""

    def show(message: Warning | str, category: type[Warning], filename: str, lineno: int, file: Any = None, line: Any = None) -> None:
        _say(f"uavcov {command}: warning: {' '.join(str(message).split())}")

    return show


def _run(args: Any) -> int:
    """The command's function, its errors as one line each and an exit code."""
    from ..errors import UavcovError

    try:
        return int(args.run(args))
    except UavcovError as exc:
        _say(f"uavcov {args.command}: error: {_one_line(exc)}")
        return EXIT_BAD_INPUT
    except BrokenPipeError as exc:
        if _stdout_closed():
            _quiet_stdout()
            return EXIT_PIPE_CLOSED
        _say(f"uavcov {args.command}: error: {type(exc).__name__}: {_one_line(exc)}")  # another pipe broke
        return EXIT_BAD_INPUT
    except (OSError, MemoryError) as exc:  # the system refused (disk full, no permission, no memory): one line too
        _say(f"uavcov {args.command}: error: {type(exc).__name__}: {_one_line(exc)}")
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        out = getattr(args, "out", None)
        where = f" in {out}/runs.csv" if out else ""
        _say(f"\ninterrupted: every finished run is saved{where}; rerun with --resume to continue")
        return EXIT_INTERRUPTED


def _stdout_closed() -> bool:
    """Whether standard output is a pipe whose reader went away (a broken pipe may also be
    another one's): the kernel flags the writing end with an error."""
    import select

    try:
        descriptor = sys.stdout.fileno()
        watch = select.poll()
        watch.register(descriptor, select.POLLOUT)
        events = watch.poll(0)
    except (AttributeError, OSError, ValueError):  # not a file (main() called with stdout captured)
        return False
    return any(event & (select.POLLERR | select.POLLHUP) for _, event in events)


def _quiet_stdout() -> None:
    """Point standard output at the null device: the reader went away, and the interpreter's own
    flush at exit would raise the broken pipe again (Python's documented remedy)."""
    try:
        descriptor = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # not a file (main() called with stdout captured)
        return
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, descriptor)
    finally:
        os.close(null)
