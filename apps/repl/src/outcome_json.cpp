// JSON trees of execution results for the terminal front ends (outcome_json.hpp).
#include "flipper/repl/outcome_json.hpp"

#include <nlohmann/json.hpp>

namespace flipper::repl {

Json cell_json(const sdk::Cell& c, int dims) {
  Json p = Json::array({c.x, c.y});
  if (dims == 3) p.push_back(c.z);
  return p;
}

Json item_json(const sdk::ItemInfo& item) {
  return Json{{"id", item.id}, {"color", item.color}, {"shape", item.shape}};
}

Json step_json(const sdk::TraceStep& step, int dims) {
  switch (step.act) {
    case sdk::TraceStep::Act::move:
      return Json{{"act", "move"}, {"to", cell_json(step.cell, dims)}};
    case sdk::TraceStep::Act::pick:
    case sdk::TraceStep::Act::drop:
      return Json{{"act", step.act == sdk::TraceStep::Act::pick ? "pick" : "drop"},
                  {"at", cell_json(step.cell, dims)},
                  {"item", item_json(step.item)}};
  }
  return Json();
}

Json trace_json(const std::vector<sdk::TraceStep>& trace, int dims) {
  Json out = Json::array();
  for (const auto& s : trace) out.push_back(step_json(s, dims));
  return out;
}

Json strings_json(const std::vector<std::string>& values) {
  Json out = Json::array();
  for (const auto& v : values) out.push_back(v);
  return out;
}

Json error_json(const std::string& code, const std::string& message) {
  return Json{{"code", code}, {"message", message}};
}
Json error_json(const sdk::Error& error) {
  return error_json(error.code(), error.what());
}

Json outcome_json(const sdk::Outcome& outcome, int dims) {
  Json j{{"trace", trace_json(outcome.trace, dims)},
         {"warnings", strings_json(outcome.warnings)},
         {"realizable", outcome.realizable && !outcome.error}};
  if (outcome.error)
    j["error"] = error_json(outcome.error_code.value_or(sdk::codes::kExecution), *outcome.error);
  return j;
}

}  // namespace flipper::repl
