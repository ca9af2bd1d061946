#!/bin/sh
# Runs a program of this Loom bundle with the bundle's libraries (see README.md
# beside this script, and deploy/bundle/make_bundle.sh in Loom's repository).
#
#   ./run.sh loom-worker --probe --json     a bundled binary: loom-server, loom-worker, loom, loom-lab
#   ./run.sh ldd bin/loom-worker            any other command, in the bundle's environment
#
# The library path is lib/ (everything the binaries link except glibc and the GL
# vendor drivers), then, for each library in lib/host-first/, the host's copy when the
# host has one new enough (it is shared with the host's GL driver, which may need the
# newer one), else the bundled copy; then what LD_LIBRARY_PATH already held. The EGL
# vendor drivers (NVIDIA's libEGL_nvidia, Mesa's libEGL_mesa) always come from the host.
set -eu

here=$(cd "$(dirname "$0")" && pwd)

if [ $# -eq 0 ]; then
  echo "usage: $0 loom-server|loom-worker|loom|loom-lab [ARGS...] | COMMAND [ARGS...]" >&2
  exit 2
fi

ldconfig_cache() {
  { /sbin/ldconfig -p 2>/dev/null || ldconfig -p 2>/dev/null || true; } | awk '/=>/ {print $1, $NF}'
}

# host_library SONAME: the host's path of SONAME (x86-64), or nothing.
host_library() {
  printf '%s\n' "$cache" | awk -v name="$1" '$1 == name {print $2; exit}'
}

# has_versions FILE VERSION...: FILE defines every symbol version named.
has_versions() {
  file=$1
  shift
  for version in "$@"; do
    grep -q -a -F "$version" "$file" || return 1
  done
}

cache=$(ldconfig_cache)

# glibc is the host's: refuse clearly when it is older than the binaries need.
if [ -s "$here/lib/glibc-versions" ]; then
  libc=$(host_library libc.so.6)
  # shellcheck disable=SC2046
  if [ -z "$libc" ] || ! has_versions "$libc" $(cat "$here/lib/glibc-versions"); then
    echo "run.sh: the host's glibc (${libc:-not found}) lacks $(tr '\n' ' ' <"$here/lib/glibc-versions")" >&2
    exit 4
  fi
fi

path=$here/lib
missing=""
if [ -f "$here/lib/host-first/versions" ]; then
  while read -r soname versions; do
    host=$(host_library "$soname")
    # shellcheck disable=SC2086
    if [ -z "$host" ] || ! has_versions "$host" $versions; then
      missing="$missing $soname"
    fi
  done <"$here/lib/host-first/versions"
fi
if [ -n "$missing" ]; then
  # The host lacks these (or has them too old): link the bundled copies into a
  # directory of their own, so that the host's others still win.
  fallback=$(mktemp -d "${TMPDIR:-/tmp}/loom-bundle.XXXXXX")
  for soname in $missing; do
    ln -s "$here/lib/host-first/$soname" "$fallback/$soname"
  done
  path=$path:$fallback
fi

# Container runtimes put the NVIDIA driver under /usr/local/nvidia when they do not
# register it with the host's linker cache; search there too, and let glvnd find the
# driver's EGL vendor file there.
for dir in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do
  if [ -d "$dir" ]; then path=$path:$dir; fi
done
if [ -z "${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] && [ -z "${__EGL_VENDOR_LIBRARY_DIRS:-}" ] &&
   [ -d /usr/local/nvidia/share/glvnd/egl_vendor.d ]; then
  __EGL_VENDOR_LIBRARY_DIRS=/etc/glvnd/egl_vendor.d:/usr/share/glvnd/egl_vendor.d:/usr/local/nvidia/share/glvnd/egl_vendor.d
  export __EGL_VENDOR_LIBRARY_DIRS
fi

LD_LIBRARY_PATH=$path${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export LD_LIBRARY_PATH

program=$1
shift
if [ -x "$here/bin/$program" ]; then
  exec "$here/bin/$program" "$@"
fi
exec "$program" "$@"
