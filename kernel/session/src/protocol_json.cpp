// Protocol JSON for execution results.
#include "flipper/kernel/session_json.hpp"

namespace flipper::kernel::protocol_json {

Json point(const sdk::Cell& c, int dims) {
  Json p = Json::array({c.x, c.y});
  if (dims == 3) p.push_back(c.z);
  return p;
}

Json item(const sdk::ItemInfo& item) {
  return Json{{"id", item.id}, {"color", item.color}, {"shape", item.shape}};
}

Json trace(const std::vector<sdk::TraceStep>& steps, int dims) {
  Json out = Json::array();
  for (const auto& s : steps) {
    switch (s.act) {
      case sdk::TraceStep::Act::move:
        out.push_back(Json{{"act", "move"}, {"to", point(s.cell, dims)}});
        break;
      case sdk::TraceStep::Act::pick:
      case sdk::TraceStep::Act::drop:
        out.push_back(Json{{"act", s.act == sdk::TraceStep::Act::pick ? "pick" : "drop"},
                           {"at", point(s.cell, dims)},
                           {"item", item(s.item)}});
        break;
    }
  }
  return out;
}

Json strings(const std::vector<std::string>& values) {
  Json out = Json::array();
  for (const auto& v : values) out.push_back(v);
  return out;
}

}  // namespace flipper::kernel::protocol_json
