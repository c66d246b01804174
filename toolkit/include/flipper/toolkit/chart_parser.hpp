#pragma once
/// @file chart_parser.hpp
/// The toolkit's chart parsers (docs/naturalization.md §2): the options and parameters every chart
/// parser shares, `IndexedParser` (a parser whose grammar and rule changes are kept in a
/// RuleIndex, with the checks every parse makes) and `ChartParser`, the exhaustive chart parser
/// itself, which the `chart` plugin publishes. A parser that changes the parse (the `floating`
/// plugin) derives from IndexedParser and runs its own ChartRun (chart_run.hpp).
#include <memory>
#include <string>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/toolkit/rule_index.hpp"

namespace flipper::toolkit {

/// The parameters of ChartOptions, for a chart parser plugin's schema.
namespace chart_params {
inline constexpr sdk::param::Int<int> kBeam{
    "beam", 50, 1, 100000, "exact derivations kept per (category, span), best first by score"};
inline constexpr sdk::param::Int<std::size_t> kMaxTokens{
    "max_tokens", 4096, 1, 65534,
    "longest token sequence parsed (the chart has (n+1)^2 cells); longer: input_too_long"};
inline constexpr sdk::param::Bool kRuleIndex{
    "rule_index", true,
    "try only the rules the rule index selects for each position (docs/naturalization.md §2); "
    "false tries every rule whose first symbol fits: the same parses, slower with large "
    "lexicons (the oracle of the index tests)"};
}  // namespace chart_params

struct ChartOptions {
  int beam = chart_params::kBeam.def;  ///< a request's own beam (> 0) overrides it
  std::size_t max_tokens = chart_params::kMaxTokens.def;
  bool rule_index = chart_params::kRuleIndex.def;  ///< false: the unindexed matcher

  static ChartOptions from(const sdk::Params& p) {
    return {sdk::param::get(p, chart_params::kBeam), sdk::param::get(p, chart_params::kMaxTokens),
            sdk::param::get(p, chart_params::kRuleIndex)};
  }
  /// Adds the three parameters to a schema.
  static void declare(sdk::ParamSchema& s) {
    sdk::param::add(s, chart_params::kBeam);
    sdk::param::add(s, chart_params::kMaxTokens);
    sdk::param::add(s, chart_params::kRuleIndex);
  }
};

/// A parser over a RuleIndex: set_grammar, add_rule and remove_rule keep the index; parse()
/// checks the request (a scorer is required; no tokens: no candidates; more than max_tokens:
/// input_too_long) and hands it to parse_chart with the beam to use.
class IndexedParser : public sdk::Parser {
 public:
  const ChartOptions& options() const { return options_; }

 protected:
  /// `name` prefixes error messages ("chart parser: ...").
  IndexedParser(std::string name, ChartOptions options)
      : name_(std::move(name)), options_(options) {}

  virtual sdk::ParseResult parse_chart(const sdk::ParseRequest& request, int beam) const = 0;
  const RuleIndex& index() const { return index_; }

  void do_set_grammar(std::shared_ptr<const sdk::Grammar> grammar) override;
  void do_add_rule(sdk::RulePtr rule) override;
  void do_remove_rule(const std::string& id) override;
  sdk::ParseResult do_parse(const sdk::ParseRequest& request) const final;

 private:
  std::string name_;
  ChartOptions options_;
  RuleIndex index_;
};

/// The exhaustive bottom-up chart parser (ExactChartRun).
class ChartParser : public IndexedParser {
 public:
  explicit ChartParser(ChartOptions options = {}) : IndexedParser("chart", options) {}
  /// The schema of ChartOptions' parameters.
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s;
    ChartOptions::declare(s);
    return s;
  }

 protected:
  sdk::ParseResult parse_chart(const sdk::ParseRequest& request, int beam) const override;
};

}  // namespace flipper::toolkit
