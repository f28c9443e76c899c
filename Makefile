# grasp_pipeline — the two first commands: `make demo` and `make test`.
# Each does its own set-up on a fresh Debian machine (root): apt packages, a .venv,
# `pip install .` (builds the C++ extension), then runs. Idempotent: a second run
# skips what is present.

SHELL := /bin/bash
.SHELLFLAGS := -o pipefail -c
# pip prints a warning per missing local index folder on some machines; keep the output readable.
# (the recipe fails when pip fails: PIPESTATUS[0] is pip's exit code)
QUIET_PIP := 2>&1 | grep -v "^WARNING: Location"; test $${PIPESTATUS[0]} -eq 0
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
GTEST_BUILD := build/gtest
JOBS ?= 2
# pytest processes (pytest-xdist): one per core, at most 4 (each holds the simulator, torch, ...)
TEST_WORKERS ?= $(shell n=$$(nproc 2>/dev/null || echo 1); echo $$(( n < 4 ? n : 4 )))

APT_PACKAGES := build-essential cmake ccache python3-dev python3-venv libpcl-dev libeigen3-dev \
	libgtest-dev libegl1 libegl-mesa0 libgl1-mesa-dri libosmesa6

# The module's build (pip) and the test binary's build compile the same core sources with the
# same flags: ccache, when the machine has it, launches the compiler of both, so the second
# build takes the first one's objects (read when a recipe runs: system-deps may install it).
# Both name the same compiler (your CXX, else c++; pip's build would otherwise take Python's).
BUILD_ENV = CXX="$${CXX:-c++}" CMAKE_CXX_COMPILER_LAUNCHER="$$(command -v ccache || true)"

SOURCES := $(shell find cpp python sim config -type f -not -name '*.pyc' 2>/dev/null) \
	CMakeLists.txt pyproject.toml

.PHONY: demo test setup system-deps gtest pytest bench clean

demo: setup
	$(VENV)/bin/grasp-pipeline demo

test: setup gtest pytest

setup: system-deps $(VENV)/.installed $(VENV)/.dataset

# apt: only when a package is missing (dpkg -s answers for installed ones).
system-deps:
	@missing=""; for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing Debian packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing; \
	else echo "Debian packages present"; fi

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip $(QUIET_PIP)

$(VENV)/.installed: $(VENV)/bin/python $(SOURCES)
	@rm -f python/grasp_pipeline/_*.so  # a dev build (scripts/dev_build_core.sh) must not ship
	$(BUILD_ENV) $(PIP) install -q ".[test,meshes,ray,rerun,learning]" $(QUIET_PIP)
	@touch $@

# LeRobot for `record`, `train`, `eval` and their tests (the 'dataset' extra, lean): torch/torchvision
# within lerobot 0.4.4's pins (taken from this machine's disk), lerobot without its robot/logging
# dependencies, and what lerobot.datasets, its ACT policy, processors and lerobot-eval import
# (requirements/dataset-ci.txt explains).
DATASET_TORCH := torch==2.9.1 torchvision==0.24.1
$(VENV)/.dataset: $(VENV)/bin/python requirements/dataset-ci.txt
	$(PIP) install -q $(DATASET_TORCH) $(QUIET_PIP)
	$(PIP) install -q --no-deps lerobot==0.4.4 $(QUIET_PIP)
	$(PIP) install -q -r requirements/dataset-ci.txt $(QUIET_PIP)
	@touch $@

gtest: system-deps
	$(BUILD_ENV) cmake -S . -B $(GTEST_BUILD) -DGRASP_BUILD_PYTHON=OFF -DGRASP_BUILD_TESTS=ON -DCMAKE_BUILD_TYPE=Release >/dev/null
	cmake --build $(GTEST_BUILD) -j $(JOBS)
	$(GTEST_BUILD)/grasp_core_tests --gtest_brief=1

# A test file runs whole in one process (--dist loadfile): its module fixtures (a simulated
# round, a recorded dataset) are built once.
pytest: setup
	$(PY) -m pytest -q -n $(TEST_WORKERS) --dist loadfile tests/python

bench: setup
	$(PIP) install -q ".[test,bench]" $(QUIET_PIP)
	$(VENV)/bin/grasp-pipeline bench perception --frames 50 --json build/bench_perception.json

clean:
	rm -rf build $(VENV)
