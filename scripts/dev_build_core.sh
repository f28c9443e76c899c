#!/usr/bin/env bash
# Developer shortcut: rebuild the extension in build/py and drop it next to the sources
# so `PYTHONPATH=python` picks it up (the real install is `pip install .`).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f build/py/CMakeCache.txt ]; then
  cmake -S . -B build/py -DGRASP_BUILD_PYTHON=ON -DGRASP_BUILD_TESTS=OFF \
    -Dpybind11_DIR="$(.venv/bin/python -m pybind11 --cmakedir)" \
    -DPython_EXECUTABLE="$(pwd)/.venv/bin/python" >/dev/null
fi
cmake --build build/py -j2 --target _core
cp build/py/_core*.so python/grasp_pipeline/
