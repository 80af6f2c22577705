#!/usr/bin/env bash
# Prints the Debian packages that package.xml's dependencies need, one per
# line, through the table scripts/debian_packages.yaml. Documentation tools
# (<doc_depend>) only with --doc. Exits 1, naming each key, when a dependency
# has no entry in the table.
#   scripts/debian_packages.sh [--doc]
set -euo pipefail
cd "$(dirname "$0")/.."
TYPES='depend|build_depend|build_export_depend|buildtool_depend|buildtool_export_depend|exec_depend|test_depend'
[ "${1:-}" = "--doc" ] && TYPES="$TYPES|doc_depend"
status=0
packages=()
for key in $(grep -oE "<($TYPES)( [^>]*)?>[^<]+</" package.xml | sed -E 's/.*>([^<]+)<.*/\1/' | sort -u); do
  entry=$({ grep -E "^$key: " scripts/debian_packages.yaml || true; } | sed -nE 's/.*debian: \[([^]]*)\].*/\1/p' | tr -d ',')
  if [ -z "$entry" ]; then
    echo "package.xml: dependency '$key' has no Debian packages in scripts/debian_packages.yaml" >&2
    status=1
  fi
  packages+=($entry)
done
[ "$status" -eq 0 ] || exit "$status"
printf '%s\n' "${packages[@]}" | sort -u
