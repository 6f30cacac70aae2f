#!/bin/sh
# Fails when the generated part of docs/configuration.md (between its GENERATED markers) differs
# from `calibench config-reference`, the reference written from the declarations of the scenario
# format. Regenerate: scripts/update_config_reference.sh BUILD/bench/calibench
# Usage: config_reference_test.sh CALIBENCH DOCS/configuration.md
set -eu
calibench=$1
page=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$calibench" config-reference >"$tmp/generated.md"
sed -n '/^<!-- BEGIN GENERATED: calibench config-reference/,/^<!-- END GENERATED -->/p' "$page" |
  sed '1d;$d' >"$tmp/page.md"
if [ ! -s "$tmp/page.md" ]; then
  echo "$page: no GENERATED markers" >&2
  exit 1
fi
if ! diff -u "$tmp/page.md" "$tmp/generated.md"; then
  echo "$page is stale: its GENERATED part differs from 'calibench config-reference' (above);" \
    "run scripts/update_config_reference.sh" >&2
  exit 1
fi
echo "$page: the generated reference is current"
