#!/usr/bin/env bash
# One of the lumislice paper's knit animations, end to end through the job
# service on this machine: starts loom-server with local workers on loopback,
# simulates examples/animations/NAME.json (`loom animate` → out/NAME.glb), then
# renders every frame of examples/scenes/NAME.json on it (`loom render --frames`: a
# job a frame, the knit fabric precomputed first) into out/NAME/f_NNNN.png and
# out/NAME.mp4 (ffmpeg), printing how long each part took.
#
#   scripts/animation_video.sh scarf_fold      (also: scarf_stretch, scarf_on_ball, ball_on_folded_scarf)
#
# Environment: BUILD_DIR (default build), OUT (default out), LOOM_PORT (default
# 7450), LOCAL_WORKERS (default 1; each renders a frame at a time), FPS (default 25,
# the examples' rate).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

NAME=${1:?usage: scripts/animation_video.sh scarf_fold|scarf_stretch|scarf_on_ball|ball_on_folded_scarf}
[[ -f examples/animations/$NAME.json && -f examples/scenes/$NAME.json ]] || {
  echo "animation_video.sh: no examples/animations/$NAME.json with examples/scenes/$NAME.json" >&2
  exit 2
}
bash scripts/setup.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT=${OUT:-out}
mkdir -p "$OUT/$NAME"
source scripts/local_server.sh

start=$SECONDS
loom animate "examples/animations/$NAME.json" --out "$OUT/$NAME.glb"
simulated=$SECONDS
last=$(python3 -c "import json,struct,sys; b=open(sys.argv[1],'rb').read(); n=struct.unpack('<I',b[12:16])[0]; \
g=json.loads(b[20:20+n]); print(g['accessors'][g['animations'][0]['samplers'][0]['input']]['count']-1)" "$OUT/$NAME.glb")
loom render "examples/scenes/$NAME.json" --frames "0..$last" --out "$OUT/$NAME/f_%04d.png" \
  --mp4 "$OUT/$NAME.mp4" --fps "${FPS:-25}"
echo "animation_video.sh: $NAME: simulation $((simulated - start)) s, $((last + 1)) frames rendered in $((SECONDS - simulated)) s (precompute included) → $OUT/$NAME.mp4"
