#!/usr/bin/env bash
# The cost of the method-only gain sweep, apart from the default benchmark (it needs the
# gain sweep run twice over): configs/sweeps/gain.yaml (N gains) against configs/sweeps/gain1.yaml
# (one gain) plus the other gains' adaptive solves from gain's timings.csv
# (tools/gain_cost.py). Writes OUT/gain/gain_cost.txt, which `calibench report` shows.
# Usage: scripts/gain_cost.sh [OUT]   (default: out/); about 2.5 minutes on 2 cores.
set -euo pipefail
source "$(dirname "$0")/common.sh"
install_packages
build
OUT="${1:-$CALIBENCH_ROOT/out}"
CALIBENCH="$BUILD_DIR/bench/calibench"
now_ms() { echo $(($(date +%s%N) / 1000000)); }
declare -A wall
for sweep in gain gain1; do
  t0=$(now_ms)
  "$CALIBENCH" run "$CALIBENCH_ROOT/configs/sweeps/$sweep.yaml" --out "$OUT/$sweep" --quiet
  ms=$(($(now_ms) - t0))
  wall[$sweep]=$((ms / 1000)).$(printf "%03d" $((ms % 1000)))
done
/usr/bin/python3 "$CALIBENCH_ROOT/tools/gain_cost.py" "$OUT/gain" "${wall[gain]}" \
  "$OUT/gain1" "${wall[gain1]}" "$(nproc)"
