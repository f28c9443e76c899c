"""CpuAccounts: exclusive accounts that add up to the block, wrappers removed afterwards
(instance, class and module attributes), misuse refused. A fake clock makes it exact."""

from __future__ import annotations

import types

import pytest

from grasp_pipeline.bench.cpu_accounts import OTHER, CpuAccounts


class _Clock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now

    def spend(self, seconds: float) -> None:
        self.now += seconds


class _Worker:
    def __init__(self, clock: _Clock) -> None:
        self.clock = clock

    def inner(self) -> str:
        self.clock.spend(2.0)
        return "inner"

    def outer(self) -> str:
        self.clock.spend(1.0)
        out = self.inner()
        self.clock.spend(0.5)
        return "outer+" + out


def test_nested_calls_are_accounted_exclusively_and_add_up():
    clock = _Clock()
    w = _Worker(clock)
    acc = CpuAccounts(clock)
    with acc.measure():
        acc.wrap(w, "outer", "a")
        acc.wrap(w, "inner", "b")
        assert w.outer() == "outer+inner"
        w.inner()
        clock.spend(0.25)  # unclaimed
    assert acc.seconds == {"a": 1.5, "b": 4.0, OTHER: 0.25}
    assert acc.calls == {"a": 1, "b": 2}
    assert acc.total_s == 5.75
    assert sum(acc.shares().values()) == pytest.approx(1.0)


def test_an_exception_is_still_accounted_and_raised():
    clock = _Clock()
    acc = CpuAccounts(clock)

    def fails():
        clock.spend(3.0)
        raise KeyError("x")

    mod = types.SimpleNamespace(fails=fails)
    with acc.measure():
        acc.wrap(mod, "fails", "f")
        with pytest.raises(KeyError):
            mod.fails()
    assert acc.seconds["f"] == 3.0 and acc.seconds[OTHER] == 0.0


def test_wrappers_are_removed_when_the_block_ends():
    clock = _Clock()
    w = _Worker(clock)
    module = types.ModuleType("m")
    module.f = lambda: 1
    original_f = module.f
    acc = CpuAccounts(clock)
    with acc.measure():
        acc.wrap(w, "inner", "b")          # a bound method: instance attribute added
        acc.wrap(_Worker, "outer", "a")    # a class attribute replaced
        acc.wrap(module, "f", "c")         # a module function replaced
        assert w.outer() == "outer+inner" and module.f() == 1
    assert "inner" not in vars(w)
    assert _Worker.__dict__["outer"].__name__ == "outer" and not hasattr(_Worker.outer, "__wrapped__")
    assert module.f is original_f
    assert acc.seconds["a"] == 1.5 and acc.seconds["b"] == 2.0 and acc.calls["c"] == 1


def test_wrapping_outside_a_measured_block_is_refused():
    acc = CpuAccounts(_Clock())
    with pytest.raises(RuntimeError, match="measure"):
        acc.wrap(types.SimpleNamespace(f=lambda: 0), "f", "x")
