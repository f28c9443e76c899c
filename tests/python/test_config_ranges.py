"""One range validator for every parameter set: each number has a declared range, and a value
beyond any bound (each bound of each parameter is tried) is a one-line ConfigError naming
``section.parameter``, the value and the range — before anything runs."""

from __future__ import annotations

import ast
import dataclasses
import inspect
import textwrap
from typing import Mapping

import pytest

from grasp_pipeline.cli import main
from grasp_pipeline.config import build_config
from grasp_pipeline.config_ranges import Range, check_ranges, numeric_fields
from grasp_pipeline.exceptions import ConfigError
from grasp_pipeline.settings import SECTIONS, load_settings, read_defaults, section_class

#: Sets that do not use the shared validator yet (their module is another work's: migrate it
#: by declaring RANGES and calling check_ranges in validate()).
NOT_YET: set = set()
SECTIONS_WITH_RANGES = sorted(set(SECTIONS) - NOT_YET)


@pytest.mark.parametrize("section", SECTIONS_WITH_RANGES)
def test_every_number_of_every_set_has_a_range(section):
    cls = section_class(section)
    missing = sorted(set(numeric_fields(cls)) - set(getattr(cls, "RANGES", {})))
    assert missing == [], f"{section}: no range for {missing}"


def _beyond(rule: Range, is_int: bool) -> list:
    """Values just outside each finite bound of ``rule``."""
    out = []
    if rule.lo is not None:
        out.append(rule.lo if rule.lo_open else (rule.lo - 1 if is_int else rule.lo - max(abs(rule.lo), 1e-3)))
    if rule.hi is not None:
        out.append(rule.hi if rule.hi_open else (rule.hi + 1 if is_int else rule.hi * 2 + 1))
    return out


def _with_item(default, value):
    """A list field's default with its first item (of its first row) replaced by ``value``."""
    if not isinstance(default, tuple):
        return value
    if default and isinstance(default[0], tuple):
        return (((value,) + default[0][1:]),) + default[1:]
    return (value,) + default[1:]


@pytest.mark.parametrize("section", SECTIONS_WITH_RANGES)
def test_a_value_beyond_a_bound_is_refused_naming_the_parameter(section):
    cls = section_class(section)
    defaults = read_defaults(section)
    fields = {f.name: f for f in dataclasses.fields(cls)}
    checked = 0
    for name, rule in cls.RANGES.items():
        is_int = "int" in str(fields[name].type) and "float" not in str(fields[name].type)
        for value in _beyond(rule, is_int):
            values = {**defaults, name: _with_item(fields[name].default, value)}
            with pytest.raises(ConfigError) as info:
                build_config(cls, values, section=section)
            msg = str(info.value)
            assert f"{section}.{name}" in msg and "\n" not in msg and len(msg) < 300, msg
            checked += 1
    assert checked >= len(cls.RANGES)


def test_the_defaults_are_inside_their_ranges():
    settings = load_settings(SECTIONS_WITH_RANGES)
    for section in SECTIONS_WITH_RANGES:
        check_ranges(getattr(settings, section), section)


@pytest.mark.parametrize("item, words", [
    ("grasp.lift_height_m=1e9", "grasp.lift_height_m = 1000000000.0 is out of range: expected a number in (0, 0.5] m"),
    ("motion.control_rate_hz=1e9", "motion.control_rate_hz = 1000000000.0 is out of range"),
    ("motion.cartesian_step_m=1e-12", "motion.cartesian_step_m = 1e-12 is out of range"),
    ("grasp.open_margin_m=1000", "grasp.open_margin_m = 1000.0 is out of range"),
    ("sim.gripper_speed_mps=1e9", "sim.gripper_speed_mps = 1000000000.0 is out of range"),
    ("grasp.held_min_force_N=50", "a force <= close_effort_N = 40 N"),
])
def test_physical_parameters_out_of_range_are_one_line_errors_before_the_run(item, words, tmp_path, caplog):
    rc = main(["run", "--scene", "reference", "--no-video", "--out", str(tmp_path / "out"), "--set", item])
    errors = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
    assert rc == 2 and len(errors) == 1 and words in errors[0], errors
    assert "\n" not in errors[0] and not (tmp_path / "out").exists()


def test_range_texts_name_the_bounds_and_the_unit():
    assert Range(0.0, 0.5, lo_open=True, unit=" m").text("a number") == "a number in (0, 0.5] m"
    assert Range(1, None).text("an integer") == "an integer >= 1"
    assert Range(None, 180.0, unit=" deg").text("a number") == "a number <= 180 deg"
    assert Range(0.0, 1.0, hi_open=True).contains(0.0) and not Range(0.0, 1.0, hi_open=True).contains(1.0)


def test_types_are_checked_with_the_range():
    @dataclasses.dataclass(frozen=True)
    class Demo:
        count: int = 1
        flag: bool = True
        steps_m: tuple[float, ...] = (0.1,)
        RANGES = {"count": Range(1, 10), "steps_m": Range(0.0, 1.0)}

    for kwargs, words in (({"count": 1.5}, "demo.count = 1.5 is not an integer"),
                          ({"count": True}, "demo.count = True is not an integer"),
                          ({"flag": 1}, "demo.flag = 1 is not a bool"),
                          ({"steps_m": 0.5}, "demo.steps_m = 0.5 is not a list"),
                          ({"steps_m": (0.5, float("nan"))}, "demo.steps_m[1] = nan is not a finite"),
                          ({"steps_m": (0.5, 2.0)}, "demo.steps_m[1] = 2.0 is out of range")):
        with pytest.raises(ConfigError, match=words.replace("[", r"\[").replace("]", r"\]")):
            check_ranges(Demo(**kwargs), "demo")


