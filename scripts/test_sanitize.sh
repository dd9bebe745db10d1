#!/usr/bin/env bash
# `scripts/test.sh --sanitize`: the core gtests (those --quick runs) built with AddressSanitizer
# and UndefinedBehaviorSanitizer in a separate build space (build_sanitize/, devel_sanitize/),
# so the Release build stays as it is. Any finding fails the test that triggered it (UBSan
# halts on the first error; ASan reports leaks at exit). Suppressions need a comment naming the
# third-party bug: scripts/sanitizer_suppressions/lsan.txt; a test whose leaks cannot be
# attributed at all (a GL driver unloaded before exit) switches leak checking off itself, with
# the reason, in its package's CMakeLists.txt (ENVIRONMENT property).
# Last line `N passed, N failed, N skipped`; exit 1 on any failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
source "$root/scripts/env.sh"

scripts/setup.sh --no-build || { echo "test: set-up failed"; echo "0 passed, 1 failed"; exit 1; }

flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
echo "test --sanitize: building with $flags (build_sanitize/, devel_sanitize/)"
build_sanitized() {
  catkin_make --source . --build build_sanitize -DCATKIN_DEVEL_PREFIX="$root/devel_sanitize" \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=ON \
    -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
    -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" -j2 tests > "$1" 2>&1
}
# GCC 12 crashed once ("internal compiler error: Segmentation fault") on an unchanged file that
# compiled on the next try: a compiler crash gets one more (incremental) build, said so; a
# compile error fails as it is.
if ! build_sanitized build_sanitize.log; then
  if grep -q "internal compiler error" build_sanitize.log; then
    mkdir -p build_sanitize && mv build_sanitize.log build_sanitize/build.first.log
    echo "test --sanitize: the compiler crashed (build_sanitize/build.first.log); building once more"
    build_sanitized build_sanitize.log
  else
    false
  fi
fi || {
  tail -n 40 build_sanitize.log; echo "test: sanitizer build failed (build_sanitize.log)"; echo "0 passed, 1 failed"; exit 1; }
mv build_sanitize.log build_sanitize/build.log

export ROS_MASTER_URI="http://localhost:$(( 20000 + RANDOM % 20000 ))"
export ROS_HOME="$root/build_sanitize/ros_home"
export ROS_LOG_DIR="$ROS_HOME/log"
mkdir -p "$ROS_LOG_DIR"
# verify_asan_link_order=0: umockdev's LD_PRELOAD library (the emulated DVS128 of the libusb
# tests) is loaded before ASan's runtime; ASan works with it but refuses to start by default.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:verify_asan_link_order=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
supp="$root/scripts/sanitizer_suppressions/lsan.txt"
[ -f "$supp" ] && export LSAN_OPTIONS="suppressions=$supp"
rm -rf build_sanitize/test_results
# shellcheck disable=SC1091
set +u; source devel_sanitize/setup.bash; set -u
# ctest's own status counts too: a sanitizer report at exit fails a test whose cases all passed.
(cd build_sanitize && ctest -R _gtest_ -LE slow --output-on-failure) > build_sanitize/run_tests.log 2>&1
run_status=$?
grep -E "^ *[0-9]+/[0-9]+ Test|tests passed|tests failed|\[ *FAILED *\]|ERROR: (Address|Leak)Sanitizer|runtime error|SUMMARY:" \
  build_sanitize/run_tests.log || true

counts=$(/usr/bin/python3 "$root/scripts/count_test_results.py" build_sanitize/test_results)
count_status=$?
echo "$counts" | sed '$d'
line=$(echo "$counts" | tail -n 1)
if [ $run_status -ne 0 ] && echo "$line" | grep -q ", 0 failed"; then
  # A test binary that died before writing its results (a sanitizer abort) is still a failure.
  echo "test --sanitize: ctest reported a failure without a failed case (see build_sanitize/run_tests.log)"
  passed=$(echo "$line" | sed -E 's/^([0-9]+) passed.*/\1/')
  echo "${passed} passed, 1 failed, 0 skipped"
  exit 1
fi
echo "$line"
[ $run_status -ne 0 ] || [ $count_status -ne 0 ] && exit 1
exit 0
