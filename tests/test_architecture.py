"""The package's import graph: no cycles, no import running up the layers.

Reference: the source itself, read with :mod:`ast` (not imported), so every import
counts, including those inside functions and ``if TYPE_CHECKING`` blocks. An import
``from a.b import c`` is an edge to the module ``a.b.c`` when that file exists, else
to ``a.b`` (a package's ``__init__``); a parent package that Python imports on the
way is not an edge (every package's ``__init__`` imports its own modules, and that
is not a cycle in the sense that matters: who needs whom).

What is checked, for the packages listed in ``CHECKED`` (``modalinfo`` and ``closedloop``):

* no import cycle between its modules (strongly connected components of size 1);
* ``modalinfo`` never imports ``closedloop`` or ``paper_figures``;
* modalinfo's subpackages respect the declared layer order ``LAYERS``: a module may
  import from its own layer or any lower one, never from a higher one.

For ``closedloop``: its modules respect ``CLOSEDLOOP_LAYERS`` the same way, its core
(every module but the command line, the sweeps and ``__main__``) imports no
``modalinfo.cli`` or ``modalinfo.batch``, and it has no import cycle
(``KNOWN_CYCLES`` is the place for a cycle a restructure in progress has yet to remove:
each must disappear, none may be added; empty since the issue 19 restructure).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

#: Packages whose graph is read.
PACKAGES = ("modalinfo", "closedloop")
#: Packages whose graph must be acyclic.
CHECKED = ("modalinfo", "closedloop")

#: modalinfo's layers, lowest first; a module imports only from its layer or below.
#: Top-level modules are named by their module name, subpackages by their folder.
LAYERS: tuple[tuple[str, ...], ...] = (
    ("_numba", "_validation", "_stats"),
    ("bases", "servo"),
    ("telemetry",),
    ("io",),
    ("information",),
    ("ordering", "forecast"),
    ("batch",),
    ("cli", "__main__"),
)


#: closedloop's layers, lowest first (same rule). The package's ``__init__`` is above all.
CLOSEDLOOP_LAYERS: tuple[tuple[str, ...], ...] = (
    ("config", "kinds", "theory"),  # numbers, the config and the registry of kinds
    ("optics", "control", "parts", "presets", "resources", "result"),  # parts, what a run returns
    ("model", "state", "simulation", "budget", "training", "aot"),  # the loop, its budget
    ("studies",),  # studies made of runs
    ("sweep", "cli", "__main__"),  # the command line and the sweeps on modalinfo.batch
)
#: closedloop's modules that may use modalinfo's command line and batch layers
CLOSEDLOOP_FRONT = ("closedloop.cli", "closedloop.sweep", "closedloop.__main__")
#: cycles left to a restructure in progress; each must disappear, none may be added
KNOWN_CYCLES: dict[str, list[list[str]]] = {}


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _modules(package: str) -> dict[str, Path]:
    return {_module_name(p): p for p in sorted((ROOT / package).rglob("*.py"))}


def _resolve(name: str, known: set[str]) -> str | None:
    """The module ``name`` refers to (itself, or the package holding it), if ours."""
    while name:
        if name in known:
            return name
        name = name.rpartition(".")[0]
    return None


def _imports(module: str, path: Path, known: set[str]) -> set[str]:
    """Every module of ``known`` that ``module`` imports, at any depth of its code."""
    is_package = path.name == "__init__.py"
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = module.split(".")
                base = base[: len(base) - node.level + (1 if is_package else 0)]
                prefix = ".".join(base + ([node.module] if node.module else []))
            else:
                prefix = node.module or ""
            names = [f"{prefix}.{alias.name}" for alias in node.names]
        else:
            continue
        for name in names:
            target = _resolve(name, known)
            if target is not None and target != module:
                found.add(target)
    return found


def _graph(packages=PACKAGES) -> dict[str, set[str]]:
    modules: dict[str, Path] = {}
    for package in packages:
        modules.update(_modules(package))
    # the other top-level packages of the tree, so that imports of them are seen
    known = set(modules) | {"closedloop", "paper_figures", "modalinfo"}
    return {name: _imports(name, path, known) for name, path in modules.items()}


def _cycles(graph: dict[str, set[str]], package: str) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan), sorted."""
    nodes = sorted(n for n in graph if n == package or n.startswith(package + "."))
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in nodes:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                components.append(sorted(component))

    for v in nodes:
        if v not in index:
            visit(v)
    return sorted(components)


