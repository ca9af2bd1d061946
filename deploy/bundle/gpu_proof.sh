#!/usr/bin/env bash
# Proves a bundled loom-worker renders on this machine's GPU through EGL, end to end
# through the job service (docs/gpu.md). Run from the bundle (make_bundle.sh):
#
#   ./gpu_proof.sh [--software] [OUT_DIR]      (OUT_DIR default ./gpu-proof)
#
# It starts loom-server --local-workers 0 on loopback (data in a temporary
# directory) and one bundled loom-worker, precomputes the example knit
# (proof/stockinette.json with the small settings proof/precompute.json) with
# `loom fabric precompute`, renders the example scene with the same settings
# (proof/scene.json, 480x270) with `loom render` into OUT_DIR/frame.exr and
# frame.png, and prints the worker's GL renderer (loom-worker --probe --json) and
# the time of each step; then runs frame_benchmark.sh (every method at 1920x1080 on
# the bench cloth, its GPU time, the reference's time and PSNR) into
# OUT_DIR/frame-benchmark, starting from the bench cloth's fabrics in proof/fabrics
# when the bundle carries them (precomputed where it was made: the device's minutes
# go to the frames). If the bundle carries proof/llvmpipe.exr (the same frame
# made with --software on Mesa llvmpipe; make_bundle.sh's caller adds it), it
# compares the two with loom-lab compare and fails unless PSNR >= 40 dB; a failed
# frame benchmark render fails it too, after the rest has run.
#
# --software: the worker uses llvmpipe even on a GPU machine; this is how
# proof/llvmpipe.exr is made. Environment: LOOM_PORT (default 7460), FRAMES (frames
# per benchmark render, default 5).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
run=$here/run.sh
worker_flags=()
if [[ "${1:-}" == "--software" ]]; then
  worker_flags=(--software)
  shift
fi
out=${1:-$PWD/gpu-proof}
mkdir -p "$out"
out=$(cd "$out" && pwd)
address=127.0.0.1:${LOOM_PORT:-7460}
min_psnr_db=40

now() { date +%s.%N; }
seconds_since() { awk -v start="$1" -v end="$(now)" 'BEGIN {printf "%.1f", end - start}'; }
loom() { "$run" loom --server "$address" "$@"; }

echo "== machine"
echo "$(uname -srm), $(nproc) cores, $(. /etc/os-release 2>/dev/null && echo "${PRETTY_NAME:-}")"
if command -v nvidia-smi >/dev/null; then
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader || true
fi

echo "== worker GL context (loom-worker --probe --json ${worker_flags[*]})"
"$run" loom-worker --probe --json "${worker_flags[@]}" | tee "$out/probe.json"

data=$(mktemp -d "${TMPDIR:-/tmp}/loom-proof.XXXXXX")
server_pid="" worker_pid=""
stop() {
  [[ -n "$worker_pid" ]] && kill -TERM "$worker_pid" 2>/dev/null && wait "$worker_pid" || true
  [[ -n "$server_pid" ]] && kill -TERM "$server_pid" 2>/dev/null && wait "$server_pid" || true
  rm -rf "$data"
}
trap stop EXIT

"$run" loom-server --data "$data" --listen "$address" --local-workers 0 2>"$out/server.log" &
server_pid=$!
loom server-info --wait 60 >/dev/null
"$run" loom-worker --server "$address" "${worker_flags[@]}" 2>"$out/worker.log" &
worker_pid=$!

echo "== precompute (proof/stockinette.json, proof/precompute.json)"
start=$(now)
loom fabric precompute "$here/proof/stockinette.json" --settings "$here/proof/precompute.json"
echo "precompute: $(seconds_since "$start") s"

echo "== render (proof/scene.json)"
start=$(now)
loom render "$here/proof/scene.json" -o "$out/frame.exr"
echo "render: $(seconds_since "$start") s (a cached fabric: the frame job alone)"
loom render "$here/proof/scene.json" -o "$out/frame.png" >/dev/null
echo "frame: $out/frame.exr, $out/frame.png"
loom jobs list --kind render >"$out/jobs.txt" || true

echo "== frame benchmark (frame_benchmark.sh: every method at 1920x1080 on the bench cloth, and the reference)"
start=$(now)
status=0
if [[ -d "$here/proof/fabrics" ]]; then  # the bench cloth's fabrics, precomputed where the bundle was made
  mkdir -p "$out/frame-benchmark"
  cp -r "$here/proof/fabrics" "$out/frame-benchmark/"
fi
LOOM_LAB="$run loom-lab" "$here/frame_benchmark.sh" "${worker_flags[@]}" "$out/frame-benchmark" \
  2>"$out/frame-benchmark.log" || status=1
echo "frame benchmark: $(seconds_since "$start") s"

reference=$here/proof/llvmpipe.exr
if [[ ! -f "$reference" ]]; then
  echo "== no proof/llvmpipe.exr in the bundle: nothing to compare with"
  exit "$status"
fi
echo "== compare with proof/llvmpipe.exr (loom-lab compare)"
"$run" loom-lab --json compare "$out/frame.exr" "$reference" --heatmap "$out/error.png" | tee "$out/compare.json"
psnr=$(sed -n 's/.*"psnr_db":\([^,}]*\).*/\1/p' "$out/compare.json")
if [[ "$psnr" == "null" ]]; then
  echo "PASS: the frames are identical (PSNR infinite)"
elif awk -v psnr="$psnr" -v min="$min_psnr_db" 'BEGIN {exit !(psnr >= min)}'; then
  echo "PASS: PSNR $psnr dB >= $min_psnr_db dB"
else
  echo "FAIL: PSNR $psnr dB < $min_psnr_db dB"
  exit 1
fi
[[ $status -eq 0 ]] || echo "FAIL: a frame benchmark render failed (frame-benchmark.log)"
exit "$status"
