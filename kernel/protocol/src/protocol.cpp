#include <nlohmann/json.hpp>

#include "flipper/kernel/protocol.hpp"
#include "flipper/toolkit/json/json_writer.hpp"

namespace flipper::kernel::protocol {

using toolkit::json::JsonWriter;

namespace {
[[noreturn]] void bad(const std::string& what) {
  throw sdk::Error(sdk::codes::kBadRequest, what);
}

const Json& field(const Json& j, const char* name, const char* in) {
  if (!j.is_object()) bad(std::string(in) + " must be an object");
  auto it = j.find(name);
  if (it == j.end()) bad(std::string(in) + " has no \"" + name + "\"");
  return *it;
}
}  // namespace

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

sdk::Cell cell_from_json(const Json& j) {
  if (!j.is_array() || (j.size() != 2 && j.size() != 3))
    bad("a point must be [x, y] or [x, y, z], got " + j.dump());
  for (const auto& v : j)
    if (!v.is_number_integer()) bad("point coordinates must be integers, got " + j.dump());
  sdk::Cell c;
  c.x = j[0].get<std::int32_t>();
  c.y = j[1].get<std::int32_t>();
  if (j.size() == 3) c.z = j[2].get<std::int32_t>();
  return c;
}

sdk::ItemInfo item_from_json(const Json& j) {
  sdk::ItemInfo item;
  const Json& id = field(j, "id", "an item");
  const Json& color = field(j, "color", "an item");
  const Json& shape = field(j, "shape", "an item");
  if (!id.is_number_integer()) bad("item \"id\" must be an integer");
  if (!color.is_string() || !shape.is_string()) bad("item \"color\" and \"shape\" must be strings");
  item.id = id.get<std::int64_t>();
  item.color = color.get<std::string>();
  item.shape = shape.get<std::string>();
  return item;
}

sdk::TraceStep step_from_json(const Json& j) {
  const Json& act = field(j, "act", "a trace step");
  sdk::TraceStep s;
  if (act == "move") {
    s.act = sdk::TraceStep::Act::move;
    s.cell = cell_from_json(field(j, "to", "a move step"));
  } else if (act == "pick" || act == "drop") {
    s.act = act == "pick" ? sdk::TraceStep::Act::pick : sdk::TraceStep::Act::drop;
    s.cell = cell_from_json(field(j, "at", "a pick/drop step"));
    s.item = item_from_json(field(j, "item", "a pick/drop step"));
  } else {
    bad("unknown trace step act " + act.dump() + " (expected move, pick or drop)");
  }
  return s;
}

std::vector<sdk::TraceStep> trace_from_json(const Json& j) {
  if (!j.is_array()) bad("a trace must be an array");
  std::vector<sdk::TraceStep> out;
  out.reserve(j.size());
  for (const auto& s : j) out.push_back(step_from_json(s));
  return out;
}

}  // namespace flipper::kernel::protocol
