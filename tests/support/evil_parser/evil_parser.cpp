// evil_parser: the chart parser (flipper/toolkit/chart_parser.hpp) misbehaving on purpose, for
// the tests of what the kernel checks and contains (docs/plugins-untrusted.md). In mode `ok` it
// parses as `chart` does; every other mode misbehaves on a parse whose tokens include `on_token`
// (empty: every parse) and parses correctly otherwise:
//   throw   throws std::runtime_error from parse()
//   segv    dereferences a null pointer
//   abort   calls std::abort()
//   span    answers the correct candidates with the first one's derivation ending one token past
//           the utterance
//   nan     answers the correct candidates with the first one's score NaN
// Tests build it with flipper_add_plugin (tests/support/evil_parser/CMakeLists.txt) and select it
// with --set plugin_paths=[build/tests/plugins/evil] --set parser.plugin=evil_parser.
#include <algorithm>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "flipper/sdk/config_handles.hpp"
#include "flipper/sdk/plugin.hpp"
#include "flipper/toolkit/chart_parser.hpp"

namespace evil_parser {
namespace {

namespace sdk = flipper::sdk;
namespace param = flipper::sdk::param;

enum class Mode { ok, throws, segv, abort_, span, nan };
constexpr param::Choice<Mode, 6> kMode{
    "mode",
    Mode::ok,
    {"ok", "throw", "segv", "abort", "span", "nan"},
    "how to misbehave (tests/support/evil_parser/evil_parser.cpp)"};
constexpr param::Text kOnToken{"on_token", "",
                               "misbehave only on utterances with this token (empty: every one)"};

class EvilParser final : public flipper::toolkit::ChartParser {
 public:
  explicit EvilParser(const sdk::Params& p)
      : ChartParser(flipper::toolkit::ChartOptions::from(p)),
        mode_(param::get(p, kMode)),
        on_token_(param::get(p, kOnToken)) {}
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s = ChartParser::schema();
    param::add(s, kMode);
    param::add(s, kOnToken);
    return s;
  }

 protected:
  sdk::ParseResult parse_chart(const sdk::ParseRequest& request, int beam) const override {
    sdk::ParseResult r = ChartParser::parse_chart(request, beam);
    if (mode_ == Mode::ok ||
        (!on_token_.empty() && std::find(request.tokens.begin(), request.tokens.end(), on_token_) ==
                                   request.tokens.end()))
      return r;
    switch (mode_) {
      case Mode::throws:
        throw std::runtime_error("evil_parser: thrown on purpose");
      case Mode::segv: {
        volatile int* null = nullptr;
        *null = 1;  // NOLINT: a crash on purpose
        return r;
      }
      case Mode::abort_:
        std::abort();
      case Mode::span:
        if (!r.candidates.empty() && !r.candidates[0].derivations.empty()) {
          auto d = std::make_shared<sdk::Derivation>(*r.candidates[0].derivations[0]);
          d->end += 1;
          r.candidates[0].derivations[0] = d;
        }
        return r;
      case Mode::nan:
        if (!r.candidates.empty()) r.candidates[0].score = std::numeric_limits<double>::quiet_NaN();
        return r;
      case Mode::ok:
        return r;
    }
    return r;
  }

 private:
  Mode mode_;
  std::string on_token_;
};

}  // namespace
}  // namespace evil_parser

FLIPPER_PLUGIN(evil_parser::EvilParser, parser, "evil_parser", FLIPPER_PLUGIN_VERSION,
               "A chart parser that misbehaves on purpose (tests only)")
