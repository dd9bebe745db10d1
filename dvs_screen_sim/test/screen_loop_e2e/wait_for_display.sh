#!/bin/sh
# Test helper (launch-prefix): wait until the X server of $DISPLAY accepts clients (xdpyinfo
# connects; at most 30 s), then run the command. The tests start their own Xvfb as a node,
# in parallel with the nodes that need it (dvs_screen_sim screen_loop_node.test, dvs_launch screen_sim.test). Fails with a message naming the display on timeout.
i=0
until xdpyinfo -display "$DISPLAY" >/dev/null 2>&1; do
  if [ $i -ge 300 ]; then
    echo "wait_for_display.sh: no X server accepting clients on DISPLAY=$DISPLAY after 30 s" >&2
    exit 1
  fi
  sleep 0.1
  i=$((i + 1))
done
exec "$@"
