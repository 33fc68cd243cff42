#!/usr/bin/env python3
"""How much of the front-end's error against a reference is the reference's own noise?

usage: reference_noise.py REFERENCE.tum OURS.tum LASER.tum ODOMETRY.tum [LASER_REFGUESS.tum]
                          [--delta 1.0] [--block 20] [--resamples 400] [--seed 1]
                          [--crispness PLUGSLAM_BINARY LOG]

All trajectories come from runs on the same log (poses matched by timestamp):
  A  REFERENCE       the log's poses (GMapping's estimate in the corrected CARMEN logs)
  P  OURS            the front-end as shipped (laser + odometry prior)
  B  LASER           the front-end with the laser slice only (no odometry factor; the odometry
                     only predicts the starting guess)
  C  ODOMETRY        dead reckoning (the odometry prior slice only)
  B' LASER_REFGUESS  as B but predicted from the reference (source.use_laser_odometry): if B and
                     B' agree, the laser-only estimate does not depend on where it starts, so it
                     shares no error with C (or A) through the guess.

Three estimates of the reference's noise, each a LOWER bound under the stated assumption:
 1. Jitter (white per-pose noise, no segment model): consecutive-step differences of A and B,
    d_k = (A's step k -> k+1) - (B's step), world-aligned by A's heading. White per-pose noise
    e_k of either makes d_k = e_{k+1} - e_k + ..., so cov(d_k, d_{k+1}) = -(var(e_A) + var(e_B))
    while errors that vary slowly (drift) give a positive covariance at every lag. Robust:
    cov(x, y) = (rvar(x + y) - rvar(x - y)) / 4 with rvar = (1.4826 MAD)^2. The lag-2
    covariance is reported too: white noise leaves it near 0. This sees A's and B's jitter
    together (dead reckoning cannot separate them: its step errors are strongly correlated from
    one step to the next, reported as odometry_lag1_correlation); its 1 m error is what that
    jitter alone costs; local crispness (scans 1-10 apart) tells whose it mostly is.
 2. Three-cornered hat over DELTA-metre segments with A, B and C (sigma_A^2 =
    (var(A-B) + var(A-C) - var(B-C)) / 2, robust variances). A and B see the same scans, so
    their errors correlate positively, which lowers sigma_A (GMapping's scan matcher and ours
    fail in the same corridors).
 3. The floor each implies: the mean translation error in % (and rotation in degrees) that an
    estimate with no error of its own would show against A over the same segments, from the
    actual segment lengths and displacements (Monte Carlo).
Whose jitter (--crispness): white noise of sigma = s * (the combined jitter, both components
scaled alike) is added to OUR poses until their local crispness (`plugslam eval crispness LOG
--min-gap 1 --max-gap 10 --max-range 20`) equals the reference's; s_eq is interpolated from
s = 0, 0.5, 1, 1.5, 2 (two noise seeds each). If jitter were the only difference between the two
trajectories, sigma_eq^2 = sigma_A^2 - sigma_P^2 and, with the combined sigma_A^2 + sigma_P^2, the
reference's share is sigma_A^2 = (combined^2 + sigma_eq^2) / 2 (s_eq near 1: nearly all of the
combined jitter is the reference's).
Our own error: sigma_P^2 = var(A - P) - sigma_A^2 per component (hat estimate of A), turned
into the mean error the front-end would show against a perfect reference.
Vote: on the steps where A and P differ by more than 5 cm, dead reckoning (which shares no
input with either) is a tie-breaker: it counts for P when it is within half that difference of
P's step, for A when within half of A's.
Every figure has a 95 % confidence interval from a moving-block bootstrap (blocks of BLOCK
consecutive steps / segments, so the overlap of neighbouring segments is kept inside blocks).

Prints JSON.
"""
import bisect
import json
import math
import os
import random
import subprocess
import sys
import tempfile

from tum2d import load, matched, relative, take_options


