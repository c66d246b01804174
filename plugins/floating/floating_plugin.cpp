#include "floating_parser.hpp"

#include "flipper/sdk/plugin.hpp"

namespace flipper::plugins::floating {

namespace {

namespace param = sdk::param;

constexpr param::Int<int> kFloatingBeam{"floating_beam", 10, 1, 100000,
                                        "derivations that skip words kept per (category, span)"};
constexpr param::Int<int> kMaxSkips{
    "max_skips", 4, 0, 8, "words one derivation may leave out (0: parse exactly as chart)"};
constexpr param::Double kSkipCost{"skip_cost", 1.0, 0.0, 1000.0,
                                  "score subtracted per skipped word"};

}  // namespace

FloatingParser::FloatingParser(const sdk::Params& params)
    : IndexedParser("floating", toolkit::ChartOptions::from(params)),
      skips_{param::get(params, kFloatingBeam), param::get(params, kMaxSkips),
             param::get(params, kSkipCost)} {}

sdk::ParamSchema FloatingParser::schema() {
  sdk::ParamSchema s;
  toolkit::ChartOptions::declare(s);
  param::add(s, kFloatingBeam);
  param::add(s, kMaxSkips);
  param::add(s, kSkipCost);
  return s;
}

sdk::ParseResult FloatingParser::parse_chart(const sdk::ParseRequest& request, int beam) const {
  return parse_floating(index(), request, beam, options().rule_index, skips_);
}

bool skippable(const std::string& token) {
  if (token.empty()) return false;
  const auto c = static_cast<unsigned char>(token[0]);
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c >= 0x80;
}

}  // namespace flipper::plugins::floating

FLIPPER_PLUGIN(flipper::plugins::floating::FloatingParser, parser, "floating",
               FLIPPER_PLUGIN_VERSION,
               "Skip-tolerant chart parser (SEMPRE FloatingParser style): skipped words cost")
