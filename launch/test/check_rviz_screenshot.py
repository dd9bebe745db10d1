#!/usr/bin/env python3
"""rostest: rviz draws what its configs promise, against a running simulation.

For each config, starts rviz under its own X server (xvfb-run), takes a screenshot of the whole
screen (ImageMagick `import -window root`) about every second and counts pixels of the colours
that only the wanted objects have, until they are all drawn (then stops rviz):
  map        the map's segments: the simulator's ground-truth map (green 0.1 0.9 0.1) or the
             tracker's map markers (~map_colors)
  estimate   the estimated camera: its frustum (orange 1 0.5 0, camera_visuals) and the TF axes
  truth      (simulation config only) the ground-truth camera's frustum (cyan 0 0.8 1)
A config passes when every required colour covers at least ~min_pixels pixels; rviz start-up
is retried (up to ~attempts times, waiting up to 20 s, 30 s, 40 s for the drawing). The last
screenshots are kept in ~out_dir (<config>.png) for a human to look at.
"""
import os
import subprocess
import sys
import time
import unittest

import numpy as np
import rospy
import rostest
from PIL import Image

PKG = "dvs_launch"
HERE = os.path.dirname(os.path.realpath(__file__))
RVIZ_DIR = os.path.join(HERE, "..", "rviz")


def colour_mask(img, rgb, tol):
    diff = np.abs(img[:, :, :3].astype(np.int32) - np.array(rgb, dtype=np.int32)[None, None, :])
    return np.all(diff <= tol, axis=2)


def render_area(img):
    """The 3D view: the bounding box of rviz's background colour (48, 48, 48); None if absent."""
    bg = colour_mask(img, (48, 48, 48), 0)
    if bg.sum() < 10000:
        return None
    # Rows and columns mostly made of background (text and icons elsewhere may share the colour).
    row_share, col_share = bg.sum(axis=1), bg.sum(axis=0)
    rows = np.where(row_share > 0.5 * row_share.max())[0]
    cols = np.where(col_share > 0.5 * col_share.max())[0]
    return img[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]


def count_colours(img, colours, tol):
    """Pixels within `tol` (per channel) of any of `colours`; a colour "red" means the lit red
    of TF's x axes (any shade with r > 100 and g, b < r / 3)."""
    mask = np.zeros(img.shape[:2], dtype=bool)
    for c in colours:
        if c == "red":
            i = img.astype(np.int32)
            mask |= (i[:, :, 0] > 100) & (i[:, :, 1] * 3 < i[:, :, 0]) & (i[:, :, 2] * 3 < i[:, :, 0])
        else:
            mask |= colour_mask(img, c, tol)
    return int(mask.sum())


class RvizScreenshotTest(unittest.TestCase):
    def watch_rviz(self, config, path, judge, wait_s):
        """rviz with `config` under its own X server; a screenshot of the whole screen about every
        second (ImageMagick `import`, renamed into `path` when complete) until judge(image) is
        true or wait_s have passed. Returns (passed, the last verdict)."""
        stop = path + ".stop"
        for stale in (path, stop):
            if os.path.exists(stale):
                os.remove(stale)
        script = ('rviz -d "$0" > "$1.rviz.log" 2>&1 & pid=$!; '
                  'while [ ! -e "$1.stop" ] && kill -0 $pid 2>/dev/null; do '
                  'import -window root "$1.tmp.png" 2>/dev/null && mv -f "$1.tmp.png" "$1"; sleep 1; done; '
                  'kill -INT $pid; for i in $(seq 50); do kill -0 $pid 2>/dev/null || break; sleep 0.1; done; '
                  'kill -KILL $pid 2>/dev/null; true')
        cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "bash", "-c", script, config, path]
        proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + wait_s
        verdict, seen, passed = {"screenshot": "missing"}, None, False
        try:
            while time.monotonic() < deadline and proc.poll() is None and not rospy.is_shutdown():
                stamp = os.path.getmtime(path) if os.path.exists(path) else None
                if stamp is not None and stamp != seen:
                    seen = stamp
                    try:
                        img = np.asarray(Image.open(path).convert("RGB"))
                    except (OSError, ValueError):
                        continue  # replaced while reading: the next one
                    passed, verdict = judge(img)
                    if passed:
                        break
                time.sleep(0.2)
        finally:
            open(stop, "w").close()
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                proc.kill()
            os.remove(stop)
        return passed, verdict

    def check_config(self, name, required):
        out_dir = rospy.get_param("~out_dir")
        os.makedirs(out_dir, exist_ok=True)
        attempts = int(rospy.get_param("~attempts", 3))
        min_pixels = int(rospy.get_param("~min_pixels", 40))
        tol = int(rospy.get_param("~tolerance", 30))
        config = os.path.realpath(os.path.join(RVIZ_DIR, name + ".rviz"))

        def judge(img):
            view = render_area(img)
            if view is None:
                return False, {"3d view": "not found"}
            counts = {k: count_colours(view, colours, tol) for k, colours in required.items()}
            return all(v >= min_pixels for v in counts.values()), counts

        counts = {}
        for attempt in range(attempts):
            path = os.path.join(out_dir, "%s.png" % name)
            # Until drawn, at most 20 s (+10 s per retry) after rviz starts; a retry starts a new rviz.
            passed, counts = self.watch_rviz(config, path, judge, wait_s=20 + 10 * attempt)
            rospy.loginfo("rviz %s attempt %d: %s", name, attempt + 1, counts)
            if passed:
                rospy.loginfo("rviz %s: drawn", name)
                return counts
        self.fail("rviz config %s: not drawn after %d attempts: pixel counts %s (need >= %d each; see %s)" % (
            name, attempts, counts, min_pixels, out_dir))

    def colours(self):
        # simulator's map (0.1 0.9 0.1), then the tracker's map markers (0 1 0)
        map_colours = [[25, 229, 25]] + [list(c) for c in rospy.get_param("~map_colors", [[0, 255, 0]])]
        return {
            "map": map_colours,
            "estimate": [[255, 128, 0]],     # camera_visuals frustum of dvs
            "axes_red": ["red"],             # TF x axes
        }

    def test_simulation_config(self):
        req = self.colours()
        req["truth"] = [[0, 204, 255]]       # camera_visuals frustum of dvs_gt
        self.check_config("simulation", req)

    def test_flight_config(self):
        req = self.colours()
        req["map"] = req["map"][1:] or req["map"]   # flight shows the tracker's map only
        self.check_config("flight", req)

    def test_replay_config(self):
        req = self.colours()
        req["map"] = req["map"][1:] or req["map"]
        self.check_config("replay", req)


if __name__ == "__main__":
    rospy.init_node("check_rviz_screenshot")
    rostest.rosrun(PKG, "check_rviz_screenshot", RvizScreenshotTest, sys.argv)
