#!/usr/bin/env bash
# The sweep's scale targets (issue 44): planning 10,000 cases under 2 s, reporting them under 5 s.
# Plans 2 configs x 100 x 50 grid values (every config and every number's extremes are built, as
# a real plan does), plans again (a resume), gives every case a made-up result, and reports it
# (table, heat tables, plots). Prints the wall times; writes only under a temporary folder.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
bin="${PLUGSLAM_BIN:-$root/build/bin/plugslam}"
[ -x "$bin" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
python3 - <<'PY'
d = ", ".join(f"{0.1 + 0.01 * i:.2f}" for i in range(100))
a = ", ".join(f"{0.1 + 0.01 * i:.2f}" for i in range(50))
open("scale.sweep.yaml", "w").write(f"""config: [configs/sim2d_single_laser.yaml, configs/sim2d_double_laser.yaml]
grid:
  pipeline.tracker.splitter.distance: [{d}]
  pipeline.tracker.splitter.angle: [{a}]
metrics: [ate, hz, loops]
""")
PY
now() { date +%s.%N; }
t0=$(now); "$bin" -q sweep plan scale.sweep.yaml -o s > /dev/null; t1=$(now)
"$bin" -q sweep plan scale.sweep.yaml -o s > /dev/null; t2=$(now)
python3 - <<'PY'
import json, os, random
random.seed(1)
for c in json.load(open("s/plan.json"))["cases"]:
    m = {"ate": random.uniform(0.001, 0.01), "hz": random.uniform(200, 600), "loops": random.randint(50, 90)}
    with open(f"s/cases/{c['id']}/result.json", "w") as f:
        json.dump({"id": c["id"], "status": "ok", "exit_code": 0, "metrics": m}, f)
PY
t3=$(now); "$bin" -q sweep report s > /dev/null; t4=$(now)
"$bin" -q sweep report s --no-plots > /dev/null; t5=$(now)
python3 - "$t0" "$t1" "$t2" "$t3" "$t4" "$t5" <<'PY'
import sys
t = [float(x) for x in sys.argv[1:]]
print(f"plan 10000 cases:                 {t[1] - t[0]:.2f} s (target < 2 s)")
print(f"plan again (all case files kept): {t[2] - t[1]:.2f} s")
print(f"report 10000 results with plots:  {t[4] - t[3]:.2f} s (target < 5 s)")
print(f"report without plots:             {t[5] - t[4]:.2f} s")
PY
