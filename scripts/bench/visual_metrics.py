#!/usr/bin/env python3
"""Trajectory figures of the visual bench, from TUM files (reference, estimate), pure Python.

  visual_metrics.py kitti REF EST    KITTI devkit drift: mean translation error [%] and rotation
                                     error [deg/100 m] over every segment of 100, 200, ..., 800 m
                                     starting every 10 frames (the devkit's evaluate_odometry)
  visual_metrics.py f2f REF EST [PEER TIMES]
                                     frame-to-frame errors: translation [% of the step], rotation
                                     [deg per frame], as mean and max; with PEER (KITTI poses of
                                     another system, one a frame) and TIMES (the frames' stamps),
                                     also against that system's estimate (peer_* keys)
  visual_metrics.py static REF EST   the largest departure of the estimate from its first pose
                                     [m, deg] over every frame of the estimate, and the
                                     reference's own over its rows (it may start later)
  visual_metrics.py rpe1 REF EST     frame-to-frame error of consecutive frames (RPE, delta one
                                     frame): translation [m] and rotation [deg], RMSE and max
  visual_metrics.py loops RUN_DIR [RADIUS [TRAVEL]]
                                     the loop edges of RUN_DIR/graph.g2o against the reference
                                     (each map matched to the frame whose pose is its origin in
                                     trajectory.tum): count, worst error [m, deg], how many are off
                                     by > 0.5 m or 2 deg; and the returns to an earlier place, from
                                     the reference alone (a map within RADIUS m, default 10, of an
                                     earlier map more than TRAVEL m of path back, default 50), each
                                     with whether a loop edge ends in it
  visual_metrics.py stages RUN_JSON  per frame: keypoints, with depth, matched landmarks,
                                     landmarks in the local map, and the time per stage [ms]
                                     (run.json statistics, each stage summed over its modules)
  visual_metrics.py steps2d REF EST  frame to frame in the plane: RMS of each step's (x, y) and
                                     heading error against the reference, and the heading errors
                                     summed over the run (a bias's drift) [mm, mrad, deg]
  visual_metrics.py depth < CHECK    the worst step of build/bin/rgbd_depth_check's output
                                     (against the motion the depth images give) [mm, deg]
Prints one JSON object. Poses are associated by equal timestamps (both files come from one run).
"""
import bisect
import json
import math
import sys


