#!/usr/bin/env bash
# Merging sessions (issue 45): `plugslam merge` on sessions whose relative pose it is not told.
#  1. A real log cut in two halves, the second re-based to start at its own origin, each mapped
#     alone with configs/laser2d_carmen.yaml, then merged; scored with the Freiburg benchmark's
#     relations (all, and those spanning the two halves) beside one run over the whole log. Each
#     link across the halves is judged against the one run's trajectory (the log has no ground
#     truth; that run's relation error is ~1 cm): wrong when off by more than 0.5 m or 5 deg.
#  2. The simulated office toured twice from starts 4.75 m apart (configs/sim2d_single_laser.yaml,
#     stage-0 and stage-1, two seeds), merged: both trajectories against ground truth with one
#     alignment (found on the first).
#  3. Two buildings (a half of the log above and another benchmark log): must not merge.
#  4. Localization from 20 random starts in the one run's session (--start-anywhere).
# Writes the table into docs/benchmarks.md (section merge); PLUGSLAM_BENCH_NO_DOC=1 prints it.
set -euo pipefail
. "$(dirname "$0")/common.sh" merge
need_data laser2d/intel-kuemmerle-benchmark
need_data laser2d/fr079-kuemmerle-benchmark
laser="$root/configs/laser2d_carmen.yaml"
office="$root/configs/sim2d_single_laser.yaml"
rm -rf "$out"
mkdir -p "$out"
log="$data/laser2d/intel-kuemmerle-benchmark/intel.clf.bz2"
rel="$data/laser2d/intel-kuemmerle-benchmark/intel.relations"
other="$data/laser2d/fr079-kuemmerle-benchmark/fr079.clf.bz2"

run() {  # run NAME CONFIG [--set ...]: a run into $out/NAME, timed
  local name=$1 cfg=$2
  shift 2
  echo "$name ..." >&2
  /usr/bin/time -f "%e" -o "$out/$name.time" "$bin" run "$cfg" -q -o "$out/$name" "$@" \
    > "$out/$name.stdout" 2> "$out/$name.stderr"
}
merge() {  # merge NAME SESSION...: exit status kept in $out/NAME.status
  local name=$1
  shift
  echo "merge $name ..." >&2
  set +e
  /usr/bin/time -f "%e" -o "$out/$name.time" "$bin" merge "$@" -o "$out/$name" \
    > "$out/$name.stdout" 2> "$out/$name.stderr"
  echo $? > "$out/$name.status"
  set -e
}