def rvar(values):
    v = sorted(values)
    n = len(v)
    med = v[n // 2]
    dev = sorted(abs(x - med) for x in v)
    return (1.4826 * dev[n // 2]) ** 2


def rcov(x, y):
    return (rvar([a + b for a, b in zip(x, y)]) - rvar([a - b for a, b in zip(x, y)])) / 4


def percentile(values, q):
    v = sorted(values)
    k = min(len(v) - 1, max(0, int(round(q * (len(v) - 1)))))
    return v[k]


def block_indices(n, block, rng):
    """Indices of one moving-block bootstrap resample of a sequence of length n."""
    out = []
    while len(out) < n:
        start = rng.randrange(0, max(1, n - block + 1))
        out.extend(range(start, min(n, start + block)))
    return out[:n]


def lag_cov(steps_a, steps_b, idx, lag=1):
    """Robust covariance of d_k and d_{k+lag}, d = a - b, per component."""
    ks = [k for k in idx if k + lag < len(steps_a)]
    out = []
    for c in range(3):
        x = [steps_a[k][c] - steps_b[k][c] for k in ks]
        y = [steps_a[k + lag][c] - steps_b[k + lag][c] for k in ks]
        out.append(rcov(x, y))
    return out


def jitter(steps_a, steps_b, idx):
    """Combined white per-pose noise variance of a and b (x, y in m^2, theta in rad^2)."""
    return [max(0.0, -c) for c in lag_cov(steps_a, steps_b, idx)]


def hat(diffs, idx):
    """sigma^2 per component of A, B, C from the pairwise differences (robust)."""
    res = {"A": [], "B": [], "C": []}
    for c in range(3):
        vab, vac, vbc = (rvar([diffs[k][i][c] for i in idx]) for k in ("AB", "AC", "BC"))
        res["A"].append(max(0.0, (vab + vac - vbc) / 2))
        res["B"].append(max(0.0, (vab + vbc - vac) / 2))
        res["C"].append(max(0.0, (vac + vbc - vab) / 2))
    return res


def floor_from_segment_var(var_pct, n=20000, seed=7):
    """Mean |N(0, diag(var_x, var_y))| in % and E|N(0, var_theta)| in degrees."""
    rng = random.Random(seed)
    sx, sy = math.sqrt(var_pct[0]), math.sqrt(var_pct[1])
    t = sum(math.hypot(rng.gauss(0, sx), rng.gauss(0, sy)) for _ in range(n)) / n
    return t, math.sqrt(var_pct[2]) * math.sqrt(2 / math.pi)


def floor_from_jitter(var, segments, n_per=20, seed=7):
    """Mean error in % / degrees of a perfect estimate against A with white per-pose noise var
    (x, y in m^2, theta in rad^2): segment error = R_i^T (e_j - e_i) + eps_i x (p_j - p_i) and
    eps_j - eps_i, over the actual segments (length L, displacement in frame i)."""
    rng = random.Random(seed)
    sx, sy, st = (math.sqrt(v) for v in var)
    tsum = rsum = 0.0
    count = 0
    for length, dx, dy in segments:
        for _ in range(n_per):
            ex = rng.gauss(0, sx) * math.sqrt(2)
            ey = rng.gauss(0, sy) * math.sqrt(2)
            ei, ej = rng.gauss(0, st), rng.gauss(0, st)
            # A heading error at i turns the whole segment: displacement cross-product term.
            ex += -ei * dy
            ey += ei * dx
            tsum += 100 * math.hypot(ex, ey) / length
            rsum += math.degrees(abs(ej - ei))
            count += 1
    return tsum / count, rsum / count


def write_perturbed(rows, e, path, sxy, sth, seed):
    """Writes estimate e of rows as TUM with white noise (sxy m per axis, sth rad) added."""
    rng = random.Random(seed)
    with open(path, "w") as f:
        for r in rows:
            t, x, y, th = r[e]
            th += rng.gauss(0, sth)
            f.write("%.9f %.9f %.9f 0 0 0 %.12f %.12f\n" % (
                t, x + rng.gauss(0, sxy), y + rng.gauss(0, sxy), math.sin(th / 2), math.cos(th / 2)))


def crispness(binary, log, path):
    out = subprocess.run([binary, "eval", "crispness", log, path, "--min-gap", "1", "--max-gap",
                          "10", "--max-range", "20", "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)["mean_m"]


def main():
    args = sys.argv[1:]
    crisp_args = None
    if "--crispness" in args:
        k = args.index("--crispness")
        crisp_args = args[k + 1:k + 3]
        del args[k:k + 3]
    opts = take_options(args, {"--delta": 1.0, "--block": 20, "--resamples": 400, "--seed": 1})
    if len(args) not in (4, 5):
        print(__doc__, file=sys.stderr)
        return 2
    trajs = [load(p) for p in args]
    rows = [poses for _, poses in matched(trajs)]
    n = len(rows)
    if n < 50:
        print("reference_noise.py: fewer than 50 matched poses", file=sys.stderr)
        return 1
    A, P, B, C = 0, 1, 2, 3
    rng = random.Random(opts["--seed"])

    # 1. Jitter: world-aligned consecutive steps (A's heading rotates every estimate's step).
    def world_step(k, e):
        m = relative(rows[k][e], rows[k + 1][e])
        c, s = math.cos(rows[k][A][3]), math.sin(rows[k][A][3])
        return (c * m[0] - s * m[1], s * m[0] + c * m[1], m[2])

    steps = {e: [world_step(k, e) for k in range(n - 1)] for e in (A, P, B, C)}
    step_idx = list(range(n - 1))
    lag2 = lag_cov(steps[A], steps[B], step_idx, 2)
    odo_var = [rvar([steps[A][k][c] - steps[C][k][c] for k in step_idx]) for c in range(3)]
    odo_lag1 = lag_cov(steps[A], steps[C], step_idx)

    # 2. Segments of DELTA metres along A.
    dist = [0.0]
    for a, b in zip(rows, rows[1:]):
        dist.append(dist[-1] + math.hypot(b[A][1] - a[A][1], b[A][2] - a[A][2]))
    diffs = {"AB": [], "AC": [], "BC": [], "AP": []}
    segments = []
    for i in range(n):
        j = bisect.bisect_left(dist, dist[i] + opts["--delta"])
        if j >= n:
            break
        length = dist[j] - dist[i]
        m = {e: relative(rows[i][e], rows[j][e]) for e in (A, P, B, C)}
        segments.append((length, m[A][0], m[A][1]))
        for key, (u, v) in {"AB": (A, B), "AC": (A, C), "BC": (B, C), "AP": (A, P)}.items():
            diffs[key].append((100 * (m[u][0] - m[v][0]) / length,
                               100 * (m[u][1] - m[v][1]) / length,
                               math.degrees(math.remainder(m[u][2] - m[v][2], 2 * math.pi))))
    nseg = len(segments)
    if nseg < 20:
        print("reference_noise.py: fewer than 20 segments of %g m" % opts["--delta"],
              file=sys.stderr)
        return 1
    seg_idx = list(range(nseg))

    def estimates(sidx, tidx):
        h = hat(diffs, sidx)
        ap = [rvar([diffs["AP"][i][c] for i in sidx]) for c in range(3)]
        own = [max(0.0, ap[c] - h["A"][c]) for c in range(3)]
        jv = jitter(steps[A], steps[B], tidx)
        segs = [segments[i] for i in sidx]
        return {
            "hat_floor": floor_from_segment_var(h["A"], n=4000),
            "jitter_floor": floor_from_jitter(jv, segs, n_per=4),
            "own": floor_from_segment_var(own, n=4000),
            "jitter_sigma_cm": 100 * math.sqrt((jv[0] + jv[1]) / 2),
            "jitter_sigma_deg": math.degrees(math.sqrt(jv[2])),
        }

    point = estimates(seg_idx, step_idx)
    point_jv = jitter(steps[A], steps[B], step_idx)
    boot = []
    for _ in range(opts["--resamples"]):
        boot.append(estimates(block_indices(nseg, opts["--block"], rng),
                              block_indices(n - 1, opts["--block"], rng)))

    def ci(getter):
        vals = [getter(b) for b in boot]
        return [percentile(vals, 0.025), percentile(vals, 0.975)]

    # Vote on the steps where ours and the reference disagree by more than 5 cm.
    vote = {"steps": 0, "odometry_sides_with_ours": 0, "odometry_sides_with_reference": 0}
    for k in range(n - 1):
        m = [relative(rows[k][e], rows[k + 1][e]) for e in (A, P, C)]
        d_pa = math.hypot(m[1][0] - m[0][0], m[1][1] - m[0][1])
        if d_pa <= 0.05:
            continue
        vote["steps"] += 1
        if math.hypot(m[2][0] - m[1][0], m[2][1] - m[1][1]) < d_pa / 2:
            vote["odometry_sides_with_ours"] += 1
        if math.hypot(m[2][0] - m[0][0], m[2][1] - m[0][1]) < d_pa / 2:
            vote["odometry_sides_with_reference"] += 1

    # Measured error of ours against A, for comparison (mean, as `plugslam eval rpe`).
    measured_t = sum(math.hypot(d[0], d[1]) for d in diffs["AP"]) / nseg
    measured_r = sum(abs(d[2]) for d in diffs["AP"]) / nseg
    h = hat(diffs, seg_idx)
    out = {
        "delta_m": opts["--delta"],
        "poses": n,
        "segments": nseg,
        "block": opts["--block"],
        "resamples": opts["--resamples"],
        "measured": {"translation_pct_mean": measured_t, "rotation_deg_mean": measured_r},
        "jitter": {
            "combined_sigma_cm": point["jitter_sigma_cm"],
            "combined_sigma_cm_ci": ci(lambda b: b["jitter_sigma_cm"]),
            "combined_sigma_deg": point["jitter_sigma_deg"],
            "combined_sigma_deg_ci": ci(lambda b: b["jitter_sigma_deg"]),
            "lag2_over_lag1": [lag2[c] / min(-1e-300, -point_jv[c]) for c in range(3)],
            "odometry_lag1_correlation": [odo_lag1[c] / odo_var[c] for c in range(3)],
            "translation_pct_mean": point["jitter_floor"][0],
            "translation_pct_ci": ci(lambda b: b["jitter_floor"][0]),
            "rotation_deg_mean": point["jitter_floor"][1],
            "rotation_deg_ci": ci(lambda b: b["jitter_floor"][1]),
        },
        "hat": {
            "sigma_pct_deg": {k: [math.sqrt(v) for v in h[k]] for k in h},
            "floor_translation_pct_mean": point["hat_floor"][0],
            "floor_translation_pct_ci": ci(lambda b: b["hat_floor"][0]),
            "floor_rotation_deg_mean": point["hat_floor"][1],
            "floor_rotation_deg_ci": ci(lambda b: b["hat_floor"][1]),
        },
        "vote": vote,
        "own": {
            "translation_pct_mean": point["own"][0],
            "translation_pct_ci": ci(lambda b: b["own"][0]),
            "rotation_deg_mean": point["own"][1],
            "rotation_deg_ci": ci(lambda b: b["own"][1]),
        },
    }
    if len(trajs) == 5:
        # How much the laser-only estimate depends on its starting guess (odometry vs reference).
        by = {round(p[0], 6): p for p in trajs[4]}
        d = []
        for i in range(nseg):
            j = bisect.bisect_left(dist, dist[i] + opts["--delta"])
            bi, bj = rows[i][B], rows[j][B]
            gi, gj = by.get(round(bi[0], 6)), by.get(round(bj[0], 6))
            if not gi or not gj:
                continue
            m1, m2 = relative(bi, bj), relative(gi, gj)
            d.append(100 * math.hypot(m1[0] - m2[0], m1[1] - m2[1]) / segments[i][0])
        d.sort()
        out["guess_dependence"] = {"median_pct": d[len(d) // 2],
                                   "mean_pct": sum(d) / len(d),
                                   "fraction_below_0.1_pct": sum(x < 0.1 for x in d) / len(d)}
    if crisp_args:
        binary, log = crisp_args
        with tempfile.TemporaryDirectory() as tmp:
            # The reference and our estimate as matched here (same poses, same file format).
            write_perturbed(rows, A, os.path.join(tmp, "a.tum"), 0, 0, 0)
            c_ref = crispness(binary, log, os.path.join(tmp, "a.tum"))
            curve = []
            for scale in (0.0, 0.5, 1.0, 1.5, 2.0):
                vals = []
                for seed in ((0,) if scale == 0 else (1, 2)):
                    path = os.path.join(tmp, "p.tum")
                    write_perturbed(rows, P, path, scale * math.sqrt((point_jv[0] + point_jv[1]) / 2),
                                    scale * math.sqrt(point_jv[2]), seed)
                    vals.append(crispness(binary, log, path))
                curve.append((scale, sum(vals) / len(vals)))
        s_eq = None
        for (s0, c0), (s1, c1) in zip(curve, curve[1:]):
            if c0 <= c_ref <= c1 and c1 > c0:
                s_eq = s0 + (s1 - s0) * (c_ref - c0) / (c1 - c0)
                break
        if s_eq is None:
            s_eq = 0.0 if c_ref < curve[0][1] else float("inf")
        combined = point["jitter_sigma_cm"]
        share = min(1.0, math.sqrt((1 + min(s_eq, 1.0) ** 2) / 2))
        out["crispness_calibration"] = {
            "reference_mm": 1000 * c_ref,
            "ours_plus_noise_mm": [[sc, 1000 * c] for sc, c in curve],
            "s_eq": s_eq,
            "reference_share_of_jitter_sigma": share,
            "reference_jitter_sigma_cm": share * combined,
            "reference_jitter_sigma_deg": share * point["jitter_sigma_deg"],
        }
        segs = [segments[i] for i in seg_idx]
        ref_var = [share * share * v for v in point_jv]
        t, r = floor_from_jitter(ref_var, segs, n_per=20)
        out["crispness_calibration"]["reference_jitter_translation_pct_mean"] = t
        out["crispness_calibration"]["reference_jitter_rotation_deg_mean"] = r
    boot_hat = [b["hat_floor"][0] for b in boot]
    out["hat"]["probability_floor_below_2_pct"] = sum(v < 2.0 for v in boot_hat) / len(boot_hat)
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
