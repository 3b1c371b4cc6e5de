"""The results folder: where a sweep writes, and what reports and figures read.

A results folder holds

* ``runs.csv``: one row per finished run (the columns of ``RUN_COLUMNS``, then one column
  per swept setting), appended and synced the moment a run finishes, so an interrupted sweep
  loses nothing; a last line cut short by a crash is ignored by the reader and dropped before
  the next append;
* ``runs/<run_id>.npz``: each run's whole result (:func:`uavcov.records.save_mission`);
* ``config.json``: what was run (one schema for every command, ``config_document``);
* ``.uavcov.lock``: held while a process writes, so two sweeps never write one folder at once;
* and what reports and figures derive from these (Markdown tables, ``coverage.csv``,
  ``figures/``).

:class:`ResultsFolder` owns all of it; :func:`read_runs` is the one reader of ``runs.csv``.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import tempfile
import unicodedata
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._core import __version__
from .._io import atomic_write
from .._validate import as_path, as_tuple
from ..errors import InvalidInputError, InvalidTypeError, ResultsFolderError, ResultsFormatError, ResultsInUseError

RUN_COLUMNS: tuple[str, ...] = (
    "run_id",
    "experiment",
    "init",
    "n_uavs",
    "seed",
    "sensing_range",
    "iterations",
    "initial_coverage",
    "max_coverage",
    "final_coverage",
    "best_iteration",
    "iterations_to_95",
    "evaluations",
    "wall_time_s",
    "time_measure_s",
    "time_optimizer_s",
    "time_feasibility_s",
    "settings_hash",
    "error",
    "distance_mean_m",
    "distance_max_m",
    "start_time_s",
)
"""Columns of ``runs.csv``, in order; a sweep adds one column per swept setting after these.

