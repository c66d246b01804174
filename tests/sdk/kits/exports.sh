#!/usr/bin/env bash
# Every plugin library in the given directories exports exactly one dynamic symbol, the entry
# function (flipper_add_plugin's linker version script); nothing else of a plugin can bind to
# the kernel or to another plugin. Usage: exports.sh <plugin dir>...
set -euo pipefail
count=0
for dir in "$@"; do
  for lib in "$dir"/*.so; do
    [[ -e $lib ]] || continue
    exported=$(nm -D --defined-only "$lib" | awk '{print $3}')
    if [[ $exported != flipper_plugin_entry ]]; then
      echo "$lib exports more than flipper_plugin_entry:"; echo "$exported" | head -5
      exit 1
    fi
    count=$((count + 1))
  done
done
if ((count == 0)); then echo "no plugin library found in $*"; exit 1; fi
echo "$count plugin libraries export only flipper_plugin_entry"