def test_the_shared_opening_and_force_bounds_are_the_robot_s_published_figures():
    from grasp_pipeline.config_ranges import FORCE_N, OPENING_M
    from grasp_pipeline.robot.limits import GRIPPER_MAX_FORCE_N, GRIPPER_MAX_WIDTH_M

    assert (OPENING_M.hi, FORCE_N.hi) == (GRIPPER_MAX_WIDTH_M, GRIPPER_MAX_FORCE_N)


# ----------------------------------------------------------------------------- one validator
#: The shared validator's functions: a config module calls them, it does not wrap them.
SHARED = {"check_ranges", "require", "require_min_max"}


def _is_number(node: ast.AST) -> bool:
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        node = node.operand
    return isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) \
        and not isinstance(node.value, bool)


def _is_field(node: ast.AST) -> bool:
    return isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "self"


def _calls(node: ast.AST) -> set:
    return {n.func.id for n in ast.walk(node) if isinstance(n, ast.Call) and isinstance(n.func, ast.Name)}


def own_range_helpers(module_source: str) -> list:
    """Module-level functions of a config module that check values themselves: they wrap the
    shared validator or compare with numbers (a range of its own)."""
    out = []
    for node in ast.parse(module_source).body:
        if isinstance(node, ast.FunctionDef):
            numbers = [c for c in ast.walk(node) if isinstance(c, ast.Compare)
                       and any(_is_number(x) for x in [c.left, *c.comparators])]
            if _calls(node) & SHARED or numbers:
                out.append(node.name)
    return out


def bounds_outside_ranges(class_source: str) -> list:
    """Comparisons of a parameter with a number in ``validate`` (and the ``_validate*`` methods
    it calls): a bound that belongs in ``RANGES``. A comparison that is one alternative of an
    ``or``/``and`` (``x <= 0 or x >= y``: 0 switches a rule off) is a rule between values."""
    cls = ast.parse(textwrap.dedent(class_source)).body[0]
    in_boolop = {id(v) for n in ast.walk(cls) if isinstance(n, ast.BoolOp) for v in n.values}
    out = []
    for fn in cls.body:
        if not (isinstance(fn, ast.FunctionDef) and fn.name.startswith(("validate", "_validate"))):
            continue
        for c in ast.walk(fn):
            if isinstance(c, ast.Compare) and id(c) not in in_boolop:
                ops = [c.left, *c.comparators]
                if all(_is_field(x) or _is_number(x) for x in ops) and any(map(_is_number, ops)) \
                        and any(map(_is_field, ops)):
                    out.append(f"{fn.name}: {ast.unparse(c)}")
    return out


def validates_with_the_shared_checker(class_source: str, section: str) -> bool:
    """``validate()`` starts with ``check_ranges(self, "<section>")`` (after its docstring)."""
    cls = ast.parse(textwrap.dedent(class_source)).body[0]
    fn = next((f for f in cls.body if isinstance(f, ast.FunctionDef) and f.name == "validate"), None)
    if fn is None:
        return False
    body = [b for b in fn.body if not (isinstance(b, ast.Expr) and isinstance(b.value, ast.Constant))]
    first = body[0].value if body and isinstance(body[0], ast.Expr) else None
    return (isinstance(first, ast.Call) and isinstance(first.func, ast.Name) and first.func.id == "check_ranges"
            and len(first.args) == 2 and isinstance(first.args[0], ast.Name) and first.args[0].id == "self"
            and isinstance(first.args[1], ast.Constant) and first.args[1].value == section)


@pytest.mark.parametrize("section", sorted(SECTIONS))
def test_every_set_checks_its_ranges_with_the_one_shared_validator(section):
    cls = section_class(section)
    assert isinstance(cls.__dict__.get("RANGES"), Mapping), f"{section}: no RANGES declared"
    assert validates_with_the_shared_checker(inspect.getsource(cls), section), \
        f"{section}: validate() must start with check_ranges(self, {section!r})"
    assert bounds_outside_ranges(inspect.getsource(cls)) == [], f"{section}: bounds belong in RANGES"
    assert own_range_helpers(inspect.getsource(inspect.getmodule(cls))) == [], \
        f"{section}: use config_ranges' require / require_min_max, not a helper of its own"


def test_the_checks_of_the_shared_validator_rule_can_fail():
    module = textwrap.dedent("""
        def _require(ok, name, value, expected):
            require(ok, "demo", name, value, expected)

        def _positive(x):
            return x > 0

        def synonyms(pairs):
            return dict(p.split("=") for p in pairs)
        """)
    assert own_range_helpers(module) == ["_require", "_positive"]
    cls = textwrap.dedent("""
        class Demo:
            RANGES = {}

            def validate(self):
                check_ranges(self, "other")
                _require(0.001 <= self.voxel_m <= 0.1, "voxel_m", self.voxel_m, "[0.001, 0.1] m")
                require(self.max_extent <= 0 or self.max_extent >= self.min_extent, "demo", "x", 1, "")
                self._validate_more()

            def _validate_more(self):
                require(self.frames >= 1, "demo", "frames", self.frames, ">= 1")
        """)
    assert bounds_outside_ranges(cls) == ["validate: 0.001 <= self.voxel_m <= 0.1",
                                          "_validate_more: self.frames >= 1"]
    assert not validates_with_the_shared_checker(cls, "demo")
    assert validates_with_the_shared_checker(cls, "other")
