#!/usr/bin/env bash
# Loom's libFuzzer targets (fuzz/; docs/operations.md "Fuzzing").
#
#   scripts/fuzz.sh build                 configure and build them into build-fuzz/ (clang,
#                                         ASan + UBSan)
#   scripts/fuzz.sh run TARGET SECONDS    a long run of one target, its corpus kept in
#                                         build-fuzz/corpus/TARGET (seeded from fuzz/corpus)
#   scripts/fuzz.sh all SECONDS           a long run of every target, one after another
#   scripts/fuzz.sh list                  the targets
#   scripts/fuzz.sh test BINARY SEEDS RUNS  what ctest's fuzz.<target> runs: RUNS inputs
#                                         from seed 1, a fresh output corpus; crashes fail
#
# A crash leaves its input as build-fuzz/crashes/TARGET/crash-*; reproduce it with
# `build-fuzz/fuzz/TARGET FILE`. Environment: FUZZ_BUILD_DIR (default build-fuzz),
# JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

BUILD=${FUZZ_BUILD_DIR:-build-fuzz}
TARGETS=(fabric_spec_fuzzer precompute_spec_fuzzer scene_spec_fuzzer obj_fuzzer samples_fuzzer asset_fuzzer
         upload_fuzzer)
# Bounds that keep one input cheap (the largest seed is ~40 KB); one allocation
# over 512 MB is a finding: no input of these sizes has a use for one.
FLAGS=(-max_len=262144 -rss_limit_mb=2048 -malloc_limit_mb=512 -timeout=20 -print_final_stats=1)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}

build() {
  bash scripts/setup.sh --no-build  # clang and its fuzzer runtime among the packages
  CC=clang CXX=clang++ cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLOOM_FUZZ=ON \
    -DLOOM_BUILD_TESTS=OFF
  cmake --build "$BUILD" --target fuzzers -j "${JOBS:-$(nproc)}"
}

run() {
  local target=$1 seconds=$2
  local corpus="$BUILD/corpus/$target" crashes="$BUILD/crashes/$target"
  mkdir -p "$corpus" "$crashes"
  "$BUILD/fuzz/$target" "${FLAGS[@]}" -max_total_time="$seconds" -artifact_prefix="$crashes/" \
    "$corpus" "fuzz/corpus/$target"
}

case "${1:-}" in
  build) build ;;
  list) printf '%s\n' "${TARGETS[@]}" ;;
  run) run "$2" "$3" ;;
  all) for target in "${TARGETS[@]}"; do run "$target" "$2"; done ;;
  test)
    binary=$2 seeds=$3 runs=$4
    work=$(mktemp -d -t loom-fuzz.XXXXXX)
    trap 'rm -rf "$work"' EXIT
    mkdir -p "$work/corpus"
    cd "$work"
    "$binary" "${FLAGS[@]}" -seed=1 -runs="$runs" -artifact_prefix="$work/" "$work/corpus" "$seeds"
    ;;
  *) sed -n '2,17p' "$0"; exit 2 ;;
esac
