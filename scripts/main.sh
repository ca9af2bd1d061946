#!/usr/bin/env bash
# Loom's main job, end to end on this machine, through the job service: installs
# what is missing, builds, starts loom-server with one local worker on loopback
# (data in a temporary directory), precomputes the example knit fabric
# (examples/fabrics/stockinette.json: geometry → radiance acquisition → Lafortune +
# lookup-table fit, every mip level) with `loom fabric precompute`, renders the
# example scene with it (`loom render`: the fabric is a cache hit, the frame is
# rendered by the worker on headless EGL: llvmpipe without a GPU, the GPU with one)
# into out/knit_plane.png, and stops the server.
#
# Environment: BUILD_DIR (default build), OUT (default out), LOOM_PORT (default 7450).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out}
mkdir -p "$OUT"
source scripts/local_server.sh

loom fabric precompute examples/fabrics/stockinette.json
loom render examples/scenes/knit_plane.json -o "$OUT/knit_plane.png"
