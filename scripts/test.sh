#!/usr/bin/env bash
# Runs every test of risas on a fresh Debian 12: installs what is missing,
# then five stages, and exits non-zero when any test fails:
#   1. ros: the catkin package (Release, gcc), built with
#      -DCATKIN_ENABLE_TESTING=OFF and installed, then its unit tests and
#      rostests (the display test among them, under an Xvfb of its own),
#      and scripts/demo.sh headless;
#   2. sanitize: the ROS-free core with ASan+UBSan (clang; any report is
#      fatal), its row loops' AVX2 copy alone where the CPU has AVX2: its
#      unit tests and the fuzz loop for RISAS_FUZZ_SECONDS (60);
#   3. thread: the ROS-free core with ThreadSanitizer (clang; any report is
#      fatal), OpenCV's parallel_for_ on test/tsan's std::thread backend: its
#      unit tests, the stage's check that it sees a race, and the fuzz loop
#      for RISAS_TSAN_FUZZ_SECONDS (30);
#   4. clang: the ROS-free core with clang, unsanitized (Release): its unit
#      tests;
#   5. downstream: the ros stage's install (built here when that stage did
#      not run), the clang build installed with `cmake --install`, and a
#      user's catkin package and plain-CMake project built against each
#      install and run (test/downstream).
# Ends with one line over all of them: "N passed, N failed, N skipped".
# RISAS_TEST_STAGES (default "ros sanitize thread clang downstream") picks stages.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

stages="${RISAS_TEST_STAGES:-ros sanitize thread clang downstream}"
plain_root="${RISAS_PLAIN_BUILDS:-$(dirname "$RISAS_WS")/risas_plain}"
results=()

# install_package: the catkin package built with -DCATKIN_ENABLE_TESTING=OFF
# (it must build so) and installed into $RISAS_WS/install, for the downstream
# stage. In the ros stage's workspace: turning tests on afterwards builds
# only the tests, since the package's own objects keep their flags.
install_package() {
  mkdir -p "$RISAS_WS"
  rm -rf "$RISAS_WS/install"
  risas_build -DCATKIN_ENABLE_TESTING=OFF install > "$RISAS_WS/install.log" 2>&1 ||
    { grep -E "error|Error" "$RISAS_WS/install.log" | head -30; exit 1; }
}

if [[ " $stages " == *" ros "* ]]; then
  echo "== stage ros: catkin package, unit tests and rostests"
  SECONDS=0
  install_package
  rm -rf "$RISAS_WS/build/test_results"
  # --force-cmake: after a first configure catkin keeps an empty PYTHONPATH for
  # tests. run_tests always exits 0; the summary says what happened.
  catkin_make -C "$RISAS_WS" "${RISAS_CMAKE_ARGS[@]}" -DCATKIN_ENABLE_TESTING=ON --force-cmake -j"$(nproc)" run_tests \
    > "$RISAS_WS/run_tests.log" 2>&1 ||
    { tail -50 "$RISAS_WS/run_tests.log"; exit 1; }
  grep -E "^\[ *(RUN|OK|FAILED|PASSED) |FAILURE|Failure" "$RISAS_WS/run_tests.log" | grep -v "^\[ RUN" || true
  # The README's first command as a user without a display runs it: the
  # demo publishes keypoints (its rate printed) and saves a match overlay.
  demo_log="$RISAS_WS/demo.log"
  if DISPLAY= DEMO_SECONDS=5 "$RISAS_ROOT/scripts/demo.sh" > "$demo_log" 2>&1 && grep -q "average rate" "$demo_log"; then
    demo_failure=""
  else
    demo_failure="<failure message=\"scripts/demo.sh: no rate or no overlay; see $demo_log\"/>"
    tail -20 "$demo_log"
  fi
  grep -E "average rate|overlay" "$demo_log" || true
  echo "<testsuite name=\"demo\"><testcase classname=\"scripts\" name=\"demo_headless\">$demo_failure</testcase></testsuite>" \
    > "$RISAS_WS/build/test_results/demo.xml"
  results+=("$RISAS_WS/build/test_results")
  echo "== stage ros took ${SECONDS} s"
fi

# own_build_dir DIR SOURCE: DIR as a CMake build folder of SOURCE. One that
# another clone on this machine configured is started afresh: CMake refuses
# a second source for a build folder.
own_build_dir() {
  local dir=$1 src=$2
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -qxF "CMAKE_HOME_DIRECTORY:INTERNAL=$src" "$dir/CMakeCache.txt"; then
    rm -rf "$dir"
  fi
  mkdir -p "$dir"
}

# plain_build NAME CXX FLAGS...: configures and builds the ROS-free core, its
# tools and tests in $plain_root/NAME. The build and the tests run through
# stage_launcher (an array, empty unless a stage sets it): the build runs
# each test program to list its tests.
stage_launcher=()
plain_build() {
  local name=$1 cxx=$2 flags=$3
  shift 3
  local dir="$plain_root/$name"
  own_build_dir "$dir" "$RISAS_ROOT"
  cmake -S "$RISAS_ROOT" -B "$dir" -DRISAS_WITH_ROS=OFF -DCMAKE_CXX_COMPILER="$cxx" \
        -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" "$@" > "$dir.configure.log" 2>&1 ||
    { tail -30 "$dir.configure.log"; exit 1; }
  "${stage_launcher[@]}" cmake --build "$dir" -j"$(nproc)" > "$dir.build.log" 2>&1 || { grep -E "error|Error" "$dir.build.log" | head -30; exit 1; }
}

