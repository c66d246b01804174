#!/usr/bin/env bash
# The layer check of docs/architecture.md §2: runs each line of the block marked
# <!-- layer-check --> from the root given (the repository, or a scratch tree), and fails when any
# prints something. The block is the one source of the rules: the doc shows what this runs.
# Usage: layers.sh <doc> <root>
set -uo pipefail
doc=$1
root=$2
lines=$(awk '/<!-- layer-check -->/ {marked = 1; next}
             marked && /^```/ {if (inside) exit; inside = 1; next}
             inside {print}' "$doc")
if [[ -z $lines ]]; then
  echo "no <!-- layer-check --> block in $doc"
  exit 1
fi
cd "$root" || exit 1
failed=0
while IFS= read -r line; do
  out=$(bash -c "$line" 2>&1)
  if [[ -n $out ]]; then
    echo "layer check failed: $line"
    echo "$out" | sed 's/^/  /'
    failed=1
  fi
done <<<"$lines"
[[ $failed == 0 ]] && echo "layer check OK ($(wc -l <<<"$lines") rules)"
exit $failed
