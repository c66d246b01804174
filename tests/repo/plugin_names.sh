#!/usr/bin/env bash
# Names match folders (docs/architecture.md §2): an in-tree plugin in plugins/NAME/ declares its
# code in namespace flipper::plugins::NAME (or one nested in it), and its entry file -- the one
# that registers it with FLIPPER_PLUGIN -- is plugins/NAME/NAME_plugin.cpp, the only file that
# does. Usage: plugin_names.sh <repository root>   |   plugin_names.sh --self-test
set -euo pipefail

check() {  # check <root>: prints each violation, fails if there is one
  local root=$1 bad=0 dir name file ns
  for dir in "$root"/plugins/*/; do
    name=$(basename "$dir")
    [[ -f $dir/CMakeLists.txt ]] || continue
    while IFS= read -r file; do
      while IFS= read -r ns; do
        if [[ $ns != "flipper::plugins::$name" && $ns != "flipper::plugins::$name::"* ]]; then
          echo "plugins/$name/$(basename "$file"): namespace $ns (expected flipper::plugins::$name)"
          bad=1
        fi
      done < <(sed -nE 's/^namespace (flipper(::[A-Za-z_0-9]+)*) *\{.*/\1/p' "$file")
      if grep -q 'FLIPPER_PLUGIN(' "$file" && [[ $(basename "$file") != "${name}_plugin.cpp" ]]; then
        echo "plugins/$name/$(basename "$file"): registers the plugin (expected in ${name}_plugin.cpp)"
        bad=1
      fi
    done < <(find "$dir" -maxdepth 1 -type f \( -name '*.cpp' -o -name '*.hpp' \) | sort)
    if ! grep -qs 'FLIPPER_PLUGIN(' "$dir/${name}_plugin.cpp"; then
      echo "plugins/$name: no ${name}_plugin.cpp registering the plugin with FLIPPER_PLUGIN"
      bad=1
    fi
  done
  return $bad
}

if [[ ${1:-} != --self-test ]]; then
  check "$1"
  exit
fi

# The check must fail on each kind of misnaming and pass on a well-named tree.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
tree() {
  rm -rf "$tmp/plugins"
  mkdir -p "$tmp/plugins/demo"
  touch "$tmp/plugins/demo/CMakeLists.txt"
  printf 'namespace flipper::plugins::demo {\nnamespace {\n}\n}\nFLIPPER_PLUGIN(x)\n' \
    >"$tmp/plugins/demo/demo_plugin.cpp"
  printf 'namespace flipper::plugins::demo::detail {\n}\n' >"$tmp/plugins/demo/util.hpp"
}
expect() {  # expect pass|fail <what>
  local result=pass
  check "$tmp" >"$tmp/out" 2>&1 || result=fail
  if [[ $result != "$1" ]]; then
    echo "expected the name check to $1 for: $2"
    cat "$tmp/out"
    exit 1
  fi
  echo "$1 as expected: $2"
}
tree
expect pass "flipper::plugins::demo in demo_plugin.cpp, a nested namespace in a header"
tree
printf 'namespace flipper::demo {\n}\n' >"$tmp/plugins/demo/util.hpp"
expect fail "a header in flipper::demo"
tree
printf 'namespace flipper::plugins {\n}\n' >>"$tmp/plugins/demo/demo_plugin.cpp"
expect fail "code in flipper::plugins itself"
tree
mv "$tmp/plugins/demo/demo_plugin.cpp" "$tmp/plugins/demo/plugin.cpp"
expect fail "the entry file named plugin.cpp"
tree
printf 'FLIPPER_PLUGIN(y)\n' >>"$tmp/plugins/demo/util.hpp"
expect fail "a second file registering"
