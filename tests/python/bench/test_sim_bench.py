"""bench sim's pick loop on the smallest round (one object): the CPU breakdown covers the
round, every physics step is accounted, the factor is simulated over CPU seconds."""

from __future__ import annotations

import pytest

from grasp_pipeline.app.sim_system import SECTIONS
from grasp_pipeline.bench.pick_loop_bench import ACCOUNTS, run_pick_loop
from grasp_pipeline.settings import load_settings


def test_pick_loop_figures_of_a_one_object_round():
    settings = load_settings(SECTIONS, sets=["sim.object_count=[1,1]"])
    out = run_pick_loop("random", 5, "builtin", settings)
    assert out.status == "complete", out.error
    assert out.picks >= 1
    parts = out.breakdown_cpu_s
    assert set(parts) == set(ACCOUNTS)
    assert sum(parts.values()) == pytest.approx(out.cpu_seconds, abs=1e-9)
    assert all(parts[k] > 0 for k in ("physics", "render", "perception", "planning", "control"))
    assert out.physics_steps == round(out.sim_seconds / settings.sim.timestep_s)
    assert out.cpu_real_time_factor == pytest.approx(out.sim_seconds / out.cpu_seconds)
    assert sum(out.breakdown_share.values()) == pytest.approx(1.0)
    assert 0 < out.accounting_cpu_s < 0.2 * out.cpu_seconds
