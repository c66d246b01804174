#include <nlohmann/json.hpp>

#include "flipper/kernel/protocol.hpp"
#include "flipper/toolkit/json/json_writer.hpp"

namespace flipper::kernel::protocol {

using toolkit::json::JsonWriter;

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

// The bytes of step_json(...).dump() without the tree: members in the tree's (sorted) key order,
// strings escaped by the writer (nlohmann's escaping), integers as nlohmann writes them.
void append_trace_text(std::string& out, const std::vector<sdk::TraceStep>& trace, int dims) {
  const auto cell = [&](const sdk::Cell& c) {
    out += '[';
    JsonWriter::append_integer(out, c.x);
    out += ',';
    JsonWriter::append_integer(out, c.y);
    if (dims == 3) {
      out += ',';
      JsonWriter::append_integer(out, c.z);
    }
    out += ']';
  };
  out += '[';
  for (std::size_t i = 0; i < trace.size(); ++i) {
    const sdk::TraceStep& s = trace[i];
    if (i != 0) out += ',';
    if (s.act == sdk::TraceStep::Act::move) {
      out += R"({"act":"move","to":)";
      cell(s.cell);
      out += '}';
      continue;
    }
    out += s.act == sdk::TraceStep::Act::pick ? R"({"act":"pick","at":)" : R"({"act":"drop","at":)";
    cell(s.cell);
    out += R"(,"item":{"color":)";
    JsonWriter::append_string(out, s.item.color);
    out += R"(,"id":)";
    JsonWriter::append_integer(out, s.item.id);
    out += R"(,"shape":)";
    JsonWriter::append_string(out, s.item.shape);
    out += "}}";
  }
  out += ']';
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

}  // namespace flipper::kernel::protocol
