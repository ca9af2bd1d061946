#!/usr/bin/env bash
# The server, worker, client and store tests (ctest -L service) under a sanitizer,
# in a build of their own:
#
#   scripts/sanitize.sh asan     AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/)
#   scripts/sanitize.sh tsan     ThreadSanitizer (build-tsan/)
#
# Every Loom target is instrumented; the system libraries (gRPC, protobuf, SQLite,
# Mesa) are not, and scripts/sanitizers/*.supp names the reports inside them that
# are theirs (docs/operations.md "Sanitizers"). Extra arguments go to ctest.
# Environment: JOBS (default: number of cores).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

case "${1:-}" in
  asan) sanitizers=address,undefined ;;
  tsan) sanitizers=thread ;;
  *) sed -n '2,12p' "$0"; exit 2 ;;
esac
kind=$1
shift
build="build-$kind"
bash scripts/setup.sh --no-build
# Tests are listed when ctest runs, not at build time: a sanitizer's report then
# fails a test instead of the build.
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLOOM_SANITIZE="$sanitizers" \
  -DCMAKE_GTEST_DISCOVER_TESTS_DISCOVERY_MODE=PRE_TEST
targets=(store_test job_service_test job_pins_test parse_slots_test service_limits_test tls_test loom_cli_test
         job_runner_test alive_file_test server_restart_test worker_kill_test loom loom-server loom-worker)
cmake --build "$build" -j "${JOBS:-$(nproc)}" --target "${targets[@]}"

supp="$PWD/scripts/sanitizers"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
# ignore_noninstrumented_modules: memory accesses that intercepted calls (memcpy,
# memcmp, new) make from inside uninstrumented libraries are not checked; their
# synchronisation (pthread_create, mutexes) still is.
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:ignore_noninstrumented_modules=1:report_signal_unsafe=0:suppressions=$supp/tsan.supp"
ctest --test-dir "$build" -L service --output-on-failure -j "${JOBS:-$(nproc)}" "$@"
