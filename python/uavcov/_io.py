"""Atomic file writes: the one way uavcov puts a file on disk.

A file is written to a temporary name in its own folder, synced, then renamed over its target
(``os.replace``): a reader sees the old file or the whole new one, never half of it, and a crash
leaves at most a ``.tmp-*`` file behind. The rename replaces the target itself, so a symbolic
link there is replaced, never followed. Every file gets :func:`file_mode`, the mode ``open()``
would give it, so a folder holds one mode whatever wrote its files.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import IO

from .errors import ResultsFolderError

__all__ = ["atomic_write", "atomic_write_with", "file_mode", "make_parent", "refuse_what_is_no_file"]


def file_mode() -> int:
    """The mode of every file uavcov writes: ``0o666`` less the process's umask (0o644 usually).

    What ``open()`` gives a new file; :func:`tempfile.mkstemp` makes 0o600 files, which the
    writers here widen to this.
    """
    with contextlib.suppress(OSError, ValueError), open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("Umask:"):
                return 0o666 & ~int(line.split()[1], 8)
    mask = os.umask(0o022)  # no /proc: read the umask by setting it, then put it back
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write_with(path: str | os.PathLike[str], write: Callable[[IO[bytes]], object]) -> None:
    """Call ``write`` on a binary file that becomes ``path`` once it returns, synced.

    On any exception the temporary file is removed and ``path`` is left as it was.

    Raises
    ------
    ResultsFolderError
        (an ``OSError``) ``path`` cannot be written, naming it (not the temporary file): its
        folder is missing or a file, the name is too long, or a folder, FIFO, socket or device
        stands there (the rename would replace a device node, as root, by a file).
    """
    target = refuse_what_is_no_file(Path(path))
    try:
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=".tmp-", suffix=target.suffix)
    except OSError as exc:  # name the file asked for, not the temporary one
        raise ResultsFolderError(f"cannot write {target}: {exc.strerror or exc}") from exc
    try:
        with os.fdopen(fd, "wb") as out:
            if hasattr(os, "fchmod"):  # not on Windows, where modes mean little
                os.fchmod(out.fileno(), file_mode())
            write(out)
            out.flush()
            os.fsync(out.fileno())
        os.replace(tmp, target)
    except BaseException as exc:
        Path(tmp).unlink(missing_ok=True)
        if isinstance(exc, OSError) and not isinstance(exc, ResultsFolderError):
            raise ResultsFolderError(f"cannot write {target}: {exc.strerror or exc}") from exc
        raise


def refuse_what_is_no_file(target: Path) -> Path:
    """``target`` unless a folder, FIFO, socket or device stands there (a file or a link may).

    Writing there would fail late (a folder), block until a reader comes (a FIFO), or, renamed
    over as root, replace a device node such as ``/dev/null`` by a file.

    Raises
    ------
    ResultsFolderError
        What stands at ``target`` is no file.
    """
    try:
        mode = target.lstat().st_mode
    except OSError:  # nothing there yet (or nothing reachable: the write says which)
        return target
    if not (stat.S_ISREG(mode) or stat.S_ISLNK(mode)):  # a link is replaced, never followed
        kind = "a folder" if stat.S_ISDIR(mode) else "a FIFO, socket or device"
        raise ResultsFolderError(f"cannot write {target}: {kind} stands there, not a file")
    return target


def make_parent(target: Path) -> Path:
    """``target`` with its folder (and theirs) made, for a writer that makes its own folders.

    Raises
    ------
    ResultsFolderError
        The folder cannot be made (a file stands in its path, no permission, ...).
    """
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ResultsFolderError(f"cannot make the folder of {target}: {exc.strerror or exc}") from exc
    return target


def atomic_write(path: str | os.PathLike[str], data: str | bytes) -> None:
    """Write ``data`` (text as UTF-8) to ``path`` atomically; see the module."""
    payload = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    atomic_write_with(path, lambda out: out.write(payload))
