#pragma once
/// @file original_text.hpp
/// The original Flipper's printed interpretations (`pretty` in original-answers.jsonl) rewritten
/// into Flipper's canonical text (core-language §7), so the accepted program can be read with
/// sdk::read_canonical and compared with our candidates structurally (sdk::equal).
/// Same rewriting as tests/core/original_text.hpp (`N.0` -> `N`, prefix arithmetic -> infix,
/// the misprinted `{item at {filter}loc}`).

#include <string>

namespace flipper::kernel::replay {

std::string normalize_original_pretty(std::string text);

}  // namespace flipper::kernel::replay
