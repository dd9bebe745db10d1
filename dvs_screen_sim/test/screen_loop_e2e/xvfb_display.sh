#!/bin/sh
# Test helper: an X server for the screen_loop end-to-end rostest (ROS args are ignored).
exec Xvfb "$DISPLAY" -screen 0 640x480x24 -nolisten tcp -noreset
