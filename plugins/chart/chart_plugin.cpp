// The `chart` parser plugin: the toolkit's exhaustive CKY-style chart parser
// (flipper/toolkit/chart_parser.hpp, docs/naturalization.md §2) with its parameters.
#include "flipper/sdk/plugin.hpp"
#include "flipper/toolkit/chart_parser.hpp"

namespace flipper::plugins::chart {

class Chart : public toolkit::ChartParser {
 public:
  explicit Chart(const sdk::Params& params) : ChartParser(toolkit::ChartOptions::from(params)) {}
};

}  // namespace flipper::plugins::chart

FLIPPER_PLUGIN(flipper::plugins::chart::Chart, parser, "chart", FLIPPER_PLUGIN_VERSION,
               "Exhaustive CKY-style chart parser over core and induced rules")
