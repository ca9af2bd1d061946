#!/usr/bin/env bash
# The README's picture: the bench cloth (scenes/cloth_1080p.json: the standard knit
# draped over a ball) rendered by svbrdf and by factored at their defaults, and by the
# reference ray tracer (the ground truth), the cloth cut out of each and side by side at
# half size, and each method's PSNR and SSIM against the reference.
#
#   bench/readme_picture.sh [OUT_DIR]     (OUT_DIR default out/readme-picture)
#
# Writes OUT_DIR/{svbrdf,factored,reference}.exr with their figures (*.json) and
# docs/images/cloth_methods.png; needs oiiotool (openimageio-tools).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
lab=$here/../build/lab/loom-lab
scene=$here/scenes/cloth_1080p.json
out=${1:-out/readme-picture}
picture=$here/../docs/images/cloth_methods.png
mkdir -p "$out" "$(dirname "$picture")"

"$lab" --json render "$scene" --method reference -o "$out/reference.exr" >"$out/reference.json"
for method in svbrdf factored; do
  "$lab" --json render "$scene" --method "$method" --fabric-cache "$out/fabrics" -o "$out/$method.exr" \
    >"$out/$method.json"
  printf '%-9s ' "$method"
  "$lab" --json compare "$out/$method.exr" "$out/reference.exr" | tee "$out/$method-compare.json"
done
cloth=(--cut 800x800+600+120 --resize 50%)
oiiotool "$out/svbrdf.exr" "${cloth[@]}" "$out/factored.exr" "${cloth[@]}" "$out/reference.exr" "${cloth[@]}" \
  --mosaic 3x1 --colorconvert linear sRGB -d uint8 -o "$picture"
echo "wrote $picture"
