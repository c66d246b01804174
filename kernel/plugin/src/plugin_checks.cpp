// Plugin answers checked where they enter the kernel (docs/plugins-untrusted.md): the plugin
// call through its PluginRef, then the SDK's one check of the answer
// (flipper/sdk/answer_check.hpp).
#include "flipper/kernel/plugin_checks.hpp"

#include "flipper/sdk/answer_check.hpp"
#include "flipper/sdk/errors.hpp"
#include "flipper/sdk/parser.hpp"
#include "flipper/sdk/planner.hpp"

namespace flipper::kernel {

using sdk::Cell;

void throw_invalid_output(const PluginId& plugin, const char* code, const std::string& what) {
  throw sdk::Error(code, plugin.label() + ": " + what);
}

sdk::PathResult checked_plan(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, const sdk::PathRequest& request,
                             const sdk::StopCondition& stop) {
  sdk::PathResult r =
      planner.call("plan", [&](const sdk::Planner& p) { return p.plan(geometry, request, stop); });
  if (auto v = sdk::path_violation(geometry, request, r))
    throw_invalid_output(planner.id(), sdk::codes::kInvalidPlan, *v);
  return r;
}

sdk::TourResult checked_tour(const PluginRef<const sdk::Planner>& planner,
                             const sdk::Geometry& geometry, Cell start,
                             const std::vector<Cell>& points, const sdk::StopCondition& stop) {
  sdk::TourResult t = planner.call(
      "tour", [&](const sdk::Planner& p) { return p.tour(geometry, start, points, stop); });
  if (auto v = sdk::tour_violation(points.size(), t))
    throw_invalid_output(planner.id(), sdk::codes::kInvalidPlan, *v);
  return t;
}

sdk::ParseResult checked_parse(const PluginRef<const sdk::Parser>& parser,
                               const sdk::ParseRequest& request) {
  sdk::ParseResult r = parser.call("parse", [&](const sdk::Parser& p) { return p.parse(request); });
  if (auto v = sdk::parse_violation(request, r))
    throw_invalid_output(parser.id(), v->code, v->what);
  return r;
}

}  // namespace flipper::kernel
