#pragma once
/// @file canonical.hpp
/// The lexer (core-language §2) and the canonical text of programs (§7) in both directions.
/// The reader accepts exactly what `render` produces (fully braced canonical text; whitespace
/// is free; both `is c` and `has color c`) and is deterministic; free user input goes through
/// the semantic parser plugin instead.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "flipper/sdk/ast.hpp"
#include "flipper/sdk/export.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

/// Splits an utterance into tokens per core-language §2 (lower-cased).
FLIPPER_SDK_API std::vector<std::string> tokenize(std::string_view text);
/// The numeric value of a number token (decimal literal or number word, -99..99), if it is one.
FLIPPER_SDK_API std::optional<double> number_value(std::string_view token);

/// Canonical text, e.g. `{{visit {world containing item {is red}}};{pick item {is red}}}`.
/// Numbers print as integers when integral (`3`, `-1`), else in shortest decimal form. Holes
/// print as `$1`, `$2`, ... (index + 1).
FLIPPER_SDK_API std::string render(const Program& p);

/// Reads canonical text of the given sort back into a program. Throws Error(bad_program) with
/// the position of the first problem.
FLIPPER_SDK_API Program read_canonical(std::string_view text, Sort sort = Sort::Action);

/// Reads a rule template: canonical text whose `$1`, `$2`, ... holes have the given sorts
/// (hole_sorts[i] for `$i+1`).
FLIPPER_SDK_API Program read_template(std::string_view text, Sort sort,
                                      const std::vector<Sort>& hole_sorts);

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
