#!/usr/bin/env bash
# The README's test command: set up, build, run every gtest and rostest, and print
# `N passed, N failed, N skipped` as the last line. Exits non-zero on any failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
source "$root/scripts/env.sh"

scripts/setup.sh || { echo "test: set-up or build failed"; echo "0 passed, 1 failed"; exit 1; }

# A private master port per run so a roscore left elsewhere cannot interfere.
export ROS_MASTER_URI="http://localhost:$(( 20000 + RANDOM % 20000 ))"
export ROS_HOME="$root/build/ros_home"
export ROS_LOG_DIR="$ROS_HOME/log"
mkdir -p "$ROS_LOG_DIR"

rm -rf build/test_results
# shellcheck disable=SC1091
set +u; source devel/setup.bash; set -u
catkin_make --source . -DPYTHON_EXECUTABLE=/usr/bin/python3 -j2 run_tests -j1 2>&1 | tee build/run_tests.log | \
  grep -E "^\[ *(RUN|OK|FAILED|PASSED) *\]|^\[ROSTEST\]|^(SUMMARY|FAILURE)|Error|error:" || true
run_status=${PIPESTATUS[0]}

catkin_test_results build/test_results --all > build/test_summary.log 2>&1
results_status=$?
tail -n 1 build/test_summary.log

/usr/bin/python3 "$root/scripts/count_test_results.py" build/test_results
count_status=$?

if [ $run_status -ne 0 ] || [ $results_status -ne 0 ] || [ $count_status -ne 0 ]; then
  exit 1
fi
