#pragma once
/// @file original_formula.hpp
/// The original Flipper's logical forms — the `formula` of its candidates, of `:accept` and of
/// definition bodies, e.g. `(: visitArea (call filterArea world (items?property red)))` — read
/// into Flipper's canonical text (core-language §7), so that sdk::read_canonical turns them into
/// programs. The names of the original's functions map one to one onto the core language's
/// constructs (core-language §3.6 maps the categories); the text is fully braced, as `render`
/// writes it. Used by the /sempre endpoint (docs/sempre.md), whose clients send the original's
/// formulas back in accepts and definitions, and by the corpus tests.

#include <string>
#include <string_view>

#include "flipper/sdk/ast.hpp"

namespace flipper::corpus {

/// Whether `text` looks like one of the original's formulas (a parenthesised form) rather than
/// canonical text (which starts with `{`).
bool is_original_formula(std::string_view text);

/// The canonical text of an original formula. Throws sdk::Error(bad_program) naming the part
/// that does not read (an unknown function, a wrong number of arguments, a numeric quantity
/// other than one or every, NaN, nesting deeper than 256 levels).
std::string original_formula_to_canonical(std::string_view formula);

/// The program a formula names: the original's notation (read as above) or canonical text.
/// Throws sdk::Error naming the formula when it does not read.
sdk::Program read_formula(std::string_view formula);

}  // namespace flipper::corpus