def _layer(module: str, layers=LAYERS) -> int | None:
    """Index in ``layers`` of a module of one package (None for the package itself)."""
    parts = module.split(".")
    if len(parts) < 2:
        return None
    for i, layer in enumerate(layers):
        if parts[1] in layer:
            return i
    raise AssertionError(f"{module} is in no layer; add it (or its subpackage) there")


GRAPH = _graph()


def test_graph_reader_sees_every_kind_of_import(tmp_path):
    # a module written here, with each import form once; the expected edges by hand
    src = (
        "import p.a\n"
        "from p import b\n"
        "from p.c import name\n"
        "def f():\n"
        "    from . import d\n"
        "    from .e import thing\n"
        "    import numpy\n"
    )
    path = tmp_path / "m.py"
    path.write_text(src)
    known = {"p", "p.a", "p.b", "p.c", "p.d", "p.e", "p.m"}
    assert _imports("p.m", path, known) == {"p.a", "p.b", "p.c", "p.d", "p.e"}


def test_cycle_finder_on_a_known_graph():
    graph = {"p.a": {"p.b"}, "p.b": {"p.c"}, "p.c": {"p.a"}, "p.d": {"p.a"}, "p.e": set()}
    assert _cycles(graph, "p") == [["p.a", "p.b", "p.c"]]


@pytest.mark.parametrize("package", CHECKED)
def test_no_import_cycles(package):
    assert _cycles(GRAPH, package) == []


def test_unchecked_packages_have_only_known_cycles():
    for package in sorted(set(PACKAGES) - set(CHECKED)):
        extra = [c for c in _cycles(GRAPH, package) if c not in KNOWN_CYCLES.get(package, [])]
        assert extra == []


def test_report_unchecked_cycles(capsys):
    """Print the cycles of the packages not yet checked (closedloop), for the record."""
    for package in sorted(set(PACKAGES) - set(CHECKED)):
        with capsys.disabled():
            for component in _cycles(GRAPH, package):
                print(f"\n[not yet checked] {package} import cycle: {' <-> '.join(component)}")


def test_modalinfo_never_imports_the_simulator_or_figures():
    offenders = {
        (module, target)
        for module, targets in GRAPH.items()
        if module.startswith("modalinfo")
        for target in targets
        if target.split(".")[0] in ("closedloop", "paper_figures")
    }
    assert offenders == set()


def test_modalinfo_layers_point_down():
    upward = sorted(
        (module, target)
        for module, targets in GRAPH.items()
        if module.startswith("modalinfo.")
        for target in targets
        if target.startswith("modalinfo.")
        and _layer(target) is not None
        and _layer(module) is not None
        and _layer(target) > _layer(module)
    )
    assert upward == []


def _closedloop_upward(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Imports of a closedloop module from a higher layer of CLOSEDLOOP_LAYERS."""
    return sorted(
        (module, target)
        for module, targets in graph.items()
        if module.startswith("closedloop.")
        for target in targets
        if target.startswith("closedloop.")
        and _layer(target, CLOSEDLOOP_LAYERS) > _layer(module, CLOSEDLOOP_LAYERS)
    )


def _core_front_imports(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Imports of modalinfo.cli / modalinfo.batch by closedloop's core modules."""
    return sorted(
        (module, target)
        for module, targets in graph.items()
        if module.split(".")[0] == "closedloop" and module not in CLOSEDLOOP_FRONT
        for target in targets
        if target.split(".")[:2] in (["modalinfo", "cli"], ["modalinfo", "batch"])
    )


def test_closedloop_checks_on_a_known_graph():
    graph = {"closedloop.config": {"closedloop.simulation"},  # upward
             "closedloop.simulation": {"closedloop.config", "modalinfo.batch.engine"},
             "closedloop.sweep": {"modalinfo.batch.engine", "closedloop.training"},
             "closedloop.result": {"modalinfo.cli._common"}}
    assert _closedloop_upward(graph) == [("closedloop.config", "closedloop.simulation")]
    assert _core_front_imports(graph) == [("closedloop.result", "modalinfo.cli._common"),
                                          ("closedloop.simulation", "modalinfo.batch.engine")]


def test_closedloop_layers_point_down():
    assert _closedloop_upward(GRAPH) == []


def test_closedloop_core_uses_only_modalinfos_library():
    assert _core_front_imports(GRAPH) == []
