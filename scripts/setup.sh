#!/usr/bin/env bash
# Installs Loom's Debian 12 build and run dependencies (idempotent: only missing
# packages are installed) and builds Loom into ./build (Release by default).
#
#   scripts/setup.sh                install what is missing, configure, build
#   scripts/setup.sh --no-build     install only
#   scripts/setup.sh --with-browser also Chromium, for the dashboard's browser tests
#   scripts/setup.sh --with-promtool also Prometheus's promtool, which checks /metrics
#   scripts/setup.sh --with-postgresql also PostgreSQL's server, which the store's tests start
#
# Environment: BUILD_DIR (default build), BUILD_TYPE (default Release),
#              JOBS (default: number of cores).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

PACKAGES=(
  build-essential cmake pkg-config git ca-certificates
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libceres-dev libeigen3-dev
  libopenimageio-dev openimageio-tools
  libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libegl1
  libembree-dev libsqlite3-dev libcli11-dev libglm-dev
  nlohmann-json3-dev libssl-dev
  libyaml-cpp-dev libcpp-httplib-dev prometheus-cpp-dev libpq-dev
  libtinygltf-dev
  gnuplot-nox ffmpeg
  clang libclang-rt-14-dev
  python3-grpcio python3-protobuf
)
NO_BUILD=0
for argument in "$@"; do
  case "$argument" in
    --no-build) NO_BUILD=1 ;;
    --with-browser) PACKAGES+=(chromium) ;;
    --with-promtool) PACKAGES+=(prometheus) ;;
    --with-postgresql) PACKAGES+=(postgresql) ;;
    *) echo "setup.sh: unknown argument $argument" >&2; exit 2 ;;
  esac
done
# The dashboard's front end (web/) builds with npm; a Node.js already installed
# (e.g. NodeSource's, which bundles npm) is used as it is.
if ! command -v npm >/dev/null; then PACKAGES+=(nodejs npm); fi

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if ((${#missing[@]})); then
  echo "loom setup: installing ${#missing[@]} missing package(s): ${missing[*]}"
  SUDO=""
  if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
  # Debian's prometheus and postgresql packages start their servers where systemd
  # runs; Loom's tests need only promtool and start PostgreSQL servers of their own,
  # so a server this script installed is stopped again.
  for service in prometheus postgresql; do
    if [[ " ${missing[*]} " == *" $service "* ]] && command -v systemctl >/dev/null &&
      systemctl is-active --quiet "$service" 2>/dev/null; then
      $SUDO systemctl disable --now "$service"
    fi
  done
else
  echo "loom setup: all ${#PACKAGES[@]} packages present"
fi

if ((NO_BUILD)); then exit 0; fi

# The dashboard: npm ci when the lockfile changed, then tsc into web/dist.
if [[ ! -f web/node_modules/.package-lock.json || web/package-lock.json -nt web/node_modules/.package-lock.json ]]; then
  (cd web && npm ci --no-audit --no-fund)
fi
(cd web && npm run --silent build)

BUILD_DIR=${BUILD_DIR:-build}
BUILD_TYPE=${BUILD_TYPE:-Release}
JOBS=${JOBS:-$(nproc)}
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE="$BUILD_TYPE"
cmake --build "$BUILD_DIR" -j "$JOBS"
