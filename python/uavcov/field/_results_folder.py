"""The folder a plan writes, owned by the run that writes it: a new plan replaces the old as a whole.

A plan's files are written into a fresh sibling folder (``.NAME.tmp-XXXX``, beside ``out``), then
swapped in by renames: a reader sees the old plan or the new one, never a mix (no ``uav_05.plan``
of a five-UAV plan beside a three-UAV plan's files), and a failure leaves ``out`` as it was.

Only a folder that is empty or holds a previous plan (a ``plan.json`` and nothing but the names
a plan writes, :func:`is_plan_file`) is replaced. A folder with anything else in it is refused
(:class:`~uavcov.errors.ResultsInUseError`, naming what is there): a plan never deletes files it
did not write.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import shutil
from pathlib import Path
from typing import Any

from .._io import file_mode
from .._validate import checked_path_text
from ..errors import InvalidTypeError, ResultsFolderError, ResultsInUseError

PLAN_FILE_NAMES = frozenset(
    {
        "positions.csv",
        "waypoints.csv",
        "plan.geojson",
        "plan.kml",
        "coverage.tif",
        "quality.tif",
        "plan.json",
        "report.md",
        "report.png",
        "seen.ply",
        "seen.png",
        "parts.csv",
    }
)
"""Every name a DEM or structure plan writes, besides its ``uav_NN.plan`` files."""

_UAV_PLAN = re.compile(r"uav_\d{2,}\.plan")
_LEFTOVER = re.compile(r"\.tmp-.*")  # a crashed atomic write's temporary file


def is_plan_file(name: str) -> bool:
    """True for a name a plan writes (or a temporary file of an interrupted write)."""
    return name in PLAN_FILE_NAMES or bool(_UAV_PLAN.fullmatch(name) or _LEFTOVER.fullmatch(name))


def check_plan_folder(out: Any) -> None:
    """Refuse, before any work, a folder a plan could not be written into (see the module).

    Raises
    ------
    ResultsInUseError
        ``out`` holds files that are not a plan's.
    ResultsFolderError
        ``out`` is a file or a symbolic link, or cannot be read.
    """
    if not isinstance(out, (str, os.PathLike)):
        raise InvalidTypeError(f"out must be a path, got {type(out).__name__}")
    _check_replaceable(Path(checked_path_text(os.fspath(out), "out")))  # "" would be the working directory


def _check_replaceable(folder: Path) -> bool:
    """Whether ``folder`` exists (then empty or a previous plan's, else refused)."""
    if folder.is_symlink():
        raise ResultsFolderError(f"{folder} is a symbolic link: give the folder itself as --out")
    if not folder.exists():
        return False
    if not folder.is_dir():
        raise ResultsFolderError(f"{folder} exists and is not a folder")
    try:
        entries = sorted(os.listdir(folder))
    except OSError as exc:
        raise ResultsFolderError(f"cannot read {folder}: {exc}") from None
    foreign = [name for name in entries if not is_plan_file(name) or (folder / name).is_dir()]
    if entries and (foreign or "plan.json" not in entries):
        shown = ", ".join((foreign or entries)[:3]) + (" ..." if len(foreign or entries) > 3 else "")
        raise ResultsInUseError(
            f"{folder} holds files that are not a uavcov plan's ({shown}); a plan replaces its folder as a whole, "
            "so give a new or empty folder (--out), or move those files away"
        )
    return True


def write_files(files: dict[str, bytes], out: Any) -> list[Path]:
    """Make the folder ``out`` hold exactly ``files`` (``{name: bytes}``); see the module.

    Returns
    -------
    list of Path
        The files written, in ``files``' order.

    Raises
    ------
    ResultsInUseError
        ``out`` holds files that no plan writes (nothing is changed).
    ResultsFolderError
        ``out`` is a file or a symbolic link, or cannot be created or written.
    """
    if not isinstance(out, (str, os.PathLike)):
        raise InvalidTypeError(f"out must be a path, got {type(out).__name__}")
    folder = Path(checked_path_text(os.fspath(out), "out"))  # "" would replace the working directory
    if any(os.sep in name or name in ("", ".", "..") or not is_plan_file(name) for name in files):
        raise ResultsFolderError(f"not a plan's file names: {sorted(files)}")
    existing = _check_replaceable(folder)
    target = Path(os.path.abspath(folder))  # "." and ".." resolved: the folder has a name and a parent
    parent = target.parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ResultsFolderError(f"cannot create {parent}: {exc}") from None
    staging = _sibling(target, "tmp")
    try:
        staging.mkdir()  # the mode a folder made by mkdir gets (0o777 less the umask)
        for name, data in files.items():
            path = staging / name
            with open(path, "wb") as handle:
                handle.write(data)
                handle.flush()
                os.fsync(handle.fileno())
            os.chmod(path, file_mode())
        _swap_in(staging, target, existing)
    except OSError as exc:
        raise ResultsFolderError(f"cannot write the plan into {folder}: {exc}") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return [folder / name for name in files]


def _sibling(folder: Path, kind: str) -> Path:
    """A fresh name beside ``folder``, ``.NAME.KIND-XXXXXXXX``, its NAME cut to 64 bytes: a folder
    whose own name nears the 255 bytes a name may have still gets a sibling."""
    short = folder.name.encode()[:64].decode(errors="ignore")
    return folder.parent / f".{short}.{kind}-{secrets.token_hex(4)}"


def _swap_in(staging: Path, folder: Path, existing: bool) -> None:
    """Rename ``staging`` to ``folder``; an existing ``folder`` is moved aside first, then removed
    (and put back if the second rename fails)."""
    if not existing:
        os.rename(staging, folder)
        return
    with contextlib.suppress(OSError):
        mode = folder.stat().st_mode & 0o7777
        os.chmod(staging, mode)  # the folder keeps the mode it had
    aside = _sibling(folder, "old")
    os.rename(folder, aside)
    try:
        os.rename(staging, folder)
    except OSError:
        os.rename(aside, folder)
        raise
    shutil.rmtree(aside, ignore_errors=True)
