#!/usr/bin/env python3
"""laser2d_variants_test.py SOURCE_DIR: the bench's variant generator keeps what the CARMEN
source reads as unknown odometry (issue 20): a dead-reckoning restart directly followed by the
next laser stays a restart (the ODOM line repeats the preceding laser's pose), in every variant
with odometry, while the other restarts join one continuous track."""
import gzip
import os
import sys
import tempfile

sys.path.insert(0, os.path.join(sys.argv[1], "scripts", "bench"))
import laser2d_variants as lv  # noqa: E402


def flaser(pose, odom, t):
    # FLASER n ranges... x y theta odom_x odom_y odom_theta timestamp host logger_timestamp
    return "FLASER 3 1.0 1.0 1.0 %s %s %.3f test %.3f\n" % (pose, odom, t, t)


# Laser 2's corrected pose (0.6) is ahead of the odometry (0.5): its restart line jumps there.
# After it a reading follows (a joined restart); after laser 3's restart the next laser follows
# directly (unknown odometry for laser 4, which turned 1.4 rad).
LOG = [
    "ODOM 0 0 0 0 0 0 0.0 test 0.0\n",
    flaser("0 0 0", "0 0 0", 0.1),
    "ODOM 0 0 0 0 0 0 0.2 test 0.2\n",
    "ODOM 0.5 0 0 0 0 0 0.3 test 0.3\n",
    flaser("0.6 0 0", "0.6 0 0", 0.4),
    "ODOM 0.6 0 0 0 0 0 0.5 test 0.5\n",
    "ODOM 1.1 0 0 0 0 0 0.6 test 0.6\n",
    flaser("1.2 0 0", "1.2 0 0", 0.7),
    "ODOM 1.2 0 0 0 0 0 0.8 test 0.8\n",
    flaser("1.2 0 1.4", "1.2 0 1.4", 0.9),
]


def variant(name):
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, name + ".log.gz")
        lv.write_variant(LOG, name, path)
        with gzip.open(path, "rt") as f:
            return [l.split() for l in f if l.strip()]


def fail(msg):
    print("FAIL: " + msg, file=sys.stderr)
    sys.exit(1)


assert lv.unknown_restarts(LOG) == {8}, lv.unknown_restarts(LOG)
for name in ["original", "scale_up", "drift", "sparse"]:
    lines = variant(name)
    kinds = [t[0] for t in lines]
    last = len(kinds) - 1
    if kinds[last] != "FLASER" or kinds[last - 1] != "ODOM":
        fail("%s: the unknown restart before the last laser is missing: %s" % (name, kinds))
    restart = tuple(float(v) for v in lines[last - 1][1:4])
    if not lv.same(restart, lv.laser_pose(lines[last - 2])):
        fail("%s: the restart %s does not repeat the preceding laser's pose" % (name, restart))
    # The joined restart after laser 2 is a point of the continuous track: 0.5 (odometry), not
    # the corrected 0.6, for the undegraded original.
    if name == "original":
        joined = [tuple(float(v) for v in t[1:4]) for t in lines if t[0] == "ODOM"]
        if (0.5, 0.0, 0.0) not in joined or (0.6, 0.0, 0.0) in joined:
            fail("original: the restart after laser 2 is not joined into the track: %s" % joined)
if any(t[0] == "ODOM" for t in variant("no_odom")):
    fail("no_odom kept an ODOM line")
print("ok: unknown-odometry restarts survive every variant")
