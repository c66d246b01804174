// The trace of an execution result as protocol text (protocol.hpp).
#include "flipper/kernel/protocol.hpp"
#include "flipper/toolkit/json/json_writer.hpp"

namespace flipper::kernel::protocol {

using toolkit::json::JsonWriter;

// The bytes of the trace's JSON tree dumped (trace_json, flipper/repl/outcome_json.hpp), without
// the tree: members in the tree's (sorted) key order, strings escaped by the writer (nlohmann's
// escaping), integers as nlohmann writes them.
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

}  // namespace flipper::kernel::protocol
