#!/usr/bin/env bash
# Packs a bundle (make_bundle.sh) for a machine reached only through a transfer of
# at most 64 MiB per call (this workplace's device tool, docs/gpu.md): the bundle as
# one tar.xz, cut into parts under REPO/.lb0, REPO/.lb1, ... (each under PART_MIB),
# one folder per call's `carry`. Adds /.lb*/ to REPO/.git/info/exclude.
#
#   deploy/bundle/pack_for_device.sh BUNDLE_DIR REPO_ROOT [PART_MIB]   (default 56)
#
# There, after every part has arrived:
#   cat .lb*/part | { xz -d 2>/dev/null || python3 -c 'import lzma,shutil,sys; shutil.copyfileobj(lzma.open(sys.stdin.buffer), sys.stdout.buffer)'; } | tar -x -C /tmp
# unpacks it to /tmp/<bundle folder name>.
set -euo pipefail

if [[ $# -lt 2 ]]; then
  echo "usage: $0 BUNDLE_DIR REPO_ROOT [PART_MIB]" >&2
  exit 2
fi
bundle=$(cd "$1" && pwd)
repo=$(cd "$2" && pwd)
part_mib=${3:-56}

exclude=$(git -C "$repo" rev-parse --git-path info/exclude)
[[ "$exclude" = /* ]] || exclude=$repo/$exclude
grep -qx '/.lb\*/' "$exclude" 2>/dev/null || echo '/.lb*/' >>"$exclude"
rm -rf "$repo"/.lb[0-9]*

archive=$(mktemp "${TMPDIR:-/tmp}/loom-bundle.XXXXXX.tar.xz")
tar -C "$(dirname "$bundle")" -cf - "$(basename "$bundle")" | xz -T0 -6 >"$archive"
split -b "${part_mib}M" -d -a 1 "$archive" "$archive.part."
index=0
for part in "$archive".part.*; do
  mkdir -p "$repo/.lb$index"
  mv "$part" "$repo/.lb$index/part"
  index=$((index + 1))
done
echo "pack_for_device: $(du -h "$archive" | cut -f1) in $index parts: $(cd "$repo" && echo .lb[0-9]*)"
echo "sha256 $(sha256sum "$archive" | cut -d' ' -f1)"
rm -f "$archive"
