"""The package's shape: who imports whom, no cycles, short functions, no import-time effects."""

import ast
import functools
import os
import subprocess
import sys
import textwrap
from dataclasses import dataclass
from pathlib import Path

import pytest

import grasp_pipeline

PKG = Path(grasp_pipeline.__file__).parent
MAX_FUNCTION_LINES = 60
#: Packages that talk to the robot only through grasp_pipeline.robot's protocols.
SIM_FREE = ("motion", "perception", "orchestration", "robot", "language")


@functools.lru_cache(maxsize=None)
def _modules() -> dict[str, Path]:
    out = {}
    for path in PKG.rglob("*.py"):
        rel = path.relative_to(PKG.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


@dataclass(frozen=True)
class ImportSite:
    """Where a module imports another: the line and the function (``Class.method``) it is in
    ("" at module level)."""

    line: int
    function: str

    def __str__(self) -> str:
        return f"line {self.line}" + (f" in {self.function}()" if self.function else "")


class _ImportCollector(ast.NodeVisitor):
    """Every ``import`` / ``from ... import`` of a module, at any depth (module level, functions,
    methods, ``if`` / ``try`` blocks), relative ones resolved against the module's package;
    what it imports -> where."""

    def __init__(self, name: str, is_package: bool) -> None:
        self.package = name.split(".") if is_package else name.split(".")[:-1]
        self.found: dict[str, list[ImportSite]] = {}
        self._functions: list[str] = []

    def _add(self, target: str, node: ast.AST) -> None:
        site = ImportSite(node.lineno, ".".join(self._functions))
        self.found.setdefault(target, []).append(site)

    def _visit_function(self, node) -> None:
        self._functions.append(node.name)
        self.generic_visit(node)
        self._functions.pop()

    visit_FunctionDef = visit_AsyncFunctionDef = visit_ClassDef = _visit_function

    def visit_Import(self, node: ast.Import) -> None:
        for alias in node.names:
            self._add(alias.name, node)

    def visit_ImportFrom(self, node: ast.ImportFrom) -> None:
        if node.level:
            base = self.package[: len(self.package) - node.level + 1]
            module = ".".join(base + ([node.module] if node.module else []))
        else:
            module = node.module or ""
        self._add(module, node)  # (its package's __init__ runs: a dependency even for "from . import x")
        for alias in node.names:
            self._add(f"{module}.{alias.name}", node)  # kept below only when it is a module


def imports_of(name: str, source: str, is_package: bool = False) -> dict[str, list[ImportSite]]:
    """What the module ``name`` with text ``source`` imports (dotted names, relative imports
    resolved; names that are not modules included), at every depth -> where."""
    collector = _ImportCollector(name, is_package)
    collector.visit(ast.parse(source))
    return collector.found


@functools.lru_cache(maxsize=None)
def _import_graph() -> dict[str, dict[str, tuple[ImportSite, ...]]]:
    """module -> {module of grasp_pipeline it imports (module or function level) -> where}."""
    mods = _modules()
    graph = {}
    for name, path in mods.items():
        found = imports_of(name, path.read_text(), path.name == "__init__.py")
        graph[name] = {m: tuple(sites) for m, sites in found.items() if m in mods and m != name}
    return graph


def _imports(name: str) -> set[str]:
    """Modules of grasp_pipeline that ``name`` imports, at module or function level."""
    return set(_import_graph()[name])


def test_the_import_graph_sees_function_level_and_relative_imports():
    source = textwrap.dedent("""
        import numpy
        from . import sibling
        from ..sim import world as w

        def later():
            from ..report.serialize import write_json
            if True:
                import grasp_pipeline.app.run

        class K:
            def method(self):
                from .. import evaluation
    """)
    found = imports_of("grasp_pipeline.bench.x", source)
    for target in ("numpy", "grasp_pipeline.bench", "grasp_pipeline.bench.sibling", "grasp_pipeline.sim",
                   "grasp_pipeline.sim.world", "grasp_pipeline.report.serialize",
                   "grasp_pipeline.app.run", "grasp_pipeline.evaluation"):
        assert target in found, target
    assert [str(s) for s in found["grasp_pipeline.report.serialize"]] == ["line 7 in later()"]
    assert [str(s) for s in found["grasp_pipeline.evaluation"]] == ["line 13 in K.method()"]
    assert imports_of("grasp_pipeline.bench", "from .x import y", is_package=True) == \
        {"grasp_pipeline.bench.x": [ImportSite(1, "")], "grasp_pipeline.bench.x.y": [ImportSite(1, "")]}


def test_motion_perception_orchestration_never_import_the_simulator():
    offenders = []
    for name in _modules():
        if name.split(".")[1:2] and name.split(".")[1] in SIM_FREE:
            for dep, sites in _import_graph()[name].items():
                if dep.startswith(("grasp_pipeline.sim", "grasp_pipeline.app", "grasp_pipeline.evaluation")):
                    offenders.append(f"{name} imports {dep} ({', '.join(map(str, sites))})")
    assert offenders == []


#: The run loop on any robot and its parts: never the simulator, nor its ground truth, not even
#: through what they import (the simulated composition root, app.sim_system, builds on them).
GENERIC_APP = ("grasp_pipeline.app.run_loop", "grasp_pipeline.app.robot_system",
               "grasp_pipeline.app.robot_run", "grasp_pipeline.app.work_cell_file")
SIM_APP = ("grasp_pipeline.app.sim_system", "grasp_pipeline.app.run", "grasp_pipeline.app.run_command")


def test_the_run_loop_on_any_robot_never_reaches_the_simulator():
    mods = _modules()
    seen, todo, offenders = set(), list(GENERIC_APP), []
    while todo:
        name = todo.pop()
        if name in seen:
            continue
        seen.add(name)
        for dep in _imports(name):
            if dep.startswith(("grasp_pipeline.sim", "grasp_pipeline.evaluation", "grasp_pipeline.bench")) \
                    or dep in SIM_APP:
                offenders.append(f"{name} imports {dep}")
            todo.append(dep)
    assert all(m in mods for m in GENERIC_APP)
    assert offenders == []


def test_ground_truth_is_read_only_by_evaluation_code():
    allowed = ("grasp_pipeline.evaluation", "grasp_pipeline.bench", "grasp_pipeline.sim")
    offenders = [f"{n} imports it" for n in _modules()
                 if not n.startswith(allowed) and "grasp_pipeline.sim.ground_truth" in _imports(n)]
    assert offenders == []


def _strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """The groups of modules that import each other, directly or not (Tarjan; groups of 2+)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    groups: list[list[str]] = []

    def visit(n: str) -> None:
        index[n] = low[n] = len(index)
        stack.append(n)
        for d in sorted(graph[n]):
            if d not in index:
                visit(d)
                low[n] = min(low[n], low[d])
            elif d in stack:
                low[n] = min(low[n], index[d])
        if low[n] == index[n]:
            group = []
            while True:
                m = stack.pop()
                group.append(m)
                if m == n:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for n in sorted(graph):
        if n not in index:
            visit(n)
    return groups


def _one_cycle(graph: dict[str, set[str]], group: list[str]) -> list[str]:
    """A shortest cycle through the group's first module (breadth-first within the group)."""
    start, members = group[0], set(group)
    paths = {start: [start]}
    queue = [start]
    while queue:
        n = queue.pop(0)
        for d in sorted(graph[n] & members):
            if d == start:
                return paths[n] + [start]
            if d not in paths:
                paths[d] = paths[n] + [d]
                queue.append(d)
    raise AssertionError(f"no cycle through {start}")


def _describe(cycle: list[str]) -> str:
    sites = _import_graph()
    steps = [cycle[0]] + [f"-> {b} ({', '.join(map(str, sites[a][b]))})" for a, b in zip(cycle, cycle[1:])]
    return " ".join(steps)


def test_no_import_cycles_between_modules():
    """Module-level and function-level imports alike: a cycle hidden in a function's import
    is still two modules that need each other. (A submodule importing its own package is not
    a cycle with the package's __init__ re-exporting it.) Imports of other packages (optional
    extras imported inside functions) are not part of this graph."""
    graph = {n: {d for d in deps if not n.startswith(d + ".")} for n, deps in
             ((n, _imports(n)) for n in _modules())}
    cycles = [_describe(_one_cycle(graph, g)) for g in _strongly_connected(graph)]
    assert cycles == [], "import cycles:\n" + "\n".join(cycles)


def test_no_python_function_is_longer_than_60_lines():
    long = []
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES:
                    long.append(f"{name}.{node.name}: {n} lines")
    assert long == []


def test_no_task_waits_while_it_is_being_closed():
    """A generator that yields in a ``finally`` (or in ``except BaseException``) yields while it is
    closed ("generator ignored GeneratorExit") and swallows an interrupt until it is stepped
    again: cleanup motions go through ``runtime.then_cleanup``."""
    found = []
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Try):
                continue
            blocks = [node.finalbody] + [h.body for h in node.handlers if h.type is None or
                                         ast.unparse(h.type) in ("BaseException", "GeneratorExit")]
            if any(isinstance(m, (ast.Yield, ast.YieldFrom)) for b in blocks for s in b for m in ast.walk(s)):
                found.append(f"{name}: line {node.lineno}")
    assert found == []


def test_orchestration_has_an_explicit_public_api():
    import grasp_pipeline.orchestration as orch

    assert orch.__all__ and all(hasattr(orch, n) for n in orch.__all__)
    for name in ("GraspAction", "ActiveScan", "GraspSource", "EventBus", "pick_object"):
        assert name in orch.__all__


@pytest.mark.parametrize("module", ["grasp_pipeline.sim", "grasp_pipeline.sim.world",
                                    "grasp_pipeline.cli", "grasp_pipeline.orchestration",
                                    "grasp_pipeline.settings", "grasp_pipeline.app.run"])
def test_importing_changes_no_environment(module):
    code = (f"import os; before = dict(os.environ); import {module}; "
            "assert dict(os.environ) == before, set(os.environ.items()) ^ set(before.items())")
    env = {k: v for k, v in os.environ.items() if k != "MUJOCO_GL"}
    res = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr[-2000:]
