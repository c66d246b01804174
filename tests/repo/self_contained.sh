#!/usr/bin/env bash
# The repository is self-contained (README "Set up and test"): no tracked file may read from a
# folder beside the checkout. Fails, listing file:line, if any tracked file names the sibling
# folder the project's brief lived in, or the build variable that once pointed there.
# Usage: self_contained.sh SOURCE_DIR
set -euo pipefail
cd "$1"
# The patterns are spelled in two pieces so that this file does not match itself.
sibling='..''/shared'
variable='FLIPPER_''SHARED_DIR'
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  list() { git ls-files -z; }
else  # an exported tree without .git: every file but build output and npm packages
  list() { find . -type f -not -path './build*' -not -path './out/*' -not -path '*/node_modules/*' \
             -not -path './.git/*' -print0; }
fi
hits=$(list | xargs -0 grep -n -I -F -e "$sibling" -e "$variable" -- 2>/dev/null || true)
if [[ -n $hits ]]; then
  echo "FAIL: tracked files refer to a folder outside the repository (or to $variable):"
  echo "$hits"
  exit 1
fi
# What the tests, benchmarks and experiments read is here.
for f in data/study2018/dev/{worlds,queries,definitions,original-answers}.jsonl \
         data/study2018/dev/sessions.json data/study2018/original-probes.jsonl \
         data/study2018/README.md data/study2018/NOTICE; do
  [[ -s $f ]] || { echo "FAIL: $f is missing or empty"; exit 1; }
done
echo "self-contained: no tracked file names $sibling or $variable"
