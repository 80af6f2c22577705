#!/usr/bin/env bash
# Fetches the benchmark datasets listed in scripts/datasets.sha256 into the
# datasets folder (RRR_DATASETS, default ../shared/datasets beside the
# package, or the first argument) and checks every file against its sha256.
# Files without a download URL (marked -) must be copied by hand; README,
# "Data", says where each comes from. Exits 1 if any file is missing or
# differs after fetching.
#   scripts/fetch_datasets.sh [DATASETS_FOLDER]
set -uo pipefail
cd "$(dirname "$0")/.."
DEST=${1:-${RRR_DATASETS:-$(pwd)/../shared/datasets}}
mkdir -p "$DEST" || { echo "cannot create $DEST"; exit 1; }
ok=0; fetched=0; bad=0; missing=0
while read -r sum path url; do
  [[ -z "$sum" || "$sum" == \#* ]] && continue
  file="$DEST/$path"
  if [ -f "$file" ] && echo "$sum  $file" | sha256sum --check --status; then
    ok=$((ok + 1)); continue
  fi
  if [ "$url" = "-" ]; then
    echo "missing or different, no download: $path (copy it by hand; README, Data)"
    missing=$((missing + 1)); continue
  fi
  mkdir -p "$(dirname "$file")"
  if ! curl -fsSL --connect-timeout 10 --max-time 300 -o "$file.part" "$url"; then
    echo "could not download $path from $url (no network?)"
    rm -f "$file.part"; missing=$((missing + 1)); continue
  fi
  if echo "$sum  $file.part" | sha256sum --check --status; then
    mv "$file.part" "$file"; fetched=$((fetched + 1))
  else
    echo "checksum mismatch for $path from $url (kept as $file.part)"
    bad=$((bad + 1))
  fi
done < scripts/datasets.sha256
echo "datasets in $DEST: $ok verified, $fetched fetched, $missing missing, $bad mismatched"
[ $((missing + bad)) -eq 0 ]
