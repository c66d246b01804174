#pragma once
// The `floating` parser: a skip-tolerant chart parser in the manner of SEMPRE's FloatingParser.
// Derivations may leave out words that no rule of theirs covers: each skipped word is a derivation
// node of its own (rule `floating:skip:<word>`, `$C -> $C`, so the scorer sees it as a feature)
// and costs `skip_cost`. Exact derivations are built exactly as by `chart` (same rule index, same
// beam) and kept apart from floating ones, so every exact candidate is the chart's; a floating
// derivation is never core-only (it is not the core reading of what was typed), so every exact
// core candidate ranks first and a definition's head that only floats is not `head_is_core`.
#include "flipper/sdk/parser.hpp"
#include "rule_index.hpp"

namespace flipper::floating {

struct Options {
  int beam = 50;           ///< exact derivations per (category, span), as chart's beam
  int floating_beam = 10;  ///< floating derivations per (category, span)
  int max_skips = 4;       ///< words a derivation may leave out
  double skip_cost = 1.0;  ///< subtracted from the score per skipped word
  bool rule_index = true;  ///< false: try every rule whose first symbol fits (the index's oracle)
};

class FloatingParser : public sdk::Parser {
 public:
  explicit FloatingParser(const sdk::Params& params);
  static sdk::ParamSchema schema();

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar> grammar) override;
  void do_add_rule(sdk::RulePtr rule) override;
  void do_remove_rule(const std::string& id) override;
  sdk::ParseResult do_parse(const sdk::ParseRequest& request) const override;

 private:
  chart::RuleIndex index_;
  Options options_;
};

/// Whether a token may be skipped: a word (starts with a letter or a non-ASCII byte), never
/// brackets, separators, operators or numbers, which carry the structure of core language.
bool skippable(const std::string& token);

/// One parse (floating_run.cpp).
sdk::ParseResult parse_floating(const chart::RuleIndex& index, const sdk::ParseRequest& request,
                                const Options& options);

}  // namespace flipper::floating