def quat_to_matrix(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def read_kitti(path, times_path):
    poses = {}
    times = [float(line.split()[0]) for line in open(times_path) if line.strip()]
    for t, line in zip(times, open(path)):
        v = list(map(float, line.split()))
        if len(v) != 12:
            continue
        poses[round(t, 6)] = ([v[0:3], v[4:7], v[8:11]], [v[3], v[7], v[11]])
    return poses


def read_tum(path):
    poses = {}
    for line in open(path):
        f = line.split()
        if not f or f[0].startswith('#'):
            continue
        t, x, y, z, qx, qy, qz, qw = map(float, f[:8])
        poses[round(t, 6)] = (quat_to_matrix(qx, qy, qz, qw), [x, y, z])
    return poses


def inverse(p):
    r, t = p
    rt = [[r[j][i] for j in range(3)] for i in range(3)]
    return rt, [-sum(rt[i][k] * t[k] for k in range(3)) for i in range(3)]


def compose(a, b):
    ra, ta = a
    rb, tb = b
    r = [[sum(ra[i][k] * rb[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    t = [sum(ra[i][k] * tb[k] for k in range(3)) + ta[i] for i in range(3)]
    return r, t


def relative(a, b):
    return compose(inverse(a), b)


def angle(p):
    r = p[0]
    c = (r[0][0] + r[1][1] + r[2][2] - 1) / 2
    return math.acos(max(-1.0, min(1.0, c)))


def norm(p):
    return math.sqrt(sum(v * v for v in p[1]))


def associated(ref_path, est_path):
    ref, est = read_tum(ref_path), read_tum(est_path)
    stamps = sorted(set(ref) & set(est))
    if len(stamps) < 2:
        sys.exit(f"visual_metrics: {ref_path} and {est_path} share fewer than 2 timestamps")
    return [ref[s] for s in stamps], [est[s] for s in stamps]


def kitti(gt, est):
    dist = [0.0]
    for i in range(1, len(gt)):
        dist.append(dist[-1] + math.dist(gt[i][1], gt[i - 1][1]))
    t_err, r_err = [], []
    for first in range(0, len(gt), 10):
        for length in range(100, 900, 100):
            last = bisect.bisect_right(dist, dist[first] + length, lo=first)
            if last >= len(gt):
                continue
            err = relative(relative(est[first], est[last]), relative(gt[first], gt[last]))
            t_err.append(norm(err) / length)
            r_err.append(angle(err) / length)
    if not t_err:
        return {"segments": 0, "length_m": dist[-1]}
    return {"segments": len(t_err), "length_m": dist[-1],
            "translation_percent": 100 * sum(t_err) / len(t_err),
            "rotation_deg_per_100m": 100 * math.degrees(sum(r_err) / len(r_err))}


def f2f(gt, est):
    t, r = [], []
    for i in range(1, len(gt)):
        g, e = relative(gt[i - 1], gt[i]), relative(est[i - 1], est[i])
        err = relative(e, g)
        step = norm(g)
        if step > 1e-6:
            t.append(100 * norm(err) / step)
        r.append(math.degrees(angle(err)))
    return {"frames": len(gt), "translation_percent_mean": sum(t) / max(1, len(t)),
            "translation_percent_max": max(t, default=0.0),
            "steps_over_5_percent": sum(1 for x in t if x > 5.0),
            "rotation_deg_mean": sum(r) / max(1, len(r)), "rotation_deg_max": max(r, default=0.0)}


def rpe1(gt, est):
    # Frame-to-frame error of consecutive frames (RPE with delta = 1 frame), RMSE and max.
    t, r = [], []
    for i in range(1, len(gt)):
        err = relative(relative(est[i - 1], est[i]), relative(gt[i - 1], gt[i]))
        t.append(norm(err))
        r.append(math.degrees(angle(err)))
    def rmse(v):
        return math.sqrt(sum(x * x for x in v) / max(1, len(v)))
    return {"pairs": len(t), "translation_rmse_m": rmse(t), "translation_max_m": max(t, default=0.0),
            "rotation_rmse_deg": rmse(r), "rotation_max_deg": max(r, default=0.0)}


def static(gt, est):
    return {"frames": len(est),
            "estimate_max_m": max(norm(relative(est[0], e)) for e in est),
            "estimate_max_deg": max(math.degrees(angle(relative(est[0], e))) for e in est),
            "reference_max_m": max(norm(relative(gt[0], g)) for g in gt),
            "reference_max_deg": max(math.degrees(angle(relative(gt[0], g))) for g in gt)}


def read_graph(path):
    nodes, edges = {}, []
    for line in open(path):
        f = line.split()
        if f and f[0] == "VERTEX_SE3:QUAT":
            v = list(map(float, f[2:9]))
            nodes[int(f[1])] = (quat_to_matrix(*v[3:7]), v[0:3])
        elif f and f[0] == "EDGE_SE3:QUAT":
            v = list(map(float, f[3:10]))
            edges.append((int(f[1]), int(f[2]), (quat_to_matrix(*v[3:7]), v[0:3])))
    return nodes, edges


def loops(run, radius=10.0, travel=50.0):
    gt, est = associated(run + "/reference.tum", run + "/trajectory.tum")
    nodes, edges = read_graph(run + "/graph.g2o")
    # A map's origin is the pose of the frame that opened it, so it is that frame's corrected pose.
    frame = {k: min(range(len(est)), key=lambda i: math.dist(est[i][1], p[1])) for k, p in nodes.items()}
    path = [0.0]
    for i in range(1, len(gt)):
        path.append(path[-1] + math.dist(gt[i][1], gt[i - 1][1]))
    closed, errors = set(), []
    for a, b, rel in edges:
        if abs(b - a) == 1:
            continue
        err = relative(relative(gt[frame[a]], gt[frame[b]]), rel)
        errors.append((norm(err), math.degrees(angle(err)), a, b))
        closed.update((a, b))
    ids = sorted(nodes)
    revisit = {}
    for j in ids:
        near = [i for i in ids if i < j and path[frame[j]] - path[frame[i]] > travel
                and math.dist(gt[frame[i]][1], gt[frame[j]][1]) <= radius]
        if near:
            revisit[j] = near
    returns, run_maps = [], []
    for j in ids + [None]:
        if j is not None and j in revisit and (not run_maps or j == run_maps[-1] + 1):
            run_maps.append(j)
            continue
        if run_maps:
            earlier = sorted({i for m in run_maps for i in revisit[m]})
            # The viewing direction decides what a camera can recognise: a return driven the
            # other way sees the other side of the landmarks.
            heading = min(math.degrees(angle(relative(gt[frame[m]], gt[frame[i]])))
                          for m in run_maps for i in revisit[m])
            returns.append({"maps": [run_maps[0], run_maps[-1]], "earlier": [earlier[0], earlier[-1]],
                            "closest_m": min(math.dist(gt[frame[m]][1], gt[frame[i]][1])
                                             for m in run_maps for i in revisit[m]),
                            "heading_deg": heading,
                            "closed": any(m in closed for m in run_maps)})
        run_maps = [j] if j is not None and j in revisit else []
    wrong = [e for e in errors if e[0] > 0.5 or e[1] > 2.0]
    return {"loops": len(errors), "wrong": len(wrong),
            "worst_m": max((e[0] for e in errors), default=0.0),
            "worst_deg": max((e[1] for e in errors), default=0.0),
            "wrong_pairs": [[e[2], e[3], round(e[0], 3), round(e[1], 3)] for e in wrong[:20]],
            "returns": len(returns), "returns_closed": sum(r["closed"] for r in returns),
            "returns_opposite": sum(1 for r in returns if r["heading_deg"] > 90),
            "return_list": returns}


def steps2d(ref_path, est_path):
    """Frame to frame in the plane: each step's (x, y, heading) in the robot frame against the
    reference's; its RMS is the random part, its heading errors summed over the run the drift a
    bias leaves."""
    def load(p):
        return [list(map(float, l.split())) for l in open(p) if l.strip() and not l.startswith("#")]

    def yaw(q):
        return math.atan2(2 * (q[3] * q[2] + q[0] * q[1]), 1 - 2 * (q[1] ** 2 + q[2] ** 2))

    def step(a, b):
        t = yaw(a[4:8])
        dx, dy = b[1] - a[1], b[2] - a[2]
        return (math.cos(t) * dx + math.sin(t) * dy, -math.sin(t) * dx + math.cos(t) * dy,
                (yaw(b[4:8]) - t + math.pi) % (2 * math.pi) - math.pi)
    ref = {round(r[0], 6): r for r in load(ref_path)}
    est = [e for e in load(est_path) if round(e[0], 6) in ref]
    if len(est) < 2:
        sys.exit(f"visual_metrics: {est_path} shares fewer than two stamps with {ref_path}")
    e = []
    for a, b in zip(est, est[1:]):
        mine, truth = step(a, b), step(ref[round(a[0], 6)], ref[round(b[0], 6)])
        e.append([u - v for u, v in zip(mine, truth)])
    return {"steps": len(e),
            "translation_rms_mm": 1000 * math.sqrt(sum(x * x + y * y for x, y, _ in e) / len(e)),
            "heading_rms_mrad": 1000 * math.sqrt(sum(h * h for _, _, h in e) / len(e)),
            "heading_drift_deg": math.degrees(sum(h for _, _, h in e))}


def stages(run_json):
    r = json.load(open(run_json))
    stats = r.get("statistics", {})
    n = max(1, r["frames"])

    def first(key):
        return next((figures[key] for figures in stats.values() if key in figures), None)

    def ms(key):
        # Summed over the modules: each aligner slice times its own share of the alignment.
        v = [figures[key] for figures in stats.values() if key in figures]
        return 1e3 * sum(v) / n if v else None
    return {"keypoints": first("keypoints_per_frame"), "with_depth": first("with_depth_per_frame"),
            "matched": first("matched_per_frame"), "landmarks": first("landmarks_per_frame"),
            "extraction_ms": ms("extraction_s"), "matching_ms": ms("matching_s"),
            "alignment_ms": ms("alignment_s"), "merge_ms": ms("merge_s"),
            "pipeline_ms": 1e3 * r["pipeline_time_s"] / n,
            "unchecked": r.get("tracking_unchecked", 0)}


def depth(check):
    steps = [s for s in check["steps"] if "estimate_vs_depth_mm" in s]
    if not steps:
        sys.exit("visual_metrics: the depth check measured no step")
    return {"worst_mm": max(s["estimate_vs_depth_mm"] for s in steps),
            "worst_deg": max(s["estimate_vs_depth_deg"] for s in steps),
            "reference_off_max_mm": check["summary"]["reference_off_max_mm"]}


if __name__ == "__main__":
    if sys.argv[1:2] == ["stages"] and len(sys.argv) == 3:
        print(json.dumps(stages(sys.argv[2])))
        sys.exit(0)
    if sys.argv[1:2] == ["steps2d"] and len(sys.argv) == 4:
        print(json.dumps(steps2d(sys.argv[2], sys.argv[3])))
        sys.exit(0)
    if sys.argv[1:2] == ["depth"] and len(sys.argv) == 2:
        print(json.dumps(depth(json.load(sys.stdin))))
        sys.exit(0)
    if sys.argv[1:2] == ["loops"] and 3 <= len(sys.argv) <= 5:
        print(json.dumps(loops(sys.argv[2], *map(float, sys.argv[3:]))))
        sys.exit(0)
    if sys.argv[1:2] == ["f2f"] and len(sys.argv) == 6:
        gt, est = associated(sys.argv[2], sys.argv[3])
        out = f2f(gt, est)
        peer, mine = read_kitti(sys.argv[4], sys.argv[5]), read_tum(sys.argv[3])
        stamps = sorted(set(peer) & set(mine))
        if len(stamps) >= 2:
            p = f2f([peer[s] for s in stamps], [mine[s] for s in stamps])
            out.update({"peer_" + k: v for k, v in p.items()})
        print(json.dumps(out))
        sys.exit(0)
    if len(sys.argv) != 4 or sys.argv[1] not in ("kitti", "f2f", "static", "rpe1"):
        sys.exit(__doc__)
    if sys.argv[1] == "static":
        # Every estimated frame counts, also those before the reference's first row.
        ref, est = read_tum(sys.argv[2]), read_tum(sys.argv[3])
        if not ref or not est:
            sys.exit(f"visual_metrics: {sys.argv[2]} or {sys.argv[3]} has no pose")
        print(json.dumps(static([ref[s] for s in sorted(ref)], [est[s] for s in sorted(est)])))
        sys.exit(0)
    gt, est = associated(sys.argv[2], sys.argv[3])
    print(json.dumps({"kitti": kitti, "f2f": f2f, "static": static, "rpe1": rpe1}[sys.argv[1]](gt, est)))
