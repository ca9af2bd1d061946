#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds, runs ctest.
# Tests that need OpenGL run on Mesa's llvmpipe through headless EGL: no GPU needed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
