"""Each subpackage's ``__all__`` is what a user calls: a few names, each used outside the tests.

A name earns its place in a subpackage's ``__all__`` by a use somewhere a user would meet it:
another module of the package (the command line included), ``docs/tutorials``,
``docs/gallery``, ``docs/figures``, ``scripts``, ``benches``, ``examples`` or the README; or as a type a public
function takes or returns (a result a user reads, as scipy's ``OptimizeResult``). A name only the tests
use is private: the tests import it from its private module, as scikit-learn's do. The limit
on each ``__all__`` keeps a folder's reference a page a newcomer reads whole.
"""

from __future__ import annotations

import ast
import functools
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "python" / "uavcov"

# The subpackages and the most names each may list. A limit only comes down.
LIMITS = {
    "engine": 25,
    "terrain": 21,
    "structures": 14,
    "limits": 25,
    "cover": 25,
    "placement": 14,
    "optim": 25,
    "experiments": 25,
    "paper": 25,
    "field": 25,
    "plotting": 25,
}
# Where a user meets a name, beside the package's other modules.
USER_FACING = ("docs/tutorials", "docs/gallery", "docs/figures", "scripts", "benches", "examples")
README = "README.md"


def declared_names(init: Path) -> list[str]:
    """The ``__all__`` of a package's ``__init__.py``, read without importing it."""
    for node in ast.parse(init.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets):
            return [ast.literal_eval(element) for element in node.value.elts]  # type: ignore[attr-defined]
    raise AssertionError(f"{init} has no __all__")


@functools.cache
def _python_words(path: Path) -> set[str]:
    """The identifiers a Python file uses (names, attributes, imported names); not its strings or comments."""
    words: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Name):
            words.add(node.id)
        elif isinstance(node, ast.Attribute):
            words.add(node.attr)
        elif isinstance(node, ast.alias):
            words.add(node.name.rpartition(".")[2])
    return words


@functools.cache
def _text_words(path: Path) -> set[str]:
    return set(re.findall(r"[A-Za-z_][A-Za-z0-9_]*", path.read_text(encoding="utf-8", errors="replace")))


def used_outside(root: Path, unit: str) -> set[str]:
    """Every identifier used outside the tests and outside the folder ``unit`` of the package at ``root``."""
    package = root / "python" / "uavcov"
    words: set[str] = set()
    for path in package.rglob("*.py"):
        if path.relative_to(package).parts[0] != unit:
            words |= _python_words(path)
    for place in USER_FACING:
        for path in sorted((root / place).rglob("*")):
            if path.is_file():
                words |= (
                    _python_words(path)
                    if path.suffix == ".py"
                    else _text_words(path)
                    if path.suffix in {".md", ".rst", ".toml", ".sh"}
                    else set()
                )
    if (root / README).is_file():
        words |= _text_words(root / README)
    return words


def _annotation_words(node: ast.AST) -> set[str]:
    return {n.id for n in ast.walk(node) if isinstance(n, ast.Name)} | {n.attr for n in ast.walk(node) if isinstance(n, ast.Attribute)}


def met_through(folder: Path, names: set[str]) -> set[str]:
    """The types a user meets through the public ``names`` of ``folder``: what a public function or
    method takes or returns, and the fields of a public class (a result's type is read, not called)."""
    words: set[str] = set()
    for path in folder.glob("*.py"):
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, ast.FunctionDef | ast.ClassDef) and node.name in names:
                members = [node] if isinstance(node, ast.FunctionDef) else node.body
                for member in members:
                    if isinstance(member, ast.FunctionDef) and (
                        member is node or not member.name.startswith("_") or member.name == "__init__"
                    ):
                        for annotation in [a.annotation for a in (*member.args.args, *member.args.kwonlyargs) if a.annotation] + [
                            member.returns
                        ]:
                            words |= _annotation_words(annotation) if annotation is not None else set()
                    elif isinstance(member, ast.AnnAssign) and not getattr(member.target, "id", "_").startswith("_"):
                        words |= _annotation_words(member.annotation)
    return words


def surface_problems(root: Path, planted: dict[str, list[str]] | None = None) -> list[str]:
    """What is wrong with the public surfaces of the package at ``root`` (one line each; empty when none).

    ``planted`` adds names to a subpackage's ``__all__``, to show the check catches them.
    """
    problems = []
    for unit, limit in LIMITS.items():
        names = declared_names(root / "python" / "uavcov" / unit / "__init__.py") + (planted or {}).get(unit, [])
        if len(names) > limit:
            problems.append(
                f"uavcov.{unit} lists {len(names)} names, more than {limit}: move what a user does not call to a private module"
            )
        folder = root / "python" / "uavcov" / unit
        used = set(names) & used_outside(root, unit)
        while (more := set(names) & met_through(folder, used)) - used:
            used |= more
        unused = sorted(set(names) - used)
        if unused:
            problems.append(f"uavcov.{unit} lists names only its own modules or the tests use: {unused}; make them private")
    return problems


def test_every_public_name_is_used_outside_the_tests() -> None:
    assert surface_problems(ROOT) == []


@pytest.mark.parametrize("unit", sorted(LIMITS))
def test_a_name_only_the_tests_use_is_caught(unit: str) -> None:
    problems = surface_problems(ROOT, planted={unit: ["only_the_tests_call_this"]})
    assert [p for p in problems if "only_the_tests_call_this" in p and "make them private" in p], problems


def test_a_surface_past_its_limit_is_caught() -> None:
    used = sorted(used_outside(ROOT, "engine") - set(declared_names(PACKAGE / "engine" / "__init__.py")))
    problems = surface_problems(ROOT, planted={"engine": used[: LIMITS["engine"]]})
    assert problems == [problems[0]] and f"more than {LIMITS['engine']}" in problems[0], problems
