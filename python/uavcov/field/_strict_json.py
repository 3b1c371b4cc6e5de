"""JSON as RFC 8259 defines it, both ways: no NaN, no Infinity, whatever Python's json allows.

Python's :mod:`json` writes ``NaN`` and ``Infinity`` by default and reads them back, but they are
not JSON: QGroundControl, browsers and GIS tools refuse such a file. Every JSON file a plan writes
goes through :func:`json_bytes`, and every reader through :func:`read_json`.
"""

from __future__ import annotations

import json
import os
from typing import Any

from ..errors import InvalidInputError


def json_bytes(document: Any, *, indent: int | None = None, what: str = "a plan file") -> bytes:
    """``document`` as UTF-8 JSON text ending in a newline; a non-finite number is an error, never ``NaN``.

    Raises
    ------
    InvalidInputError
        ``document`` holds NaN or an infinity (the message names ``what``).
    """
    try:
        text = json.dumps(document, indent=indent, allow_nan=False)
    except ValueError as exc:
        raise InvalidInputError(f"{what} would hold a number that is not finite ({exc}); nothing was written") from None
    return (text + "\n").encode("utf-8")


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a JSON number")


def unique_names(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON object as a dict, refusing a name it gives twice (``object_pairs_hook``).

    RFC 8259 leaves an object with a repeated name to each reader: Python keeps the last value,
    others the first, so a GIS would show one area and uavcov plan another.
    """
    document: dict[str, Any] = {}
    for name, value in pairs:
        if name in document:
            raise ValueError(f"the name {name!r} appears twice in one object (readers disagree on which counts)")
        document[name] = value
    return document


def read_json(path: Any) -> dict[str, Any]:
    """A JSON object from ``path``, strictly: ``NaN``, ``Infinity`` and ``-Infinity`` are refused.

    Raises
    ------
    InvalidInputError
        The file cannot be read, is not strict JSON, or is not an object.
    """
    try:
        with open(os.fspath(path), encoding="utf-8") as handle:
            document = json.load(handle, parse_constant=_no_constant, object_pairs_hook=unique_names)
    except (OSError, UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise InvalidInputError(f"cannot read {path} as JSON: {exc}") from None
    if not isinstance(document, dict):
        raise InvalidInputError(f"{path}: expected a JSON object")
    return document
