#!/usr/bin/env bash
# Runs every test of risas on a fresh Debian 12: installs what is missing,
# then three stages, and exits non-zero when any test fails:
#   1. the catkin package (Release, gcc): unit tests and rostests;
#   2. the ROS-free core with ASan+UBSan (gcc; any report is fatal): its unit
#      tests and the fuzz loop for RISAS_FUZZ_SECONDS (60);
#   3. the ROS-free core with clang (Release): its unit tests.
# Ends with one line over all of them: "N passed, N failed, N skipped".
# RISAS_TEST_STAGES (default "ros sanitize clang") picks stages.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

stages="${RISAS_TEST_STAGES:-ros sanitize clang}"
plain_root="${RISAS_PLAIN_BUILDS:-$(dirname "$RISAS_WS")/risas_plain}"
results=()

if [[ " $stages " == *" ros "* ]]; then
  echo "== stage ros: catkin package, unit tests and rostests"
  SECONDS=0
  risas_build
  rm -rf "$RISAS_WS/build/test_results"
  # --force-cmake: after a first configure catkin keeps an empty PYTHONPATH for
  # tests. run_tests always exits 0; the summary says what happened.
  catkin_make -C "$RISAS_WS" "${RISAS_CMAKE_ARGS[@]}" --force-cmake -j"$(nproc)" run_tests > "$RISAS_WS/run_tests.log" 2>&1 ||
    { tail -50 "$RISAS_WS/run_tests.log"; exit 1; }
  grep -E "^\[ *(RUN|OK|FAILED|PASSED) |FAILURE|Failure" "$RISAS_WS/run_tests.log" | grep -v "^\[ RUN" || true
  results+=("$RISAS_WS/build/test_results")
  echo "== stage ros took ${SECONDS} s"
fi

# plain_stage NAME CXX FLAGS...: configures and builds the ROS-free core, its
# tools and tests in $plain_root/NAME, runs ctest into NAME/junit.xml.
plain_stage() {
  local name=$1 cxx=$2 flags=$3
  shift 3
  local dir="$plain_root/$name"
  echo "== stage $name: ROS-free core with $cxx $flags"
  SECONDS=0
  cmake -S "$RISAS_ROOT" -B "$dir" -DRISAS_WITH_ROS=OFF -DCMAKE_CXX_COMPILER="$cxx" \
        -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" "$@" > "$dir.configure.log" 2>&1 ||
    { tail -30 "$dir.configure.log"; exit 1; }
  cmake --build "$dir" -j"$(nproc)" > "$dir.build.log" 2>&1 || { grep -E "error|Error" "$dir.build.log" | head -30; exit 1; }
  (cd "$dir" && ctest -j"$(nproc)" --output-on-failure --output-junit junit.xml > ctest.log 2>&1) ||
    grep -E "Failed|\*\*\*|ERROR|runtime error|invariant" "$dir/ctest.log" | head -40 || true
  tail -3 "$dir/ctest.log"
  results+=("$dir/junit.xml")
  echo "== stage $name took ${SECONDS} s"
}
mkdir -p "$plain_root"

if [[ " $stages " == *" sanitize "* ]]; then
  # Every report aborts its test. Leaks are not checked: OpenCV's thread
  # pool and caches live until exit.
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  plain_stage sanitize g++ "-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRISAS_FUZZ_SECONDS="${RISAS_FUZZ_SECONDS:-60}"
  unset ASAN_OPTIONS UBSAN_OPTIONS
fi

if [[ " $stages " == *" clang "* ]]; then
  plain_stage clang clang++ "" -DCMAKE_BUILD_TYPE=Release
fi

python3 "$RISAS_ROOT/scripts/summarise_test_results.py" "${results[@]}"
