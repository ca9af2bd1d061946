#!/usr/bin/env bash
# Runs the stability suite (ctest label "stability") on an existing build and
# collects every figure its tests report into docs/results/stability.csv: one row
# per (regime, method, metric), sorted, with the bound the test asserts.
# Extra arguments go to ctest (e.g. -j2). Writes nothing if a test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
rows=$(mktemp)
trap 'rm -f "$rows"' EXIT
LOOM_STABILITY_CSV="$rows" ctest --test-dir build -L stability --output-on-failure "$@"
mkdir -p docs/results
# -u: a figure two comparisons share (the reference's) is one row.
{ echo "regime,method,metric,value,bound"; LC_ALL=C sort -u "$rows"; } > docs/results/stability.csv
echo "wrote docs/results/stability.csv ($(wc -l < "$rows") figures)"
