#!/usr/bin/env bash
# sweep_engines_test.sh MODE SOURCE_DIR BUILD_DIR: `plugslam sweep` through real engines (issue 44).
#   local     sweep-file errors stop everything before a run; a small simulator sweep (2 configs x
#             2 datasets x 2 values) through --engine local -j2; a failing and a timed-out case are
#             recorded and reported, not fatal; a sweep killed midway (SIGKILL) and interrupted
#             (SIGINT) runs only the missing cases when started again and loses no result; a
#             second sweep on a folder in use is refused
#   slurm     the same sweep through a one-node Slurm cluster on localhost (scripts/slurm-local.sh)
#             gives the same table as --engine local; only missing cases are resubmitted; a
#             --no-wait job still running blocks a second submission
#   parallel  the same sweep through GNU parallel's local login (--hosts :) gives the same table
# Exit 77 (skipped) only when the engine's packages cannot be installed. Writes only under a fresh
# temporary folder, removed at the end.
set -euo pipefail
mode="$1"
src="$2"
build="$3"
bin="$build/bin/plugslam"
tmp="$(mktemp -d)"
cleanup() {
  [ "$mode" = slurm ] && "$src/scripts/slurm-local.sh" stop "$tmp/slurm" > /dev/null 2>&1 || true
  rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
cd "$tmp"

# The small sweep: a few hundred simulator frames per case, deterministic runs, so any two
# engines must give the same figures (all but the rates, which depend on the load).
cat > small.sweep.yaml <<'EOF'
config: [configs/sim2d_single_laser.yaml, configs/sim2d_double_laser.yaml]
datasets:
  office-a: {source.seed: 11, source.session: stage-0}
  office-b: {source.seed: 12, source.session: stage-0}
set: {max_frames: 200}
grid:
  pipeline.tracker.splitter.distance: [0.5, 1.0]
metrics: [ate, rpe, loops, tracking_failures, hz]
EOF
# The table without the rate columns: config, dataset, the swept value, runs, ok, failed, missing,
# then median/min/max of ate, rpe, loops and tracking_failures (19 columns); hz's three follow.
figures() { cut -d, -f1-19 "$1/report/table.csv"; }
# Starts the small sweep into folder $1 (-j 1, log ${1}1.log) in the background, its pid in
# $sweep, and returns once $2 of its cases have a result (or after 20 s).
start_sweep_until() {
  "$bin" -q sweep run small.sweep.yaml -o "$1" -j 1 > "${1}1.log" 2>&1 &
  sweep=$!
  for _ in $(seq 200); do
    [ "$(ls "$1"/cases/*/result.json 2>/dev/null | wc -l)" -ge "$2" ] && break
    sleep 0.1
  done
}

run_local() {
  "$bin" -q sweep run small.sweep.yaml -o "$1" --engine local -j 2 > "$1.log" 2>&1 \
    || fail "local sweep: $(cat "$1.log")"
  "$bin" -q sweep report "$1" > /dev/null || fail "report of $1"
  [ "$(tail -n +2 "$1/report/table.csv" | wc -l)" -eq 8 ] || fail "table of $1: $(cat "$1/report/table.csv")"
  grep -q ',1,1,0,0,' "$1/report/table.csv" || fail "no finished case in $1: $(cat "$1/report/table.csv")"
}

case "$mode" in
local)
  # Errors name the file, line, column and key; nothing is planned.
  printf 'config: configs/sim2d_single_laser.yaml\ngrid:\n  pipeline.tracker.splitter.distanc: [0.5]\nmetrics: [ate]\n' > bad-key.yaml
  if out="$("$bin" sweep run bad-key.yaml -o bad 2>&1)"; then fail "a grid key that is no parameter ran: $out"; fi
  grep -q "bad-key.yaml:3:3: pipeline.tracker.splitter.distanc: unknown key 'distanc'" <<< "$out" \
    || fail "grid key error: $out"
  [ ! -e bad/plan.json ] || fail "a sweep with an error was planned"
  printf 'config: configs/sim2d_single_laser.yaml\nmetrics: [ate, hzz]\nrepeats: 2\n' > bad-metric.yaml
  if out="$("$bin" sweep plan bad-metric.yaml -o bad 2>&1)"; then fail "an unknown metric was planned: $out"; fi
  grep -q "bad-metric.yaml:2:16: metrics: unknown metric 'hzz'; did you mean 'hz'?" <<< "$out" || fail "metric error: $out"
  grep -q "bad-metric.yaml:3:1: repeats: unknown key 'repeats'; did you mean 'repeat'?" <<< "$out" || fail "key error: $out"
  echo "ok: sweep-file errors name file:line:col and the key, before anything runs"

  run_local a
  grep -q "running 8 on this machine, 2 at a time" a.log || fail "local: $(cat a.log)"
  # Content ids: a second plan of the same file finds every result and runs nothing.
  "$bin" -q sweep run small.sweep.yaml -o a -j 2 > again.log 2>&1 || fail "rerun: $(cat again.log)"
  grep -q "8 cases, 8 with a result; running 0" again.log || fail "rerun ran cases: $(cat again.log)"
  echo "ok: local -j2, 8 cases; planned again, nothing runs"

  # A failing case and a timed-out one are recorded with their exit and log; the sweep goes on.
  cat > counting.yaml <<'EOF'
