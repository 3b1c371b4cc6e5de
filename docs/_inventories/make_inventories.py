"""Write the small intersphinx inventories the site links through (python.inv, numpy.inv, scipy.inv).

The site is built without network (CI reaches only the package indexes), so Sphinx cannot
download the projects' ``objects.inv``. These hold only the objects uavcov's pages name, each at
the address of its entry in that project's documentation, in Sphinx's inventory format (v2).
Add an object here and rerun ``python docs/_inventories/make_inventories.py`` when a page names a
new one (the build fails on the unresolved reference until then).
"""

from __future__ import annotations

import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent

# name, domain:role, uri (relative to the project's root; "$" is the name), display name ("-": the name)
INVENTORIES: dict[str, tuple[str, str, list[tuple[str, str, str, str]]]] = {
    "python": (
        "Python",
        "3",
        [
            *[(n, "py:class", "library/functions.html#$", "-") for n in ("int", "float", "bool", "object")],
            *[(n, "py:class", "library/stdtypes.html#$", "-") for n in ("str", "tuple", "list", "dict", "bytes", "set")],
            *[(n, "py:data", "library/constants.html#$", "-") for n in ("None", "True", "False")],
            ("callable", "py:function", "library/functions.html#$", "-"),
            *[
                (n, "py:exception", "library/exceptions.html#$", "-")
                for n in ("ValueError", "TypeError", "OSError", "ImportError", "TimeoutError")
            ],
            ("pathlib.Path", "py:class", "library/pathlib.html#$", "-"),
            ("os.PathLike", "py:class", "library/os.html#$", "-"),
            ("concurrent.futures.Executor", "py:class", "library/concurrent.futures.html#$", "-"),
            ("sequence", "std:term", "glossary.html#term-sequence", "-"),
            ("iterable", "std:term", "glossary.html#term-iterable", "-"),
            ("path-like object", "std:term", "glossary.html#term-path-like-object", "-"),
            ("bltin-boolean-values", "std:label", "library/stdtypes.html#$", "Boolean Values"),
        ],
    ),
    "numpy": (
        "NumPy",
        "2",
        [
            ("numpy.ndarray", "py:class", "reference/generated/numpy.ndarray.html#$", "-"),
            ("numpy.dtype", "py:class", "reference/generated/numpy.dtype.html#$", "-"),
            ("numpy.random.Generator", "py:class", "reference/random/generator.html#$", "-"),
            ("numpy.random.default_rng", "py:function", "reference/random/generator.html#$", "-"),
            ("numpy.random.SeedSequence", "py:class", "reference/random/bit_generators/generated/numpy.random.SeedSequence.html#$", "-"),
            ("array_like", "std:term", "glossary.html#term-array_like", "-"),
        ],
    ),
    "scipy": (
        "SciPy",
        "1",
        [
            ("scipy.spatial.cKDTree", "py:class", "reference/generated/scipy.spatial.cKDTree.html#$", "-"),
            ("scipy.spatial.Delaunay", "py:class", "reference/generated/scipy.spatial.Delaunay.html#$", "-"),
            (
                "scipy.interpolate.LinearNDInterpolator",
                "py:class",
                "reference/generated/scipy.interpolate.LinearNDInterpolator.html#$",
                "-",
            ),
        ],
    ),
}


def write(name: str, project: str, version: str, entries: list[tuple[str, str, str, str]]) -> Path:
    header = (
        f"# Sphinx inventory version 2\n# Project: {project}\n# Version: {version}\n"
        "# The remainder of this file is compressed using zlib.\n"
    )
    body = "".join(f"{n} {role} 1 {uri} {disp}\n" for n, role, uri, disp in sorted(entries))
    path = HERE / f"{name}.inv"
    path.write_bytes(header.encode() + zlib.compress(body.encode(), 9))
    return path


if __name__ == "__main__":
    for key, (project, version, entries) in INVENTORIES.items():
        print(write(key, project, version, entries))
