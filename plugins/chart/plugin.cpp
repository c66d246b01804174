#include "chart_parser.hpp"

namespace flipper::chart {

ChartParser::ChartParser(const sdk::Params& params) {
  if (params.has("beam")) beam_ = static_cast<int>(params.get_int("beam"));
  if (params.has("max_tokens"))
    max_tokens_ = static_cast<std::size_t>(params.get_int("max_tokens"));
  if (params.has("rule_index")) rule_index_ = params.get_bool("rule_index");
}

sdk::ParamSchema ChartParser::schema() {
  sdk::ParamSchema s;
  s.add_int("beam", 50, "derivations kept per (category, span), best first by score", 1, 100000);
  s.add_int("max_tokens", 4096,
            "longest token sequence parsed (the chart has (n+1)^2 cells); longer: input_too_long",
            1, 65534);
  s.add_bool("rule_index", true,
             "try only the rules the rule index selects for each position (docs/naturalization.md "
             "§2); false tries every rule whose first symbol fits: the same parses, slower with "
             "large lexicons (the oracle of the index tests)");
  return s;
}

void ChartParser::do_set_grammar(std::shared_ptr<const sdk::Grammar> grammar) {
  index_.reset(std::move(grammar));
}
void ChartParser::do_add_rule(sdk::RulePtr rule) {
  index_.add(std::move(rule));
}
void ChartParser::do_remove_rule(const std::string& id) {
  index_.remove(id);
}

}  // namespace flipper::chart

FLIPPER_PLUGIN(flipper::chart::ChartParser, parser, "chart", FLIPPER_PLUGIN_VERSION,
               "Exhaustive CKY-style chart parser over core and induced rules")