# 1. The log's halves: split at the middle laser line; the second half's odometry (ODOM lines and
# the odometry in laser lines) re-based to start at the identity.
bzcat "$log" > "$out/whole.clf"
python3 - "$out/whole.clf" "$out/half1.clf" "$out/half2.clf" <<'EOF'
import math, sys
src, a_out, b_out = sys.argv[1:4]
lines = open(src).read().splitlines()
scans = [i for i, l in enumerate(lines) if l.startswith(("FLASER", "ROBOTLASER1"))]
cut = scans[len(scans) // 2]
origin = None
def rebase(x, y, t):
    ox, oy, ot = origin
    c, s = math.cos(-ot), math.sin(-ot)
    return (c * (x - ox) - s * (y - oy), s * (x - ox) + c * (y - oy),
            math.atan2(math.sin(t - ot), math.cos(t - ot)))
second = []
for l in lines[cut:]:
    f = l.split()
    if f and f[0] == "ODOM":
        if origin is None: origin = tuple(map(float, f[1:4]))
        f[1:4] = ["%.6f" % v for v in rebase(*map(float, f[1:4]))]
    elif f and f[0] == "FLASER":
        k = 2 + int(f[1])
        if origin is None: origin = tuple(map(float, f[k + 3:k + 6]))
        for j in (k, k + 3):
            f[j:j + 3] = ["%.6f" % v for v in rebase(*map(float, f[j:j + 3]))]
    second.append(" ".join(f))
header = [l for l in lines[:cut] if l.startswith(("#", "PARAM"))]
open(a_out, "w").write("\n".join(lines[:cut]) + "\n")
open(b_out, "w").write("\n".join(header + second) + "\n")
EOF
run whole "$laser" --set "source.path=$out/whole.clf"
run half1 "$laser" --set "source.path=$out/half1.clf"
run half2 "$laser" --set "source.path=$out/half2.clf"
merge halves "$out/half1/session" "$out/half2/session"
for r in whole halves; do
  "$bin" eval relations "$out/$r/trajectory.tum" --relations "$rel" --format json -o "$out/$r.relations.json"
done

# 2. The office, two robots.
run office0 "$office" --set source.session=stage-0 --set source.seed=0
run office1 "$office" --set source.session=stage-1 --set source.seed=1
merge office "$out/office0/session" "$out/office1/session"

# 3. Two buildings.
run other "$laser" --set "source.path=$other"
merge buildings "$out/half1/session" "$out/other/session"

# 4. Localization from 20 random starts in the one run's session: 300 scans of the log from a
# random laser line each (seeded), localized with --start-anywhere.
python3 - "$out/whole.clf" "$out" <<'EOF2'
import random, sys
src, out = sys.argv[1:3]
lines = open(src).read().splitlines()
scans = [i for i, l in enumerate(lines) if l.startswith(("FLASER", "ROBOTLASER1"))]
header = [l for l in lines[:scans[0]] if l.startswith(("#", "PARAM"))]
rng = random.Random(45)
for k in range(20):
    s = rng.randrange(0, len(scans) - 301)
    open(f"{out}/start{k:02d}.clf", "w").write("\n".join(header + lines[scans[s]:scans[s + 300]]) + "\n")
EOF2
for k in $(seq -w 0 19); do
  run "localize$k" "$laser" --set "source.path=$out/start$k.clf" --session "$out/whole/session" \
    --localize --start-anywhere
done

table=$(python3 - "$out" "$rel" <<'EOF'
import bisect, json, math, pathlib, sys
out, rel_file = pathlib.Path(sys.argv[1]), sys.argv[2]

def tum(path):
    poses = []
    for l in open(path):
        if l.startswith("#") or not l.strip(): continue
        t, x, y, z, qx, qy, qz, qw = map(float, l.split())
        poses.append((t, x, y, 2 * math.atan2(qz, qw)))
    poses.sort()
    return poses

def at(poses, stamps, t, tol=1e-6):
    i = bisect.bisect_left(stamps, t - tol)
    return poses[i] if i < len(poses) and abs(stamps[i] - t) <= tol else None

def between(a, b):  # b in a's frame (x, y, theta)
    c, s = math.cos(a[3]), math.sin(a[3])
    dx, dy = b[1] - a[1], b[2] - a[2]
    return (c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(b[3] - a[3]), math.cos(b[3] - a[3])))

def compose_inv(r, m):  # r^-1 * m
    c, s = math.cos(r[2]), math.sin(r[2])
    dx, dy = m[0] - r[0], m[1] - r[1]
    return (c * dx + s * dy, -s * dx + c * dy, math.atan2(math.sin(m[2] - r[2]), math.cos(m[2] - r[2])))

def se2_align(ref, est):  # x -> R x + t mapping est points onto ref points (least squares)
    n = len(ref)
    mr = [sum(p[i] for p in ref) / n for i in (0, 1)]
    me = [sum(p[i] for p in est) / n for i in (0, 1)]
    sxx = sum((e[0] - me[0]) * (r[0] - mr[0]) + (e[1] - me[1]) * (r[1] - mr[1]) for r, e in zip(ref, est))
    sxy = sum((e[0] - me[0]) * (r[1] - mr[1]) - (e[1] - me[1]) * (r[0] - mr[0]) for r, e in zip(ref, est))
    th = math.atan2(sxy, sxx)
    c, s = math.cos(th), math.sin(th)
    return th, (mr[0] - (c * me[0] - s * me[1]), mr[1] - (s * me[0] + c * me[1]))

def ate(ref, est, align=None):
    rs = [p[0] for p in ref]
    pairs = [(at(ref, rs, p[0], 1e-3), p) for p in est]
    pairs = [(r, e) for r, e in pairs if r]
    if align is None:
        align = se2_align([(r[1], r[2]) for r, _ in pairs], [(e[1], e[2]) for _, e in pairs])
    th, (tx, ty) = align
    c, s = math.cos(th), math.sin(th)
    err = [math.hypot(r[1] - (c * e[1] - s * e[2] + tx), r[2] - (s * e[1] + c * e[2] + ty)) for r, e in pairs]
    return math.sqrt(sum(x * x for x in err) / len(err)), align

def seconds(name):
    return float((out / f"{name}.time").read_text().split()[-1])

rows = []
# 1. Halves.
half1_end = max(p[0] for p in tum(out / "half1" / "trajectory.tum"))
relations = [tuple(map(float, l.split()[1:9] if l.startswith("EDGE") else l.split()[:8]))
             for l in open(rel_file) if l.strip() and not l.startswith("#")]
def crossing_error(path):
    poses = tum(path)
    stamps = [p[0] for p in poses]
    errs = []
    for t1, t2, x, y, z, roll, pitch, yaw in relations:
        if (t1 <= half1_end) == (t2 <= half1_end): continue
        a, b = at(poses, stamps, t1), at(poses, stamps, t2)
        if not a or not b: continue
        e = compose_inv((x, y, yaw), between(a, b))
        errs.append(math.hypot(e[0], e[1]))
    return (sum(errs) / len(errs) if errs else float("nan")), len(errs)
whole = json.loads((out / "whole.relations.json").read_text())
halves = json.loads((out / "halves.relations.json").read_text())
mj = json.loads((out / "halves" / "merge.json").read_text())
ref = tum(out / "whole" / "trajectory.tum")
rs = [p[0] for p in ref]
wrong, worst_t, worst_r, judged = 0, 0.0, 0.0, 0
for l in mj["link_list"]:
    a, b = at(ref, rs, l["from_stamp"]), at(ref, rs, l["to_stamp"])
    if not a or not b: continue
    x, y, z, qx, qy, qz, qw = l["relative"]
    e = compose_inv((x, y, 2 * math.atan2(qz, qw)), between(a, b))
    et, er = math.hypot(e[0], e[1]), abs(math.degrees(e[2]))
    judged += 1
    worst_t, worst_r = max(worst_t, et), max(worst_r, er)
    wrong += et > 0.5 or er > 5
cw, nw = crossing_error(out / "whole" / "trajectory.tum")
ch, nh = crossing_error(out / "halves" / "trajectory.tum")
ratio = halves["translation_m"]["mean"] / whole["translation_m"]["mean"]
rows.append(f"| log in two halves, merged | {halves['used']} / {halves['relations']} relations: "
            f"{halves['translation_m']['mean']:.4f} m ({ratio:.2f}x one run); the {nh} spanning the halves: "
            f"{ch:.4f} m | {mj['links']} links, {wrong} wrong of {judged} judged (worst {worst_t:.3f} m, "
            f"{worst_r:.2f} deg) | {seconds('halves'):.1f} |")
rows.append(f"| the same log, one run | {whole['used']} / {whole['relations']} relations: "
            f"{whole['translation_m']['mean']:.4f} m; spanning the halves: {cw:.4f} m | | {seconds('whole'):.1f} |")
# 2. Office.
oj = json.loads((out / "office" / "merge.json").read_text())
r0, r1 = tum(out / "office0" / "reference.tum"), tum(out / "office1" / "reference.tum")
a0, align = ate(r0, tum(out / "office" / "trajectory_1.tum"))
a1, _ = ate(r1, tum(out / "office" / "trajectory_2.tum"), align)
alone, _ = ate(r1, tum(out / "office1" / "trajectory.tum"), align)
rows.append(f"| office, two robots from starts 4.75 m apart | ATE in one frame: {a0:.4f} m and {a1:.4f} m "
            f"(the second unmerged: {alone:.2f} m) | {oj['links']} links | {seconds('office'):.1f} |")
# 3. Two buildings.
status = int((out / "buildings.status").read_text())
bj = out / "buildings" / "merge.json"
rows.append(f"| two buildings (log half + another log) | "
            f"{'not merged (exit ' + str(status) + ')' if status != 0 else 'MERGED: wrong'} | "
            f"{json.loads(bj.read_text())['links'] if bj.exists() else 0} links | {seconds('buildings'):.1f} |")
# 4. Localization from random starts: frames to lock on, then the error against the one run.
locked, wrong, frames, errs = 0, 0, [], []
for k in range(20):
    d = out / f"localize{k:02d}"
    rj = json.loads((d / "run.json").read_text())
    n = rj["locked_on_after_frames"]
    if n < 0:
        continue
    locked += 1
    frames.append(n)
    est = tum(d / "trajectory.tum")
    after = est[n:]
    e = [math.hypot(p[1] - r[1], p[2] - r[2]) for p in after for r in [at(ref, rs, p[0])] if r]
    if e:
        errs.append(sum(x * x for x in e) / len(e))
        wrong += max(e) > 0.5
frames.sort()
rows.append(f"| localization from 20 random starts (300 scans each) | locked on: {locked} of 20, "
            f"{sum(n <= 20 for n in frames)} within 20 frames; "
            f"after {frames[len(frames) // 2] if frames else 'n/a'} frames (median; max "
            f"{max(frames) if frames else 'n/a'}); {wrong} wrong lock-ons (>0.5 m); RMSE after "
            f"lock-on {math.sqrt(sum(errs) / len(errs)) if errs else float('nan'):.3f} m | | "
            f"{sum(seconds(f'localize{k:02d}') for k in range(20)) / 20:.1f} per run |")
print("\n".join(rows))
EOF
)

