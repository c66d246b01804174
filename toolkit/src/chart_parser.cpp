#include "flipper/toolkit/chart_parser.hpp"

#include "flipper/sdk/errors.hpp"
#include "flipper/toolkit/chart_run.hpp"

namespace flipper::toolkit {

void IndexedParser::do_set_grammar(std::shared_ptr<const sdk::Grammar> grammar) {
  index_.reset(std::move(grammar));
}
void IndexedParser::do_add_rule(sdk::RulePtr rule) {
  index_.add(std::move(rule));
}
void IndexedParser::do_remove_rule(const std::string& id) {
  index_.remove(id);
}

sdk::ParseResult IndexedParser::do_parse(const sdk::ParseRequest& request) const {
  if (request.scorer == nullptr)
    throw sdk::Error(sdk::codes::kBadRequest, name_ + " parser: the parse request has no scorer");
  if (request.tokens.empty()) return {};
  if (request.tokens.size() > options_.max_tokens)
    throw sdk::Error(
        sdk::codes::kInputTooLong,
        name_ + " parser: " + std::to_string(request.tokens.size()) +
            " tokens; the limit is max_tokens = " + std::to_string(options_.max_tokens));
  return parse_chart(request, request.beam > 0 ? request.beam : options_.beam);
}

sdk::ParseResult ChartParser::parse_chart(const sdk::ParseRequest& request, int beam) const {
  return ExactChartRun(index(), request, beam, !options().rule_index).run();
}

}  // namespace flipper::toolkit
