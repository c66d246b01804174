// Out-of-line destructors and small helpers: they anchor each interface's vtable and typeinfo in
// libflipper_sdk.so, so kernel and plugins share one copy (dynamic_cast and catch work across).
#include <algorithm>
#include <cstring>
#include <numeric>

#include "flipper/sdk/frontend.hpp"
#include "flipper/sdk/sdk.hpp"

namespace flipper::sdk {
inline namespace FLIPPER_ABI_NAMESPACE {

Plugin::~Plugin() = default;
World::~World() = default;
Planner::~Planner() = default;
Parser::~Parser() = default;
Scorer::~Scorer() = default;
IncrementalScorer::~IncrementalScorer() = default;
WeightValues::~WeightValues() = default;
StateWeights::~StateWeights() = default;
Rewriter::~Rewriter() = default;
Similarity::~Similarity() = default;
ContinuousSpace::~ContinuousSpace() = default;
ExecutionService::~ExecutionService() = default;
UsageCounters::~UsageCounters() = default;

namespace {
struct KindEntry {
  PluginKind kind;
  const char* name;
};
constexpr KindEntry kPluginKinds[] = {
    {PluginKind::world, "world"},       {PluginKind::planner, "planner"},
    {PluginKind::parser, "parser"},     {PluginKind::scorer, "scorer"},
    {PluginKind::rewriter, "rewriter"}, {PluginKind::similarity, "similarity"},
    {PluginKind::frontend, "frontend"},
};
}  // namespace

const char* kind_name(PluginKind kind) {
  for (const auto& k : kPluginKinds)
    if (k.kind == kind) return k.name;
  return "unknown";
}

bool parse_kind(const char* name, PluginKind& out) {
  for (const auto& k : kPluginKinds) {
    if (std::strcmp(k.name, name) == 0) {
      out = k.kind;
      return true;
    }
  }
  return false;
}

const char* to_string(StopCause c) {
  switch (c) {
    case StopCause::none:
      return "none";
    case StopCause::cancelled:
      return "cancelled";
    case StopCause::cpu_budget:
      return "cpu_budget";
    case StopCause::wall_backstop:
      return "wall_backstop";
  }
  return "unknown";
}

const char* to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::found:
      return "found";
    case PlanStatus::no_path:
      return "no_path";
    case PlanStatus::stopped:
      return "stopped";
    case PlanStatus::invalid:
      return "invalid";
  }
  return "unknown";
}

PathResult Planner::plan(const Geometry& geometry, const PathRequest& request,
                         const StopCondition& stop) const {
  PathResult r;
  if (request.goals == nullptr || request.goals->empty()) {
    r.status = PlanStatus::invalid;
    r.message = "the goal set is empty";
    return r;
  }
  if (!geometry.in_bounds(request.start)) {
    r.status = PlanStatus::invalid;
    r.message = "start " + to_string(request.start, geometry.dims()) + " is outside the bounds";
    return r;
  }
  if (stop.expired()) {
    r.status = PlanStatus::stopped;
    r.message = "stopped before planning";
    return r;
  }
  return do_plan(geometry, request, stop);
}

TourResult Planner::tour(const Geometry& geometry, Cell start, const std::vector<Cell>& points,
                         const StopCondition& stop) const {
  TourResult t;
  if (points.empty()) return t;  // found, nothing to order
  if (stop.expired()) {
    t.status = PlanStatus::stopped;
    t.order.resize(points.size());
    std::iota(t.order.begin(), t.order.end(), std::size_t{0});
    std::stable_sort(t.order.begin(), t.order.end(),
                     [&](std::size_t a, std::size_t b) { return points[a] < points[b]; });
    return t;
  }
  return do_tour(geometry, start, points, stop);
}

const char* to_string(RuleOrigin o) {
  switch (o) {
    case RuleOrigin::core:
      return "core";
    case RuleOrigin::simple:
      return "simple";
    case RuleOrigin::best:
      return "best";
    case RuleOrigin::alignment:
      return "alignment";
    case RuleOrigin::rewriting:
      return "rewriting";
  }
  return "unknown";
}

std::size_t Rule::arity() const {
  std::size_t n = 0;
  for (const auto& s : rhs)
    if (s.type == Symbol::Type::category) ++n;
  return n;
}

}  // namespace FLIPPER_ABI_NAMESPACE
}  // namespace flipper::sdk
