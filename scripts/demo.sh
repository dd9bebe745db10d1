#!/usr/bin/env bash
# The demo: a simulated quadrotor flip (1200 deg/s peak roll rate) seen by the software DVS and
# tracked LIVE through ROS by the line tracker nodelet (roslaunch dvs_launch simulation.launch).
#
#   scripts/demo.sh                 set up + build (scripts/setup.sh), run, print accuracy and
#                                   throughput, write the Fig. 4.15-like plot; rviz if $DISPLAY is set
#   scripts/demo.sh --no-setup      skip set-up and build (already built)
#   scripts/demo.sh --no-rviz       never open rviz (--rviz: always)
#   scripts/demo.sh --out DIR       outputs into DIR (default: build/demo)
#   scripts/demo.sh --devel DIR     use another catkin devel space (default: devel)
#
# Outputs: DIR/estimate.tum, DIR/groundtruth.tum (TUM `t tx ty tz qx qy qz qw`, T_world_camera),
# DIR/run.json (counts, rates, latency, tracker diagnostics), DIR/accuracy.json, DIR/summary.json,
# DIR/flip.png, DIR/launch.log, DIR/log/ (ROS logs).
# Uses a private ROS master on a random port and stops every process it started.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=env.sh
source "$root/scripts/env.sh"

setup=1
rviz=auto
out="$root/build/demo"
devel="$root/devel"
while [ $# -gt 0 ]; do
  case "$1" in
    --no-setup) setup=0 ;;
    --no-rviz) rviz=no ;;
    --rviz) rviz=yes ;;
    --out) shift; out="${1:?--out needs a directory}" ;;
    --devel) shift; devel="${1:?--devel needs a directory}" ;;
    -h|--help) sed -n '2,15p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "demo: unknown argument $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if [ "$rviz" = auto ]; then
  if [ -n "${DISPLAY:-}" ]; then rviz=yes; else rviz=no; fi
fi

if [ $setup -eq 1 ]; then
  "$root/scripts/setup.sh"
fi
if [ ! -f "$devel/setup.bash" ]; then
  echo "demo: $devel/setup.bash missing: build first (scripts/setup.sh)" >&2
  exit 1
fi
set +u
# shellcheck disable=SC1091
source "$devel/setup.bash"
set -u

mkdir -p "$out"
out="$(cd "$out" && pwd)"
rm -f "$out"/estimate.tum "$out"/groundtruth.tum "$out"/run.json "$out"/accuracy.json "$out"/flip.png
# A free port: roslaunch -p would join a master already listening there instead of starting one.
for _ in $(seq 1 50); do
  port=$(( 20000 + RANDOM % 20000 ))
  (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null || break
done
export ROS_MASTER_URI="http://localhost:$port"
export ROS_HOME="$out/ros_home"
export ROS_LOG_DIR="$out/log"
mkdir -p "$ROS_HOME" "$ROS_LOG_DIR"

launch_pid=""
cleanup() {
  if [ -n "$launch_pid" ] && kill -0 "$launch_pid" 2>/dev/null; then
    # roslaunch (own process group) stops its nodes and the master it started on SIGINT.
    kill -INT -- "-$launch_pid" 2>/dev/null || true
    for _ in $(seq 1 100); do kill -0 "$launch_pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL -- "-$launch_pid" 2>/dev/null || true
  fi
  launch_pid=""
}
trap cleanup EXIT
trap 'exit 130' INT TERM

run_launch() {  # args: log file, time limit (s, 0: none), roslaunch arguments
  local log="$1" limit="$2"; shift 2
  local guard=()
  [ "$limit" -gt 0 ] && guard=(timeout -s INT -k 15 "$limit")
  # Own session and process group (non-interactive shell: setsid does not fork, so $! is the
  # group's id): cleanup stops roslaunch, its nodes and the master it started together.
  setsid "${guard[@]}" roslaunch -p "$port" dvs_launch simulation.launch "$@" > "$log" 2>&1 &
  launch_pid=$!
  wait "$launch_pid" || true
  launch_pid=""
}

echo "demo: simulated 1200 deg/s flip -> software DVS -> tracker nodelet (live, real time), master on port $port"
start=$(date +%s)
# The launch ends by itself when the recorder has seen the run end (record_dir); 100 s at most.
run_launch "$out/launch.log" 100 scenario:=flip real_time_factor:=1.0 record_dir:="$out" rviz:=false visuals:=false
echo "demo: run finished in $(( $(date +%s) - start )) s (log: $out/launch.log)"

estimates=$(/usr/bin/python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["estimates"])' "$out/run.json" 2>/dev/null || echo 0)
if [ "$estimates" -eq 0 ]; then
  echo "demo: the tracker published no pose (recording: $out/run.json); the launch's last lines:" >&2
  grep -E "ERROR|FATAL|died" "$out/launch.log" | tail -n 10 >&2 || true
  echo "demo: full log: $out/launch.log" >&2
  exit 1
fi

/usr/bin/python3 "$root/launch/scripts/evaluate_trajectory.py" --gt "$out/groundtruth.tum" --est "$out/estimate.tum" \
  --plot "$out/flip.png" --json "$out/accuracy.json" \
  --title "1200 deg/s flip, software DVS, tracker nodelet live (scripts/demo.sh)" > /dev/null
/usr/bin/python3 "$root/launch/scripts/demo_report.py" "$out"

if [ "$rviz" = yes ]; then
  echo "demo: opening rviz (the flip in a loop at 1/4 speed; close rviz or press Ctrl-C to end)"
  run_launch "$out/rviz_launch.log" 0 scenario:=flip real_time_factor:=0.25 loop:=true rviz:=true rviz_required:=true
fi
