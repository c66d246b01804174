// example_parser: the toolkit's chart parser (flipper/toolkit/chart_parser.hpp: the exhaustive
// parse of docs/naturalization.md §2 with its rule index, beam and limits) that first replaces
// words by their synonyms, so that with `go=visit` "go room1" parses as "visit room1". A parser of
// your own can change parse_chart as here, or derive from toolkit::IndexedParser and run a
// toolkit::ChartRun of its own (flipper/toolkit/chart_run.hpp).
#include <flipper/sdk/config_handles.hpp>
#include <flipper/sdk/errors.hpp>
#include <flipper/sdk/plugin.hpp>
#include <flipper/toolkit/chart_parser.hpp>

#include <map>
#include <string>

namespace example_parser {

namespace sdk = flipper::sdk;
namespace toolkit = flipper::toolkit;
namespace param = flipper::sdk::param;

constexpr param::TextList<2> kSynonyms{
    "synonyms", {"go=visit", "grab=pick"}, "word=replacement pairs applied before parsing"};

class ExampleParser : public toolkit::ChartParser {
 public:
  explicit ExampleParser(const sdk::Params& p) : ChartParser(toolkit::ChartOptions::from(p)) {
    for (const std::string& pair : param::get(p, kSynonyms)) {
      const auto eq = pair.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == pair.size())
        throw sdk::Error(sdk::codes::kBadConfig,
                         "synonyms: '" + pair + "' is not word=replacement");
      synonyms_[pair.substr(0, eq)] = pair.substr(eq + 1);
    }
  }

  // The chart parser's parameters (beam, max_tokens, rule_index) and this one.
  static sdk::ParamSchema schema() {
    sdk::ParamSchema s = ChartParser::schema();
    param::add(s, kSynonyms);
    return s;
  }

 protected:
  sdk::ParseResult parse_chart(const sdk::ParseRequest& request, int beam) const override {
    if (synonyms_.empty()) return ChartParser::parse_chart(request, beam);
    sdk::ParseRequest replaced = request;
    for (auto& token : replaced.tokens)
      if (auto it = synonyms_.find(token); it != synonyms_.end()) token = it->second;
    replaced.context.tokens = nullptr;  // features read the replaced tokens
    return ChartParser::parse_chart(replaced, beam);
  }

 private:
  std::map<std::string, std::string> synonyms_;
};

}  // namespace example_parser

FLIPPER_PLUGIN(example_parser::ExampleParser, parser, "example_parser", FLIPPER_PLUGIN_VERSION,
               "The toolkit's chart parser, reading synonyms of core words")