machine=$("$here/machine_info.sh")
doc=$(cat <<EOF
## Merging sessions (issue 45)

$machine
Command: \`scripts/bench/merge.sh\`. Each session is a run of a shipped config
(configs/laser2d_carmen.yaml, configs/sim2d_single_laser.yaml) saved by \`plugslam run\`; \`plugslam
merge\` is told nothing of their relative pose: laser2d.PlaceRecognizer joins them. The log is the
Freiburg benchmark's intel log cut at its middle laser line, the second half re-based to start at
its own origin; relations: the benchmark's, mean translational error (\`plugslam eval relations\`).
A link is judged against the one run's trajectory (the log has no ground truth): wrong when off
by more than 0.5 m or 5 deg. Seconds: wall time of the merge (or of the one run).
Localization: 300 scans of the log from each of 20 random laser lines (seeded), \`plugslam run
--session whole --localize --start-anywhere\`; frames before lock-on from run.json, the error after
it against the one run's poses at the same stamps (a lock-on is wrong when any is off by > 0.5 m).

| case | accuracy | links | seconds |
|---|---|---|---|
$table
EOF
)
if [ -n "${PLUGSLAM_BENCH_NO_DOC:-}" ]; then
  echo "$doc"
else
  echo "$doc" | python3 "$here/update_section.py" merge "$root/docs/benchmarks.md"
  echo "table written into docs/benchmarks.md (section merge)" >&2
fi
