#pragma once
// Reading the shared corpus and probe files for the differential tests.
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "flipper/sdk/execution.hpp"

namespace flipper::testsupport {

inline std::vector<nlohmann::json> read_jsonl(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<nlohmann::json> out;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) out.push_back(nlohmann::json::parse(line));
  return out;
}

inline std::string shared_path(const std::string& rel) {
  return std::string(FLIPPER_SHARED_DIR) + "/" + rel;
}

/// worlds.jsonl by world_id.
inline std::map<std::string, nlohmann::json> corpus_worlds() {
  std::map<std::string, nlohmann::json> out;
  for (auto& w : read_jsonl(shared_path("corpus/dev/worlds.jsonl"))) {
    std::string id = w["world_id"];
    out.emplace(std::move(id), std::move(w));
  }
  return out;
}

// One comparable step: "m x y" or "p x y colour shape" / "d ...".
using Steps = std::vector<std::string>;

inline Steps ours(const std::vector<sdk::TraceStep>& trace) {
  Steps out;
  for (const auto& s : trace) {
    std::string t = s.act == sdk::TraceStep::Act::move   ? "m"
                    : s.act == sdk::TraceStep::Act::pick ? "p"
                                                         : "d";
    t += " " + std::to_string(s.cell.x) + " " + std::to_string(s.cell.y);
    if (s.act != sdk::TraceStep::Act::move) t += " " + s.item.color + " " + s.item.shape;
    out.push_back(t);
  }
  return out;
}

// §5: drop start entries and zero-length destinations (entries on the current cell) and
// possible=false entries.
inline Steps theirs(const nlohmann::json& path, sdk::Cell robot) {
  Steps out;
  int x = robot.x, y = robot.y;
  for (const auto& e : path) {
    const int ex = e[0], ey = e[1];
    const std::string act = e[2];
    const bool ok = e[5];
    if (!ok) continue;
    if (act == "path" || act == "destination") {
      if (ex == x && ey == y) continue;
      x = ex;
      y = ey;
      out.push_back("m " + std::to_string(ex) + " " + std::to_string(ey));
    } else {
      const std::string c = e[3], s = e[4];
      out.push_back(std::string(act == "pickitem" ? "p" : "d") + " " + std::to_string(ex) + " " +
                    std::to_string(ey) + " " + c + " " + s);
    }
  }
  return out;
}

}  // namespace flipper::testsupport