plugins: [fixture]
source: {type: fixture.CountingSource, frames: 50}
pipeline:
  preprocessors: [{type: fixture.Scale}]
outputs: [{type: fixture.SumWriter}]
EOF
  cat > faults.sweep.yaml <<'EOF'
config: counting.yaml
datasets:
  good: {source.frames: 20}
  broken: {source.fail_at: 5}
  endless: {source.frames: 1000000000}
timeout: 2
metrics: [time, memory]
EOF
  export PLUGSLAM_PLUGIN_PATH="$build/tests/plugins"
  "$bin" -q sweep run faults.sweep.yaml -o f > f.log 2>&1 || fail "a failing case made the sweep fail: $(cat f.log)"
  "$bin" -q sweep report f --no-plots > f.md || fail "report of failures"
  grep -q "counting broken: failed, exit 1" f.md || fail "failed case not reported: $(cat f.md)"
  grep -q "fixture failure at frame 5" f.md || fail "no log tail: $(cat f.md)"
  grep -q "counting endless: timeout, stopped after the timeout of 2 s" f.md || fail "timeout not reported: $(cat f.md)"
  grep -q "| counting | good | 1 |" f.md || fail "good case: $(cat f.md)"
  unset PLUGSLAM_PLUGIN_PATH
  echo "ok: a failing and a timed-out case are reported with exit code and log tail; the sweep goes on"

  # Killed outright midway: finished results stay, the runs in flight die with the sweep, and
  # the next start runs only the missing cases.
  start_sweep_until k 2
  kill -9 "$sweep"
  wait "$sweep" 2> /dev/null || true
  done_before="$(ls k/cases/*/result.json | wc -l)"
  [ "$done_before" -ge 2 ] && [ "$done_before" -lt 8 ] || fail "killed sweep left $done_before results"
  # They die with it, not at once: wait for that (no event to wait on) with a generous deadline.
  for _ in $(seq 300); do
    pgrep -f "$tmp/k/cases" > /dev/null || break
    sleep 0.1
  done
  pgrep -f "$tmp/k/cases" > /dev/null && fail "runs of the killed sweep still run 30 s after it"
  sums_before="$(md5sum k/cases/*/result.json)"
  "$bin" -q sweep run small.sweep.yaml -o k -j 2 > k2.log 2>&1 || fail "resume: $(cat k2.log)"
  grep -q "8 cases, $done_before with a result; running $((8 - done_before))" k2.log || fail "resume ran: $(cat k2.log)"
  while read -r sum file; do
    [ "$(md5sum < "$file" | cut -d' ' -f1)" = "$sum" ] || fail "result $file changed on resume"
  done <<< "$sums_before"
  "$bin" -q sweep report k > /dev/null
  [ "$(figures k)" = "$(figures a)" ] || fail "resumed table differs: $(diff <(figures a) <(figures k))"
  echo "ok: killed after $done_before cases, resumed: $((8 - done_before)) ran, no result lost, same table"

  # Ctrl-C: the run in flight is stopped and not recorded; exit 130.
  start_sweep_until i 1
  # A second sweep on the same folder would run the same cases into the same folders.
  if out="$("$bin" -q sweep run small.sweep.yaml -o i -j 1 2>&1)"; then fail "two sweeps ran in one folder: $out"; fi
  grep -q "another \`plugslam sweep run\` is running cases in" <<< "$out" || fail "second sweep: $out"
  kill -INT "$sweep"
  rc=0
  wait "$sweep" || rc=$?
  [ "$rc" = 130 ] || fail "interrupted sweep exit $rc: $(cat i1.log)"
  grep -q "interrupted:" i1.log || fail "no interruption message: $(cat i1.log)"
  n="$(ls i/cases/*/result.json | wc -l)"
  "$bin" -q sweep run small.sweep.yaml -o i -j 2 > i2.log 2>&1 || fail "resume after SIGINT: $(cat i2.log)"
  grep -q "8 cases, $n with a result; running $((8 - n))" i2.log || fail "resume after SIGINT: $(cat i2.log)"
  grep -q '"status": "ok"' i/cases/*/result.json || fail "no ok result"
  ! grep -l '"status": "failed"' i/cases/*/result.json || fail "an interrupted case was recorded as failed"
  echo "ok: interrupted (SIGINT) after $n cases, exit 130, resumed with the missing ones"
  ;;

