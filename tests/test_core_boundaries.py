"""The package map of crustview.core as tests: who may import whom, read from the source (ast).

Every ``import`` and ``from ... import`` counts, also those inside functions
(the lazy ones).  ``from package import name`` depends on the package's
``__init__`` and, when ``name`` is a module of it, on that module.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "crustview"
CORE = "crustview.core"

#: What each subpackage of crustview.core may import from crustview (besides itself).
ALLOWED = {
    "paper": ("delaunay", "util", "result", "steps", "errors"),
    "delaunay": ("util", "errors"),
    "analysis": ("delaunay", "samples", "util", "result", "steps", "errors"),
    "samples": ("errors",),
    "util": (),
}


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in ROOT.rglob("*.py")}


MODULES = _modules()


def _is_package(name: str) -> bool:
    return MODULES.get(name, Path()).name == "__init__.py"


@functools.cache
def _imports(name: str) -> frozenset[str]:
    """The crustview modules that module ``name`` imports directly (absolute names).

    Read once per module and process (the source does not change during a run): the closures below
    ask for the same modules hundreds of times.
    """
    tree = ast.parse(MODULES[name].read_text())
    package = name if _is_package(name) else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join([*base, node.module] if node.module else base)
            else:
                target = node.module or ""
            found.add(target)
            found.update(f"{target}.{alias.name}" for alias in node.names if f"{target}.{alias.name}" in MODULES)
    return frozenset(m for m in found if m == "crustview" or m.startswith("crustview."))


def _closure(name: str) -> set[str]:
    seen, todo = set(), [name]
    while todo:
        m = todo.pop()
        for dep in _imports(m):
            # a dotted name also loads its parent packages' __init__ (below crustview.core, whose
            # own __init__ loads the pipeline: importing it explicitly is checked by its own test)
            parts = dep.split(".")
            subs = {".".join(parts[:i]) for i in range(3, len(parts) + 1)} | {dep}
            for sub in sorted(subs):
                if sub in MODULES and sub not in seen:
                    seen.add(sub)
                    todo.append(sub)
    return seen


def _in(module: str, *packages: str) -> bool:
    return any(module == p or module.startswith(p + ".") for p in packages)


def _subpackage_modules(sub: str) -> list[str]:
    return sorted(m for m in MODULES if _in(m, f"{CORE}.{sub}"))


@pytest.mark.parametrize("sub", sorted(ALLOWED))
def test_each_subpackage_imports_only_what_its_docstring_allows(sub):
    allowed = (f"{CORE}.{sub}", *(f"{CORE}.{a}" for a in ALLOWED[sub]))
    wrong = {
        (m, dep)
        for m in _subpackage_modules(sub)
        for dep in _imports(m)
        if not _in(dep, *allowed) and dep not in ("crustview", CORE)
    }
    assert not wrong
    # importing the package crustview.core itself would load the whole pipeline
    assert not {m for m in _subpackage_modules(sub) if CORE in _imports(m) or "crustview" in _imports(m)}


def test_the_paper_imports_nothing_from_the_extension():
    for m in _subpackage_modules("paper"):
        deps = _closure(m)
        assert not {d for d in deps if _in(d, f"{CORE}.robust", f"{CORE}.reconstruct")}, m


def test_analysis_imports_neither_the_extension_nor_the_viewer():
    viewer = ("crustview.scene", "crustview.render", "crustview.qt", "crustview.session", "crustview.animation")
    for m in _subpackage_modules("analysis"):
        deps = _closure(m)
        assert not {d for d in deps if _in(d, f"{CORE}.robust", f"{CORE}.reconstruct", *viewer)}, m


def test_the_core_imports_nothing_of_crustview_outside_it():
    outside = {(m, d) for m in MODULES if _in(m, CORE) for d in _imports(m) if not _in(d, CORE) and d != "crustview"}
    assert not outside


def test_the_boundary_reader_sees_lazy_and_relative_imports():
    # the check above would pass vacuously if the reader missed these
    assert f"{CORE}.delaunay.faces" in _imports(f"{CORE}.paper.candidates")  # from ..delaunay.faces import
    assert f"{CORE}.robust.driver" in _imports(f"{CORE}.reconstruct")
    assert f"{CORE}.delaunay.cgal" in _imports(f"{CORE}.delaunay.triangulation")  # imported inside functions
    assert f"{CORE}.robust.fill_hole" in _closure(f"{CORE}.robust.driver")
