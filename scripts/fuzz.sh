#!/usr/bin/env bash
# Fuzz every parser of the suite with libFuzzer (clang, -fsanitize=fuzzer,address,undefined).
#   scripts/fuzz.sh [SECONDS]   run each target for SECONDS (default 60); exit 1 on any finding
#   FUZZ_RUNS=N scripts/fuzz.sh SECONDS   at most N inputs per target (CI: with the fixed seed the
#                               run is the same on every machine, whatever its speed)
# Targets (fuzz/targets/): events.txt, AEDAT 2.0, the DVS128 USB decoder, camera files (calib.txt
# and camera_info YAML), line map YAML, the tracker's parameter YAML, serialized EventArray
# messages, the event file formats (Prophesee RAW EVT 2.0/3.0, AEDAT 4.0, AEDAT 3.1) and
# event_camera_msgs/EventPacket payloads (evt3, mono, libcaer). Seed corpora come from ../shared/data and the project's own config files; findings
# (crash-*, leak-*, timeout-*) land in build_fuzz/findings/<target>/ with the libFuzzer log.
# Needs a catkin build first for the EventArray target (scripts/setup.sh builds one).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=env.sh
source "$root/scripts/env.sh"
seconds="${1:-60}"
case "$seconds" in ''|*[!0-9]*) echo "fuzz: SECONDS must be a whole number (got '$seconds')" >&2; exit 2 ;; esac
command -v clang++ >/dev/null || { echo "fuzz: clang++ missing (scripts/setup.sh installs it)" >&2; exit 2; }

build="$root/build_fuzz"; mkdir -p "$build"
CC=clang CXX=clang++ cmake -S "$root/fuzz" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEVEL_DIR="$root/devel" \
  > "$build/cmake.log" 2>&1 || { cat "$build/cmake.log"; echo "fuzz: cmake failed" >&2; exit 2; }
make -C "$build" -j2 > "$build/make.log" 2>&1 || { tail -n 30 "$build/make.log"; echo "fuzz: build failed" >&2; exit 2; }

data="$root/../shared/data"
seed() {  # target, files...
  local dir="$build/corpus/$1"; shift
  mkdir -p "$dir"
  for f in "$@"; do
    [ -f "$f" ] && head -c 65536 "$f" > "$dir/seed_$(basename "$f")"
  done
}
tmp="$build/seed_src"; mkdir -p "$tmp"
printf '0.000100000 10 20 1\n0.000200000 11 20 0\n# comment\n0.000300000 127 127 1\n' > "$tmp/events.txt"
printf '115 115 63.5 63.5 -0.1 0.01 0 0 0\n' > "$tmp/calib.txt"
printf '\001image_width: 128\nimage_height: 128\ncamera_name: dvs\ncamera_matrix: {rows: 3, cols: 3, data: [115, 0, 63.5, 0, 115, 63.5, 0, 0, 1]}\ndistortion_model: plumb_bob\ndistortion_coefficients: {rows: 1, cols: 5, data: [-0.1, 0.01, 0, 0, 0]}\n' > "$tmp/camera.yaml"
printf '\000115 115 63.5 63.5 -0.1 0.01 0 0 0\n' > "$tmp/calib_selected.txt"
seed fuzz_events_text "$tmp/events.txt"
seed fuzz_aedat2 "$data"/real/*.aedat
seed fuzz_dvs128_decoder "$data"/real/colleen_pen_short.aedat
seed fuzz_camera_files "$tmp/camera.yaml" "$tmp/calib_selected.txt"
seed fuzz_line_map "$root"/dvs_line_tracker/config/square_map.yaml
seed fuzz_tracker_params "$root"/dvs_line_tracker/config/thesis_params.yaml
seed fuzz_event_array "$tmp/events.txt"
# Format seeds: the header byte (0 EVT 3.0, 1 EVT 2.0, 2 AEDAT 4.0, 3 AEDAT 3.1, 4 as is) then the
# data after the real samples' headers.
fseed() {  # target, selector byte (octal), file, header bytes to skip
  local dir="$build/corpus/$1"; mkdir -p "$dir"
  [ -f "$3" ] && { printf "\\$2"; tail -c +$(( $4 + 1 )) "$3" | head -c 65536; } > "$dir/seed_$(basename "$3")"
}
fseed fuzz_event_formats 000 "$data/formats/prophesee_evt3_gen41_1280x720.raw" 166
fseed fuzz_event_formats 001 "$data/formats/prophesee_evt2_gen3_640x480.raw" 164
fseed fuzz_event_formats 004 "$data/formats/dvxplorer_320x240.aedat4" 0
fseed fuzz_event_formats 004 "$data/formats/davis346_346x260.aedat4" 0
fseed fuzz_event_packet 000 "$data/formats/prophesee_evt3_gen41_1280x720.raw" 166

status=0
ok=0 bad=0
for target in fuzz_events_text fuzz_aedat2 fuzz_dvs128_decoder fuzz_camera_files fuzz_line_map fuzz_tracker_params \
              fuzz_event_array fuzz_event_formats fuzz_event_packet; do
  exe="$build/$target"
  if [ ! -x "$exe" ]; then echo "fuzz: $target was not built" >&2; status=1; bad=$(( bad + 1 )); continue; fi
  findings="$build/findings/$target"; mkdir -p "$findings" "$build/corpus/$target"
  log="$findings/log.txt"
  # -seed=1: the same run on every machine (CI repeats what was run here).
  runs_limit=()
  [ -n "${FUZZ_RUNS:-}" ] && runs_limit=(-runs="$FUZZ_RUNS")
  TMPDIR="$findings" "$exe" "$build/corpus/$target" -seed=1 "${runs_limit[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -artifact_prefix="$findings/" -print_final_stats=1 > "$log" 2>&1
  rc=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
  if [ $rc -ne 0 ]; then
    echo "fuzz: $target FOUND A PROBLEM (exit $rc, ${runs:-?} runs): $log"
    grep -E "ERROR|SUMMARY|runtime error|Test unit written" "$log" | head -n 8
    status=1
    bad=$(( bad + 1 ))
  else
    echo "fuzz: $target ok (${runs:-?} runs, at most ${seconds} s)"
    ok=$(( ok + 1 ))
  fi
done
echo "${ok} passed, ${bad} failed"
exit $status