``run_id`` names the run (:attr:`uavcov.experiments.RunSpec.run_id`); ``experiment`` is its label,
``init`` its start, ``sensing_range`` is d_max (m); ``initial_coverage``, ``max_coverage`` (the
best reached), ``final_coverage`` are shares of the surface; ``best_iteration`` and
``iterations_to_95`` (first iteration at 95 % of the best) count CAO iterations;
``wall_time_s`` is the whole mission and ``time_measure_s``, ``time_optimizer_s``,
``time_feasibility_s`` its coverage measurements, the optimiser's own work and the constraint
checks (the rest is prior, S', CVT and start); ``settings_hash`` is
``uavcov.experiments._sweep.settings_hash``; ``error`` is empty for a run that finished;
``distance_mean_m`` and ``distance_max_m`` are the mean and the largest distance a UAV flew
(:attr:`uavcov.MissionResult.distance_flown`, metres); ``start_time_s`` is the start's off-line
time on S' (:attr:`uavcov.MissionResult.start_time_s`: the CVT, or the greedy start's lattice,
seen-matrix and greedy; seconds).
"""

LATER_RUN_COLUMNS: tuple[str, ...] = ("distance_mean_m", "distance_max_m", "start_time_s")
"""The last columns of ``RUN_COLUMNS``, added after results folders were published: a
``runs.csv`` without them is still read, and a sweep resumed in it goes on writing its columns."""

_REQUIRED_COLUMNS = tuple(c for c in RUN_COLUMNS if c not in LATER_RUN_COLUMNS)

CONFIG_FORMAT = "uavcov.results/1"
"""The ``format`` entry of ``config.json``."""

_INT_COLUMNS = frozenset({"n_uavs", "seed", "iterations", "best_iteration", "iterations_to_95", "evaluations"})
_FLOAT_COLUMNS = frozenset(
    {
        "sensing_range",
        "initial_coverage",
        "max_coverage",
        "final_coverage",
        "wall_time_s",
        "time_measure_s",
        "time_optimizer_s",
        "time_feasibility_s",
        "distance_mean_m",
        "distance_max_m",
        "start_time_s",
    }
)


def json_default(value: Any) -> Any:
    """``json.dumps(default=...)`` for numpy scalars and arrays."""
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value)
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"cannot write {type(value).__name__} as JSON")


# ---------------------------------------------------------------------------------------------
# runs.csv


def _refuse_link(path: Path) -> None:
    if path.is_symlink():
        raise ResultsFolderError(
            f"{path} is a symbolic link: uavcov writes only inside the results folder and never through a link; "
            "remove it or write to another folder (nothing was changed)"
        )


def format_cell(value: Any) -> str:
    """How ``runs.csv`` writes a value: floats exactly (repr), lists as JSON, None empty."""
    if isinstance(value, float):
        return repr(value)  # round-trips exactly
    if isinstance(value, (list, tuple)):
        return json.dumps(list(value))
    return "" if value is None else str(value)


def _file_name(name: Any, what: str) -> str:
    """``name`` when it is a plain file name of a results folder; a uavcov error naming ``what`` else."""
    if not isinstance(name, str):
        raise InvalidTypeError(f"{what} must be a file name (a string), got {type(name).__name__}")
    if not name or "\0" in name or name in (".", "..") or os.path.basename(name) != name or "/" in name or "\\" in name:
        raise InvalidInputError(f"{what} must be a plain file name (no directory, '..' or NUL), got {name!r}")
    if any(unicodedata.category(c) == "Cc" for c in name):  # a newline or an escape: a name no listing shows as it is
        raise InvalidInputError(f"{what} must be a plain file name without control characters (newline, tab, escape), got {name!r}")
    return name


def csv_line(values: Sequence[Any]) -> str:
    """One CSV line (with its newline) of ``values``; floats written so they read back exactly."""
    buffer = io.StringIO()
    csv.writer(buffer, lineterminator="\n").writerow([format_cell(v) for v in values])
    return buffer.getvalue()


def _parse(name: str, text: str, where: str) -> Any:
    if text == "":
        return None if name != "error" else ""
    try:
        if name in _INT_COLUMNS:
            return int(text)
        if name in _FLOAT_COLUMNS:
            return float(text)
    except ValueError:
        raise ResultsFormatError(f"{where}: {name} = {text!r} is not a number") from None
    return text


def _complete_text(path: Path) -> tuple[str, int]:
    """The text of ``path`` up to its last newline, and the byte length of that part."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ResultsFormatError(f"cannot read {path}: {exc.strerror or exc}") from exc
    end = data.rfind(b"\n") + 1
    try:
        return data[:end].decode("utf-8"), end
    except UnicodeDecodeError as exc:
        raise ResultsFormatError(f"{path} is not a uavcov runs file: not UTF-8 text ({exc.reason} at byte {exc.start})") from None


def read_runs(path: str | os.PathLike[str], *, required: Sequence[str] = _REQUIRED_COLUMNS) -> list[dict[str, Any]]:
    """Read a ``runs.csv``: one ``dict`` per run, numbers as numbers, empty cells as None.

    A last line without its newline (a write cut off by a crash) is ignored: every complete row
    is returned. Columns beyond ``RUN_COLUMNS`` (swept settings) come back as strings.

    Parameters
    ----------
    path : path
        The file.
    required : sequence of str
        Columns the header must have (all of ``RUN_COLUMNS`` but ``LATER_RUN_COLUMNS`` by default).

    Raises
    ------
    ResultsFormatError
        No such file, not UTF-8, a header without a required column, a row of the wrong length,
        or a number column that holds no number.
    """
    path = as_path(path, "path")
    required = as_tuple(required, "required")
    if any(not isinstance(column, str) for column in required):
        raise InvalidTypeError(f"required must hold column names (strings), got {required!r}")
    if not path.is_file():
        raise ResultsFormatError(f"no runs file at {path}")
    text, _ = _complete_text(path)
    reader = csv.reader(io.StringIO(text))
    try:
        header = next(reader, None)
        if header is None:
            return []
        missing = [c for c in required if c not in header]
        if missing:
            raise ResultsFormatError(f"{path} is not a uavcov runs file: it lacks the column(s) {', '.join(missing)}")
        repeated = sorted({c for c in header if header.count(c) > 1})
        if repeated:  # a row would keep one of its cells under that name and drop the other
            raise ResultsFormatError(f"{path} names the column(s) {', '.join(repeated)} twice in its header")
        rows = []
        for line_number, cells in enumerate(reader, start=2):
            if len(cells) != len(header):
                raise ResultsFormatError(f"{path}, line {line_number}: {len(cells)} cells for {len(header)} columns")
            where = f"{path}, line {line_number}"
            rows.append({name: _parse(name, cell, where) for name, cell in zip(header, cells, strict=True)})
    except csv.Error as exc:
        raise ResultsFormatError(f"{path} is not a CSV file: {exc}") from None
    return rows


