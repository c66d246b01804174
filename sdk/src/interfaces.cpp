// Out-of-line destructors and small helpers: they anchor each interface's vtable and typeinfo in
// libflipper_sdk.so, so kernel and plugins share one copy (dynamic_cast and catch work across).
#include <cstring>

#include "flipper/sdk/sdk.hpp"

namespace flipper::sdk {
inline namespace v1 {

Plugin::~Plugin() = default;
World::~World() = default;
Planner::~Planner() = default;
Parser::~Parser() = default;
Scorer::~Scorer() = default;
IncrementalScorer::~IncrementalScorer() = default;
Rewriter::~Rewriter() = default;
Similarity::~Similarity() = default;
ContinuousSpace::~ContinuousSpace() = default;
ExecutionService::~ExecutionService() = default;

namespace {
struct KindEntry {
  PluginKind kind;
  const char* name;
};
constexpr KindEntry kKinds[] = {
    {PluginKind::world, "world"},       {PluginKind::planner, "planner"},
    {PluginKind::parser, "parser"},     {PluginKind::scorer, "scorer"},
    {PluginKind::rewriter, "rewriter"}, {PluginKind::similarity, "similarity"},
};
}  // namespace

const char* kind_name(PluginKind kind) {
  for (const auto& k : kKinds)
    if (k.kind == kind) return k.name;
  return "unknown";
}

bool parse_kind(const char* name, PluginKind& out) {
  for (const auto& k : kKinds) {
    if (std::strcmp(k.name, name) == 0) {
      out = k.kind;
      return true;
    }
  }
  return false;
}

const char* to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::found: return "found";
    case PlanStatus::no_path: return "no_path";
    case PlanStatus::stopped: return "stopped";
    case PlanStatus::invalid: return "invalid";
  }
  return "unknown";
}

const char* to_string(RuleOrigin o) {
  switch (o) {
    case RuleOrigin::core: return "core";
    case RuleOrigin::simple: return "simple";
    case RuleOrigin::best: return "best";
    case RuleOrigin::alignment: return "alignment";
    case RuleOrigin::rewriting: return "rewriting";
  }
  return "unknown";
}

std::size_t Rule::arity() const {
  std::size_t n = 0;
  for (const auto& s : rhs)
    if (s.type == Symbol::Type::category) ++n;
  return n;
}

}  // namespace v1
}  // namespace flipper::sdk
