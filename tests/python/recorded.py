"""One small ``record`` run shared by the dataset and learning tests (a pytest plugin of the
session): 2 episodes of one-object ``sparse`` scenes, 64 px images, 2 workers of one episode
each, through the installed console script in a clean environment; and a tiny ACT policy
trained 3 steps on it (``train``)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

EXE = Path(sys.executable).parent / "grasp-pipeline"
SEED, EPISODES, IMAGE_PX = 3, 2, 64   # small images: rendering and encoding cost ~ pixels
ONE_OBJECT = ("sim.object_count=[1,1]",)
RECORD_ARGS = ["--log-level", "WARNING", "record", "--protocol", "sparse", "--episodes", str(EPISODES),
               "--seed", str(SEED), "--workers", "2", "--keep-failed", "--no-progress",
               "--image-size", str(IMAGE_PX), "--set", ONE_OBJECT[0], "--set", "env.episodes_per_job=1"]


def clean_env(home: Path) -> dict:
    """What a plain shell gives (PATH, HOME); a developer's ``PYTHONPATH=python`` is passed on
    so that a source checkout runs its own code (``make test`` sets none)."""
    env = {"PATH": f"{EXE.parent}:/usr/local/bin:/usr/bin:/bin", "HOME": str(home), "LANG": "C.UTF-8"}
    if os.environ.get("PYTHONPATH"):
        env["PYTHONPATH"] = os.path.abspath(os.environ["PYTHONPATH"])
    return env


def run_cli(args: list, cwd: Path, timeout_s: float = 1800) -> subprocess.CompletedProcess:
    assert EXE.exists(), f"{EXE} is missing: install the package first (make setup)"
    return subprocess.run([str(EXE), *args], cwd=cwd, env=clean_env(cwd), capture_output=True, text=True,
                          timeout=timeout_s, stdin=subprocess.DEVNULL)


def record(d: Path, backend: str = "local", extra: tuple = ()) -> subprocess.CompletedProcess:
    return run_cli([*RECORD_ARGS, *extra, "--backend", backend, "--out", "ds"], d)


@pytest.fixture(scope="session")
def recorded_dataset(tmp_path_factory):
    """(dataset folder, printed summary) of the shared local run (with ``--rerun recs``)."""
    d = tmp_path_factory.mktemp("recorded")
    res = record(d, "local", ("--rerun", "recs"))
    assert res.returncode == 0 and "Traceback" not in res.stderr, res.stderr[-3000:]
    return d / "ds", json.loads(res.stdout)


TINY_ACT = ["--set", "train.dim_model=32", "--set", "train.dim_feedforward=64", "--set", "train.n_heads=4",
            "--set", "train.chunk_size=5", "--set", "train.n_action_steps=5", "--set", "train.latent_dim=8",
            "--set", "train.torch_threads=1"]


@pytest.fixture(scope="session")
def trained_policy(recorded_dataset, tmp_path_factory):
    """(policy folder, printed summary) of ``train`` a few steps on the shared dataset."""
    d = tmp_path_factory.mktemp("policy")
    res = run_cli(["--log-level", "WARNING", "train", "--dataset", str(recorded_dataset[0]), "--out", "pol",
                   "--steps", "3", "--batch-size", "2", "--image-size", str(IMAGE_PX), *TINY_ACT], d)
    assert res.returncode == 0 and "Traceback" not in res.stderr, res.stderr[-3000:]
    return d / "pol", json.loads(res.stdout)
