#pragma once
// The `floating` parser: a skip-tolerant chart parser in the manner of SEMPRE's FloatingParser.
// Derivations may leave out words that no rule of theirs covers: each skipped word is a derivation
// node of its own (rule `floating:skip:<word>`, `$C -> $C`, so the scorer sees it as a feature)
// and costs `skip_cost`. Exact derivations are built exactly as by `chart` (the toolkit's chart
// run, same rule index, same beam) and kept apart from floating ones, so every exact candidate is
// the chart's; a floating derivation is never core-only (it is not the core reading of what was
// typed), so every exact core candidate ranks first and a definition's head that only floats is
// not `head_is_core`.
#include "flipper/toolkit/chart_parser.hpp"

namespace flipper::plugins::floating {

struct SkipOptions {
  int floating_beam = 10;  ///< floating derivations per (category, span)
  int max_skips = 4;       ///< words a derivation may leave out
  double skip_cost = 1.0;  ///< subtracted from the score per skipped word
};

class FloatingParser : public toolkit::IndexedParser {
 public:
  explicit FloatingParser(const sdk::Params& params);
  static sdk::ParamSchema schema();

 protected:
  sdk::ParseResult parse_chart(const sdk::ParseRequest& request, int beam) const override;

 private:
  SkipOptions skips_;
};

/// Whether a token may be skipped: a word (starts with a letter or a non-ASCII byte), never
/// brackets, separators, operators or numbers, which carry the structure of core language.
bool skippable(const std::string& token);

/// One parse (floating_run.cpp): the toolkit's chart run with the skip logic added.
sdk::ParseResult parse_floating(const toolkit::RuleIndex& index, const sdk::ParseRequest& request,
                                int beam, bool rule_index, const SkipOptions& options);

}  // namespace flipper::plugins::floating
