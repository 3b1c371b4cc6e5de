"""Cross-references to uavcov's objects by any path that reaches them.

Docstrings name objects by the path a reader uses (``uavcov.Terrain``, ``uavcov.plotting.plot_cvt``)
or the private module that defines them (``uavcov.plotting._figures.plot_cvt``); the site
documents each once, at the lowest layer that lists it (``uavcov.engine.Terrain``). A missing
reference is resolved by importing what it names and looking up where that object is
documented. A reference into a private name that has no page is shown as plain code, not as a
warning; any other unresolved reference stays a warning (an error under ``-W``).

At the end of reading, every public name must have been documented: a name of a layer's
``__all__`` with no page is a warning (an error under ``-W``).
"""

from __future__ import annotations

import importlib
from typing import Any

from docutils import nodes
from sphinx.application import Sphinx
from sphinx.environment import BuildEnvironment
from sphinx.util import logging
from sphinx.util.nodes import make_refnode

from .public import MODULES, TOP, canonical_names, public_names

logger = logging.getLogger(__name__)
_CANONICAL: dict[int, str] = {}


def _lookup(path: str) -> Any:
    """The object ``path`` names (a module, then attributes), or None."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        try:
            for part in parts[cut:]:
                obj = getattr(obj, part)
        except AttributeError:
            return None
        return obj
    return None


def _documented(path: str) -> str | None:
    """The documented name of what ``path`` names: the longest prefix that is a documented
    object, with the rest of the path (a method, an attribute) after it."""
    if not _CANONICAL:
        _CANONICAL.update(canonical_names())
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        obj = _lookup(".".join(parts[:cut]))
        if obj is not None and id(obj) in _CANONICAL:
            return ".".join([_CANONICAL[id(obj)], *parts[cut:]])
    return None


def _private(path: str) -> bool:
    return any(p.startswith("_") and not p.startswith("__") for p in path.split("."))


def resolve(app: Sphinx, env: BuildEnvironment, node: Any, contnode: nodes.Element) -> nodes.Element | None:
    if node.get("refdomain") != "py":
        return None
    target = str(node["reftarget"]).lstrip("~.")
    module = node.get("py:module")
    cls = node.get("py:class")
    candidates = [target]
    if module:
        candidates += [f"{module}.{cls}.{target}" if cls else None, f"{module}.{target}"]
    candidates.append(f"{TOP}.{target}")
    objects = env.get_domain("py").objects  # type: ignore[attr-defined]
    for candidate in filter(None, candidates):
        if not candidate.startswith(TOP):
            continue
        name = _documented(candidate)
        if name is not None and name in objects:
            entry = objects[name]
            return make_refnode(app.builder, node["refdoc"], entry.docname, entry.node_id, contnode, name)
    # A short name from a summary shown away from its module (the top page's table): the one
    # documented uavcov object of that name.
    suffix = "." + target
    matches = [name for name in objects if name.startswith(TOP + ".") and name.endswith(suffix)]
    matches = [name for name in matches if name.count(".") == min(m.count(".") for m in matches)]
    if len(matches) == 1:
        entry = objects[matches[0]]
        return make_refnode(app.builder, node["refdoc"], entry.docname, entry.node_id, contnode, matches[0])
    if _private(target):
        return contnode  # a private helper: named in the prose, no page of its own
    return None


def check_every_name(app: Sphinx, env: BuildEnvironment) -> None:
    """Warn for every public name without a page."""
    objects = env.get_domain("py").objects  # type: ignore[attr-defined]
    for module in (*MODULES, TOP):
        for name in public_names(module):
            full = f"{module}.{name}"
            if full in objects:
                continue
            documented = _documented(full)
            if documented is None or documented not in objects:
                logger.warning("the public name %s has no page in the API reference (docs/api)", full)


def setup(app: Sphinx) -> dict[str, Any]:
    app.connect("missing-reference", resolve)
    app.connect("env-check-consistency", check_every_name)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
