#!/usr/bin/env bash
# Developer shortcut: rebuild the extensions (_core, and _pcl_io for cloud files) in build/py
# and drop them next to the sources so `PYTHONPATH=python` picks them up (the real install is
# `pip install .`). Pass target names to build only some, e.g. `dev_build_core.sh _pcl_io`.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -f build/py/CMakeCache.txt ]; then
  cmake -S . -B build/py -DGRASP_BUILD_PYTHON=ON -DGRASP_BUILD_TESTS=OFF \
    -Dpybind11_DIR="$(.venv/bin/python -m pybind11 --cmakedir)" \
    -DPython_EXECUTABLE="$(pwd)/.venv/bin/python" >/dev/null
else
  cmake build/py >/dev/null  # re-configure: picks up targets added to CMakeLists.txt
fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(_core _pcl_io)
for t in "${targets[@]}"; do
  cmake --build build/py -j2 --target "$t"
  cp build/py/"$t"*.so python/grasp_pipeline/
done