class RunsFile:
    """``runs.csv`` opened for appending one complete, synced line per finished run."""

    def __init__(self, path: Path, columns: Sequence[str]) -> None:
        self.path = path
        self.columns = list(columns)
        end = self.check(path, self.columns)
        fresh = end == 0
        if path.exists() and end != path.stat().st_size:
            # A line cut off by a crash (its run was not finished, or the header itself was cut
            # on the first write): drop it before appending.
            with open(path, "r+b") as handle:
                handle.truncate(end)
        try:  # never through a symbolic link (check refuses one; O_NOFOLLOW closes the race)
            fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o666)
        except OSError as exc:
            raise ResultsFolderError(f"cannot write {path}: {exc.strerror or exc}") from exc
        self.handle = os.fdopen(fd, "a", encoding="utf-8", newline="")
        if fresh:
            self._write(csv_line(self.columns))

    @staticmethod
    def check(path: Path, columns: Sequence[str]) -> int:
        """Refuse a ``runs.csv`` whose header is not ``columns``; the length of its complete lines.

        Raises
        ------
        ResultsInUseError
            The file holds another kind of sweep.
        ResultsFolderError
            ``path`` is a symbolic link (uavcov never writes through one) or not a file.
        ResultsFormatError
            It cannot be read, or is not UTF-8 text.
        """
        _refuse_link(path)
        if not path.exists():
            return 0
        if not path.is_file():
            raise ResultsFolderError(f"{path} is not a file")
        text, end = _complete_text(path)
        if end == 0:
            return 0
        try:
            header = next(csv.reader(io.StringIO(text)), None)
        except csv.Error as exc:
            raise ResultsFormatError(f"{path} is not a CSV file: {exc}") from None
        if header != list(columns):
            raise ResultsInUseError(f"{path} has the columns {header}, this sweep writes {list(columns)}: it holds another kind of sweep")
        return end

    def _write(self, line: str) -> None:
        self.handle.write(line)
        self.handle.flush()
        os.fsync(self.handle.fileno())

    def append(self, row: Mapping[str, Any]) -> None:
        """Write one row (missing columns empty)."""
        self._write(csv_line([row.get(c, "") for c in self.columns]))

    def close(self) -> None:
        """Close the file."""
        self.handle.close()


# ---------------------------------------------------------------------------------------------
# config.json


