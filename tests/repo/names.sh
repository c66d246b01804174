#!/usr/bin/env bash
# Names match folders (docs/architecture.md §2). Every C++ file of a layer declares its code in the
# namespace its folder gives, or one nested in it:
#   sdk/ -> flipper::sdk (its conformance kit, include/flipper/testing/, -> flipper::testing)
#   toolkit/ -> flipper::toolkit      language/ -> flipper::language      kernel/ -> flipper::kernel
#   naturalization/ -> flipper::naturalization      apps/NAME/ -> flipper::NAME
#   plugins/NAME/ -> flipper::plugins::NAME
# A block that only forward-declares another layer's classes (`namespace flipper::kernel { class
# Config; }`) is not code and is allowed. A plugin's entry file -- the one that registers it with
# FLIPPER_PLUGIN -- is plugins/NAME/NAME_plugin.cpp, the only file that does.
# Usage: names.sh <repository root>   |   names.sh --self-test
set -euo pipefail

# The namespaces of `file` that hold more than forward declarations, one per line.
code_namespaces() {
  awk '
    /^namespace flipper(::[A-Za-z_0-9]+)* *\{/ {
      ns = $2; sub(/\{.*/, "", ns); depth = 1; forward_only = 1; open = 1; next
    }
    open {
      line = $0
      if (line ~ /^}/) { if (!forward_only) print ns; open = 0; next }
      if (line !~ /^[[:space:]]*((class|struct) [A-Za-z_0-9]+;)?[[:space:]]*$/ &&
          line !~ /^[[:space:]]*\/\//) forward_only = 0
    }
    END { if (open && !forward_only) print ns }
  ' "$1"
}

expected_for() {  # expected_for <path relative to the root>: the allowed namespace prefixes
  local rel=$1
  case $rel in
    sdk/include/flipper/testing/*) echo "flipper::testing" ;;
    sdk/*) echo "flipper::sdk" ;;
    toolkit/*) echo "flipper::toolkit" ;;
    language/*) echo "flipper::language" ;;
    kernel/*) echo "flipper::kernel" ;;
    naturalization/*) echo "flipper::naturalization" ;;
    apps/*) rel=${rel#apps/}; echo "flipper::${rel%%/*}" ;;
    plugins/*) rel=${rel#plugins/}; echo "flipper::plugins::${rel%%/*}" ;;
  esac
}

check() {  # check <root>: prints each violation, fails if there is one
  local root=$1 bad=0 file rel want ns dir name
  while IFS= read -r file; do
    rel=${file#"$root"/}
    want=$(expected_for "$rel")
    while IFS= read -r ns; do
      if [[ $ns != "$want" && $ns != "$want::"* ]]; then
        echo "$rel: namespace $ns (expected $want)"
        bad=1
      fi
    done < <(code_namespaces "$file")
  done < <(find "$root"/sdk "$root"/toolkit "$root"/language "$root"/kernel "$root"/naturalization "$root"/apps \
             "$root"/plugins -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) \
             -not -path '*/node_modules/*' 2>/dev/null | sort)
  for dir in "$root"/plugins/*/; do
    name=$(basename "$dir")
    [[ -f $dir/CMakeLists.txt ]] || continue
    while IFS= read -r file; do
      if grep -q 'FLIPPER_PLUGIN(' "$file" && [[ $(basename "$file") != "${name}_plugin.cpp" ]]; then
        echo "plugins/$name/${file#"$dir"}: registers the plugin (expected in ${name}_plugin.cpp)"
        bad=1
      fi
    done < <(find "$dir" -type f \( -name '*.cpp' -o -name '*.hpp' \) | sort)
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
  rm -rf "${tmp:?}"/*
  mkdir -p "$tmp/plugins/demo/src" "$tmp/sdk/include/flipper/testing" "$tmp/kernel/config/src" \
    "$tmp/naturalization/lexicon/src" "$tmp/apps/studio/src" "$tmp/toolkit/src"
  touch "$tmp/plugins/demo/CMakeLists.txt"
  printf 'namespace flipper::plugins::demo {\nnamespace {\n}\n}\nFLIPPER_PLUGIN(x)\n' \
    >"$tmp/plugins/demo/demo_plugin.cpp"
  printf 'namespace flipper::plugins::demo::detail {\nint x;\n}\n' >"$tmp/plugins/demo/src/util.hpp"
  printf 'namespace flipper::testing {\nint kit;\n}\n' >"$tmp/sdk/include/flipper/testing/kit.hpp"
  printf 'namespace flipper::kernel {\nint config;\n}\n' >"$tmp/kernel/config/src/config.cpp"
  printf 'namespace flipper::naturalization::sqlite {\nint db;\n}\n' \
    >"$tmp/naturalization/lexicon/src/db.cpp"
  printf 'namespace flipper::toolkit {\nint t;\n}\n' >"$tmp/toolkit/src/t.cpp"
  printf 'namespace flipper::naturalization {\nclass Naturalizer;\n}\n\nnamespace flipper::studio {\n// x\nint api;\n}  // namespace flipper::studio\n' \
    >"$tmp/apps/studio/src/api.hpp"
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
expect pass "each layer in its namespace, nested ones, a forward declaration of another layer's class"
printf 'namespace flipper::demo {\nint y;\n}\n' >"$tmp/plugins/demo/src/util.hpp"
expect fail "a plugin header (in a subfolder) in flipper::demo"
tree
printf 'namespace flipper::plugins {\nint z;\n}\n' >>"$tmp/plugins/demo/demo_plugin.cpp"
expect fail "code in flipper::plugins itself"
tree
printf 'namespace flipper::kernel {\nint z;\n}\n' >"$tmp/naturalization/lexicon/src/db.cpp"
expect fail "naturalization code in flipper::kernel"
tree
printf 'namespace flipper::kernel {\nclass Naturalizer;\nint leaked;\n}\n' >>"$tmp/apps/studio/src/api.hpp"
expect fail "an app defining code in the kernel's namespace beside a forward declaration"
tree
printf 'namespace flipper::kernel::replay {\nint r;\n}\n' >"$tmp/apps/studio/src/api.hpp"
expect fail "an app in flipper::kernel::replay"
tree
printf 'namespace flipper::sdk {\nint s;\n}\n' >"$tmp/toolkit/src/t.cpp"
expect fail "toolkit code in flipper::sdk"
tree
printf 'namespace flipper::sdk {\nint s;\n}\n' >"$tmp/kernel/config/src/config.cpp"
expect fail "kernel code in flipper::sdk"
tree
mv "$tmp/plugins/demo/demo_plugin.cpp" "$tmp/plugins/demo/plugin.cpp"
expect fail "the entry file named plugin.cpp"
tree
printf 'FLIPPER_PLUGIN(y)\n' >>"$tmp/plugins/demo/src/util.hpp"
expect fail "a second file (in a subfolder) registering"
