#!/usr/bin/env python3
"""How noisy is a reference trajectory over short segments? A three-cornered hat.

usage: reference_floor.py REFERENCE.tum LASER.tum ODOMETRY.tum [--delta 1.0]

Three estimates of the same motions: the reference (GMapping's poses in the CARMEN logs), a
laser-only front-end and wheel odometry. Over every segment i -> j of the RPE (j the first pose
at least DELTA metres further along the reference path), each estimate gives a relative motion
(x, y, theta in frame i). If the three estimates' errors are independent,
    var(A - B) = sA^2 + sB^2,  var(A - C) = sA^2 + sC^2,  var(B - C) = sB^2 + sC^2
and the three variances follow. Variances are robust ((1.4826 MAD)^2), so a few failed
alignments or odometry slips do not dominate. Translation components are in % of the segment's
path length, rotation in degrees. A negative variance (the data contradict independence, or the
estimator is far below the others' noise) is reported as 0.

Prints JSON: per estimator sigma_x_pct, sigma_y_pct, sigma_theta_deg, and for the reference the
mean translation error in % that a perfect estimator would show against it (the floor):
the mean norm of a 2D Gaussian with those sigmas, estimated by sampling.
"""
import bisect
import json
import math
import random
import sys


def load(path):
    poses = []
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            v = [float(x) for x in line.split()]
            qx, qy, qz, qw = v[4:8]
            poses.append((v[0], v[1], v[2], math.atan2(2 * (qw * qz + qx * qy),
                                                      1 - 2 * (qy * qy + qz * qz))))
    return poses


def relative(a, b):
    c, s = math.cos(a[3]), math.sin(a[3])
    dx, dy = b[1] - a[1], b[2] - a[2]
    return (c * dx + s * dy, -s * dx + c * dy, math.remainder(b[3] - a[3], 2 * math.pi))


def robust_var(values):
    v = sorted(values)
    med = v[len(v) // 2]
    dev = sorted(abs(x - med) for x in v)
    return (1.4826 * dev[len(dev) // 2]) ** 2


def main():
    args = [a for a in sys.argv[1:]]
    delta = 1.0
    if "--delta" in args:
        k = args.index("--delta")
        delta = float(args[k + 1])
        del args[k:k + 2]
    if len(args) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    ref, laser, odom = (load(p) for p in args)
    # Association by timestamp (all three come from the same run of the same log).
    by_time = [{round(p[0], 6): p for p in t} for t in (laser, odom)]
    rows = [(r, by_time[0].get(round(r[0], 6)), by_time[1].get(round(r[0], 6))) for r in ref]
    rows = [x for x in rows if x[1] and x[2]]
    dist = [0.0]
    for a, b in zip(rows, rows[1:]):
        dist.append(dist[-1] + math.hypot(b[0][1] - a[0][1], b[0][2] - a[0][2]))
    diffs = {"AB": [], "AC": [], "BC": []}
    for i in range(len(rows)):
        j = bisect.bisect_left(dist, dist[i] + delta)
        if j >= len(rows):
            break
        length = dist[j] - dist[i]
        m = [relative(rows[i][k], rows[j][k]) for k in range(3)]
        for key, (u, v) in {"AB": (0, 1), "AC": (0, 2), "BC": (1, 2)}.items():
            diffs[key].append((100 * (m[u][0] - m[v][0]) / length,
                               100 * (m[u][1] - m[v][1]) / length,
                               math.degrees(math.remainder(m[u][2] - m[v][2], 2 * math.pi))))
    if len(diffs["AB"]) < 10:
        print("reference_floor.py: fewer than 10 segments of %g m" % delta, file=sys.stderr)
        return 1
    sigma = {"reference": [], "laser": [], "odometry": []}
    for c in range(3):
        vab, vac, vbc = (robust_var([d[c] for d in diffs[k]]) for k in ("AB", "AC", "BC"))
        for name, var in (("reference", (vab + vac - vbc) / 2), ("laser", (vab + vbc - vac) / 2),
                          ("odometry", (vac + vbc - vab) / 2)):
            sigma[name].append(math.sqrt(max(0.0, var)))
    out = {"delta_m": delta, "segments": len(diffs["AB"])}
    for name, s in sigma.items():
        out[name] = {"sigma_x_pct": s[0], "sigma_y_pct": s[1], "sigma_theta_deg": s[2]}
    rng = random.Random(1)
    sx, sy = sigma["reference"][0], sigma["reference"][1]
    n = 200000
    out["reference"]["floor_translation_pct_mean"] = sum(
        math.hypot(rng.gauss(0, sx), rng.gauss(0, sy)) for _ in range(n)) / n
    # A perfect estimator's mean rotation error against the reference: E|N(0, s)|.
    out["reference"]["floor_rotation_deg_mean"] = sigma["reference"][2] * math.sqrt(2 / math.pi)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