def config_document(
    command: str | None,
    settings: Mapping[str, Any],
    runs: Mapping[str, Any],
    *,
    execution: Mapping[str, Any] | None = None,
    about: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """The ``config.json`` of a results folder (one schema for every command).

    Parameters
    ----------
    command : str
        What wrote the folder ("reproduce table1", "sweep", "demo", ...).
    settings : mapping
        ``settings hash -> {"label", "swept", "experiment"}``: every configuration of the runs.
        On resume this entry must be unchanged (seeds, team sizes and execution may differ).
    runs : mapping
        Seeds, team sizes, starts and count of the runs asked for.
    execution : mapping, optional
        How they were run (executor, workers, threads).
    about : mapping, optional
        Anything else the command records (a sweep's name, base, description and axes).
    """
    return {
        "format": CONFIG_FORMAT,
        "command": command,
        "uavcov_version": str(__version__),
        "settings": dict(settings),
        "runs": dict(runs),
        "execution": dict(execution or {}),
        "about": dict(about or {}),
    }


# ---------------------------------------------------------------------------------------------
# The folder


def _is_our_document(document: Any) -> bool:
    """Whether a parsed ``config.json`` is uavcov's: its ``format`` is ``CONFIG_FORMAT``, or it
    comes from a release before that tag (``uavcov_version`` and ``settings``, no ``format``)."""
    if not isinstance(document, dict):
        return False
    if "format" in document:
        return bool(document["format"] == CONFIG_FORMAT)
    return "uavcov_version" in document and "settings" in document


def _is_our_config(path: Path) -> bool:
    """Whether ``path`` is a ``config.json`` uavcov wrote."""
    if not path.is_file():  # a FIFO would block the read forever, a device never end it
        return False
    try:
        document = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError):  # RecursionError: arrays nested thousands deep
        return False
    return _is_our_document(document)


def _is_our_runs(path: Path) -> bool:
    """Whether ``path`` starts with a header of uavcov's ``runs.csv``."""
    try:
        with open(path, "rb") as handle:
            first = handle.readline(1 << 16).decode("utf-8")
        header = next(csv.reader(io.StringIO(first)), [])
    except (OSError, UnicodeDecodeError, csv.Error):
        return False
    return all(c in header for c in _REQUIRED_COLUMNS)


_HELD_LOCKS: dict[Path, tuple[int, int]] = {}


