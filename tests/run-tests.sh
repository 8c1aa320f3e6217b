#!/usr/bin/env bash
# Runs every test of a build (default: build) and fails when any failed, none ran, or any was
# skipped or not run: ctest exits 0 on a GoogleTest skip ("Not Run (Skipped)"), and a skipped
# test checks nothing. The README's test command and .ci/run end here.
set -uo pipefail
build="${1:-build}"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
ctest --test-dir "$build" --output-on-failure --no-tests=error -j2 | tee "$log"
status=${PIPESTATUS[0]}
# ctest lists the tests it did not run (skipped or missing) under this heading of its summary.
if grep -q '^The following tests did not run:' "$log"; then
  echo "run-tests.sh: tests were skipped or not run (listed above); every test must run" >&2
  exit 1
fi
exit "$status"
