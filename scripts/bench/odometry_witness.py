#!/usr/bin/env python3
"""Whose error is it: odometry as a third witness between our SLAM and the reference.

usage: odometry_witness.py OURS.tum REFERENCE.tum ODOMETRY.tum FRONTEND.tum [--max-gap 40]

Over a short stretch of path, wheel odometry (dead reckoning, ODOMETRY) measures the relative
pose of two scans independently of either laser estimate. For the relation-metric pairs (scans
within 2 m by the reference, plus consecutive scans) at most --max-gap scans apart, each relation
error of ours against the reference above 0.1 m is put down to whichever of the two the odometry
disagrees with more. Relations that span a tracking failure of the front-end (FRONTEND.tum: a
step that moved exactly by the odometry) are left out, because there our estimate is the
odometry's. The odometry drifts and both estimators use it as a prior, so this is a tally, not
a proof: on a log where the reference is good (intel) it splits about evenly.
Prints JSON.
"""
import json
import math
import sys

from tum2d import load, relative


def dist(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    max_gap = 40
    if "--max-gap" in argv:
        max_gap = int(argv[argv.index("--max-gap") + 1])
        args.remove(str(max_gap))
    if len(args) != 4:
        sys.exit(__doc__)
    ours, ref, odo, front = (load(p) for p in args)
    n = min(len(ours), len(ref), len(odo), len(front))
    for t in (ref, odo, front):
        if any(abs(ours[i][0] - t[i][0]) > 0.01 for i in range(n)):
            sys.exit("trajectories are not one pose per scan with matching stamps")
    failed = set()
    for i in range(n - 1):
        a, b = relative(front[i], front[i + 1]), relative(odo[i], odo[i + 1])
        if dist(a, b) < 1e-5 and abs(a[2] - b[2]) < 1e-6:
            failed.add(i)
    rows = []
    for i in range(n):
        for j in range(i + 1, min(n, i + max_gap + 1)):
            near = math.hypot(ref[i][1] - ref[j][1], ref[i][2] - ref[j][2]) <= 2.0
            if not (near or j == i + 1) or any(k in failed for k in range(i, j)):
                continue
            o, r, w = relative(ours[i], ours[j]), relative(ref[i], ref[j]), relative(odo[i], odo[j])
            rows.append((dist(o, r), dist(o, w), dist(r, w)))
    big = [x for x in rows if x[0] > 0.1]
    with_ref = [x[0] for x in big if x[2] < x[1]]
    with_ours = [x[0] for x in big if x[2] >= x[1]]
    small = sum(x[0] for x in rows if x[0] <= 0.1)
    print(json.dumps({
        "relations": len(rows),
        "tracking_failures": len(failed),
        "mean_m": sum(x[0] for x in rows) / max(1, len(rows)),
        "odometry_sides_with_reference": {"count": len(with_ref), "error_m": sum(with_ref)},
        "odometry_sides_with_ours": {"count": len(with_ours), "error_m": sum(with_ours)},
        # The mean if the relations where the odometry sides with ours were the reference's error.
        "mean_without_ours_sided_m": (small + sum(with_ref)) / max(1, len(rows) - len(with_ours)),
    }, indent=1))


if __name__ == "__main__":
    main(sys.argv[1:])
