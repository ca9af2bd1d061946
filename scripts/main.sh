#!/usr/bin/env bash
# Loom's main job, end to end on this machine: installs what is missing, builds,
# then renders through headless EGL (llvmpipe without a GPU, the NVIDIA GPU with one)
# and writes the image to out/. While the job service and fabric pipeline are being
# built, the main job is the GL test scene; it grows into server + local worker,
# fabric precompute and frame render as those land.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out}
mkdir -p "$OUT"
"$BUILD_DIR/lab/loom-lab" info
"$BUILD_DIR/lab/loom-lab" test-scene --width 960 --height 540 --out "$OUT/test-scene.png"
