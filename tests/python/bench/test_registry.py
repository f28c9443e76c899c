"""The benchmark registry the command line is built from (bench/registry.py), and ``bench
language`` (registered there) run through the command line on a one-object scene (real MuJoCo,
PCL core, scan; the truth only scores)."""

from __future__ import annotations

import json

import pytest

from grasp_pipeline.bench.registry import BENCHMARKS, Benchmark
from grasp_pipeline.cli import _uses_mujoco, build_parser, main


def test_every_registered_benchmark_is_a_bench_sub_command():
    parser = build_parser()
    assert list(BENCHMARKS) == ["perception", "sim", "planning", "grasp", "workers", "frames", "clutter",
                                "language"]
    for name, b in BENCHMARKS.items():
        assert isinstance(b, Benchmark) and b.name == name
        args = parser.parse_args(["bench", name, "--json", "x.json"])
        assert args.bench == name and _uses_mujoco(args) == (name != "perception")


def test_a_registered_benchmark_rejects_bad_arguments_like_the_others(capsys):
    with pytest.raises(SystemExit):
        build_parser().parse_args(["bench", "language", "--scene", "heap"])
    assert "invalid choice: 'heap'" in capsys.readouterr().err


def test_bench_language_names_the_perceived_object(tmp_path, capsys):
    json_path = tmp_path / "language.json"
    rc = main(["--log-level", "WARNING", "bench", "language", "--scene", "sparse", "--seeds", "0",
               "--set", "sim.object_count=[1,1]", "--json", str(json_path)])
    assert rc == 0
    out = capsys.readouterr().out
    assert out.startswith("1 objects, scenes ['sparse'] seeds [0]") and "colour (true: perceived counts)" in out
    res = json.loads(json_path.read_text())
    assert set(res) == {"rows", "colour", "shape", "cpu_s"} and len(res["rows"]) == 1
    row = res["rows"][0]
    assert (row["scene"], row["seed"]) == ("sparse", 0) and row["true_shape"] in ("box", "cylinder")
    assert row["colour"] != "missed" and row["tid"] is not None  # the one object was seen and named
    assert res["colour"] == {row["true_colour"]: {row["colour"]: 1}}