class ResultsFolder:
    """A results folder (see the module docstring), created when missing.

    Parameters
    ----------
    path : path
        The folder.

    Raises
    ------
    ResultsFolderError
        ``path`` is a file, cannot be created, or is not writable. Nothing in it is touched.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        path = as_path(path, "path")
        if path.exists() and not path.is_dir():
            raise ResultsFolderError(f"the results folder {path} is a file, not a directory")
        try:
            path.mkdir(parents=True, exist_ok=True)
            fd, probe = tempfile.mkstemp(dir=path, prefix=".write-test-")
            os.close(fd)
            os.unlink(probe)
        except OSError as exc:
            raise ResultsFolderError(f"cannot write to the results folder {path}: {exc.strerror or exc}") from exc
        self.path = path

    @property
    def runs_csv(self) -> Path:
        """``runs.csv``."""
        return self.path / "runs.csv"

    @property
    def config_json(self) -> Path:
        """``config.json``."""
        return self.path / "config.json"

    def run_file(self, run_id: str) -> Path:
        """Where the whole result of run ``run_id`` is stored.

        Raises ``InvalidTypeError`` / ``InvalidInputError`` for a ``run_id`` that is not a plain
        file name (a path, ``..``, a NUL byte): a file outside ``runs/`` is never named.
        """
        return self.path / "runs" / f"{_file_name(run_id, 'run_id')}.npz"

    def read_runs(self) -> list[dict[str, Any]]:
        """The rows of ``runs.csv`` (none when it does not exist yet)."""
        return read_runs(self.runs_csv) if self.runs_csv.exists() else []

    def columns_for(self, columns: Sequence[str]) -> list[str]:
        """The columns a sweep writing ``columns`` writes here: ``columns``, or, in a ``runs.csv``
        made before some of ``LATER_RUN_COLUMNS``, its own header when that is ``columns``
        without the later ones it lacks (they were added in order)."""
        olders = [[c for c in columns if c not in LATER_RUN_COLUMNS[i:]] for i in range(len(LATER_RUN_COLUMNS))]
        if self.runs_csv.is_file() and not self.runs_csv.is_symlink():
            with contextlib.suppress(OSError, UnicodeDecodeError, csv.Error):
                with open(self.runs_csv, encoding="utf-8") as handle:
                    header = next(csv.reader([handle.readline()]), [])
                if header in olders:
                    return header
        return list(columns)

    def check_columns(self, columns: Sequence[str]) -> None:
        """Refuse a ``runs.csv`` of another kind of sweep (see ``RunsFile.check``)."""
        RunsFile.check(self.runs_csv, columns)

    def open_runs(self, columns: Sequence[str]) -> RunsFile:
        """``runs.csv`` for appending rows with these columns."""
        return RunsFile(self.runs_csv, columns)

    def write_text(self, name: str, text: str) -> Path:
        """Write a file of the folder atomically (never through a symbolic link); returns its path.

        ``name`` is a plain file name (no directory, no ``..``, no NUL byte), ``text`` a string.
        """
        path = self.path / _file_name(name, "name")
        if not isinstance(text, str):
            raise InvalidTypeError(f"text must be a string, got {type(text).__name__}")
        _refuse_link(path)
        atomic_write(path, text)
        return path

    def write_csv(self, name: str, header: Sequence[Any], rows: Iterable[Sequence[Any]]) -> Path:
        """Write a CSV table of the folder atomically, floats so they read back exactly; returns its path.

        ``header`` holds column names (strings), each of ``rows`` one value per column.
        """
        names = as_tuple(header, "header")
        if not names or any(not isinstance(column, str) for column in names):
            raise InvalidTypeError(f"header must hold column names (strings), got {header!r}")
        lines = [as_tuple(row, "rows") for row in as_tuple(rows, "rows")]
        ragged = next((k for k, line in enumerate(lines) if len(line) != len(names)), None)
        if ragged is not None:
            raise InvalidInputError(f"rows must have {len(names)} values (the header's), row {ragged} has {len(lines[ragged])}")
        return self.write_text(name, "".join(csv_line(line) for line in (names, *lines)))

    def drop_runs(self, run_ids: set[str]) -> None:
        """Rewrite ``runs.csv`` atomically without the rows of these runs."""
        text, _ = _complete_text(self.runs_csv)
        lines = text.splitlines(keepends=True)
        if not lines:
            return
        header = next(csv.reader(io.StringIO(lines[0])))
        index = header.index("run_id")
        kept = [lines[0]]
        for line in lines[1:]:
            cells = next(csv.reader(io.StringIO(line)))
            if cells[index] not in run_ids:
                kept.append(line)
        atomic_write(self.runs_csv, "".join(kept))

    def claim(self, names: Sequence[str] = ()) -> None:
        """Check, before anything is written, that uavcov may write ``runs.csv``, ``runs/``,
        ``config.json`` and ``names`` here.

        Refused: a symbolic link in place of any of them (uavcov writes only inside the
        folder), a ``runs`` that is not a directory, a ``config.json`` that uavcov did not
        write, and, in a folder that holds no uavcov results yet (neither its ``config.json``
        nor its ``runs.csv``), any file uavcov would overwrite.

        Raises
        ------
        ResultsFolderError
            A symbolic link, or ``runs`` is a file.
        ResultsInUseError
            A file that is not uavcov's would be overwritten.
        """
        written = list(dict.fromkeys(["runs.csv", "config.json", *names]))
        for name in dict.fromkeys([*written, "runs", ".uavcov.lock"]):
            _refuse_link(self.path / name)
        runs = self.path / "runs"
        if runs.exists() and not runs.is_dir():
            raise ResultsFolderError(f"{runs} is a file: uavcov keeps a folder's runs in a directory of that name")
        config = self.config_json
        ours = config.exists() and _is_our_config(config)
        if config.exists() and not ours:
            raise ResultsInUseError(
                f'{config} is not a uavcov results file (no "format": "{CONFIG_FORMAT}") and would be overwritten: '
                "move it away or write to another folder (nothing was changed)"
            )
        if not ours and not (self.runs_csv.is_file() and _is_our_runs(self.runs_csv)):
            clash = [n for n in written if (self.path / n).exists()]
            if clash:
                raise ResultsInUseError(
                    f"{self.path} holds {', '.join(clash)} but no uavcov results, and uavcov would overwrite them: "
                    "move them away or write to another folder (nothing was changed)"
                )

    def remove_leftovers(self) -> None:
        """Delete the temporary files (``.tmp-*``) a write cut short by a crash left in the folder
        and in ``runs/``; call it holding :meth:`lock`, so that no write of ours is under way."""
        for where in (self.path, self.path / "runs"):
            if where.is_dir() and not where.is_symlink():
                for leftover in where.glob(".tmp-*"):
                    with contextlib.suppress(OSError):
                        if leftover.is_file() and not leftover.is_symlink():
                            leftover.unlink()

    def check_config(self, config: Mapping[str, Any], *, resume: bool) -> None:
        """On ``resume``, an existing ``config.json`` must hold the same ``"settings"`` entry.

        Raises
        ------
        ResultsInUseError
            The folder holds results of other settings, or a ``config.json`` that uavcov did not
            write or cannot read.
        """
        path = self.config_json
        if not path.exists() and not path.is_symlink():
            return
        if not path.is_file():  # a FIFO would block the read forever, a device never end it
            raise ResultsInUseError(
                f"{path} is not a regular file (a folder, FIFO, device or link to none): move it away or write to another folder"
            )
        try:
            previous = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:  # RecursionError: arrays nested thousands deep
            raise ResultsInUseError(f"cannot read {path}: {exc}; move it away or write to another folder") from None
        if not _is_our_document(previous):
            raise ResultsInUseError(f'{path} is not a uavcov results file (no "format": "{CONFIG_FORMAT}")')
        if not resume:
            return
        old = json.dumps(previous.get("settings"), sort_keys=True, default=json_default)
        new = json.dumps(config.get("settings"), sort_keys=True, default=json_default)
        if old != new:
            raise ResultsInUseError(
                f"{self.path} holds results of other settings (see {path}); resume them with the same settings, or write to another folder"
            )

    def write_config(self, config: Mapping[str, Any], *, resume: bool) -> Path:
        """Write ``config.json`` (atomically), after :meth:`check_config`.

        On ``resume``, an existing ``config.json`` must hold the same ``"settings"`` entry:
        results of two configurations are never mixed in one folder.

        Raises
        ------
        ResultsInUseError
            The folder holds results of other settings, or a ``config.json`` that is not uavcov's.
        """
        self.check_config(config, resume=resume)
        path = self.config_json
        _refuse_link(path)
        atomic_write(path, json.dumps(config, indent=2, sort_keys=True, default=json_default) + "\n")
        return path

    @contextlib.contextmanager
    def lock(self) -> Iterator[None]:
        """Hold ``.uavcov.lock`` so that two processes never write the folder at once.

        An advisory ``flock``: the system drops it when the process dies, so a crash leaves no
        stale lock. Re-entrant within one process. Does nothing where ``fcntl`` is missing
        (Windows).

        Raises
        ------
        ResultsInUseError
            Another process holds the lock.
        """
        try:
            import fcntl
        except ImportError:  # no advisory locks here; the folder is written unguarded
            yield
            return
        key = self.path.resolve()
        if key in _HELD_LOCKS:
            fd, depth = _HELD_LOCKS[key]
            _HELD_LOCKS[key] = (fd, depth + 1)
            try:
                yield
            finally:
                fd, depth = _HELD_LOCKS[key]
                _HELD_LOCKS[key] = (fd, depth - 1)
            return
        lock_file = key / ".uavcov.lock"
        try:
            fd = os.open(lock_file, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0), 0o666)
        except OSError as exc:  # a symbolic link there (O_NOFOLLOW), no permission, ...
            raise ResultsFolderError(f"cannot open the lock file {key / '.uavcov.lock'}: {exc.strerror or exc}") from exc
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)
            raise ResultsInUseError(f"another uavcov process is writing to {self.path}; wait for it or write to another folder") from None
        _HELD_LOCKS[key] = (fd, 1)
        try:
            yield
        finally:
            del _HELD_LOCKS[key]
            os.close(fd)  # closing the descriptor releases the lock
