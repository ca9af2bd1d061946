#!/usr/bin/env bash
# The frame benchmark (issues 5, 23 and 28): every GPU fabric method at 1920x1080 on
# the bench cloth (scenes/cloth_1080p.json: the standard knit draped over a ball, on a
# floor, one shadow-casting light): svbrdf at the default settings (trilinear levels,
# bilinear texels), with anisotropic levels and with nearest texels (the paper's
# lookup), tabulated, factored and neural at the defaults, then each method in the
# compute pass (--shading-pass compute) and shaded once per MSAA sample
# (--shading-rate sample); each the fastest of FRAMES frames of one renderer (the
# first compiles its shader variant and allocates the shadow maps), with its GPU
# time, the shadow maps' and the cloth's share of it and, in the compute pass, the
# fragments shaded in place; then the reference of the same view once (64 samples
# per pixel), each method's PSNR and SSIM against it and the reference/method time
# ratio.
# Each render's figures are in OUT_DIR/*.json; a summary goes to stdout and
# OUT_DIR/summary.txt.
#
#   bench/frame_benchmark.sh [--software] [OUT_DIR]     (OUT_DIR default out/frame-benchmark)
#
# --software: Mesa llvmpipe even on a GPU machine. LOOM_LAB: the loom-lab command
# (default: build/lab/loom-lab of this checkout; the bundle's gpu_proof.sh passes
# "run.sh loom-lab"). Each method's fabric is precomputed once into the fabric cache
# LOOM_FABRICS (default OUT_DIR/fabrics) and loaded from there afterwards: pointing
# it at a cache made elsewhere (the bundle carries one) spares the precomputes.
# FRAMES (default 5): frames per render, the fastest counts. A render that fails
# (a shader a driver refuses, say) is reported in the summary and the rest go on;
# the script then exits 1.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
read -r -a lab <<<"${LOOM_LAB:-$here/../build/lab/loom-lab}"
gl_flags=()
if [[ "${1:-}" == "--software" ]]; then
  gl_flags=(--software)
  shift
fi
out=${1:-out/frame-benchmark}
scene=$here/scenes/cloth_1080p.json
mkdir -p "$out"
fabrics=${LOOM_FABRICS:-$out/fabrics}
frames=${FRAMES:-5}
failed=0

# A top-level number from one of loom-lab's --json objects.
field() { sed -n "s/.*\"$1\":\([-0-9.e+]*\).*/\1/p" "$2"; }

gpu() {  # NAME METHOD, then loom-lab render flags
  local name=$1 method=$2
  shift 2
  if ! "${lab[@]}" --json render "$scene" --method "$method" --fabric-cache "$fabrics" --frames "$frames" \
    "${gl_flags[@]}" -o "$out/$name.exr" "$@" >"$out/$name.json"; then
    echo "frame_benchmark: $name failed" >&2
    rm -f "$out/$name.json" "$out/$name.exr"
    failed=1
  fi
}

methods=(svbrdf tabulated factored neural)
renders=(svbrdf svbrdf-anisotropic svbrdf-nearest tabulated factored neural)
gpu svbrdf svbrdf
gpu svbrdf-anisotropic svbrdf --level-mode anisotropic
gpu svbrdf-nearest svbrdf --texel-filter nearest
gpu tabulated tabulated
gpu factored factored
gpu neural neural
for method in "${methods[@]}"; do
  renders+=("$method-compute")
  gpu "$method-compute" "$method" --shading-pass compute
done
for method in "${methods[@]}"; do
  renders+=("$method-sample")
  gpu "$method-sample" "$method" --shading-rate sample
done
"${lab[@]}" --json render "$scene" --method reference -o "$out/reference.exr" >"$out/reference.json"
for name in "${renders[@]}"; do
  if [[ -f "$out/$name.exr" ]]; then
    "${lab[@]}" --json compare "$out/$name.exr" "$out/reference.exr" >"$out/$name-compare.json"
  fi
done

reference_ms=$(field frame_ms "$out/reference.json")
{
  sed -n 's/.*"gl_renderer":"\([^"]*\)".*/GL renderer: \1/p' "$out"/*.json | head -n 1
  printf '%-20s %10s %10s %10s %10s %10s %9s %7s %16s %9s\n' render "frame ms" "GPU ms" "shadow ms" "cloth ms" \
    "first ms" "PSNR dB" SSIM "reference/this" "in place"
  for name in "${renders[@]}"; do
    if [[ ! -f "$out/$name.json" ]]; then
      printf '%-20s %10s\n' "$name" failed
      continue
    fi
    frame_ms=$(field frame_ms "$out/$name.json")
    printf '%-20s %10.1f %10.2f %10.2f %10.2f %10.1f %9.2f %7.3f %16.0f %9s\n' "$name" "$frame_ms" \
      "$(field gpu_ms "$out/$name.json")" "$(field shadow_gpu_ms "$out/$name.json")" \
      "$(field cloth_gpu_ms "$out/$name.json")" "$(field first_frame_ms "$out/$name.json")" \
      "$(field psnr_db "$out/$name-compare.json")" "$(field ssim "$out/$name-compare.json")" \
      "$(awk -v r="$reference_ms" -v s="$frame_ms" 'BEGIN {print r / s}')" \
      "$(sed -n 's/.*"shaded_in_place":\([0-9]*\).*/\1/p' "$out/$name.json")"
  done
  printf '%-20s %10.1f   (%s samples per pixel, CPU)\n' reference "$reference_ms" "$(field samples_per_pixel "$out/reference.json")"
} | tee "$out/summary.txt"
exit "$failed"
