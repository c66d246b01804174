#!/usr/bin/env bash
# scripts/docs --links-only (repo.readme_links) fails on what it is there to catch, on scratch
# copies of the repository's README.md, docs/, .ci/run and the script: a relative link to a missing
# page, a set-up block that is not the two commands, and a .ci/run that runs something else.
set -euo pipefail
src=$1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "readme_links_detect: $*" >&2; exit 1; }
scratch() {  # a fresh copy in $tmp/t
  rm -rf "$tmp/t"
  mkdir -p "$tmp/t/scripts" "$tmp/t/.ci"
  cp "$src/scripts/docs" "$tmp/t/scripts/"
  cp "$src/.ci/run" "$tmp/t/.ci/"
  cp "$src/README.md" "$tmp/t/"
  cp -r "$src/docs" "$tmp/t/"
}
expect_refusal() {  # expect_refusal WHAT MESSAGE
  if bash "$tmp/t/scripts/docs" --links-only 2>"$tmp/err"; then fail "$1: passed"; fi
  grep -qF -- "$2" "$tmp/err" || fail "$1: no '$2' in: $(cat "$tmp/err")"
}
scratch
bash "$tmp/t/scripts/docs" --links-only 2>"$tmp/err" || fail "the copy fails: $(cat "$tmp/err")"

scratch
rm "$tmp/t/docs/usage.md"
expect_refusal "a missing page" "links to 'docs/usage.md', which does not exist"

scratch
sed -i 's|^bash scripts/test |bash scripts/tests|' "$tmp/t/README.md"
expect_refusal "a third set-up command" "set-up block is not the two commands"

scratch
sed -i 's|^bash scripts/test$|bash scripts/test --quick|' "$tmp/t/.ci/run"
expect_refusal "CI running another command" ".ci/run does not run 'bash scripts/test'"
echo "readme_links_detect: 3 of 3 breakages refused" >&2
