#!/usr/bin/env bash
# The SDK's ABI surface has no holes (docs/sdk-migration.md "What the ABI number covers"):
# 1. libflipper_sdk's SONAME is libflipper_sdk.so.<FLIPPER_PLUGIN_ABI> (version.hpp);
# 2. every C++ symbol it exports under flipper:: lies in flipper::sdk::abi<FLIPPER_PLUGIN_ABI>;
# 3. every installed SDK header that declares code in flipper::sdk opens the generated inline
#    namespace (FLIPPER_ABI_NAMESPACE), none a literal one (`v1`, `abi3`);
# 4. no std::function in the SDK's interface headers (callbacks are plain structs).
# Usage: abi_surface.sh <source dir> <libflipper_sdk.so>
set -euo pipefail
src=$1
lib=$2
fail() {
  echo "FAILED: $*"
  exit 1
}
abi=$(sed -n 's/^#define FLIPPER_PLUGIN_ABI \([0-9]*\)$/\1/p' "$src/sdk/include/flipper/sdk/version.hpp")
[[ -n $abi ]] || fail "no FLIPPER_PLUGIN_ABI in version.hpp"
echo "plugin ABI $abi"

soname=$(readelf -d "$lib" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
[[ $soname == "libflipper_sdk.so.$abi" ]] || fail "SONAME is '$soname', not libflipper_sdk.so.$abi"
echo "SONAME $soname"

exported=$(nm -DC --defined-only "$lib" | grep -E ' [TWVBDR] .*flipper::' || true)
n=$(grep -c . <<<"$exported" || true)
[[ $n -gt 50 ]] || fail "only $n flipper symbols exported: is $lib the SDK?"
outside=$(grep -vF "flipper::sdk::abi$abi::" <<<"$exported" || true)
[[ -z $outside ]] || fail "exported outside flipper::sdk::abi$abi:"$'\n'"$outside"
echo "$n exported flipper symbols, all in flipper::sdk::abi$abi"

headers=0
for h in "$src"/sdk/include/flipper/sdk/*.hpp; do
  grep -qE '^namespace flipper::sdk' "$h" || continue
  # A header-only header whose code is compiled into each side and never crosses the boundary
  # (config_handles.hpp: constexpr handles and inline readers) exports nothing to version; it
  # says so in its @file comment.
  grep -qF 'Header-only: no exported symbol, no ABI' "$h" && continue
  headers=$((headers + 1))
  grep -qE '^inline namespace FLIPPER_ABI_NAMESPACE \{' "$h" ||
    fail "${h#"$src"/} declares code in flipper::sdk outside 'inline namespace FLIPPER_ABI_NAMESPACE'"
done
literal=$(grep -nE 'inline namespace [A-Za-z_0-9]+ *\{' "$src"/sdk/include/flipper/sdk/*.hpp \
  "$src"/sdk/src/*.cpp | grep -v FLIPPER_ABI_NAMESPACE || true)
[[ -z $literal ]] || fail "a literal inline namespace:"$'\n'"$literal"
echo "$headers headers open the generated namespace"

functions=$(grep -n 'std::function\|<functional>' "$src"/sdk/include/flipper/sdk/*.hpp |
  grep -v '///' || true)
[[ -z $functions ]] || fail "std::function in the SDK's interface:"$'\n'"$functions"
echo "no std::function in the SDK headers"
