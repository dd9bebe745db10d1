#!/usr/bin/env bash
# The README's test command: set up, build, run every gtest and rostest, and print
# `N passed, N failed, N skipped` as the last line. Exits non-zero on any failure.
#   scripts/test.sh           everything (what .ci/run calls)
#   scripts/test.sh --quick   the core gtests only: no rostest, no test labelled `slow`
#   scripts/test.sh --sanitize  the --quick gtests built with ASan + UBSan in build_sanitize/
#                               (scripts/test_sanitize.sh)
# How a test is marked slow: catkin registers every gtest with ctest as
# _ctest_<package>_gtest_<target>; a package's CMakeLists.txt gives its slow ones the ctest
# label `slow` right where it registers them:
#   set_tests_properties(_ctest_${PROJECT_NAME}_gtest_<target> PROPERTIES LABELS slow)
# --quick runs `ctest -R _gtest_ -LE slow`: every gtest not so labelled (rostests are registered
# as _ctest_<package>_rostest_..., launch-file checks as ..._roslaunch-check_..., so neither
# matches). A new gtest is quick unless labelled; label it when it takes more than ~10 s.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
source "$root/scripts/env.sh"

quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  --sanitize) exec bash "$root/scripts/test_sanitize.sh" ;;
  "") ;;
  *) echo "usage: scripts/test.sh [--quick | --sanitize]" >&2; echo "0 passed, 1 failed"; exit 2 ;;
esac

scripts/setup.sh || { echo "test: set-up or build failed"; echo "0 passed, 1 failed"; exit 1; }

# A private master port per run so a roscore left elsewhere cannot interfere.
export ROS_MASTER_URI="http://localhost:$(( 20000 + RANDOM % 20000 ))"
export ROS_HOME="$root/build/ros_home"
export ROS_LOG_DIR="$ROS_HOME/log"
mkdir -p "$ROS_LOG_DIR"

rm -rf build/test_results
# shellcheck disable=SC1091
set +u; source devel/setup.bash; set -u
if [ $quick -eq 1 ]; then
  # Build the test executables (catkin builds gtests only for `tests`), then run the quick ones;
  # each writes its JUnit XML into build/test_results as under run_tests.
  make -C build -j2 tests > build/build_tests.log 2>&1 || {
    tail -n 30 build/build_tests.log; echo "test: building the tests failed (build/build_tests.log)"
    echo "0 passed, 1 failed"; exit 1; }
  (cd build && ctest -R _gtest_ -LE slow --output-on-failure) > build/run_tests.log 2>&1
  run_status=$?  # (not through a pipe: with pipefail, `|| true` would reset PIPESTATUS)
  grep -E "^ *[0-9]+/[0-9]+ Test|tests passed|tests failed|\[ *FAILED *\]|Failure|error:" build/run_tests.log || true
else
  catkin_make --source . -DPYTHON_EXECUTABLE=/usr/bin/python3 -j2 run_tests -j1 > build/run_tests.log 2>&1
  run_status=$?
  grep -E "^\[ *(RUN|OK|FAILED|PASSED) *\]|^\[ROSTEST\]|^(SUMMARY|FAILURE)|Error|error:" build/run_tests.log || true
fi

catkin_test_results build/test_results --all > build/test_summary.log 2>&1
results_status=$?
tail -n 1 build/test_summary.log

/usr/bin/python3 "$root/scripts/count_test_results.py" build/test_results
count_status=$?

if [ $run_status -ne 0 ] || [ $results_status -ne 0 ] || [ $count_status -ne 0 ]; then
  exit 1
fi
