#pragma once
/// @file original_text.hpp
/// The original Flipper's printed interpretations (`pretty` in original-answers.jsonl and in the
/// probes) rewritten into Flipper's canonical text (core-language §7), so the program can be read
/// with sdk::read_canonical and compared structurally (sdk::equal): `N.0` -> `N`, prefix
/// arithmetic `(+ (number 2) (number 1))` -> `{2 + 1}`, and the misprinted
/// `{item at {is red}room3}` -> `{item {is red} at room3}`. Nested sequences need no rewriting:
/// sdk::make flattens them when the text is read. The one implementation, used by the replay,
/// the canonical and executor tests and the executor benchmark.

#include <string>

namespace flipper::corpus {

std::string normalize_original_pretty(std::string text);

}  // namespace flipper::corpus
