#!/usr/bin/env bash
# Fault injection: kills a running sweep with SIGKILL at KILLS random moments, resuming after each
# (`calibench run --resume`), then lets it finish; the final runs.csv and summary.csv must equal
# those of an uninterrupted run, byte for byte.
#   scripts/fault_inject.sh CALIBENCH CONFIG.yaml [KILLS=5] [SEED=1]
# Each kill comes 5-20% of the uninterrupted run's wall time after a (re)start, so that all of them
# land mid-run. Exit 0 when the files are equal; prints each kill and the tasks complete on disk.
set -euo pipefail
calibench="$1"
config="$2"
kills="${3:-5}"
RANDOM="${4:-1}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
now_ms() { echo $(($(date +%s%N) / 1000000)); }
t0=$(now_ms)
"$calibench" run "$config" --out "$work/reference" --quiet --threads 2 2>/dev/null
reference_ms=$(($(now_ms) - t0))
landed=0
for ((i = 1; i <= kills; ++i)); do
  resume=()
  [[ $i -gt 1 ]] && resume=(--resume)
  "$calibench" run "$config" --out "$work/killed" --quiet --threads 2 "${resume[@]}" \
    2>/dev/null &
  pid=$!
  delay_ms=$((reference_ms * (5 + RANDOM % 16) / 100))
  sleep "$((delay_ms / 1000)).$(printf '%03d' $((delay_ms % 1000)))"
  if kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null; then
    landed=$((landed + 1))
    done_tasks=$(($(grep -c '' "$work/killed/run.partial/tasks.idx" 2>/dev/null || echo 2) - 2))
    echo "kill $i: SIGKILL after ${delay_ms} ms, ${done_tasks} tasks complete on disk"
  else
    echo "kill $i: the run had finished before ${delay_ms} ms"
  fi
  wait "$pid" 2>/dev/null || true
done
"$calibench" run "$config" --out "$work/killed" --quiet --threads 2 --resume 2>/dev/null
for f in runs.csv summary.csv curves.csv; do
  if ! cmp "$work/reference/$f" "$work/killed/$f"; then
    echo "FAIL: $f differs from the uninterrupted run's after $landed kills" >&2
    exit 1
  fi
done
rows=$(($(grep -c '' "$work/reference/runs.csv") - 1))
echo "PASS: $landed of $kills SIGKILLs landed mid-run; after resuming, runs.csv ($rows rows)," \
  "summary.csv and curves.csv equal the uninterrupted run's"