parallel)
  if ! command -v parallel > /dev/null; then
    "$src/scripts/apt-install.sh" sweep-test parallel > install.log 2>&1 || {
      echo "SKIP: GNU parallel is not installed and cannot be installed here: $(tail -2 install.log)"
      exit 77
    }
  fi
  run_local a
  "$bin" -q sweep run small.sweep.yaml -o p --engine parallel --hosts : -j 2 > p.log 2>&1 \
    || fail "parallel sweep: $(cat p.log)"
  grep -q "running 8 through GNU parallel on :" p.log || fail "parallel: $(cat p.log)"
  [ "$(tail -n +2 p/parallel/joblog-1.txt | wc -l)" -eq 8 ] || fail "joblog: $(cat p/parallel/joblog-1.txt)"
  "$bin" -q sweep report p > /dev/null
  [ "$(figures p)" = "$(figures a)" ] || fail "parallel and local tables differ: $(diff <(figures a) <(figures p))"
  echo "ok: GNU parallel (--sshlogin :) and local give the same table"
  ;;

slurm)
  if ! "$src/scripts/slurm-local.sh" install > install.log 2>&1; then
    echo "SKIP: the Slurm packages (slurmctld slurmd slurm-client munge) cannot be installed here: $(tail -2 install.log)"
    exit 77
  fi
  "$src/scripts/slurm-local.sh" start "$tmp/slurm" > start.log 2>&1 || fail "slurm-local.sh start: $(cat start.log)"
  export SLURM_CONF="$tmp/slurm/slurm.conf"
  run_local a
  "$bin" -q sweep run small.sweep.yaml -o s --engine slurm --time 10 > s.log 2>&1 || fail "slurm sweep: $(cat s.log)"
  grep -q "submitted job array .* (8 tasks" s.log || fail "slurm: $(cat s.log)"
  "$bin" -q sweep report s > /dev/null
  [ "$(figures s)" = "$(figures a)" ] || fail "slurm and local tables differ: $(diff <(figures a) <(figures s))"
  grep -q '"host"' "$(ls s/cases/*/result.json | head -1)" || fail "no host in a result"
  echo "ok: Slurm (one job array of 8) and local give the same table"
  # Only the missing cases go again: two results removed, two tasks submitted, without waiting.
  rm "$(ls s/cases/*/result.json | head -1)" "$(ls s/cases/*/result.json | tail -1)"
  "$bin" -q sweep run small.sweep.yaml -o s --engine slurm --no-wait > s2.log 2>&1 || fail "resubmit: $(cat s2.log)"
  grep -q "8 cases, 6 with a result; 2 to submit" s2.log || fail "resubmit: $(cat s2.log)"
  grep -q "submitted job array .* (2 tasks" s2.log || fail "resubmit: $(cat s2.log)"
  job="$(cat s/slurm/last_job)"
  if out="$("$bin" -q sweep run small.sweep.yaml -o s --engine slurm 2>&1)"; then
    squeue -h -j "$job" | grep -q . && fail "submitted again while job $job runs: $out"
  else
    grep -q "job $job of this sweep is still queued or running" <<< "$out" || fail "second submission: $out"
  fi
  for _ in $(seq 600); do squeue -h -j "$job" 2>/dev/null | grep -q . || break; sleep 0.1; done
  "$bin" -q sweep report s > /dev/null
  [ "$(figures s)" = "$(figures a)" ] || fail "resubmitted table differs: $(diff <(figures a) <(figures s))"
  echo "ok: a second run submits only the 2 missing cases (--no-wait), and refuses while that job runs"
  ;;
*) fail "mode: local, slurm or parallel" ;;
esac
