"""The hand-tidied type stubs (python/grasp_pipeline/_core.pyi) must not drift from the
compiled module: every public name of `_core`, every public attribute of its classes and
the parameter names of its functions and methods must appear in the stub.
"""

import ast
import inspect
from pathlib import Path

import pytest

import grasp_pipeline
from grasp_pipeline import _core

PKG = Path(grasp_pipeline.__file__).resolve().parent
STUB = PKG / "_core.pyi"
# stub-only type aliases (documented in the stub; not module attributes)
STUB_ONLY = {"Vec3", "Mat3", "Mat4", "Vec3Like", "Mat3Like", "Points"}


def _stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"), filename=str(STUB))


def _names_in(body):
    """name -> node for the definitions of one module/class body."""
    out = {}
    for node in body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            out.setdefault(node.name, node)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            out.setdefault(node.target.id, node)
        elif isinstance(node, ast.Assign):
            for t in node.targets:
                if isinstance(t, ast.Name):
                    out.setdefault(t.id, node)
    return out


STUB_TOP = _names_in(_stub_tree().body)
RUNTIME_TOP = sorted(n for n in dir(_core) if not n.startswith("_"))
RUNTIME_CLASSES = sorted(n for n in RUNTIME_TOP if inspect.isclass(getattr(_core, n)))
RUNTIME_FUNCS = sorted(n for n in RUNTIME_TOP if callable(getattr(_core, n)) and n not in RUNTIME_CLASSES)


def _split_top_level(s):
    parts, depth, cur = [], 0, ""
    for ch in s:
        if ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(cur)
            cur = ""
        else:
            cur += ch
    if cur.strip():
        parts.append(cur)
    return parts


def runtime_param_names(func):
    """Parameter names from pybind11's signature line(s) (one list per overload)."""
    doc = func.__doc__ or ""
    sigs = []
    for line in doc.splitlines():
        line = line.strip()
        head = func.__name__ + "("
        if line.startswith(head) or (line[:3].rstrip(".").isdigit() and head in line):
            inner = line[line.index(head) + len(head):]
            depth, end = 1, 0
            for i, ch in enumerate(inner):
                depth += ch == "("
                depth -= ch == ")"
                if depth == 0:
                    end = i
                    break
            params = [p.split(":")[0].split("=")[0].strip() for p in _split_top_level(inner[:end])]
            sigs.append([p for p in params if p and p != "self"])
    return sigs


def stub_param_names(node):
    args = node.args
    names = [a.arg for a in args.posonlyargs + args.args + args.kwonlyargs]
    return [n for n in names if n != "self"]


def test_stub_and_marker_files_exist():
    assert STUB.is_file()
    assert (PKG / "py.typed").is_file()
    assert (PKG / "py.typed").read_text() == ""


def test_stub_is_valid_python_with_no_stray_any_for_arrays():
    text = STUB.read_text(encoding="utf-8")
    ast.parse(text)
    # arrays are typed with numpy.typing, not the stubgen placeholder
    assert "points: typing.Any" not in text and "numpy.typing.NDArray[numpy.float64]" in text


@pytest.mark.parametrize("name", RUNTIME_TOP)
def test_every_public_module_attribute_is_in_the_stub(name):
    assert name in STUB_TOP, f"_core.{name} is missing from {STUB.name}"


def test_stub_declares_nothing_the_module_lacks():
    extra = {n for n in STUB_TOP if not n.startswith("_")} - set(RUNTIME_TOP) - STUB_ONLY
    assert extra == set()


@pytest.mark.parametrize("cls_name", RUNTIME_CLASSES)
def test_every_public_class_attribute_is_in_the_stub(cls_name):
    node = STUB_TOP[cls_name]
    assert isinstance(node, ast.ClassDef)
    stub_members = _names_in(node.body)
    cls = getattr(_core, cls_name)
    missing = [a for a in dir(cls) if not a.startswith("_") and a not in stub_members]
    assert missing == [], f"{cls_name}: {missing} missing from the stub"
    extra = [a for a in stub_members if not a.startswith("_") and not hasattr(cls, a)]
    assert extra == [], f"{cls_name}: the stub declares {extra}, which the module lacks"


@pytest.mark.parametrize("func_name", RUNTIME_FUNCS)
def test_function_parameter_names_match(func_name):
    sigs = runtime_param_names(getattr(_core, func_name))
    assert sigs, f"no signature in _core.{func_name}.__doc__"
    node = STUB_TOP[func_name]
    assert isinstance(node, ast.FunctionDef)
    assert stub_param_names(node) in sigs


def _methods():
    for cls_name in RUNTIME_CLASSES:
        cls = getattr(_core, cls_name)
        for attr in dir(cls):
            if attr.startswith("_") and attr != "__init__":
                continue
            member = inspect.getattr_static(cls, attr)
            if isinstance(member, staticmethod):
                member = member.__func__
            if type(member).__name__ in ("instancemethod", "builtin_function_or_method"):
                yield cls_name, attr


@pytest.mark.parametrize("cls_name, method", list(_methods()))
def test_method_parameter_names_match(cls_name, method):
    cls = getattr(_core, cls_name)
    sigs = runtime_param_names(getattr(cls, method))
    assert sigs, f"no signature in _core.{cls_name}.{method}.__doc__"
    stub_cls = _names_in(STUB_TOP[cls_name].body)
    node = stub_cls.get(method)
    assert isinstance(node, ast.FunctionDef), f"{cls_name}.{method} missing from the stub"
    assert stub_param_names(node) in sigs
