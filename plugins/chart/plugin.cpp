#include "chart_parser.hpp"

namespace flipper::chart {

ChartParser::ChartParser(const sdk::Params& params) {
  if (params.has("beam")) beam_ = static_cast<int>(params.get_int("beam"));
}

sdk::ParamSchema ChartParser::schema() {
  sdk::ParamSchema s;
  s.add_int("beam", 50, "derivations kept per (category, span), best first by score", 1, 100000);
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

FLIPPER_PLUGIN(flipper::chart::ChartParser, parser, "chart", "1.0.0",
               "Exhaustive CKY-style chart parser over core and induced rules")
