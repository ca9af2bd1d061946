#!/usr/bin/env bash
# Loom's main job, end to end on this machine: installs what is missing, builds,
# then precomputes the example knit fabric (geometry → radiance acquisition →
# Lafortune + lookup-table fit, all mip levels) and renders the example scene with
# it on the GPU through headless EGL (llvmpipe without a GPU, the NVIDIA GPU with
# one), writing out/knit_plane.png. Until the job service lands this runs in one
# process through loom-lab; it becomes server + local worker + client then.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out}
mkdir -p "$OUT"
"$BUILD_DIR/lab/loom-lab" info
"$BUILD_DIR/lab/loom-lab" render examples/scenes/knit_plane.json --out "$OUT/knit_plane.png"
