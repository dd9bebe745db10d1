#!/bin/sh
# realtime_exec's behaviour, as JUnit XML into $1: normal scheduling at 0; SCHED_FIFO at the
# priority asked when permitted (root here, as in CI), else normal scheduling and a note; the
# command's exit code passed through; bad priorities refused with a message naming them.
xml=${1:?usage: test_realtime_exec.sh RESULT.xml}
exe="$(cd "$(dirname "$0")/.." && pwd)/scripts/realtime_exec"
cases=""
failures=0
count=0
check() {  # name, condition (0 = pass), detail
  count=$((count + 1))
  if [ "$2" -eq 0 ]; then
    cases="$cases<testcase classname=\"realtime_exec\" name=\"$1\"/>"
  else
    failures=$((failures + 1))
    cases="$cases<testcase classname=\"realtime_exec\" name=\"$1\"><failure message=\"$3\"/></testcase>"
    echo "FAILED: $1: $3" >&2
  fi
}
policy() { "$exe" "$@" sh -c 'chrt -p $$' 2>/dev/null | sed -n 's/.*policy: //p'; }

p=$(policy 0); [ "$p" = SCHED_OTHER ]; check zero_is_normal_scheduling $? "policy $p"
if chrt -f 10 true 2>/dev/null; then
  p=$(policy 10); [ "$p" = SCHED_FIFO ]; check fifo_when_permitted $? "policy $p"
  prio=$("$exe" 17 sh -c 'chrt -p $$' | sed -n 's/.*priority: //p'); [ "$prio" = 17 ]; check the_priority_asked $? "priority $prio"
else
  p=$(policy 10); [ "$p" = SCHED_OTHER ]; check normal_when_not_permitted $? "policy $p"
fi
if command -v setpriv >/dev/null 2>&1 && [ "$(id -u)" -eq 0 ] &&
   setpriv --reuid=65534 --regid=65534 --clear-groups test -x "$exe" 2>/dev/null; then
  # An unprivileged user (no CAP_SYS_NICE, rtprio limit 0): normal scheduling and a note.
  out=$(setpriv --reuid=65534 --regid=65534 --clear-groups "$exe" 10 sh -c 'chrt -p $$' 2>&1)
  echo "$out" | grep -q "policy: SCHED_OTHER" && echo "$out" | grep -q "not permitted"
  check unprivileged_falls_back_with_a_note $? "$(echo "$out" | tr '\n<>"&' ' ')"
fi
"$exe" 10 sh -c 'exit 3' 2>/dev/null; [ $? -eq 3 ]; check exit_code_passed_through $? "exit code"
for bad in abc 100 -1 "" 99999999999999999999; do
  out=$("$exe" "$bad" true 2>&1); rc=$?
  [ $rc -eq 2 ] && echo "$out" | grep -q "realtime_priority must be an integer in \[0, 99\]"
  check "refuses_priority_'$bad'" $? "rc $rc: $out"
done
"$exe" 10 >/dev/null 2>&1; [ $? -eq 2 ]; check refuses_a_missing_command $? "rc"

mkdir -p "$(dirname "$xml")"
printf '<?xml version="1.0" encoding="UTF-8"?>\n<testsuite name="realtime_exec" tests="%d" failures="%d" errors="0">%s</testsuite>\n' \
  "$count" "$failures" "$cases" > "$xml"
[ $failures -eq 0 ]
