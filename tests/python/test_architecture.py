"""The package's shape: who imports whom, no cycles, short functions, no import-time effects."""

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

import grasp_pipeline

PKG = Path(grasp_pipeline.__file__).parent
MAX_FUNCTION_LINES = 60
#: Packages that talk to the robot only through grasp_pipeline.robot's protocols.
SIM_FREE = ("motion", "perception", "orchestration", "robot", "language")


def _modules() -> dict[str, Path]:
    out = {}
    for path in PKG.rglob("*.py"):
        rel = path.relative_to(PKG.parent).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


def _imports(name: str, path: Path, top_level_only: bool) -> set[str]:
    """Modules of grasp_pipeline that ``name`` imports (resolving relative imports)."""
    tree = ast.parse(path.read_text())
    is_pkg = path.name == "__init__.py"
    base = name.split(".") if is_pkg else name.split(".")[:-1]
    nodes = tree.body if top_level_only else list(ast.walk(tree))
    found = set()
    for node in nodes:
        if isinstance(node, ast.ImportFrom):
            if node.level:
                mod = ".".join(base[: len(base) - node.level + 1] + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            found.add(mod)
            found.update(f"{mod}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
    mods = _modules()
    return {m for m in found if m in mods and m != name}


def test_motion_perception_orchestration_never_import_the_simulator():
    offenders = []
    for name, path in _modules().items():
        if name.split(".")[1:2] and name.split(".")[1] in SIM_FREE:
            for dep in _imports(name, path, top_level_only=False):
                if dep.startswith("grasp_pipeline.sim") or dep.startswith("grasp_pipeline.app") \
                        or dep.startswith("grasp_pipeline.evaluation"):
                    offenders.append(f"{name} imports {dep}")
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
        for dep in _imports(name, mods[name], top_level_only=False):
            if dep.startswith(("grasp_pipeline.sim", "grasp_pipeline.evaluation", "grasp_pipeline.bench")) \
                    or dep in SIM_APP:
                offenders.append(f"{name} imports {dep}")
            todo.append(dep)
    assert all(m in mods for m in GENERIC_APP)
    assert offenders == []


def test_ground_truth_is_read_only_by_evaluation_code():
    allowed = ("grasp_pipeline.evaluation", "grasp_pipeline.bench", "grasp_pipeline.sim")
    offenders = [f"{n} imports it" for n, p in _modules().items()
                 if not n.startswith(allowed)
                 and "grasp_pipeline.sim.ground_truth" in _imports(n, p, top_level_only=False)]
    assert offenders == []


def test_no_import_cycles_between_modules():
    mods = _modules()
    graph = {n: {d for d in _imports(n, p, top_level_only=True)} for n, p in mods.items()}
    # a package's __init__ re-exporting its submodules is not a cycle with them
    graph = {n: {d for d in deps if not n.startswith(d + ".")} for n, deps in graph.items()}
    state, cycles = {}, []

    def visit(n, stack):
        state[n] = 1
        for d in graph.get(n, ()):
            if state.get(d) == 1:
                cycles.append(" -> ".join(stack[stack.index(d):] + [d]))
            elif d not in state:
                visit(d, stack + [d])
        state[n] = 2

    for n in graph:
        if n not in state:
            visit(n, [n])
    assert cycles == []


def test_no_python_function_is_longer_than_60_lines():
    long = []
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES:
                    long.append(f"{name}.{node.name}: {n} lines")
    assert long == []


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
