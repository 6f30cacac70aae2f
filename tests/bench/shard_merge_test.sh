#!/usr/bin/env bash
# Runs scripts/slurm_sweep.sbatch as a 3-task job array would (Slurm variables set by hand), merges
# the shards, and compares with one unsharded run: runs.csv, summary.csv and schema.json must be
# equal.
set -euo pipefail
calibench="$1"
root="$2"
config="$root/tests/bench/sweeps/small.yaml"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$calibench" run "$config" --out "$work/whole" --quiet 2>/dev/null
for k in 3 1 2; do
  CALIBENCH="$calibench" SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=3 SLURM_CPUS_PER_TASK=1 \
    "$root/scripts/slurm_sweep.sbatch" "$config" "$work/array" 2>/dev/null
done
"$calibench" merge "$work"/array/shard-*-of-3 --out "$work/merged" 2>/dev/null
cmp "$work/whole/runs.csv" "$work/merged/runs.csv"
cmp "$work/whole/summary.csv" "$work/merged/summary.csv"
cmp "$work/whole/schema.json" "$work/merged/schema.json"
echo "PASS: 3 Slurm array shards merged equal the unsharded run"
