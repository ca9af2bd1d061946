#!/usr/bin/env bash
# Collects Loom's binaries and every shared library they link into one folder that
# runs on another x86-64 Linux machine with a glibc at least as new (Ubuntu 24.04
# for one), without installing anything there:
#
#   deploy/bundle/make_bundle.sh [--link] BUILD_DIR OUT_DIR
#   OUT_DIR/run.sh loom-worker --probe --json
#
# --link hard-links the libraries instead of copying them where the filesystem
# allows (the test does, to spare 400 MB of copying); a bundle to ship is copied.
#
# OUT_DIR/
#   bin/                loom-server, loom-worker, loom, loom-lab (as built)
#   lib/                the libraries ldd finds, except the three groups below
#   lib/host-first/     libraries the host's GL driver shares with Loom; used only
#                       when the host has none or an older one (host-first/versions
#                       lists the symbol versions the bundle needs of each)
#   lib/glibc-versions  the glibc symbol versions the bundle needs (run.sh checks)
#   run.sh              sets LD_LIBRARY_PATH and runs a bundled binary
#   gpu_proof.sh, proof/  the NVIDIA proof (docs/gpu.md) and its inputs
#   frame_benchmark.sh, scenes/  issue 5's frame benchmark (gpu_proof.sh runs it) and its bench cloth
#   MANIFEST            what went in: version, commit, every library with its package
#
# What stays out, and why:
# - glibc (libc, libm, ld-linux, ...): it must match the host's dynamic loader; every
#   newer glibc runs binaries built against an older one.
# - GL vendor drivers: NVIDIA's (libEGL_nvidia, libnvidia-*) must match the host's
#   kernel module, so only the host has the right one; Mesa's (libEGL_mesa, the dri
#   drivers, libgallium, libLLVM: about 150 MB) is the host's distribution package
#   (libegl-mesa0 libgl1-mesa-dri on Debian/Ubuntu) where llvmpipe is wanted. Neither
#   is linked (glvnd loads them at run time), so ldd never lists them.
# - The glvnd dispatch libraries (libEGL, libOpenGL, libGLdispatch, libGLX) ARE
#   bundled: they are vendor-neutral, their interface to vendor drivers is stable,
#   and a bare machine (a CUDA container) may lack them.
set -euo pipefail

link=""
if [[ "${1:-}" == "--link" ]]; then
  link=--link
  shift