# plain_stage NAME CXX FLAGS...: plain_build, then ctest into NAME/junit.xml,
# with ctest_preload (a library of the build, if set) preloaded into every
# test and the tools they start.
ctest_preload=""
plain_stage() {
  local name=$1 dir="$plain_root/$1"
  echo "== stage $name: ROS-free core with $2 $3"
  SECONDS=0
  plain_build "$@"
  (cd "$dir" && LD_PRELOAD="${ctest_preload:+$dir/$ctest_preload}" \
     "${stage_launcher[@]}" ctest -j"$(nproc)" --output-on-failure --output-junit junit.xml > ctest.log 2>&1) ||
    grep -E "Failed|\*\*\*|ERROR|runtime error|invariant" "$dir/ctest.log" | head -40 || true
  tail -3 "$dir/ctest.log"
  results+=("$dir/junit.xml")
  echo "== stage $name took ${SECONDS} s"
}
mkdir -p "$plain_root"

# The sanitizer stages' build: clang, optimised, with line tables only
# (reports name file and line; full debug information would cost a fifth
# more compile time and ten times the object size). Clang, not GCC: it builds
# and runs both stages in two thirds of GCC's time (docs/ci.md).
sanitized_build=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG")

if [[ " $stages " == *" sanitize "* ]]; then
  # Every report aborts its test. Leaks are not checked: OpenCV's thread
  # pool and caches live until exit.
  export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
  export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
  # The row loops' AVX2 copy alone where the CPU has AVX2: the ros stage runs
  # the copy the CPU picks (AVX-512 on CI's), clang and thread the baseline.
  avx2=OFF
  grep -qw avx2 /proc/cpuinfo && avx2=ON
  plain_stage sanitize clang++ "-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer" \
    "${sanitized_build[@]}" -DRISAS_FUZZ_SECONDS="${RISAS_FUZZ_SECONDS:-60}" -DRISAS_ROW_LOOPS_AVX2="$avx2"
  unset ASAN_OPTIONS UBSAN_OPTIONS
fi

if [[ " $stages " == *" thread "* ]]; then
  # Every report ends its process (exit code 66) and fails its test. OpenCV's
  # TBB hands work over in ways TSan cannot see, so its parallel_for_ runs on
  # std::threads instead (docs/thread-safety.md). The fuzz loop runs for
  # RISAS_TSAN_FUZZ_SECONDS (30) from a seed of its own: its frames of any
  # size are extracted on those threads.
  export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$RISAS_ROOT/test/tsan/suppressions.txt"
  # Address randomisation off where the system lets a process turn it off:
  # clang 14's and GCC 12's TSan runtimes cannot map their shadow memory on
  # kernels that randomise more bits (vm.mmap_rnd_bits 32; google/sanitizers#1716).
  if setarch "$(uname -m)" -R true 2> /dev/null; then stage_launcher=(setarch "$(uname -m)" -R); fi
  ctest_preload=lib/librisas_std_thread_backend.so
  plain_stage thread clang++ "-fsanitize=thread -fno-omit-frame-pointer" "${sanitized_build[@]}" -DRISAS_TSAN_STAGE=ON \
    -DRISAS_FUZZ_SECONDS="${RISAS_TSAN_FUZZ_SECONDS:-30}" -DRISAS_FUZZ_SEED=2
  stage_launcher=()
  ctest_preload=""
  unset TSAN_OPTIONS
fi

if [[ " $stages " == *" clang "* ]]; then
  plain_stage clang clang++ "" -DCMAKE_BUILD_TYPE=Release
fi

if [[ " $stages " == *" downstream "* ]]; then
  echo "== stage downstream: installed package, a user's catkin package and CMake project against it"
  SECONDS=0
  # The catkin package without tests, installed (the ros stage's, built here when that stage did not run).
  [[ " $stages " == *" ros "* ]] || install_package
  # The plain build (the clang stage's; built here when that stage did not run), installed.
  plain_build clang clang++ "" -DCMAKE_BUILD_TYPE=Release
  rm -rf "$plain_root/prefix"
  cmake --install "$plain_root/clang" --prefix "$plain_root/prefix" > "$plain_root/install.log" 2>&1 ||
    { tail -20 "$plain_root/install.log"; exit 1; }
  dir="$plain_root/downstream"
  own_build_dir "$dir" "$RISAS_ROOT/test/downstream"
  cmake -S "$RISAS_ROOT/test/downstream" -B "$dir" -DRISAS_PREFIX="$plain_root/prefix" \
        -DRISAS_CATKIN_INSTALL="$RISAS_WS/install" > "$dir.configure.log" 2>&1 || { tail -20 "$dir.configure.log"; exit 1; }
  (cd "$dir" && ctest --output-on-failure --output-junit junit.xml > ctest.log 2>&1) ||
    grep -vE "^\s*$" "$dir/ctest.log" | tail -40 || true
  tail -3 "$dir/ctest.log"
  results+=("$dir/junit.xml")
  echo "== stage downstream took ${SECONDS} s"
fi

python3 "$RISAS_ROOT/scripts/summarise_test_results.py" "${results[@]}"
