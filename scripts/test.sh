#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs ctest, then builds
# and runs the fuzz targets.
# Tests that need OpenGL run on Mesa's llvmpipe through headless EGL: no GPU needed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh --with-browser --with-promtool --with-postgresql
BUILD_DIR=${BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"

# The fuzz targets (clang, ASan + UBSan): a fixed number of inputs each from a
# fixed seed (fuzz/CMakeLists.txt). FUZZ=0 skips them.
if [[ "${FUZZ:-1}" != 0 ]]; then
  bash scripts/fuzz.sh build
  ctest --test-dir "${FUZZ_BUILD_DIR:-build-fuzz}" --output-on-failure -j "${JOBS:-$(nproc)}" -L fuzz
fi
