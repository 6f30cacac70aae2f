#!/usr/bin/env bash
# Disk full while writing, simulated by a file-size limit (ulimit -f: writes past it fail with
# EFBIG, as on a full disk; calibench ignores SIGXFSZ so the failure is reported, not fatal):
#   1. the run stops with exit code 3 and a message naming the file and the reason;
#   2. run.partial keeps every task finished before the failure;
#   3. `--resume` without the limit finishes, and runs.csv and summary.csv equal an uninterrupted
#      run's byte for byte: nothing lost, nothing duplicated.
#   tests/bench/disk_full_test.sh CALIBENCH SOURCE_DIR
set -euo pipefail
calibench="$1"
config="$2/tests/bench/sweeps/small.yaml"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$calibench" run "$config" --out "$work/reference" --quiet --threads 2 2>/dev/null
# 120 KiB: room for config.resolved.yaml (28 KB) and a few of the 8 tasks' curves (177 KB in all).
set +e
(ulimit -f 120 && exec "$calibench" run "$config" --out "$work/full" --quiet --threads 2) \
  2>"$work/stderr"
status=$?
set -e
cat "$work/stderr"
[[ $status -eq 3 ]] || { echo "FAIL: exit code $status, expected 3 (output error)"; exit 1; }
grep -q "run.partial/.*: write failed: File too large" "$work/stderr" ||
  { echo "FAIL: the message does not name the file and the reason"; exit 1; }
done_tasks=$(($(grep -c '' "$work/full/run.partial/tasks.idx") - 2))
echo "tasks complete on disk when the disk filled: $done_tasks of 8"
[[ $done_tasks -ge 1 && $done_tasks -lt 8 ]] ||
  { echo "FAIL: the limit should land mid-run (1..7 tasks done)"; exit 1; }
"$calibench" run "$config" --out "$work/full" --quiet --threads 2 --resume
for f in runs.csv summary.csv; do
  cmp "$work/reference/$f" "$work/full/$f" || { echo "FAIL: $f differs"; exit 1; }
done
echo "PASS: disk full after $done_tasks tasks, resumed; runs.csv and summary.csv identical"
