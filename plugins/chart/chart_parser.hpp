#pragma once
// The `chart` parser: exhaustive bottom-up CKY-style chart parsing (docs/naturalization.md §2).
#include "flipper/sdk/parser.hpp"
#include "rule_index.hpp"

namespace flipper::chart {

class ChartParser : public sdk::Parser {
 public:
  explicit ChartParser(const sdk::Params& params);
  static sdk::ParamSchema schema();

 protected:
  void do_set_grammar(std::shared_ptr<const sdk::Grammar> grammar) override;
  void do_add_rule(sdk::RulePtr rule) override;
  void do_remove_rule(const std::string& id) override;
  sdk::ParseResult do_parse(const sdk::ParseRequest& request) const override;

 private:
  RuleIndex index_;
  int beam_ = 50;
  std::size_t max_tokens_ = 4096;  // the chart has (n + 1)^2 cells
  bool rule_index_ = true;         // false: the unindexed matcher (StartRules' oracle)
};

}  // namespace flipper::chart