fi
if [[ $# -ne 2 ]]; then
  echo "usage: $0 [--link] BUILD_DIR OUT_DIR" >&2
  exit 2
fi
build=$(cd "$1" && pwd)
out=$2
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

binaries=("$build/server/loom-server" "$build/worker/loom-worker" "$build/client/loom" "$build/lab/loom-lab")
for binary in "${binaries[@]}"; do
  [[ -x "$binary" ]] || { echo "make_bundle: $binary is missing: build loom-server loom-worker loom loom-lab first" >&2; exit 3; }
done

# glibc's own libraries: from the host, always.
glibc='^(ld-linux-x86-64\.so|libc\.so|libm\.so|libmvec\.so|libdl\.so|libpthread\.so|librt\.so|libresolv\.so|libutil\.so|libanl\.so|libnsl\.so|libBrokenLocale\.so|libthread_db\.so)'
# GL vendor drivers: from the host, always (never linked; listed in case one ever is).
vendor='^(libEGL_|libGLX_|libGLESv[12]_CM_nvidia|libnvidia-|libcuda\.so|libgallium|libLLVM|libdrm_)'
# Shared with the host's GL driver: the host's copy wins when it is new enough.
host_first='^(libstdc\+\+\.so|libgcc_s\.so|libz\.so|libzstd\.so|libexpat\.so|libdrm\.so|libX[a-z0-9-]*\.so|libxcb[a-z0-9-]*\.so|libffi\.so|libelf\.so|libbsd\.so|libmd\.so|libudev\.so|liblzma\.so)'

rm -rf "$out"
mkdir -p "$out/bin" "$out/lib/host-first" "$out/proof"
out=$(cd "$out" && pwd)
cp "${binaries[@]}" "$out/bin/"

# soname -> path, over every binary (ldd gives the whole closure).
declare -A libraries=()
for binary in "${binaries[@]}"; do
  while read -r soname arrow path _; do
    [[ "$arrow" == "=>" ]] || continue
    if [[ "$path" == "not" ]]; then
      echo "make_bundle: $binary: $soname not found by ldd" >&2
      exit 3
    fi
    libraries[$soname]=$path
  done < <(ldd "$binary")
done

{
  echo "loom $("$build/server/loom-server" --version) bundle"
  echo "commit $(git -C "$repo" rev-parse HEAD 2>/dev/null || echo unknown)"
  echo "built on $(. /etc/os-release && echo "$PRETTY_NAME"), glibc $(ldd --version | head -n1 | awk '{print $NF}')"
  echo
  echo "# soname  placement  package"
} >"$out/MANIFEST"

# copy_library PATH DESTINATION: the file PATH names (not the symbolic link).
copy_library() {
  if [[ -n "$link" ]] && cp -L --link "$1" "$2" 2>/dev/null; then return; fi
  cp -L "$1" "$2"
}

# Which Debian package each library comes from, for the MANIFEST (one dpkg call:
# dpkg knows a library by the path its package installed, /lib/... or /usr/lib/...,
# while ldd names it by either).
declare -A packages=()
while read -r package path; do
  packages[$(basename "$path")]=${package%%:*}
done < <(for path in "${libraries[@]}"; do echo "${path#/usr}"; echo "/usr${path#/usr}"; done |
         xargs dpkg -S 2>/dev/null | grep -v '^diversion' || true)

bundled=0 host_first_count=0
for soname in $(printf '%s\n' "${!libraries[@]}" | sort); do
  path=${libraries[$soname]}
  if [[ "$soname" =~ $glibc ]]; then placement=host
  elif [[ "$soname" =~ $vendor ]]; then placement=host
  elif [[ "$soname" =~ $host_first ]]; then
    placement=host-first
    copy_library "$path" "$out/lib/host-first/$soname"
    host_first_count=$((host_first_count + 1))
  else
    placement=bundled
    copy_library "$path" "$out/lib/$soname"
    bundled=$((bundled + 1))
  fi
  echo "$soname $placement ${packages[$soname]:-?}" >>"$out/MANIFEST"
done

# The symbol versions the bundle needs of each library it may take from the host.
# readelf -V lists, per ELF file, "File: libfoo.so.N" then "Name: VERSION" lines.
needed_versions() {
  find "$out/bin" "$out/lib" -type f ! -name versions ! -name glibc-versions -print0 |
    xargs -0 readelf -V -W 2>/dev/null |
    awk '/File:/ {file = $0; sub(/.*File: /, "", file); sub(/ .*/, "", file)}
         /Name:/ && file != "" {print file, $3}' | sort -u
}
versions=$(needed_versions)
: >"$out/lib/host-first/versions"
for library in "$out"/lib/host-first/*; do
  soname=$(basename "$library")
  [[ "$soname" == versions ]] && continue
  echo "$soname $(awk -v name="$soname" '$1 == name {printf "%s ", $2}' <<<"$versions")" >>"$out/lib/host-first/versions"
done
awk '$1 == "libc.so.6" || $1 == "libm.so.6" || $1 == "libpthread.so.0" || $1 == "libdl.so.2" || $1 == "librt.so.1" {print $2}' \
  <<<"$versions" | grep '^GLIBC_2\.' | sort -u -V | tail -n 1 >"$out/lib/glibc-versions"

install -m 755 "$repo/deploy/bundle/run.sh" "$repo/deploy/bundle/gpu_proof.sh" "$repo/bench/frame_benchmark.sh" "$out/"
mkdir -p "$out/scenes"
cp "$repo/bench/scenes/cloth_1080p.json" "$out/scenes/"
cp "$repo/deploy/bundle/README.md" "$out/"
cp "$repo/examples/fabrics/stockinette.json" "$repo/deploy/bundle/proof/precompute.json" \
   "$repo/deploy/bundle/proof/scene.json" "$out/proof/"

echo "make_bundle: $out: ${#binaries[@]} binaries, $bundled libraries bundled, $host_first_count host-first," \
     "$(du -sh "$out" | cut -f1) ($(grep -c ' host ' "$out/MANIFEST") left to the host)"
