"""The package's layers, enforced: every import of every module points down, never at a caller.

Layers from the bottom up (docs/design.md): the shared helpers, ``engine``, ``terrain``, ``structures``,
``placement`` and ``optim``, the mission (``mission.py``, ``records.py``), ``experiments`` and
``field``, the paper (``paper``: its experiments, reproduction, reports and claims, which
``plotting`` draws beside the runs), ``plotting``, and the command line on top. A module imports from a lower layer, or
from its own unit (its folder; the shared helpers, the mission's two files and the command line's count as one each); it reaches another
folder only through that folder's ``__init__`` (its public names), never a private module or
name. Lazy imports inside functions count like the others.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "python" / "uavcov"

# unit -> layer. A unit is a folder of the package, or one top-level module.
LAYERS = {
    "errors": 1,
    "_validate": 1,
    "_io": 1,
    "_core": 1,
    "engine": 2,
    "terrain": 3,
    # Structures, not height fields: a structure file is read with terrain's mesh loader.
    "structures": 3.5,
    # Where a team may fly, then the candidate viewpoints and how good a placement can be: above
    # the surfaces they judge, under the starts (the greedy start is cover's) and the optimisers.
    "limits": 3.7,
    "cover": 3.8,
    "placement": 4,
    "optim": 4,
    "settings": 5,
    "mission": 5,
    "records": 5,
    "experiments": 6,
    "field": 6,
    # The flown mission: above the mission and the optimiser it wraps; under the paper, whose
    # realistic scenario it flies.
    "sim": 6,
    "paper": 7,
    "plotting": 8,
    "cli": 9,
    "__main__": 9,
    "__init__": 9,
}
# Units of one layer that form one idea and may import each other: the shared helpers, the
# mission's settings, its run and its record, the command line.
ONE_IDEA = ({"errors", "_validate", "_io", "_core"}, {"settings", "mission", "records"}, {"cli", "__main__", "__init__"})
# Top-level private modules every layer shares (the extension, argument checks, atomic writes).
SHARED_PRIVATE = {"_core", "_validate", "_io"}


def _unit_of(module: str) -> str:
    """``engine._surface`` -> ``engine``; ``mission`` -> ``mission``; ``""`` (the package) -> ``__init__``."""
    return module.split(".", maxsplit=1)[0] if module else "__init__"


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imports(path: Path, module: str) -> list[tuple[int, str, list[str]]]:
    """Every import of the package by ``module``: (line, the module imported, the names taken)."""
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".") if package else []
                base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                target = ".".join([*base, node.module] if node.module else base)
            elif node.module and (node.module == "uavcov" or node.module.startswith("uavcov.")):
                target = node.module.removeprefix("uavcov").lstrip(".")
            else:
                continue
            names = [alias.name for alias in node.names]
            if node.module is None or (not node.level and node.module == "uavcov"):
                # `from . import x`: each name may be a module of the package
                found.extend((node.lineno, f"{target}.{name}".strip("."), []) for name in names)
            else:
                found.append((node.lineno, target, names))
        elif isinstance(node, ast.Import):
            found.extend(
                (node.lineno, alias.name.removeprefix("uavcov").lstrip("."), [])
                for alias in node.names
                if alias.name == "uavcov" or alias.name.startswith("uavcov.")
            )
    return found


def layer_violations(root: Path) -> list[str]:
    """What breaks the layering in the package at ``root`` (one line each; empty when it holds)."""
    problems = []
    for path in sorted(root.rglob("*.py")):
        module = _module_name(path, root)
        unit = _unit_of(module)
        if unit not in LAYERS:
            problems.append(f"{module}: not in any layer (add its folder to LAYERS and to docs/design.md)")
            continue
        for line, target, names in _imports(path, module):
            other = _unit_of(target)
            where = f"{path.relative_to(root)}:{line}"
            if other not in LAYERS:
                problems.append(f"{where}: imports {target!r}, which is in no layer")
                continue
            same = other == unit or any({unit, other} <= group for group in ONE_IDEA)
            if not same and LAYERS[other] >= LAYERS[unit]:
                problems.append(
                    f"{where}: {unit} (layer {LAYERS[unit]}) imports {target or 'uavcov'} (layer {LAYERS[other]}), not below it"
                )
            if not same and other not in SHARED_PRIVATE:
                private = [part for part in target.split(".")[1:] if part.startswith("_")]
                private += [name for name in names if name.startswith("_") and name != "__version__"]
                if private:
                    problems.append(f"{where}: {unit} takes private {private} of {other}; import its public names from uavcov.{other}")
    return problems


def test_every_import_points_down() -> None:
    assert layer_violations(PACKAGE) == []


def test_every_folder_lists_its_public_names() -> None:
    for init in sorted(PACKAGE.glob("*/__init__.py")):
        tree = ast.parse(init.read_text(encoding="utf-8"))
        declared = [n for n in tree.body if isinstance(n, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in n.targets)]
        assert declared, f"{init.parent.name}/__init__.py has no __all__"
        for module in init.parent.glob("*.py"):
            if module.name != "__init__.py":
                assert module.name.startswith("_"), f"{init.parent.name}/{module.name}: a folder's modules are private (_name.py)"


@pytest.mark.parametrize(
    "module, planted",
    [
        ("engine/_targets.py", "from ..mission import MissionSettings\n"),  # a layer up
        ("terrain/_hills.py", "def later():\n    from ..placement import cvt\n"),  # lazy, a layer up
        ("experiments/_sweep.py", "from ..field import plan\n"),  # a sibling of the same layer
        ("experiments/_summary.py", "def later():\n    from ..paper import EXPERIMENTS\n"),  # the paper, above every study
        ("experiments/_results.py", "from uavcov.paper import reproduce\n"),  # the paper, by its absolute name
        ("mission.py", "from .engine._surface import Terrain\n"),  # a private module of another folder
        ("field/_plan.py", "from ..terrain import _dem\n"),  # a private name of another folder
    ],
)
def test_a_planted_import_is_caught(tmp_path: Path, module: str, planted: str) -> None:
    copy = tmp_path / "uavcov"
    for path in PACKAGE.rglob("*.py"):
        target = copy / path.relative_to(PACKAGE)
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(path.read_text(encoding="utf-8"), encoding="utf-8")
    (copy / module).write_text((copy / module).read_text(encoding="utf-8") + "\n" + planted, encoding="utf-8")
    problems = layer_violations(copy)
    assert len(problems) == 1 and problems[0].startswith(module), problems
