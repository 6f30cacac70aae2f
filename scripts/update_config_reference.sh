#!/bin/sh
# Rewrites the GENERATED part of docs/configuration.md from `calibench config-reference` (the
# declarations of the scenario format). Usage: scripts/update_config_reference.sh [CALIBENCH]
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
calibench=${1:-$root/build/bench/calibench}
page=$root/docs/configuration.md
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
"$calibench" config-reference >"$tmp.gen"
awk -v gen="$tmp.gen" '
  /^<!-- BEGIN GENERATED: calibench config-reference/ { print; while ((getline line < gen) > 0) print line; skip = 1; next }
  /^<!-- END GENERATED -->/ { skip = 0 }
  !skip { print }
' "$page" >"$tmp"
rm -f "$tmp.gen"
cat "$tmp" >"$page"
