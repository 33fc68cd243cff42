#!/usr/bin/env python3
# Which loop edges of a run are wrong: each local map of graph.g2o is matched to the scan whose
# final pose it is (its origin), and each loop edge is compared with the reference's relative pose
# of those two scans. Usage: loop_errors.py RUN_DIR [-e] [-a] (with graph.g2o, trajectory.tum
# and reference.tum, one pose per scan; run with outputs TrajectoryWriter tum and sdk.GraphWriter);
# -e sorts by error (else by query map), -a lists every wrong loop (else the first 25).
import sys, math
from tum2d import load, relative
d = sys.argv[1]
T = [p[1:] for p in load(d+'/trajectory.tum')]; R = load(d+'/reference.tum')
V = {}; E = []
for l in open(d+'/graph.g2o'):
    f = l.split()
    if f[0] == 'VERTEX_SE2': V[int(f[1])] = tuple(map(float, f[2:5]))
    elif f[0] == 'EDGE_SE2': E.append((int(f[1]), int(f[2]), *map(float, f[3:6])))
scan = {}
for k, (vx, vy, vt) in V.items():
    best = min(range(len(T)), key=lambda i: (T[i][0]-vx)**2 + (T[i][1]-vy)**2 + math.remainder(T[i][2]-vt, 2*math.pi)**2)
    scan[k] = best
bad = []; n = 0
for a, b, mx, my, mt in E:
    if b - a == 1: continue
    n += 1
    i, j = scan[a], scan[b]
    r = relative(R[i], R[j]); e = math.hypot(r[0]-mx, r[1]-my)
    if e > 0.5: bad.append((e, a, b, i, j))
bad.sort(key=lambda z: -z[0] if "-e" in sys.argv else z[1])
print(f"{n} loop edges in the final graph, {len(bad)} off by > 0.5 m from the reference (by query map):")
for e, a, b, i, j in (bad if "-a" in sys.argv else bad[:25]): print(f"  maps {a}->{b} scans {i}->{j} error {e:.2f} m")
