#!/usr/bin/env python3
"""Degraded variants of a CARMEN log (issue 20), written from the original each time.

  laser2d_variants.py LOG OUT_DIR [VARIANT ...]

writes OUT_DIR/<variant>.log.gz for each variant (default: all):
  original   the odometry rewritten as one continuous dead-reckoning track (see below), else
             unchanged: the baseline every other variant differs from in one thing only
  no_odom    no ODOM lines: laser only
  scale_up   odometry translation scaled by 1.1 (+10 %)
  scale_down odometry translation scaled by 0.9 (-10 %)
  drift      odometry heading drifting by 5 deg per metre travelled
  sparse     every 5th ODOM line only
  decimate3  every 3rd laser line only (all odometry kept)
  decimate5  every 5th laser line only

GMapping-corrected logs restart dead reckoning after every scan: an ODOM line that repeats the
preceding laser's pose (the corrected one), which the source treats as "no motion here". A
degradation of the odometry must survive those restarts, so every variant first turns the ODOM
lines into the track the source itself integrates (increments composed, restart jumps left out),
then degrades that track's increments. Laser lines and their (reference) poses stay verbatim.
One restart is kept as it is: one followed by the next laser line with no reading in between. The
source takes that laser's odometry as unknown (the wheels were not read across the scan pair; on
seattle the robot turned 81 deg there), so the variant writes the restart verbatim and continues
its track from it; written as a point of the continuous track it would say "no motion" instead.
Nothing of the log is tuned here: the variants are the issue's, the same for every log.
"""
import gzip
import math
import os
import sys

VARIANTS = ["original", "no_odom", "scale_up", "scale_down", "drift", "sparse", "decimate3",
            "decimate5"]


def compose(a, b):
    x, y, t = a
    c, s = math.cos(t), math.sin(t)
    return (x + c * b[0] - s * b[1], y + s * b[0] + c * b[1], t + b[2])


def between(a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    c, s = math.cos(a[2]), math.sin(a[2])
    return (c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(b[2] - a[2]), math.cos(b[2] - a[2])))


def same(a, b):
    d = math.atan2(math.sin(a[2] - b[2]), math.cos(a[2] - b[2]))
    return abs(a[0] - b[0]) < 1e-6 and abs(a[1] - b[1]) < 1e-6 and abs(d) < 1e-6


def laser_pose(tokens):
    """The robot pose of a FLASER line (the field a restart line repeats), or None."""
    if tokens[0] != "FLASER":
        return None
    n = int(tokens[1])
    return tuple(float(v) for v in tokens[2 + n + 3:2 + n + 6])


def degrade(step, variant):
    x, y, t = step
    if variant == "scale_up":
        return (1.1 * x, 1.1 * y, t)
    if variant == "scale_down":
        return (0.9 * x, 0.9 * y, t)
    if variant == "drift":
        return (x, y, t + math.radians(5.0) * math.hypot(x, y))
    return step


def unknown_restarts(lines):
    """Indices of the ODOM lines that restart dead reckoning and are followed by a laser line
    before any other reading: the source marks that laser's odometry as unknown."""
    found = set()
    after_laser = None
    pending = None
    for i, line in enumerate(lines):
        tokens = line.split()
        if not tokens:
            continue
        if tokens[0] == "FLASER":
            if pending is not None:
                found.add(pending)
            pending = None
            after_laser = laser_pose(tokens)
        elif tokens[0] == "ODOM":
            raw = tuple(float(v) for v in tokens[1:4])
            pending = i if after_laser is not None and same(raw, after_laser) else None
            after_laser = None
    return found


def write_variant(lines, variant, path):
    track = None      # the degraded continuous track (what the source will integrate)
    last_raw = None   # the previous ODOM line's logged pose
    after_laser = None
    odom_index = 0
    laser_index = 0
    laser_kept = False  # whether the last laser line was written
    unknown = unknown_restarts(lines)
    with gzip.open(path, "wt") as out:
        for i, line in enumerate(lines):
            tokens = line.split()
            if not tokens:
                out.write(line)
                continue
            kind = tokens[0]
            if kind == "FLASER":
                laser_index += 1
                keep = variant not in ("decimate3", "decimate5") or \
                    (laser_index - 1) % (3 if variant == "decimate3" else 5) == 0
                after_laser = laser_pose(tokens)
                laser_kept = keep
                if keep:
                    out.write(line)
                continue
            if kind != "ODOM":
                out.write(line)
                continue
            raw = tuple(float(v) for v in tokens[1:4])
            if i in unknown and laser_kept and variant != "no_odom":
                # Verbatim, so the source sees the restart after the laser it follows; the track
                # goes on from the restarted pose.
                track = raw
                last_raw = raw
                after_laser = None
                out.write(line)
                continue
            if last_raw is None:
                track = raw
            elif not (after_laser is not None and same(raw, after_laser)):
                track = compose(track, degrade(between(last_raw, raw), variant))
            # else: a restart line, the jump to the corrected pose is not motion
            last_raw = raw
            after_laser = None
            odom_index += 1
            if variant == "no_odom" or (variant == "sparse" and (odom_index - 1) % 5 != 0):
                continue
            theta = math.atan2(math.sin(track[2]), math.cos(track[2]))
            out.write(" ".join(["ODOM", "%.6f" % track[0], "%.6f" % track[1], "%.6f" % theta] +
                               tokens[4:]) + "\n")


def main(argv):
    if len(argv) < 3:
        sys.stderr.write(__doc__)
        return 2
    log, out_dir = argv[1], argv[2]
    variants = argv[3:] or VARIANTS
    for v in variants:
        if v not in VARIANTS:
            sys.stderr.write("unknown variant '%s' (expected one of %s)\n" % (v, ", ".join(VARIANTS)))
            return 2
    opener = gzip.open if log.endswith(".gz") else open
    with opener(log, "rt", errors="replace") as f:
        lines = f.readlines()
    os.makedirs(out_dir, exist_ok=True)
    for v in variants:
        write_variant(lines, v, os.path.join(out_dir, v + ".log.gz"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
