#!/bin/sh
# Test helper (launch-prefix): wait until the X server of $DISPLAY listens (its socket exists,
# at most 30 s), then run the command. screen_sim.test starts its own Xvfb as a node, in
# parallel with the nodes that need it.
number="${DISPLAY#*:}"
socket="/tmp/.X11-unix/X${number%%.*}"
i=0
while [ ! -S "$socket" ] && [ $i -lt 300 ]; do
  sleep 0.1
  i=$((i + 1))
done
sleep 0.5
exec "$@"
