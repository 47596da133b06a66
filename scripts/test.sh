#!/usr/bin/env bash
# Runs every test of risas on a fresh Debian 12: installs what is missing,
# builds the catkin package, runs its unit tests (and rostests) and exits
# non-zero when any fails.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

risas_build
rm -rf "$RISAS_WS/build/test_results"
# --force-cmake: after a first configure catkin keeps an empty PYTHONPATH for
# tests. run_tests always exits 0; catkin_test_results says what happened.
catkin_make -C "$RISAS_WS" "${RISAS_CMAKE_ARGS[@]}" --force-cmake -j"$(nproc)" run_tests > "$RISAS_WS/run_tests.log" 2>&1 ||
  { tail -50 "$RISAS_WS/run_tests.log"; exit 1; }
grep -E "^\[ *(RUN|OK|FAILED|PASSED) |FAILURE|Failure" "$RISAS_WS/run_tests.log" | grep -v "^\[ RUN" || true
python3 "$RISAS_ROOT/scripts/summarise_test_results.py" "$RISAS_WS/build/test_results"
