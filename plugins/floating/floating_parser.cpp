#include "floating_parser.hpp"

#include "flipper/sdk/errors.hpp"

namespace flipper::floating {

FloatingParser::FloatingParser(const sdk::Params& params) {
  if (params.has("beam")) options_.beam = static_cast<int>(params.get_int("beam"));
  if (params.has("floating_beam"))
    options_.floating_beam = static_cast<int>(params.get_int("floating_beam"));
  if (params.has("max_skips")) options_.max_skips = static_cast<int>(params.get_int("max_skips"));
  if (params.has("skip_cost")) options_.skip_cost = params.get_double("skip_cost");
  if (params.has("rule_index")) options_.rule_index = params.get_bool("rule_index");
}

sdk::ParamSchema FloatingParser::schema() {
  sdk::ParamSchema s;
  s.add_int("beam", 50, "exact derivations kept per (category, span), best first by score", 1,
            100000);
  s.add_int("floating_beam", 10, "derivations that skip words kept per (category, span)", 1,
            100000);
  s.add_int("max_skips", 4, "words one derivation may leave out (0: parse exactly as chart)", 0, 8);
  s.add_double("skip_cost", 1.0, "score subtracted per skipped word", 0.0, 1000.0);
  s.add_bool("rule_index", true,
             "try only the rules the rule index selects for each position (docs/naturalization.md "
             "§2); false tries every rule whose first symbol fits: the same parses, slower with "
             "large lexicons (the oracle of the index tests)");
  return s;
}

void FloatingParser::do_set_grammar(std::shared_ptr<const sdk::Grammar> grammar) {
  index_.reset(std::move(grammar));
}
void FloatingParser::do_add_rule(sdk::RulePtr rule) {
  index_.add(std::move(rule));
}
void FloatingParser::do_remove_rule(const std::string& id) {
  index_.remove(id);
}

sdk::ParseResult FloatingParser::do_parse(const sdk::ParseRequest& request) const {
  if (request.scorer == nullptr)
    throw sdk::Error(sdk::codes::kBadRequest, "floating parser: the parse request has no scorer");
  if (request.tokens.empty()) return {};
  Options o = options_;
  if (request.beam > 0) o.beam = request.beam;
  return parse_floating(index_, request, o);
}

bool skippable(const std::string& token) {
  if (token.empty()) return false;
  const auto c = static_cast<unsigned char>(token[0]);
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c >= 0x80;
}

}  // namespace flipper::floating

FLIPPER_PLUGIN(flipper::floating::FloatingParser, parser, "floating", FLIPPER_PLUGIN_VERSION,
               "Skip-tolerant chart parser (SEMPRE FloatingParser style): skipped words cost")
